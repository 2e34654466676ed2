// The rotating waves' search over a speed range, precessions up to 200 Hz: the options the studies'
// tests on the thesis cases continue their branches with (identification, hysteresis map, whirl
// limits).
#pragma once

#include "models/units.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

inline RotatingWaveBranchOptions SpeedRange(double min_rpm, double max_rpm) {
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(min_rpm);
  options.search.speed_max = RpmToRadPerSecond(max_rpm);
  options.search.precession_max = HzToRadPerSecond(200.0);
  return options;
}

}  // namespace rubcont
