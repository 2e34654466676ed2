// Periodic orbits born at a Hopf point: the Stuart–Landau equilibrium z = 0 loses stability at
// λ = 0 (eigenvalues λ ± iω), located by the engine on the equilibrium branch; the switch onto
// the orbits born there follows them to λ = 1 with the closed form r = √λ, T = 2π/|ω − γλ| and
// nontrivial multiplier e^{−2λT} on every point.
#include <cmath>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "models/textbook.h"
#include "shooting/hopf_orbits.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

TEST_CASE("Stuart–Landau: Hopf point of the equilibrium located, the orbits born there continued "
          "to lambda = 1 as in closed form",
          "[hopf][shooting]") {
  StuartLandauParams params;
  params.omega = 1.0;
  params.gamma = 0.5;
  params.lambda = -0.5;
  StuartLandauOscillator system(params);

  EquilibriumProblem equilibria(system);
  ContinuationOptions options;
  options.bounds.lambda_min = -0.5;
  options.bounds.lambda_max = 0.5;
  options.detect.stability = true;
  const Branch equilibrium_branch = Continue(equilibria, Vector::Zero(2), -0.5, options);
  INFO(equilibrium_branch.BriefReport());
  REQUIRE(equilibrium_branch.Count(SpecialPointType::kHopf) == 1);
  const SpecialPoint* hopf = nullptr;
  for (const SpecialPoint& p : equilibrium_branch.special_points) {
    if (p.type == SpecialPointType::kHopf) hopf = &p;
  }
  CHECK(hopf->converged);
  CHECK(hopf->lambda == Approx(0.0).epsilon(0).margin(1e-8));
  CHECK(hopf->frequency == Approx(params.omega).epsilon(1e-8));

  for (int segments : {1, 4}) {
    CAPTURE(segments);
    HopfOrbitOptions hopf_options;
    hopf_options.amplitude = 1e-2;
    hopf_options.orbits.lambda_min = -0.5;
    hopf_options.orbits.lambda_max = 1.0;
    hopf_options.orbits.shooting.segments = segments;
    hopf_options.orbits.shooting.integrator.method = IntegrationMethod::kExplicitRungeKutta;
    hopf_options.orbits.shooting.integrator.explicit_order = 8;
    hopf_options.orbits.shooting.sensitivities_in_residual = true;
    hopf_options.orbits.continuation.step.target_iterations = 5;
    hopf_options.orbits.continuation.step.max = 0.5;
    const PeriodicOrbitBranch orbits = ContinueOrbitsFromHopf(system, *hopf, hopf_options);
    const Branch& branch = orbits.branch;
    INFO(branch.BriefReport() << " — " << branch.message);
    REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
    REQUIRE(branch.Size() > 5);
    // Supercritical: the orbits lie at λ > 0, the first one at λ = a² (r = a = 1e-2).
    CHECK(branch.points.front().lambda == Approx(1e-4).epsilon(1e-6));
    CHECK(branch.points.back().lambda == Approx(1.0).epsilon(0).margin(1e-9));
    const Vector period = branch.Measure("period");
    for (Index i = 0; i < branch.Size(); ++i) {
      const BranchPoint& p = branch.points[static_cast<std::size_t>(i)];
      CAPTURE(p.lambda);
      // On the circle r = √λ every point has |x| = r; the phase condition picks one of them.
      CHECK(p.u.head(2).norm() == Approx(std::sqrt(p.lambda)).epsilon(0).margin(1e-9));
      const double T = kTwoPi / std::abs(params.omega - params.gamma * p.lambda);
      CHECK(period(i) == Approx(T).epsilon(1e-9));
      REQUIRE(p.spectrum.valid);
      REQUIRE(p.spectrum.values.size() == 1);
      CHECK(p.spectrum.values(0).real() ==
            Approx(std::exp(-2 * p.lambda * T)).epsilon(0).margin(1e-8));
      CHECK(p.num_unstable == 0);
    }
  }
}

// A relative equilibrium that undergoes a Hopf bifurcation, in closed form: a rotating wave p
// (|p| = 1, shown here in the frame that co-rotates with it, where it is a circle of equilibria)
// and a Stuart–Landau oscillator w that it carries, whose amplitude makes p drift:
//   ṗ = (1 − |p|²) p + i c |w|² p,     ẇ = (λ + iν) w − |w|² w,     symmetry p → e^{iφ} p.
// At λ = 0 the wave (p, w) = (1, 0) has eigenvalues ±iν: the orbits born there have |w| = √λ,
// T = 2π/ν, and p turns by φ = cλT per period: relative periodic orbits, x(T) = R_φ x(0), with
// nontrivial multipliers e^{−2T} (|p|) and e^{−2λT} (|w|).
class CarriedOscillator : public OdeSystem {
 public:
  static constexpr double kNu = 2.0, kC = 0.5;
  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const double r2 = x(0) * x(0) + x(1) * x(1), s = x(2) * x(2) + x(3) * x(3);
    f(0) = (1 - r2) * x(0) - kC * s * x(1);
    f(1) = (1 - r2) * x(1) + kC * s * x(0);
    f(2) = lambda_ * x(2) - kNu * x(3) - s * x(2);
    f(3) = kNu * x(2) + lambda_ * x(3) - s * x(3);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double r2 = x(0) * x(0) + x(1) * x(1), s = x(2) * x(2) + x(3) * x(3);
    J << 1 - r2 - 2 * x(0) * x(0), -2 * x(0) * x(1) - kC * s, -2 * kC * x(2) * x(1),
        -2 * kC * x(3) * x(1),  //
        -2 * x(0) * x(1) + kC * s, 1 - r2 - 2 * x(1) * x(1), 2 * kC * x(2) * x(0),
        2 * kC * x(3) * x(0),  //
        0, 0, lambda_ - s - 2 * x(2) * x(2), -kNu - 2 * x(2) * x(3),  //
        0, 0, kNu - 2 * x(2) * x(3), lambda_ - s - 2 * x(3) * x(3);
  }
  double Parameter() const override { return lambda_; }
  void SetParameter(double lambda) override { lambda_ = lambda; }
  void DfDparameter(double, ConstVectorRef x, VectorRef df) override {
    df << 0, 0, x(2), x(3);
  }
  bool HasRotationSymmetry() const override { return true; }
  void Rotate(double phi, VectorRef x) const override {
    const double c = std::cos(phi), s = std::sin(phi), x0 = x(0);
    x(0) = c * x0 - s * x(1);
    x(1) = s * x0 + c * x(1);
  }
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override { g << -x(1), x(0), 0, 0; }

 private:
  double lambda_ = 0.0;
};

TEST_CASE("Hopf point of a relative equilibrium: the orbits born there continued as relative "
          "periodic orbits, drift and multipliers as in closed form",
          "[hopf][shooting][relative]") {
  CarriedOscillator system;
  SpecialPoint hopf;  // as the rotating-wave branches report it: the wave, λ, and ω = ν
  hopf.type = SpecialPointType::kHopf;
  hopf.u = (Vector(4) << 1.0, 0.0, 0.0, 0.0).finished();
  hopf.lambda = 0.0;
  hopf.frequency = CarriedOscillator::kNu;

  HopfOrbitOptions options;
  options.kind = OrbitKind::kRelative;
  options.amplitude = 1e-2;
  options.orbits.lambda_min = -0.5;
  options.orbits.lambda_max = 1.0;
  options.orbits.shooting.segments = 2;
  options.orbits.shooting.integrator.method = IntegrationMethod::kExplicitRungeKutta;
  options.orbits.shooting.integrator.explicit_order = 8;
  options.orbits.shooting.sensitivities_in_residual = true;
  options.orbits.continuation.step.target_iterations = 5;
  options.orbits.continuation.step.max = 0.5;
  const PeriodicOrbitBranch orbits = ContinueOrbitsFromHopf(system, hopf, options);
  const Branch& branch = orbits.branch;
  INFO(branch.BriefReport() << " — " << branch.message);
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Size() > 5);
  CHECK(branch.points.back().lambda == Approx(1.0).epsilon(0).margin(1e-9));
  const Vector period = branch.Measure("period"), rotation = branch.Measure("rotation");
  const double T = kTwoPi / CarriedOscillator::kNu;
  for (Index i = 0; i < branch.Size(); ++i) {
    const BranchPoint& p = branch.points[static_cast<std::size_t>(i)];
    CAPTURE(p.lambda);
    CHECK(p.u.segment(2, 2).norm() == Approx(std::sqrt(p.lambda)).epsilon(0).margin(1e-9));
    CHECK(p.u.head(2).norm() == Approx(1.0).epsilon(0).margin(1e-9));
    CHECK(period(i) == Approx(T).epsilon(1e-9));
    CHECK(rotation(i) == Approx(CarriedOscillator::kC * p.lambda * T).epsilon(0).margin(1e-9));
    REQUIRE(p.spectrum.valid);
    REQUIRE(p.spectrum.values.size() == 2);
    CHECK(p.spectrum.trivial_removed == 2);
    const double radial_w = std::exp(-2 * p.lambda * T), radial_p = std::exp(-2 * T);
    CHECK(p.spectrum.values(0).real() ==
          Approx(std::max(radial_w, radial_p)).epsilon(0).margin(1e-8));
    CHECK(p.spectrum.values(1).real() ==
          Approx(std::min(radial_w, radial_p)).epsilon(0).margin(1e-8));
    CHECK(p.num_unstable == 0);
  }
}

}  // namespace
}  // namespace rubcont
