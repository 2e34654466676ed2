// Design parameters of the two-point rub model as a second continuation parameter η of its
// rotating waves, for hysteresis maps (studies/hysteresis_map.h), fold location as an optimization
// and identification (studies/identification.h).
//
// A design parameter is one scalar of TwoPointParams, or one scalar that moves several of them
// together, with its physical range:
//   friction          μ [-] ≥ 0
//   stator_damping    c̄ = (c_L + c_R)/2 [N·s/m] ≥ 0; both supports scaled by c̄/c̄₀ (both set to c̄
//                     when the scene's are zero), so an asymmetric stator stays as asymmetric
//   support_stiffness k̄ = (k_L + k_R)/2 [N/m] > 0; both scaled by k̄/k̄₀
//   center_damping    c_d [N·s/m] ≥ 0
//   rci_ratio         RCI_R / RCI_L [-] > 0; the right clearance moves, C_R = R_R / (ratio·RCI_L)
//   contact_stiffness k1 [N/m] > 0
#pragma once

#include <string>
#include <vector>

#include "models/two_point_params.h"
#include "waves/rotating_wave.h"

namespace rubcont {

enum class DesignParameter {
  kFriction,
  kStatorDamping,
  kSupportStiffness,
  kCenterDamping,
  kRciRatio,
  kContactStiffness,
};

// "friction", "stator_damping", ... (the names above).
const char* ToString(DesignParameter parameter);
// The unit, e.g. "N·s/m" ("-" for dimensionless).
const char* UnitOf(DesignParameter parameter);
// Every name, in declaration order.
std::vector<std::string> DesignParameterNames();
// Throws std::invalid_argument naming the value and listing the valid names.
DesignParameter ParseDesignParameter(const std::string& name);

// The parameter's value in `params`.
double GetDesignParameter(const TwoPointParams& params, DesignParameter parameter);
// Physical range: the smallest allowed value and whether it is allowed itself (μ = 0 is, a
// stiffness of 0 is not). The largest is +∞ for all of them.
double LowerLimit(DesignParameter parameter);
bool LowerLimitIncluded(DesignParameter parameter);
// True when `value` is finite and inside the physical range.
bool InPhysicalRange(DesignParameter parameter, double value);
// `params` with the parameter set to `value`. Throws std::invalid_argument
// ("<name> = <value>: must be ...") when the value is outside the physical range, and whatever
// Validate(TwoPointParams) throws for the result.
TwoPointParams WithDesignParameter(TwoPointParams params, DesignParameter parameter, double value);

// The rotating waves of the two-point structure (RotatingWaveProblem) with one design parameter as
// second parameter η. The structure is rebuilt on every SetSecondParameter (a few 4 × 4 matrices);
// the imbalance is left out, as for every rotating wave. ∂F/∂η is the central difference of the
// base class. Setting η outside the physical range throws std::invalid_argument: continuations in η
// must bound it (HysteresisMap does, with the physical range intersected with the user's).
class RotatingWaveDesignProblem : public RotatingWaveProblem {
 public:
  RotatingWaveDesignProblem(const TwoPointParams& params, DesignParameter parameter);

  bool HasSecondParameter() const override { return true; }
  double SecondParameter() const override { return eta_; }
  void SetSecondParameter(double eta) override;
  double SecondParameterScale() const override { return eta_scale_; }

  DesignParameter parameter() const { return parameter_; }
  // The parameters at the current η.
  const TwoPointParams& params() const { return params_; }

 private:
  TwoPointParams base_;    // as given (η is applied to it, so repeated sets do not drift)
  TwoPointParams params_;  // at the current η
  DesignParameter parameter_;
  double eta_;
  double eta_scale_;
};

// The two-point params without imbalance (the rotating waves' symmetry needs none).
TwoPointParams WithoutImbalance(TwoPointParams params);

}  // namespace rubcont
