// The forced Duffing branch ẍ + 0.05 ẋ + x + x³ = 0.3 cos(w t), w ∈ [0.5, 2.5], continued by
// shooting through the engine with stability on and both folds located (not part of the test
// suite; tests/shooting/duffing_branch_test.cpp asserts the same branch). Every row: wall time of
// the whole branch (median of repeated runs), continuation steps, residual / Jacobian / stability
// evaluations, integrator steps, segment integrations, and the error of both folds (w and x(0))
// against the harmonic-balance folds (H = 25, Moore–Spence; tests/shooting/duffing_harmonic_balance.h).
//   1. per shooting variant (single, multiple N = 2, 4, 8), integrator and tolerance;
//   2. the step controller: the engine's defaults against settings that let the step grow;
//   3. monodromy by forward sensitivities against central finite differences of the flow (single
//      shooting; the Jacobian M − I, ∂F/∂w and the multipliers all from differences): cost and
//      accuracy of the branch and its folds.
// Usage: duffing_branch_bench [--quick]
//        duffing_branch_bench custom bdf|adams|erk5|erk6|erk8 TOL SEGMENTS STEP_MAX TARGET_ANGLE BUDGET_S
//                             [TARGET_ITERATIONS [SENSITIVITIES_IN_RESIDUAL 0|1]]   (one row)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "continuation/continuation.h"
#include "models/textbook.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "tests/shooting/duffing_harmonic_balance.h"

namespace rubcont {
namespace {

using Clock = std::chrono::steady_clock;
using testing::DuffingHarmonicBalance;

// Median wall time and median process CPU time (seconds) of `body` over repetitions filling about
// `budget` seconds (≥ 3 runs). On a shared machine the CPU time is the steadier figure.
std::pair<double, double> MedianSeconds(const std::function<void()>& body, double budget) {
  std::vector<double> wall, cpu;
  const auto start = Clock::now();
  do {
    const auto t0 = Clock::now();
    const double c0 = ProcessCpuSeconds();
    body();
    cpu.push_back(CpuSecondsSince(c0));
    wall.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  } while ((std::chrono::duration<double>(Clock::now() - start).count() < budget ||
            wall.size() < 3) &&
           wall.size() < 50);
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

// Single forced shooting with every derivative by central differences of the flow map: F = y − x,
// so M = F_x + I. Stability is eig(M); nothing of the sensitivities is used.
class FiniteDifferenceShooting : public Problem {
 public:
  explicit FiniteDifferenceShooting(ShootingProblem& inner) : inner_(inner) {}
  Index Dimension() const override { return inner_.Dimension(); }
  void Residual(const Vector& u, double lambda, Vector& F) override {
    inner_.Residual(u, lambda, F);
  }
  // Problem's defaults: central differences of Residual.
  void Jacobian(const Vector& u, double lambda, Matrix& J) override {
    Problem::Jacobian(u, lambda, J);
  }
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override {
    Problem::DfDlambda(u, lambda, dF);
  }
  Vector Scale() const override { return inner_.Scale(); }
  double LambdaScale() const override { return inner_.LambdaScale(); }
  Vector ResidualScale() const override { return inner_.ResidualScale(); }
  bool HasStability() const override { return true; }
  Spectrum Stability(const Vector& u, double lambda) override {
    Matrix J;
    Jacobian(u, lambda, J);
    J += Matrix::Identity(J.rows(), J.cols());
    Spectrum spectrum;
    spectrum.kind = SpectrumKind::kFloquetMultipliers;
    spectrum.values = J.eigenvalues();
    std::sort(spectrum.values.data(), spectrum.values.data() + spectrum.values.size(),
              [](auto a, auto b) { return std::abs(a) > std::abs(b); });
    spectrum.valid = spectrum.values.allFinite();
    return spectrum;
  }
  std::vector<std::string> MeasureNames() const override { return inner_.MeasureNames(); }
  Vector Measures(const Vector& u, double lambda) override { return inner_.Measures(u, lambda); }

 private:
  ShootingProblem& inner_;
};

struct Reference {
  double w[2];   // lower, upper fold
  double x0[2];  // x(0) there
};

Reference HarmonicBalanceReference(const DuffingParams& params) {
  const DuffingHarmonicBalance balance(params, 25);
  Reference r{};
  const auto guesses = DuffingHarmonicBalance::OneTermFolds(params, 0.5, 2.5);
  for (int k = 0; k < 2; ++k) {
    const auto fold = balance.LocateFold(
        balance.FirstHarmonic(guesses[k].amplitude, guesses[k].phase), guesses[k].frequency);
    r.w[k] = fold.frequency;
    r.x0[k] = balance.Displacement0(fold.coefficients);
  }
  return r;
}

struct Variant {
  std::string name;
  int segments = 1;
  IntegrationMethod method = IntegrationMethod::kBdf;
  double tolerance = 1e-10;
  bool finite_differences = false;
  bool sensitivity_error_control = true;
  double step_max = 0.3;       // StepOptions::max (scaled arclength)
  double target_angle = 0.1;   // StepOptions::target_angle (rad)
  int target_iterations = 3;   // StepOptions::target_iterations
  bool sensitivities_in_residual = false;
  int explicit_order = 8;      // ERK order (kExplicitRungeKutta)
  int collocation_stages = 4;  // kGaussCollocation
  long collocation_steps = 0;  // per segment (kGaussCollocation)
};

ContinuationOptions BranchOptions(const Variant& v) {
  ContinuationOptions options;
  options.bounds.lambda_min = 0.5;
  options.bounds.lambda_max = 2.5;
  options.detect.stability = true;
  options.step.max = v.step_max;
  options.step.target_angle = v.target_angle;
  options.step.target_iterations = v.target_iterations;
  options.step.max_angle = std::max(options.step.max_angle, 2 * v.target_angle);
  return options;
}

void Row(const Variant& v, const DuffingParams& params, const Reference& ref, double budget) {
  DuffingOscillator duffing(params);
  ShootingOptions shooting;
  shooting.segments = v.segments;
  shooting.integrator.method = v.method;
  shooting.integrator.relative_tolerance = shooting.integrator.absolute_tolerance = v.tolerance;
  shooting.integrator.sensitivity_error_control = v.sensitivity_error_control;
  shooting.sensitivities_in_residual = v.sensitivities_in_residual;
  if (v.method == IntegrationMethod::kExplicitRungeKutta) {
    shooting.integrator.explicit_order = v.explicit_order;
  }
  if (v.method == IntegrationMethod::kGaussCollocation) {
    shooting.integrator.collocation_stages = v.collocation_stages;
    shooting.integrator.collocation_steps = v.collocation_steps;
  }
  const auto start = DuffingHarmonicBalance::OneTermSolutions(params)[0];
  const Vector x0 = (Vector(2) << start.first * std::cos(start.second),
                     start.first * params.frequency * std::sin(start.second)).finished();
  Branch branch;
  ShootingStatistics work;
  const auto [seconds, cpu_seconds] = MedianSeconds(
      [&] {
        // Every run from the same state: the problem's λ scale is read from the system.
        duffing.SetParameter(params.frequency);
        ShootingProblem problem(duffing, OrbitKind::kForced, shooting);
        const Vector u0 = problem.InitialGuess(x0, 0.0, params.frequency);
        if (v.finite_differences) {
          FiniteDifferenceShooting fd(problem);
          branch = Continue(fd, u0, params.frequency, BranchOptions(v));
        } else {
          branch = Continue(problem, u0, params.frequency, BranchOptions(v));
        }
        work = problem.statistics();
      },
      budget);
  double err_w[2] = {kNaN, kNaN}, err_x[2] = {kNaN, kNaN};
  int folds = 0;
  for (const SpecialPoint& p : branch.special_points) {
    if (p.type != SpecialPointType::kFold) continue;
    ++folds;
    const int k = p.lambda < 0.5 * (ref.w[0] + ref.w[1]) ? 0 : 1;
    err_w[k] = std::abs(p.lambda - ref.w[k]);
    err_x[k] = std::abs(p.u(0) - ref.x0[k]);
  }
  std::printf("%-30s %5.0e %7.3f %7.3f %5d %5ld %5ld %5ld %8ld %7ld %5d %9.1e %9.1e %9.1e %9.1e  %s\n",
              v.name.c_str(), v.tolerance, seconds, cpu_seconds, branch.statistics.steps,
              branch.statistics.residual_evaluations, branch.statistics.jacobian_evaluations,
              branch.statistics.stability_evaluations, work.steps,
              work.residual_integrations + work.sensitivity_integrations, folds, err_w[0],
              err_x[0], err_w[1], err_x[1], ToString(branch.status));
}

int Main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  if (argc >= 8 && std::strcmp(argv[1], "custom") == 0) {
    // custom METHOD(bdf|adams|erk8|gaussS:STEPS) TOL SEGMENTS STEP_MAX TARGET_ANGLE BUDGET
    // [TARGET_ITERATIONS [SENSITIVITIES_IN_RESIDUAL]]: one row (gauss4:40 = 4 stages, 40 steps
    // per segment).
    Variant v;
    v.name = std::string(argv[2]) + " N=" + argv[4];
    v.method = std::strcmp(argv[2], "adams") == 0 ? IntegrationMethod::kAdams
               : std::strncmp(argv[2], "erk", 3) == 0 ? IntegrationMethod::kExplicitRungeKutta
               : std::strncmp(argv[2], "gauss", 5) == 0 ? IntegrationMethod::kGaussCollocation
                                                      : IntegrationMethod::kBdf;
    if (v.method == IntegrationMethod::kExplicitRungeKutta) v.explicit_order = std::atoi(argv[2] + 3);
    if (v.method == IntegrationMethod::kGaussCollocation) {
      v.collocation_stages = std::atoi(argv[2] + 5);
      const char* colon = std::strchr(argv[2], ':');
      v.collocation_steps = colon != nullptr ? std::atol(colon + 1) : 0;
    }
    v.tolerance = std::atof(argv[3]);
    v.segments = std::atoi(argv[4]);
    v.step_max = std::atof(argv[5]);
    v.target_angle = std::atof(argv[6]);
    if (argc > 8) v.target_iterations = std::atoi(argv[8]);
    if (argc > 9) v.sensitivities_in_residual = std::atoi(argv[9]) != 0;
    DuffingParams params;
    params.frequency = 0.5;
    Row(v, params, HarmonicBalanceReference(params), std::atof(argv[7]));
    return 0;
  }
  const double budget = quick ? 0.0 : 1.0;
  DuffingParams params;
  params.frequency = 0.5;
  const Reference ref = HarmonicBalanceReference(params);
  std::printf("Duffing x'' + 0.05x' + x + x^3 = 0.3 cos(w t), w in [0.5, 2.5], stability on.\n");
  std::printf("Harmonic-balance folds (H = 25): lower w = %.12f (x0 = %.10f), upper w = %.12f "
              "(x0 = %.10f)\n", ref.w[0], ref.x0[0], ref.w[1], ref.x0[1]);
  auto header = [](const char* title) {
    std::printf("\n%s\n%-30s %5s %7s %7s %5s %5s %5s %5s %8s %7s %5s %9s %9s %9s %9s  %s\n", title,
                "variant", "tol", "wall s", "cpu s", "steps", "res", "jac", "stab", "int.step", "integr",
                "folds", "dw_lower", "dx_lower", "dw_upper", "dx_upper", "status");
  };
  // The step controller used in sections 1 and 3: Newton converges in 3 iterations even on tiny
  // steps (the third only confirms the 1e-8 step tolerance), so target_iterations = 3 never lets
  // the step grow; 5 does. Sensitivities in Residual: every residual of the corrector is followed
  // by a Jacobian at the same point, which then comes from the cache.
  auto tuned = [](Variant v) {
    v.step_max = 1.0;
    v.target_angle = 0.3;
    v.target_iterations = 5;
    v.sensitivities_in_residual = !v.finite_differences;
    return v;
  };
  const IntegrationMethod kErk = IntegrationMethod::kExplicitRungeKutta;
  const IntegrationMethod kAdams = IntegrationMethod::kAdams;
  const IntegrationMethod kBdf = IntegrationMethod::kBdf;

  header("1. Shooting variant, integrator and tolerance (tuned step control)");
  for (double tol : {1e-8, 1e-9, 1e-10, 1e-12}) {
    Row(tuned({"single, ERK8", 1, kErk, tol}), params, ref, budget);
    Row(tuned({"single, Adams", 1, kAdams, tol}), params, ref, budget);
    Row(tuned({"single, BDF", 1, kBdf, tol}), params, ref, budget);
    for (int n : {2, 4, 8}) {
      Row(tuned({"multiple N=" + std::to_string(n) + ", ERK8", n, kErk, tol}), params, ref, budget);
    }
    Row(tuned({"multiple N=4, BDF", 4, kBdf, tol}), params, ref, budget);
  }

  header("2. Step control: engine defaults (target 3 Newton iterations, max step 0.3, target "
         "angle 0.1, no sensitivities in Residual) against the tuned controller");
  for (IntegrationMethod method : {kErk, kBdf}) {
    const std::string name = method == kErk ? "ERK8" : "BDF";
    Row({"single, " + name + ", defaults", 1, method, 1e-10}, params, ref, budget);
    Row(tuned({"single, " + name + ", tuned", 1, method, 1e-10}), params, ref, budget);
  }

  header("3. Monodromy (and ∂F/∂w) by sensitivities against central differences of the flow, "
         "single shooting");
  for (double tol : {1e-8, 1e-10, 1e-12}) {
    for (IntegrationMethod method : {kErk, kAdams, kBdf}) {
      const std::string name = method == kErk ? "ERK8" : method == kAdams ? "Adams" : "BDF";
      Row(tuned({name + ", sensitivities", 1, method, tol}), params, ref, budget);
      Row(tuned({name + ", finite differences", 1, method, tol, true}), params, ref, budget);
      if (method != kErk) {
        Row(tuned({name + ", sens. without EC", 1, method, tol, false, false}), params, ref,
            budget);
      }
    }
  }
  header("4. Gauss collocation (solvers/ode_gauss.cpp) on a fixed mesh of STEPS per period, "
         "single shooting, against ERK8 (tuned step control; tol: the stage Newton's only)");
  Row(tuned({"single, ERK8", 1, kErk, 1e-10}), params, ref, budget);
  for (int stages : {3, 4}) {
    for (long steps : {20L, 30L, 40L, 60L}) {
      Variant v = tuned({"single, Gauss s=" + std::to_string(stages) + ", " +
                             std::to_string(steps) + " steps",
                         1, IntegrationMethod::kGaussCollocation, 1e-10});
      v.collocation_stages = stages;
      v.collocation_steps = steps;
      Row(v, params, ref, budget);
    }
  }
  std::printf("\nColumns: wall and process CPU time of the whole branch (medians), accepted continuation steps, "
              "Problem::Residual / Jacobian / Stability calls, integrator steps and segment "
              "integrations (shooting statistics), folds found, |w − w_HB| and |x(0) − x0_HB| at "
              "each fold.\n");
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("duffing_branch_bench", [&] { return rubcont::Main(argc, argv); });
}
