#!/usr/bin/python3
"""The unity build's rule (CMakeLists.txt, RUBCONT_UNITY_BUILD): no file-local name is declared in
two source files of one unity target.

    /usr/bin/python3 scripts/check_unity_names.py ROOT

A unity build compiles a target's files in batches of eight, one translation unit each, so the
anonymous namespaces of a batch's files are one namespace. Two files that declare the same name
there either fail to compile together (the same signature) or, worse, compile: a call in the later
file may then bind to the earlier file's overload (a `Reject(field, value, "rule")` taking
another file's `Reject(field, const Value&, const char*)`), and which files share a batch changes
as files are added. So every function, type, constant and alias declared at the top of an
anonymous namespace must be unique within its target: the library (solvers/ … studies/), the I/O
library (apps/ but main.cpp), and each tests/<folder> executable. Using-declarations (`using
a::b;`) and one alias declared identically in several files name the same entity and pass.

The declarations are read at column 0 of the anonymous namespace's own brace depth (the tree is
clang-formatted). Exit status 1 with one line per clash, 0 when there is none.
"""
import collections
import glob
import os
import re
import sys

LIBRARY = ("solvers", "continuation", "models", "waves", "shooting", "sweeps", "studies")
TESTS = LIBRARY + ("apps",)

TYPE = re.compile(r"^(?:class|struct|union|enum(?:\s+class)?)\s+(\w+)")
ALIAS = re.compile(r"^using\s+(\w+)\s*=")
FUNCTION = re.compile(r"^(?:template\s*<.*>\s*)?(?:\[\[\w+\]\]\s*)?(?:(?:static|inline|constexpr|const)\s+)*"
                      r"[\w:]+(?:<[^()]*>)?[\s*&]+(\w+)\s*\(")
VARIABLE = re.compile(r"^(?:(?:constexpr|const|static|inline)\s+)+[\w:<>,\s]*?\s(\w+)\s*(?:=|\{|\[|;)")


def declarations(path):
    """(name, line number, text) of each declaration at the top of the file's anonymous
    namespaces."""
    found = []
    depth = 0
    anonymous = None  # the brace depth inside an anonymous namespace
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            code = re.sub(r'"(?:\\.|[^"\\])*"', '""', re.sub(r"//.*", "", line))
            if anonymous is not None and depth == anonymous and line[:1].isalpha():
                for pattern in (TYPE, ALIAS, FUNCTION, VARIABLE):
                    m = pattern.match(line)
                    if m:
                        found.append((m.group(1), number, line.strip()))
                        break
            if anonymous is None and re.match(r"^namespace\s*\{", line):
                anonymous = depth + 1
            depth += code.count("{") - code.count("}")
            if anonymous is not None and depth < anonymous:
                anonymous = None
    return found


def targets(root):
    library = [f for d in LIBRARY for f in sorted(glob.glob(os.path.join(root, d, "*.cpp")))]
    io = [f for f in sorted(glob.glob(os.path.join(root, "apps", "*.cpp"))) if not f.endswith("main.cpp")]
    yield "the library", library
    yield "the I/O library", io
    for d in TESTS:
        yield f"tests/{d}", sorted(glob.glob(os.path.join(root, "tests", d, "*_test.cpp")))


def main(argv):
    if len(argv) != 2:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    root = argv[1]
    clashes = 0
    for target, files in targets(root):
        by_name = collections.defaultdict(list)
        for path in files:
            for name, number, text in declarations(path):
                by_name[name].append((os.path.relpath(path, root), number, text))
        for name, places in sorted(by_name.items()):
            files_declaring = {p for p, _, _ in places}
            aliases = {t for _, _, t in places if ALIAS.match(t)}
            if len(files_declaring) < 2 or (len(aliases) == 1 and all(ALIAS.match(t) for _, _, t in places)):
                continue
            clashes += 1
            where = "; ".join(f"{p}:{n}" for p, n, _ in places)
            print(f"{target}: '{name}' is file-local in {len(files_declaring)} files ({where}): "
                  "one unity batch would hold both")
    if clashes:
        print(f"{clashes} clash(es): give each file-local name its own spelling", file=sys.stderr)
        return 1
    print("unity names: every file-local name is its file's own")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
