#include "waves/rotating_wave_branches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/jeffcott.h"
#include "models/units.h"
#include "waves/rotating_wave.h"

namespace rubcont {
namespace {

RotatingWaveBranchOptions ThesisRange() {
  RotatingWaveBranchOptions options;
  options.search.speed_min = 20.0 * kRadPerSecondPerRpm;
  options.search.speed_max = 260.0 * kRadPerSecondPerRpm;
  options.search.precession_max = kTwoPi * 200.0;
  return options;
}

double Measure(const Branch& branch, const SpecialPoint& point, const std::string& name) {
  return point.measures(branch.MeasureIndex(name));
}

// The first located event on any branch whose label contains `label`, near `hz` (10 % window).
struct FoundEvent {
  const RotatingWaveBranch* branch = nullptr;
  const SpecialPoint* point = nullptr;
};
FoundEvent FindEvent(const std::vector<RotatingWaveBranch>& branches, const std::string& label,
                     double hz) {
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kEvent || p.label.find(label) == std::string::npos) continue;
      if (std::abs(Measure(b.branch, p, "precession_hz") - hz) < 0.1 * hz) return {&b, &p};
    }
  }
  return {};
}

double MuCrossingHz(const AnalyticCurve& curve, int direction, double near_hz) {
  double best = 0.0;
  for (const Transition& t : curve.transitions) {
    if (t.type == TransitionType::kMuCrossing && t.direction == direction && t.contact == 0 &&
        std::abs(t.precession_hz - near_hz) < std::abs(best - near_hz)) {
      best = t.precession_hz;
    }
  }
  return best;
}

TEST_CASE("case A(a): whirl to whip where the closed form’s μ_req reaches μ, to 1e-9",
          "[branches]") {
  const TwoPointParams params = ThesisCaseAa();
  const auto branches =
      ComputeRotatingWaveBranches(TwoPointStructure(params), FrictionLawKind::kExact, ThesisRange());
  const AnalyticResult analytic = ComputeAnalytic(params, {1.0, 200.0, 4000});
  // Mode 1: rolling → slipping at the rising crossing near 84.5 Hz; Mode 2 near 133.2 Hz.
  for (const auto& [curve, near_hz] : {std::pair{&analytic.mode1, 84.5}, {&analytic.mode2, 133.2}}) {
    const double crossing_hz = MuCrossingHz(*curve, +1, near_hz);
    const FoundEvent event = FindEvent(branches, "stick to slip+", crossing_hz);
    INFO(ToString(curve->mode) << ": closed-form crossing " << crossing_hz << " Hz");
    REQUIRE(event.point != nullptr);
    const double hz = Measure(event.branch->branch, *event.point, "precession_hz");
    CHECK(event.point->converged);
    CHECK(std::abs(hz - crossing_hz) <= 1e-9 * crossing_hz);  // measured ~1e-13
    // Rolling at RCI 100: the speed is Ω/RCI (to the compliance δ/C ~ 1e-5).
    CHECK(event.point->lambda == Approx(kTwoPi * crossing_hz / params.Rci(0)).epsilon(1e-4));
  }
  // The symmetric rotor's two contacts reach μ together: one event switches both, and the Mode 1
  // whirl continues as the whip at the crossing frequency up to the end of the range.
  const FoundEvent mode1 = FindEvent(branches, "stick to slip+", 84.5);
  const Branch& branch = mode1.branch->branch;
  const Index after = mode1.point->index + 2;  // the switch point, stored again on the new piece
  REQUIRE(after < branch.Size());
  CHECK(branch.points[after].piece == "left:slip+ right:slip+");
  CHECK(branch.points.back().lambda == Approx(260.0 * kRadPerSecondPerRpm));
  CHECK(branch.points.back().measures(0) == Approx(branch.points[after].measures(0)).epsilon(1e-6));
  // Whirl stable before the switch (compliance drift below the tolerance); the circular whip
  // unstable (growth ~262 s⁻¹, the thesis's whip is not a circular orbit).
  CHECK(branch.points[mode1.point->index].num_unstable == 0);
  CHECK(branch.points[after].num_unstable > 0);
  CHECK(branch.points[after].spectrum.values(0).real() > 100.0);
  // Each start lies on one branch: no two branches trace the same rolling whirl at 30 rpm.
  int mode1_whirls_at_30 = 0;
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    const auto& p = b.branch.points;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
      const double w = 30.0 * kRadPerSecondPerRpm;
      if (p[i].piece == "left:stick right:stick" && p[i + 1].piece == p[i].piece &&
          (p[i].lambda - w) * (p[i + 1].lambda - w) <= 0.0) {
        ++mode1_whirls_at_30;
      }
    }
  }
  CHECK(mode1_whirls_at_30 == 1);
  for (const RotatingWaveBranch& b : branches) {
    INFO(b.name << ": " << b.branch.BriefReport());
    CHECK_FALSE(IsFailure(b.branch.status));
  }
}

TEST_CASE("case A(a): the four branch points of the Mode 1 and Mode 2 families are located by "
          "Newton, each a point where DF loses rank", "[branches]") {
  const TwoPointParams params = ThesisCaseAa();
  const RubStructure structure = TwoPointStructure(params);
  const auto branches =
      ComputeRotatingWaveBranches(structure, FrictionLawKind::kExact, ThesisRange());
  int located = 0;
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kBranchPoint) continue;
      CAPTURE(b.name, RadPerSecondToRpm(p.lambda), p.note);
      CHECK(p.converged);
      CHECK(p.note.empty());
      CHECK(p.last_correction <= 1e-10);  // the Newton correction, scaled
      ++located;
    }
  }
  // 91.364 and 76.578 rpm on the Mode 1 whip, 76.577 on the Mode 2 whirl, 91.363 on the Mode 2
  // whip (results/thesis_A_a/summary.txt).
  CHECK(located == 4);
}

TEST_CASE("a slipping rotating wave's spectrum does not depend on the running speed",
          "[branches]") {
  // With exact Coulomb slip, F = μN whatever V: the slipping orbit and its linearization do not
  // involve ω, so along a whip piece the spectrum is constant. The whip of one contact has a
  // close pair near 675.8 rad/s (Re 0 and −4.57 s⁻¹); without balancing the eigenvalue solver
  // scattered it by ±2.5 s⁻¹ and the engine reported a dozen spurious Hopf points.
  const auto branches = ComputeRotatingWaveBranches(TwoPointStructure(ThesisCaseAa()),
                                                    FrictionLawKind::kExact, ThesisRange());
  int pieces = 0;
  for (const RotatingWaveBranch& b : branches) {
    const auto& p = b.branch.points;
    for (std::size_t i = 1; i < p.size(); ++i) {
      if (p[i].piece != p[i - 1].piece || p[i].piece.find("stick") != std::string::npos) continue;
      REQUIRE(p[i].spectrum.values.size() == p[i - 1].spectrum.values.size());
      double change = 0.0;
      for (Index k = 0; k < p[i].spectrum.values.size(); ++k) {
        change = std::max(change, std::abs(p[i].spectrum.values(k).real() -
                                           p[i - 1].spectrum.values(k).real()));
      }
      INFO(b.name << " " << p[i].piece << " at " << p[i].lambda / kRadPerSecondPerRpm << " rpm");
      CHECK(change < 1e-3);
      ++pieces;
    }
    if (b.branch.points.front().piece.find("stick") == std::string::npos &&
        b.branch.points.back().piece.find("stick") == std::string::npos) {
      CHECK(b.branch.Count(SpecialPointType::kHopf) == 0);
    }
  }
  CHECK(pieces > 50);
}

TEST_CASE("case A(b), unequal RCI: contact loss is located where the penetration vanishes",
          "[branches]") {
  TwoPointParams params = ThesisCaseAa();
  params.clearance = {3.81e-4, 3.048e-4};  // RCI 100 / 125
  const auto branches =
      ComputeRotatingWaveBranches(TwoPointStructure(params), FrictionLawKind::kExact, ThesisRange());
  int losses = 0;
  for (const RotatingWaveBranch& b : branches) {
    INFO(b.name << ": " << b.branch.BriefReport());
    CHECK_FALSE(IsFailure(b.branch.status));
    // The step grows back after cuts (4 target Newton iterations): with the engine's default of 3
    // the Mode 1 whirl crawled at Δs = 1.25e-3 and ran out of its 1000 steps.
    CHECK(b.branch.message.find("maximum of") == std::string::npos);
    CHECK(b.branch.Size() < 600);
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kEvent || p.label.find("contact loss") == std::string::npos) {
        continue;
      }
      ++losses;
      const std::string contact = p.label.substr(0, p.label.find(' '));
      CHECK(p.converged);
      // Penetration ~1e-9 m on the branch; at the located loss it is zero to the location error.
      CHECK(std::abs(Measure(b.branch, p, "penetration_" + contact)) < 1e-15);
    }
  }
  CHECK(losses >= 1);
}

TEST_CASE("Jeffcott rotor: the whip branch meets the whirl at Black's μ crossing", "[branches]") {
  const JeffcottParams params;
  RotatingWaveBranchOptions options = ThesisRange();
  const auto branches =
      ComputeRotatingWaveBranches(JeffcottStructure(params), FrictionLawKind::kExact, options);
  const AnalyticCurve curve = ComputeJeffcottCurve(params, {1.0, 200.0, 4000});
  int matched = 0;
  for (const Transition& t : curve.transitions) {
    if (t.type != TransitionType::kMuCrossing) continue;
    const double rolling_speed = kTwoPi * t.precession_hz * params.C / params.R;
    if (rolling_speed < options.search.speed_min || rolling_speed > options.search.speed_max) {
      continue;
    }
    // Whirl → whip (μ_req rising) or whip → whirl (falling): a stick ↔ slip event either way.
    const FoundEvent event =
        FindEvent(branches, t.direction > 0 ? "stick to slip+" : "slip to stick", t.precession_hz);
    INFO("closed-form crossing " << t.precession_hz << " Hz");
    REQUIRE(event.point != nullptr);
    CHECK(std::abs(Measure(event.branch->branch, *event.point, "precession_hz") - t.precession_hz) <=
          1e-9 * t.precession_hz);
    ++matched;
  }
  CHECK(matched >= 1);
}

TEST_CASE("branch-set options are validated", "[branches]") {
  RotatingWaveBranchOptions options = ThesisRange();
  options.continuation.step.min = -1.0;
  CHECK_THROWS_WITH(ComputeRotatingWaveBranches(TwoPointStructure(ThesisCaseAa()),
                                                FrictionLawKind::kExact, options),
                    Catch::Contains("step.min"));
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// The regularized whirl → whip transition: the knee (dΩ/dω = R/2C) of the Mode 1 branch.
double KneePrecessionHz(double epsilon) {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.velocity_scale = epsilon;
  const auto branches = ComputeRotatingWaveBranches(TwoPointStructure(params),
                                                    FrictionLawKind::kTanh, ThesisRange());
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.label == "left knee" && std::abs(p.measures(0) - 84.5) < 5.0) return p.measures(0);
    }
  }
  return 0.0;
}

TEST_CASE("case A(a), tanh friction: the whirl's Hopf points at 51.68 and 51.90 rpm are "
          "supercritical, and a Hopf point without a coefficient says why", "[branches]") {
  const auto branches =
      ComputeRotatingWaveBranches(TwoPointStructure(ThesisCaseAa()), FrictionLawKind::kTanh, ThesisRange());
  int with_coefficient = 0, without = 0, mode1_points = 0;
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf) continue;
      CAPTURE(b.name, RadPerSecondToRpm(p.lambda), p.note);
      const bool mode1_whirl = PatternName(b.normals) == "mode1" &&
                               std::abs(RadPerSecondToRpm(p.lambda) - 51.8) < 0.15;
      if (mode1_whirl) {
        // The Mode 1 whirl loses stability to the modulated whip, which the orbits stage finds
        // stable beyond the Hopf point (results/thesis_A_a_modulated_whip): supercritical.
        ++mode1_points;
        CHECK(p.lyapunov < 0.0);
      }
      if (std::isfinite(p.lyapunov)) {
        ++with_coefficient;
      } else {
        ++without;
        CHECK_THAT(p.note, Catch::Matchers::Contains("first Lyapunov coefficient: not converged"));
      }
    }
  }
  CHECK(mode1_points == 2);
  CHECK(with_coefficient >= 2);
  CHECK(without >= 1);
  // The exact law's Hopf points: no coefficient, and the reason.
  for (const RotatingWaveBranch& b :
       ComputeRotatingWaveBranches(TwoPointStructure(ThesisCaseAa()), FrictionLawKind::kExact, ThesisRange())) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf) continue;
      CHECK(std::isnan(p.lyapunov));
      CHECK_THAT(p.note, Catch::Matchers::Contains("the exact law is not smooth"));
    }
  }
}

TEST_CASE("the first Lyapunov coefficient is taken in the Hopf point's own contact modes",
          "[branches]") {
  // The problem keeps the modes of the last piece it continued, which need not be the Hopf
  // point's (the one-contact whips' points at 81.96 rpm have a free contact): the coefficient must
  // not depend on them.
  RotatingWaveBranchOptions options = ThesisRange();
  options.search.speed_max = 100.0 * kRadPerSecondPerRpm;
  const RubStructure structure = TwoPointStructure(ThesisCaseAa());
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options);
  RotatingWaveProblem problem(structure, FrictionLawKind::kTanh);
  int points = 0, on_free_pieces = 0;
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf) continue;
      CAPTURE(b.name, p.piece, RadPerSecondToRpm(p.lambda));
      ++points;
      on_free_pieces += p.piece.find(":free") != std::string::npos;
      problem.SetModes({ContactMode::kStick, ContactMode::kStick});
      const LyapunovCoefficient touching = problem.FirstLyapunov(p.u, p.lambda, p.critical_value);
      problem.SetModes({ContactMode::kFree, ContactMode::kFree});
      const LyapunovCoefficient free = problem.FirstLyapunov(p.u, p.lambda, p.critical_value);
      CHECK(touching.omega == free.omega);
      CHECK(touching.real_part == free.real_part);
      CHECK(touching.l1_coarse == free.l1_coarse);
    }
  }
  CHECK(points >= 10);
  CHECK(on_free_pieces >= 2);
}

TEST_CASE("case A(a), tanh friction: a one-contact whirl switches where the other contact touches",
          "[branches]") {
  // The normal force's kink at δ = 0 inside a piece stalled Newton: until the tanh law's contacts
  // became events, the left- and right-only whirls ended in corrector failures at 52.36 rpm.
  RotatingWaveBranchOptions options = ThesisRange();
  options.search.speed_max = 100.0 * kRadPerSecondPerRpm;
  const auto branches =
      ComputeRotatingWaveBranches(TwoPointStructure(ThesisCaseAa()), FrictionLawKind::kTanh, options);
  int regains = 0;
  for (const RotatingWaveBranch& b : branches) {
    INFO(b.name << ": " << b.branch.BriefReport());
    CHECK_FALSE(IsFailure(b.branch.status));
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kEvent || p.label.find("contact regain") == std::string::npos) {
        continue;
      }
      ++regains;
      CHECK(p.converged);
      CHECK(RadPerSecondToRpm(p.lambda) == Approx(52.358).epsilon(0).margin(0.01));
      // Where the contact closes: its penetration 0 there (about 1e-8 m where a contact carries
      // the whirl's normal force).
      const std::string contact = p.label.substr(0, p.label.find(' '));
      CHECK(std::abs(Measure(b.branch, p, "penetration_" + contact)) <= 1e-11);
    }
  }
  CHECK(regains >= 1);
}

TEST_CASE("tanh friction: the whirl → whip knee converges to the exact event as ε → 0",
          "[branches]") {
  const double exact_hz = 84.47801334971142;  // the closed form's μ_req = μ crossing (A(a))
  const double coarse = std::abs(KneePrecessionHz(1e-3) - exact_hz) / exact_hz;
  const double fine = std::abs(KneePrecessionHz(1e-4) - exact_hz) / exact_hz;
  INFO("relative errors " << coarse << " (ε = 1e-3), " << fine << " (ε = 1e-4)");
  CHECK(fine < 5e-4);               // measured 2.5e-4
  CHECK(coarse / fine > 5.0);        // first order in ε: measured 9.7
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

TEST_CASE("an imbalanced rotor's branch set is the balanced rotor's", "[branches]") {
  TwoPointParams params = ThesisCaseAa();
  const auto balanced = ComputeRotatingWaveBranches(TwoPointStructure(params),
                                                    FrictionLawKind::kExact, ThesisRange());
  params.imbalance = 3.43e-5;  // case A(a)'s 3.43 g·cm
  const auto imbalanced = ComputeRotatingWaveBranches(TwoPointStructure(params),
                                                      FrictionLawKind::kExact, ThesisRange());
  REQUIRE(imbalanced.size() == balanced.size());
  for (std::size_t i = 0; i < balanced.size(); ++i) {
    CHECK(imbalanced[i].branch.Size() == balanced[i].branch.Size());
    CHECK(imbalanced[i].branch.Lambda() == balanced[i].branch.Lambda());
  }
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// RotatingWaveProblem::StabilityTolerance decides what is called stable. Its 0.1 s⁻¹ must sit in
// the gap docs/studies/rotating_waves.md reports between the compliance-driven phase drift of two
// rolling contacts (≤ 0.010 s⁻¹) and the slowest real instability (the 1.65 Hz whips, ≥ 5.19 s⁻¹),
// with a margin of 5 on each side, so that no measured growth rate is classified by the last
// digits.
TEST_CASE("the rotating waves' stability tolerance, 0.1 s⁻¹, lies in the gap of the growth rates",
          "[branches]") {
  const double tolerance = 0.1;
  TwoPointParams symmetric = ThesisCaseAa();  // case A(a): the drift of two rolling contacts
  TwoPointParams unequal = ThesisCaseAa();    // case A(b), RCI 100/125: its 1.65 Hz whip is the slowest instability
  unequal.clearance[1] = unequal.radius[1] / 125.0;
  double largest_marginal = 0.0, smallest_unstable = kInfinity;
  for (const TwoPointParams& params : {symmetric, unequal}) {
    const RubStructure structure = TwoPointStructure(params);
    RotatingWaveProblem problem(structure, FrictionLawKind::kExact);
    CHECK(problem.StabilityTolerance() == tolerance);
    for (const RotatingWaveBranch& b :
         ComputeRotatingWaveBranches(structure, FrictionLawKind::kExact, ThesisRange())) {
      for (const BranchPoint& p : b.branch.points) {
        if (p.spectrum.values.size() == 0) continue;
        const double growth = p.spectrum.values.real().maxCoeff();
        if (growth <= 0.0) continue;
        if (growth < 1.0) largest_marginal = std::max(largest_marginal, growth);
        else smallest_unstable = std::min(smallest_unstable, growth);
      }
    }
  }
  CAPTURE(largest_marginal, smallest_unstable);
  CHECK(largest_marginal > 0.0);  // the drift is there to be tolerated
  CHECK(5.0 * largest_marginal <= tolerance);
  CHECK(tolerance <= smallest_unstable / 5.0);
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// Whether `point` (a point of another branch set, on piece `piece`) lies on some branch of
// `branches`: within `tolerance` of a segment of that piece in (speed, precession, normal forces),
// each relative to the point's own value (forces below 1 N count as 1 N). A distance to the segment,
// not an interpolation in speed, since the points may lie on either side of a fold.
bool OnSomeBranch(const std::vector<RotatingWaveBranch>& branches, const Branch& from,
                  const BranchPoint& point, double tolerance) {
  const std::vector<std::string> names{"precession_hz", "normal_force_left", "normal_force_right"};
  auto coordinates = [&](const Branch& branch, const BranchPoint& q) {
    Vector x(names.size() + 1);
    x(0) = q.lambda / point.lambda;
    for (std::size_t j = 0; j < names.size(); ++j) {
      const double own = point.measures(from.MeasureIndex(names[j]));
      x(static_cast<Index>(j) + 1) = q.measures(branch.MeasureIndex(names[j])) / std::max(std::abs(own), 1.0);
    }
    return x;
  };
  const Vector x = coordinates(from, point);
  for (const RotatingWaveBranch& b : branches) {
    const auto& p = b.branch.points;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
      if (p[i].piece != point.piece || p[i + 1].piece != point.piece) continue;
      const Vector a = coordinates(b.branch, p[i]), d = coordinates(b.branch, p[i + 1]) - a;
      const double t = d.squaredNorm() == 0.0 ? 0.0 : std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((a + t * d - x).lpNorm<Eigen::Infinity>() <= tolerance) return true;
    }
  }
  return false;
}

// Issue 50: A(a) over [20, 1000] rpm had lost the Mode 1 whip at 1.67 Hz (its μ crossing lay below
// the first point of the family search's grid, whose spacing grew with the range), over
// [20, 10000] rpm two branches more. Every point and special point of a narrower range's branches
// lies on a branch of the wider range's.
TEST_CASE("a wider speed range's branch set holds every branch of a narrower one (A(a), 260 → 10⁴ rpm)",
          "[branches]") {
  const RubStructure structure = TwoPointStructure(ThesisCaseAa());
  std::vector<std::vector<RotatingWaveBranch>> sets;
  for (double top_rpm : {260.0, 1000.0, 1e4}) {
    RotatingWaveBranchOptions options = ThesisRange();
    options.search.speed_max = top_rpm * kRadPerSecondPerRpm;
    sets.push_back(ComputeRotatingWaveBranches(structure, FrictionLawKind::kExact, options));
  }
  for (std::size_t narrow = 0; narrow + 1 < sets.size(); ++narrow) {
    for (const RotatingWaveBranch& b : sets[narrow]) {
      int points_off = 0;
      for (const BranchPoint& p : b.branch.points) {
        points_off += OnSomeBranch(sets[narrow + 1], b.branch, p, 5e-3) ? 0 : 1;
      }
      INFO("range " << narrow << " → " << narrow + 1 << ": " << b.name << " (" << b.family
                    << "): " << b.branch.BriefReport());
      CHECK(points_off == 0);
      for (const SpecialPoint& sp : b.branch.special_points) {
        bool found = false;
        for (const RotatingWaveBranch& w : sets[narrow + 1]) {
          for (const SpecialPoint& q : w.branch.special_points) {
            // An event's label names the contact that switched first: either of a symmetric pair.
            found = found || (q.type == sp.type && std::abs(q.lambda - sp.lambda) <= 1e-6 * sp.lambda);
          }
        }
        INFO(sp.Name() << " at " << sp.lambda << " rad/s");
        CHECK(found);
      }
    }
  }
}

}  // namespace
}  // namespace rubcont
