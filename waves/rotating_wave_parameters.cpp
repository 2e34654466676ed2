#include "waves/rotating_wave_parameters.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/rub_model.h"

namespace rubcont {

namespace {

constexpr DesignParameter kAll[] = {
    DesignParameter::kFriction,      DesignParameter::kStatorDamping,
    DesignParameter::kSupportStiffness, DesignParameter::kCenterDamping,
    DesignParameter::kRciRatio,      DesignParameter::kContactStiffness,
};

double Mean(const std::array<double, 2>& a) { return 0.5 * (a[0] + a[1]); }

// Scales both entries by value / mean (both set to value when the mean is zero).
std::array<double, 2> ScaledPair(const std::array<double, 2>& a, double value) {
  const double mean = Mean(a);
  if (mean == 0.0) return {value, value};
  return {a[0] * value / mean, a[1] * value / mean};
}

// A typical magnitude of the parameter, for steps and scales when its value is 0.
double TypicalMagnitude(DesignParameter parameter) {
  switch (parameter) {
    case DesignParameter::kFriction: return 0.1;
    case DesignParameter::kStatorDamping: return 100.0;
    case DesignParameter::kSupportStiffness: return 1e6;
    case DesignParameter::kCenterDamping: return 10.0;
    case DesignParameter::kRciRatio: return 1.0;
    case DesignParameter::kContactStiffness: return 1e10;
  }
  return 1.0;
}

}  // namespace

const char* ToString(DesignParameter parameter) {
  switch (parameter) {
    case DesignParameter::kFriction: return "friction";
    case DesignParameter::kStatorDamping: return "stator_damping";
    case DesignParameter::kSupportStiffness: return "support_stiffness";
    case DesignParameter::kCenterDamping: return "center_damping";
    case DesignParameter::kRciRatio: return "rci_ratio";
    case DesignParameter::kContactStiffness: return "contact_stiffness";
  }
  return "?";
}

const char* UnitOf(DesignParameter parameter) {
  switch (parameter) {
    case DesignParameter::kFriction: return "-";
    case DesignParameter::kStatorDamping: return "N·s/m";
    case DesignParameter::kSupportStiffness: return "N/m";
    case DesignParameter::kCenterDamping: return "N·s/m";
    case DesignParameter::kRciRatio: return "-";
    case DesignParameter::kContactStiffness: return "N/m";
  }
  return "?";
}

std::vector<std::string> DesignParameterNames() {
  std::vector<std::string> names;
  for (DesignParameter p : kAll) names.emplace_back(ToString(p));
  return names;
}

DesignParameter ParseDesignParameter(const std::string& name) {
  for (DesignParameter p : kAll) {
    if (name == ToString(p)) return p;
  }
  throw std::invalid_argument(fmt::format("parameter = \"{}\": must be one of {}", name,
                                          fmt::join(DesignParameterNames(), ", ")));
}

double GetDesignParameter(const TwoPointParams& params, DesignParameter parameter) {
  switch (parameter) {
    case DesignParameter::kFriction: return params.friction;
    case DesignParameter::kStatorDamping: return Mean(params.support_damping);
    case DesignParameter::kSupportStiffness: return Mean(params.support_stiffness);
    case DesignParameter::kCenterDamping: return params.center_damping;
    case DesignParameter::kRciRatio: return params.Rci(1) / params.Rci(0);
    case DesignParameter::kContactStiffness: return params.contact_stiffness;
  }
  return 0.0;
}

double LowerLimit(DesignParameter /*parameter*/) { return 0.0; }

bool LowerLimitIncluded(DesignParameter parameter) {
  switch (parameter) {
    case DesignParameter::kFriction:
    case DesignParameter::kStatorDamping:
    case DesignParameter::kCenterDamping: return true;
    case DesignParameter::kSupportStiffness:
    case DesignParameter::kRciRatio:
    case DesignParameter::kContactStiffness: return false;
  }
  return false;
}

bool InPhysicalRange(DesignParameter parameter, double value) {
  if (!std::isfinite(value)) return false;
  return LowerLimitIncluded(parameter) ? value >= LowerLimit(parameter)
                                       : value > LowerLimit(parameter);
}

TwoPointParams WithDesignParameter(TwoPointParams params, DesignParameter parameter, double value) {
  if (!InPhysicalRange(parameter, value)) {
    throw std::invalid_argument(fmt::format(
        "{} = {}: must be {} {} ({})", ToString(parameter), value,
        LowerLimitIncluded(parameter) ? "finite and ≥" : "finite and >", LowerLimit(parameter),
        UnitOf(parameter)));
  }
  switch (parameter) {
    case DesignParameter::kFriction: params.friction = value; break;
    case DesignParameter::kStatorDamping:
      params.support_damping = ScaledPair(params.support_damping, value);
      break;
    case DesignParameter::kSupportStiffness:
      params.support_stiffness = ScaledPair(params.support_stiffness, value);
      break;
    case DesignParameter::kCenterDamping: params.center_damping = value; break;
    case DesignParameter::kRciRatio:
      params.clearance[1] = params.radius[1] / (value * params.Rci(0));
      break;
    case DesignParameter::kContactStiffness: params.contact_stiffness = value; break;
  }
  Validate(params);
  return params;
}

TwoPointParams WithoutImbalance(TwoPointParams params) {
  params.imbalance = 0.0;
  return params;
}

RotatingWaveDesignProblem::RotatingWaveDesignProblem(const TwoPointParams& params,
                                                     DesignParameter parameter)
    : RotatingWaveProblem(TwoPointStructure(WithoutImbalance(params)), params.friction_law.kind),
      base_(WithoutImbalance(params)),
      params_(base_),
      parameter_(parameter),
      eta_(GetDesignParameter(base_, parameter)),
      eta_scale_(std::max(std::abs(eta_), TypicalMagnitude(parameter))) {}

void RotatingWaveDesignProblem::SetSecondParameter(double eta) {
  if (eta == eta_) return;
  params_ = WithDesignParameter(base_, parameter_, eta);
  SetStructure(TwoPointStructure(params_));
  eta_ = eta;
}

}  // namespace rubcont
