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
#pragma once

#include <filesystem>
#include <iosfwd>

#include "apps/scene.h"
#include "solvers/stopwatch.h"
#include "studies/lifetime_study.h"

namespace rubcont {

// Writes the study's result file `file` (its directory created), for the scene it ran. The result
// must hold an estimate (status kComplete or kCopiesFailed).
void WriteLifetimeResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                         const LifetimeStudyResult& result);

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
