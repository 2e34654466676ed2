#include "models/two_point_params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rubcont {

TwoPointParams ThesisCaseAa() {
  TwoPointParams params;
  params.center_damping = 52.0;
  return params;
}

TwoPointParams ThesisCaseCa() {
  TwoPointParams params = ThesisCaseAa();
  params.rotor_inertia = 0.07;
  params.rotor_mass_center = 0.26;
  return params;
}

TwoPointParams ThesisCaseCb() {
  TwoPointParams params = ThesisCaseCa();
  params.clearance = {3.81e-4, 3.048e-4};
  return params;
}

TwoPointParams ThesisCaseCc() {
  TwoPointParams params = ThesisCaseCa();
  params.clearance = {3.048e-4, 3.81e-4};
  return params;
}

namespace {

enum class Sign { kPositive, kNonNegative, kAny };

void Check(const char* field, double value, Sign sign, const char* unit) {
  const char* rule = nullptr;
  if (!std::isfinite(value)) {
    rule = "must be finite";
  } else if (sign == Sign::kPositive && !(value > 0.0)) {
    rule = "must be positive";
  } else if (sign == Sign::kNonNegative && !(value >= 0.0)) {
    rule = "must be non-negative";
  }
  if (rule != nullptr) {
    std::ostringstream message;
    message << "TwoPointParams." << field << " = " << value << ": " << rule << " (" << unit << ")";
    throw std::invalid_argument(message.str());
  }
}

void CheckPair(const char* field, const std::array<double, 2>& value, Sign sign, const char* unit) {
  for (int k = 0; k < 2; ++k) {
    Check((std::string(field) + (k == 0 ? "[0] (left)" : "[1] (right)")).c_str(), value[k], sign, unit);
  }
}

}  // namespace

void Validate(const TwoPointParams& p) {
  Check("rotor_mass", p.rotor_mass, Sign::kPositive, "kg");
  Check("rotor_inertia", p.rotor_inertia, Sign::kPositive, "kg·m²");
  Check("contact_span", p.contact_span, Sign::kPositive, "m");
  Check("rotor_mass_center", p.rotor_mass_center, Sign::kAny, "m");
  Check("stator_mass", p.stator_mass, Sign::kPositive, "kg");
  Check("stator_inertia", p.stator_inertia, Sign::kPositive, "kg·m²");
  Check("stator_span", p.stator_span, Sign::kPositive, "m");
  Check("stator_mass_center", p.stator_mass_center, Sign::kAny, "m");
  CheckPair("support_stiffness", p.support_stiffness, Sign::kPositive, "N/m");
  CheckPair("support_damping", p.support_damping, Sign::kNonNegative, "N·s/m");
  CheckPair("clearance", p.clearance, Sign::kPositive, "m");
  CheckPair("radius", p.radius, Sign::kPositive, "m");
  Check("friction", p.friction, Sign::kNonNegative, "-");
  Check("contact_stiffness", p.contact_stiffness, Sign::kPositive, "N/m");
  Check("contact_stiffness2", p.contact_stiffness2, Sign::kNonNegative, "N/m²");
  Check("contact_damping", p.contact_damping, Sign::kNonNegative, "N·s/m²");
  Check("friction_law.velocity_scale", p.friction_law.velocity_scale, Sign::kPositive, "m/s");
  Check("imbalance", p.imbalance, Sign::kNonNegative, "kg·m");
  Check("center_damping", p.center_damping, Sign::kNonNegative, "N·s/m");
}

}  // namespace rubcont
