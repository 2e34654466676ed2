// The ensemble study (studies/ensemble_study.h) on file and on the terminal: its HDF5 file, its
// summary, its progress lines.
//
// HDF5 layout (written atomically): root attributes as every result (scene_toml, level "L3", ...);
// /ensemble attributes speed_rpm, direction, copies, duration, window, perturbation, seed, until,
// until_contacts (absent in files made before it: every), until_above_hz and arrival (the target
// in words; both absent in files made before them: 0, by regime),
// approach_from_rpm / approach_to_rpm (NaN without an approach), approach_regime_left/_right,
// wall_seconds, threads; datasets (one entry per copy) arrival_time_s (NaN: not reached),
// reached, failed, untrusted (why the copy is untrusted, RubArrival::untrusted, or ""; absent in
// files made before it), simulated_s, cpu_seconds; time_s (the end of each stretch); matrices copies ×
// stretches precession_hz_<contact>, contact_fraction_<contact>, slip_velocity_<contact> and
// regime codes regime_<contact> (the RubRegime order: 0 unknown, 1 no_contact, 2 intermittent,
// 3 whirl, 4 whip).
#pragma once

#include <filesystem>
#include <iosfwd>

#include "apps/scene.h"
#include "solvers/stopwatch.h"
#include "studies/ensemble_study.h"

namespace rubcont {

// Writes the study's result file `file` (its directory created), for the scene it ran.
void WriteEnsembleResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                         const EnsembleStudyResult& result);

// The summary on `out`, ending in "wrote <file>".
void PrintEnsembleSummary(std::ostream& out, const Scene& scene, const RubStructure& structure,
                          const EnsembleStudyResult& result, const std::filesystem::path& file);

// "rubcont: numerical failure: copy <c>: <message>" on `err` for each failed copy.
void PrintEnsembleFailures(std::ostream& err, const EnsembleStudyResult& result);

// Progress lines on `err`: the approach's speeds and the copies, with the seconds since `start`.
EnsembleStudyProgress PrintEnsembleProgress(std::ostream& err, SteadyClock::time_point start);

}  // namespace rubcont
