// Gauss–Legendre collocation (solvers/ode_gauss.cpp) against closed forms: its order, that its
// state-transition matrix is the exact derivative of the discrete map, and that a stiff undamped
// mode it does not resolve keeps its amplitude (|R(iy)| = 1), where BDF damps it.
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "flow_differences.h"
#include "solvers/constants.h"
#include "solvers/ode.h"

namespace rubcont {
namespace {

IntegratorOptions Gauss(int stages, long steps) {
  IntegratorOptions options;
  options.method = IntegrationMethod::kGaussCollocation;
  options.collocation_stages = stages;
  options.collocation_steps = steps;
  options.relative_tolerance = 1e-12;
  options.absolute_tolerance = 1e-12;
  return options;
}

// Central differences of the map x0 ↦ x(t1): in the system's parameter (step h), and in the end
// time t1 (step 1e-7·t1).
Vector ParameterDerivativeByDifferences(OdeIntegrator& integrator, OdeSystem& system,
                                        const Vector& x0, double t1, double h) {
  const double p = system.Parameter();
  Vector plus(x0.size()), minus(x0.size());
  system.SetParameter(p + h);
  REQUIRE(integrator.Integrate(0.0, x0, t1, plus).Succeeded());
  system.SetParameter(p - h);
  REQUIRE(integrator.Integrate(0.0, x0, t1, minus).Succeeded());
  system.SetParameter(p);
  return (plus - minus) / (2 * h);
}

Vector EndTimeDerivativeByDifferences(OdeIntegrator& integrator, const Vector& x0, double t1) {
  const double dt = 1e-7 * t1;
  Vector later(x0.size()), earlier(x0.size());
  REQUIRE(integrator.Integrate(0.0, x0, t1 + dt, later).Succeeded());
  REQUIRE(integrator.Integrate(0.0, x0, t1 - dt, earlier).Succeeded());
  return (later - earlier) / (2.0 * dt);
}

// Stuart–Landau ż = (λ + iω) z − (1 + iγ)|z|² z from z0 = r0 (real): r² = λ r0² e^{2λt} / D,
// D = λ + r0²(e^{2λt} − 1), θ = ωt − (γ/2) ln(D/λ).
Vector StuartLandauExact(const StuartLandauParams& p, double r0, double t) {
  const double D = p.lambda + r0 * r0 * (std::exp(2 * p.lambda * t) - 1.0);
  const double r = std::sqrt(p.lambda * r0 * r0 * std::exp(2 * p.lambda * t) / D);
  const double theta = p.omega * t - 0.5 * p.gamma * std::log(D / p.lambda);
  return (Vector(2) << r * std::cos(theta), r * std::sin(theta)).finished();
}

StuartLandauParams Shear() {
  StuartLandauParams p;
  p.lambda = 0.5;
  p.omega = 2.0;
  p.gamma = 0.7;
  return p;
}

TEST_CASE("Gauss collocation with s stages converges with order 2s on Stuart-Landau", "[ode][gauss]") {
  const StuartLandauParams p = Shear();
  StuartLandauOscillator system(p);
  const double r0 = 0.2, T = 4.0;
  const Vector exact = StuartLandauExact(p, r0, T);
  const Vector x0 = (Vector(2) << r0, 0.0).finished();
  for (int s = 1; s <= 4; ++s) {
    CAPTURE(s);
    // Coarse enough that the error is far above rounding at the finer mesh.
    const long coarse = s <= 2 ? 40 : 10;
    double errors[2];
    for (int k = 0; k < 2; ++k) {
      OdeIntegrator integrator(system, Gauss(s, coarse << k));
      Vector x(2);
      REQUIRE(integrator.Integrate(0.0, x0, T, x).Succeeded());
      errors[k] = (x - exact).norm();
    }
    const double order = std::log2(errors[0] / errors[1]);
    CHECK(order == Approx(2.0 * s).epsilon(0).margin(0.3));
  }
}

TEST_CASE("Gauss collocation's STM and dx/dp are the derivatives of its discrete map",
          "[ode][gauss]") {
  DuffingOscillator system;  // forced, nonlinear, with ∂f/∂w
  const Vector x0 = (Vector(2) << 0.7, -0.3).finished();
  const double T = kTwoPi / system.Parameter();
  OdeIntegrator integrator(system, Gauss(3, 25));  // coarse: the map differs from the flow
  Vector x(2), dxdp;
  Matrix stm;
  REQUIRE(integrator.Integrate(0.0, x0, T, x, &stm, &dxdp).Succeeded());
  // Central differences of the map x0 ↦ x(T), steps 1e-6 (|x0_i| < 1).
  const double h = 1e-6;
  const Matrix fd = testing::FlowJacobianByDifferences(integrator, x0, T, h);
  CHECK((stm - fd).norm() <= 1e-8 * stm.norm());
  CHECK((dxdp - ParameterDerivativeByDifferences(integrator, system, x0, T, h)).norm() <=
        1e-7 * dxdp.norm());
}

// ẍ = −ω² x, ω = 1e5 — the stiff contact's scale — over steps with ωh = 20.
class StiffOscillator : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f << x(1), -kOmega * kOmega * x(0); }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef, MatrixRef J) override { J << 0, 1, -kOmega * kOmega, 0; }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  Vector StateScale() const override { return (Vector(2) << 1.0, kOmega).finished(); }
  static constexpr double kOmega = 1e5;
};

TEST_CASE("an unresolved undamped stiff mode keeps its energy under Gauss collocation, not BDF",
          "[ode][gauss]") {
  StiffOscillator system;
  const double T = 0.01;  // 159 oscillations
  const Vector x0 = (Vector(2) << 1e-6, 0.0).finished();
  const auto energy = [](const Vector& x) {
    return x(1) * x(1) + StiffOscillator::kOmega * StiffOscillator::kOmega * x(0) * x(0);
  };
  OdeIntegrator gauss(system, Gauss(4, 50));  // ωh = 20
  Vector x(2);
  Matrix stm;
  REQUIRE(gauss.Integrate(0.0, x0, T, x, &stm).Succeeded());
  // Exact in exact arithmetic; rounding of 50 solves with cond(M) ~ (ωh)² leaves ~3e-12.
  CHECK(energy(x) == Approx(energy(x0)).epsilon(1e-10));
  const Eigen::VectorXcd multipliers = stm.eigenvalues();
  CHECK(std::abs(multipliers(0)) == Approx(1.0).epsilon(1e-10));
  CHECK(std::abs(multipliers(1)) == Approx(1.0).epsilon(1e-10));
  // BDF ≤ 2 with its error control off the mode (loose tolerance): the energy is damped away.
  IntegratorOptions bdf;
  bdf.max_order = 2;
  bdf.relative_tolerance = bdf.absolute_tolerance = 1e-2;
  bdf.max_step = T / 50;
  OdeIntegrator damped(system, bdf);
  REQUIRE(damped.Integrate(0.0, x0, T, x).Succeeded());
  CHECK(energy(x) < 1e-3 * energy(x0));
}

// Two forced oscillators, coupled, with a cubic spring and a velocity-dependent damping — a
// second-order system x = [q; v], f = [v; a(t, q, v)] with its analytic Jacobian — or the same
// system with its halves swapped (x = [v; q], f = [a; v]), which is not of that form.
class CoupledOscillators : public OdeSystem {
 public:
  explicit CoupledOscillators(bool swapped) : swapped_(swapped) {}
  Index Dimension() const override { return 4; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    const double q1 = Q(x, 0), q2 = Q(x, 1), v1 = V(x, 0), v2 = V(x, 1);
    const double a1 = -0.1 * v1 - q1 - 0.5 * q1 * q1 * q1 + 0.3 * (q2 - q1) + 0.4 * std::cos(w_ * t);
    const double a2 = -0.1 * v2 - 2.0 * q2 + 0.3 * (q1 - q2) - 0.2 * q2 * v2;
    if (swapped_) {
      f << a1, a2, v1, v2;
    } else {
      f << v1, v2, a1, a2;
    }
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double q1 = Q(x, 0), q2 = Q(x, 1), v2 = V(x, 1);
    Matrix K = Matrix::Zero(4, 4);  // in the order [q1, q2, v1, v2]
    K(0, 2) = K(1, 3) = 1.0;
    K(2, 0) = -1.0 - 1.5 * q1 * q1 - 0.3;
    K(2, 1) = 0.3;
    K(2, 2) = -0.1;
    K(3, 0) = 0.3;
    K(3, 1) = -2.0 - 0.3 - 0.2 * v2;
    K(3, 3) = -0.1 - 0.2 * q2;
    if (!swapped_) {
      J = K;
      return;
    }
    const Eigen::PermutationMatrix<4> P = Swap();
    J = P * K * P.transpose();
  }
  double Parameter() const override { return w_; }
  void SetParameter(double w) override { w_ = w; }
  void DfDparameter(double t, ConstVectorRef, VectorRef df) override {
    df.setZero();
    df(swapped_ ? 0 : 2) = -0.4 * t * std::sin(w_ * t);
  }
  // Maps a state of the plain order to this system's order.
  static Eigen::PermutationMatrix<4> Swap() {
    Eigen::PermutationMatrix<4> P;
    P.indices() << 2, 3, 0, 1;  // plain entry i goes to place indices(i)
    return P;
  }

 private:
  double Q(ConstVectorRef x, Index i) const { return x(swapped_ ? 2 + i : i); }
  double V(ConstVectorRef x, Index i) const { return x(swapped_ ? i : 2 + i); }
  bool swapped_;
  double w_ = 1.3;
};

// A forced Duffing oscillator (n = 2: the reduced system's blocks are numbers,
// SolveScalarOscillator), plain x = [q; v] or swapped x = [v; q].
class ForcedDuffing : public OdeSystem {
 public:
  explicit ForcedDuffing(bool swapped) : swapped_(swapped) {}
  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    const double q = x(swapped_ ? 1 : 0), v = x(swapped_ ? 0 : 1);
    const double a = -0.2 * v - q - q * q * q + 0.5 * std::cos(w_ * t);
    f(swapped_ ? 1 : 0) = v;
    f(swapped_ ? 0 : 1) = a;
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double q = x(swapped_ ? 1 : 0);
    const Index iq = swapped_ ? 1 : 0, iv = swapped_ ? 0 : 1;
    J.setZero();
    J(iq, iv) = 1.0;
    J(iv, iq) = -1.0 - 3.0 * q * q;
    J(iv, iv) = -0.2;
  }
  double Parameter() const override { return w_; }
  void SetParameter(double w) override { w_ = w; }
  void DfDparameter(double t, ConstVectorRef, VectorRef df) override {
    df.setZero();
    df(swapped_ ? 0 : 1) = -0.5 * t * std::sin(w_ * t);
  }

 private:
  bool swapped_;
  double w_ = 1.2;
};

// `plain` (second order) and `swapped` (the same system, states permuted by P: not second order)
// integrated by Gauss collocation give the same map and derivatives, the first on the reduced system.
void CheckReducedAgainstFull(OdeSystem& plain, OdeSystem& swapped,
                             const Eigen::PermutationMatrix<Eigen::Dynamic>& P, const Vector& x0) {
  const Index n = x0.size();
  const double t1 = 7.0;
  OdeIntegrator reduced(plain, Gauss(4, 30)), full(swapped, Gauss(4, 30));
  Vector x(n), y(n), dxdp, dydp, dxdt1, dydt1;
  Matrix stm, stm_full;
  const IntegrationResult a = reduced.Integrate(0.0, x0, t1, x, &stm, &dxdp, &dxdt1);
  const IntegrationResult b = full.Integrate(0.0, P * x0, t1, y, &stm_full, &dydp, &dydt1);
  REQUIRE(a.Succeeded());
  REQUIRE(b.Succeeded());
  CHECK(a.statistics.reduced_setups == a.statistics.linear_solver_setups);
  CHECK(a.statistics.reduced_setups > 0);
  CHECK(b.statistics.reduced_setups == 0);
  CHECK(a.statistics.nonlinear_iterations == b.statistics.nonlinear_iterations);
  // The same iterates up to rounding: the block elimination is exact linear algebra.
  CHECK((P * x - y).norm() <= 1e-13 * y.norm());
  const Matrix stm_plain = P.transpose() * stm_full * P;
  CHECK((stm - stm_plain).norm() <= 1e-12 * stm.norm());
  CHECK((P * dxdp - dydp).norm() <= 1e-12 * dydp.norm());
  CHECK((P * dxdt1 - dydt1).norm() <= 1e-12 * dydt1.norm());
  // And the STM is the derivative of the map (central differences, steps 1e-6).
  const Matrix fd = testing::FlowJacobianByDifferences(reduced, x0, t1, 1e-6);
  CHECK((stm - fd).norm() <= 1e-7 * stm.norm());
}

TEST_CASE("Gauss collocation solves a second-order system's stages on half the unknowns, "
          "with the full method's map and derivatives",
          "[ode][gauss]") {
  SECTION("two coupled oscillators (blocks of 2 × 2)") {
    CoupledOscillators plain(false), swapped(true);
    const Eigen::PermutationMatrix<Eigen::Dynamic> P(CoupledOscillators::Swap().indices());
    CheckReducedAgainstFull(plain, swapped, P, (Vector(4) << 0.8, -0.4, 0.2, 0.5).finished());
  }
  SECTION("one Duffing oscillator (blocks of 1 × 1: numbers)") {
    ForcedDuffing plain(false), swapped(true);
    Eigen::PermutationMatrix<Eigen::Dynamic> P(2);
    P.indices() << 1, 0;
    CheckReducedAgainstFull(plain, swapped, P, (Vector(2) << 0.8, -0.3).finished());
  }
}

TEST_CASE("Gauss collocation's dx/dt1 is the derivative of its map in the end time, not f(t1, x1)",
          "[ode][gauss]") {
  // The map on N uniform steps of [0, t1] moves with t1 through h = t1/N: where the mesh does not
  // resolve a mode the two differ. Central differences of the map in t1 (steps 1e-7 of t1).
  SECTION("the unresolved stiff oscillator (ωh = 20): f(t1, x1) is off by its whole size") {
    StiffOscillator system;
    const double t1 = 0.01;
    const Vector x0 = (Vector(2) << 1e-6, 0.0).finished();
    OdeIntegrator gauss(system, Gauss(4, 50));
    Vector x(2), dxdt1, f(2);
    Matrix stm;
    REQUIRE(gauss.Integrate(0.0, x0, t1, x, &stm, nullptr, &dxdt1).Succeeded());
    const Vector scale = system.StateScale();
    const Vector fd = EndTimeDerivativeByDifferences(gauss, x0, t1);
    CHECK((dxdt1 - fd).cwiseQuotient(scale).norm() <= 1e-5 * dxdt1.cwiseQuotient(scale).norm());
    system.Rhs(t1, x, f);
    CHECK((f - fd).cwiseQuotient(scale).norm() > 0.5 * fd.cwiseQuotient(scale).norm());
  }
  SECTION("the forced Duffing oscillator (f depends on t), dx/dp asked for as well") {
    DuffingOscillator system;
    const Vector x0 = (Vector(2) << 0.7, -0.3).finished();
    const double t1 = kTwoPi / system.Parameter();
    OdeIntegrator gauss(system, Gauss(3, 25));
    Vector x(2), dxdp, dxdt1, f(2);
    Matrix stm;
    REQUIRE(gauss.Integrate(0.0, x0, t1, x, &stm, &dxdp, &dxdt1).Succeeded());
    const Vector fd = EndTimeDerivativeByDifferences(gauss, x0, t1);
    CHECK((dxdt1 - fd).norm() <= 1e-6 * dxdt1.norm());
    // Resolved: here the map's derivative is near the flow's.
    system.Rhs(t1, x, f);
    CHECK((f - fd).norm() <= 1e-2 * fd.norm());
  }
  SECTION("an error-controlled method returns f(t1, x1)") {
    DuffingOscillator system;
    const Vector x0 = (Vector(2) << 0.7, -0.3).finished();
    OdeIntegrator bdf(system, IntegratorOptions());
    Vector x(2), dxdt1, f(2);
    Matrix stm;
    REQUIRE(bdf.Integrate(0.0, x0, 1.0, x, &stm, nullptr, &dxdt1).Succeeded());
    system.Rhs(1.0, x, f);
    CHECK(dxdt1 == f);
    CHECK_THROWS_AS(bdf.Integrate(0.0, x0, 1.0, x, nullptr, nullptr, &dxdt1), std::invalid_argument);
  }
}

TEST_CASE("Gauss collocation's dense output is the collocation polynomial", "[ode][gauss]") {
  const StuartLandauParams p = Shear();
  StuartLandauOscillator system(p);
  const Vector x0 = (Vector(2) << 0.2, 0.0).finished();
  OdeIntegrator integrator(system, Gauss(4, 100));
  const Vector times = Vector::LinSpaced(37, 0.0, 4.0);
  Matrix states;
  REQUIRE(integrator.Sample(0.0, x0, times, states).Succeeded());
  for (Index k = 0; k < times.size(); ++k) {
    CAPTURE(times(k));
    // Stage order s = 4 between mesh points: h⁵ ≈ 1e-8.
    CHECK((states.col(k) - StuartLandauExact(p, 0.2, times(k))).norm() <= 1e-8);
  }
  Vector x(2);
  REQUIRE(integrator.Integrate(0.0, x0, 4.0, x).Succeeded());
  CHECK((states.col(times.size() - 1) - x).norm() <= 1e-15);  // the same mesh, the same end
}

TEST_CASE("the Gauss stability function is the diagonal Padé approximant of the exponential",
          "[ode][gauss]") {
  using C = std::complex<double>;
  for (const C z : {C(-0.7, 0.3), C(0.2, -1.5), C(-40.0, 3.0)}) {
    CAPTURE(z);
    CHECK(std::abs(GaussStabilityFunction(1, z) - (1.0 + z / 2.0) / (1.0 - z / 2.0)) < 1e-14);
    const C p2 = 1.0 + z / 2.0 + z * z / 12.0, q2 = 1.0 - z / 2.0 + z * z / 12.0;
    CHECK(std::abs(GaussStabilityFunction(2, z) - p2 / q2) < 1e-13);
  }
  for (int s = 1; s <= 6; ++s) {
    CAPTURE(s);
    // Rounding of the coefficients (a Vandermonde inverse) grows with s: 1e-12 covers s = 6.
    CHECK(std::abs(GaussStabilityFunction(s, C(0.0, 7.3))) == Approx(1.0).epsilon(1e-12));
    // Order 2s: the error constant of the (s, s) Padé approximant, (s!)²/((2s)!(2s+1)!), times
    // 1 + O(z) (1.11 at z = 0.1 for s = 1).
    double constant = 1.0;
    for (int k = 1; k <= s; ++k) constant *= k * k;
    for (int k = 1; k <= 2 * s; ++k) constant /= k;
    for (int k = 1; k <= 2 * s + 1; ++k) constant /= k;
    const double error = std::abs(GaussStabilityFunction(s, C(0.1, 0.0)) - std::exp(0.1));
    CHECK(error <= 1.2 * constant * std::pow(0.1, 2 * s + 1) + 1e-15);
    CHECK(error >= 0.9 * constant * std::pow(0.1, 2 * s + 1) - 1e-15);
    CHECK(std::abs(GaussStabilityFunction(s, C(-1e-3, 50.0))) < 1.0);
  }
  CHECK_THROWS_AS(GaussStabilityFunction(0, 1.0), std::invalid_argument);
}

// ẋ = −tanh(x/ε): the regularized dry friction of the rub, sliding at rate 1 until x ≈ 0, then
// held there (x(t) = 1 − t for t < 1 − O(ε), then |x| = O(ε)).
class TanhFriction : public OdeSystem {
 public:
  Index Dimension() const override { return 1; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f(0) = -std::tanh(x(0) / kEpsilon); }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double c = std::cosh(x(0) / kEpsilon);
    J(0, 0) = -1.0 / (kEpsilon * c * c);
  }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  static constexpr double kEpsilon = 1e-3;
};

TEST_CASE("Gauss collocation's stage Newton backtracks through the steep tanh of friction",
          "[ode][gauss]") {
  // Steps of 0.1 (100 ε): the step that reaches x ≈ 0 starts its Newton from the extrapolated
  // slide, far out on the flat of the tanh, where full Newton steps diverge.
  TanhFriction system;
  for (long steps : {20L, 13L}) {
    CAPTURE(steps);
    OdeIntegrator integrator(system, Gauss(4, steps));
    Vector x(1);
    const IntegrationResult result = integrator.Integrate(0.0, Vector::Ones(1), 2.0, x);
    INFO(result.BriefReport());
    REQUIRE(result.Succeeded());
    // Held near 0: within 10 ε (Gauss does not damp the stiff decay there, |R(−∞)| = 1, so the
    // arrival step's error stays: 1.4 ε with 13 steps), against 1 at the start.
    CHECK(std::abs(x(0)) <= 10 * TanhFriction::kEpsilon);
    Vector halfway(1);
    OdeIntegrator(system, Gauss(4, steps)).Integrate(0.0, Vector::Ones(1), 0.5, halfway);
    CHECK(halfway(0) == Approx(0.5).epsilon(0).margin(1e-9));
  }
}

TEST_CASE("Gauss collocation refuses events and invalid meshes, and reports Newton failure",
          "[ode][gauss]") {
  StuartLandauOscillator system(Shear());
  OdeIntegrator integrator(system, Gauss(2, 10));
  EventOptions events;
  events.count = 1;
  events.function = [](double, ConstVectorRef x, VectorRef g) { g(0) = x(0); };
  CHECK_THROWS_AS(integrator.SetEvents(events), std::invalid_argument);
  CHECK_THROWS_AS(OdeIntegrator(system, Gauss(7, 10)), std::invalid_argument);
  CHECK_THROWS_AS(OdeIntegrator(system, Gauss(2, 0)), std::invalid_argument);
  // One step over a long time from a large amplitude: the cubic term defeats the stage Newton.
  OdeIntegrator coarse(system, Gauss(2, 1));
  Vector x(2);
  const IntegrationResult result = coarse.Integrate(0.0, (Vector(2) << 30.0, 0.0).finished(), 50.0, x);
  CHECK(result.status == IntegrationStatus::kConvergenceFailures);
  CHECK(result.message.find("collocation_steps") != std::string::npos);
}

// A smooth non-uniform mesh θ(x) = x + a sin(2πx)/(2π) on N steps (θ' = 1 + a cos 2πx > 0).
std::vector<double> GradedMesh(long steps, double a) {
  std::vector<double> mesh(static_cast<std::size_t>(steps) + 1);
  for (long k = 0; k <= steps; ++k) {
    const double x = static_cast<double>(k) / static_cast<double>(steps);
    mesh[static_cast<std::size_t>(k)] = x + a * std::sin(kTwoPi * x) / kTwoPi;
  }
  mesh.back() = 1.0;
  return mesh;
}

// ẍ = −x: x = cos t, v = −sin t from (1, 0).
class HarmonicWithoutJacobian : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f << x(1), -x(0); }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
};

TEST_CASE("Gauss collocation on a set mesh: the uniform one reproduced, order 2s on a graded one, "
          "the STM and dx/dt1 the derivatives of its map",
          "[ode][gauss]") {
  SECTION("the uniform mesh as fractions integrates as the default mesh, to rounding") {
    StuartLandauOscillator system(Shear());
    const Vector x0 = (Vector(2) << 0.2, 0.0).finished();
    OdeIntegrator integrator(system, Gauss(4, 20));
    Vector uniform(2), meshed(2);
    REQUIRE(integrator.Integrate(0.0, x0, 4.0, uniform).Succeeded());
    integrator.SetCollocationMesh(GradedMesh(20, 0.0));
    REQUIRE(integrator.Integrate(0.0, x0, 4.0, meshed).Succeeded());
    CHECK((meshed - uniform).norm() <= 1e-14);
    integrator.SetCollocationMesh({});
    REQUIRE(integrator.Integrate(0.0, x0, 4.0, meshed).Succeeded());
    CHECK(meshed == uniform);  // back to the uniform mesh, bit for bit
  }
  SECTION("order 2s = 8 on the graded mesh") {
    const StuartLandauParams p = Shear();
    StuartLandauOscillator system(p);
    const double T = 4.0;
    const Vector exact = StuartLandauExact(p, 0.2, T);
    const Vector x0 = (Vector(2) << 0.2, 0.0).finished();
    double errors[2];
    for (int k = 0; k < 2; ++k) {
      OdeIntegrator integrator(system, Gauss(4, 1));
      integrator.SetCollocationMesh(GradedMesh(10L << k, 0.5));
      Vector x(2);
      REQUIRE(integrator.Integrate(0.0, x0, T, x).Succeeded());
      CHECK(integrator.CollocationDerivatives().cols() == (10L << k));
      errors[k] = (x - exact).norm();
    }
    CHECK(std::log2(errors[0] / errors[1]) == Approx(8.0).epsilon(0).margin(0.3));
  }
  SECTION("the forced Duffing oscillator: STM, dx/dp and dx/dt1 by differences of the map") {
    DuffingOscillator system;
    const Vector x0 = (Vector(2) << 0.7, -0.3).finished();
    const double T = kTwoPi / system.Parameter();
    OdeIntegrator integrator(system, Gauss(3, 1));
    integrator.SetCollocationMesh(GradedMesh(25, 0.6));  // coarse: the map differs from the flow
    Vector x(2), dxdp, dxdt1;
    Matrix stm;
    REQUIRE(integrator.Integrate(0.0, x0, T, x, &stm, &dxdp, &dxdt1).Succeeded());
    const double h = 1e-6;
    const Matrix fd = testing::FlowJacobianByDifferences(integrator, x0, T, h);
    CHECK((stm - fd).norm() <= 1e-8 * stm.norm());
    CHECK((dxdt1 - EndTimeDerivativeByDifferences(integrator, x0, T)).norm() <= 1e-6 * dxdt1.norm());
    CHECK((dxdp - ParameterDerivativeByDifferences(integrator, system, x0, T, h)).norm() <=
          1e-7 * dxdp.norm());
  }
  SECTION("meshes that break the rules, and other methods, are refused") {
    DuffingOscillator system;
    OdeIntegrator gauss(system, Gauss(4, 10));
    CHECK_THROWS_WITH(gauss.SetCollocationMesh({0.0, 0.5}), Catch::Contains("exactly 0 to exactly 1"));
    CHECK_THROWS_WITH(gauss.SetCollocationMesh({0.0, 0.6, 0.6, 1.0}),
                      Catch::Contains("must increase strictly"));
    OdeIntegrator bdf(system, IntegratorOptions());
    CHECK_THROWS_WITH(bdf.SetCollocationMesh({}), Catch::Contains("Gauss collocation only"));
    CHECK_THROWS_WITH(bdf.CollocationDerivatives(), Catch::Contains("Gauss collocation only"));
  }
}

TEST_CASE("Gauss collocation's u^(s) on each step, the monitor and the equidistributed mesh",
          "[ode][gauss]") {
  SECTION("u^(4) of x = cos t, v = −sin t on each step is (cos, −sin) at its middle, to O(h²)") {
    HarmonicWithoutJacobian system;
    OdeIntegrator integrator(system, Gauss(4, 40));
    Vector x(2);
    REQUIRE(integrator.Integrate(0.0, (Vector(2) << 1.0, 0.0).finished(), 4.0, x).Succeeded());
    const Matrix& d = integrator.CollocationDerivatives();
    REQUIRE(d.cols() == 40);
    const double h = 0.1;
    for (Index k = 0; k < 40; ++k) {
      CAPTURE(k);
      CHECK(d(0, k) == Approx(std::cos((k + 0.5) * h)).epsilon(0).margin(h * h));
      CHECK(d(1, k) == Approx(-std::sin((k + 0.5) * h)).epsilon(0).margin(h * h));
    }
  }
  SECTION("a linear u^(s) gives the constant monitor |slope|^(1/(s+1)) on any mesh") {
    const Vector times = (Vector(6) << 0.0, 0.1, 0.15, 0.4, 0.8, 1.0).finished();
    Matrix derivatives(2, 5);
    for (Index k = 0; k < 5; ++k) {
      const double middle = 0.5 * (times(k) + times(k + 1));
      derivatives(0, k) = 3.0 * middle;
      derivatives(1, k) = -32.0 * middle;  // the larger slope: the ∞-norm takes it
    }
    const Vector density = CollocationMonitor(times, derivatives, 4);
    for (Index k = 0; k < 5; ++k) CHECK(density(k) == Approx(2.0));  // 32^(1/5)
  }
  SECTION("the equidistributed mesh of a two-level density, on the whole span and on a part") {
    const Vector times = (Vector(3) << 0.0, 0.5, 1.0).finished();
    const Vector density = (Vector(2) << 1.0, 3.0).finished();
    // ∫ = 2, a quarter per step: 0.25, 0.5, then steps of 1/12.
    const std::vector<double> mesh = EquidistributedMesh(times, density, 0.0, 1.0, 8);
    const std::vector<double> expected = {0.0, 0.25, 0.5, 7.0 / 12, 2.0 / 3, 0.75, 5.0 / 6, 11.0 / 12, 1.0};
    REQUIRE(mesh.size() == expected.size());
    for (std::size_t k = 0; k < mesh.size(); ++k) CHECK(mesh[k] == Approx(expected[k]).margin(1e-15));
    // [0.25, 0.75] in two: ∫ = 0.25 + 0.75, halved at t = 0.5 + 0.25/3, 2/3 of the way.
    const std::vector<double> part = EquidistributedMesh(times, density, 0.25, 0.75, 2);
    REQUIRE(part.size() == 3);
    CHECK(part[1] == Approx(2.0 / 3.0));
    CHECK_THROWS_WITH(EquidistributedMesh(times, (Vector(2) << 1.0, 0.0).finished(), 0.0, 1.0, 4),
                      Catch::Contains("must be positive"));
    CHECK_THROWS_WITH(EquidistributedMesh(times, density, 0.5, 0.5, 4), Catch::Contains("a < b"));
  }
}

}  // namespace
}  // namespace rubcont
