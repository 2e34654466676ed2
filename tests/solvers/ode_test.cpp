#include "solvers/constants.h"
#include "solvers/ode.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include <unistd.h>

#include <catch2/catch.hpp>
#include <unsupported/Eigen/MatrixFunctions>

#include "flow_differences.h"
#include "models/textbook.h"
#include "solvers/parallel.h"

namespace rubcont {
namespace {

// ẋ = A(p) x with A(p) = A0 + p A1: x(t) = e^{A(p) t} x0, Φ = e^{A(p) t}, and ∂x/∂p from the
// derivative of the exponential (evaluated below by differences of the exact exponential).
class LinearSystem : public OdeSystem {
 public:
  LinearSystem() : A0_(3, 3), A1_(3, 3) {
    A0_ << -0.3, 1.2, 0.0,
           -1.1, -0.2, 0.4,
            0.3, 0.0, -0.7;
    A1_ << 0.1, 0.0, 0.2,
           0.0, -0.3, 0.0,
           0.5, 0.1, 0.0;
  }
  Index Dimension() const override { return 3; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f.noalias() = A() * x; }
  bool HasJacobian() const override { return analytic_jacobian; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override {
    if (analytic_jacobian) {
      J = A();
    } else {
      OdeSystem::JacobianX(t, x, J);
    }
  }
  double Parameter() const override { return p_; }
  void SetParameter(double p) override { p_ = p; }
  void DfDparameter(double, ConstVectorRef x, VectorRef df) override { df.noalias() = A1_ * x; }
  Matrix A() const { return A0_ + p_ * A1_; }
  Matrix Exponential(double t, double p) const { return ((A0_ + p * A1_) * t).exp(); }
  bool analytic_jacobian = true;

 private:
  Matrix A0_, A1_;
  double p_ = 0.4;
};

Vector X0() { return (Vector(3) << 1.0, -0.5, 0.25).finished(); }

IntegratorOptions Tight(IntegrationMethod method) {
  IntegratorOptions options;
  options.method = method;
  options.relative_tolerance = 1e-11;
  options.absolute_tolerance = 1e-11;
  return options;
}

const std::vector<IntegrationMethod> kEveryMethod = {
    IntegrationMethod::kBdf, IntegrationMethod::kAdams, IntegrationMethod::kExplicitRungeKutta,
    IntegrationMethod::kDiagonallyImplicitRungeKutta, IntegrationMethod::kGaussCollocation};

TEST_CASE("state and state-transition matrix of a linear system match the matrix exponential",
          "[ode]") {
  LinearSystem system;
  const double T = 3.0;
  const Matrix expected_stm = system.Exponential(T, system.Parameter());
  const Vector expected_x = expected_stm * X0();
  // ∂x/∂p = d/dp e^{A(p)T} x0: central difference of the exact exponential (error O(h²) ≈ 1e-12).
  const double h = 1e-6;
  const Vector expected_dxdp =
      (system.Exponential(T, system.Parameter() + h) - system.Exponential(T, system.Parameter() - h)) *
      X0() / (2 * h);
  for (IntegrationMethod method : kEveryMethod) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    Vector x(3), dxdp;
    Matrix stm;
    const IntegrationResult result = integrator.Integrate(0.0, X0(), T, x, &stm, &dxdp);
    REQUIRE(result.Succeeded());
    CHECK(result.t_reached == T);
    CHECK((x - expected_x).norm() <= 1e-9 * expected_x.norm());
    CHECK((stm - expected_stm).norm() <= 1e-9 * expected_stm.norm());
    CHECK((dxdp - expected_dxdp).norm() <= 1e-8 * expected_dxdp.norm());
    CHECK(result.statistics.steps > 0);
  }
}

TEST_CASE("work: steps × the method's weight × states, the same for the same integration, summed "
          "in the current work account",
          "[ode]") {
  LinearSystem system;
  for (IntegrationMethod method : {IntegrationMethod::kBdf, IntegrationMethod::kDormandPrince,
                                   IntegrationMethod::kExplicitRungeKutta, IntegrationMethod::kGaussCollocation}) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    Vector x(3);
    WorkAccount account;
    const WorkScope counting(&account);
    const IntegrationResult first = integrator.Integrate(0.0, X0(), 3.0, x);
    const IntegrationResult second = integrator.Integrate(0.0, X0(), 3.0, x);
    REQUIRE(first.Succeeded());
    REQUIRE(second.Succeeded());
    CHECK(first.statistics.work == first.statistics.steps * WorkPerStep(method) * 3);
    CHECK(first.statistics.work > 0);
    CHECK(second.statistics.work == first.statistics.work);
    CHECK(account.Work() == 2 * first.statistics.work);
  }
  CHECK(WorkPerStep(IntegrationMethod::kDormandPrince) < WorkPerStep(IntegrationMethod::kBdf));
  CHECK(WorkPerStep(IntegrationMethod::kBdf) < WorkPerStep(IntegrationMethod::kGaussCollocation));
}

TEST_CASE("work accounts: each counts its own thread's integrations and its ParallelFor workers', "
          "not another thread's, and a nested one's work counts in its outer one",
          "[ode]") {
  LinearSystem system;
  // Its work, or −1 where it failed (no assertions on other threads: Catch2's are not thread-safe).
  auto integrate = [&system]() -> long long {
    OdeIntegrator integrator(system, Tight(IntegrationMethod::kDormandPrince));
    Vector x(3);
    const IntegrationResult result = integrator.Integrate(0.0, X0(), 3.0, x);
    return result.Succeeded() ? result.statistics.work : -1;
  };
  // Two computations on two threads of one process at once, each with its own account: both
  // accounts are made before either thread integrates and read after both have (a count of the
  // process would give each the sum).
  long long own[2] = {0, 0}, counted[2] = {0, 0};
  std::atomic<int> made{0}, done{0};
  auto wait_for_both = [](std::atomic<int>& arrived) {
    ++arrived;
    while (arrived.load() < 2) std::this_thread::yield();
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      WorkAccount account;
      const WorkScope scope(&account);
      wait_for_both(made);
      for (int k = 0; k <= t; ++k) own[t] += integrate();  // the second thread integrates twice
      wait_for_both(done);
      counted[t] = account.Work();
    });
  }
  for (std::thread& thread : threads) thread.join();
  CHECK(own[0] > 0);
  CHECK(own[1] == 2 * own[0]);
  CHECK(counted[0] == own[0]);
  CHECK(counted[1] == own[1]);
  // Jobs over three threads count in the caller's account; a nested account's work counts in its
  // outer one too; with the scope ended, the account counts no more.
  WorkAccount outer;
  long long one = 0;
  {
    const WorkScope scope(&outer);
    std::vector<long long> jobs(6);
    ParallelFor(6, 3, [&](int i) { jobs[static_cast<std::size_t>(i)] = integrate(); });
    one = integrate();
    CHECK(one > 0);
    for (const long long work : jobs) CHECK(work == one);
    WorkAccount inner;
    const WorkScope nested(&inner);
    CHECK(integrate() == one);
    CHECK(inner.Work() == one);
  }
  CHECK(outer.Work() == 8 * one);
  CHECK(CurrentWorkAccount() == nullptr);
  CHECK(integrate() == one);
  CHECK(outer.Work() == 8 * one);
}

TEST_CASE("tangents: Φ applied to k directions, by every method, between full-STM calls",
          "[ode]") {
  LinearSystem system;
  const double T = 2.5;
  const Matrix expected_stm = system.Exponential(T, system.Parameter());
  const Vector expected_x = expected_stm * X0();
  Matrix directions(3, 2);
  directions << 1.0, 0.2,
                -2.0, 0.0,
                0.5, 3.0;
  const Matrix expected = expected_stm * directions;
  for (IntegrationMethod method : kEveryMethod) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    Vector x(3), dxdp;
    Matrix stm, images = directions;
    // A full STM first and after: the seeded columns must not leak into the identity's (CVODES
    // reuses its sensitivity memory, ARKODE keeps one memory per column count).
    REQUIRE(integrator.Integrate(0.0, X0(), T, x, &stm, &dxdp).Succeeded());
    const IntegrationResult result = integrator.IntegrateTangents(0.0, X0(), T, x, images, images);
    REQUIRE(result.Succeeded());
    CHECK(images.cols() == 2);
    // The state is as accurate as a plain integration's: BDF alone errs by 9.5e-10 (relative) at
    // these tolerances, 1.3e-9 with two tangent columns under error control.
    CHECK((x - expected_x).norm() <= 3e-9 * expected_x.norm());
    CHECK((images - expected).norm() <= 1e-9 * expected.norm());
    Matrix one;
    REQUIRE(integrator.IntegrateTangents(0.0, X0(), T, x, directions.col(1), one).Succeeded());
    CHECK((one - expected.col(1)).norm() <= 1e-9 * expected.norm());
    REQUIRE(integrator.Integrate(0.0, X0(), T, x, &stm).Succeeded());
    CHECK((stm - expected_stm).norm() <= 1e-9 * expected_stm.norm());
  }
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x(3);
  Matrix none(3, 0), images;
  CHECK_THROWS_WITH(integrator.IntegrateTangents(0.0, X0(), T, x, none, images),
                    Catch::Contains("0 directions: must be 1 … 3"));
}

TEST_CASE("tangents with samples: the states at the sample times, the same map", "[ode]") {
  LinearSystem system;
  const double T = 2.5;
  const Vector times = (Vector(4) << 0.0, 0.7, 1.9, 2.5).finished();  // t0 and t1 included
  Matrix directions(3, 2);
  directions << 1.0, 0.2,
                -2.0, 0.0,
                0.5, 3.0;
  for (IntegrationMethod method : kEveryMethod) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    Vector x(3);
    Matrix images, samples;
    REQUIRE(integrator.IntegrateTangents(0.0, X0(), T, x, directions, images, times, &samples)
                .Succeeded());
    REQUIRE(samples.cols() == 4);
    for (Index k = 0; k < times.size(); ++k) {
      const Vector expected = system.Exponential(times(k), system.Parameter()) * X0();
      CAPTURE(k);
      CHECK((samples.col(k) - expected).norm() <= 3e-9 * expected.norm());
    }
    const Matrix expected = system.Exponential(T, system.Parameter()) * directions;
    CHECK((images - expected).norm() <= 1e-9 * expected.norm());
    CHECK((samples.col(3) - x).norm() <= 1e-12 * x.norm());
  }
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x(3);
  Matrix images, samples;
  const Vector late = (Vector(2) << 1.0, 3.0).finished();  // past t1
  CHECK_THROWS_WITH(integrator.IntegrateTangents(0.0, X0(), T, x, directions, images, late, &samples),
                    Catch::Contains("times(1) = 3: the sample times must be monotone within [t0, t1]"));
  const Vector backwards = (Vector(2) << 1.0, 0.5).finished();
  CHECK_THROWS_WITH(integrator.IntegrateTangents(0.0, X0(), T, x, directions, images, backwards, &samples),
                    Catch::Contains("times(1) = 0.5"));
}

TEST_CASE("CVODES without an analytic Jacobian gives the same STM", "[ode]") {
  LinearSystem system;
  system.analytic_jacobian = false;
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x(3);
  Matrix stm;
  REQUIRE(integrator.Integrate(0.0, X0(), 2.0, x, &stm).Succeeded());
  const Matrix expected = system.Exponential(2.0, system.Parameter());
  CHECK((stm - expected).norm() <= 1e-8 * expected.norm());
}

TEST_CASE("repeated integrations reuse the memory and are reproducible in any order", "[ode]") {
  LinearSystem system;
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x_plain(3), x_stm(3), x_both(3), x_again(3), dxdp;
  Matrix stm, stm_again;
  REQUIRE(integrator.Integrate(0.0, X0(), 1.5, x_plain).Succeeded());
  REQUIRE(integrator.Integrate(0.0, X0(), 1.5, x_both, &stm, &dxdp).Succeeded());
  REQUIRE(integrator.Integrate(0.0, X0(), 1.5, x_stm, &stm_again).Succeeded());
  REQUIRE(integrator.Integrate(0.0, X0(), 1.5, x_again).Succeeded());
  CHECK(x_again == x_plain);  // bit-for-bit: the same step sequence after CVodeReInit
  CHECK((stm - stm_again).norm() <= 1e-10);
  CHECK((x_stm - x_plain).norm() <= 1e-9);
}

TEST_CASE("backward integration inverts forward integration", "[ode]") {
  LinearSystem system;
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x1(3), x0(3);
  Matrix forward, backward;
  REQUIRE(integrator.Integrate(0.0, X0(), 2.0, x1, &forward).Succeeded());
  REQUIRE(integrator.Integrate(2.0, x1, 0.0, x0, &backward).Succeeded());
  // Backwards the contracting flow expands the forward error (≈ 1e-9 at rtol 1e-11) by up to
  // ‖e^{−2A}‖ ≈ 4.
  CHECK((x0 - X0()).norm() <= 1e-8);
  CHECK((backward * forward - Matrix::Identity(3, 3)).norm() <= 1e-8);
}

TEST_CASE("van der Pol: CVODES sensitivities agree with ARKODE's variational equations and with "
          "finite differences",
          "[ode]") {
  VanDerPolOscillator system({2.0});
  const Vector x0 = (Vector(2) << 1.5, 0.3).finished();
  const double T = 4.0;
  OdeIntegrator cvodes(system, Tight(IntegrationMethod::kBdf));
  OdeIntegrator arkode(system, Tight(IntegrationMethod::kExplicitRungeKutta));
  Vector x_c(2), x_a(2), q_c, q_a;
  Matrix stm_c, stm_a;
  REQUIRE(cvodes.Integrate(0.0, x0, T, x_c, &stm_c, &q_c).Succeeded());
  REQUIRE(arkode.Integrate(0.0, x0, T, x_a, &stm_a, &q_a).Succeeded());
  CHECK((x_c - x_a).norm() <= 1e-8 * x_a.norm());
  CHECK((stm_c - stm_a).norm() <= 1e-7 * stm_a.norm());
  CHECK((q_c - q_a).norm() <= 1e-7 * q_a.norm());

  // Central differences of the tightly integrated flow: steps 1e-4·max(|x0_i|, 1) balance the
  // O(h²) truncation against the O(tol/h) integration noise (both ≈ 1e-8 here).
  const double h = 1e-4;
  const Matrix fd = testing::FlowJacobianByDifferences(arkode, x0, T, h);
  CHECK((stm_c - fd).norm() <= 1e-6 * fd.norm());
  Vector plus(2), minus(2);
  system.SetParameter(2.0 + h);
  REQUIRE(arkode.Integrate(0.0, x0, T, plus).Succeeded());
  system.SetParameter(2.0 - h);
  REQUIRE(arkode.Integrate(0.0, x0, T, minus).Succeeded());
  system.SetParameter(2.0);
  const Vector q_fd = (plus - minus) / (2 * h);
  CHECK((q_c - q_fd).norm() <= 1e-6 * q_fd.norm());
}

// ẋ = x² blows up at t = 1/x0.
class BlowUp : public OdeSystem {
 public:
  Index Dimension() const override { return 1; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f(0) = x(0) * x(0); }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override { J(0, 0) = 2 * x(0); }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
};

// Runs `body` with the process's stderr redirected into a temporary file; returns what was written.
template <typename Body>
std::string CaptureStderr(Body body) {
  std::fflush(stderr);
  char path[] = "/tmp/rubcont_stderr_XXXXXX";
  const int fd = mkstemp(path);
  REQUIRE(fd >= 0);
  const int saved = dup(2);
  dup2(fd, 2);
  body();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  close(fd);
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  std::remove(path);
  return text.str();
}

TEST_CASE("a finite-time blow-up is reported as a status with the reason, and nothing is printed",
          "[ode]") {
  BlowUp system;
  for (IntegrationMethod method : {IntegrationMethod::kBdf, IntegrationMethod::kExplicitRungeKutta}) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    Vector x(1);
    IntegrationResult result;
    const std::string printed = CaptureStderr([&] {
      result = integrator.Integrate(0.0, Vector::Ones(1), 2.0, x);
    });
    CHECK(printed.empty());
    CHECK(result.status == IntegrationStatus::kStateBound);
    CHECK_FALSE(result.flag_name.empty());
    CHECK_THAT(result.message, Catch::Contains("state_bound"));
    // It stopped just before the singularity at t = 1 (x = 1e12 at t = 1 − 1e-12).
    CHECK(result.t_reached == Approx(1.0).epsilon(0).margin(1e-6));
    CHECK(result.t_reached < 1.0);
    // The same integrator recovers on the next call: x(0.5) = 1/(1 − 0.5). (On this growing
    // solution, ∂x(t)/∂x0 = 1/(1 − t)², BDF's global error is ≈ 2e-9 at rtol 1e-11.)
    REQUIRE(integrator.Integrate(0.0, Vector::Ones(1), 0.5, x).Succeeded());
    CHECK(x(0) == Approx(2.0).epsilon(1e-8));
  }
}

TEST_CASE("integrator failures carry SUNDIALS' flag name and message", "[ode]") {
  BlowUp system;
  IntegratorOptions options = Tight(IntegrationMethod::kBdf);
  options.max_steps = 5;
  OdeIntegrator integrator(system, options);
  Vector x(1);
  IntegrationResult result;
  const std::string printed = CaptureStderr([&] {
    result = integrator.Integrate(0.0, Vector::Constant(1, 0.01), 50.0, x);
  });
  CHECK(printed.empty());
  CHECK(result.status == IntegrationStatus::kTooMuchWork);
  CHECK(result.flag_name == "CV_TOO_MUCH_WORK");
  CHECK_THAT(result.message, Catch::Contains("mxstep"));
  CHECK_THAT(result.BriefReport(), Catch::Contains("CV_TOO_MUCH_WORK"));
}

// A model evaluated outside its domain (e.g. a parameter that makes it NaN everywhere). NaN is a
// recoverable error for the integrator (a Newton iterate may probe an invalid state), so it ends
// with kNonFinite only when no smaller step helps.
class NotANumber : public BlowUp {
 public:
  void Rhs(double, ConstVectorRef, VectorRef f) override { f(0) = kNaN; }
};

TEST_CASE("a right-hand side that returns NaN ends with kNonFinite", "[ode]") {
  NotANumber system;
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x(1);
  const IntegrationResult result = integrator.Integrate(0.0, Vector::Ones(1), 1.0, x);
  CHECK(result.status == IntegrationStatus::kNonFinite);
  CHECK(result.t_reached == 0.0);
}

class Throwing : public BlowUp {
 public:
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    if (t > 0.1) throw std::invalid_argument("model: contact stiffness is negative");
    f(0) = x(0);
  }
};

TEST_CASE("an exception thrown by the model crosses SUNDIALS safely and reaches the caller",
          "[ode]") {
  Throwing system;
  OdeIntegrator integrator(system, Tight(IntegrationMethod::kBdf));
  Vector x(1);
  CHECK_THROWS_WITH(integrator.Integrate(0.0, Vector::Ones(1), 1.0, x),
                    Catch::Contains("contact stiffness"));
}

// ẋ = v, v̇ = −x: x = cos t.
class Harmonic : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f(0) = x(1);
    f(1) = -x(0);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef, MatrixRef J) override { J << 0, 1, -1, 0; }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
};

TEST_CASE("dense output samples the solution at requested times", "[ode]") {
  Harmonic system;
  for (IntegrationMethod method : {IntegrationMethod::kBdf, IntegrationMethod::kExplicitRungeKutta}) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    const Vector times = Vector::LinSpaced(41, 0.0, kTwoPi);
    Matrix states;
    const Vector x0 = (Vector(2) << 1.0, 0.0).finished();
    REQUIRE(integrator.Sample(0.0, x0, times, states).Succeeded());
    REQUIRE(states.cols() == 41);
    // The global error of one period at tolerances 1e-11: BDF's interpolated output measured up
    // to 1.6e-9, the Runge–Kutta one's below 1e-9.
    const double tolerance = method == IntegrationMethod::kBdf ? 3e-9 : 1e-9;
    for (Index k = 0; k < times.size(); ++k) {
      CHECK(states(0, k) == Approx(std::cos(times(k))).epsilon(0).margin(tolerance));
      CHECK(states(1, k) == Approx(-std::sin(times(k))).epsilon(0).margin(tolerance));
    }
  }
}

TEST_CASE("events: zeros located with direction filters, terminal or recorded", "[ode]") {
  Harmonic system;
  const Vector x0 = (Vector(2) << 1.0, 0.0).finished();
  for (IntegrationMethod method : {IntegrationMethod::kBdf, IntegrationMethod::kExplicitRungeKutta}) {
    CAPTURE(ToString(method));
    OdeIntegrator integrator(system, Tight(method));
    EventOptions events;
    events.count = 1;
    events.function = [](double, ConstVectorRef x, VectorRef g) { g(0) = x(0); };
    events.directions = {+1};  // x rising through 0: t = 3π/2, 7π/2
    integrator.SetEvents(events);
    Vector x(2);
    IntegrationResult result = integrator.Integrate(0.0, x0, 12.0, x);
    REQUIRE(result.Succeeded());
    REQUIRE(result.events.size() == 2);
    CHECK(result.events[0].t == Approx(1.5 * kPi).epsilon(1e-10));
    CHECK(result.events[1].t == Approx(3.5 * kPi).epsilon(1e-10));
    CHECK(result.events[0].direction == 1);
    // BDF's global error at t = 12 measured 1.6e-9 (tolerances 1e-11), Runge–Kutta's below 1e-9.
    const double tolerance = method == IntegrationMethod::kBdf ? 3e-9 : 1e-9;
    CHECK(x(0) == Approx(std::cos(12.0)).epsilon(0).margin(tolerance));

    events.directions.clear();
    events.terminal = true;
    integrator.SetEvents(events);
    Matrix stm;
    result = integrator.Integrate(0.0, x0, 12.0, x, &stm);
    REQUIRE(result.Succeeded());
    CHECK(result.stopped_at_event);
    CHECK(result.t_reached == Approx(0.5 * kPi).epsilon(1e-10));
    CHECK(x(0) == Approx(0.0).epsilon(0).margin(1e-9));
    CHECK(stm(0, 0) == Approx(0.0).epsilon(0).margin(1e-8));  // Φ(t) = rotation by −t

    integrator.ClearEvents();
    result = integrator.Integrate(0.0, x0, 12.0, x);
    CHECK(result.events.empty());
    CHECK_FALSE(result.stopped_at_event);
  }
}

// The soft impact oscillator at w = 0.9 and a point of its striking orbit: x crosses the stop g = 1
// twice per forcing period (into it and off it), a kink of f each time.
SoftImpactOscillator StrikingOscillator() {
  SoftImpactParams params;
  params.frequency = 0.9;
  return SoftImpactOscillator(params);
}
Vector StrikingPoint() { return (Vector(2) << 0.2, 1.3).finished(); }
// Its reference trajectories: BDF at rtol = atol = 1e-12.
IntegratorOptions ReferenceBdf() {
  IntegratorOptions options = Tight(IntegrationMethod::kBdf);
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  return options;
}

TEST_CASE("events with restart: CVODES re-initialized at each kink of a striking oscillator, "
          "state and STM as accurate as stepping across, in fewer steps",
          "[ode][events]") {
  SoftImpactOscillator system = StrikingOscillator();
  const double T = system.ForcingPeriod();
  const Vector x0 = StrikingPoint();
  const IntegratorOptions tight = ReferenceBdf();
  Vector reference(2);
  REQUIRE(OdeIntegrator(system, tight).Integrate(0.0, x0, 2.0 * T, reference).Succeeded());

  IntegratorOptions loose = Tight(IntegrationMethod::kBdf);
  loose.relative_tolerance = loose.absolute_tolerance = 1e-8;
  EventOptions events;
  events.count = 1;
  events.function = [&system](double t, ConstVectorRef x, VectorRef h) {
    system.SwitchingFunctions(t, x, h);
  };
  events.restart = true;
  OdeIntegrator plain(system, loose), restarted(system, loose);
  restarted.SetEvents(events);
  Vector x_plain(2), x_restarted(2);
  Matrix stm_plain, stm_restarted;
  const IntegrationResult a = plain.Integrate(0.0, x0, 2.0 * T, x_plain, &stm_plain);
  const IntegrationResult b = restarted.Integrate(0.0, x0, 2.0 * T, x_restarted, &stm_restarted);
  REQUIRE(a.Succeeded());
  REQUIRE(b.Succeeded());
  CAPTURE(a.statistics.steps, a.statistics.error_test_failures, b.statistics.steps,
          b.statistics.error_test_failures);
  REQUIRE(b.events.size() == 4);  // into and off the stop, twice
  CHECK(b.statistics.restarts == 4);
  CHECK(a.statistics.restarts == 0);
  // Both meet the tolerance; restarted, the method does not step across the kinks: fewer steps.
  CHECK((x_plain - reference).lpNorm<Eigen::Infinity>() < 1e-6);
  CHECK((x_restarted - reference).lpNorm<Eigen::Infinity>() < 1e-6);
  CHECK(b.statistics.steps < a.statistics.steps);
  // The STM is continuous through a kink (no saltation): restarted at 1e-8 it equals the STM of
  // an integration at 1e-12 to the tolerance's level (measured 1.8e-6 of its norm; 1.4e-6
  // stepping across the kinks).
  Matrix stm_reference;
  REQUIRE(OdeIntegrator(system, tight).Integrate(0.0, x0, 2.0 * T, reference, &stm_reference)
              .Succeeded());
  CHECK((stm_restarted - stm_reference).lpNorm<Eigen::Infinity>() <
        1e-5 * stm_reference.lpNorm<Eigen::Infinity>());
}

// Two decoupled modes with rates −1 and −1e5 (the order of the rub contact's eigenvalues).
class StiffLinear : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f(0) = -x(0) + x(1);
    f(1) = -1e5 * x(1);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef, MatrixRef J) override { J << -1, 1, 0, -1e5; }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
};

TEST_CASE("stiff system: BDF takes few steps, the explicit method is stability-limited", "[ode]") {
  StiffLinear system;
  const Vector x0 = Vector::Ones(2);
  IntegratorOptions options = Tight(IntegrationMethod::kBdf);
  options.relative_tolerance = options.absolute_tolerance = 1e-8;
  OdeIntegrator bdf(system, options);
  Vector x(2);
  const IntegrationResult implicit_result = bdf.Integrate(0.0, x0, 10.0, x);
  REQUIRE(implicit_result.Succeeded());
  // x0 ≈ 4.5e-5 at t = 10 is below the absolute tolerance's reach: its global error is a few atol.
  CHECK(x(0) == Approx(std::exp(-10.0) * (1 + 1 / (1e5 - 1))).epsilon(0).margin(5e-8));
  CHECK(implicit_result.statistics.steps < 1000);

  options.method = IntegrationMethod::kExplicitRungeKutta;
  options.max_steps = 20000;
  OdeIntegrator erk(system, options);
  const IntegrationResult explicit_result = erk.Integrate(0.0, x0, 10.0, x);
  // Dormand–Prince's stability interval is ≈ 3.3/1e5: about 3e5 steps would be needed.
  CHECK(explicit_result.status == IntegrationStatus::kTooMuchWork);
  CHECK(explicit_result.t_reached < 1.0);
}

// Eight damped oscillators, ẋ = A x with A block-diagonal: 16 states, the size of the two-point
// rotor (the odeint backend's fixed-size path), x(t) = e^{At} x0.
class EightOscillators : public OdeSystem {
 public:
  EightOscillators() : A_(Matrix::Zero(16, 16)) {
    for (Index k = 0; k < 8; ++k) {
      const double w = 1.0 + 0.7 * static_cast<double>(k), zeta = 0.02 * static_cast<double>(k + 1);
      A_(2 * k, 2 * k + 1) = 1.0;
      A_(2 * k + 1, 2 * k) = -w * w;
      A_(2 * k + 1, 2 * k + 1) = -2.0 * zeta * w;
    }
  }
  Index Dimension() const override { return 16; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override { f.noalias() = A_ * x; }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
  Matrix Exponential(double t) const { return (A_ * t).exp(); }

 private:
  Matrix A_;
};

TEST_CASE("Odeint Dormand-Prince: states and dense output to the tolerance, forwards and "
          "backwards, on the fixed-size (16) and the dynamic path",
          "[ode][odeint]") {
  IntegratorOptions options = Tight(IntegrationMethod::kDormandPrince);
  options.relative_tolerance = options.absolute_tolerance = 1e-10;
  const Vector times = Vector::LinSpaced(21, 0.1, 2.0);
  // 16 states: the fixed-size std::array path.
  EightOscillators oscillators;
  const Vector x0 = Vector::LinSpaced(16, 1.0, -0.5);
  OdeIntegrator integrator(oscillators, options);
  Matrix states;
  const IntegrationResult result = integrator.Sample(0.0, x0, times, states);
  REQUIRE(result.Succeeded());
  CHECK(result.statistics.steps > 0);
  CHECK(result.statistics.rhs_evaluations >= 6 * result.statistics.steps);
  for (Index k = 0; k < times.size(); ++k) {
    // Dense output (Dormand–Prince's order-4 interpolant) between steps, the step itself at t = 2.
    CHECK((states.col(k) - oscillators.Exponential(times(k)) * x0).lpNorm<Eigen::Infinity>() < 1e-8);
  }
  Vector x1(16), back(16);
  REQUIRE(integrator.Integrate(0.0, x0, 2.0, x1).Succeeded());
  CHECK((x1 - oscillators.Exponential(2.0) * x0).lpNorm<Eigen::Infinity>() < 1e-8);
  CHECK(x1 == states.col(times.size() - 1));  // the final step ends on t1 exactly
  REQUIRE(integrator.Integrate(2.0, x1, 0.0, back).Succeeded());
  CHECK((back - x0).lpNorm<Eigen::Infinity>() < 1e-8);
  // 3 states: the std::vector path.
  LinearSystem linear;
  OdeIntegrator small(linear, options);
  Vector y(3);
  REQUIRE(small.Integrate(0.0, X0(), 1.5, y).Succeeded());
  CHECK((y - linear.Exponential(1.5, 0.4) * X0()).lpNorm<Eigen::Infinity>() < 1e-9);
}

TEST_CASE("Odeint Dormand-Prince: blow-up, NaN and too much work are statuses, a model's "
          "exception reaches the caller, sensitivities and events are refused",
          "[ode][odeint]") {
  const IntegratorOptions options = Tight(IntegrationMethod::kDormandPrince);
  BlowUp blow_up;
  OdeIntegrator integrator(blow_up, options);
  Vector x(1);
  IntegrationResult result = integrator.Integrate(0.0, Vector::Ones(1), 2.0, x);
  CHECK(result.status == IntegrationStatus::kStateBound);
  CHECK_THAT(result.message, Catch::Contains("state_bound"));
  CHECK(result.t_reached == Approx(1.0).epsilon(0).margin(1e-6));
  CHECK(result.t_reached < 1.0);
  REQUIRE(integrator.Integrate(0.0, Vector::Ones(1), 0.5, x).Succeeded());
  CHECK(x(0) == Approx(2.0).epsilon(1e-9));

  IntegratorOptions few = options;
  few.max_steps = 5;
  result = OdeIntegrator(blow_up, few).Integrate(0.0, Vector::Constant(1, 0.01), 50.0, x);
  CHECK(result.status == IntegrationStatus::kTooMuchWork);
  CHECK_THAT(result.BriefReport(), Catch::Contains("5 steps"));

  NotANumber nan;
  result = OdeIntegrator(nan, options).Integrate(0.0, Vector::Ones(1), 1.0, x);
  CHECK(result.status == IntegrationStatus::kNonFinite);
  CHECK(result.t_reached == 0.0);

  Throwing throwing;
  OdeIntegrator throws(throwing, options);
  CHECK_THROWS_WITH(throws.Integrate(0.0, Vector::Ones(1), 1.0, x), Catch::Contains("contact stiffness"));

  Harmonic harmonic;
  OdeIntegrator plain(harmonic, options);
  Vector y(2);
  Matrix stm;
  CHECK_THROWS_WITH(plain.Integrate(0.0, Vector::Ones(2), 1.0, y, &stm), Catch::Contains("sensitivities"));
  EventOptions events;
  events.count = 1;
  events.function = [](double, ConstVectorRef z, VectorRef g) { g(0) = z(0); };
  CHECK_THROWS_WITH(plain.SetEvents(events), Catch::Contains("root finding"));
}

TEST_CASE("Odeint Dormand-Prince landing on kinks: a striking oscillator as accurate, in fewer "
          "rejected steps and f evaluations",
          "[ode][odeint][events]") {
  SoftImpactOscillator system = StrikingOscillator();
  const double T = system.ForcingPeriod();
  const Vector x0 = StrikingPoint();
  const IntegratorOptions tight = ReferenceBdf();
  Vector reference(2);
  REQUIRE(OdeIntegrator(system, tight).Integrate(0.0, x0, 10.0 * T, reference).Succeeded());

  // Landed or straddling, at rtol = atol = 1e-8 and 1e-10: the error and the work.
  struct Run {
    double error;
    IntegrationStatistics statistics;
  };
  auto run = [&](double tolerance, bool land) {
    IntegratorOptions options = Tight(IntegrationMethod::kDormandPrince);
    options.relative_tolerance = options.absolute_tolerance = tolerance;
    options.land_on_switches = land;
    Vector x(2);
    const IntegrationResult result = OdeIntegrator(system, options).Integrate(0.0, x0, 10.0 * T, x);
    REQUIRE(result.Succeeded());
    return Run{(x - reference).lpNorm<Eigen::Infinity>(), result.statistics};
  };
  for (const bool land : {true, false}) {
    CAPTURE(land);
    const Run loose = run(1e-8, land), tight = run(1e-10, land);
    CAPTURE(loose.error, tight.error, loose.statistics.steps, tight.statistics.steps);
    // Over ten forcing periods the error follows the tolerance down (order 5: 100^(5/6) ≈ 46;
    // measured landed 1.2e-6 → 7.6e-9, straddling 5.7e-7 → 3.0e-9). Landing does not buy accuracy
    // (the error test holds either way): it saves work (measured 89 against 202 rejected steps,
    // 5377 against 6523 f evaluations at 1e-8).
    CHECK(loose.error < 5e-6);
    CHECK(tight.error < loose.error / 20.0);
  }
  const Run landed = run(1e-8, true), straddled = run(1e-8, false);
  CAPTURE(landed.statistics.error_test_failures, straddled.statistics.error_test_failures,
          landed.statistics.rhs_evaluations, straddled.statistics.rhs_evaluations);
  CHECK(2 * landed.statistics.error_test_failures < straddled.statistics.error_test_failures);
  CHECK(landed.statistics.rhs_evaluations < straddled.statistics.rhs_evaluations);
}

TEST_CASE("invalid options and sizes are rejected with the field name", "[ode]") {
  Harmonic system;
  IntegratorOptions options;
  options.relative_tolerance = 0.0;
  CHECK_THROWS_WITH(OdeIntegrator(system, options), Catch::Contains("relative_tolerance"));
  options = {};
  options.explicit_order = 7;
  CHECK_THROWS_WITH(OdeIntegrator(system, options), Catch::Contains("explicit_order"));
  OdeIntegrator integrator(system);
  Vector x(3);
  CHECK_THROWS_WITH(integrator.Integrate(0.0, Vector::Ones(2), 1.0, x), Catch::Contains("x1"));
  Matrix states;
  const Vector bad_times = (Vector(2) << 1.0, 0.5).finished();
  CHECK_THROWS_WITH(integrator.Sample(0.0, Vector::Ones(2), bad_times, states),
                    Catch::Contains("out of order"));
}

}  // namespace
}  // namespace rubcont
