// Shooting benchmarks (not part of the test suite). Prints tables to stdout:
//   1. Newton solve of a forced Duffing orbit (w = 1.5, the large response) from a nearby guess,
//      per shooting variant (single, multiple with N = 2, 4, 8), integrator and tolerance: wall
//      time, Newton iterations, integrator steps, error of x(0) against a tight reference.
//   2. The monodromy matrix by forward sensitivities against finite differences (forward and
//      central): cost and accuracy against a tight reference, for Duffing (n = 2) and for a stiff
//      16-state stand-in with the rub contact's stiffness (eigenvalues ~1e5 rad/s).
//   3. One period of the stiff stand-in: BDF with and without sensitivities against explicit RK.
//   4. Floquet multipliers of N factors 16 × 16: periodic Schur, QZ pencil, product.
// Usage: shooting_bench [--quick] [duffing] [monodromy] [stiff] [floquet]   (default: all)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "models/textbook.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/floquet.h"
#include "solvers/newton.h"
#include "solvers/ode.h"

namespace rubcont {
namespace {

using Clock = std::chrono::steady_clock;

// Median wall time (seconds) of `body` over repetitions filling about `budget` seconds.
double MedianSeconds(const std::function<void()>& body, double budget) {
  std::vector<double> times;
  const auto start = Clock::now();
  do {
    const auto t0 = Clock::now();
    body();
    times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  } while (std::chrono::duration<double>(Clock::now() - start).count() < budget &&
           times.size() < 200);
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

// A stand-in for the rub model's numerics (not its physics): 8 masses of 10 kg in a chain
// (16 states), supports 4.7e6 N/m and 324.9 N·s/m as the thesis stator, one contact-like spring of
// 1.75e11 N/m between masses 4 and 5 (a mode at ≈ 1.9e5 rad/s), a cubic hardening spring on mass 1
// and a force 100 cos(w t) N on it (w = 600 rad/s). The contact damping sets the character of the
// fast mode: 9.35e4 N·s/m (ζ = 0.05) makes it stiff and dissipative, the BDF-friendly case;
// 1.75 N·s/m (Hunt–Crossley c_nl·δ at δ = 10 µm, ζ ≈ 1e-6) leaves a fast, nearly undamped
// oscillation that any accurate integrator has to resolve once it is excited.
class StiffChain : public OdeSystem {
 public:
  static constexpr int kMasses = 8;
  explicit StiffChain(double contact_damping) : contact_damping_(contact_damping) {}
  Index Dimension() const override { return 2 * kMasses; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    const auto q = x.head(kMasses);
    const auto v = x.tail(kMasses);
    f.head(kMasses) = v;
    for (int i = 0; i < kMasses; ++i) {
      double force = -kSupport * q(i) - kDamping * v(i);
      if (i > 0) force += Coupling(i - 1) * (q(i - 1) - q(i)) + Damper(i - 1) * (v(i - 1) - v(i));
      if (i + 1 < kMasses) {
        force += Coupling(i) * (q(i + 1) - q(i)) + Damper(i) * (v(i + 1) - v(i));
      }
      if (i == 0) force += -kCubic * q(0) * q(0) * q(0) + kForce * std::cos(w_ * t);
      f(kMasses + i) = force / kMass;
    }
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    J.setZero();
    J.topRightCorner(kMasses, kMasses).setIdentity();
    for (int i = 0; i < kMasses; ++i) {
      double stiffness = kSupport, damping = kDamping;
      if (i > 0) {
        stiffness += Coupling(i - 1);
        damping += Damper(i - 1);
        J(kMasses + i, i - 1) = Coupling(i - 1) / kMass;
        J(kMasses + i, kMasses + i - 1) = Damper(i - 1) / kMass;
      }
      if (i + 1 < kMasses) {
        stiffness += Coupling(i);
        damping += Damper(i);
        J(kMasses + i, i + 1) = Coupling(i) / kMass;
        J(kMasses + i, kMasses + i + 1) = Damper(i) / kMass;
      }
      if (i == 0) stiffness += 3 * kCubic * x(0) * x(0);
      J(kMasses + i, i) = -stiffness / kMass;
      J(kMasses + i, kMasses + i) = -damping / kMass;
    }
  }
  double Parameter() const override { return w_; }
  void SetParameter(double w) override { w_ = w; }
  double ForcingPeriod() const override { return kTwoPi / w_; }
  Vector StateScale() const override {
    Vector s(2 * kMasses);
    s.head(kMasses).setConstant(1e-5);
    s.tail(kMasses).setConstant(1e-5 * 600);
    return s;
  }

 private:
  static constexpr double kMass = 10.0, kSupport = 4.7e6, kDamping = 324.9;
  static constexpr double kCoupling = 2.0e6, kContact = 1.75e11;
  static constexpr double kCubic = 1e16, kForce = 100.0;
  static double Coupling(int i) { return i == 3 ? kContact : kCoupling; }
  double Damper(int i) const { return i == 3 ? contact_damping_ : 10.0; }
  double contact_damping_;
  double w_ = 600.0;
};

IntegratorOptions Integrator(IntegrationMethod method, double tolerance) {
  IntegratorOptions options;
  options.method = method;
  options.relative_tolerance = options.absolute_tolerance = tolerance;
  if (method == IntegrationMethod::kExplicitRungeKutta) options.explicit_order = 8;
  return options;
}

// Converged forced orbit by Newton; returns u (throws nothing; prints on failure).
Vector SolveForced(OdeSystem& system, const IntegratorOptions& integrator, int segments,
                   const Vector& x0, NewtonResult* result = nullptr) {
  ShootingOptions options;
  options.segments = segments;
  options.integrator = integrator;
  ShootingProblem problem(system, OrbitKind::kForced, options);
  const double lambda = system.Parameter();
  Vector u = problem.InitialGuess(x0, 0.0, lambda);
  NewtonOptions newton;
  newton.max_iterations = 30;
  newton.residual_tolerance = newton.step_tolerance = 1e-12;
  const NewtonResult r =
      NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, lambda, F); },
                  [&](const Vector& v, Matrix& J) { problem.Jacobian(v, lambda, J); }, u, newton,
                  problem.Scale(), problem.ResidualScale());
  if (result != nullptr) *result = r;
  return u;
}

void DuffingNewtonTable(bool quick) {
  DuffingParams params;
  params.frequency = 1.5;
  DuffingOscillator duffing(params);
  const double w = params.frequency;
  // Reference: ERK order 8 at 1e-13 (the one-term guess of the large response: A = 1.391).
  const double A = 1.3914665480451416, psi = std::atan2(0.05 * w, 1 - w * w + 0.75 * A * A);
  const Vector one_term = (Vector(2) << A * std::cos(psi), A * w * std::sin(psi)).finished();
  NewtonResult reference_newton;
  const Vector reference = SolveForced(
      duffing, Integrator(IntegrationMethod::kExplicitRungeKutta, 1e-13), 1, one_term,
      &reference_newton);
  std::printf("Duffing w = 1.5, large response: reference x(0) = (%.12f, %.12f) [%s]\n",
              reference(0), reference(1), reference_newton.BriefReport().c_str());
  std::printf("Newton from x(0) + (0.02, -0.02), tolerances 1e-9 (residual) / 1e-9 (step):\n");
  std::printf("%-12s %-8s %4s %5s %6s %10s %9s %9s %10s\n", "method", "rtol", "N", "resid", "iter",
              "steps", "time ms", "F+J ms", "err x(0)");
  const Vector guess = reference.head(2) + Vector::Constant(2, 0.02).cwiseProduct(
                                               (Vector(2) << 1.0, -1.0).finished());
  const std::vector<double> tolerances =
      quick ? std::vector<double>{1e-8} : std::vector<double>{1e-6, 1e-8, 1e-10};
  for (IntegrationMethod method : {IntegrationMethod::kBdf, IntegrationMethod::kAdams,
                                   IntegrationMethod::kExplicitRungeKutta}) {
    for (double tolerance : tolerances) {
      for (int segments : {1, 2, 4, 8}) {
        for (bool sensitivities_in_residual : {false, true}) {
          ShootingOptions options;
          options.segments = segments;
          options.integrator = Integrator(method, tolerance);
          options.sensitivities_in_residual = sensitivities_in_residual;
          ShootingProblem problem(duffing, OrbitKind::kForced, options);
          NewtonOptions newton;
          newton.residual_tolerance = newton.step_tolerance = 1e-9;
          newton.max_iterations = 20;
          NewtonResult result;
          Vector u;
          long steps = 0;
          const double seconds = MedianSeconds(
              [&] {
                problem.ResetStatistics();
                u = problem.InitialGuess(guess, 0.0, w);
                result = NewtonSolve(
                    [&](const Vector& v, Vector& F) { problem.Residual(v, w, F); },
                    [&](const Vector& v, Matrix& J) { problem.Jacobian(v, w, J); }, u, newton,
                    problem.Scale(), problem.ResidualScale());
                steps = problem.statistics().steps;
              },
              quick ? 0.02 : 0.2);
          // One residual + Jacobian evaluation near the solution (a new point each time, so that
          // nothing comes from the cache; the integrator memory is reused, as in continuation).
          Vector F, shifted = u;
          Matrix J;
          const double evaluation = MedianSeconds(
              [&] {
                shifted(0) += 1e-9;
                problem.Residual(shifted, w, F);
                problem.Jacobian(shifted, w, J);
              },
              quick ? 0.01 : 0.1);
          const double error = (u.head(2) - reference.head(2)).lpNorm<Eigen::Infinity>();
          std::printf("%-12s %-8.0e %4d %5s %6d %10ld %9.3f %9.3f %10.2e%s\n", ToString(method),
                      tolerance, segments, sensitivities_in_residual ? "sens" : "plain",
                      result.iterations, steps, 1e3 * seconds, 1e3 * evaluation, error,
                      result.Converged() ? "" : "  (not converged)");
        }
      }
    }
  }
}

// Monodromy by sensitivities and by differences of the flow, against a reference.
void MonodromyTable(OdeSystem& system, const char* name, const Vector& x0, double t1,
                    const Matrix& reference, const std::vector<double>& tolerances, bool quick) {
  const Index n = system.Dimension();
  const Vector scale = system.StateScale();
  std::printf("%s: monodromy over one period, error = max |ΔM ./ (scale_i/scale_j)| / max |M̂|\n",
              name);
  std::printf("%-30s %-8s %10s %10s %12s %14s\n", "method", "rtol", "time ms", "steps", "error",
              "mult. error");
  // Compare in scaled coordinates S⁻¹ M S, where entries of different units are commensurate.
  const Matrix scaled_reference = scale.cwiseInverse().asDiagonal() * reference * scale.asDiagonal();
  auto error_of = [&](const Matrix& M) {
    const Matrix scaled = scale.cwiseInverse().asDiagonal() * M * scale.asDiagonal();
    return (scaled - scaled_reference).cwiseAbs().maxCoeff() /
           scaled_reference.cwiseAbs().maxCoeff();
  };
  // Multipliers that matter for stability (|μ| > 1e-3 in the reference): the largest relative
  // error of the nearest computed multiplier.
  const ComplexVector reference_multipliers =
      ProductEigenvalues({reference}, FloquetMethod::kPeriodicSchur);
  auto multiplier_error_of = [&](const Matrix& M) {
    const ComplexVector computed = ProductEigenvalues({M}, FloquetMethod::kPeriodicSchur);
    double worst = 0.0;
    for (Index k = 0; k < reference_multipliers.size(); ++k) {
      if (std::abs(reference_multipliers(k)) < 1e-3) continue;
      double nearest = kInfinity;
      for (Index j = 0; j < computed.size(); ++j) {
        nearest = std::min(nearest, std::abs(computed(j) - reference_multipliers(k)));
      }
      worst = std::max(worst, nearest / std::abs(reference_multipliers(k)));
    }
    return worst;
  };
  for (double tolerance : tolerances) {
    OdeIntegrator integrator(system, Integrator(IntegrationMethod::kBdf, tolerance));
    Vector x1(n);
    Matrix M;
    long steps = 0;
    double seconds = 0.0;
    for (int variant = 0; variant < 4; ++variant) {
      IntegratorOptions options = Integrator(IntegrationMethod::kBdf, tolerance);
      options.sensitivity_error_control = variant == 0;
      if (variant == 2) options.max_order = 2;
      if (variant == 3) options.stability_limit_detection = true;
      OdeIntegrator sensitivities(system, options);
      seconds = MedianSeconds(
          [&] { steps = sensitivities.Integrate(0.0, x0, t1, x1, &M).statistics.steps; },
          quick ? 0.02 : 0.2);
      const char* label = variant == 0   ? "CVODES sens, errcon"
                          : variant == 1 ? "CVODES sens, no errcon"
                          : variant == 2 ? "CVODES sens, no errcon, BDF<=2"
                                         : "CVODES sens, no errcon, stabdet";
      std::printf("%-30s %-8.0e %10.3f %10ld %12.2e %14.2e\n", label, tolerance, 1e3 * seconds,
                  steps, error_of(M), multiplier_error_of(M));
    }
    for (bool central : {false, true}) {
      // Step balancing truncation against integration noise: h ≈ √tol (forward), ∛tol (central).
      const double relative_step = central ? std::cbrt(tolerance) : std::sqrt(tolerance);
      Matrix D(n, n);
      long total_steps = 0;
      seconds = MedianSeconds(
          [&] {
            total_steps = 0;
            Vector base(n), plus(n), minus(n), xp = x0;
            if (!central) total_steps += integrator.Integrate(0.0, x0, t1, base).statistics.steps;
            for (Index j = 0; j < n; ++j) {
              const double h = relative_step * std::max(std::abs(x0(j)), scale(j));
              xp(j) = x0(j) + h;
              total_steps += integrator.Integrate(0.0, xp, t1, plus).statistics.steps;
              if (central) {
                xp(j) = x0(j) - h;
                total_steps += integrator.Integrate(0.0, xp, t1, minus).statistics.steps;
                D.col(j) = (plus - minus) / (2 * h);
              } else {
                D.col(j) = (plus - base) / h;
              }
              xp(j) = x0(j);
            }
          },
          quick ? 0.02 : 0.2);
      std::printf("%-30s %-8.0e %10.3f %10ld %12.2e %14.2e\n",
                  central ? "central differences" : "forward differences", tolerance,
                  1e3 * seconds, total_steps, error_of(D), multiplier_error_of(D));
    }
  }
}

void StiffPeriodTable(StiffChain& chain, const char* name, const Vector& x0, double period,
                      bool quick) {
  std::printf("%s, one forcing period (%.4g s) from a point of the damped orbit:\n", name, period);
  std::printf("%-30s %-8s %10s %10s %10s  %s\n", "integrator", "rtol", "time ms", "steps",
              "f evals", "status");
  for (double tolerance : {1e-6, 1e-8, 1e-10}) {
    for (int variant = 0; variant < 5; ++variant) {
      const bool explicit_method = variant >= 3;
      IntegratorOptions options = Integrator(
          explicit_method ? IntegrationMethod::kExplicitRungeKutta : IntegrationMethod::kBdf,
          tolerance);
      if (explicit_method) options.explicit_order = 5;
      if (variant == 2) options.sensitivity_error_control = false;
      OdeIntegrator integrator(chain, options);
      Vector x1(16);
      Matrix M;
      IntegrationResult result;
      const bool sensitivities = variant == 1 || variant == 2 || variant == 4;
      const double seconds = MedianSeconds(
          [&] { result = integrator.Integrate(0.0, x0, period, x1, sensitivities ? &M : nullptr); },
          quick ? 0.02 : 0.2);
      const char* label = variant == 0   ? "BDF"
                          : variant == 1 ? "BDF + 16 sens (error control)"
                          : variant == 2 ? "BDF + 16 sens (no sens errcon)"
                          : variant == 3 ? "ERK (Dormand-Prince 5)"
                                         : "ERK + variational (272 states)";
      std::printf("%-30s %-8.0e %10.3f %10ld %10ld  %s\n", label, tolerance, 1e3 * seconds,
                  result.statistics.steps,
                  result.statistics.rhs_evaluations + result.statistics.sensitivity_rhs_evaluations,
                  ToString(result.status));
    }
  }
}

void StiffTables(bool quick);

void FloquetTable(bool quick) {
  std::printf("Floquet multipliers of N factors 16 × 16 (random, contracting and expanding):\n");
  std::printf("%4s %12s %12s %12s\n", "N", "Schur ms", "pencil ms", "product ms");
  for (int N : {1, 5, 10, 20, 40}) {
    std::vector<Matrix> factors;
    for (int i = 0; i < N; ++i) {
      Matrix M(16, 16);
      for (int r = 0; r < 16; ++r) {
        for (int c = 0; c < 16; ++c) M(r, c) = std::sin(1.7 * r + 0.3 * c * c + i) * (r == c ? 3 : 1);
      }
      factors.push_back(M);
    }
    double seconds[3];
    int k = 0;
    for (FloquetMethod method :
         {FloquetMethod::kPeriodicSchur, FloquetMethod::kPencil, FloquetMethod::kProduct}) {
      seconds[k++] = MedianSeconds([&] { ProductEigenvalues(factors, method); },
                                   quick ? 0.02 : 0.2);
    }
    std::printf("%4d %12.3f %12.3f %12.3f\n", N, 1e3 * seconds[0], 1e3 * seconds[1],
                1e3 * seconds[2]);
  }
}

int Main(int argc, char** argv) {
  bool quick = false;
  std::vector<std::string> sections;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else {
      sections.emplace_back(argv[i]);
    }
  }
  auto wanted = [&](const char* name) {
    return sections.empty() || std::find(sections.begin(), sections.end(), name) != sections.end();
  };
  if (wanted("duffing")) {
    DuffingNewtonTable(quick);
    std::printf("\n");
  }
  if (wanted("monodromy")) {
    DuffingParams params;
    params.frequency = 1.5;
    DuffingOscillator duffing(params);
    const double A = 1.3914665480451416, w = 1.5;
    const double psi = std::atan2(0.05 * w, 1 - w * w + 0.75 * A * A);
    const Vector x0 = SolveForced(duffing, Integrator(IntegrationMethod::kExplicitRungeKutta, 1e-13),
                                  1, (Vector(2) << A * std::cos(psi), A * w * std::sin(psi)).finished());
    OdeIntegrator tight(duffing, Integrator(IntegrationMethod::kExplicitRungeKutta, 1e-13));
    Vector x1(2);
    Matrix reference;
    tight.Integrate(0.0, x0.head(2), kTwoPi / w, x1, &reference);
    MonodromyTable(duffing, "Duffing (n = 2)", x0.head(2), kTwoPi / w, reference,
                   {1e-6, 1e-8, 1e-10}, quick);
  }
  std::printf("\n");

  if (wanted("stiff")) StiffTables(quick);
  if (wanted("floquet")) FloquetTable(quick);
  return 0;
}

void StiffTables(bool quick) {
  StiffChain damped(9.35e4), undamped(1.75);
  const double period = damped.ForcingPeriod();
  // The forced orbit of the damped chain: a transient of 20 periods from rest, then Newton.
  OdeIntegrator settle(damped, Integrator(IntegrationMethod::kBdf, 1e-10));
  Vector rest = Vector::Zero(16), x0(16);
  settle.Integrate(0.0, rest, 20 * period, x0);
  NewtonResult newton;
  Vector orbit;
  const double solve_seconds = MedianSeconds(
      [&] { orbit = SolveForced(damped, Integrator(IntegrationMethod::kBdf, 1e-8), 1, x0, &newton); },
      quick ? 0.02 : 0.5);
  std::printf("Stiff stand-in (damped contact), forced orbit from a 20-period transient, BDF 1e-8: "
              "%s, %.1f ms\n",
              newton.BriefReport().c_str(), 1e3 * solve_seconds);
  std::printf("Newton for that orbit from the transient (tolerances 100·rtol), per integrator:\n");
  std::printf("%-34s %-6s %-8s %6s %10s %10s\n", "integrator", "chain", "rtol", "iter", "time ms",
              "err x(0)");
  for (StiffChain* chain : {&damped, &undamped}) {
    // Reference orbit of this chain: BDF with sensitivities under error control at 1e-11.
    NewtonResult reference_newton;
    const Vector reference_orbit = SolveForced(*chain, Integrator(IntegrationMethod::kBdf, 1e-11),
                                               1, orbit.head(16), &reference_newton);
    for (double tolerance : {1e-6, 1e-8}) {
      for (int variant = 0; variant < 3; ++variant) {
        IntegratorOptions options = Integrator(
            variant == 2 ? IntegrationMethod::kExplicitRungeKutta : IntegrationMethod::kBdf,
            tolerance);
        if (variant == 2) options.explicit_order = 5;
        options.sensitivity_error_control = variant != 1;
        ShootingOptions shooting;
        shooting.integrator = options;
        ShootingProblem problem(*chain, OrbitKind::kForced, shooting);
        NewtonOptions newton_options;
        newton_options.max_iterations = 10;
        newton_options.residual_tolerance = newton_options.step_tolerance = 100 * tolerance;
        NewtonResult result;
        Vector u;
        const double seconds = MedianSeconds(
            [&] {
              u = problem.InitialGuess(x0, 0.0, chain->Parameter());
              result = NewtonSolve(
                  [&](const Vector& v, Vector& F) { problem.Residual(v, chain->Parameter(), F); },
                  [&](const Vector& v, Matrix& J) { problem.Jacobian(v, chain->Parameter(), J); },
                  u, newton_options, problem.Scale(), problem.ResidualScale());
            },
            0.01);
        const double error = (u - reference_orbit).cwiseQuotient(problem.Scale()).lpNorm<Eigen::Infinity>();
        const char* label = variant == 0   ? "BDF, sensitivities under errcon"
                            : variant == 1 ? "BDF, sensitivities without errcon"
                                           : "ERK DP5 + variational equations";
        std::printf("%-34s %-6s %-8.0e %6d %10.1f %10.2e%s\n", label,
                    chain == &damped ? "damped" : "HC", tolerance, result.iterations,
                    1e3 * seconds, error, result.Converged() ? "" : "  (not converged)");
      }
    }
  }
  std::printf("\n");
  OdeIntegrator tight(damped, Integrator(IntegrationMethod::kBdf, 1e-12));
  Vector x1(16);
  Matrix reference;
  tight.Integrate(0.0, orbit.head(16), period, x1, &reference);
  MonodromyTable(damped, "Stiff stand-in, damped contact (n = 16)", orbit.head(16), period,
                 reference, {1e-6, 1e-8, 1e-10}, quick);
  std::printf("\n");
  StiffPeriodTable(damped, "Stiff stand-in, damped contact (zeta = 0.05)", orbit.head(16), period,
                   quick);
  std::printf("\n");
  StiffPeriodTable(undamped, "Stiff stand-in, Hunt-Crossley contact damping (zeta = 1e-6)",
                   orbit.head(16), period, quick);
  std::printf("\n");
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("shooting_bench", [&] { return rubcont::Main(argc, argv); });
}
