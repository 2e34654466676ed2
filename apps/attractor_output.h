// The attractor study (studies/attractor_study.h) on file and on the terminal: its HDF5 file, its
// summary, its progress lines.
//
// HDF5 layout (written atomically): root attributes as every result (scene_toml, level "L3", ...);
// /attractor attributes direction, approach, duration, discard, interval, sample_interval,
// exponents, blocks, zero_tolerance, integrator, relative_tolerance, absolute_tolerance,
// approach_from_rpm / approach_to_rpm (NaN without an approach), wall_seconds; datasets (one row
// per speed) speed_rpm, exponents and standard_errors [speeds × k, 1/s], zero_exponents,
// positive_exponents, section_period (RubSectionPeriod, 0: none), motion (RubMotion), status,
// message, untrusted (UntrustedSection: why, or ""; absent in files made before it),
// counted_s, cpu_seconds, steps; per contact the section, one entry per point in speed order:
// section_speed_rpm_<contact>, section_time_s_<contact> (from the start of the counted record),
// section_penetration_<contact> [m], section_normal_force_<contact> [N]; and per speed i
// /attractor/running/<i> [k × intervals]: the running estimates, with running_time_s.
#pragma once

#include <filesystem>
#include <iosfwd>

#include "apps/scene.h"
#include "solvers/stopwatch.h"
#include "studies/attractor_study.h"

namespace rubcont {

// Writes the study's result file `file` (its directory created), for the scene it ran
// (AttractorSceneOf).
void WriteAttractorResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                          const AttractorStudyResult& result);

// The summary on `out`, ending in "wrote <file>", and each failed speed on `err` ("rubcont:
// numerical failure at <rpm> rpm: <message>").
void PrintAttractorSummary(std::ostream& out, std::ostream& err, const Scene& scene,
                           const RubStructure& structure, const AttractorStudyResult& result,
                           const std::filesystem::path& file);

// Progress lines on `err`: the approach's speeds, each speed's integration every tenth of its
// time, and each speed's verdict.
AttractorStudyProgress PrintAttractorProgress(std::ostream& err, SteadyClock::time_point start);

}  // namespace rubcont
