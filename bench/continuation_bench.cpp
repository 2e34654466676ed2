// Continuation engine: steps per second, and the cost of a step against the bare Newton solves it
// contains, measured in the same run (issue 3: the engine should add less than 2× over them).
//
// For every problem the branch is run `repetitions` times (median and minimum reported). Then, for
// every accepted point k+1 of the branch, Newton at fixed λ_{k+1} is solved from the point's own
// predictor u_k + Δs τ_u (what the corrector started from), with the same scales and tolerances:
//  - "NewtonSolve" is the project's kernel (solvers/newton.h), as a caller would write it;
//  - "lean Newton" is a hand-written loop with a preallocated LU, the least a Newton solve costs.
// The ratio engine / bare is per branch: all the engine's work (tangents, step control, rejected
// steps, detection and location of special points, measures, events, storing the points) against
// the Newton solves alone.
//
//   build/bench/continuation_bench [repetitions]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "bench/bench_main.h"
#include "continuation/continuation.h"
#include "continuation/fold.h"
#include "models/rub_model.h"
#include "models/two_point_params.h"
#include "models/units.h"
#include "solvers/newton.h"
#include "waves/rotating_wave.h"

namespace rubcont {
namespace {

// x³ − x + λ = 0 (n = 1): the cheapest problem with two folds.
class Cubic : public Problem {
 public:
  Index Dimension() const override { return 1; }
  void Residual(const Vector& u, double l, Vector& F) override {
    F.resize(1);
    F(0) = u(0) * u(0) * u(0) - u(0) + l;
  }
  void Jacobian(const Vector& u, double, Matrix& J) override {
    J.resize(1, 1);
    J(0, 0) = 3 * u(0) * u(0) - 1;
  }
  void DfDlambda(const Vector&, double, Vector& dF) override { dF = Vector::Ones(1); }
};

// Bratu's problem −u'' = λ eᵘ on (0, 1), u(0) = u(1) = 0, by central differences on n interior
// points: a fold near λ = 3.51 (n = 16: 3.5087), then the upper branch towards λ → 0.
class Bratu : public Problem {
 public:
  explicit Bratu(Index n) : n_(n), h2_(1.0 / ((n + 1.0) * (n + 1.0))) {}
  Index Dimension() const override { return n_; }
  void Residual(const Vector& u, double l, Vector& F) override {
    F.resize(n_);
    for (Index i = 0; i < n_; ++i) {
      const double left = i > 0 ? u(i - 1) : 0.0;
      const double right = i + 1 < n_ ? u(i + 1) : 0.0;
      F(i) = (left - 2 * u(i) + right) / h2_ + l * std::exp(u(i));
    }
  }
  void Jacobian(const Vector& u, double l, Matrix& J) override {
    J.setZero(n_, n_);
    for (Index i = 0; i < n_; ++i) {
      J(i, i) = -2 / h2_ + l * std::exp(u(i));
      if (i > 0) J(i, i - 1) = 1 / h2_;
      if (i + 1 < n_) J(i, i + 1) = 1 / h2_;
    }
  }
  void DfDlambda(const Vector& u, double, Vector& dF) override { dF = u.array().exp(); }
  Vector ResidualScale() const override { return Vector::Constant(n_, 1.0 / h2_); }

 private:
  Index n_;
  double h2_;
};

template <class Function>
std::vector<double> TimeMs(int repetitions, Function&& function) {
  std::vector<double> ms;
  for (int i = 0; i < repetitions; ++i) {
    const auto start = std::chrono::steady_clock::now();
    function();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(ms.begin(), ms.end());
  return ms;
}

// Newton at fixed λ with a preallocated LU and the corrector's convergence test.
int LeanNewton(Problem& problem, Vector& u, double lambda, const Vector& scale,
               const Vector& residual_inverse, const CorrectorOptions& options,
               Eigen::PartialPivLU<Matrix>& lu, Vector& F, Matrix& J, Vector& delta) {
  problem.Residual(u, lambda, F);
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    problem.Jacobian(u, lambda, J);
    J = residual_inverse.asDiagonal() * J * scale.asDiagonal();
    lu.compute(J);
    delta = lu.solve(-F.cwiseProduct(residual_inverse));
    u += delta.cwiseProduct(scale);
    problem.Residual(u, lambda, F);
    if (F.cwiseProduct(residual_inverse).lpNorm<Eigen::Infinity>() <=
            options.residual_tolerance &&
        delta.lpNorm<Eigen::Infinity>() <= options.step_tolerance) {
      return iteration;
    }
  }
  return -1;
}

struct Row {
  std::string name;
  Index n = 0;
  Branch branch;
  std::vector<double> engine_ms;
  std::vector<double> newton_ms;
  std::vector<double> lean_ms;
  long bare_jacobians = 0;
  int bare_failures = 0;
};

// Runs the branch `repetitions` times (`make` builds a fresh problem each time, since problems keep
// state such as contact modes), then the bare Newton solves on the last branch's points.
Row Measure(const std::string& name, int repetitions,
            const std::function<std::unique_ptr<Problem>()>& make,
            const std::function<Branch(Problem&)>& run, bool bare) {
  Row row;
  row.name = name;
  std::unique_ptr<Problem> problem;
  row.engine_ms = TimeMs(repetitions, [&] {
    problem = make();
    row.branch = run(*problem);
  });
  row.n = problem->Dimension();
  if (!bare) return row;
  // Predictors of the accepted steps, in problem units.
  const Vector scale = problem->Scale();
  const Vector residual_inverse = problem->ResidualScale().cwiseInverse();
  const double lambda_scale = problem->LambdaScale();
  const std::vector<BranchPoint>& points = row.branch.points;
  std::vector<Vector> predictors;
  std::vector<double> lambdas;
  for (size_t k = 0; k + 1 < points.size(); ++k) {
    if (points[k + 1].step <= 0.0 || points[k].u.size() != row.n) continue;
    const Vector& tangent = points[k].tangent;
    predictors.push_back(points[k].u +
                         points[k + 1].step * tangent.head(row.n).cwiseProduct(scale));
    lambdas.push_back(points[k + 1].lambda);
  }
  const CorrectorOptions& corrector = row.branch.options.corrector;
  NewtonOptions newton;
  newton.max_iterations = corrector.max_iterations;
  newton.residual_tolerance = corrector.residual_tolerance;
  newton.step_tolerance = corrector.step_tolerance;
  const Vector residual_scale = problem->ResidualScale();
  long jacobians = 0;
  int failures = 0;
  row.newton_ms = TimeMs(repetitions, [&] {
    jacobians = 0;
    failures = 0;
    for (size_t i = 0; i < predictors.size(); ++i) {
      Vector u = predictors[i];
      const double lambda = lambdas[i];
      const NewtonResult result = NewtonSolve(
          [&](const Vector& x, Vector& F) { problem->Residual(x, lambda, F); },
          [&](const Vector& x, Matrix& J) { problem->Jacobian(x, lambda, J); }, u, newton, scale,
          residual_scale);
      jacobians += result.iterations;
      failures += result.Converged() ? 0 : 1;
    }
  });
  row.bare_jacobians = jacobians;
  row.bare_failures = failures;
  Eigen::PartialPivLU<Matrix> lu(row.n);
  Vector F(row.n), delta(row.n);
  Matrix J(row.n, row.n);
  row.lean_ms = TimeMs(repetitions, [&] {
    for (size_t i = 0; i < predictors.size(); ++i) {
      Vector u = predictors[i];
      LeanNewton(*problem, u, lambdas[i], scale, residual_inverse, corrector, lu, F, J, delta);
    }
  });
  (void)lambda_scale;
  return row;
}

void Print(const Row& row) {
  const Branch& b = row.branch;
  const double median = row.engine_ms[row.engine_ms.size() / 2];
  const int steps = std::max(1, b.statistics.steps);
  std::printf("\n%s (n = %ld)\n  %s\n", row.name.c_str(), static_cast<long>(row.n),
              b.BriefReport().c_str());
  std::printf("  branch: median %.3f ms, min %.3f ms; %d steps, %.1f µs/step, %.0f steps/s\n",
              median, row.engine_ms.front(), steps, 1e3 * median / steps, 1e3 * steps / median);
  std::printf("  per step: %.2f Jacobians, %.2f residuals, %.2f stability, %d corrector failures, "
              "%d angle rejections\n",
              static_cast<double>(b.statistics.jacobian_evaluations) / steps,
              static_cast<double>(b.statistics.residual_evaluations) / steps,
              static_cast<double>(b.statistics.stability_evaluations) / steps,
              b.statistics.corrector_failures, b.statistics.angle_rejections);
  if (row.newton_ms.empty()) return;
  const double newton = row.newton_ms[row.newton_ms.size() / 2];
  const double lean = row.lean_ms[row.lean_ms.size() / 2];
  std::printf("  bare Newton on the same points: NewtonSolve %.3f ms (%.2f Jacobians/point, %d "
              "failed), lean %.3f ms\n",
              newton, static_cast<double>(row.bare_jacobians) / steps, row.bare_failures, lean);
  std::printf("  engine / bare Newton: %.2f× (vs NewtonSolve), %.2f× (vs lean Newton)\n",
              median / newton, median / lean);
}

}  // namespace
}  // namespace rubcont

static int Run(int argc, char** argv) {
  using namespace rubcont;
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
  std::printf("continuation engine benchmark, %d repetitions per measurement\n", repetitions);
  std::vector<Row> rows;

  rows.push_back(Measure(
      "cubic x³ − x + λ, λ ∈ [−1, 1], two folds", repetitions,
      [] { return std::make_unique<Cubic>(); },
      [](Problem& p) {
        ContinuationOptions o;
        o.bounds.lambda_min = -1.0;
        o.bounds.lambda_max = 1.0;
        return Continue(p, Vector::Constant(1, 1.3), -1.0, o);
      },
      true));

  rows.push_back(Measure(
      "Bratu, 16 interior points, λ from 0.1 round the fold to ‖u‖∞ = 6", repetitions,
      [] { return std::make_unique<Bratu>(16); },
      [](Problem& p) {
        ContinuationOptions o;
        o.bounds.lambda_min = 0.0;
        o.bounds.max_state_norm = 6.0;
        return Continue(p, Vector::Zero(16), 0.1, o);
      },
      true));

  // The rub model's rotating waves (thesis case A(a)): whirl from the analytic Mode 1 orbit at
  // 60 Hz precession, continued in running speed over the thesis range 20–258 rpm.
  const TwoPointParams params = ThesisCaseAa();
  const RubStructure structure = TwoPointStructure(params);
  const double precession = HzToRadPerSecond(60.0);
  const double omega0 = precession / params.Rci(0);
  auto rub = [&](FrictionLawKind law) {
    return [&structure, law]() -> std::unique_ptr<Problem> {
      return std::make_unique<RotatingWaveProblem>(structure, law);
    };
  };
  auto whirl = [&](bool stability) {
    return [&, stability](Problem& p) {
      auto& problem = static_cast<RotatingWaveProblem&>(p);
      Vector u = problem.FromRigidContactOrbit(SolveRigidContactOrbit(structure, precession, {1, 1}));
      problem.SolveConsistent(u, omega0);
      ContinuationOptions o;
      o.detect.stability = stability;
      o.bounds.lambda_min = RpmToRadPerSecond(20.0);
      o.bounds.lambda_max = RpmToRadPerSecond(258.0);
      return Continue(p, u, omega0, o);
    };
  };
  rows.push_back(Measure("rub rotating waves, tanh friction, whirl 36 → 258 rpm", repetitions,
                         rub(FrictionLawKind::kTanh), whirl(false), true));
  rows.push_back(Measure("rub rotating waves, tanh friction, with stability", repetitions,
                         rub(FrictionLawKind::kTanh), whirl(true), true));
  rows.push_back(Measure("rub rotating waves, exact stick/slip (events), with stability",
                         repetitions, rub(FrictionLawKind::kExact), whirl(true), false));

  // Two-parameter fold curve through a cusp: x³ − ηx + λ, η from 1 through 0 and back to 1.5.
  class CuspProblem : public Cubic {
   public:
    void Residual(const Vector& u, double l, Vector& F) override {
      F = Vector::Constant(1, u(0) * u(0) * u(0) - eta_ * u(0) + l);
    }
    void Jacobian(const Vector& u, double, Matrix& J) override {
      J = Matrix::Constant(1, 1, 3 * u(0) * u(0) - eta_);
    }
    bool HasSecondParameter() const override { return true; }
    double SecondParameter() const override { return eta_; }
    void SetSecondParameter(double eta) override { eta_ = eta; }
    void DfDeta(const Vector& u, double, Vector& dF) override { dF = -u; }

   private:
    double eta_ = 1.0;
  };
  rows.push_back(Measure(
      "fold curve of x³ − ηx + λ through the cusp (FoldProblem)", repetitions,
      [] { return std::make_unique<CuspProblem>(); },
      [](Problem& p) {
        const double x = 1.0 / std::sqrt(3.0);
        SpecialPoint fold;
        fold.type = SpecialPointType::kFold;
        fold.u = Vector::Constant(1, x);
        fold.lambda = 2.0 * x * x * x;
        ContinuationOptions o;
        o.direction = -1;
        o.bounds.lambda_min = -1.0;
        o.bounds.lambda_max = 1.5;
        return ContinueFoldCurve(p, fold, o);
      },
      false));

  for (const Row& row : rows) Print(row);
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("continuation_bench", [&] { return Run(argc, argv); });
}
