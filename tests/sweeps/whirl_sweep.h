// The cheap case the L3 run and study tests (tests/sweeps, tests/studies) run on: case A(a)
// (scenes/thesis_A_a.toml's model) swept up through 40, 44 and 48 rpm, 0.75 s per speed (as
// tests/apps/cli_support.h's WhirlScene): the rotor rolls on both contacts from the impulse on
// (the Mode 1 whirl, slipping from 50.96 rpm on the tanh law: docs/studies/sweeps.md, the A(a) row
// of the jump table). The options are the library's, without a scene: what
// apps/stage_options.cpp's RubSweepOptionsOf makes of that scene.
#pragma once

#include <stdexcept>
#include <string>

#include "models/rub_model.h"
#include "models/two_point_params.h"
#include "models/units.h"
#include "sweeps/rub_runs.h"

namespace rubcont::testing {

inline RubStructure WhirlStructure() { return TwoPointStructure(ThesisCaseAa()); }

// Odeint's Dormand–Prince 5(4) at rtol = atol = 1e-8 (the scenes' default sweep integrator), or
// CVODES BDF of order ≤ 2 at 1e-6 (`bdf`: the attractor study's).
inline RubSweepOptions WhirlSweep(bool bdf = false) {
  RubSweepOptions o;
  o.direction = SweepDirection::kUp;
  for (double rpm : {40.0, 44.0, 48.0}) o.sweep.parameters.push_back(RpmToRadPerSecond(rpm));
  o.sweep.dwell = 0.75;
  o.sweep.window = 0.25;
  o.sweep.settle_windows = 2;
  o.sweep.analysis_length = 0.5;
  o.sweep.sample_rate = 4096.0;
  o.sweep.band = 600.0;
  o.sweep.peak_side = PeakSide::kNegative;
  if (bdf) {
    o.sweep.integrator.method = IntegrationMethod::kBdf;
    o.sweep.integrator.max_order = 2;
    o.sweep.integrator.relative_tolerance = o.sweep.integrator.absolute_tolerance = 1e-6;
  } else {
    o.sweep.integrator.method = IntegrationMethod::kDormandPrince;
    o.sweep.integrator.relative_tolerance = o.sweep.integrator.absolute_tolerance = 1e-8;
  }
  o.sweep.integrator.max_steps = 100000000;
  o.impulse = 1.0;
  return o;
}

// A stretch is two windows of round(0.05 s × 4096 Hz) = 205 samples.
inline constexpr double kStretch = 410.0 / 4096.0;

// What Validate(options, structure) says of `options` after change(options): the message of the
// std::invalid_argument it throws, or "accepted".
template <class Options, class Change>
std::string Rejection(Options options, const RubStructure& structure, Change&& change) {
  change(options);
  try {
    Validate(options, structure);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace rubcont::testing
