#include "models/scale_check.h"

#include <cmath>

#include <fmt/format.h>

#include "models/flexible.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {

std::string LengthScaleMistake(double metres) {
  const double size = std::abs(metres);
  if (size > kLargestRotorLength) {
    return fmt::format("larger than any rotor ({:g} m): a length in mm written as m?", kLargestRotorLength);
  }
  if (size > 0.0 && size < kSmallestRotorLength) {
    return fmt::format("smaller than any machined clearance ({:g} µm): a length converted to m twice?",
                       kSmallestRotorLength * 1e6);
  }
  return {};
}

std::string ClearanceRatioMistake(double radius, double clearance) {
  const double rci = radius / clearance;
  if (rci < kSmallestRci) {
    return fmt::format("R/C = {:.3g}: a clearance of more than 1/{:g} of the radius; radius and "
                       "clearance in different units?", rci, kSmallestRci);
  }
  if (rci > kLargestRci) {
    return fmt::format("R/C = {:.3g}: above any rotor's {:g}; radius and clearance in different units?",
                       rci, kLargestRci);
  }
  return {};
}

std::string SurfaceSpeedMistake(double radius, double omega) {
  const double speed = radius * omega;
  if (!(speed > kFastestSurfaceSpeed)) return {};
  return fmt::format("the surface speed R·ω reaches {:.3g} m/s at R = {:g} m, beyond any rotor's burst "
                     "speed ({:g} m/s): rpm for rad/s, or a radius in mm written as m?",
                     speed, radius, kFastestSurfaceSpeed);
}

double PinnedNaturalFrequency(const RubStructure& structure) {
  // Undamped, without spin: the natural frequencies, not the damped whirls.
  RubStructure undamped = structure;
  undamped.damping.setZero();
  const std::vector<StructureMode> modes = StructureModes(undamped, true);
  return modes.empty() ? kNaN : HzToRadPerSecond(modes.front().frequency_hz);
}

double RollingKneeSpeed(const RubStructure& structure) {
  const double natural = PinnedNaturalFrequency(structure);
  double knee = kNaN;
  for (const RubContact& c : structure.contacts) {
    const double speed = natural * c.geometry.clearance / c.geometry.radius;
    if (!(knee <= speed)) knee = speed;
  }
  return knee;
}

std::string SpeedRangeMistake(double knee, double low, double high) {
  if (!std::isfinite(knee)) return {};
  if (!(high < knee / kKneeSpeedFactor) && !(low > knee * kKneeSpeedFactor)) return {};
  return fmt::format("the range lies more than {:g} times {} the speed {:.4g} rpm where a rolling "
                     "contact's precession (R/C)·ω meets the structure's lowest natural frequency: "
                     "a mass, stiffness or length in the wrong unit?",
                     kKneeSpeedFactor, high < knee ? "below" : "above", RadPerSecondToRpm(knee));
}

}  // namespace rubcont
