#!/usr/bin/env bash
# The two quick-start commands (see README.md):
#   ./build.sh run    install missing Debian packages, build, run `rubcont run` on the default scene
#   ./build.sh test   install missing Debian packages, build, run the whole test suite through ctest
# Extra arguments after `run` are passed to `rubcont run` (e.g. a scene file).
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-}
shift || true
case "$mode" in
  run|test) ;;
  *) echo "usage: ./build.sh run [SCENE] | ./build.sh test" >&2; exit 2 ;;
esac

scripts/install-deps.sh
jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel "$jobs"

if [ "$mode" = run ]; then
  exec build/rubcont run "$@"
else
  exec ctest --test-dir build --output-on-failure --parallel "$jobs"
fi
