// Invariant circles of stroboscopic maps (shooting/invariant_circle.h): an exact torus with a
// known rotation number and normal multiplier, its continuation, and the forced van der Pol
// oscillator's quasi-periodic regime against its own long transient; then autonomous and relative
// tori of coupled Stuart–Landau oscillators, whose period, rotation number, rotation and
// exponents are known in closed form.
#include "shooting/invariant_circle.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "models/textbook.h"
#include "solvers/constants.h"
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

IntegratorOptions TightCircle() {
  IntegratorOptions options;
  options.relative_tolerance = 1e-11;
  options.absolute_tolerance = 1e-11;
  return options;
}

NewtonResult SolveCircle(InvariantCircleProblem& problem, Vector& u, double lambda) {
  problem.SetPhaseReference(u);
  return NewtonSolve([&](const Vector& x, Vector& F) { problem.Residual(x, lambda, F); },
                     [&](const Vector& x, Matrix& J) { problem.Jacobian(x, lambda, J); }, u, {},
                     problem.Scale(), problem.ResidualScale());
}

double Fraction(double x) { return x - std::floor(x); }

// The clocked Stuart–Landau torus of the tests: λ = 0.5, ω = 1, γ = 0.3, T = 2π/√2.
struct ClockedTorus {
  StuartLandauParams params{0.5, 1.0, 0.3};
  double period = kTwoPi / std::sqrt(2.0);
  std::shared_ptr<ClockedStuartLandau> system = std::make_shared<ClockedStuartLandau>(params, period);
  InvariantCircleProblem problem{system, 3, OrbitKind::kForced, TightCircle()};
  double Rho(double lambda) const {
    return Fraction((params.omega - params.gamma * lambda) * period / kTwoPi);
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
  const NewtonResult result = SolveCircle(problem, u, params.lambda);
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
  CHECK(std::abs(lyapunov.exponents(lyapunov.trivial.at(0))) <= 1e-2);
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
  OdeIntegrator integrator(*system, TightCircle());
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
    InvariantCircleProblem problem(system, harmonics, OrbitKind::kForced, TightCircle());
    Vector u = problem.CircleFromOrbit(orbit);
    const double from_orbit = problem.RotationNumber(u);
    const NewtonResult result = SolveCircle(problem, u, params.frequency);
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
    CHECK(lyapunov.trivial == std::vector<Index>{0});
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
  OdeIntegrator integrator(*system, TightCircle());
  Vector x(2);
  x << 2.0, 0.0;
  for (int k = 0; k < 300; ++k) REQUIRE(integrator.Integrate(0.0, x, period, x).Succeeded());
  Matrix orbit(2, 200);
  for (int k = 0; k < 200; ++k) {
    orbit.col(k) = x;
    REQUIRE(integrator.Integrate(0.0, x, period, x).Succeeded());
  }
  InvariantCircleProblem problem(system, 12, OrbitKind::kForced, TightCircle());
  problem.SetMaxFourierTail(3e-6);  // (see below)
  Vector u = problem.CircleFromOrbit(orbit);
  REQUIRE(SolveCircle(problem, u, params.frequency).Converged());
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
  // On its way to 1:1 the rotation number falls from 0.168 and passes the resonances p/q, q ≤ K,
  // whose thin tongues also roughen the circle: where the branch ends depends on the tail limit and
  // on the steps taken. Measured: at a limit of 3e-6 it ends at w = 1.11454, ρ = 0.1035, as the
  // 1:10 resonance nears (4 s); at 1e-4 it crept along the 1:10 tongue's edge in steps of 1e-6
  // in w to 1.1108 (ρ = 0.10036; 167 s in the suite), and from the geometric angles' start, the
  // same circle shifted in θ, it stepped over 1/10 and ended at 1.1000 near 1/11.
  const double rho = problem.RotationNumber(last.u);
  CHECK(rho > 0.0);
  CHECK(rho < 0.11);
  CHECK(last.measures(1) >= 3e-6 * 0.99);
}

// m Stuart–Landau oscillators z_k = x_{2k} + i x_{2k+1} with growth μ (the parameter):
//     ż_k = a_k (μ − |z_k|²) z_k + i (ω_k + b_k |z_k|²) z_k + κ (μ − |z_0|²) z_k   (κ for k ≥ 1),
// the last term zero on the torus |z_k|² = μ but coupling the oscillators off it. Every z_k turns
// at Ω_k = ω_k + b_k μ on the torus; the radial perturbations decay at −2 a_k μ (distinct rates:
// the QR estimates of equal exponents under a coupling converge only like log(k)/k). The system
// commutes with the common rotation z_k ↦ e^{iφ} z_k (generator i z_k), offered when `symmetric`.
class StuartLandauChain : public OdeSystem {
 public:
  StuartLandauChain(std::vector<double> omega, std::vector<double> shear, double mu, double kappa,
                    bool symmetric)
      : omega_(std::move(omega)), shear_(std::move(shear)), mu_(mu), kappa_(kappa),
        symmetric_(symmetric) {}
  // a_k = 1 + k/2.
  static double Rate(size_t k) { return 1.0 + 0.5 * static_cast<double>(k); }
  Index Dimension() const override { return 2 * static_cast<Index>(omega_.size()); }
  void Rhs(double /*t*/, ConstVectorRef x, VectorRef f) override {
    const double off = mu_ - x(0) * x(0) - x(1) * x(1);
    for (size_t k = 0; k < omega_.size(); ++k) {
      const double a = x(2 * k), b = x(2 * k + 1), r2 = a * a + b * b;
      const double grow = Rate(k) * (mu_ - r2) + (k > 0 ? kappa_ * off : 0.0);
      const double turn = omega_[k] + shear_[k] * r2;
      f(2 * k) = grow * a - turn * b;
      f(2 * k + 1) = grow * b + turn * a;
    }
  }
  double Parameter() const override { return mu_; }
  void SetParameter(double p) override { mu_ = p; }
  bool HasRotationSymmetry() const override { return symmetric_; }
  void Rotate(double phi, VectorRef x) const override {
    for (size_t k = 0; k < omega_.size(); ++k) {
      const double a = x(2 * k), b = x(2 * k + 1);
      x(2 * k) = std::cos(phi) * a - std::sin(phi) * b;
      x(2 * k + 1) = std::sin(phi) * a + std::cos(phi) * b;
    }
  }
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override {
    for (size_t k = 0; k < omega_.size(); ++k) {
      g(2 * k) = -x(2 * k + 1);
      g(2 * k + 1) = x(2 * k);
    }
  }
  double Turn(size_t k) const { return omega_[k] + shear_[k] * mu_; }  // Ω_k at μ

 private:
  std::vector<double> omega_, shear_;
  double mu_, kappa_;
  bool symmetric_;
};

// A circle of the torus, off on purpose: the oscillators in `fixed` at angles 0.3, 1.1 with
// radius 1.08 √μ, the last (`turning`) as a slightly elliptic circle in θ, with a second harmonic.
Matrix RoughCircle(Index states, double mu) {
  const double r = std::sqrt(mu);
  Matrix c = Matrix::Zero(states, 7);
  for (Index k = 0; 2 * k + 2 < states; ++k) {
    const double angle = k == 0 ? 0.3 : 1.1;
    c(2 * k, 0) = 1.08 * r * std::cos(angle);
    c(2 * k + 1, 0) = 1.08 * r * std::sin(angle);
  }
  c(states - 2, 1) = 1.05 * r;
  c(states - 1, 2) = 0.95 * r;
  c(states - 2, 3) = 0.02;
  return c;
}

// The largest entry of |[J, ∂F/∂λ] − its central differences| over that of |[J, ∂F/∂λ]| (steps 1e-5
// of each unknown's scale: round-off of the 1e-11 integrations ~1e-6 of it; a wrong column is off by
// O(1)).
double JacobianMismatch(InvariantCircleProblem& problem, const Vector& u, double lambda) {
  Matrix J;
  Vector dF;
  problem.Jacobian(u, lambda, J);
  problem.DfDlambda(u, lambda, dF);
  Matrix exact(J.rows(), J.cols() + 1), fd(J.rows(), J.cols() + 1);
  exact << J, dF;
  const Vector scale = problem.Scale();
  Vector plus, minus;
  for (Index i = 0; i <= u.size(); ++i) {
    const double h = 1e-5 * (i < u.size() ? scale(i) : problem.LambdaScale());
    Vector up = u, down = u;
    double lambda_up = lambda, lambda_down = lambda;
    (i < u.size() ? up(i) : lambda_up) += h;
    (i < u.size() ? down(i) : lambda_down) -= h;
    problem.Residual(up, lambda_up, plus);
    problem.Residual(down, lambda_down, minus);
    fd.col(i) = (plus - minus) / (2.0 * h);
  }
  return (exact - fd).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

// What every torus of the chain must show: each oscillator at radius √μ on the circle and the
// invariance error (both to `tolerance`), [J, ∂F/∂λ] against differences, and the exponents of P
// per period — m trivial ones (the circle, the flow, the group orbit: as many as oscillators here)
// and −2 a_k μT across the torus — stable.
void CheckChainTorus(InvariantCircleProblem& problem, const Vector& u, double mu, double period,
                     double tolerance) {
  const Index m = problem.states() / 2;
  for (double theta : {0.0, 1.3, 4.0}) {
    const Vector x = problem.PointAt(u, theta);
    for (Index k = 0; k < m; ++k) CHECK(std::abs(x.segment(2 * k, 2).norm() - std::sqrt(mu)) <= tolerance);
  }
  CHECK(problem.InvarianceError(u, mu) <= tolerance);
  CHECK(JacobianMismatch(problem, u, mu) <= 1e-5);
  const InvariantCircleProblem::TorusStability lyapunov = problem.LyapunovStability(u, mu, 200);
  REQUIRE(lyapunov.valid);
  CHECK(lyapunov.stable);
  REQUIRE(lyapunov.trivial.size() == static_cast<size_t>(m));
  for (Index k = 0; k < m; ++k) {
    CHECK(lyapunov.exponents(m + k) ==
          Approx(-2.0 * StuartLandauChain::Rate(static_cast<size_t>(k)) * mu * period).epsilon(1e-5));
  }
}

TEST_CASE("invariant circle: autonomous torus, period 2pi/Omega_0 and rotation number Omega_1/Omega_0",
          "[torus]") {
  // Two oscillators: Φ_T with T = 2π/Ω₀ leaves z₀ where it was and turns z₁ by 2π Ω₁/Ω₀: the
  // circle z₀ = const, |z₁| = √μ, with ρ = frac(Ω₁/Ω₀).
  const double mu = 0.5;
  auto system = std::make_shared<StuartLandauChain>(std::vector<double>{1.0, 1.7},
                                                    std::vector<double>{0.2, -0.3}, mu, 0.5, false);
  InvariantCircleProblem problem(system, 3, OrbitKind::kAutonomous, TightCircle());
  REQUIRE(problem.Dimension() == 4 * 7 + 2);
  const double period = kTwoPi / system->Turn(0);
  const double rho = Fraction(system->Turn(1) / system->Turn(0));  // 0.40909...
  Vector u = problem.Pack(RoughCircle(4, mu), rho + 0.01, 1.02 * period);
  const NewtonResult result = SolveCircle(problem, u, mu);
  INFO(result.BriefReport());
  REQUIRE(result.Converged());
  // Newton stops at |F| ≤ 1e-9 (100 times the integration's tolerance): ρ and T to about that.
  CHECK(std::abs(problem.RotationNumber(u) - rho) <= 1e-9);
  CHECK(std::abs(problem.Period(u, mu) - period) <= 1e-9 * period);
  CheckChainTorus(problem, u, mu, period, 1e-9);
  CHECK(problem.MeasureNames()[3] == "period");
  CHECK(problem.Measures(u, mu)(3) == Approx(period).epsilon(1e-10));
  CHECK(problem.MeasureNames().back() == "radius");

  // Continued in μ from 0.5 to 0.62: ρ(μ) = frac(Ω₁(μ)/Ω₀(μ)) from 0.409 to 0.345 and T(μ) follow
  // at every point. (The phases of this system do not interact, so at a rational ρ = p/q every
  // curve z₀ = c(θ) with c of period 2π/q is invariant too: the Jacobian is singular there once
  // K ≥ q. With K = 3 the range avoids q ≤ 3 (it crosses 2/5 and 3/8); a generic torus locks at
  // rationals instead.)
  ContinuationOptions options;
  options.bounds.lambda_min = 0.4;
  options.bounds.lambda_max = 0.62;
  options.step.max = 0.03;
  options.detect.stability = false;
  options.corrector.residual_tolerance = 1e-9;  // 100 times the integration's tolerance
  const Branch branch = Continue(problem, u, mu, options);
  INFO(branch.message);
  CHECK(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.points.size() >= 5);
  for (const BranchPoint& p : branch.points) {
    system->SetParameter(p.lambda);
    CHECK(std::abs(problem.RotationNumber(p.u) - Fraction(system->Turn(1) / system->Turn(0))) <= 1e-8);
    CHECK(std::abs(problem.Period(p.u, p.lambda) * system->Turn(0) - kTwoPi) <= 1e-8);
  }
}

// Newton on a relative torus of the chain from u; ρ, T and φ against their closed forms to 1e-9
// (Newton stops at |F| ≤ 1e-9, 100 times the integration's tolerance).
void SolveRelativeTorus(InvariantCircleProblem& problem, Vector& u, double mu, double rho,
                        double period, double rotation) {
  const NewtonResult result = SolveCircle(problem, u, mu);
  INFO(result.BriefReport());
  REQUIRE(result.Converged());
  CHECK(std::abs(problem.RotationNumber(u) - rho) <= 1e-9);
  CHECK(std::abs(problem.Period(u, mu) - period) <= 1e-9 * period);
  CHECK(std::abs(std::remainder(problem.Rotation(u) - rotation, kTwoPi)) <= 1e-9);
}

TEST_CASE("invariant circle: relative torus, period, rotation and rotation number in closed form",
          "[torus]") {
  // Three oscillators with the common rotation: P = R_{−φ} Φ_T with T = 2π/(Ω₁ − Ω₀) and
  // φ = Ω₀T (mod 2π) leaves z₀ and z₁ where they were and turns z₂ by 2π (Ω₂ − Ω₀)/(Ω₁ − Ω₀).
  const double mu = 0.5;
  auto system = std::make_shared<StuartLandauChain>(std::vector<double>{1.0, 2.3, 2.75},
                                                    std::vector<double>{0.2, -0.3, 0.1}, mu, 0.5, true);
  InvariantCircleProblem problem(system, 3, OrbitKind::kRelative, TightCircle());
  REQUIRE(problem.Dimension() == 6 * 7 + 3);
  const double period = kTwoPi / (system->Turn(1) - system->Turn(0));
  const double rotation = std::remainder(system->Turn(0) * period, kTwoPi);
  const double rho = Fraction((system->Turn(2) - system->Turn(0)) / (system->Turn(1) - system->Turn(0)));
  Vector u = problem.Pack(RoughCircle(6, mu), rho - 0.01, 0.98 * period, rotation + 0.05);
  SolveRelativeTorus(problem, u, mu, rho, period, rotation);
  // Radii to the integration's global error over T ≈ 6 at tolerance 1e-11 (measured 1.1e-9).
  CheckChainTorus(problem, u, mu, period, 5e-9);
  // Its images under the map lie on it, 2π·nρ further along: P³(u(ϑ)) = u(ϑ + 6πρ).
  const Vector angles = (Vector(3) << 0.1, 2.0, 4.5).finished();
  std::string failure;
  const Matrix images = problem.Images(u, mu, angles, 3, failure);
  REQUIRE(failure.empty());
  REQUIRE(images.cols() == 3);
  for (Index k = 0; k < 3; ++k) {
    CAPTURE(k);
    CHECK((images.col(k) - problem.PointAt(u, angles(k) + 3.0 * kTwoPi * rho)).norm() <= 1e-8);
    CHECK((images.col(k) - problem.PointAt(u, angles(k))).norm() >= 0.1);  // moved along it
  }
  // The same torus seen without the rotation as an unknown: Φ_T alone has no invariant circle near
  // this one (z₀ and z₁ turn by φ per T), and Newton says so instead of inventing one.
  InvariantCircleProblem plain(system, 3, OrbitKind::kAutonomous, TightCircle());
  Vector v = plain.Pack(RoughCircle(6, mu), rho, period);
  CHECK(!SolveCircle(plain, v, mu).Converged());
}

TEST_CASE("invariant circle: a circle turned half a turn against the reference is named stray, a "
          "nearby one is not",
          "[torus]") {
  // The relative torus above, solved; the phase conditions' reference at it. Each condition is a
  // function of its shift (θ, the flow, the group orbit) with a second root about half a period
  // away: the same torus, its circle met from the other side.
  const double mu = 0.5;
  auto system = std::make_shared<StuartLandauChain>(std::vector<double>{1.0, 2.3, 2.75},
                                                    std::vector<double>{0.2, -0.3, 0.1}, mu, 0.5, true);
  InvariantCircleProblem problem(system, 3, OrbitKind::kRelative, TightCircle());
  const double period = kTwoPi / (system->Turn(1) - system->Turn(0));
  const double rotation = std::remainder(system->Turn(0) * period, kTwoPi);
  const double rho = Fraction((system->Turn(2) - system->Turn(0)) / (system->Turn(1) - system->Turn(0)));
  Vector u = problem.Pack(RoughCircle(6, mu), rho - 0.01, 0.98 * period, rotation + 0.05);
  SolveRelativeTorus(problem, u, mu, rho, period, rotation);
  problem.SetPhaseReference(u);
  CHECK(problem.StrayPoint(u, mu).empty());
  // u(θ + α): harmonic k's (a_k, b_k) turned by kα.
  auto turned = [&](double alpha) {
    Matrix c = problem.Coefficients(u);
    for (int k = 1; k <= problem.harmonics(); ++k) {
      const Vector a = c.col(2 * k - 1), b = c.col(2 * k);
      c.col(2 * k - 1) = std::cos(k * alpha) * a + std::sin(k * alpha) * b;
      c.col(2 * k) = -std::sin(k * alpha) * a + std::cos(k * alpha) * b;
    }
    return problem.Pack(c, problem.RotationNumber(u), problem.Period(u, mu), problem.Rotation(u));
  };
  CHECK(problem.StrayPoint(turned(0.3), mu).empty());
  CHECK_THAT(problem.StrayPoint(turned(kPi), mu), Catch::Contains("turned against the last one along θ"));
  // The circle turned by π about the symmetry's axis (every oscillator's z ↦ −z): against the
  // reference along all three shifts; θ is named first.
  const Vector opposite = problem.Pack(-problem.Coefficients(u), problem.RotationNumber(u),
                                       problem.Period(u, mu), problem.Rotation(u));
  CHECK_THAT(problem.StrayPoint(opposite, mu), Catch::Contains("turned against the last one"));
}

// The chain with a chart: every oscillator but the last in polar coordinates (|z_k|, arg z_k),
// the last (the one that turns along the circle) as it is.
class ChartedChain : public StuartLandauChain {
 public:
  using StuartLandauChain::StuartLandauChain;
  bool HasStateChart() const override { return true; }
  void ToChart(ConstVectorRef x, VectorRef y) const override {
    y = x;
    for (Index k = 0; 2 * k + 2 < Dimension(); ++k) {
      y(2 * k) = std::hypot(x(2 * k), x(2 * k + 1));
      y(2 * k + 1) = std::atan2(x(2 * k + 1), x(2 * k));
    }
  }
  void FromChart(ConstVectorRef y, VectorRef x, Matrix* jacobian) const override {
    x = y;
    if (jacobian) jacobian->setIdentity(Dimension(), Dimension());
    for (Index k = 0; 2 * k + 2 < Dimension(); ++k) {
      const double r = y(2 * k), c = std::cos(y(2 * k + 1)), s = std::sin(y(2 * k + 1));
      x(2 * k) = r * c;
      x(2 * k + 1) = r * s;
      if (jacobian) {
        (*jacobian)(2 * k, 2 * k) = c;
        (*jacobian)(2 * k + 1, 2 * k) = s;
        (*jacobian)(2 * k, 2 * k + 1) = -r * s;
        (*jacobian)(2 * k + 1, 2 * k + 1) = r * c;
      }
    }
  }
  std::vector<Index> ChartAngles() const override {
    std::vector<Index> angles;
    for (Index k = 0; 2 * k + 2 < Dimension(); ++k) angles.push_back(2 * k + 1);
    return angles;
  }
};

TEST_CASE("invariant circle in a chart: the relative torus in closed form, its Jacobian exact",
          "[torus]") {
  // The relative torus above, its circle written in polar coordinates for z₀ and z₁ (angles near
  // ±π, so that the fit must unwrap them) and Cartesian ones for z₂; fitted from points of the
  // rough circle at θ_k = 2πkρ (CircleAtRotationNumber), then solved.
  const double mu = 0.5;
  auto system = std::make_shared<ChartedChain>(std::vector<double>{1.0, 2.3, 2.75},
                                               std::vector<double>{0.2, -0.3, 0.1}, mu, 0.5, true);
  InvariantCircleProblem problem(system, 3, OrbitKind::kRelative, TightCircle(), CircleCoordinates::kChart);
  CHECK(problem.coordinates() == CircleCoordinates::kChart);
  const double period = kTwoPi / (system->Turn(1) - system->Turn(0));
  const double rotation = std::remainder(system->Turn(0) * period, kTwoPi);
  const double rho = Fraction((system->Turn(2) - system->Turn(0)) / (system->Turn(1) - system->Turn(0)));
  Matrix rough = RoughCircle(6, mu);
  // z₀ = −0.7 + 0.02 i cos θ: its angle crosses ±π twice along the circle.
  rough.block(0, 0, 2, 2) << -0.7, 0.0, 0.0, 0.02;
  Matrix points(6, 30);
  for (Index k = 0; k < points.cols(); ++k) {
    const double theta = kTwoPi * rho * static_cast<double>(k);
    Vector basis(7);
    basis << 1.0, std::cos(theta), std::sin(theta), std::cos(2 * theta), std::sin(2 * theta),
        std::cos(3 * theta), std::sin(3 * theta);
    points.col(k) = rough * basis;
  }
  Vector u = problem.CircleAtRotationNumber(points, rho, 0.98 * period, rotation + 0.05);
  // The fit reproduces the rough circle (in states; z₀'s angle is no trigonometric polynomial,
  // but its third harmonic is ~(0.02/0.7)³), its z₀ angle unwrapped across ±π: mean π.
  CHECK((problem.PointAt(u, 0.0) - points.col(0)).norm() <= 1e-4);
  CHECK(std::abs(problem.Coefficients(u)(1, 0) - kPi) <= 1e-3);
  u(problem.Dimension() - 3) = rho - 0.01;
  SolveRelativeTorus(problem, u, mu, rho, period, rotation);
  // In the chart the oscillators' radii are coefficients of their own: constant on the circle.
  CHECK(std::abs(problem.Coefficients(u)(0, 0) - std::sqrt(mu)) <= 5e-9);
  CHECK(problem.HarmonicSize(u, 1) >= 0.5);  // z₂ turns once along the circle
  CheckChainTorus(problem, u, mu, period, 5e-9);
  // Without a chart the system refuses kChart.
  CHECK_THROWS_WITH(InvariantCircleProblem(std::make_shared<StuartLandauChain>(
                                               std::vector<double>{1.0, 2.3}, std::vector<double>{0.2, -0.3},
                                               mu, 0.5, true),
                                           3, OrbitKind::kRelative, TightCircle(), CircleCoordinates::kChart),
                    Catch::Contains("no state chart"));
}

// Only the points matter to CircleFromOrbit: a forced system of four states that does nothing.
class FourStatesAtRest : public OdeSystem {
 public:
  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef, VectorRef f) override { f.setZero(); }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  double ForcingPeriod() const override { return 1.0; }
};

TEST_CASE("invariant circle: a circle through points at given angles (a circle's images under a "
          "map) is the trigonometric polynomial through them",
          "[torus]") {
  // The refinement in K's start (shooting/modulated_torus.h): points of a coarser circle mapped n
  // times lie at θ_k + 2πnρ. Here the points of a polynomial of 2 harmonics at uneven angles: the
  // fit returns its coefficients, and ρ as given.
  InvariantCircleProblem problem(std::make_shared<FourStatesAtRest>(), 2, OrbitKind::kForced);
  Matrix coefficients(4, 5);
  coefficients << 0.1, 1.0, 0.0, 0.2, -0.1,  //
      -0.3, 0.0, 1.0, 0.05, 0.0,             //
      0.0, 0.3, -0.2, 0.0, 0.4,              //
      2.0, 0.0, 0.0, -0.6, 0.1;
  const Index m = 13;
  Vector angles(m);
  Matrix points(4, m);
  for (Index k = 0; k < m; ++k) {
    angles(k) = kTwoPi * static_cast<double>(k) / m + 2.0 * kTwoPi * 0.37 + 0.2 * std::sin(1.7 * k);
    Vector basis(5);
    basis << 1.0, std::cos(angles(k)), std::sin(angles(k)), std::cos(2 * angles(k)),
        std::sin(2 * angles(k));
    points.col(k) = coefficients * basis;
  }
  const Vector u = problem.CircleAtAngles(points, angles, 0.37);
  CHECK((problem.Coefficients(u) - coefficients).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK(problem.RotationNumber(u) == 0.37);
  CHECK_THROWS_WITH(problem.CircleAtAngles(points, angles.head(m - 1), 0.37),
                    Catch::Contains("4 × 13 points at 12 angles"));
  CHECK_THROWS_WITH(problem.CircleAtAngles(points.leftCols(5), angles.head(5), 0.37),
                    Catch::Contains("at least 6 columns"));
}

TEST_CASE("invariant circle: points on a curve that winds twice round its centre in its principal "
          "plane are fitted once round, not as a circle covered twice",
          "[torus]") {
  // u(θ) = (cos 2θ, sin 2θ, 0.3 cos θ, 0.3 sin θ) at θ_k = 2πkρ, ρ = 0.694: in the (x, y) plane the
  // points advance 2ρ − 1 = 0.388 turns per iterate, and angles 2πk·ρ/2 fit them exactly with
  // harmonics 2 and 4 (u = w(2θ)): a circle covered twice, whose invariance equation is singular
  // (C(c) at 64 rpm). The fit must return the curve itself, once round, in the orientation whose
  // rotation number is at most 1/2: ρ = 1 − 0.694 = 0.306 and u(θ) = curve(−θ).
  const double rho = 0.694;
  const int harmonics = 8;
  InvariantCircleProblem problem(std::make_shared<FourStatesAtRest>(), harmonics,
                                 OrbitKind::kForced);
  auto curve = [](double theta) {
    return Eigen::Vector4d(std::cos(2 * theta), std::sin(2 * theta), 0.3 * std::cos(theta),
                           0.3 * std::sin(theta));
  };
  Matrix points(4, 4 * (2 * harmonics + 1));
  for (Index k = 0; k < points.cols(); ++k) {
    points.col(k) = curve(kTwoPi * rho * static_cast<double>(k));
  }
  const Vector u = problem.CircleFromOrbit(points);
  // To the fit's grid in ρ (its last step 4/(100 m · 50) = 1.2e-5): a start for Newton.
  CHECK(std::abs(problem.RotationNumber(u) - (1.0 - rho)) <= 1e-5);
  for (const double theta : {0.0, 0.37, 1.9, 4.4}) {
    CAPTURE(theta);
    CHECK((problem.PointAt(u, theta) - curve(-theta)).norm() <= 1e-3);
  }
  CHECK(problem.HarmonicSize(u, 1) == Approx(0.3 * std::sqrt(2.0)).epsilon(1e-6));
  CHECK(problem.HarmonicSize(u, 2) == Approx(std::sqrt(2.0)).epsilon(1e-6));
  for (int k = 3; k <= harmonics; ++k) CHECK(problem.HarmonicSize(u, k) <= 1e-3);
}

TEST_CASE("invariant circle: the same circle traversed either way is fitted with its rotation "
          "number at most 1/2",
          "[torus]") {
  // Points x_k = c(θ_s + 2πkρ) of c(θ) = (cos θ, sin θ, 0.2 cos 2θ, 0.1 sin 3θ) for ρ = 0.37 and
  // for ρ = 0.63 (the first traversed the other way, θ → −θ), from nine starting angles θ_s:
  // every fit returns ρ = 0.37 and a circle u along which the points advance by +0.37 turns per
  // iterate. Without the rule the principal directions' signs decided (here 0.63 from six of the
  // eighteen), and with them the points' rounding (C(a) at 49 rpm: 0.3789 or 0.6211).
  const int harmonics = 8;
  InvariantCircleProblem problem(std::make_shared<FourStatesAtRest>(), harmonics,
                                 OrbitKind::kForced);
  auto curve = [](double theta) {
    return Eigen::Vector4d(std::cos(theta), std::sin(theta), 0.2 * std::cos(2 * theta),
                           0.1 * std::sin(3 * theta));
  };
  for (const double rho : {0.37, 0.63}) {
    for (const double start : {0.0, 0.7, 1.4, 2.1, 2.8, 3.5, 4.2, 4.9, 5.6}) {
      CAPTURE(rho, start);
      Matrix points(4, 4 * (2 * harmonics + 1));
      for (Index k = 0; k < points.cols(); ++k) {
        points.col(k) = curve(start + kTwoPi * rho * static_cast<double>(k));
      }
      const Vector u = problem.CircleFromOrbit(points);
      // The fit's ρ: the points' mean angle advance, or refined on its grid.
      CHECK(std::abs(problem.RotationNumber(u) - 0.37) <= 1e-4);
      // Each point's angle on u (the nearest of 3600), and the advance to the next point's.
      auto angle_of = [&](const Vector& x) {
        double best = 0.0, nearest = kInfinity;
        for (int i = 0; i < 3600; ++i) {
          const double theta = kTwoPi * i / 3600.0;
          const double d = (problem.PointAt(u, theta) - x).norm();
          if (d < nearest) {
            nearest = d;
            best = theta;
          }
        }
        CHECK(nearest <= 0.01);
        return best;
      };
      for (Index k = 0; k < 5; ++k) {
        CAPTURE(k);
        double advance = angle_of(points.col(k + 1)) - angle_of(points.col(k));
        advance -= kTwoPi * std::floor(advance / kTwoPi);
        CHECK(advance / kTwoPi == Approx(0.37).margin(0.01));
      }
    }
  }
}

TEST_CASE("invariant circle: a map that fails names its point and the integrator's report",
          "[torus][failure]") {
  // The clocked torus's circle under an integrator allowed 3 steps per period: each point's map
  // fails, the residual is non-finite, and MapFailure says where and why; under the tests' own
  // integrator the maps succeed and it says nothing.
  ClockedTorus torus;
  const double r = std::sqrt(torus.params.lambda);
  Matrix c = Matrix::Zero(2, 7);
  c.col(1) << r, 0.0;
  c.col(2) << 0.0, r;
  IntegratorOptions starved = TightCircle();
  starved.max_steps = 3;
  InvariantCircleProblem problem(torus.system, 3, OrbitKind::kForced, starved);
  const Vector u = problem.Pack(c, torus.Rho(torus.params.lambda));
  Vector F;
  problem.Residual(u, torus.params.lambda, F);
  CHECK_FALSE(F.allFinite());
  CHECK_THAT(problem.MapFailure(),
             Catch::StartsWith("the map of the circle's point 0 of 7 (θ = 0.0000) failed: "
                               "too much work"));
  torus.problem.Residual(u, torus.params.lambda, F);
  CHECK(F.allFinite());
  CHECK(torus.problem.MapFailure().empty());
}

TEST_CASE("invariant circle: a kind the system cannot have is rejected", "[torus][failure]") {
  auto plain = std::make_shared<StuartLandauChain>(std::vector<double>{1.0, 1.7},
                                                   std::vector<double>{0.0, 0.0}, 0.5, 0.0, false);
  CHECK_THROWS_WITH(InvariantCircleProblem(plain, 3, OrbitKind::kRelative),
                    Catch::Contains("a relative torus needs a system with a rotation symmetry"));
  CHECK_THROWS_WITH(InvariantCircleProblem(plain, 3, OrbitKind::kForced),
                    Catch::Contains("the system is not forced"));
  StuartLandauParams params{0.5, 1.0, 0.3};
  auto clocked = std::make_shared<ClockedStuartLandau>(params, 2.0);
  CHECK_THROWS_WITH(InvariantCircleProblem(clocked, 3, OrbitKind::kAutonomous),
                    Catch::Contains("an autonomous torus needs an unforced system"));
}

}  // namespace
}  // namespace rubcont
