#include "apps/stage_options.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/core.h>

#include "apps/models.h"
#include "models/units.h"
#include "solvers/parallel.h"

namespace rubcont {

AnalyticOptions AnalyticOptionsOf(const Scene& scene) { return scene.analysis.analytic; }

namespace {

const ModelEntry& RubModelOf(const Scene& scene) {
  const ModelEntry& model = ModelOf(scene);
  if (!model.IsRub()) {
    std::string rub;
    for (const ModelEntry& m : Models()) rub += m.IsRub() ? (rub.empty() ? "" : ", ") + m.name : "";
    throw std::invalid_argument(fmt::format(
        "model = \"{}\" in scene {}: rotating waves need a rub model ({})", model.name,
        scene.name, rub));
  }
  return model;
}

}  // namespace

RubStructure StructureOf(const Scene& scene) { return RubModelOf(scene).structure(scene); }

FrictionLawKind FrictionLawOf(const Scene& scene) { return RubModelOf(scene).wave_friction(scene); }

int ThreadsOption(int requested) {
  if (requested < 0 || requested > 1024) {
    throw std::invalid_argument(fmt::format("--threads = {}: must be in 0 … 1024", requested));
  }
  return ThreadsFor(requested);
}

RotatingWaveBranchOptions BranchOptionsOf(const Scene& scene) {
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(scene.analysis.speed_range_rpm[0]);
  options.search.speed_max = RpmToRadPerSecond(scene.analysis.speed_range_rpm[1]);
  options.search.precession_max = HzToRadPerSecond(scene.analysis.analytic.max_precession_hz);
  return options;
}

const TwoPointParams& TwoPointParamsOf(const Scene& scene, const char* user) {
  if (scene.model != ModelKind::kTwoPoint) {
    throw std::invalid_argument(fmt::format("model = \"{}\" in scene {}: {} needs the two_point "
                                            "model", ToString(scene.model), scene.name, user));
  }
  if (scene.flexible.enabled) {
    throw std::invalid_argument(fmt::format(
        "[flexible] in scene {}: {} varies the rigid model's parameters; remove [flexible] (level "
        "L4 is not yet mapped or fitted)", scene.name, user));
  }
  return scene.two_point;
}

SweepOptions SweepOptionsOf(const Scene& scene, SweepDirection direction) {
  const SweepSettings& s = scene.analysis.sweep;
  SweepOptions o;
  const std::vector<double> rpm =
      direction == SweepDirection::kUp
          ? SpeedSchedule(s.up_range_rpm[0], s.up_range_rpm[1], s.speed_step_rpm)
          : SpeedSchedule(s.down_range_rpm[1], s.down_range_rpm[0], s.speed_step_rpm);
  for (double v : rpm) o.parameters.push_back(RpmToRadPerSecond(v));
  o.dwell = s.dwell;
  o.window = s.settle_window;
  o.settle_windows = s.settle_windows;
  o.spectrum_tolerance = s.spectrum_tolerance;
  o.frequency_tolerance = s.frequency_tolerance_hz;
  o.analysis_length = s.analysis_length;
  o.sample_rate = s.sample_rate_hz;
  o.band = s.spectrum_max_hz;
  o.peak_side = PeakSide::kNegative;
  o.rotate_forcing_phase = StructureOf(scene).imbalance > 0.0;
  // BDF orders 1–2 are A-stable: the nearly undamped contact modes (36 and 85 kHz, k1 = 1.75e11
  // N/m) cannot limit the step. Measured on the A(a) whip at 54–56 rpm, rtol 1e-8: order ≤ 5 took
  // 3× the wall time of order ≤ 2 for the same BP and slip velocity (docs/levels/l3_sweeps.md).
  IntegratorOptions bdf;
  bdf.method = IntegrationMethod::kBdf;
  bdf.max_order = 2;
  // Dormand–Prince 5(4): of ARKODE's explicit pairs the only one that is both right and cheapest
  // on the contact at the sweeps' tolerance (Verner 6(5) reports a wrong contact fraction in
  // continuous contact, Fehlberg 8(7) fails), and Boost.Odeint's the cheapest step of it, landing
  // on contact closing and opening (bench/sweep_integrators_bench.cpp).
  IntegratorOptions explicit_rk;
  explicit_rk.method = IntegrationMethod::kDormandPrince;
  bdf.relative_tolerance = s.relative_tolerance;
  bdf.absolute_tolerance = s.absolute_tolerance;
  explicit_rk.relative_tolerance = explicit_rk.absolute_tolerance = s.explicit_tolerance;
  bdf.max_steps = explicit_rk.max_steps = 100000000;  // per window; the dwell bounds the work
  o.integrator = s.integrator == SweepIntegrator::kExplicit ? explicit_rk : bdf;
  if (s.integrator == SweepIntegrator::kAuto) o.intermittent_integrator = explicit_rk;
  return o;
}

RubRegimeOptions RegimeOptionsOf(const Scene& scene) {
  RubRegimeOptions o;
  o.rolling_slip_tolerance = scene.analysis.sweep.rolling_slip_tolerance;
  o.rolling_micro_slip = scene.analysis.sweep.rolling_micro_slip;
  o.whirl_tolerance = scene.analysis.sweep.whirl_tolerance;
  o.frequency_jump_hz = scene.analysis.sweep.frequency_jump_hz;
  o.max_penetration = scene.analysis.sweep.max_penetration;
  return o;
}

RubSweepOptions RubSweepOptionsOf(const Scene& scene, SweepDirection direction) {
  RubSweepOptions o;
  o.direction = direction;
  o.sweep = SweepOptionsOf(scene, direction);
  o.regimes = RegimeOptionsOf(scene);
  o.impulse = scene.analysis.sweep.impulse;
  return o;
}

Scene AttractorSceneOf(const Scene& scene) {
  Scene bdf = scene;
  bdf.analysis.sweep.integrator = SweepIntegrator::kBdf;
  return bdf;
}

AttractorStudyOptions AttractorStudyOptionsOf(const Scene& scene, SweepDirection approach) {
  AttractorStudyOptions o;
  o.approach = RubSweepOptionsOf(AttractorSceneOf(scene), approach);
  o.attractor.integrator = o.approach.sweep.integrator;
  o.attractor.integrator.sensitivity_error_control = false;
  return o;
}

RubStructure SweepStructureOf(const Scene& scene) {
  if (!ModelOf(scene).Has(Stage::kSweep)) {
    throw std::invalid_argument(fmt::format("the sweep stage needs a model that has it ({}); scene "
                                            "{} has \"{}\"", ModelsWith(Stage::kSweep),
                                            scene.name, ToString(scene.model)));
  }
  return StructureOf(scene);
}

LoopOptions LoopOptionsOf(const Scene& scene) {
  LoopOptions o;
  o.up = RubSweepOptionsOf(scene, SweepDirection::kUp);
  o.down = RubSweepOptionsOf(scene, SweepDirection::kDown);
  o.step_rpm = scene.analysis.sweep.speed_step_rpm;
  o.dwell = scene.analysis.sweep.dwell;
  o.waves = BranchOptionsOf(scene);
  o.budget = scene.analysis.loop.budget;
  o.escapes.target_width = scene.analysis.loop.target_width_rpm;
  o.escapes.copies = scene.analysis.loop.copies;
  o.escapes.max_duration = scene.analysis.loop.max_copy_seconds;
  // L2 asks [analysis.orbits]' shooting and mesh (a flexible structure's too: its orbits are the
  // stage's, apps/orbits_stage.cpp); not with an imbalance, which the co-rotating frame excludes.
  o.orbit_start = TransientOrbitStartOf(scene);
  // Decision: the loop's L2 tries keep the shooting's integrator for their search (BDF ≤ 2), as the
  // committed loops were made; whether the sweep's moves their tries is not measured (the 12 loops
  // again: about 95 min of CPU).
  o.orbit_start.search_integrator.reset();
  // A departure that is no orbit (a chaotic whip) fails Newton whatever the iterations, and the
  // stage's 20 cost B(b) at 172 rpm 37 s of CPU (19 iterations to a non-finite residual): 10.
  o.orbit_start.newton.max_iterations = 10;
  o.orbit_family = RubOrbitOptionsOf(scene).orbits;
  return o;
}

std::vector<PlannedWork> SweepPlanOf(const Scene& scene) {
  const SweepSettings& s = scene.analysis.sweep;
  const double bytes = SweepSpeedBytes(static_cast<int>(SweepStructureOf(scene).contacts.size()),
                                       s.spectrum_max_hz, s.analysis_length);
  return {SweepWork("analysis.sweep.up_range_rpm", "speeds of the speed-up sweep", s.up_range_rpm[0],
                    s.up_range_rpm[1], s.speed_step_rpm, s.dwell, bytes),
          SweepWork("analysis.sweep.down_range_rpm", "speeds of the speed-down sweep",
                    s.down_range_rpm[1], s.down_range_rpm[0], s.speed_step_rpm, s.dwell, bytes)};
}

PlannedWork CopiesWorkOf(const Scene& scene, std::string key, std::string value, std::string what,
                         double runs, double duration, double window) {
  const double bytes = SweepSpeedBytes(static_cast<int>(SweepStructureOf(scene).contacts.size()),
                                       scene.analysis.sweep.spectrum_max_hz, 2.0 * window);
  return CopiesWork(std::move(key), std::move(value), std::move(what), runs, duration, window, bytes);
}

std::vector<PlannedWork> StagePlanOf(const Scene& scene, const std::vector<Stage>& stages) {
  std::vector<PlannedWork> plan;
  auto runs = [&](Stage stage) { return std::find(stages.begin(), stages.end(), stage) != stages.end(); };
  if (runs(Stage::kSweep) || runs(Stage::kLoop)) plan = SweepPlanOf(scene);
  if (runs(Stage::kLoop)) {
    PlannedWork budget;
    budget.key = "analysis.loop.budget";
    budget.value = fmt::format("{:g} G work units", scene.analysis.loop.budget);
    budget.what = "loop";
    budget.items = 1.0;
    budget.cpu_seconds = scene.analysis.loop.budget * kCpuSecondsPerGigaWorkUnit;
    budget.cpu_basis = fmt::format("{:g} s per G work units", kCpuSecondsPerGigaWorkUnit);
    plan.push_back(budget);
  }
  const RubOrbitsSettings::Transient& orbit = scene.analysis.orbits.transient;
  if (runs(Stage::kOrbits) && orbit.enabled) {
    plan.push_back(MarchingWork("analysis.orbits.transient.seconds", fmt::format("{:g} s", orbit.seconds),
                                "transient", 1.0, orbit.seconds, 0.0));
  }
  const RubToriSettings::Transient& torus = scene.analysis.tori.transient;
  if (runs(Stage::kTori) && torus.enabled) {
    plan.push_back(MarchingWork("analysis.tori.transient.seconds", fmt::format("{:g} s", torus.seconds),
                                "transient", 1.0, torus.seconds, 0.0));
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------
// The orbits and tori stages (level L2).

namespace {

// mesh = "adapted": the mesh moves at every third orbit, AUTO-07p's default (IAD = 3).
constexpr int kAdaptMeshEvery = 3;

// `tolerance`: the integrator's rtol = atol on scaled states.
ShootingOptions OrbitShootingOptions(int segments, double tolerance, IntegrationMethod method) {
  ShootingOptions options;
  options.segments = segments;
  options.integrator.method = method;
  if (method == IntegrationMethod::kExplicitRungeKutta) options.integrator.explicit_order = 8;
  options.integrator.relative_tolerance = tolerance;
  options.integrator.absolute_tolerance = tolerance;
  options.sensitivities_in_residual = true;
  return options;
}

}  // namespace

ContinuationOptions OrbitContinuationOptions(int max_steps) {
  ContinuationOptions options;
  options.step.max = 1.0;
  options.step.target_angle = 0.3;
  options.step.target_iterations = 5;
  options.bounds.max_steps = max_steps;
  return options;
}

PeriodicOrbitBranchOptions TextbookOrbitOptionsOf(const Scene& scene, IntegrationMethod method) {
  PeriodicOrbitBranchOptions options;
  options.lambda_min = scene.orbits.parameter_range[0];
  options.lambda_max = scene.orbits.parameter_range[1];
  options.continuation = OrbitContinuationOptions(scene.orbits.max_steps);
  options.shooting = OrbitShootingOptions(scene.orbits.segments, scene.orbits.tolerance, method);
  options.shooting.integrator.collocation_steps =
      CollocationStepsPerSegment(scene.orbits.collocation_intervals, scene.orbits.segments);
  return options;
}

IntegrationMethod TextbookOrbitMethodOf(const Scene& scene, IntegrationMethod model_default) {
  switch (scene.orbits.integrator) {
    case TextbookIntegrator::kModel: return model_default;
    case TextbookIntegrator::kExplicit: return IntegrationMethod::kExplicitRungeKutta;
    case TextbookIntegrator::kBdf: return IntegrationMethod::kBdf;
    case TextbookIntegrator::kGauss: return IntegrationMethod::kGaussCollocation;
  }
  return model_default;
}

ShootingOptions RubShootingOptionsOf(const Scene& scene) {
  const RubOrbitsSettings& settings = scene.analysis.orbits;
  const bool gauss = settings.integrator == OrbitIntegrator::kGauss;
  ShootingOptions options = OrbitShootingOptions(
      settings.segments, settings.tolerance,
      gauss ? IntegrationMethod::kGaussCollocation : IntegrationMethod::kBdf);
  options.integrator.max_steps = 2000000;
  options.integrator.collocation_steps =
      CollocationStepsPerSegment(settings.collocation_intervals, settings.segments);
  options.adapt_mesh_every = settings.adapt_mesh ? kAdaptMeshEvery : 0;
  return options;
}

HopfOrbitOptions RubOrbitOptionsOf(const Scene& scene) {
  HopfOrbitOptions options;
  options.amplitude = scene.analysis.orbits.amplitude;
  options.orbits.lambda_min = RpmToRadPerSecond(scene.analysis.speed_range_rpm[0]);
  options.orbits.lambda_max = RpmToRadPerSecond(scene.analysis.speed_range_rpm[1]);
  options.orbits.shooting = RubShootingOptionsOf(scene);
  options.orbits.continuation = OrbitContinuationOptions(scene.analysis.orbits.max_steps);
  options.orbits.stop_at_grazing = scene.analysis.orbits.stop_at_grazing;
  options.orbits.continuation.step.curved_predictor = scene.analysis.orbits.curved_predictor;
  options.orbits.defect_check = scene.analysis.orbits.defect_check;
  return options;
}

ModulatedOrbitOptions TransientOrbitStartOf(const Scene& scene) {
  const PeriodicOrbitBranchOptions orbits = RubOrbitOptionsOf(scene).orbits;
  const int laps = scene.analysis.orbits.transient.laps;
  ModulatedOrbitOptions start;
  start.shooting = orbits.shooting;
  start.shooting.segments *= laps;
  start.laps = laps;
  // The search continues the transient with the transient's own integrator (the sweep's).
  start.search_integrator = SweepOptionsOf(scene, SweepDirection::kUp).integrator;
  start.search_duration = scene.analysis.orbits.transient.search_seconds;
  start.newton.residual_tolerance = orbits.continuation.corrector.residual_tolerance;
  start.newton.step_tolerance = orbits.continuation.corrector.step_tolerance;
  start.newton.max_iterations = 20;
  return start;
}

SweepOptions TransientSweepOptionsOf(const Scene& scene, double speed_rpm, double seconds) {
  SweepOptions sweep = SweepOptionsOf(scene, SweepDirection::kUp);
  sweep.parameters = {RpmToRadPerSecond(speed_rpm)};
  sweep.dwell = seconds;
  sweep.rotate_forcing_phase = false;
  return sweep;
}

RubTorusOptions TorusOptionsOf(const Scene& scene) {
  const RubToriSettings& t = scene.analysis.tori;
  const PeriodicOrbitBranchOptions orbits = RubOrbitOptionsOf(scene).orbits;
  RubTorusOptions options;
  options.tori.lambda_min = orbits.lambda_min;
  options.tori.lambda_max = orbits.lambda_max;
  options.tori.harmonics = t.harmonics;
  options.tori.max_harmonics = t.max_harmonics;
  options.tori.amplitude = t.amplitude;
  options.tori.max_fourier_tail = t.max_fourier_tail;
  options.tori.lyapunov_iterates = t.lyapunov_iterates;
  options.tori.continuation = orbits.continuation;
  options.tori.continuation.bounds.max_steps = t.max_steps;
  const bool gauss = scene.analysis.orbits.integrator == OrbitIntegrator::kGauss;
  options.tori.continuation.corrector.residual_tolerance =
      (gauss ? 0.1 : 100.0) * scene.analysis.orbits.tolerance;
  options.samples = t.samples;
  options.centre_orbits = orbits;
  options.centre_orbits.stop_at_neimark_sacker = !t.centre_orbits_onward;
  options.tori.coordinates = t.contact_chart ? CircleCoordinates::kChart : CircleCoordinates::kState;
  return options;
}

ModulatedTorusOptions TransientTorusStartOf(const Scene& scene) {
  const RubToriSettings& t = scene.analysis.tori;
  ModulatedTorusOptions start = SettledTransientStart(t.transient.harmonics);
  start.max_harmonics = t.transient.max_harmonics;
  start.laps = t.transient.laps;
  const bool gauss = scene.analysis.orbits.integrator == OrbitIntegrator::kGauss;
  if (t.contact_chart) {
    start.coordinates = CircleCoordinates::kChart;
    if (gauss) start.collocation_intervals = scene.analysis.orbits.collocation_intervals;
  } else if (gauss) {
    // The state's first circle by CVODES BDF, then reported and refined in K under the families'
    // map (ModulatedTorusOptions::final_collocation_intervals).
    start.final_collocation_intervals = scene.analysis.orbits.collocation_intervals;
  }
  return start;
}

RubTorusOptions TransientTorusOptionsOf(const Scene& scene) {
  const RubToriSettings::Transient& t = scene.analysis.tori.transient;
  RubTorusOptions options = TorusOptionsOf(scene);
  options.tori.max_fourier_tail = t.max_fourier_tail;
  options.tori.max_harmonics = t.max_harmonics;
  options.tori.continuation.bounds.max_steps = t.max_steps;
  if (scene.analysis.orbits.integrator == OrbitIntegrator::kBdf) {
    options.tori.integrator = TransientTorusStartOf(scene).integrator;
    options.tori.integrator.relative_tolerance = options.tori.integrator.absolute_tolerance =
        scene.analysis.orbits.tolerance;
  } else {
    const ShootingOptions shooting = RubShootingOptionsOf(scene);
    options.tori.integrator = JoinedIntegrator(shooting.integrator, shooting.segments);
  }
  return options;
}

}  // namespace rubcont
