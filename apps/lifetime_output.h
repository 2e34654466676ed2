// The lifetime study (studies/lifetime_study.h) on file and on the terminal: its HDF5 file, its
// summary, its progress lines.
//
// HDF5 layout (written atomically): root attributes as every result; /lifetime attributes
// direction, copies, duration, window, perturbation, seed, until, until_contacts (absent in
// files made before it: every), until_above_hz and arrival (the target in words; both absent in
// files made before them: 0, by regime), approach_from_rpm /
// approach_to_rpm, wall_seconds, cpu_seconds, threads; datasets speed_rpm, escapes, stayed, failed,
// untrusted (copies with a stretch beyond [analysis.sweep] max_penetration before they arrived,
// RubArrival::untrusted; absent in files made before it), escape_rate (1/s; +inf: every copy in its first stretch), rate_lower, rate_upper, rate_status
// ("estimated", "no escape", "all in the first stretch"), arrival_time_s (speeds × copies; NaN:
// stayed); /lifetime/crisis attributes status, message, critical_speed_rpm, critical_lower_rpm,
// critical_upper_rpm, lower_bounded, upper_bounded (0/1), exponent, amplitude (1/s per rpm^γ),
// log_likelihood; /lifetime/check (when check_copies > 0) attributes dwell, step_rpm; datasets
// speed_rpm (the schedule), predicted_leave_probability (per speed), jump_speed_rpm (per copy:
// the speed at which it arrived; NaN: kept the state to the end), jump_time_s.
//
// The checkpoint `<stem>.checkpoint.h5` beside the result file (written atomically after the
// approach and after each speed, removed when the result is written): root attributes as every
// result; /checkpoint attribute `request` (the options that decide the numbers, as text);
// /checkpoint/approach: datasets state, speed_rad_s, regimes, attribute message;
// /checkpoint/speed<i> (i = 0, 1, … in the schedule's order): attributes speed_rpm, stretch,
// duration, stayed, failed, untrusted, first_untrusted_copy, first_untrusted, wall_seconds;
// datasets escape_stretch, arrival_time_s, failure_copy, failure_message.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "apps/scene.h"
#include "solvers/stopwatch.h"
#include "studies/lifetime_study.h"

namespace rubcont {

// Writes the study's result file `file` (its directory created), for the scene it ran. The result
// must hold an estimate (status kComplete or kCopiesFailed).
void WriteLifetimeResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                         const LifetimeStudyResult& result);

// `<stem>.checkpoint.h5` next to the result file `h5_file`.
std::filesystem::path LifetimeCheckpointPath(const std::filesystem::path& h5_file);

// Writes what a study of `scene` has finished (LifetimeStudyProgress::finished) to `file`;
// `request` names the options that decide its numbers (a resumed study must have the same).
void WriteLifetimeCheckpoint(const std::filesystem::path& file, const Scene& scene, const std::string& request,
                             const SweepApproach& approach, const std::vector<SpeedEscapes>& escapes);

// Reads a checkpoint written for this scene and request; nothing when `file` does not exist.
// Throws std::invalid_argument when it was written for another scene or other options,
// std::runtime_error when it is unreadable.
std::optional<LifetimeStudyStart> ReadLifetimeCheckpoint(const std::filesystem::path& file, const Scene& scene,
                                                         const std::string& request);

// The summary on `out`, ending in "wrote <file>".
void PrintLifetimeSummary(std::ostream& out, const Scene& scene, const RubStructure& structure,
                          const LifetimeStudyResult& result, const std::filesystem::path& file);

// "rubcont: numerical failure: <rpm> rpm, copy <c>: <message>" (and "check sweep <c>: ...") on
// `err` for each failed copy.
void PrintLifetimeFailures(std::ostream& err, const LifetimeStudyResult& result);

// Progress lines on `err`: the approach's speeds, the copies, each speed's rate, with the seconds
// since `start`.
LifetimeStudyProgress PrintLifetimeProgress(std::ostream& err, SteadyClock::time_point start);

}  // namespace rubcont
