// A limit cycle with a period doubling in closed form, for the tests of doubled orbits
// (tests/shooting/orbit_branches_test.cpp, tests/studies/loop_skeleton_test.cpp).
#pragma once

#include <cmath>

#include "shooting/orbit_branches.h"
#include "solvers/constants.h"

namespace rubcont {

// Period doubling with a closed form: the same limit cycle (θ̇ = 1 on r = 1, period 2π) with a
// transverse vector w = (p, q) that sees a frame turning half as fast: with e(θ) = (cos θ/2,
// sin θ/2) and P(θ) = e eᵀ = ½[[1 + cos θ, sin θ], [sin θ, 1 − cos θ]] (single-valued in x, y),
//     ẇ = ½ J w + (λ P − (I − P) − |w|²) w.
// Along e and e⊥ = J e the components obey ȧ = (λ − a² − b²) a, ḃ = −(1 + a² + b²) b, and e
// turns into −e over one lap: the cycle with w = 0 has the multipliers e^{−4π} (its radius),
// −e^{2πλ} and −e^{−2π}, a period doubling at λ = 0, and the orbits born there have a = √λ,
// period 4π and the multipliers e^{−16π}, e^{−8πλ}, e^{−4π(1 + λ)}.
class CycleWithMoebiusBand : public OdeSystem {
 public:
  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const double r2 = x(0) * x(0) + x(1) * x(1), r = std::sqrt(r2);
    const double c = x(0) / r, s = x(1) / r;
    const double p = x(2), q = x(3), w2 = p * p + q * q;
    // λP − (I − P) = ((λ − 1)/2) I + ((λ + 1)/2) [[c, s], [s, −c]].
    const double m = 0.5 * (lambda_ - 1.0), k = 0.5 * (lambda_ + 1.0);
    f << (1.0 - r2) * x(0) - x(1), (1.0 - r2) * x(1) + x(0),
        -0.5 * q + (m + k * c - w2) * p + k * s * q, 0.5 * p + k * s * p + (m - k * c - w2) * q;
  }
  double Parameter() const override { return lambda_; }
  void SetParameter(double lambda) override { lambda_ = lambda; }

 private:
  double lambda_ = -0.5;
};

// The band's cycle (w = 0) at λ = −0.5, where it is stable.
inline OrbitStart MoebiusCycleStart() {
  OrbitStart start;
  start.x0 = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  start.period = kTwoPi;
  start.lambda = -0.5;
  start.valid = true;
  return start;
}

// Shooting on 2 segments with an explicit Runge–Kutta of order 8, λ in [−0.5, 0.5], steps ≤ 0.2.
inline PeriodicOrbitBranchOptions MoebiusBandOptions() {
  PeriodicOrbitBranchOptions options;
  options.lambda_min = -0.5;
  options.lambda_max = 0.5;
  options.shooting.segments = 2;
  options.shooting.integrator.method = IntegrationMethod::kExplicitRungeKutta;
  options.shooting.integrator.explicit_order = 8;
  options.shooting.sensitivities_in_residual = true;
  options.continuation.step.max = 0.2;
  return options;
}

}  // namespace rubcont
