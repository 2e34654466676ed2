// Shooting with `segments` segments and both integrator tolerances at `tolerance`: the options the
// shooting tests on closed-form and textbook orbits solve with (shooting_test, van_der_pol_test).
#pragma once

#include "shooting/shooting.h"

namespace rubcont {

inline ShootingOptions ShootingWith(int segments, double tolerance = 1e-10) {
  ShootingOptions options;
  options.segments = segments;
  options.integrator.relative_tolerance = tolerance;
  options.integrator.absolute_tolerance = tolerance;
  return options;
}

}  // namespace rubcont
