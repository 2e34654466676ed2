// Invariant circles of stroboscopic maps (shooting/invariant_circle.h): an exact torus with a
// known rotation number and normal multiplier, its continuation, and the forced van der Pol
// oscillator's quasi-periodic regime against its own long transient.
#include "shooting/invariant_circle.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "models/textbook.h"
#include "solvers/newton.h"

namespace rubcont {
namespace {

// The Stuart–Landau oscillator beside an uncoupled clock of period T: the product of a limit cycle
// and a circle, a torus whose stroboscopic section is the cycle |z| = √λ, turned per period by
// ρ = (ω − γλ)T / 2π (mod 1), with the normal multiplier e^{−2λT}.
class ClockedStuartLandau : public OdeSystem {
 public:
  ClockedStuartLandau(const StuartLandauParams& params, double period)
      : oscillator_(params), period_(period) {}
  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override { oscillator_.Rhs(t, x, f); }
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override { oscillator_.JacobianX(t, x, J); }
  double Parameter() const override { return oscillator_.Parameter(); }
  void SetParameter(double p) override { oscillator_.SetParameter(p); }
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override {
    oscillator_.DfDparameter(t, x, df);
  }
  double ForcingPeriod() const override { return period_; }

 private:
  StuartLandauOscillator oscillator_;
  double period_;
};

IntegratorOptions Tight() {
  IntegratorOptions options;
  options.relative_tolerance = 1e-11;
  options.absolute_tolerance = 1e-11;
  return options;
}

NewtonResult Solve(InvariantCircleProblem& problem, Vector& u, double lambda) {
  problem.SetPhaseReference(u);
  return NewtonSolve([&](const Vector& x, Vector& F) { problem.Residual(x, lambda, F); },
                     [&](const Vector& x, Matrix& J) { problem.Jacobian(x, lambda, J); }, u, {},
                     problem.Scale(), problem.ResidualScale());
}

double Fraction(double x) { return x - std::floor(x); }

// The clocked Stuart–Landau torus of the tests: λ = 0.5, ω = 1, γ = 0.3, T = 2π/√2.
struct ClockedTorus {
  StuartLandauParams params{0.5, 1.0, 0.3};
  double period = 2.0 * M_PI / std::sqrt(2.0);
  std::shared_ptr<ClockedStuartLandau> system = std::make_shared<ClockedStuartLandau>(params, period);
  InvariantCircleProblem problem{system, 3, Tight()};
  double Rho(double lambda) const {
    return Fraction((params.omega - params.gamma * lambda) * period / (2 * M_PI));
  }
};

TEST_CASE("invariant circle: the clocked Stuart-Landau torus, radius, rotation number, multipliers",
          "[torus]") {
  ClockedTorus torus;
  const StuartLandauParams& params = torus.params;
  const double period = torus.period;
  InvariantCircleProblem& problem = torus.problem;
  REQUIRE(problem.Dimension() == 2 * 7 + 1);
  // A wrong first circle: off-centre, elliptic, tilted, with a second harmonic; ρ off by 0.02.
  const double r = std::sqrt(params.lambda);
  Matrix c = Matrix::Zero(2, 7);
  c.col(0) << 0.05, -0.03;
  c.col(1) << 1.1 * r, 0.05;
  c.col(2) << 0.02, 0.9 * r;
  c.col(3) << 0.01, 0.0;
  const double rho_exact = torus.Rho(params.lambda);
  Vector u = problem.Pack(c, rho_exact + 0.02);
  const NewtonResult result = Solve(problem, u, params.lambda);
  INFO(result.BriefReport());
  REQUIRE(result.Converged());
  CHECK(std::abs(problem.RotationNumber(u) - rho_exact) <= 1e-10);
  for (double theta : {0.0, 0.7, 2.0, 4.1, 5.9}) {
    CHECK(std::abs(problem.PointAt(u, theta).norm() - r) <= 1e-9);
  }
  CHECK(problem.InvarianceError(u, params.lambda) <= 1e-9);
  // Λ: 2K + 1 = 7 values along the circle (modulus 1) and 7 across it (e^{−2λT}); in each cluster
  // the pair of the last harmonic is polluted by the truncation (0.972 and 0.0121 here), the other
  // 2K − 1 = 5 are exact.
  const std::vector<double> moduli = problem.CircleMultipliers(u, params.lambda);
  REQUIRE(moduli.size() == 14);
  const double normal = std::exp(-2.0 * params.lambda * period);
  int along = 0, across = 0;
  for (double m : moduli) {
    along += std::abs(m - 1.0) <= 1e-6;
    across += std::abs(m - normal) <= 1e-6 * normal;
  }
  CHECK(along == 5);
  CHECK(across == 5);
  CHECK(moduli[0] <= 1.0 + 1e-6);  // attracting: nothing beyond the circle's own modulus
  // The verdict: Lyapunov exponents 0 (along the circle) and −2λT per period (across).
  const InvariantCircleProblem::TorusStability lyapunov =
      problem.LyapunovStability(u, params.lambda, 400);
  REQUIRE(lyapunov.valid);
  CHECK(lyapunov.stable);
  CHECK(std::abs(lyapunov.exponents(lyapunov.tangent)) <= 1e-2);
  CHECK(std::abs(lyapunov.exponents(1) + 2.0 * params.lambda * period) <= 1e-2);
}

TEST_CASE("invariant circle: continued in the growth rate, the rotation number follows the shear",
          "[torus]") {
  ClockedTorus torus;
  const StuartLandauParams& params = torus.params;
  InvariantCircleProblem& problem = torus.problem;
  const double r = std::sqrt(params.lambda);
  Matrix c = Matrix::Zero(2, 7);
  c.col(1) << r, 0.0;
  c.col(2) << 0.0, r;
  Vector u = problem.Pack(c, torus.Rho(params.lambda));
  problem.SetPhaseReference(u);
  ContinuationOptions options;
  options.bounds.lambda_min = 0.2;
  options.bounds.lambda_max = 1.0;
  options.step.max = 0.1;
  options.detect.stability = false;
  const Branch branch = Continue(problem, u, params.lambda, options);
  INFO(branch.message);
  REQUIRE(branch.points.size() >= 5);
  CHECK(branch.status == BranchStatus::kReachedLambdaBound);
  for (const BranchPoint& p : branch.points) {
    CHECK(std::abs(problem.RotationNumber(p.u) - torus.Rho(p.lambda)) <= 1e-8);
    CHECK(std::abs(problem.PointAt(p.u, 1.0).norm() - std::sqrt(p.lambda)) <= 1e-8);
  }
}

TEST_CASE("invariant circle: the forced van der Pol torus agrees with its long transient",
          "[torus]") {
  ForcedVanDerPolParams params;  // μ = 0.2, F = 0.1
  params.frequency = 1.6;        // far from 1:1 locking: a quasi-periodic torus
  auto system = std::make_shared<ForcedVanDerPolOscillator>(params);
  const double period = system->ForcingPeriod();
  // A long transient onto the torus, then 400 iterates of the stroboscopic map.
  OdeIntegrator integrator(*system, Tight());
  Vector x(2);
  x << 2.0, 0.0;
  for (int k = 0; k < 300; ++k) REQUIRE(integrator.Integrate(k * period, x, (k + 1) * period, x).Succeeded());
  Matrix orbit(2, 400);
  for (int k = 0; k < 400; ++k) {
    orbit.col(k) = x;
    REQUIRE(integrator.Integrate(0.0, x, period, x).Succeeded());
  }
  double rho[2] = {0.0, 0.0}, invariance[2] = {0.0, 0.0};
  int index = 0;
  for (int harmonics : {8, 16}) {
    InvariantCircleProblem problem(system, harmonics, Tight());
    Vector u = problem.CircleFromOrbit(orbit);
    const double from_orbit = problem.RotationNumber(u);
    const NewtonResult result = Solve(problem, u, params.frequency);
    INFO(harmonics << " harmonics: " << result.BriefReport());
    REQUIRE(result.Converged());
    rho[index] = problem.RotationNumber(u);
    // The transient's mean advance per iterate against the circle's conjugate rotation.
    CHECK(std::abs(problem.RotationNumber(u) - from_orbit) <= 2e-3);
    const Vector measures = problem.Measures(u, params.frequency);
    CHECK(measures(1) <= 1e-3);  // the Fourier tail: a smooth circle
    invariance[index++] = measures(2);  // invariance between the collocation points
    // Attracting: besides the 2K + 1 values along the circle, all moduli below 1.
    const std::vector<double> moduli = problem.CircleMultipliers(u, params.frequency);
    REQUIRE(moduli.size() == static_cast<size_t>(2 * (2 * harmonics + 1)));
    CHECK(moduli[static_cast<size_t>(2 * harmonics + 1)] < 0.9);
    const InvariantCircleProblem::TorusStability lyapunov =
        problem.LyapunovStability(u, params.frequency, 400);
    REQUIRE(lyapunov.valid);
    CHECK(lyapunov.stable);
    CHECK(lyapunov.tangent == 0);
  }
  // Spectral convergence in K: the defect between the points falls by orders of magnitude.
  CHECK(std::abs(rho[0] - rho[1]) <= 1e-8);
  CHECK(invariance[1] <= 1e-7);
  CHECK(invariance[1] <= 1e-2 * invariance[0]);
}


TEST_CASE("invariant circle: continued into 1:1 locking, the circle breaks down and the branch ends",
          "[torus]") {
  // Below w ≈ 1.0226 the forced van der Pol response locks to the forcing (the fold of the locked
  // orbit bounds it: forced_van_der_pol_test.cpp). Continued from w = 1.2 towards it, the torus's
  // rotation number tends to 1 (≡ 0) and its circle to the locked orbit's unstable manifold: its
  // Fourier series converges ever more slowly (12 harmonics here), and the branch ends at the
  // breakdown event, before the locking boundary, instead of continuing into the locked region
  // with collocation solutions that are no invariant circles.
  ForcedVanDerPolParams params;
  params.frequency = 1.2;
  auto system = std::make_shared<ForcedVanDerPolOscillator>(params);
  const double period = system->ForcingPeriod();
  OdeIntegrator integrator(*system, Tight());
  Vector x(2);
  x << 2.0, 0.0;
  for (int k = 0; k < 300; ++k) REQUIRE(integrator.Integrate(0.0, x, period, x).Succeeded());
  Matrix orbit(2, 200);
  for (int k = 0; k < 200; ++k) {
    orbit.col(k) = x;
    REQUIRE(integrator.Integrate(0.0, x, period, x).Succeeded());
  }
  InvariantCircleProblem problem(system, 12, Tight());
  problem.SetMaxFourierTail(1e-4);
  Vector u = problem.CircleFromOrbit(orbit);
  REQUIRE(Solve(problem, u, params.frequency).Converged());
  ContinuationOptions options;
  options.bounds.lambda_min = 0.9;
  options.bounds.lambda_max = 1.2;
  options.step.max = 0.05;
  options.detect.stability = false;
  options.direction = -1;
  const Branch branch = Continue(problem, u, params.frequency, options);
  INFO(branch.message);
  CHECK(branch.status == BranchStatus::kSwitchRefused);
  CHECK_THAT(branch.message, Catch::Contains("circle breaks down (Fourier tail)"));
  REQUIRE(!branch.points.empty());
  const BranchPoint& last = branch.points.back();
  CHECK(last.lambda > 1.0226);
  CHECK(last.lambda < 1.2);
  // Near an integer: 1:1 (the circle's orientation, from the principal plane, may reverse it).
  const double rho = problem.RotationNumber(last.u);
  CHECK(std::min(rho, 1.0 - rho) < 0.1);
}

}  // namespace
}  // namespace rubcont
