// Fold location by Ipopt (continuation/fold_optimization.h) on the rub model's rotating waves,
// cross-checked against the continuation engine's minimally augmented fold location.
#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "continuation/fold_optimization.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

TEST_CASE("Ipopt and the engine locate the folds of the tanh-friction whirl branches to 1e-8",
          "[design][fold_optimization]") {
  // Case A(a) with regularized friction (ε = 1e-3 m/s): the rolling whirl's Mode 1 branch that
  // starts beyond the whip turns back in speed near 66.5 rpm. The knee test functions are off so
  // that the turning points are located as folds (otherwise the knee, at the same point, is kept).
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  const RubStructure structure = TwoPointStructure(params);
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(20.0);
  options.search.speed_max = RpmToRadPerSecond(120.0);
  options.search.precession_max = HzToRadPerSecond(200.0);
  options.continuation.detect.test_functions = false;
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options);
  RotatingWaveProblem problem(structure, FrictionLawKind::kTanh);
  int checked = 0;
  double worst = 0.0;
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& fold : b.branch.special_points) {
      if (fold.type != SpecialPointType::kFold || !fold.converged) continue;
      // A fold at a branch point (the one-contact whirl turning where it meets the Mode 2 whirl,
      // 52.33 rpm: a pitchfork) is no regular fold: F_u and [F_u F_λ] are both singular there.
      const bool at_branch_point =
          std::any_of(b.branch.special_points.begin(), b.branch.special_points.end(),
                      [&](const SpecialPoint& p) {
                        return p.type == SpecialPointType::kBranchPoint &&
                               std::abs(p.lambda - fold.lambda) <= 1e-6 * fold.lambda;
                      });
      if (at_branch_point) continue;
      // Start from the stored branch point before the fold, a step away from it.
      const BranchPoint& before = b.branch.points[fold.index];
      problem.SetModes(ModesAt(b.branch, fold, problem.Contacts()));  // e.g. one contact free
      problem.SetPhaseReference(before.u);
      FoldOptimizationOptions nlp;
      nlp.sense = before.lambda < fold.lambda ? +1 : -1;
      const FoldOptimizationResult r = LocateFoldByOptimization(problem, before.u, before.lambda, nlp);
      INFO(b.name << ": engine fold at " << fold.lambda << " rad/s; Ipopt: " << r.message);
      REQUIRE(r.Solved());
      const double difference = std::abs(r.lambda - fold.lambda) / fold.lambda;
      worst = std::max(worst, difference);
      CHECK(difference <= 1e-8);
      CHECK(problem.Precession(r.u) == Approx(problem.Precession(fold.u)).epsilon(1e-7));
      ++checked;
    }
  }
  INFO("largest relative difference " << worst);
  CHECK(checked >= 1);
}

}  // namespace
}  // namespace rubcont

#include "studies/hysteresis_map.h"

namespace rubcont {
namespace {

TEST_CASE("along a fold curve in friction (tanh law) Ipopt finds the same fold at each friction",
          "[design][fold_optimization][map]") {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  HysteresisMapOptions options;
  options.parameter = DesignParameter::kFriction;
  options.eta_min = 0.45;
  options.eta_max = 0.55;
  options.eta_points = 2;
  options.speed_points = 11;
  options.branches.search.speed_min = RpmToRadPerSecond(20.0);
  options.branches.search.speed_max = RpmToRadPerSecond(120.0);
  options.branches.search.precession_max = HzToRadPerSecond(200.0);
  const HysteresisMap map = ComputeHysteresisMap(params, options);
  const MapCurve* fold_curve = nullptr;
  for (const MapCurve& c : map.curves) {
    if (c.kind == "fold" && c.pattern == "mode1" && c.curve.Size() >= 5) fold_curve = &c;
  }
  REQUIRE(fold_curve != nullptr);
  REQUIRE(std::abs(fold_curve->fold_sense) == 1);
  RotatingWaveDesignProblem problem(params, DesignParameter::kFriction);
  const Index n = problem.Dimension();
  int checked = 0;
  for (Index i : {Index(1), fold_curve->curve.Size() / 2, fold_curve->curve.Size() - 2}) {
    const BranchPoint& p = fold_curve->curve.points[i];
    problem.SetSecondParameter(p.lambda);
    const Vector u = p.u.head(n);
    const double omega = p.u(n);
    problem.SetPhaseReference(u);
    // Start off the fold, on the branch: solve F(u, ω_s) = 0 a little inside the fold
    // (ω_s = ω (1 ∓ 1e-3), on the side where the branch exists).
    FoldOptimizationOptions nlp;
    nlp.sense = fold_curve->fold_sense;
    const double start_speed = omega * (1.0 - 1e-3 * nlp.sense);
    Vector start = u;
    const auto solved = problem.SolveConsistent(start, start_speed);
    REQUIRE(solved.newton.Converged());
    CHECK((start - u).norm() > 0.0);
    const FoldOptimizationResult r = LocateFoldByOptimization(problem, start, start_speed, nlp);
    INFO("μ = " << p.lambda << ": fold curve " << omega << " rad/s, Ipopt " << r.message);
    REQUIRE(r.Solved());
    CHECK(std::abs(r.lambda - omega) <= 1e-8 * omega);
    ++checked;
  }
  CHECK(checked == 3);
}

}  // namespace
}  // namespace rubcont
