#include "apps/stage_options.h"

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
  // 3× the wall time of order ≤ 2 for the same BP and slip velocity (README.md, level L3).
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
  return o;
}

}  // namespace rubcont
