// The checks a fixed-mesh orbit carries (shooting/shooting.h): the defect under an independent
// integrator, and the multipliers of the modes the mesh does not resolve; each measured once per
// orbit.
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

TEST_CASE("an orbit asked for its measures again is not measured again", "[shooting][checks]") {
  DuffingOscillator duffing(DuffingParams{});
  ShootingProblem problem(duffing, OrbitKind::kForced);
  int evaluations = 0;
  problem.SetMeasures({{"first_state", [&evaluations](const OrbitSamples& orbit) {
                          ++evaluations;
                          return orbit.states(0, 0);
                        }}});
  const Vector x0 = Vector::Constant(2, 0.1);
  const Vector u = problem.InitialGuess(x0, 0.0, 1.0);
  const Vector first = problem.Measures(u, 1.0);
  CHECK(problem.Measures(u, 1.0) == first);  // the same orbit: the same values, no evaluation
  CHECK(evaluations == 1);
  CHECK(first(1) == 0.1);
  problem.Measures(u, 1.1);  // another speed, another orbit
  CHECK(evaluations == 2);
  const Vector v = problem.InitialGuess(Vector::Constant(2, 0.2), 0.0, 1.1);
  CHECK(problem.Measures(v, 1.1)(1) == 0.2);
  CHECK(evaluations == 3);
  problem.SetMeasures({{"twice_first_state", [](const OrbitSamples& orbit) {
                          return 2.0 * orbit.states(0, 0);
                        }}});
  CHECK(problem.Measures(v, 1.1)(1) == 0.4);  // new measures: measured again
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

// ẍ + 2ζω ẋ + ω² x = 0 with ω = 1e5: with ζ = 1e-4 the lightly damped stiff contact mode in
// miniature; with ζ < 0 a growing one (the frozen contact mode of A(a)'s doubled whip).
class DampedStiffMode : public OdeSystem {
 public:
  explicit DampedStiffMode(double zeta = 1e-4) : zeta_(zeta) {}
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f << x(1), -kOmega * kOmega * x(0) - 2 * zeta_ * kOmega * x(1);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef, MatrixRef J) override {
    J << 0, 1, -kOmega * kOmega, -2 * zeta_ * kOmega;
  }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  static constexpr double kOmega = 1e5;

 private:
  double zeta_;
};

// One sample at the origin (the Jacobian is constant) of an orbit of period T.
OrbitSamples OneSample(double period) {
  OrbitSamples orbit;
  orbit.times = Vector::LinSpaced(2, 0.0, period);
  orbit.states = Matrix::Zero(2, 2);
  orbit.period = period;
  orbit.valid = true;
  return orbit;
}

TEST_CASE("the unresolved multiplier flags a lightly damped stiff mode the mesh steps over",
          "[shooting][checks]") {
  auto system = std::make_shared<DampedStiffMode>();
  const OrbitSamples orbit = OneSample(0.05);  // e^{−ζωT} = e^{−0.5} = 0.607
  // 1e4 steps: |λ|h = 0.5, resolved (Padé error far below 1e-3).
  CHECK(UnresolvedMultiplier(system, 4, 10000).evaluate(orbit) == 0.0);
  // 200 steps: |λ|h = 25; Gauss keeps the mode but damps it less than the flow does.
  const double coarse = UnresolvedMultiplier(system, 4, 200).evaluate(orbit);
  CHECK(coarse > std::exp(-0.5) + 1e-3);
  CHECK(coarse < 1.0);
}

TEST_CASE("the unresolved multiplier leaves out a growing mode the mesh resolves",
          "[shooting][checks]") {
  // ζ = −6e-3: e^{−ζωT} = e^{30} = 1.1e13 over T = 0.05, the size of A(a)'s doubled whip's frozen
  // contact mode at its first sample. 1e4 steps resolve it (|λ|h = 0.5): |R(λh)|^N equals e^{30}
  // to round-off, which is far above 1e-3 in absolute terms (the check once reported e^{30}).
  auto system = std::make_shared<DampedStiffMode>(-6e-3);
  const OrbitSamples orbit = OneSample(0.05);
  CHECK(UnresolvedMultiplier(system, 4, 10000).evaluate(orbit) == 0.0);
  // 200 steps (|λ|h = 25) do not resolve it: Gauss keeps it growing (|R| > 1 for Re z > 0) but
  // by far less than the flow, and the check reports it.
  const double coarse = UnresolvedMultiplier(system, 4, 200).evaluate(orbit);
  CHECK(coarse > 1.0);
  CHECK(coarse < 1e-3 * std::exp(30.0));
}

}  // namespace
}  // namespace rubcont
