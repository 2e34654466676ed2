// The sweep stage of a scene (level L3) on file: the /sweeps part of a result file, the checkpoints
// that let an interrupted sweep resume, and the sweep-driven commands' options (the runs
// themselves are sweeps/rub_runs.h's, their options from the scene apps/stage_options.h's).
//
//   /sweeps/up, /sweeps/down     attrs direction, level = "L3", status ("complete" | "partial" |
//                                "failure"), speeds_planned, wall_seconds, integrator, max_order,
//                                relative_tolerance, absolute_tolerance and every [analysis.sweep]
//                                setting (the run is reproducible from them and /scene_toml)
//     speed_rpm                                      one value per finished speed, in sweep order
//     precession_hz_left|right      BP [Hz]: minus the refined dominant negative frequency of
//                                   d_k = u_rk − u_sk over the analysed stretch (NaN: no peak)
//     precession_amplitude_left|right   its amplitude [m]
//     slip_velocity_left|right      mean slip velocity V [m/s] over the samples in contact (NaN: none)
//     slip_velocity_min_left|right, slip_velocity_max_left|right
//     slip_ratio_left|right         |mean V| / (R ω): the input of the rolling rule (NaN: no contact)
//     normal_force_left|right       mean N [N] over the samples in contact; normal_force_max_*
//     penetration_max_left|right    largest penetration δ [m] over the samples in contact (absent
//                                   in files made before it)
//     untrusted                     per speed: why its integration is not to be trusted ("" when
//                                   it is): a penetration beyond max_penetration × the clearance
//     contact_fraction_left|right   share of the analysed samples in contact
//     orbit_radius_left|right       mean |d_k| [m]
//     regime_left|right             "whirl" | "whip" | "intermittent" | "no_contact" | "unknown":
//                                   rolling decided by slip_ratio, BP as the check; intermittent:
//                                   in contact for less than min_contact_fraction of the time
//                                   (sweeps/rub_sweep.h)
//     status                        "settled" | "not settled" | "integration failure"; settled (0/1)
//     windows, simulated_time [s], spectrum_change, frequency_change [Hz] (the last settle test),
//     wall_seconds, steps, rhs_evaluations, jacobian_evaluations, linear_solver_setups,
//     newton_iterations (= dense linear solves), error_test_failures, convergence_failures, message
//     spectrum_frequency_hz         [m] two-sided, |f| ≤ spectrum_max_hz
//     spectrum_magnitude_left|right [speeds × m] amplitude spectra [m] (the waterfall)
//     jumps/{contact, kind, speed_from_rpm, speed_to_rpm, precession_from_hz, precession_to_hz,
//            settled, trusted}
//
// The sweep stage also writes /sweeps/branches (the L1 branches of the tanh law the sweeps
// integrate, layout of apps/branch_output.h) and the jump table:
//
//   /sweeps/jump_table   one row per jump (studies/jump_prediction.h), speed-up jumps first
//                        (attrs level "L3 with L1", rule)
//     direction ("up" | "down"), contact, kind (RubJumpKind), speed_from_rpm, speed_to_rpm,
//     precession_from_hz, precession_to_hz       the jump as the sweep saw it (sweeps/rub_sweep.h)
//     settled            1 when both speeds settled, 0 when one ran to its dwell (RubSweepJump)
//     trusted            1 when neither speed is untrusted, 0 otherwise (RubSweepJump)
//     matched_side       "departure" | "landing" | "none": the state whose branch predicts the jump
//                        (without a prediction: the state that lies on a branch, if any)
//     branch             the branch it lies on ("" for none); branch_stable: 1 / 0 / −1 unknown,
//                        at that speed
//     bifurcation        SpecialPoint::Name() of the predicting point ("" for none); for a jump
//                        the waves leave open that the scene's loop (loop.h5 beside the file, made
//                        for the same structure) decided at L3, "crisis of a chaotic whip (L3,
//                        loop.h5): this schedule leaves it at <median> rpm, 5–95 % …", its
//                        bifurcation_speed_rpm that median for this sweep's own schedule and dwell
//     bifurcation_speed_rpm, bifurcation_precession_hz   where the branches put it (NaN for none)
//     difference_rpm     jump speed − bifurcation speed, the jump speed being the middle of
//                        [speed_from, speed_to] (± half a step); NaN for none
//
// A checkpoint file holds the same group for the finished speeds plus /checkpoint/state (the state
// to continue from) and the resolved scene; it is rewritten atomically after every speed.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "solvers/stopwatch.h"
#include "studies/jump_prediction.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {

// ApproachSweep's progress (sweeps/rub_runs.h) on `err`, one line per speed: "rubcont: [<tag>]
// approach <direction> <rpm> rpm (<done>/<speeds>, <seconds since start> s)".
std::function<void(const SweepRun& run)> PrintApproachProgress(std::ostream& err, const std::string& tag,
                                                               SteadyClock::time_point start);

// The sweep direction named by option `option` ("up" or "down"); throws std::invalid_argument
// naming the option, the value and the rule.
SweepDirection ParseDirection(const char* option, const std::string& value);

// The options of RunRubCopies (sweeps/rub_runs.h) as a command takes them (--copies, --window, --duration,
// --perturbation, --threads); throws std::invalid_argument naming the option, value and rule.
void CheckCopyOptions(int copies, double window, double duration, double perturbation, int threads);

// The target (RubArrivals) named by the options --until (whirl, whip, intermittent, no_contact),
// --until-above (a precession in Hz; 0: by regime) and --until-contacts (every, any or a contact's
// name); throws std::invalid_argument naming the option, the value and the rule.
ArrivalTarget ParseUntil(const RubStructure& structure, const std::string& regime, double above_hz,
                         const std::string& contacts);
// The options --until-contacts and --until-above that ParseUntil reads as `target`: "every", "any"
// or the contact's name; the precession threshold [Hz], 0 when by regime. (--until is
// ToString(target.regime).)
std::string UntilContacts(const RubStructure& structure, const ArrivalTarget& target);
double UntilAboveHz(const ArrivalTarget& target);

// Writes /sweeps/<direction> for the points finished so far of `run`, a sweep of `scene`.
void WriteSweep(ResultWriter& writer, const Scene& scene, const SweepRun& run);

// The points of /sweeps/<direction> read back (what resuming needs; bins of the peaks are not
// stored). Throws std::runtime_error when the group is missing or malformed.
std::vector<SweepPoint> ReadSweepPoints(const ResultReader& reader, SweepDirection direction);

// Writes the checkpoint of `run`, a sweep of `scene` (its finished speeds that did not fail, and
// the state), atomically to `file`.
void WriteSweepCheckpoint(const std::filesystem::path& file, const Scene& scene, const SweepRun& run);

struct SweepCheckpoint {
  std::vector<SweepPoint> points;
  Vector state;
};
// Reads a checkpoint written for this scene and direction; nothing when `file` does not exist.
// Throws std::invalid_argument when it was written for another scene (or other settings) or
// direction, std::runtime_error when it is unreadable.
std::optional<SweepCheckpoint> ReadSweepCheckpoint(const std::filesystem::path& file,
                                                   const Scene& scene, SweepDirection direction);

// The finished speeds of /sweeps/<direction> in an earlier result file `file` of this scene (same
// settings): nothing when the file does not exist, holds no such group, or was written for another
// scene or other settings. A one-direction run carries the other direction over from it, and
// --resume takes a complete direction from it instead of running it again.
// "Same settings" (here and for checkpoints) leaves out the keys that only classify the finished
// speeds (rolling_slip_tolerance, rolling_micro_slip, whirl_tolerance, frequency_jump_hz,
// max_penetration):
// `rubcont sweep --resume` on a complete file re-derives its regimes, jump table and figures
// under the scene's current rules (and the current code's) without integrating again.
std::optional<std::vector<SweepPoint>> ReadFinishedSweep(const std::filesystem::path& file,
                                                         const Scene& scene, SweepDirection direction);

// The result file of a study driven by sweeps (lifetime, attractor, ensemble), to be committed
// when complete: its directory created, the scene's root attributes and level (ResultLevel of L3)
// written, and the group `group` created.
std::unique_ptr<ResultWriter> OpenStudyResult(const std::filesystem::path& file, const Scene& scene,
                                              const std::string& group);
// The attributes approach_from_rpm and approach_to_rpm of `group`: the first and the last speed of
// the approach (NaN: none).
void WriteApproachSpeeds(ResultWriter& writer, const std::string& group, const SweepApproach& approach);

// Writes /sweeps/jump_table (layout above).
void WriteJumpTable(ResultWriter& writer, const std::vector<PredictedJump>& rows);

// `<stem>.<direction>.checkpoint.h5` next to the result file `h5_file`.
std::filesystem::path CheckpointPath(const std::filesystem::path& h5_file, SweepDirection direction);

}  // namespace rubcont
