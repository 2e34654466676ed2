#!/usr/bin/env bash
# Regenerates everything in results/: the result file (analytic L0, rotating-wave branches L1),
# figures and summary of the
# eight thesis scenes (Kumar 2010, Table 1), of the truly overhung contrast scene and of the
# textbook scenes (periodic orbits by shooting: Duffing, Stuart–Landau, van der Pol, forced van
# der Pol), and the
# thesis-vs-rubcont tables in docs/studies/thesis_comparison.md. Run from anywhere; takes a few seconds after the
# build (most of it is matplotlib).
#   --sweeps        also re-runs the time-marching sweeps (L3) of the eight thesis scenes and of
#                   thesis_A_a_imbalance: 2–16 min per scene (docs/studies/sweeps.md).
#   --sweep-tables  instead re-derives the regimes, jump tables and figures of the committed
#                   results/<scene>/sweep.h5 from their finished speeds, without integrating
#                   (`rubcont sweep --resume` on a complete file; a second or two per scene plus
#                   the figures). Use it after a change of the regime rules. A file whose stored
#                   scene leaves a key to its default that is not a sweep rule (a key added since,
#                   e.g. [analysis.loop]'s in 0.2.0) is integrated again (2–5 min per scene).
#   --orbits        also re-runs the modulated whip of case A(a) (stage "orbits",
#                   scenes/thesis_A_a_modulated_whip.toml and thesis_A_a_whip_doubling.toml):
#                   about 20 min on 2 cores; and on the flexible shafts
#                   (thesis_A_a_modulated_whip_flexible.toml: 19 min of CPU); and case C(a)'s
#                   whip modulated at two frequencies (stages "orbits" and "tori",
#                   scenes/thesis_C_a_tori.toml at K up to 32: about 31 min of CPU, 13.5 of
#                   them the torus a transient settles on at 49 rpm); and its whip locked at
#                   1:3, from a transient at 49.4 rpm (scenes/thesis_C_a_locked.toml: about 9 min of CPU),
#                   and at 3:7, from one at 75 rpm (scenes/thesis_C_a_locked_75.toml: about 6 min),
#                   and at 19:45, from one at 74 rpm (scenes/thesis_C_a_locked_74.toml: about 12 min);
#                   and C(c)'s two-frequency whip as tori in the contact chart
#                   (scenes/thesis_C_c_tori.toml: about 27 min of CPU), C(b)'s
#                   (scenes/thesis_C_b_tori.toml: about 82 min of CPU), the tori from the
#                   Neimark–Sacker point of C(b)'s whip at 53 rpm (scenes/thesis_C_b_tori_53.toml:
#                   about 20 min of CPU), C(b)'s period-1 whip from a transient at 64 rpm
#                   (scenes/thesis_C_b_whip_64.toml: about 2 min of CPU) and C(a)'s from 60 rpm
#                   (scenes/thesis_C_a_tori_60.toml: about 127 min of wall on one core).
#   --attractor     also re-runs what A(a)'s speed-up whip is, 52 → 184 rpm (`rubcont attractor`,
#                   results/thesis_A_a/attractor_*rpm.*: three runs side by side, about 15 min on
#                   2 cores, then the step back down from 134 rpm, about 35 min) and prints the
#                   table of docs/studies/attractors.md "What the whip is"; then what C(a)'s speed-up whip
#                   is at 49–124 rpm (results/thesis_C_a/attractor_*rpm.*: five runs, two side
#                   by side, about 30 min on 2 cores; docs/studies/attractors.md, "C(a)'s speed-up whip,
#                   speed by speed"); then C(b)'s and C(c)'s (results/thesis_C_{b,c}/attractor_*:
#                   four runs, two side by side, about 25 min on 2 cores, then C(b)'s at 53–54.6
#                   rpm both ways, two runs side by side, about 11 min, and down from 60 to 57.6
#                   rpm, about 4 min).
#   --flexible      also re-runs the flexible A(a)'s sweeps and the lifetimes of its speed-up whip
#                   (level L4, results/thesis_A_a_flexible/: about 16 min on 2 cores), then the
#                   flexible B(a)'s and C(a)'s sweeps (30 and 7 min of CPU; 46 min in all, 2026-11-30).
#   --whip-end      also re-runs where A(a)'s speed-up whip ends (`rubcont lifetime`,
#                   results/thesis_A_a_whip_end/lifetime_*rpm.*: 16 copies × 5 s at 174 … 184 rpm
#                   in 1 rpm steps with 4 check sweeps, about 35 min on 2 cores; then 16 × 10 s
#                   at 168, 170 and 172 rpm, about 20 min), B(a)'s (results/thesis_B_a_whip_end/:
#                   186 … 196 rpm, about 33 min), C(a)'s (52 min, then 206 … 216 rpm, 18 min),
#                   B(c)'s (24 min), A(b)'s (35 min), C(b)'s (70 min of CPU), C(c)'s (17 min) and
#                   B(b)'s (22 min; docs/studies/whip_end.md, "The end of the speed-up whip in every case").
#   --loops         also re-runs the loops of the thesis scenes, the imbalanced and the flexible A(a)
#                   (`rubcont loop --schedule 2 1.5 --budget 15`, C(b) and C(c) 40: their lines in
#                   scripts/result_scenes.txt; results/<scene>/loop.{h5,txt,png}:
#                   the budget in work units, so each explains the same corners on any machine and
#                   beside any other job; 3–25 min of CPU each) and writes their table into
#                   results/README.md (scripts/loop_table.py); then run --sweep-tables, whose jump
#                   tables take the whip's end from the loop beside each sweep.
# Every run draws each swept scene's hysteresis loop (results/<scene>/hysteresis.png) from the
# committed sweep files (A(a)'s with its whip-doubling file; each case's with its whip's lifetimes).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel "$(nproc)"

# The sweeps first: `rubcont sweep` also draws the branches next to its file without the closed
# form (its file has no /analytic), and `rubcont run` below draws them again with it.
# The scenes: scripts/result_scenes.txt (scripts/check_results.sh checks the same list).
source scripts/result_scenes.sh  # scenes_of KIND; loop_options_of SCENE: a loop's schedule and budget
mapfile -t sweep_scenes < <(scenes_of sweep)
case "${1:-}" in
  --sweeps) resume=() ;;
  --sweep-tables) resume=(--resume) ;;
  *) sweep_scenes=() ;;
esac
for scene in "${sweep_scenes[@]}"; do
  if [[ ${#resume[@]} -gt 0 && ! -f "results/$scene/sweep.h5" ]]; then
    echo "results/$scene/sweep.h5 is missing: --sweep-tables would integrate it; use --sweeps" >&2
    exit 1
  fi
  build/rubcont sweep "scenes/$scene.toml" "${resume[@]}" --quiet \
    --out "results/$scene/sweep.h5" > "results/$scene/sweep_summary.txt"
  echo "results/$scene: sweeps"
done

mapfile -t scenes < <(scenes_of quick)
if [[ "${1:-}" == "--orbits" ]]; then mapfile -t -O "${#scenes[@]}" scenes < <(scenes_of orbits); fi
for scene in "${scenes[@]}"; do
  summary=$(build/rubcont run "scenes/$scene.toml" --out results --quiet)
  # The summary names files by path; keep it relative so results/ reads the same anywhere.
  printf '%s\n' "$summary" > "results/$scene/summary.txt"
  echo "results/$scene: $(ls "results/$scene" | tr '\n' ' ')"
done
# ε → 0 convergence of the regularized whirl → whip transition (case A(a)), and branch-set timings.
build/bench/branches_bench scenes 5 results/regularization/thesis_A_a.csv \
  > results/regularization/branches_bench.txt
PYTHONPATH=python /usr/bin/python3 -m rubcont.plots.regularization results/regularization/thesis_A_a.csv \
  results/regularization/convergence.png
# Hysteresis maps and the identification example of the default scene (results/design).
mkdir -p results/design
for spec in "friction --range 0.1 1.0" "stator_damping --range 50 2000" "rci_ratio"; do
  name=${spec%% *}
  # shellcheck disable=SC2086  # $spec holds the parameter name and its options
  build/rubcont map scenes/default.toml --parameter $spec --eta-points 41 --quiet \
    --out "results/design/map_$name.h5" > "results/design/map_$name.txt"
done
# The tanh law's Hopf curves in friction (case A(a): where the whirl's speed-up and speed-down
# jumps move with μ), beside the scene's branch set.
build/rubcont map scenes/thesis_A_a_tanh.toml --parameter friction --range 0.3 0.7 --eta-points 41 \
  --quiet > results/thesis_A_a_tanh/map_friction.txt 2>&1 || true  # exit 1: one curve fails (docs/studies/design.md)
build/rubcont fit scenes/default.toml --targets scenes/fits/default_hidden.toml --quiet \
  --out results/design/fit_hidden.h5 > results/design/fit_hidden.txt
# Exit code 1 expected: no friction reproduces the thesis's jump (docs/studies/design.md).
build/rubcont fit scenes/thesis_A_a.toml --targets scenes/fits/thesis_A_a_speed_up_jump.toml \
  --quiet --out results/design/fit_thesis_A_a_jump.h5 > results/design/fit_thesis_A_a_jump.txt 2>&1 || true
echo "results/design: $(ls results/design | tr '\n' ' ')"

# Level L4: the flexible analogues of cases A(a) (both friction laws), B(a), C(a) (shafts fitted
# to the thesis's Tables 2–3) against the rigid model, point by point of the L1 branch sets
# (`rubcont flexible`; results/<scene>/flexible.{h5,txt}, 2 s each).
for scene in thesis_A_a thesis_A_a_tanh thesis_B_a thesis_C_a; do
  build/rubcont flexible "scenes/$scene.toml" --quiet --out "results/$scene/flexible.h5" \
    > "results/$scene/flexible.txt"
done
echo "results/thesis_{A_a,A_a_tanh,B_a,C_a}: flexible.h5 flexible.txt"
# What the whip is (docs/studies/attractors.md, "What the whip is, speed by speed"): three schedules side by
# side, the impacting whip at a tighter tolerance and shorter records.
if [[ "${1:-}" == "--attractor" ]]; then
  attractor() {  # FROM TO then extra options
    local name="results/thesis_A_a/attractor_$1_$2rpm"
    build/rubcont attractor scenes/thesis_A_a.toml --from "$1" --to "$2" --step 4 "${@:3}" --quiet \
      --out "$name.h5" > "$name.txt"
  }
  pids=()
  attractor 52 128 --duration 2 --discard 1 --tolerance 1e-7 & pids+=($!)
  attractor 132 144 --duration 1 --discard 1 --tolerance 1e-7 & pids+=($!)
  attractor 148 184 --duration 0.2 --discard 0.1 --interval 0.002 --tolerance 1e-8 & pids+=($!)
  for pid in "${pids[@]}"; do wait "$pid"; done  # a failing run stops the script (set -e)
  # Back down from the period-2 whip the speed-up sweep reaches (the fold of the doubled orbits).
  down=results/thesis_A_a/attractor_134_119rpm_down
  build/rubcont attractor scenes/thesis_A_a.toml --from 134 --to 119 --step 0.5 --direction down \
    --approach up --duration 1.5 --discard 0.5 --exponents 3 --tolerance 1e-7 --quiet \
    --out "$down.h5" > "$down.txt"
  /usr/bin/python3 scripts/attractor_table.py results/thesis_A_a/attractor_52_128rpm.h5 \
    results/thesis_A_a/attractor_132_144rpm.h5 results/thesis_A_a/attractor_148_184rpm.h5 \
    --orbits results/thesis_A_a_modulated_whip/thesis_A_a_modulated_whip.h5
  # C(a): the torus's end, the chaos and the torus again (49–61 rpm), the smooth whip to its
  # contact loss (62–98 rpm) and the impacting whip around the left contact's departure (100–124).
  attractor_case() {  # CASE (a, b or c) FROM TO STEP DURATION DISCARD
    local name="results/thesis_C_$1/attractor_$2_$3rpm"
    build/rubcont attractor "scenes/thesis_C_$1.toml" --from "$2" --to "$3" --step "$4" \
      --duration "$5" --discard "$6" --tolerance 1e-7 --quiet --out "$name.h5" > "$name.txt"
  }
  attractor_case a 49 60 1 2 1 & first=$!
  attractor_case a 100 124 2 1 0.5 & second=$!
  wait "$first"
  attractor_case a 49 50 0.1 4 2
  attractor_case a 57 61 0.25 4 2
  wait "$second"
  attractor_case a 62 98 4 2 1
  # C(b) and C(c): the whip from its birth to the impacting chaos, then the speeds between.
  attractor_case b 40 112 4 2 1 & first=$!
  attractor_case c 44 112 4 2 1
  wait "$first"
  attractor_case b 52 60 1 4 2 & first=$!
  attractor_case c 48 70 2 4 2
  wait "$first"
  # C(b) where the rotor takes its torus and leaves it (53–54.6 rpm, 0.1 rpm steps): up from the
  # whip the speed-up sweep reaches, and down from the torus (attractors.md, C(b)'s torus).
  attractor_case b 53 54.6 0.1 4 2 & first=$!
  down=results/thesis_C_b/attractor_54.6_53rpm_down
  build/rubcont attractor scenes/thesis_C_b.toml --from 54.6 --to 53 --step 0.1 --direction down \
    --approach up --duration 4 --discard 2 --tolerance 1e-7 --quiet --out "$down.h5" > "$down.txt"
  wait "$first"
  # Down from C(b)'s one-period whip past its Neimark–Sacker point and fold (58.13, 58.05 rpm).
  down=results/thesis_C_b/attractor_60_57.6rpm_down
  build/rubcont attractor scenes/thesis_C_b.toml --from 60 --to 57.6 --step 0.2 --direction down \
    --duration 2 --discard 1 --tolerance 1e-7 --quiet --out "$down.h5" > "$down.txt"
fi
# Level L4 sweeps (docs/studies/flexible.md, "Level L4: does flexibility move the jumps?"): the flexible
# A(a)'s speed-up and speed-down sweeps (16 min on one core) beside the lifetimes of its speed-up
# whip at 152–164 and 161–163 rpm (8 copies × 2 s per speed, 8 and 7 min on one core); then the
# flexible B(a)'s and C(a)'s sweeps side by side (30 and 7 min of wall; 2026-11-30).
if [[ "${1:-}" == "--flexible" ]]; then
  out=results/thesis_A_a_flexible
  mkdir -p "$out"
  build/rubcont sweep scenes/thesis_A_a_flexible.toml --quiet --out "$out/sweep.h5" \
    > "$out/sweep_summary.txt" & sweep_pid=$!
  build/rubcont lifetime scenes/thesis_A_a_flexible.toml --from 152 --to 164 --step 4 --copies 8 \
    --duration 2 --threads 1 --check-copies 0 --quiet --out "$out/lifetime_152_164rpm.h5" \
    > "$out/lifetime_152_164rpm.txt"
  build/rubcont lifetime scenes/thesis_A_a_flexible.toml --from 161 --to 163 --step 1 --copies 8 \
    --duration 2 --threads 1 --check-copies 0 --quiet --out "$out/lifetime_161_163rpm.h5" \
    > "$out/lifetime_161_163rpm.txt"
  wait "$sweep_pid"
  build/rubcont sweep scenes/thesis_B_a_flexible.toml --quiet \
    --out results/thesis_B_a_flexible/sweep.h5 > results/thesis_B_a_flexible/sweep_summary.txt &
  build/rubcont sweep scenes/thesis_C_a_flexible.toml --quiet \
    --out results/thesis_C_a_flexible/sweep.h5 > results/thesis_C_a_flexible/sweep_summary.txt
  wait
fi
if [[ "${1:-}" == "--whip-end" ]]; then
  lifetime() {  # SCENE FROM TO STEP DURATION CHECK-COPIES [ARRIVAL OPTIONS]
    local name="results/$1_whip_end/lifetime_$2_$3rpm"
    mkdir -p "results/$1_whip_end"
    build/rubcont lifetime "scenes/$1_whip_end.toml" --from "$2" --to "$3" --step "$4" --copies 16 \
      --duration "$5" --check-copies "$6" "${@:7}" --quiet --out "$name.h5" > "$name.txt"
  }
  lifetime thesis_A_a 174 184 1 5 4
  lifetime thesis_A_a 168 172 2 10 0
  lifetime thesis_B_a 186 196 1 5 4
  # The unequal-clearance and overhung cases: their whips (80–85 Hz) land on states the regime
  # rules still call whip (250–400 Hz). A contact that barely touches reads 83 or ~340 Hz from one
  # 0.1 s stretch to the next (B(c)'s left at 182 rpm), so the copy has left when every contact
  # is above 150 Hz; in case C the left contact is elsewhere all along: the right one decides.
  lifetime thesis_C_a 201 211 1 5 2 --until-above 150 --until-contacts right
  lifetime thesis_C_a 206 216 1 5 2 --until-above 150 --until-contacts right
  lifetime thesis_B_c 182 194 2 5 2 --until-above 150 --until-contacts every
  lifetime thesis_A_b 158 170 2 5 2 --until-above 150 --until-contacts every
  lifetime thesis_C_b 162 174 2 5 2 --until-above 150 --until-contacts right
  lifetime thesis_C_c 202 214 2 5 2 --until-above 150 --until-contacts right
fi
# The loops, one after the other (each runs its run-up and run-down side by side, then its
# ensembles over both cores), with the options of the `options loop` line of result_scenes.txt or
# those of the scene's own line.
if [[ "${1:-}" == "--loops" ]]; then
  for scene in $(scenes_of loop); do
    read -ra loop_options < <(loop_options_of "$scene")
    build/rubcont loop "scenes/$scene.toml" "${loop_options[@]}" --quiet \
      --out "results/$scene/loop.h5" > "results/$scene/loop.txt"
    echo "results/$scene: loop.h5 loop.txt loop.png"
  done
  /usr/bin/python3 scripts/loop_table.py --write results
fi
# Each swept scene's hysteresis loop, with the crisis of its whip's lifetimes (the file whose
# speeds bracket it); A(a)'s also with its periodic orbits.
for scene in $(scenes_of sweep); do
  extra=()
  case $scene in
    thesis_A_a) extra=(--orbits results/thesis_A_a_whip_doubling/thesis_A_a_whip_doubling.h5
                       --lifetime results/thesis_A_a_whip_end/lifetime_174_184rpm.h5) ;;
    thesis_B_a) extra=(--lifetime results/thesis_B_a_whip_end/lifetime_186_196rpm.h5) ;;
    thesis_A_b) extra=(--lifetime results/thesis_A_b_whip_end/lifetime_158_170rpm.h5) ;;
    thesis_B_b) extra=(--lifetime results/thesis_B_b_whip_end/lifetime_158_170rpm.h5) ;;
    thesis_B_c) extra=(--lifetime results/thesis_B_c_whip_end/lifetime_182_194rpm.h5) ;;
    thesis_C_a) extra=(--lifetime results/thesis_C_a_whip_end/lifetime_206_216rpm.h5) ;;
    thesis_C_b) extra=(--lifetime results/thesis_C_b_whip_end/lifetime_162_174rpm.h5) ;;
    thesis_C_c) extra=(--lifetime results/thesis_C_c_whip_end/lifetime_202_214rpm.h5) ;;
  esac
  # A file not made yet (its --whip-end run not done) is left out of the figure.
  present=()
  for ((i = 0; i < ${#extra[@]}; i += 2)); do
    if [[ -f "${extra[i + 1]}" ]]; then present+=("${extra[i]}" "${extra[i + 1]}"); fi
  done
  PYTHONPATH=python /usr/bin/python3 -m rubcont.plots.hysteresis --sweep "results/$scene/sweep.h5" "${present[@]}" \
    --out "results/$scene/hysteresis.png"
done
/usr/bin/python3 scripts/thesis_comparison.py results --update docs/studies/thesis_comparison.md
echo "docs/studies/thesis_comparison.md: tables updated"
