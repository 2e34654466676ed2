#!/usr/bin/python3
"""The test tiers' table, tests/test_costs.txt: checked against the tests a build defines, and
updated from measured times.

    /usr/bin/python3 scripts/test_tiers.py check BUILD_DIR [--table FILE]
    /usr/bin/python3 scripts/test_tiers.py update BUILD_DIR JUNIT.xml... [--prune]

Each line of the table gives one test its measured seconds, its tier and its full ctest name:

      2.3  quick  solvers: ...

cmake/TestTiers.cmake turns the lines into ctest labels ("quick", "full", "full;slow" for
`slow`), a TIMEOUT of 3 × seconds + 30 and a COST when ctest reads the tests.

check (a ctest, in the quick tier) fails when a test the build defines has no line (a new test
must be given a tier), when a name has two lines, when a test with a line got no label (its line
cannot be read), when a folder's Catch executable has no quick test, or when the quick tier is
over its budget (--table checks another table against the build's tests, for the ctest that
makes it fail). Lines naming no test of this build are reported but pass: the MPI and Python
tests exist only in builds with those options.

update reads the times of a ctest run (`ctest --output-junit FILE`, FILE relative to the build
directory) and writes the table again: measured tests get their new seconds and keep their tier;
new tests get one by their time (quick up to QUICK_NEW_MAX s, slow from SLOW_MIN s, full between),
to be moved by hand where the folder's coverage or the budget wants it; --prune drops the lines
naming no test of this build. It prints the quick tier's total against its budget.
"""
import collections
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

TABLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "test_costs.txt")
TIERS = ("quick", "full", "slow")
# The quick tier's test seconds, summed: ≤ 3 min of wall on 2 cores with --parallel 2 would allow
# 360 s; 240 s leaves 1.5× for a loaded machine and for the two cores not finishing together.
QUICK_BUDGET = 240.0
QUICK_NEW_MAX = 5.0  # a new test measured at up to this many seconds goes to quick
SLOW_MIN = 60.0      # a new test measured at this many seconds or more is slow
LINE = re.compile(r"^\s*(\d+(?:\.\d*)?)\s+(quick|full|slow)\s+(\S.*?)\s*$")
CATCH_EXECUTABLE = re.compile(r"rubcont_(\w+)_tests$")

HEADER = """\
# The test tiers: one line per ctest test, `seconds tier name`, read by cmake/TestTiers.cmake when
# ctest runs (labels, TIMEOUT = 3 × seconds + 30, COST) and checked by scripts/test_tiers.py check
# (a ctest that fails on a test without a line). Tiers: quick (every change: `./build.sh quick`,
# ctest -L quick; every folder has some; their seconds sum to at most {budget:.0f}), full (the rest
# of `./build.sh test`), slow (the longest of full; labelled full and slow). Seconds: wall time of
# each test in one `ctest --parallel 2` of the whole suite on the shared 2-core machine.
# A new test: run it with `ctest --test-dir BUILD -R NAME --output-junit new.xml`, then
# `/usr/bin/python3 scripts/test_tiers.py update BUILD new.xml` adds its line; or add it by hand.
"""


def read_table(path):
    """(seconds, tier, name) of each line, in order; a line that cannot be read stops here."""
    entries = []
    if not os.path.exists(path):
        return entries
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            match = LINE.match(line)
            if not match:
                sys.exit(f"{path}:{number}: cannot read {line.strip()!r} "
                         "(wanted: seconds, quick|full|slow, the test's name)")
            entries.append((float(match.group(1)), match.group(2), match.group(3)))
    return entries


def defined_tests(build):
    """name -> (labels, timeout, group) of every test ctest finds in BUILD; group is the Catch
    executable's folder, or "" for a scripted test.

    ctest lists them from a copy of BUILD's CTestTestfile.cmake files (they name everything else
    by its absolute path): even with --show-only, ctest rewrites Testing/Temporary/LastTest.log,
    and this runs as a test inside the ctest that writes that log."""
    with tempfile.TemporaryDirectory() as copy:
        for folder, _, files in os.walk(build):
            if "CTestTestfile.cmake" in files:
                target = os.path.join(copy, os.path.relpath(folder, build))
                os.makedirs(target, exist_ok=True)
                shutil.copy(os.path.join(folder, "CTestTestfile.cmake"), target)
        listing = subprocess.run(["ctest", "--test-dir", copy, "--show-only=json-v1"],
                                 check=True, capture_output=True, text=True).stdout
    tests = {}
    for test in json.loads(listing)["tests"]:
        properties = {p["name"]: p["value"] for p in test.get("properties", [])}
        command = test.get("command") or [""]
        match = CATCH_EXECUTABLE.search(os.path.basename(command[0]))
        tests[test["name"]] = (properties.get("LABELS", []), properties.get("TIMEOUT"),
                               match.group(1) if match else "")
    return tests


def quick_seconds(entries):
    return sum(seconds for seconds, tier, _ in entries if tier == "quick")


def check(build, path):
    entries = read_table(path)
    tests = defined_tests(build)
    problems = []
    counts = collections.Counter(name for _, _, name in entries)
    problems += [f"two lines for {name!r}" for name, n in counts.items() if n > 1]
    listed = set(counts)
    missing = sorted(name for name in tests if name not in listed)
    problems += [f"no line for {name!r}: give it a tier (scripts/test_tiers.py update)"
                 for name in missing]
    problems += [f"{name!r} has a line but no label: its line was not read by ctest"
                 for name, (labels, _, _) in tests.items() if name in listed and not labels]
    tier_of = {name: tier for _, tier, name in entries}
    groups = sorted({group for _, _, group in tests.values() if group})
    for group in groups:
        if not any(tier_of.get(name) == "quick" for name, (_, _, g) in tests.items() if g == group):
            problems.append(f"rubcont_{group}_tests has no quick test: every folder needs some")
    quick = quick_seconds(entries)
    if quick > QUICK_BUDGET:
        problems.append(f"the quick tier's tests add up to {quick:.0f} s, over its {QUICK_BUDGET:.0f} s")
    absent = [name for name in listed if name not in tests]
    for name in sorted(absent):
        print(f"note: {name!r} is not a test of this build (an option off?)")
    by_label = collections.Counter(label for labels, _, _ in tests.values() for label in labels)
    print(f"tiers: {len(tests)} tests: {by_label['quick']} quick ({quick:.0f} s of {QUICK_BUDGET:.0f}), "
          f"{by_label['full']} full of which {by_label['slow']} slow; "
          f"{len(groups)} folders, each with quick tests")
    for problem in problems:
        print(f"problem: {problem}")
    if problems:
        print(f"tiers: {len(problems)} problem(s) in {path}")
        return 1
    print("tiers: every test has a tier, a timeout and a cost")
    return 0


def measured_seconds(build, junit_files):
    seconds = {}
    for file in junit_files:
        root = ElementTree.parse(os.path.join(build, file)).getroot()
        for case in root.iter("testcase"):
            seconds[case.get("name")] = float(case.get("time", "0"))
    return seconds


def update(build, path, junit_files, prune):
    entries = read_table(path)
    tests = defined_tests(build)
    seconds = measured_seconds(build, junit_files)
    tier_of = {name: tier for _, tier, name in entries}
    cost_of = {name: cost for cost, _, name in entries}
    for name, measured in seconds.items():
        if name not in tests:
            continue
        cost_of[name] = measured
        if name not in tier_of:
            tier_of[name] = ("quick" if measured <= QUICK_NEW_MAX else
                             "slow" if measured >= SLOW_MIN else "full")
            print(f"new: {tier_of[name]:5} {measured:7.1f} s  {name}")
    names = [name for name in tier_of if not prune or name in tests]
    unmeasured = [name for name in tests if name not in cost_of]
    for name in unmeasured:
        print(f"not measured and without a line: {name!r}")
    groups = collections.defaultdict(list)
    for name in names:
        groups[tests[name][2] if name in tests else ""].append(name)
    with open(path, "w", encoding="utf-8") as f:
        f.write(HEADER.format(budget=QUICK_BUDGET))
        for group in sorted(groups, key=lambda g: (g == "", g)):
            f.write(f"\n# {'rubcont_' + group + '_tests' if group else 'scripted tests'}\n")
            for name in sorted(groups[group]):
                f.write(f"{cost_of[name]:7.1f}  {tier_of[name]:5}  {name}\n")
    entries = read_table(path)
    print(f"quick tier: {sum(1 for e in entries if e[1] == 'quick')} tests, "
          f"{quick_seconds(entries):.0f} s of {QUICK_BUDGET:.0f}")
    return 0


def main(argv):
    if len(argv) in (2, 4) and argv[0] == "check":
        return check(argv[1], argv[3] if len(argv) == 4 and argv[2] == "--table" else TABLE)
    if len(argv) >= 3 and argv[0] == "update":
        prune = "--prune" in argv
        return update(argv[1], TABLE, [a for a in argv[2:] if a != "--prune"], prune)
    sys.exit(__doc__)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
