#!/usr/bin/env bash
# Checks that the committed results are what the code makes now (results/README.md, "Check").
#   scripts/check_results.sh BUILD_DIR quick|sweep|orbits|loop [SCENE ...]
# re-runs the scenes of that kind (scripts/result_scenes.txt; all of them when none is named) into a
# temporary directory with BUILD_DIR/rubcont, no figures, and compares with results/<scene>/:
#   quick   <scene>.h5 and summary.txt      (`rubcont run`; under a second per scene)
#   sweep   sweep.h5 and sweep_summary.txt  (`rubcont sweep`; 2–16 min per scene)
#   orbits  <scene>.h5 and summary.txt      (`rubcont run` with the rub's orbits; about 20 min)
#   loop    loop.h5 and loop.txt            (`rubcont loop` with its options in result_scenes.txt; 1–12 min)
# Numbers must agree within |a − b| ≤ 1e-12 + 1e-9·|b| (the runs are deterministic; the margin is
# for another CPU's last digits), strings exactly — the stored scene text (`scene_toml`) included,
# except a key added since at the default that keeps the older behaviour (SCENE_KEYS_ADDED) —
# and wall-clock times are not compared (scripts/compare_results.py). The summaries' "wrote ..."
# lines name the output paths and are left out. Exit code 0 when everything matches, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 2 ]]; then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
build=$1 kind=$2
shift 2
case "$kind" in
  quick|sweep|orbits|loop) ;;
  *) echo "check_results.sh: kind = '$kind': must be quick, sweep, orbits or loop" >&2; exit 2 ;;
esac
scenes=("$@")
source scripts/result_scenes.sh  # scenes_of KIND; loop_options_of SCENE: a loop's schedule and budget
if [[ ${#scenes[@]} -eq 0 ]]; then
  mapfile -t scenes < <(scenes_of "$kind")
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
without_paths() { grep -v '^wrote ' "$1" > "$2" || true; }

failed=0
for scene in "${scenes[@]}"; do
  committed=results/$scene
  case "$kind" in
    sweep)
      "$build/rubcont" sweep "scenes/$scene.toml" --quiet --no-figures --out "$tmp/$scene/sweep.h5" \
        > "$tmp/$scene.summary" || true
      files=(sweep.h5) summary=sweep_summary.txt ;;
    loop)
      mkdir -p "$tmp/$scene"
      read -ra loop_options < <(loop_options_of "$scene")
      "$build/rubcont" loop "scenes/$scene.toml" "${loop_options[@]}" --quiet --no-figures \
        --out "$tmp/$scene/loop.h5" > "$tmp/$scene.summary" || true
      files=(loop.h5) summary=loop.txt ;;
    *)
      "$build/rubcont" run "scenes/$scene.toml" --quiet --no-figures --out "$tmp" \
        > "$tmp/$scene.summary" || true
      files=("$scene.h5") summary=summary.txt ;;
  esac
  without_paths "$committed/$summary" "$tmp/$scene.committed_summary.txt"
  without_paths "$tmp/$scene.summary" "$tmp/$scene.summary.txt"
  pairs=("$tmp/$scene.committed_summary.txt" "$tmp/$scene.summary.txt")
  for f in "${files[@]}"; do pairs+=("$committed/$f" "$tmp/$scene/$f"); done
  if ! /usr/bin/python3 scripts/compare_results.py "${pairs[@]}" --rtol 1e-9 --atol 1e-12 \
       > "$tmp/$scene.compare"; then
    failed=1
    echo "results/$scene: differs from what the code makes now (scripts/regenerate-results.sh):"
    grep -v '^same' "$tmp/$scene.compare" | sed "s|$tmp/||g"
  else
    echo "results/$scene: $kind results reproduce"
  fi
done
exit $failed
