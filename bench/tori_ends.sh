#!/usr/bin/env bash
# Where case C(b)'s two-frequency whip ends (scenes/thesis_C_b_tori.toml: the circles in the contact
# chart on sections of 2 modulation periods, K = 16, Gauss on 1600 intervals per period). The
# scene's family runs out of its 30 steps each way (at 53.59 and 55.08 rpm); here each way is one
# run of stage "tori" with the scene's settings but the range and steps:
#   down  from the scene's BDF transient at 54.5 rpm, the range cut to 53.0–54.55 rpm and 70 steps:
#         the family downwards past its fold near the 3:13 resonance (its upward family one step to
#         the range's end);
#   up    from a BDF transient at 54.7 rpm (the scene's family takes 22 short steps over
#         54.5–54.7 rpm; transients at 54.8, 54.9 and 55.0 rpm give no circle or a singular
#         Jacobian), the range cut to 54.69–57.0 rpm and 45 steps.
# The two run side by side, one core each; each prints its CPU seconds (user + system) and its
# summary from the stage on (how each family ended, every torus's lines and stability, the notes),
# then every torus's K, Fourier tail and invariance error from its file (bench/tori_tails.py: the
# summary gives them only where the family refines in K).
# Usage, from the repository root:
#   bench/tori_ends.sh BUILD_DIR > results/bench/tori_ends_C_b.txt
set -euo pipefail
build=${1:?usage: bench/tori_ends.sh BUILD_DIR}
rubcont="$build/rubcont"
scene=scenes/thesis_C_b_tori.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The scene with the transient at $2 rpm, the range [$3] and $4 steps each way, as $work/$1.toml.
cut_scene() {
  sed -e "s/^speed_range_rpm = .*/speed_range_rpm = [$3]/" -e "s/^speed_rpm = .*/speed_rpm = $2/" \
    -e "s/^max_steps = .*/max_steps = $4/" "$scene" > "$work/$1.toml"
}

echo "# bench/tori_ends.sh $build, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores," \
  "$(git describe --always --dirty)"
cut_scene down 54.5 "53.0, 54.55" 70
cut_scene up 54.7 "54.69, 57.0" 45
# The two runs side by side (one core each), each timed on its own.
for way in down up; do
  { /usr/bin/time -f "%U %S" "$rubcont" run "$work/$way.toml" --quiet --no-figures --out "$work" \
      > "$work/$way.summary"; } 2> "$work/$way.time" &
done
wait
for way in down up; do
  echo
  keys=$(grep -E '^(speed_rpm|speed_range_rpm|max_steps) ' "$work/$way.toml" | tr '\n' ' ')
  echo "## $way: $keys"
  echo "CPU seconds (user + system): $(tail -1 "$work/$way.time" | awk '{ print $1 + $2 }')"
  sed -n '/^\[tori\]/,$p' "$work/$way.summary" | grep -v '^wrote '
  /usr/bin/python3 bench/tori_tails.py "$work/$way/$way.h5"
done
