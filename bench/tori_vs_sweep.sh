#!/usr/bin/env bash
# A whip modulated at two frequencies, by continuation of its tori (L2) and by a sweep over the
# same speeds (L3), in one run: CPU time (user + system), then bench/tori_vs_sweep.py compares the
# lines the sweep's spectra show with the tori's (interpolated to each sweep speed).
# CASE a (default): case C(a)'s tori born at a Neimark–Sacker point (scenes/thesis_C_a_tori.toml):
#   orbits  the modulated whip from its Hopf point past its Neimark–Sacker point (stage "orbits":
#           60 orbits, Gauss collocation);
#   first   stage "tori" stopped after its first torus (the family above, then the torus started
#           at the Neimark–Sacker point and one continuation step; no Lyapunov exponents);
#   tori    stage "tori" as committed but without [analysis.tori.transient]: the torus family
#           to its end (refined in K up to the scene's max_harmonics), each torus's lines and
#           Lyapunov exponents (200 iterates), the locked orbits round their closed curve;
#   sweep   a speed-up sweep over 48.10–48.85 rpm in 0.05 rpm steps (Dormand–Prince at 1e-8, 8 s
#           dwell, 6 s analysed: 1/6 Hz bins), the speeds the tori cover and the stable
#           modulated whip below them.
# CASE c: case C(c)'s whip on a contact pressed by nanometres (scenes/thesis_C_c_tori.toml: the
# circles in the contact chart, from a BDF transient at 64 rpm):
#   tori    stage "tori" with the range cut to 63.9–72 rpm: the transient, its torus and the family
#           from it upwards to where the left contact lifts off (located at 70.91 rpm), each torus's
#           lines and Lyapunov exponents (100 iterates); downwards one step to the range's end;
#   sweep   a speed-up sweep over 64–70.5 rpm in 0.5 rpm steps (as above), the speeds the tori cover.
# CASE b: case C(b)'s whip (scenes/thesis_C_b_tori.toml: the circles in the contact chart on sections
# of 2 modulation periods, from a BDF transient at 54.5 rpm):
#   tori    stage "tori" with the range cut to 54.4–55.1 rpm: the transient, its torus and the
#           family from it upwards in the scene's 30 steps (to about 55.08 rpm), each torus's lines
#           and Lyapunov exponents (100 iterates); downwards to the range's end;
#   sweep   a speed-up sweep over 54.5–55.0 rpm in 0.1 rpm steps (as above).
# CASE a60: case C(a)'s whip above its 1:3 tongue (scenes/thesis_C_a_tori_60.toml: the circles in the
# contact chart on sections of 5 modulation periods, from a BDF transient at 60 rpm):
#   tori    stage "tori" as committed but with centre_orbits = "to_point": the transient, its torus
#           and the family down to the range's end (59 rpm) and up to where it shrinks onto the
#           5-lap whip at its centre (62.988 rpm), each torus's lines and Lyapunov exponents (100
#           iterates), and the centre orbits up to that Neimark–Sacker point;
#   sweep   a speed-up sweep over 59.0–62.5 rpm in 0.5 rpm steps (as above); the lines compared are
#           the carrier, carrier + 5 f1 and + 13 f1 (the contacts' strongest) and four with the
#           second frequency (l = ±1): at 60 rpm 0.3–0.4 % of the carrier's magnitude in the left
#           contact's spectrum, about 0.02 % in the right's.
# Usage, from the repository root:
#   bench/tori_vs_sweep.sh BUILD_DIR > results/bench/tori_vs_sweep.txt
#   bench/tori_vs_sweep.sh BUILD_DIR c > results/bench/tori_vs_sweep_C_c.txt
#   bench/tori_vs_sweep.sh BUILD_DIR b > results/bench/tori_vs_sweep_C_b.txt
#   bench/tori_vs_sweep.sh BUILD_DIR a60 > results/bench/tori_vs_sweep_C_a_60.txt
set -euo pipefail
build=${1:?usage: bench/tori_vs_sweep.sh BUILD_DIR [a|b|c|a60]}
case_letter=${2:-a}
rubcont="$build/rubcont"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# CPU seconds (user + system) of a command, its output discarded.
cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -1 | awk '{ print $1 + $2 }'; }

# The scene's structure ($body) with a speed-up sweep over [$1, $2] in $3 rpm steps, 8 s dwell.
sweep_scene() {
  cat > "$work/sweep.toml" <<EOF
$body
[analysis]
stages = ["sweep"]

[analysis.sweep]
up_range_rpm = [$1, $2]
down_range_rpm = [$(awk "BEGIN { print $2 - $3 }"), $2]
speed_step_rpm = $3
dwell = 8.0
settle_window = 2.0
settle_windows = 2
analysis_length = 6.0
sample_rate_hz = 2048.0
spectrum_max_hz = 600.0
EOF
}

case "$case_letter" in
  a) scene=scenes/thesis_C_a_tori.toml ;;
  b) scene=scenes/thesis_C_b_tori.toml range="54.4, 55.1" sweep_range="54.5 55.0 0.1" ;;
  c) scene=scenes/thesis_C_c_tori.toml range="63.9, 72.0" sweep_range="64.0 70.5 0.5" ;;
  a60) scene=scenes/thesis_C_a_tori_60.toml range="59.0, 78.0" sweep_range="59.0 62.5 0.5"
       lines="0,0;0,-5;0,-13;-1,-1;1,-4;-1,-4;1,1" groups=tori/transient_down,tori/transient_up
       centre_orbits=to_point ;;
  *) echo "bench/tori_vs_sweep.sh: CASE = $case_letter: must be a, b, c or a60" >&2; exit 2 ;;
esac
body=$(sed '/^\[analysis\]/,$d' "$scene")
analysis=$(sed -n '/^\[analysis\]/,$p' "$scene")
echo "# bench/tori_vs_sweep.sh $build $case_letter, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, $(git describe --always --dirty)"
echo "CPU seconds (user + system), one run each:"
if [ "$case_letter" = a ]; then
  # The Neimark–Sacker family alone: the scene's transient at 49 rpm lies past the sweep's speeds.
  analysis=$(sed '/^\[analysis.tori.transient\]/,$d' <<< "$analysis")
  printf '%s\n%s\n' "$body" "$(sed 's/^stages = .*/stages = ["orbits"]/' <<< "$analysis")" > "$work/orbits.toml"
  printf '%s\n%s\n' "$body" "$(sed -e 's/^stages = .*/stages = ["tori"]/' -e 's/^max_steps = 40/max_steps = 1/' \
    -e 's/^lyapunov_iterates = .*/lyapunov_iterates = 1/' <<< "$analysis")" > "$work/first.toml"
  printf '%s\n%s\n' "$body" "$(sed 's/^stages = .*/stages = ["tori"]/' <<< "$analysis")" > "$work/tori.toml"
  sweep_scene 48.10 48.85 0.05
  orbits=$(cpu "$rubcont" run "$work/orbits.toml" --quiet --no-figures --out "$work")
  first=$(cpu "$rubcont" run "$work/first.toml" --quiet --no-figures --out "$work")
  tori=$(cpu "$rubcont" run "$work/tori.toml" --quiet --no-figures --out "$work")
  group=tori/branch1_hopf2_ns1
else
  centre='s/^coordinates = "chart"/coordinates = "chart"\ncentre_orbits = "to_point"/'
  printf '%s\n%s\n' "$body" "$(sed -e "s/^speed_range_rpm = .*/speed_range_rpm = [$range]/" \
    -e "${centre_orbits:+$centre}" <<< "$analysis")" > "$work/tori.toml"
  read -r sweep_from sweep_to sweep_step <<< "$sweep_range"
  sweep_scene "$sweep_from" "$sweep_to" "$sweep_step"
  tori=$(cpu "$rubcont" run "$work/tori.toml" --quiet --no-figures --out "$work")
  group=${groups:-tori/transient_up}
fi
sweep=$(cpu "$rubcont" sweep "$work/sweep.toml" --direction up --quiet --no-figures --out "$work/sweep.h5")
count=$(/usr/bin/python3 -c "import h5py; f = h5py.File('$work/tori/tori.h5'); \
  print(len({s for g in '$group'.split(',') for s in f[g + '/speed_rpm'][()]}))")
speeds=$(/usr/bin/python3 -c "import h5py; print(len(h5py.File('$work/sweep.h5')['sweeps/up/speed_rpm']))")
if [ "$case_letter" = a ]; then
  echo "  orbits  modulated whip, 60 orbits                       $orbits s"
  echo "  first   orbits + the first torus (start and one step)   $first s  (the torus: $(awk "BEGIN { print $first - $orbits }") s)"
  echo "  tori    orbits + the torus family ($count tori, lines, Lyapunov)  $tori s  (the tori: $(awk "BEGIN { print $tori - $orbits }") s)"
  echo "  sweep   $speeds speeds, 48.10-48.85 rpm, 8 s dwell              $sweep s"
  echo "  ratio   sweep / torus family (tori - orbits)            $(awk "BEGIN { printf \"%.2f\", $sweep / ($tori - $orbits) }")"
else
  echo "  tori    transient, its torus and the family up ($count tori, lines, Lyapunov)  $tori s"
  echo "  sweep   $speeds speeds, $sweep_from-$sweep_to rpm, 8 s dwell                     $sweep s"
  echo "  ratio   sweep / tori                                       $(awk "BEGIN { printf \"%.2f\", $sweep / $tori }")"
fi
/usr/bin/python3 bench/tori_vs_sweep.py "$work/tori/tori.h5" "$work/sweep.h5" "$group" ${lines:+--lines "$lines"}
