// The checks a fixed-mesh orbit carries (shooting/shooting.h): the defect under an independent
// integrator, and the multipliers of the modes the mesh does not resolve.
#include <cmath>
#include <memory>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

// Samples of the Stuart–Landau limit cycle r = √λ, θ = (ω − γλ)t: a relative periodic orbit with
// any period (rotation φ = (ω − γλ)T), and a periodic one with T = 2π/(ω − γλ).
OrbitSamples StuartLandauCycle(const StuartLandauOscillator& system, double period) {
  const double r = system.OrbitRadius(), w = system.AngularVelocity();
  OrbitSamples orbit;
  orbit.times = Vector::LinSpaced(9, 0.0, period);
  orbit.states.resize(2, 9);
  for (Index k = 0; k < 9; ++k) {
    orbit.states(0, k) = r * std::cos(w * orbit.times(k));
    orbit.states(1, k) = r * std::sin(w * orbit.times(k));
  }
  orbit.period = period;
  orbit.parameter = system.Parameter();
  orbit.valid = true;
  return orbit;
}

TEST_CASE("the periodicity defect is small on a true orbit and large on a wrong one",
          "[shooting][checks]") {
  StuartLandauParams p;
  p.gamma = 0.4;
  StuartLandauOscillator system(p);
  IntegratorOptions bdf;
  bdf.relative_tolerance = bdf.absolute_tolerance = 1e-10;
  const OrbitMeasure defect = PeriodicityDefect(std::make_shared<StuartLandauOscillator>(p), bdf);
  CHECK(defect.name == "defect");
  OrbitSamples orbit = StuartLandauCycle(system, system.Period());
  CHECK(defect.evaluate(orbit) < 1e-8);
  // As a relative orbit over half the period, rotated by the phase it gains.
  orbit = StuartLandauCycle(system, 0.5 * system.Period());
  orbit.rotation = kPi;
  CHECK(defect.evaluate(orbit) < 1e-8);
  orbit.rotation = 0.0;  // the same samples claimed periodic: off by the diameter
  CHECK(defect.evaluate(orbit) == Approx(2 * system.OrbitRadius()).epsilon(1e-6));
  orbit.valid = false;
  CHECK(std::isnan(defect.evaluate(orbit)));
}

// ẍ + 2ζω ẋ + ω² x = 0 with ω = 1e5, ζ = 1e-4: the lightly damped stiff contact mode in miniature.
class DampedStiffMode : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f << x(1), -kOmega * kOmega * x(0) - 2 * kZeta * kOmega * x(1);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef, MatrixRef J) override {
    J << 0, 1, -kOmega * kOmega, -2 * kZeta * kOmega;
  }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  static constexpr double kOmega = 1e5, kZeta = 1e-4;
};

TEST_CASE("the unresolved multiplier flags a lightly damped stiff mode the mesh steps over",
          "[shooting][checks]") {
  auto system = std::make_shared<DampedStiffMode>();
  OrbitSamples orbit;
  orbit.times = Vector::LinSpaced(2, 0.0, 0.05);
  orbit.states = Matrix::Zero(2, 2);
  orbit.period = 0.05;  // e^{−ζωT} = e^{−0.5} = 0.607
  orbit.valid = true;
  // 1e4 steps: |λ|h = 0.5, resolved (Padé error far below 1e-3).
  CHECK(UnresolvedMultiplier(system, 4, 10000).evaluate(orbit) == 0.0);
  // 200 steps: |λ|h = 25; Gauss keeps the mode but damps it less than the flow does.
  const double coarse = UnresolvedMultiplier(system, 4, 200).evaluate(orbit);
  CHECK(coarse > std::exp(-0.5) + 1e-3);
  CHECK(coarse < 1.0);
}

}  // namespace
}  // namespace rubcont
