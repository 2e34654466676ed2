// Branch switching on periodic orbits with a known answer: a limit cycle (the unit circle of
// ẋ = (1 − r²)x − y, ẏ = (1 − r²)y + x, period 2π) times a pitchfork ż = z(λ − z²). The orbits
// with z = 0 exist for every λ and lose stability at λ = 0 (multiplier e^{2πλ} through +1); the
// new orbits have z = ±√λ and the multiplier e^{−4πλ}. The mirror z → −z maps one onto the other.
// With ż = z(1 − λ² − z²) instead ("bubble"), the new orbits z² = 1 − λ² join pitchforks at λ = ±1.
#include "shooting/orbit_branches.h"
#include "solvers/constants.h"
#include "tests/shooting/moebius_band.h"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

class CycleTimesPitchfork : public OdeSystem {
 public:
  explicit CycleTimesPitchfork(bool declare_mirror, bool bubble = false)
      : declare_mirror_(declare_mirror), bubble_(bubble) {}
  Index Dimension() const override { return 3; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const double g = 1.0 - x(0) * x(0) - x(1) * x(1);
    f << g * x(0) - x(1), g * x(1) + x(0), x(2) * (Growth() - x(2) * x(2));
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double g = 1.0 - x(0) * x(0) - x(1) * x(1);
    J << g - 2 * x(0) * x(0), -1 - 2 * x(0) * x(1), 0,  //
        1 - 2 * x(0) * x(1), g - 2 * x(1) * x(1), 0,    //
        0, 0, Growth() - 3 * x(2) * x(2);
  }
  double Parameter() const override { return lambda_; }
  void SetParameter(double lambda) override { lambda_ = lambda; }
  void DfDparameter(double, ConstVectorRef x, VectorRef df) override {
    df << 0, 0, x(2) * (bubble_ ? -2 * lambda_ : 1.0);
  }
  bool HasMirrorSymmetry() const override { return declare_mirror_; }
  void Mirror(VectorRef x) const override { x(2) = -x(2); }

 private:
  double Growth() const { return bubble_ ? 1 - lambda_ * lambda_ : lambda_; }
  bool declare_mirror_;
  bool bubble_;
  double lambda_ = -0.5;
};

PeriodicOrbitBranchOptions BandOptions() { return MoebiusBandOptions(); }

PeriodicOrbitBranch SymmetricFamily(CycleTimesPitchfork& system) {
  OrbitStart start;
  start.x0 = Eigen::Vector3d(1.0, 0.0, 0.0);
  start.period = kTwoPi;
  start.lambda = -0.5;
  start.valid = true;
  return ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, BandOptions());
}

TEST_CASE("cycle times pitchfork: the z = 0 orbits' branch point at lambda = 0 breaks the mirror "
          "symmetry, the new orbits have z^2 = lambda",
          "[shooting][branch_point]") {
  CycleTimesPitchfork system(true);
  const PeriodicOrbitBranch family = SymmetricFamily(system);
  INFO(family.branch.BriefReport());
  REQUIRE(family.branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(family.branch.Count(SpecialPointType::kBranchPoint) == 1);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kBranchPoint) ++k;
  CHECK(family.branch.special_points[k].lambda == Approx(0.0).epsilon(0).margin(1e-6));

  const OrbitBranchSwitch change = ContinueOrbitsFromBranchPoint(system, family, k, BandOptions());
  INFO(change.message);
  REQUIRE(change.ok);
  CHECK(change.mirror_symmetric_orbit);
  CHECK(change.breaks_mirror_symmetry);
  CHECK(change.direction_odd_part > 0.999);
  // Mirror images: one side followed.
  REQUIRE(change.branches.size() == 1);
  const Branch& other = change.branches[0].branch;
  INFO(other.BriefReport() << " — " << other.message);
  REQUIRE(other.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(other.Size() > 3);
  for (std::size_t i = 1; i < other.points.size(); ++i) {
    const BranchPoint& p = other.points[i];
    CAPTURE(p.lambda);
    const double z = p.u(2);  // z is constant along the orbit
    CHECK(z * z == Approx(p.lambda).epsilon(0).margin(1e-8));
    CHECK(p.u.size() == 2 * 3 + 1);
    CHECK(p.u(6) == Approx(kTwoPi).epsilon(1e-8));  // the period
    // The nontrivial multipliers: e^{−4πλ} (the pitchfork) and e^{−4π} (the cycle's radius).
    REQUIRE(p.spectrum.values.size() == 2);
    const double largest = std::max(std::abs(p.spectrum.values(0)), std::abs(p.spectrum.values(1)));
    CHECK(largest == Approx(std::exp(-4 * kPi * p.lambda)).epsilon(1e-6));
    CHECK(p.num_unstable == 0);
  }
  CHECK(other.points.back().lambda == Approx(0.5).epsilon(0).margin(1e-9));
}

TEST_CASE("cycle times pitchfork without a declared mirror: both sides of the new branch are "
          "followed, z > 0 and z < 0",
          "[shooting][branch_point]") {
  CycleTimesPitchfork system(false);
  const PeriodicOrbitBranch family = SymmetricFamily(system);
  REQUIRE(family.branch.Count(SpecialPointType::kBranchPoint) == 1);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kBranchPoint) ++k;
  const OrbitBranchSwitch change = ContinueOrbitsFromBranchPoint(system, family, k, BandOptions());
  REQUIRE(change.ok);
  CHECK_FALSE(change.breaks_mirror_symmetry);
  REQUIRE(change.branches.size() == 2);
  double end_z[2];
  for (std::size_t side = 0; side < 2; ++side) {
    const Branch& other = change.branches[side].branch;
    INFO(other.BriefReport() << " — " << other.message);
    REQUIRE(other.status == BranchStatus::kReachedLambdaBound);
    end_z[side] = other.points.back().u(2);
  }
  CHECK(end_z[0] * end_z[1] == Approx(-0.5).epsilon(1e-8));
  CHECK(std::abs(end_z[0]) == Approx(std::sqrt(0.5)).epsilon(1e-8));
}

TEST_CASE("cycle times bubble: the asymmetric orbits from lambda = -1 end where they rejoin "
          "the symmetric ones, at lambda = +1",
          "[shooting][branch_point]") {
  CycleTimesPitchfork system(true, true);
  PeriodicOrbitBranchOptions options = BandOptions();
  options.lambda_min = -1.5;
  options.lambda_max = 1.5;
  OrbitStart start;
  start.x0 = Eigen::Vector3d(1.0, 0.0, 0.0);
  start.period = kTwoPi;
  start.lambda = -1.5;
  start.valid = true;
  system.SetParameter(-1.5);
  const PeriodicOrbitBranch family = ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, options);
  INFO(family.branch.BriefReport());
  REQUIRE(family.branch.Count(SpecialPointType::kBranchPoint) == 2);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kBranchPoint) ++k;
  CHECK(family.branch.special_points[k].lambda == Approx(-1.0).epsilon(0).margin(1e-6));
  const OrbitBranchSwitch change = ContinueOrbitsFromBranchPoint(system, family, k, options);
  REQUIRE(change.ok);
  CHECK(change.breaks_mirror_symmetry);
  REQUIRE(change.branches.size() == 1);
  const Branch& bubble = change.branches[0].branch;
  INFO(bubble.message);
  CHECK(bubble.status == BranchStatus::kStoppedByCaller);
  CHECK_THAT(bubble.message, Catch::Matchers::Contains("rejoined the symmetric orbits"));
  // It stops at the far pitchfork (the last two points on either side of z = 0, both within
  // 1e-3 of λ = 1), not at the near one; every point before lies on z² = 1 − λ².
  CHECK(change.RejoinedNear(1.0));
  CHECK_FALSE(change.RejoinedNear(-1.0));
  CHECK(std::abs(change.rejoined_between[1] - 1.0) <= 1e-3);
  for (std::size_t i = 1; i + 1 < bubble.points.size(); ++i) {
    const BranchPoint& p = bubble.points[i];
    CAPTURE(p.lambda);
    CHECK(p.u(2) * p.u(2) == Approx(1 - p.lambda * p.lambda).epsilon(0).margin(1e-8));
  }
}

TEST_CASE("ContinueOrbitsFromBranchPoint refuses a special point that is not a branch point",
          "[shooting][branch_point]") {
  CycleTimesPitchfork system(true);
  const PeriodicOrbitBranch family = SymmetricFamily(system);
  CHECK_THROWS_AS(ContinueOrbitsFromBranchPoint(system, family, family.branch.special_points.size(),
                                                BandOptions()),
                  std::invalid_argument);
}

// The cycle with a Moebius band and its start: tests/shooting/moebius_band.h.

TEST_CASE("cycle with a Moebius band: the period doubling at lambda = 0 starts the doubled "
          "orbits, a^2 = lambda, period 4 pi, multipliers in closed form",
          "[shooting][period_doubling]") {
  CycleWithMoebiusBand system;
  const OrbitStart start = MoebiusCycleStart();
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, BandOptions());
  INFO(family.branch.BriefReport());
  REQUIRE(family.branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(family.branch.Count(SpecialPointType::kPeriodDoubling) == 1);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kPeriodDoubling) ++k;
  CHECK(family.branch.special_points[k].lambda == Approx(0.0).epsilon(0).margin(1e-8));
  CHECK(family.branch.Count(SpecialPointType::kBranchPoint) == 0);

  const OrbitPeriodDoubling doubling = ContinueOrbitsFromPeriodDoubling(system, family, k, BandOptions());
  INFO(doubling.message);
  REQUIRE(doubling.ok);
  CHECK(doubling.multiplier == Approx(-1.0).epsilon(0).margin(1e-6));
  const Branch& doubled = doubling.branch.branch;
  INFO(doubled.BriefReport() << " — " << doubled.message);
  REQUIRE(doubled.status == BranchStatus::kReachedLambdaBound);
  CHECK(doubling.branch.segments == 4);
  REQUIRE(doubled.Size() > 3);
  for (const BranchPoint& p : doubled.points) {
    CAPTURE(p.lambda);
    CHECK(p.lambda >= -1e-12);  // supercritical: the doubled orbits exist for λ > 0
    REQUIRE(p.u.size() == 4 * 4 + 1);
    CHECK(p.u(16) == Approx(4 * kPi).epsilon(1e-8));  // the period
    // |w| = a at every segment start.
    for (int i = 0; i < 4; ++i) {
      CHECK(std::hypot(p.u(4 * i + 2), p.u(4 * i + 3)) ==
            Approx(std::sqrt(std::max(p.lambda, 0.0))).epsilon(0).margin(1e-7));
    }
    if (p.lambda < 1e-3) continue;
    REQUIRE(p.spectrum.values.size() == 3);
    CHECK(std::abs(p.spectrum.values(0)) == Approx(std::exp(-8 * kPi * p.lambda)).epsilon(1e-6));
    CHECK(p.num_unstable == 0);
  }
  CHECK(doubled.points.back().lambda == Approx(0.5).epsilon(0).margin(1e-9));

  CHECK_THROWS_WITH(ContinueOrbitsFromPeriodDoubling(system, family, k, BandOptions(), 0.0),
                    Catch::Contains("amplitude = 0: must be positive"));
  std::size_t not_doubling = family.branch.special_points.size();
  CHECK_THROWS_AS(ContinueOrbitsFromPeriodDoubling(system, family, not_doubling, BandOptions()),
                  std::invalid_argument);
}

TEST_CASE("stop_at_grazing ends the doubled orbits at their first located grazing as well",
          "[shooting][period_doubling][grazing]") {
  CycleWithMoebiusBand system;
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, MoebiusCycleStart(), BandOptions());
  REQUIRE(family.branch.Count(SpecialPointType::kPeriodDoubling) == 1);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kPeriodDoubling) ++k;
  // |w|² = a² = λ on the doubled orbits: they touch |w| = 0.3 at λ = 0.09.
  PeriodicOrbitBranchOptions options = BandOptions();
  options.test_functions = {Grazing([](ConstVectorRef x) { return x(2) * x(2) + x(3) * x(3) - 0.09; },
                                    GrazingSide::kTouchdown, "touchdown")};
  for (const bool stop : {true, false}) {
    CAPTURE(stop);
    options.stop_at_grazing = stop;
    const OrbitPeriodDoubling doubling = ContinueOrbitsFromPeriodDoubling(system, family, k, options);
    REQUIRE(doubling.ok);
    const Branch& doubled = doubling.branch.branch;
    INFO(doubled.BriefReport() << " — " << doubled.message);
    REQUIRE(doubled.Count(SpecialPointType::kGrazing) == 1);
    if (!stop) {
      CHECK(doubled.status == BranchStatus::kReachedLambdaBound);
      continue;
    }
    REQUIRE(doubled.status == BranchStatus::kGrazing);
    const SpecialPoint& grazing = doubled.special_points.back();
    CHECK(grazing.lambda == Approx(0.09).epsilon(0).margin(1e-6));
    CHECK(doubled.points.back().lambda < 0.5);
  }
}

// The same flow, defined only within 0.05 of the cycle (|w| ≤ 0.05): like the stiff contact's
// flow, which the integrator does not survive far inside the stator. A doubled start at amplitude
// 0.1 cannot be corrected; the retry at 0.01 starts the same doubled orbits.
class CycleWithMoebiusBandNearby : public CycleWithMoebiusBand {
 public:
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    CycleWithMoebiusBand::Rhs(t, x, f);
    if (std::hypot(x(2), x(3)) > 0.05) f.setConstant(kNaN);
  }
};

TEST_CASE("a doubled start the flow cannot take is retried closer to the orbit",
          "[shooting][period_doubling]") {
  CycleWithMoebiusBandNearby system;
  const OrbitStart start = MoebiusCycleStart();
  PeriodicOrbitBranchOptions options = BandOptions();
  options.lambda_max = 1e-3;  // the doubled orbits' a = √λ stay within 0.032 of the cycle
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, options);
  INFO(family.branch.BriefReport());
  REQUIRE(family.branch.Count(SpecialPointType::kPeriodDoubling) == 1);
  std::size_t k = 0;
  while (family.branch.special_points[k].type != SpecialPointType::kPeriodDoubling) ++k;

  const OrbitPeriodDoubling doubling =
      ContinueOrbitsFromPeriodDoubling(system, family, k, options, 0.1);
  INFO(doubling.message);
  REQUIRE(doubling.ok);
  CHECK(doubling.amplitude == Approx(0.01));
  CHECK_THAT(doubling.message, Catch::Contains("the start at amplitude 0.1 failed") &&
                                   Catch::Contains("amplitude 0.01 used"));
  const Branch& doubled = doubling.branch.branch;
  INFO(doubled.BriefReport() << " — " << doubled.message);
  REQUIRE(doubled.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(doubled.Size() > 3);
  for (const BranchPoint& p : doubled.points) {
    for (int i = 0; i < 4; ++i) {
      CHECK(std::hypot(p.u(4 * i + 2), p.u(4 * i + 3)) ==
            Approx(std::sqrt(std::max(p.lambda, 0.0))).epsilon(0).margin(1e-7));
    }
  }

  // Three starts that all fail: the family says so (no point), with each failure named.
  const OrbitPeriodDoubling far =
      ContinueOrbitsFromPeriodDoubling(system, family, k, options, 10.0);
  CHECK(far.branch.branch.status == BranchStatus::kStartFailed);
  CHECK(far.branch.branch.Size() == 0);
  CHECK_THAT(far.message, Catch::Contains("amplitude 10 failed") &&
                              Catch::Contains("amplitude 1 failed"));
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// An isola of limit cycles: ṙ = r g, θ̇ = 1 + r² with g = 1 − (r² − 2)² − λ². The cycles r² = 2 ±
// √(1 − λ²) form one closed curve in (λ, r²) with folds at λ = ±1 (r² = 2); the outer ones are
// stable (dṙ/dr = −4r²(r² − 2) on a cycle), the inner ones not. Their period 2π/(1 + r²) changes
// round the curve, so the phase reference moves with the family.
class IsolaOscillator : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const double r2 = x(0) * x(0) + x(1) * x(1), g = G(r2), w = 1.0 + r2;
    f << g * x(0) - w * x(1), g * x(1) + w * x(0);
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double, ConstVectorRef x, MatrixRef J) override {
    const double r2 = x(0) * x(0) + x(1) * x(1), g = G(r2), w = 1.0 + r2;
    const double gx = -4 * x(0) * (r2 - 2), gy = -4 * x(1) * (r2 - 2);
    J << g + x(0) * gx - 2 * x(1) * x(0), x(0) * gy - w - 2 * x(1) * x(1),  //
        x(1) * gx + w + 2 * x(0) * x(0), g + x(1) * gy + 2 * x(0) * x(1);
  }
  double Parameter() const override { return lambda_; }
  void SetParameter(double lambda) override { lambda_ = lambda; }
  void DfDparameter(double, ConstVectorRef x, VectorRef df) override {
    df << -2 * lambda_ * x(0), -2 * lambda_ * x(1);
  }

 private:
  double G(double r2) const { return 1.0 - (r2 - 2) * (r2 - 2) - lambda_ * lambda_; }
  double lambda_ = 0.0;
};

TEST_CASE("an isola of limit cycles is followed round once: stop_round_closed_curve", "[shooting]") {
  IsolaOscillator system;
  OrbitStart start;
  start.x0 = Eigen::Vector2d(std::sqrt(3.0), 0.0);  // the outer cycle at λ = 0
  start.period = kTwoPi / 4.0;
  start.lambda = 0.0;
  start.valid = true;
  PeriodicOrbitBranchOptions options = BandOptions();  // the same shooting
  options.lambda_min = -2.0;
  options.lambda_max = 2.0;
  options.continuation.step.max = 0.1;
  options.continuation.bounds.max_steps = 2000;
  options.stop_round_closed_curve = true;
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, options);
  const Branch& b = family.branch;
  INFO(b.BriefReport() << " — " << b.message);
  // Once round: the two folds, each once, and no run the other way.
  const std::vector<double> folds = DistinctFolds(b);
  REQUIRE(folds.size() == 2);
  CHECK(folds[0] == Approx(-1.0).epsilon(0).margin(1e-6));
  CHECK(folds[1] == Approx(1.0).epsilon(0).margin(1e-6));
  CHECK(b.Count(SpecialPointType::kFold) == 2);
  // Here the engine's own closure test ends the first run (the circular cycles come back with
  // their segment starts); on C(a)'s 1:3 orbits it did not, and the folds' test does
  // (bench/locked_whip_bench.cpp).
  CHECK(b.status == BranchStatus::kClosed);
  CHECK(b.points.size() < 2000);
  for (const BranchPoint& p : b.points) {
    const double r2 = p.u(0) * p.u(0) + p.u(1) * p.u(1);
    CAPTURE(p.lambda, r2);
    CHECK((r2 - 2) * (r2 - 2) + p.lambda * p.lambda == Approx(1.0).epsilon(0).margin(1e-7));
    CHECK(p.u(4) == Approx(kTwoPi / (1 + r2)).epsilon(1e-8));  // the period
    if (std::abs(r2 - 2) > 1e-2) CHECK(p.StableFlag() == (r2 > 2 ? 1 : 0));
  }
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

TEST_CASE("RoundClosedCurve: two distinct folds located and a step back across the start",
          "[shooting]") {
  Branch b;
  for (const double lambda : {0.0, -0.5, -0.9, -0.5, 0.5, 0.9, 0.5, 0.1}) {
    BranchPoint p;
    p.lambda = lambda;
    b.points.push_back(p);
  }
  auto fold = [](double lambda) {
    SpecialPoint p;
    p.type = SpecialPointType::kFold;
    p.lambda = lambda;
    p.converged = true;
    return p;
  };
  b.special_points = {fold(-1.0), fold(1.0), fold(1.0 + 1e-12)};  // the last met again
  CHECK(DistinctFolds(b) == std::vector<double>{-1.0, 1.0});
  CHECK_FALSE(RoundClosedCurve(b, 0.0));  // not back across 0 yet
  BranchPoint across;
  across.lambda = -0.1;
  b.points.push_back(across);
  CHECK(RoundClosedCurve(b, 0.0));
  b.special_points.pop_back();
  b.special_points.back().converged = false;  // a fold not located is no fold here
  CHECK_FALSE(RoundClosedCurve(b, 0.0));
}

}  // namespace
}  // namespace rubcont
