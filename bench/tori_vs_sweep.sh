#!/usr/bin/env bash
# The whip of case C(a) modulated at two frequencies, by continuation of its tori (L2) and by a
# sweep over the same speeds (L3), in one run: CPU time (user + system) of
#   orbits  the modulated whip from its Hopf point past its Neimark–Sacker point (stage "orbits" of
#           scenes/thesis_C_a_tori.toml: 60 orbits, Gauss collocation);
#   first   stage "tori" stopped after its first torus (the family above, then the torus started
#           at the Neimark–Sacker point and one continuation step; no Lyapunov exponents);
#   tori    stage "tori" as committed: the torus family to its end, each torus's lines and
#           Lyapunov exponents (200 iterates);
#   sweep   a speed-up sweep over 48.10–48.85 rpm in 0.05 rpm steps (Dormand–Prince at 1e-8, 8 s
#           dwell, 6 s analysed: 1/6 Hz bins), the speeds the tori cover and the stable
#           modulated whip below them;
# then bench/tori_vs_sweep.py compares the lines the sweep's spectra show with the tori's
# (interpolated to each sweep speed). Usage, from the repository root:
#   bench/tori_vs_sweep.sh BUILD_DIR > results/bench/tori_vs_sweep.txt
set -euo pipefail
build=${1:?usage: bench/tori_vs_sweep.sh BUILD_DIR}
rubcont="$build/rubcont"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# CPU seconds (user + system) of a command, its output discarded.
cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -1 | awk '{ print $1 + $2 }'; }

scene=scenes/thesis_C_a_tori.toml
body=$(sed '/^\[analysis\]/,$d' "$scene")
analysis=$(sed -n '/^\[analysis\]/,$p' "$scene")
printf '%s\n%s\n' "$body" "$(sed 's/^stages = .*/stages = ["orbits"]/' <<< "$analysis")" > "$work/orbits.toml"
printf '%s\n%s\n' "$body" "$(sed -e 's/^stages = .*/stages = ["tori"]/' -e 's/^max_steps = 40/max_steps = 1/' \
  -e 's/^lyapunov_iterates = .*/lyapunov_iterates = 1/' <<< "$analysis")" > "$work/first.toml"
printf '%s\n%s\n' "$body" "$(sed 's/^stages = .*/stages = ["tori"]/' <<< "$analysis")" > "$work/tori.toml"
cat > "$work/sweep.toml" <<EOF
$body
[analysis]
stages = ["sweep"]

[analysis.sweep]
up_range_rpm = [48.10, 48.85]
down_range_rpm = [48.80, 48.85]
speed_step_rpm = 0.05
dwell = 8.0
settle_window = 2.0
settle_windows = 2
analysis_length = 6.0
sample_rate_hz = 2048.0
spectrum_max_hz = 600.0
EOF

echo "# bench/tori_vs_sweep.sh $build, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores"
orbits=$(cpu "$rubcont" run "$work/orbits.toml" --quiet --no-figures --out "$work")
first=$(cpu "$rubcont" run "$work/first.toml" --quiet --no-figures --out "$work")
tori=$(cpu "$rubcont" run "$work/tori.toml" --quiet --no-figures --out "$work")
sweep=$(cpu "$rubcont" sweep "$work/sweep.toml" --direction up --quiet --no-figures --out "$work/sweep.h5")
tori_file="$work/tori/tori.h5"
count=$(/usr/bin/python3 -c "import h5py; print(len(h5py.File('$tori_file')['tori/branch1_hopf2_ns1/speed_rpm']))")
speeds=$(/usr/bin/python3 -c "import h5py; print(len(h5py.File('$work/sweep.h5')['sweeps/up/speed_rpm']))")
echo "CPU seconds (user + system), one run each:"
echo "  orbits  modulated whip, 60 orbits                       $orbits s"
echo "  first   orbits + the first torus (start and one step)   $first s  (the torus: $(awk "BEGIN { print $first - $orbits }") s)"
echo "  tori    orbits + the torus family ($count tori, lines, Lyapunov)  $tori s  (the tori: $(awk "BEGIN { print $tori - $orbits }") s)"
echo "  sweep   $speeds speeds, 48.10-48.85 rpm, 8 s dwell              $sweep s"
echo "  ratio   sweep / torus family (tori - orbits)            $(awk "BEGIN { printf \"%.2f\", $sweep / ($tori - $orbits) }")"
/usr/bin/python3 bench/tori_vs_sweep.py "$tori_file" "$work/sweep.h5"
