// The loop study's result file and summary (`rubcont loop`, stage "loop"; studies/loop.h).
//
// HDF5 layout (written atomically), beside the root attributes of every result:
//   /loop                 attrs status, message, step_rpm, dwell_s (the run's schedule),
//                         budget_g_work_units, g_work_units (what the budget counted), cpu_seconds,
//                         wall_seconds, levels (the levels that decided corners, e.g.
//                         "L1, L3"; L4 for a flexible scene)
//     corners/            one row per jump of the loop, run-up first, each direction in speed order:
//       direction ("up" | "down"), kind (RubJumpKind), contact ("left", "right", "left, right"),
//       speed_rpm (where the run jumps: the bifurcation, or the median of a jump by chance),
//       lower_rpm, upper_rpm and interval (what they are: the point at ε and at ε/10; the run's
//       5–95 % for its schedule; the run's step when nothing explains it), cause, level ("L1",
//       "L3"; "" when not explained), evidence (the dataset that shows it), cpu_seconds (spent on
//       deciding it beyond the waves and the tracker), crisis_lower_rpm, crisis_upper_rpm (p_c's
//       95 % interval of a crisis; NaN where the data do not bound it), note (the numbers and what
//       was tried), seen_from_rpm, seen_to_rpm, precession_from_hz, precession_to_hz (the jump as
//       the tracker saw it)
//     decisions           every escalation and why, in order (strings)
//     branches/           the rotating waves of the tanh law (layout of apps/branch_output.h)
//     runs/up, runs/down  the tracker: schedule_rpm (every speed of the run), speed_rpm (those
//                         integrated), regime_<c>, precession_hz_<c>, contact_fraction_<c>,
//                         settled (1/0); attrs end (where the run ends), message, cpu_seconds;
//                         skips/{from_rpm, to_rpm, branch, limit} (the stretches L1 decided)
//     orbits/<k>          L2's question k (a corner's `orbits` index; the evidence "orbits/<k>/…"):
//                         the family of the orbit found (apps/orbit_output.h's layout: speed_rpm,
//                         precession_hz, stable, multipliers, special_points/…; only attributes when
//                         no orbit converged), attrs direction, seen_from_rpm, seen_to_rpm, orbit_rpm
//                         (where the orbit was shot from: the departure, or the route's state), route
//                         (1: the departure is no orbit, the route's), tries (the route's starts),
//                         converged, start_message, skeleton (where the stable state the run rides ends)
//     orbits/<k>_pd1      the doubled family (period 2T) from the period doubling the run meets on
//                         orbits/<k>, same layout; attrs doubling_rpm, period_doubling_multiplier,
//                         start_message
//     escapes/<k>         the escape design of corner k's jump (sweeps/escape_design.h): attrs
//                         direction, seen_from_rpm, seen_to_rpm, target, status, message,
//                         median_rpm, low_rpm, high_rpm (5 / 50 / 95 % of the leave speed),
//                         median_lower_rpm, median_upper_rpm, median_open, critical_rpm,
//                         critical_lower_rpm, critical_upper_rpm, lower_bounded, upper_bounded,
//                         exponent, amplitude (1/s per rpm^γ), crisis_status, cost_cpu_seconds,
//                         rounds; datasets speed_rpm, copies, duration_s, escapes, stayed (per
//                         ensemble), stretch_s, rate, rate_lower, rate_upper (1/s, per
//                         ensemble), escape_stretch (every escaped copy's stretch, ensemble after
//                         ensemble: `escapes` of them each),
//                         schedule_rpm, leave_probability (per speed of the run), log (strings)
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include "apps/hdf5_file.h"
#include "apps/models.h"
#include "apps/scene.h"
#include "solvers/stopwatch.h"
#include "studies/loop.h"

namespace rubcont {

// The file of `rubcont loop` (atomically), and the /loop group of any result file (the stage "loop").
void WriteLoopResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                     const LoopOptions& options, const LoopResult& result);
void WriteLoop(ResultWriter& writer, const Scene& scene, const RubStructure& structure, const LoopOptions& options,
               const LoopResult& result);

// The table first (one line per corner), then each corner's numbers, where each run ends and the cost.
void PrintLoopSummary(std::ostream& out, const Scene& scene, const LoopOptions& options, const LoopResult& result);

// The stage "loop" of `rubcont run`: the study with the scene's options ([analysis.sweep]'s
// schedule, [analysis.loop]) over one thread per core, into /loop of the run's file; a run that
// failed to integrate is a failure of the stage.
void RunLoopStage(const Scene& scene, StageContext& context);

// The jumps a loop file decided at L3 (a crisis), with their ensembles: what a sweep of the same
// structure needs to take the cause of its own jumps from the loop (SweepJumpsByLoop).
struct LoopCrisis {
  std::string direction;
  std::string kind;
  std::string contact;  // "left", "right", "left, right"
  double seen_from_rpm = 0.0;
  double seen_to_rpm = 0.0;
  std::vector<EscapeObservations> observations;
};
// Nothing when `file` does not exist or was made for another structure (model, parameters,
// contacts and friction law, compared exactly); throws std::runtime_error when it is unreadable.
std::vector<LoopCrisis> ReadLoopCrises(const std::filesystem::path& file, const Scene& scene);

// A sweep's jumps that the waves leave open, explained by a loop's crisis of the same direction, kind
// and contact whose jump it overlaps (within `reach_rpm`): the crisis law refitted to the loop's
// ensembles and the speed this sweep's own schedule (`schedule_rpm` per direction, `dwell` s per
// speed) is predicted to leave at — its median, with the 5–95 % range in the bifurcation's name. A
// jump outside that range (up to the schedule's end where 95 % is not reached) is left open.
void SweepJumpsByLoop(std::vector<PredictedJump>& table, const std::vector<LoopCrisis>& crises,
                      const std::vector<double>& up_schedule_rpm, const std::vector<double>& down_schedule_rpm,
                      double dwell, double reach_rpm, const std::string& file_name);

// The study's progress on `err`: its decisions, and a line per tracked speed every 10 speeds.
LoopProgress PrintLoopProgress(std::ostream& err, SteadyClock::time_point start);

}  // namespace rubcont
