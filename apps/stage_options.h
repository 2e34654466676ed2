// What a scene asks of each stage, as the library's options: one function per stage, used by the
// commands, the benchmarks and the tests, so that a stage runs the same way wherever it is called.
#pragma once

#include "apps/scene.h"
#include "models/analytic.h"
#include "models/rub_model.h"
#include "studies/attractor_study.h"
#include "studies/loop.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

// The closed form's precession grid: [analysis] precession_range_hz and precession_points.
AnalyticOptions AnalyticOptionsOf(const Scene& scene);

// The rub structure of a rub scene (model two_point or jeffcott). Throws std::invalid_argument for
// any other model.
RubStructure StructureOf(const Scene& scene);
// The friction law a rub scene's rotating waves use ([contact.friction_law] kind).
FrictionLawKind FrictionLawOf(const Scene& scene);

// The rotating-wave branch set's options: its speed_range_rpm and the top of its
// precession_range_hz.
RotatingWaveBranchOptions BranchOptionsOf(const Scene& scene);

// A command's --threads: checked (0 … 1024; std::invalid_argument naming the option otherwise) and
// resolved (0: one per core, ThreadsFor).
int ThreadsOption(int requested);

// The two-point parameters of a scene, for what is defined on them (`rubcont map` and `rubcont
// fit` vary and identify TwoPointParams fields). Throws std::invalid_argument naming `user` and the
// scene's model for any other model, and for a scene with [flexible] (level L4).
const TwoPointParams& TwoPointParamsOf(const Scene& scene, const char* user);

// The structure a sweep integrates: the two-point rotor's. Throws std::invalid_argument naming the
// scene's model for any other.
RubStructure SweepStructureOf(const Scene& scene);
// The library options of one direction of the scene's sweep (speeds in rad/s), and its regime rule.
SweepOptions SweepOptionsOf(const Scene& scene, SweepDirection direction);
RubRegimeOptions RegimeOptionsOf(const Scene& scene);
// All of one direction of the scene's sweep as sweeps/rub_runs.h runs it: SweepOptionsOf,
// RegimeOptionsOf and the impulse.
RubSweepOptions RubSweepOptionsOf(const Scene& scene, SweepDirection direction);

// The scene as the attractor study runs it: its sweeps integrated by CVODES BDF whatever its
// [analysis.sweep] integrator, since the Lyapunov exponents integrate the variational equations as
// forward sensitivities, which Odeint's Dormand–Prince does not (the committed attractor runs were
// made so); the approach uses the same integrator. `rubcont attractor` records this scene.
Scene AttractorSceneOf(const Scene& scene);
// The attractor study's options from the scene (AttractorSceneOf): the approach sweep in
// `approach` and the exponents' integrator, the sweep's BDF at its tolerances with the tangents
// (sensitivities) outside the error test, as the committed attractor runs were made (in the error
// test they cost the rub's torus maps 830 000 steps per period against 12 000: README.md, C(a) at
// 49 rpm). The schedule and the record are the caller's.
AttractorStudyOptions AttractorStudyOptionsOf(const Scene& scene, SweepDirection approach);

// The loop study's options (studies/loop.h): the scene's sweeps in both directions (their ranges,
// integrators, windows, regime rules, impulse) with their step and dwell as the run's schedule, and
// the branch set of the sweep stage (BranchOptionsOf) as its waves, so that its L1 corners are the
// sweep's jump table's. The budget, the escape design's settings and a schedule given on the command
// line are the caller's.
LoopOptions LoopOptionsOf(const Scene& scene);

}  // namespace rubcont
