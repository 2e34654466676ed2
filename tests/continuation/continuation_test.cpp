#include "continuation/continuation.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "continuation/fold.h"
#include "solvers/constants.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// x² − λ = 0: one fold at (x, λ) = (0, 0).
LambdaProblem Parabola(bool analytic) {
  if (!analytic) {
    return LambdaProblem(1, [](const Vector& u, double l, double, Vector& F) {
      F(0) = u(0) * u(0) - l;
    });
  }
  return LambdaProblem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) * u(0) - l; },
      [](const Vector& u, double, double, Matrix& J) { J(0, 0) = 2.0 * u(0); },
      [](const Vector&, double, double, Vector& dF) { dF(0) = -1.0; });
}

// x³ − x + λ = 0: folds at x = ±1/√3, λ = ∓2/(3√3).
LambdaProblem Cubic(bool analytic) {
  auto residual = [](const Vector& u, double l, double, Vector& F) {
    F(0) = u(0) * u(0) * u(0) - u(0) + l;
  };
  if (!analytic) return LambdaProblem(1, residual);
  return LambdaProblem(
      1, residual,
      [](const Vector& u, double, double, Matrix& J) { J(0, 0) = 3 * u(0) * u(0) - 1; },
      [](const Vector&, double, double, Vector& dF) { dF(0) = 1.0; });
}

TEST_CASE("the fold of x² − λ is located to 1e-9", "[continuation][fold]") {
  const bool analytic = GENERATE(true, false);
  LambdaProblem problem = Parabola(analytic);
  ContinuationOptions options;
  options.direction = -1;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  const Branch branch = Continue(problem, Vec({1.0}), 1.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kFold) == 1);
  const SpecialPoint& fold = branch.special_points.front();
  CHECK(fold.converged);
  CHECK(std::abs(fold.lambda) <= 1e-9);
  CHECK(std::abs(fold.u(0)) <= 1e-9);
  CHECK(fold.residual_norm <= 1e-10);
  CHECK(std::abs(fold.tangent(1)) <= 1e-8);  // the tangent is vertical at a fold
  // The branch came round the fold and ends on the other half at the bound.
  CHECK(branch.points.back().lambda == Approx(1.0).epsilon(0).margin(1e-12));
  CHECK(branch.points.back().u(0) == Approx(-1.0).epsilon(0).margin(1e-9));
  CHECK(branch.Count(SpecialPointType::kBranchPoint) == 0);
}

// x² − λ with the test function dx/dλ − ¼ = 1/(2x) − ¼: a zero at x = 2 and a pole at the fold
// x = 0, where it changes sign from −∞ to +∞ (as the rub's knee test dΩ/dω − ½R/C does at every
// fold of a tanh-law branch).
class ParabolaWithSlopeTest : public LambdaProblem {
 public:
  ParabolaWithSlopeTest() : LambdaProblem(Parabola(true)) {}
  std::vector<std::string> TestFunctionNames() const override { return {"slope"}; }
  Vector TestFunctions(const Vector& u, double) override { return Vec({0.5 / u(0) - 0.25}); }
};

TEST_CASE("a test function's pole at a fold is no special point, its zero is",
          "[continuation][test_functions]") {
  ParabolaWithSlopeTest problem;
  ContinuationOptions options;
  options.direction = -1;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 5.0;
  const Branch branch = Continue(problem, Vec({-2.0}), 4.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  CHECK(branch.Count(SpecialPointType::kFold) == 1);
  REQUIRE(branch.Count(SpecialPointType::kTestFunction) == 1);
  for (const SpecialPoint& p : branch.special_points) {
    if (p.type != SpecialPointType::kTestFunction) continue;
    CHECK(p.label == "slope");
    CHECK(p.converged);
    CHECK(p.u(0) == Approx(2.0).epsilon(0).margin(1e-8));
    CHECK(p.lambda == Approx(4.0).epsilon(0).margin(1e-8));
  }
}

TEST_CASE("both folds of x³ − x + λ are located to 1e-9", "[continuation][fold]") {
  const bool analytic = GENERATE(true, false);
  LambdaProblem problem = Cubic(analytic);
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  // Start on the upper sheet at λ = −1 (x³ − x − 1 = 0, x ≈ 1.3247).
  const Branch branch = Continue(problem, Vec({1.3}), -1.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kFold) == 2);
  const double lambda_fold = 2.0 / (3.0 * std::sqrt(3.0));
  const SpecialPoint& first = branch.special_points[0];
  const SpecialPoint& second = branch.special_points[1];
  CHECK(first.converged);
  CHECK(second.converged);
  CHECK(std::abs(first.lambda - lambda_fold) <= 1e-9);
  CHECK(std::abs(first.u(0) - 1.0 / std::sqrt(3.0)) <= 1e-9);
  CHECK(std::abs(second.lambda + lambda_fold) <= 1e-9);
  CHECK(std::abs(second.u(0) + 1.0 / std::sqrt(3.0)) <= 1e-9);
  // Ends on the lower sheet: x³ − x + 1 = 0 at λ = 1.
  const double x_end = branch.points.back().u(0);
  CHECK(std::abs(x_end * x_end * x_end - x_end + 1.0) <= 1e-10);
  CHECK(x_end < -1.0);
  // Special points are listed along the branch with the index of the point before them.
  CHECK(first.index < second.index);
  CHECK(branch.points[first.index].lambda <= lambda_fold);
}

TEST_CASE("an isola is followed all the way round and recognised as closed",
          "[continuation][closed]") {
  // x² + λ² = 1, y = xλ: a closed curve with folds at λ = ±1.
  LambdaProblem problem(
      2,
      [](const Vector& u, double l, double, Vector& F) {
        F(0) = u(0) * u(0) + l * l - 1.0;
        F(1) = u(1) - u(0) * l;
      },
      [](const Vector& u, double l, double, Matrix& J) {
        J << 2 * u(0), 0.0, -l, 1.0;
      },
      [](const Vector& u, double l, double, Vector& dF) { dF << 2 * l, -u(0); });
  ContinuationOptions options;
  options.step.max = 0.2;
  const Branch branch = Continue(problem, Vec({1.0, 0.0}), 0.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kClosed);
  CHECK(branch.Count(SpecialPointType::kFold) == 2);
  for (const SpecialPoint& fold : branch.special_points) {
    CHECK(std::abs(std::abs(fold.lambda) - 1.0) <= 1e-9);
    CHECK(std::abs(fold.u(0)) <= 1e-6);
  }
  // The last point is the first, and the arclength is the circumference 2π of the circle in the
  // (x, λ) plane stretched by y = xλ.
  CHECK((branch.points.back().u - branch.points.front().u).norm() <= 1e-6);
  CHECK(std::abs(branch.points.back().lambda - branch.points.front().lambda) <= 1e-6);
  CHECK(branch.points.back().arclength > kTwoPi);
  CHECK(branch.points.size() < 300u);
  for (const BranchPoint& p : branch.points) CHECK(p.residual_norm <= 1e-10);
}

// atan(10 (x − sin 3λ)) = 0: the branch x = sin 3λ is curved, and Newton on atan diverges when
// the predictor misses by more than ~0.14; steps of 0.5 miss by far more.
LambdaProblem CurvedAtanProblem() {
  return LambdaProblem(
      1,
      [](const Vector& u, double l, double, Vector& F) {
        F(0) = std::atan(10.0 * (u(0) - std::sin(3.0 * l)));
      },
      [](const Vector& u, double l, double, Matrix& J) {
        const double e = 10.0 * (u(0) - std::sin(3.0 * l));
        J(0, 0) = 10.0 / (1.0 + e * e);
      },
      [](const Vector& u, double l, double, Vector& dF) {
        const double e = 10.0 * (u(0) - std::sin(3.0 * l));
        dF(0) = -30.0 * std::cos(3.0 * l) / (1.0 + e * e);
      });
}

// Steps of 0.5 up to λ = lambda_max, the angle test switched off: what limits them is the test's.
ContinuationOptions LongSteps(double lambda_max) {
  ContinuationOptions options;
  options.step.initial = 0.5;
  options.step.max = 0.5;
  options.step.max_angle = 3.0;
  options.step.target_angle = 3.0;
  options.bounds.lambda_max = lambda_max;
  return options;
}

TEST_CASE("a corrector that diverges at a large step halves the step and the branch recovers",
          "[continuation][step]") {
  LambdaProblem problem = CurvedAtanProblem();
  const ContinuationOptions options = LongSteps(3.0);  // Newton, not the angle test, limits them
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, options);
  INFO(branch.BriefReport());
  CHECK(branch.statistics.corrector_failures > 0);
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  CHECK(branch.points.back().lambda == Approx(3.0).epsilon(0).margin(1e-12));
  for (const BranchPoint& p : branch.points) {
    CHECK(std::abs(p.u(0) - std::sin(3.0 * p.lambda)) <= 1e-10);
  }
  // Some steps were taken at a halved length after a failure.
  bool halved = false;
  for (const BranchPoint& p : branch.points) halved = halved || (p.step > 0 && p.step < 0.5);
  CHECK(halved);
}

// u = sin 3λ whose points the problem calls stray when they lie more than 0.1 in λ from the last
// accepted one (Problem::StrayPoint): a stand-in for a root that is no neighbour of the branch.
class NearLastOnly : public LambdaProblem {
 public:
  NearLastOnly()
      : LambdaProblem(1, [](const Vector& u, double l, double, Vector& F) {
          F(0) = u(0) - std::sin(3.0 * l);
        }) {}
  void PointAccepted(const Vector& /*u*/, double lambda) override { last_ = lambda; }
  std::string StrayPoint(const Vector& /*u*/, double lambda) override {
    return std::abs(lambda - last_) > 0.1 ? "too far from the last point" : std::string();
  }

 private:
  double last_ = 0.0;
};

TEST_CASE("a converged point the problem calls stray shortens the step as a corrector failure does",
          "[continuation][step]") {
  NearLastOnly problem;
  ContinuationOptions options = LongSteps(1.0);  // StrayPoint, not the angle test, limits them
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  CHECK(branch.statistics.stray_rejections > 0);
  CHECK_THAT(branch.BriefReport(), Catch::Contains("stray points refused"));
  CHECK(branch.statistics.corrector_failures == 0);
  for (std::size_t k = 1; k < branch.points.size(); ++k) {
    CHECK(std::abs(branch.points[k].lambda - branch.points[k - 1].lambda) <= 0.1);
  }
  // At the smallest step every point is stray: the branch ends and says why.
  options.step.min = options.step.initial = options.step.max = 0.5;
  const Branch stuck = Continue(problem, Vec({0.0}), 0.0, options);
  CHECK(stuck.status == BranchStatus::kStepTooSmall);
  CHECK_THAT(stuck.message, Catch::Contains("continues no branch: too far from the last point"));
}

TEST_CASE("curved_predictor: the parabola through the previous point starts Newton closer, so the "
          "same circle costs fewer iterations and longer steps",
          "[continuation][step]") {
  // u² + λ² = 1 from (1, 0): a curvature of 1 in scaled units.
  LambdaProblem circle(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) * u(0) + l * l - 1.0; },
      [](const Vector& u, double, double, Matrix& J) { J(0, 0) = 2.0 * u(0); },
      [](const Vector&, double l, double, Vector& dF) { dF(0) = 2.0 * l; });
  const auto run = [&](bool curved, double step, int target_iterations) {
    ContinuationOptions options;
    options.step.initial = step;
    options.step.max = step;
    options.step.target_iterations = target_iterations;
    options.step.max_angle = options.step.target_angle = 1.0;
    options.step.curved_predictor = curved;
    options.bounds.max_steps = 12;
    return Continue(circle, Vec({1.0}), 0.0, options);
  };
  const auto iterations = [](const Branch& b) {
    int n = 0;
    for (const BranchPoint& p : b.points) n += p.newton_iterations;
    return n;
  };
  // Equal steps of 0.2: every point on the circle, fewer Newton iterations after the first step.
  const Branch tangent = run(false, 0.2, 8), curved = run(true, 0.2, 8);
  INFO(tangent.BriefReport() << " / " << curved.BriefReport());
  REQUIRE(curved.points.size() == tangent.points.size());
  for (const BranchPoint& p : curved.points) {
    CHECK(std::abs(p.u(0) * p.u(0) + p.lambda * p.lambda - 1.0) <= 1e-10);
  }
  CHECK(iterations(curved) < iterations(tangent));
  for (std::size_t k = 2; k < curved.points.size(); ++k) {
    CAPTURE(k);
    CHECK(curved.points[k].newton_iterations <= tangent.points[k].newton_iterations);
  }
  // With the step chosen by an iteration target of 2, the curved predictor's steps grow longer.
  const Branch tangent2 = run(false, 1.0, 2), curved2 = run(true, 1.0, 2);
  CHECK(curved2.points.back().arclength > 1.3 * tangent2.points.back().arclength);
}

TEST_CASE("failure_memory: after a corrector failure the steps stay below the one that failed, "
          "so the same branch costs fewer failures",
          "[continuation][step]") {
  LambdaProblem problem = CurvedAtanProblem();
  const auto run = [&](int failure_memory) {
    ContinuationOptions options;
    options.step.initial = 0.5;
    options.step.max = 0.5;
    options.step.max_angle = 3.0;
    options.step.target_angle = 3.0;
    options.step.target_iterations = 6;  // Newton needs fewer here: each step grows back at once
    options.step.failure_memory = failure_memory;
    options.bounds.lambda_max = 3.0;
    return Continue(problem, Vec({0.0}), 0.0, options);
  };
  const Branch forgetful = run(0);
  const Branch remembering = run(1000);
  INFO(forgetful.BriefReport() << " / " << remembering.BriefReport());
  REQUIRE(remembering.status == BranchStatus::kReachedLambdaBound);
  for (const BranchPoint& p : remembering.points) {
    CHECK(std::abs(p.u(0) - std::sin(3.0 * p.lambda)) <= 1e-10);
  }
  CHECK(remembering.statistics.corrector_failures > 0);
  CHECK(remembering.statistics.corrector_failures < forgetful.statistics.corrector_failures);
  // Every step after the first failure stays below 3/4 of the step that failed (≤ 0.5).
  double first_failed_at = 0.0;
  for (const BranchPoint& p : remembering.points) {
    if (p.step > 0.0 && p.step < 0.5 && first_failed_at == 0.0) first_failed_at = p.arclength;
    if (first_failed_at > 0.0 && p.arclength > first_failed_at) CHECK(p.step <= 0.75 * 0.5);
  }

  ContinuationOptions bad;
  bad.step.failure_memory = -1;
  CHECK_THROWS_WITH(Validate(bad), Catch::Contains("step.failure_memory") &&
                                       Catch::Contains("must be at least 0"));
}

// A Duffing-like frequency response written in the rub model's units: amplitude a ~ 1e-4 m,
// restoring force f ~ 1e3 N, backbone frequency Ω ~ 1e2 rad/s, forcing frequency λ = ω ~ 1e2
// rad/s:  (m a (Ω² − ω²))² + (c ω a)² = P²,  f = k a + κ a³,  m Ω² a = f.
struct StiffDuffing {
  double k = 1e7, kappa = 4e14, m = 1e3, c = 4e3, P = 40.0;

  LambdaProblem Make() const {
    const StiffDuffing d = *this;
    LambdaProblem problem(
        3,
        [d](const Vector& u, double w, double, Vector& F) {
          const double a = u(0), f = u(1), W = u(2);
          const double in_phase = d.m * a * (W * W - w * w);
          F(0) = in_phase * in_phase + (d.c * w * a) * (d.c * w * a) - d.P * d.P;
          F(1) = f - d.k * a - d.kappa * a * a * a;
          F(2) = d.m * W * W * a - f;
        },
        [d](const Vector& u, double w, double, Matrix& J) {
          const double a = u(0), W = u(2);
          const double in_phase = d.m * a * (W * W - w * w);
          J(0, 0) = 2 * in_phase * d.m * (W * W - w * w) + 2 * d.c * d.c * w * w * a;
          J(0, 1) = 0.0;
          J(0, 2) = 2 * in_phase * d.m * a * 2 * W;
          J(1, 0) = -d.k - 3 * d.kappa * a * a;
          J(1, 1) = 1.0;
          J(1, 2) = 0.0;
          J(2, 0) = d.m * W * W;
          J(2, 1) = -1.0;
          J(2, 2) = 2 * d.m * W * a;
        },
        [d](const Vector& u, double w, double, Vector& dF) {
          const double a = u(0), W = u(2);
          const double in_phase = d.m * a * (W * W - w * w);
          dF(0) = 2 * in_phase * d.m * a * (-2 * w) + 2 * d.c * d.c * w * a * a;
          dF(1) = 0.0;
          dF(2) = 0.0;
        });
    return problem;
  }

  // Independent fold: the scalar amplitude equation G(a, ω) = a²s² + (cωa)² − P², s = k + κa² −
  // mω² (f and Ω eliminated), with G = ∂G/∂a = 0, by Newton in (a, ω) from a guess.
  std::pair<double, double> Fold(double a, double w) const {
    for (int it = 0; it < 40; ++it) {
      const double s = k + kappa * a * a - m * w * w;
      const double ds_dw = -2 * m * w;
      const double G = a * a * s * s + c * c * w * w * a * a - P * P;
      const double Ga = 2 * a * s * s + 4 * kappa * a * a * a * s + 2 * c * c * w * w * a;
      const double Gw = 2 * a * a * s * ds_dw + 2 * c * c * w * a * a;
      const double Gaa = 2 * s * s + 20 * kappa * a * a * s + 8 * kappa * kappa * a * a * a * a +
                         2 * c * c * w * w;
      const double Gaw = 4 * a * s * ds_dw + 4 * kappa * a * a * a * ds_dw + 4 * c * c * w * a;
      Eigen::Matrix2d J;
      J << Ga, Gw, Gaa, Gaw;
      const Eigen::Vector2d step = J.fullPivLu().solve(Eigen::Vector2d(-G, -Ga));
      a += step(0);
      w += step(1);
      if (std::abs(step(0)) <= 1e-16 * std::abs(a) && std::abs(step(1)) <= 1e-16 * std::abs(w)) {
        break;
      }
    }
    return {a, w};
  }
};

TEST_CASE("a stiff-scaled problem works because of the scaling", "[continuation][scaling]") {
  const StiffDuffing duffing;
  LambdaProblem problem = duffing.Make();
  problem.SetScales(Vec({1e-4, 1e3, 1e2}), 1e2,
                    Vec({duffing.P * duffing.P, 1e3, 1e3}));
  // Start at ω = 50 rad/s near the linear response a = P / (k − mω²).
  const double w0 = 50.0;
  const double a0 = duffing.P / (duffing.k - duffing.m * w0 * w0);
  const Vector u0 = Vec({a0, duffing.k * a0, std::sqrt(duffing.k / duffing.m)});
  ContinuationOptions options;
  options.bounds.lambda_min = 40.0;
  options.bounds.lambda_max = 200.0;
  options.bounds.max_steps = 400;
  const Branch branch = Continue(problem, u0, w0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kFold) == 2);
  for (const SpecialPoint& fold : branch.special_points) {
    REQUIRE(fold.converged);
    const auto [a_fold, w_fold] = duffing.Fold(fold.u(0), fold.lambda);
    CHECK(std::abs(fold.lambda - w_fold) <= 1e-9 * w_fold);
    CHECK(std::abs(fold.u(0) - a_fold) <= 1e-9 * a_fold);
  }
  // The jump-down fold (larger ω) comes first along the branch, on the hardening side.
  CHECK(branch.special_points[0].lambda > branch.special_points[1].lambda);
  CHECK(branch.special_points[0].lambda > 110.0);

  SECTION("without scaling the same run misbehaves") {
    LambdaProblem unscaled = duffing.Make();  // Scale(), LambdaScale(), ResidualScale() all 1
    const Branch raw = Continue(unscaled, u0, w0, options);
    INFO(raw.BriefReport());
    // In unit scales the arclength is dominated by the force f (newtons): a step of at most 0.1
    // is 0.1 N, the amplitude (1e-4 m) is invisible to step control and to the corrector's step
    // tolerance, and the branch creeps: 400 steps do not even reach the resonance (ω ≈ 110).
    CHECK(raw.status == BranchStatus::kMaxSteps);
    CHECK(raw.Lambda().maxCoeff() < 100.0);
    CHECK(raw.Count(SpecialPointType::kFold) == 0);
  }
}

TEST_CASE("the stepper can take one step at a time", "[continuation][stepper]") {
  LambdaProblem problem = Cubic(true);
  ContinuationOptions options;
  Continuation continuation(problem, options);
  REQUIRE(continuation.Start(Vec({1.3}), -1.0) == StepResult::kContinue);
  REQUIRE(continuation.branch().points.size() == 1);
  // The start was corrected at fixed λ.
  const double x0 = continuation.branch().points[0].u(0);
  CHECK(std::abs(x0 * x0 * x0 - x0 - 1.0) <= 1e-12);
  CHECK(continuation.branch().points[0].lambda == -1.0);
  CHECK(continuation.branch().start_note.empty());
  REQUIRE(continuation.Step() == StepResult::kContinue);
  REQUIRE(continuation.branch().points.size() == 2);
  const BranchPoint& p = continuation.branch().points[1];
  CHECK(p.lambda > -1.0);  // direction +1
  CHECK(p.step == Approx(options.step.initial));
  CHECK(p.newton_iterations >= 1);
  CHECK(continuation.step_size() >= options.step.initial);  // an easy step grows the next
  CHECK(continuation.branch().status == BranchStatus::kRunning);
}

TEST_CASE("a start exactly at a fold: along a given tangent, or by the null-vector fallback",
          "[continuation][stepper]") {
  LambdaProblem problem = Parabola(true);
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  SECTION("StartWithTangent picks the half of the branch") {
    for (double side : {1.0, -1.0}) {
      Continuation continuation(problem, options);
      REQUIRE(continuation.StartWithTangent(Vec({0.0}), 0.0, Vec({side}), 0.0) ==
              StepResult::kContinue);
      const Branch branch = RunToEnd(continuation);
      INFO(branch.BriefReport());
      REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
      CHECK(branch.points.back().u(0) == Approx(side).epsilon(0).margin(1e-9));
      for (const BranchPoint& p : branch.points) CHECK(p.u(0) * side >= 0.0);
    }
  }
  SECTION("Start: F_u is singular at fixed λ, the start is corrected along the null vector") {
    const Branch branch = Continue(problem, Vec({0.0}), 0.0, options);
    INFO(branch.BriefReport());
    CHECK(branch.status == BranchStatus::kReachedLambdaBound);
    CHECK(branch.points.front().residual_norm <= 1e-12);
    CHECK(std::abs(branch.points.back().u(0)) == Approx(1.0).epsilon(0).margin(1e-9));
    // Said, with where the start went (here it stays at the fold, λ = 0).
    CHECK_THAT(branch.start_note,
               Catch::Contains("the start corrected along the null vector from λ = 0"));
    CHECK_THAT(branch.BriefReport(), Catch::Contains(branch.start_note));
  }
}

TEST_CASE("a Newton step that leaves the residual's domain is halved until it is back inside",
          "[continuation][stepper]") {
  // x² − λ with no residual beyond x = 3 (as a shooting problem whose integration fails there).
  // From x = 0.1 at λ = 1 the full Newton step lands at 5.05: halved once, at 2.575, Newton goes
  // on to x = 1.
  LambdaProblem problem(
      1,
      [](const Vector& u, double l, double, Vector& F) {
        F(0) = u(0) < 3.0 ? u(0) * u(0) - l : kNaN;
      },
      [](const Vector& u, double, double, Matrix& J) { J(0, 0) = 2.0 * u(0); },
      [](const Vector&, double, double, Vector& dF) { dF(0) = -1.0; });
  ContinuationOptions options;
  options.bounds.lambda_min = 0.5;
  options.bounds.lambda_max = 2.0;
  options.bounds.max_steps = 1;
  Continuation continuation(problem, options);
  REQUIRE(continuation.Start(Vec({0.1}), 1.0) == StepResult::kContinue);
  const BranchPoint& start = continuation.branch().points.front();
  CHECK(start.lambda == 1.0);
  CHECK(start.u(0) == Approx(1.0).epsilon(1e-10));
  // A step past every halving (the residual non-finite for x > 0.2: the start's own neighbourhood
  // after 4 halvings of 4.95 is still 0.41) is refused as before.
  LambdaProblem narrow(1, [](const Vector& u, double l, double, Vector& F) {
    F(0) = u(0) < 0.2 ? u(0) * u(0) - l : kNaN;
  });
  Continuation refused(narrow, options);
  CHECK(refused.Start(Vec({0.1}), 1.0) == StepResult::kFailed);
}

TEST_CASE("the per-step callback sees every step and can stop the branch",
          "[continuation][stepper]") {
  LambdaProblem problem = Cubic(true);
  int calls = 0;
  const Branch branch =
      Continue(problem, Vec({1.3}), -1.0, {}, [&calls](const Branch& b) {
        ++calls;
        return b.points.size() < 5;
      });
  CHECK(calls == 4);
  CHECK(branch.points.size() == 5u);
  CHECK(branch.status == BranchStatus::kStoppedByCaller);
}

TEST_CASE("an end test ends the branch with the caller's status and message, after the callback",
          "[continuation][stepper]") {
  LambdaProblem problem = Cubic(true);
  int calls = 0;
  const Branch branch = Continue(
      problem, Vec({1.3}), -1.0, {}, [&calls](const Branch&) { return ++calls > 0; },
      [](const Branch& b) -> std::optional<BranchEnd> {
        if (b.points.size() < 4) return std::nullopt;
        return BranchEnd{BranchStatus::kClosed, "closed: found by the caller"};
      });
  CHECK(calls == 3);
  CHECK(branch.points.size() == 4u);
  CHECK(branch.status == BranchStatus::kClosed);
  CHECK(branch.message == "closed: found by the caller");
  // Where the callback stops the branch at the same step, the end test is not asked.
  const Branch stopped = Continue(
      problem, Vec({1.3}), -1.0, {}, [](const Branch& b) { return b.points.size() < 3; },
      [](const Branch& b) -> std::optional<BranchEnd> {
        if (b.points.size() < 3) return std::nullopt;
        return BranchEnd{BranchStatus::kClosed, "never"};
      });
  CHECK(stopped.status == BranchStatus::kStoppedByCaller);
  Continuation running(problem, {});
  REQUIRE(running.Start(Vec({1.3}), -1.0) == StepResult::kContinue);
  CHECK_THROWS_WITH(running.Stop("no", BranchStatus::kRunning),
                    Catch::Contains("status = running"));
}

// x = λ with two test functions: a grazing at λ = 1 and another zero at λ = 1.5 (where a rub orbit
// family's determinant and multipliers jump, past its grazing).
class LineWithGrazing : public LambdaProblem {
 public:
  LineWithGrazing()
      : LambdaProblem(
            1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) - l; },
            [](const Vector&, double, double, Matrix& J) { J(0, 0) = 1.0; },
            [](const Vector&, double, double, Vector& dF) { dF(0) = -1.0; }) {}
  std::vector<std::string> TestFunctionNames() const override { return {"lift_off", "past"}; }
  Vector TestFunctions(const Vector& u, double) override {
    return Vec({1.0 - u(0), u(0) - 1.5});
  }
  SpecialPointType TestFunctionType(int k) const override {
    return k == 0 ? SpecialPointType::kGrazing : SpecialPointType::kTestFunction;
  }
};

TEST_CASE("end_at_grazing: the step that meets the grazing is cut there, nothing past it located",
          "[continuation][bounds]") {
  LineWithGrazing problem;
  ContinuationOptions options;
  options.bounds.lambda_max = 3.0;
  options.step.initial = options.step.max = 3.0;  // the first step crosses both sign changes
  options.bounds.end_at_grazing = true;
  const Branch ended = Continue(problem, Vec({0.0}), 0.0, options);
  INFO(ended.BriefReport() << " — " << ended.message);
  CHECK(ended.status == BranchStatus::kGrazing);
  CHECK_THAT(ended.message, Catch::Contains("ended at the grazing lift_off located at λ = 1:"));
  REQUIRE(ended.points.size() == 2u);
  CHECK(ended.points.back().lambda == Approx(1.0).epsilon(0).margin(1e-9));
  REQUIRE(ended.special_points.size() == 1u);
  CHECK(ended.special_points[0].type == SpecialPointType::kGrazing);
  CHECK(ended.special_points[0].converged);
  CHECK(ended.special_points[0].lambda == ended.points.back().lambda);
  // Without it the branch goes on through both.
  options.bounds.end_at_grazing = false;
  const Branch on = Continue(problem, Vec({0.0}), 0.0, options);
  CHECK(on.status == BranchStatus::kReachedLambdaBound);
  CHECK(on.Count(SpecialPointType::kGrazing) == 1);
  CHECK(on.Count(SpecialPointType::kTestFunction) == 1);
  CHECK(on.points.back().lambda == Approx(3.0));
}

TEST_CASE("state bounds and the step limit end the branch and say why", "[continuation][bounds]") {
  LambdaProblem problem = Cubic(true);
  SECTION("state box") {
    ContinuationOptions options;
    options.bounds.state_upper = Vec({1.0});
    const Branch branch = Continue(problem, Vec({1.3}), -1.0, options);
    CHECK(branch.status == BranchStatus::kReachedStateBound);
    CHECK(branch.message.find("state_upper(0)") != std::string::npos);
    for (const BranchPoint& p : branch.points) CHECK(p.u(0) > 1.0);
  }
  SECTION("max steps") {
    ContinuationOptions options;
    options.bounds.max_steps = 7;
    const Branch branch = Continue(problem, Vec({1.3}), -1.0, options);
    CHECK(branch.status == BranchStatus::kMaxSteps);
    CHECK(branch.points.size() == 8u);
  }
  SECTION("a start outside the λ bounds is a caller mistake") {
    ContinuationOptions options;
    options.bounds.lambda_max = -2.0;
    options.bounds.lambda_min = -3.0;
    CHECK_THROWS_AS(Continue(problem, Vec({1.3}), -1.0, options), std::invalid_argument);
  }
  SECTION("a start that cannot be corrected is a status") {
    // x² + 1 + λ² = 0 has no real solution.
    LambdaProblem none(1, [](const Vector& u, double l, double, Vector& F) {
      F(0) = u(0) * u(0) + 1.0 + l * l;
    });
    const Branch branch = Continue(none, Vec({0.3}), 0.0);
    CHECK(branch.status == BranchStatus::kStartFailed);
    CHECK(IsFailure(branch.status));
    CHECK_FALSE(branch.message.empty());
  }
}

TEST_CASE("invalid options are rejected with the field, the value and the rule",
          "[continuation][options]") {
  ContinuationOptions options;
  CHECK_NOTHROW(Validate(options));
  options.step.min = 0.5;  // above step.max = 0.1
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("step.max") && Catch::Contains("0.1"));
  options = ContinuationOptions();
  options.direction = 0;
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("direction"));
  options = ContinuationOptions();
  options.bounds.lambda_max = options.bounds.lambda_min = 1.0;
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("bounds.lambda_max"));
  options = ContinuationOptions();
  options.step.max_angle = 0.01;
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("step.max_angle"));
  LambdaProblem problem = Cubic(true);
  options = ContinuationOptions();
  options.corrector.max_iterations = 0;
  CHECK_THROWS_WITH(Continuation(problem, options),
                    Catch::Contains("corrector.max_iterations"));
}

TEST_CASE("the branch flattens into columns and reports in one line", "[continuation][branch]") {
  LambdaProblem problem = Cubic(true);
  problem.SetMeasures({"x_squared"}, [](const Vector& u, double) { return Vec({u(0) * u(0)}); });
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  const Branch branch = Continue(problem, Vec({1.3}), -1.0, options);
  const Vector lambda = branch.Lambda();
  const Vector x = branch.StateComponent(0);
  const Vector x2 = branch.Measure("x_squared");
  REQUIRE(lambda.size() == branch.Size());
  for (Index i = 0; i < lambda.size(); ++i) {
    CHECK(x2(i) == Approx(x(i) * x(i)));
    CHECK(std::abs(x(i) * x(i) * x(i) - x(i) + lambda(i)) <= 1e-10);
  }
  CHECK(std::isnan(branch.StateComponent(1)(0)));
  CHECK_THROWS_WITH(branch.Measure("nope"), Catch::Contains("x_squared"));
  CHECK(branch.MeasureIndex("x_squared") == 0);
  CHECK_THROWS_WITH(branch.MeasureIndex("nope"), Catch::Contains("x_squared"));
  CHECK(branch.Arclength()(branch.Size() - 1) > 0.0);
  // Special points carry the measures too, for the special-point table.
  for (const SpecialPoint& sp : branch.special_points) {
    REQUIRE(sp.measures.size() == 1);
    CHECK(sp.measures(0) == Approx(sp.u(0) * sp.u(0)));
    CHECK(sp.Name() == "fold");
  }
  const std::string report = branch.BriefReport();
  CHECK(report.find("2 folds") != std::string::npos);
  CHECK(report.find("λ ∈ [-1, 1]") != std::string::npos);
  CHECK(report.find("reached λ max") != std::string::npos);
  CHECK(branch.options.bounds.lambda_max == 1.0);
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

TEST_CASE("two runs from one start join into one branch ordered along it",
          "[continuation][branch]") {
  // From x = 0 on x³ − x + λ = 0 (middle sheet) both ways: each run meets one fold.
  LambdaProblem problem = Cubic(true);
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  options.direction = -1;
  const Branch backward = Continue(problem, Vec({0.0}), 0.0, options);
  options.direction = +1;
  const Branch forward = Continue(problem, Vec({0.0}), 0.0, options);
  const Branch joined = JoinAtStart(backward, forward);
  INFO(joined.BriefReport());
  CHECK(joined.Size() == backward.Size() + forward.Size() - 1);
  REQUIRE(joined.Count(SpecialPointType::kFold) == 2);
  // Along the joined branch x increases monotonically (x = 0 is passed once), arclength grows and
  // consecutive tangents agree in orientation.
  for (Index i = 1; i < joined.Size(); ++i) {
    CHECK(joined.points[i].u(0) > joined.points[i - 1].u(0));
    CHECK(joined.points[i].arclength > joined.points[i - 1].arclength);
    CHECK(joined.points[i].tangent.dot(joined.points[i - 1].tangent) > 0.0);
    CHECK(joined.points[i].step == Approx(joined.points[i].arclength -
                                          joined.points[i - 1].arclength));
  }
  // Each fold lies between the points its index names.
  for (const SpecialPoint& fold : joined.special_points) {
    const double x = fold.u(0);
    CHECK(joined.points[fold.index].u(0) <= x);
    CHECK(joined.points[fold.index + 1].u(0) >= x);
  }
  CHECK(joined.special_points[0].u(0) < joined.special_points[1].u(0));
  CHECK(joined.status == BranchStatus::kReachedLambdaBound);
  CHECK(joined.message.find("backward: ") == 0);
  CHECK(joined.statistics.steps == backward.statistics.steps + forward.statistics.steps);
  CHECK_THROWS_AS(JoinAtStart(Branch{}, forward), std::invalid_argument);
}

}  // namespace
}  // namespace rubcont
