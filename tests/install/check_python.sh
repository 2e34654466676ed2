#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and imports rubcont from there (not from the
# build tree) with the given interpreter, on a scene the install ships; the installed executable
# draws its figures with the installed rubcont.plots.
# Usage: check_python.sh BUILD_DIR PYTHON PYTHON_INSTALL_DIR (relative to the prefix)
set -euo pipefail
build=$1
python=$2
site=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cd "$work"
PYTHONPATH="$work/prefix/$site" "$python" - "$work/prefix" <<'PY'
import os, sys
import rubcont
prefix = sys.argv[1]
assert rubcont.__file__.startswith(prefix), rubcont.__file__
result = rubcont.branches(os.path.join(prefix, "share/rubcont/scenes/thesis_A_a.toml"))
points = "branches/branch2/special_points/"
labels = list(result[points + "label"])
k = labels.index("left stick to slip+")
print(f"from the prefix: left stick to slip+ at {result[points + 'speed_rpm'][k]:.6f} rpm")
PY
"$work/prefix/bin/rubcont" analytic "$work/prefix/share/rubcont/scenes/thesis_A_a.toml" \
  --out "$work/figures/a.h5" > /dev/null 2> "$work/stderr"
grep -q "(from $work/prefix/$site)" "$work/stderr" || { cat "$work/stderr"; exit 1; }
test -s "$work/figures/analytic_mode1.png"
