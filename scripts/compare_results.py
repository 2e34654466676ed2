#!/usr/bin/python3
"""Compares result files: what a run produces now against what is committed.

    scripts/compare_results.py OLD NEW [OLD NEW ...] [--rtol R] [--atol A]
    scripts/compare_results.py --git REV PATH...   each PATH against its committed version at REV

HDF5 files (.h5): every group, dataset and attribute on both sides; numbers equal within
|a − b| ≤ atol + rtol·|b| (NaN equals NaN), strings and integers exactly. Text files (.txt, .csv):
line by line, numbers within the same tolerance. Wall-clock times are not results: datasets and
attributes named *seconds* (grid_seconds, wall_seconds, ...) are skipped; in text, string
attributes and string datasets a number followed by "s", "ms" or "min" is not compared, nor the columns of a CSV file
whose header names a time (time_ms, *_seconds) or a number after "time_ms".

Provenance is not a result either: the root attributes rubcont_version and rubcont_git (the
commit) are skipped, and so is the version in the first line of scene_toml.

Files written before 0.2.0 lack what 0.2.0 adds to describe the data: `units`, `flag_values`,
`flag_meanings`, the dimension scales (CLASS, NAME, DIMENSION_LIST; DIMENSION_LIST is compared as
the names of the scales of each axis, REFERENCE_LIST not at all) and the special points' `state`.
Those present in the new file only are not differences; present in both they must agree.

A scene key added after a file was written, at the default that keeps the older behaviour
(SCENE_KEYS_ADDED), is not a difference when only the new scene_toml has it: a file written before
`[analysis.orbits] at_grazing` ran as `at_grazing = "continue"` does. At any other value it is.
A default whose unit changed (SCENE_DEFAULTS_CHANGED: `[analysis.loop] budget`, 300 CPU seconds
until 2026-11-30, 4 G work units since) is the same default in both texts.

Exit code 0 when everything matches, 1 with one line per difference otherwise.
"""
import argparse
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
# A duration in a printed line: "0.053 s", "1.08 s", "12 ms", "3 min 20 s" (the unit ends it).
DURATION = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?\s*(?:ms|s|min)\b")
TIMING_NAME = re.compile(r"seconds|time_ms")
# Root attributes that say which build made a file, not what it computed.
PROVENANCE = {"/@rubcont_version", "/@rubcont_git"}
# "# Scene "x" as resolved by rubcont 0.2.0 from ...": the version in scene_toml's first line.
RESOLVED_BY = re.compile(r"(as resolved by rubcont )\S+")
# What 0.2.0 added to describe the data (attribute names; dataset names): an older file lacks them.
ADDED_ATTRIBUTES = {"units", "flag_values", "flag_meanings", "CLASS", "NAME", "DIMENSION_LIST"}
ADDED_DATASETS = {"state"}
# Scene keys added later, as the line a resolved scene prints at the default that keeps what runs
# before the key did: the keys marked KeySpec::added_at_older_behaviour in apps/scene_schema.cpp.
SCENE_KEYS_ADDED = {'at_grazing = "continue"', 'predictor = "tangent"', 'mesh = "uniform"',
                    'coordinates = "state"', 'max_harmonics = 0', 'laps = 0', 'defect_check = "on"'}
# A line as an old file wrote it → the same default as written today (the loop's budget is the only
# key "budget = ").
SCENE_DEFAULTS_CHANGED = {"budget = 300.0": "budget = 4.0"}


def mask_durations(line):
    return TIMING_NAME.sub("<time>", DURATION.sub("<time>", re.sub(r"time_ms[ =:,]*" + NUMBER.pattern,
                                                                   "<time>", line)))


def close(a, b, rtol, atol):
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= atol + rtol * abs(b)


def flatten_h5(path):
    import h5py  # Debian's python3-h5py: run as /usr/bin/python3
    items = {}
    with h5py.File(path, "r") as f:
        def attributes(name, obj):
            for key, value in obj.attrs.items():
                if key == "REFERENCE_LIST":  # the scale's side of DIMENSION_LIST
                    continue
                if key == "DIMENSION_LIST":  # object references: compared as the scales' names
                    value = "; ".join(",".join(scale.name for scale in axis.values())
                                      for axis in obj.dims)
                elif key == "scene_toml" and name == "/":
                    value = RESOLVED_BY.sub(r"\1<version>", as_text(value))
                items[f"{name}@{key}"] = value

        attributes("/", f)

        def visit(name, obj):
            attributes("/" + name, obj)
            if isinstance(obj, h5py.Dataset):
                items["/" + name] = obj[()]

        f.visititems(visit)
    return items


def as_text(value):
    if isinstance(value, bytes):
        return value.decode()
    return value


def compare_values(key, a, b, rtol, atol):
    import numpy as np
    a, b = as_text(a), as_text(b)
    if isinstance(a, str) or isinstance(b, str):
        if not isinstance(a, str) or not isinstance(b, str) or mask_durations(a) != mask_durations(b):
            return [f"{key}: text differs"]
        return []
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return [f"{key}: shape {a.shape} → {b.shape}"]
    if a.dtype.kind in "OSU" or b.dtype.kind in "OSU":
        left = [mask_durations(as_text(x)) for x in a.ravel()]
        right = [mask_durations(as_text(x)) for x in b.ravel()]
        n = sum(x != y for x, y in zip(left, right))
        return [f"{key}: {n} of {len(left)} strings differ"] if n else []
    if a.dtype.kind in "iub" and b.dtype.kind in "iub":
        n = int((a != b).sum())
        return [f"{key}: {n} of {a.size} integers differ"] if n else []
    a, b = a.astype(float).ravel(), b.astype(float).ravel()
    bad = [i for i in range(a.size) if not close(a[i], b[i], rtol, atol)]
    if not bad:
        return []
    worst = max(bad, key=lambda i: abs(a[i] - b[i]) / max(abs(b[i]), 1e-300)
                if math.isfinite(a[i]) and math.isfinite(b[i]) else math.inf)
    return [f"{key}: {len(bad)} of {a.size} values differ, e.g. [{worst}] {a[worst]!r} → {b[worst]!r}"]


def added_in_0_2(key):
    """Whether `key` ("/path@attribute" or "/path") is one of what 0.2.0 added to describe data."""
    path, _, attribute = key.partition("@")
    if attribute:
        return attribute in ADDED_ATTRIBUTES or added_in_0_2(path)
    return path.rsplit("/", 1)[-1] in ADDED_DATASETS


def with_changed_defaults(old_text):
    """old_text with the defaults of SCENE_DEFAULTS_CHANGED as written today."""
    return "\n".join(SCENE_DEFAULTS_CHANGED.get(line, line) for line in as_text(old_text).split("\n"))


def without_added_scene_keys(old_text, new_text):
    """new_text without the lines of SCENE_KEYS_ADDED that old_text lacks."""
    old_lines = set(as_text(old_text).splitlines())
    return "\n".join(line for line in as_text(new_text).split("\n")
                     if line not in SCENE_KEYS_ADDED or line in old_lines)


def compare_h5(old, new, rtol, atol):
    a, b = flatten_h5(old), flatten_h5(new)
    if "/@scene_toml" in a and "/@scene_toml" in b:
        a["/@scene_toml"] = with_changed_defaults(a["/@scene_toml"])
        b["/@scene_toml"] = without_added_scene_keys(a["/@scene_toml"], with_changed_defaults(b["/@scene_toml"]))
    keys = {k for k in set(a) | set(b)
            if not TIMING_NAME.search(k.rsplit("/", 1)[-1]) and k not in PROVENANCE}
    problems = []
    for key in sorted(keys):
        if key not in a:
            if not added_in_0_2(key):
                problems.append(f"{key}: only in the new file")
        elif key not in b:
            problems.append(f"{key}: only in the old file")
        else:
            problems += compare_values(key, a[key], b[key], rtol, atol)
    return problems


def drop_time_columns(lines):
    """CSV: blanks the columns whose header names a time."""
    header = next((i for i, l in enumerate(lines) if not l.startswith("#") and "," in l), None)
    if header is None:
        return lines
    names = lines[header].split(",")
    timed = {k for k, name in enumerate(names) if TIMING_NAME.search(name)}
    if not timed:
        return lines
    out = lines[:header + 1]
    for line in lines[header + 1:]:
        cells = line.split(",")
        out.append(",".join("<time>" if k in timed else c for k, c in enumerate(cells)))
    return out


def compare_text(old, new, rtol, atol):
    left = Path(old).read_text().splitlines()
    right = Path(new).read_text().splitlines()
    if str(new).endswith(".csv"):
        left, right = drop_time_columns(left), drop_time_columns(right)
    problems = []
    if len(left) != len(right):
        problems.append(f"{len(left)} lines → {len(right)} lines")
    for i, (x, y) in enumerate(zip(left, right), 1):
        x, y = mask_durations(x), mask_durations(y)
        if NUMBER.sub("#", x) != NUMBER.sub("#", y):
            problems.append(f"line {i}: text differs:\n    {x}\n    {y}")
            continue
        for p, q in zip(NUMBER.findall(x), NUMBER.findall(y)):
            if not close(float(p), float(q), rtol, atol):
                problems.append(f"line {i}: {p} → {q}")
                break
    return problems


def compare(old, new, rtol, atol):
    if str(new).endswith(".h5"):
        return compare_h5(old, new, rtol, atol)
    return compare_text(old, new, rtol, atol)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+")
    parser.add_argument("--git", metavar="REV", help="compare each PATH with its version at REV")
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--atol", type=float, default=1e-12)
    args = parser.parse_args()
    pairs = []
    with tempfile.TemporaryDirectory() as tmp:
        if args.git:
            for i, path in enumerate(args.paths):
                old = Path(tmp) / f"{i}_{Path(path).name}"
                blob = subprocess.run(["git", "show", f"{args.git}:{path}"], check=True,
                                      capture_output=True).stdout
                old.write_bytes(blob)
                pairs.append((old, path))
        else:
            if len(args.paths) % 2:
                parser.error("give OLD NEW pairs")
            pairs = list(zip(args.paths[0::2], args.paths[1::2]))
        failed = 0
        for old, new in pairs:
            problems = compare(old, new, args.rtol, args.atol)
            label = new if args.git else f"{old} → {new}"
            if problems:
                failed += 1
                print(f"DIFFERS {label}")
                for p in problems:
                    print(f"  {p}")
            else:
                print(f"same    {label}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
