// What a scene asks of each stage, as the library's options: one function per stage, used by the
// commands, the benchmarks and the tests, so that a stage runs the same way wherever it is called.
#pragma once

#include "apps/scene.h"
#include "models/analytic.h"
#include "models/rub_model.h"
#include "studies/attractor_study.h"
#include "studies/loop.h"
#include "studies/work_plan.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"
#include "waves/rotating_wave_branches.h"
// The orbits and tori stages' (level L2) below.
#include "shooting/modulated_orbit.h"
#include "shooting/modulated_torus.h"
#include "shooting/orbit_branches.h"
#include "shooting/rub_orbits.h"
#include "shooting/rub_tori.h"

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
// test they cost the rub's torus maps 830 000 steps per period against 12 000:
// docs/levels/l2_orbits_tori.md, C(a) at 49 rpm). The schedule and the record are the caller's.
AttractorStudyOptions AttractorStudyOptionsOf(const Scene& scene, SweepDirection approach);

// The loop study's options (studies/loop.h): the scene's sweeps in both directions (their ranges,
// integrators, windows, regime rules, impulse) with their step and dwell as the run's schedule, and
// the branch set of the sweep stage (BranchOptionsOf) as its waves, so that its L1 corners are the
// sweep's jump table's. The budget, the escape design's settings and a schedule given on the command
// line are the caller's.
LoopOptions LoopOptionsOf(const Scene& scene);

// The work the scene's sweeps plan (studies/work_plan.h), counted from its keys before
// SweepOptionsOf makes a schedule: each direction's speeds of [analysis.sweep] dwell, with their
// spectra (SweepSpeedBytes for the model's contacts). Pure bookkeeping of the scene, here beside
// SweepOptionsOf, which it must count alike; the arithmetic and the limits are the library's.
std::vector<PlannedWork> SweepPlanOf(const Scene& scene);
// CopiesWork (studies/work_plan.h) with a sweep speed's reading of the scene's rub structure and
// [analysis.sweep] spectra, over stretches of two `window`s, as the copies keep it.
PlannedWork CopiesWorkOf(const Scene& scene, std::string key, std::string value, std::string what,
                         double runs, double duration, double window);
// The work `stages` plan: the sweeps for "sweep" and "loop" (the loop's run-up and run-down are
// the sweeps' schedule), the loop's budget ([analysis.loop] budget as CPU, at
// kCpuSecondsPerGigaWorkUnit; it counts the runs too and the runs skip speeds along waves, so the
// sum is an upper bound), and the transients
// of [analysis.orbits.transient] and [analysis.tori.transient] (one run of their seconds). The
// other stages' work is bounded by the code (continuation steps, grid points) and not counted.
std::vector<PlannedWork> StagePlanOf(const Scene& scene, const std::vector<Stage>& stages);

// ---------------------------------------------------------------------------------------------
// The orbits and tori stages (level L2: apps/orbits_stage.cpp, apps/tori_stage.cpp).

// The continuation of every orbit family the orbits stage follows: steps up to 1 (scaled), a
// tangent turning 0.3 rad and 5 Newton iterations per step aimed at. Measured in
// bench/duffing_branch_bench.cpp: Newton needs 3 iterations even on tiny steps (the last one
// confirms the step tolerance), so the engine's target of 3 would never let the step grow.
ContinuationOptions OrbitContinuationOptions(int max_steps);

// A textbook model's periodic orbits ([<model>] <parameter>_range, [<model>.orbits]): the range,
// the continuation above, and the scene's segments integrated by `method` (an explicit
// Runge–Kutta pair: of order 8) at its tolerance (rtol = atol on scaled states), sensitivities in
// every residual.
PeriodicOrbitBranchOptions TextbookOrbitOptionsOf(const Scene& scene, IntegrationMethod method);
// The method of a textbook model's orbits: [<model>.orbits] integrator, or `model_default` (the
// model's own) for "model". TextbookOrbitOptionsOf gives Gauss collocation its mesh
// (collocation_intervals per period, shared by the segments).
IntegrationMethod TextbookOrbitMethodOf(const Scene& scene, IntegrationMethod model_default);

// Model two_point's shooting ([analysis.orbits]): its segments per modulation period, each
// integrated by Gauss–Legendre collocation of order 8 on its share of collocation_intervals, or by
// CVODES BDF with the analytic Jacobian and the sensitivities under error control at `tolerance`
// (without that control Newton stalls: the STM's nearly undamped contact mode is damped
// numerically, bench/modulated_whip_bench.cpp; Gauss is 50–70 times cheaper on the thesis's
// contact, docs/studies/orbits.md, "Cost of the modulated whip"); sensitivities in every residual.
ShootingOptions RubShootingOptionsOf(const Scene& scene);

// The modulated orbits from Hopf points ([analysis.orbits]): the first orbit's amplitude, the
// scene's speed range [rad/s], the shooting and continuation above, the end at a grazing
// (at_grazing) (no on_step).
HopfOrbitOptions RubOrbitOptionsOf(const Scene& scene);

// [analysis.orbits.transient]'s first orbit: each lap with the stage's segments and mesh, the
// slip's modulation searched over 1 s (T to ~1e-5 of itself: laps > 1 need it,
// bench/locked_whip_bench.cpp), Newton to the continuation corrector's tolerance, 20 iterations.
ModulatedOrbitOptions TransientOrbitStartOf(const Scene& scene);

// The transient both [analysis.*.transient] sections start from: one speed of the scene's speed-up
// sweep ([analysis.sweep]: integrator, windows) at `speed_rpm` for `seconds`, its forcing not
// rotated (the stages' structure is balanced).
SweepOptions TransientSweepOptionsOf(const Scene& scene, double speed_rpm, double seconds);

// The torus families from Neimark–Sacker points ([analysis.tori]) over the scene's speed range, on
// the engine settings of the orbits. Newton on the circle stops at 0.1 × the Gauss tolerance (its
// own Newton stops at 1e-3 × it, so the map is that smooth) or 100 × the BDF tolerance (the map is
// only as smooth as the error-controlled integration). The map's integrator is the modulated
// family's, set by the library (ContinueModulatedTori).
RubTorusOptions TorusOptionsOf(const Scene& scene);

// [analysis.tori.transient]: its torus's start (SettledTransientStart of its harmonics, refined in
// K up to max_harmonics; with coordinates = "chart" in the contact chart, the map by the orbits'
// Gauss mesh when they use Gauss: CVODES BDF stalled there, Gauss converged), and its
// families' options: those above with the section's Fourier tail, steps and max_harmonics (the
// families refined in K as the start is), and the map by the
// start's CVODES BDF at the orbits' tolerance when the orbits use BDF (with the sensitivities under
// error control a torus's map took 70 times the steps, ModulatedTorusOptions::integrator), else by
// the orbits' Gauss mesh over a whole period.
ModulatedTorusOptions TransientTorusStartOf(const Scene& scene);
RubTorusOptions TransientTorusOptionsOf(const Scene& scene);

}  // namespace rubcont
