// The work a stage plans before it starts, estimated from its options, and the plan check that
// refuses what no real study asks (docs/robustness.md, "The plan check"): a sweep over [20, 1e9]
// rpm planned 250 M speeds and grew to 3.6 GB before its first speed (issue 50). The estimate is
// counting, not timing: speeds × dwell, copies × duration, grid cells, and the CPU that time
// marching costs per simulated second on this machine. The commands build the plan from their
// scene and options (apps/stage_options.h, SweepPlanOf) and refuse it with exit 2 unless --force.
#pragma once

#include <string>
#include <vector>

namespace rubcont {

// CPU seconds per simulated second of the rub's time marching (the sweeps, the copies of
// ensembles and lifetimes, the loop's runs), for the estimate only. Measured on this 2-core
// machine: the committed sweeps (results/<scene>/sweep.h5, the sum of /sweeps/<dir>/wall_seconds
// over that of simulated_time; wall seconds of a loaded machine, so at least the CPU) ran at 1.3
// (B(a) up) … 7.3 (A(a) up) … 17 (B(a) flexible, down) seconds per simulated second, single
// speeds up to 64; A(a)'s up sweep over 150–162 rpm took 4.75 s of CPU for 3.0 s simulated on
// 2026-11-28 (1.6). 10 is a whip's typical cost: the estimate is right to a factor of ten, which
// the limits (WorkLimits) leave room for a hundred times over.
inline constexpr double kCpuSecondsPerSimulatedSecond = 10.0;

// CPU seconds per G work units (IntegrationStatistics::work, solvers/ode.h), for the loop's budget
// in the estimate only: the committed loops took 75–94 s of CPU per G on this machine (2026-11-30, two
// at a time; A(a) 9.67 G in 763 s).
inline constexpr double kCpuSecondsPerGigaWorkUnit = 80.0;

// One item of a plan: what one key or option asks for.
struct PlannedWork {
  std::string key;    // the scene key or command-line option that sets its size, e.g.
                      // "analysis.sweep.up_range_rpm" or "--copies"
  std::string value;  // its value as the user gave it, e.g. "[20, 1e+09] in steps of 4 rpm"
  std::string what;   // what is counted, e.g. "speeds of the speed-up sweep"
  double items = 0.0;              // speeds, grid cells or copy runs (≥ 0)
  double simulated_seconds = 0.0;  // time marched in all [s] (0: none)
  double cpu_seconds = 0.0;        // estimated CPU [s]
  // How cpu_seconds was estimated, where not from simulated_seconds (kCpuSecondsPerSimulatedSecond),
  // e.g. "80 s per G work units"; messages say it.
  std::string cpu_basis;
  double memory_bytes = 0.0;       // the arrays its result keeps in memory [bytes]
};

// What no real study reaches and an absurd input does. The largest committed study by these
// estimates (docs/robustness.md, "The plan check"): A(a)'s lifetime over 174–184 rpm
// (scripts/regenerate-results.sh --whip-end): 176 copy runs of 5 s and 84 check-sweep speeds,
// ≈ 1.4e4 s of CPU with its approach, 40 MB; the loops with the thesis's schedule 120 speeds a
// direction and 4.2e3 s; the maps 41 branch sets and 0.4 MB. The limits lie 5 700, 44 and 100
// times above them.
struct WorkLimits {
  double max_items = 1e6;               // speeds, cells or copy runs of one item; > 0
  double max_cpu_seconds = 7 * 86400.0;  // a week of estimated CPU [s]; > 0
  double max_memory_bytes = 4e9;        // [bytes], a sixth of this machine's 23 GB; > 0
};
// Throws std::invalid_argument naming the field, value and rule.
void Validate(const WorkLimits& limits);

// `runs` runs of time marching of `seconds` each (a sweep's speeds × its dwell, an ensemble's
// copies × their duration), each keeping `bytes_per_run`; `cost_factor` (≥ 1) scales the CPU of
// a simulated second (the attractor's tangents: 1 + exponents).
PlannedWork MarchingWork(std::string key, std::string value, std::string what, double runs,
                         double seconds, double bytes_per_run, double cost_factor = 1.0);

// The arrays one sweep speed keeps: each contact's amplitude spectrum over |f| ≤ band_hz at the
// resolution 1/analysis_length [s] (2·band·length + 1 doubles), plus 1 kB of measures and
// statistics. The A(a) sweep's /sweeps/up holds 11 158 bytes per speed with two contacts, band
// 600 Hz and 0.5 s (this gives 10 640).
double SweepSpeedBytes(int contacts, double band_hz, double analysis_length);

// A sweep from `from_rpm` to `to_rpm` in steps of `step_rpm` (SpeedCount speeds; the schedule
// itself, two doubles a speed, counts as memory), each marched for `dwell` s and keeping
// `bytes_per_speed`. `key` names the range (its value "[lo, hi] in steps of S rpm").
PlannedWork SweepWork(std::string key, std::string what, double from_rpm, double to_rpm,
                      double step_rpm, double dwell, double bytes_per_speed);

// `runs` perturbed copy runs of `duration` s each (an ensemble's copies, a lifetime's copies at
// each speed, its check sweeps' speeds), each keeping one sweep speed's reading (`bytes_per_stretch`)
// per stretch of two `window`s: ⌈duration / (2·window)⌉ stretches, StretchCount (sweeps/rub_runs.h)
// in doubles, since a refused plan may count more than an int holds.
PlannedWork CopiesWork(std::string key, std::string value, std::string what, double runs,
                       double duration, double window, double bytes_per_stretch);

// A hysteresis map of `eta_points` × `speed_points` (studies/hysteresis_map.h): one branch set per
// grid value of the parameter (the items; its CPU is not estimated: at most 2000 of them, the
// default scene's 41 took 1.1 s), and per cell the stable count and one count per pattern (mode1,
// mode2, left_only, right_only): five ints.
PlannedWork MapWork(std::string key, std::string value, int eta_points, int speed_points);

// The first item of `plan` over a limit, as one sentence naming its key, its value, what it
// plans and the estimate against the limit; else, when the plan's CPU or memory in all is over
// its limit, the item that contributes most; empty when the plan is within the limits.
std::string ExcessiveWork(const std::vector<PlannedWork>& plan, const WorkLimits& limits = {});

// "2.5e+08 speeds of the speed-up sweep, 1.9e+08 s simulated, ≈ 1.9e+09 s of CPU (60 years),
// 2.7e+12 bytes".
std::string Describe(const PlannedWork& work);

}  // namespace rubcont
