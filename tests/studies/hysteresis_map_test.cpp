#include "studies/hysteresis_map.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

#include "continuation/event_curve.h"
#include "continuation/hopf.h"
#include "models/analytic.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "tests/studies/speed_range.h"

namespace rubcont {
namespace {

TwoPointParams ExactThesisA() {
  TwoPointParams params = ThesisCaseAa();  // case A(a): disk at centre, RCI 100/100
  params.friction_law.kind = FrictionLawKind::kExact;
  return params;
}

double MeasureOf(const Branch& branch, const SpecialPoint& point, const std::string& name) {
  return point.measures(branch.MeasureIndex(name));
}

// The Mode 1 whirl's stick → slip event of a branch set (the one near `hz`).
struct Found {
  const Branch* branch = nullptr;
  const SpecialPoint* point = nullptr;
};
Found StickToSlip(const std::vector<RotatingWaveBranch>& branches, double hz) {
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type == SpecialPointType::kEvent && p.label.find("stick to slip+") != std::string::npos &&
          std::abs(MeasureOf(b.branch, p, "precession_hz") - hz) < 0.1 * hz) {
        return {&b.branch, &p};
      }
    }
  }
  return {};
}

// Case A(a)'s Mode 1 stick → slip event near 84.5 Hz, from one branch set (20–120 rpm) computed
// for the whole file: every test below starts its design problem there.
Found ThesisAStickToSlip() {
  static const std::vector<RotatingWaveBranch> branches = ComputeRotatingWaveBranches(
      TwoPointStructure(ExactThesisA()), FrictionLawKind::kExact, SpeedRange(20, 120));
  const Found event = StickToSlip(branches, 84.5);
  REQUIRE(event.point != nullptr);
  return event;
}

// The design problem in the contact modes and phase of the event's branch.
void StartAt(RotatingWaveDesignProblem& problem, const Found& event) {
  problem.SetModes(ModesAt(*event.branch, *event.point, problem.Contacts()));
  problem.SetPhaseReference(event.point->u);
}

// The closed form's rising μ_req = μ crossing of Mode 1 at the left contact nearest `near_hz`.
double MapMuCrossingHz(const TwoPointParams& params, double near_hz) {
  const AnalyticResult analytic = ComputeAnalytic(params, {1.0, 200.0, 4000});
  double best = 0.0;
  for (const Transition& t : analytic.mode1.transitions) {
    if (t.type == TransitionType::kMuCrossing && t.direction > 0 && t.contact == 0 &&
        std::abs(t.precession_hz - near_hz) < std::abs(best - near_hz)) {
      best = t.precession_hz;
    }
  }
  return best;
}

TEST_CASE("design parameters are set, read back and kept in their physical range",
          "[design][parameters]") {
  const TwoPointParams base = ExactThesisA();
  for (const std::string& name : DesignParameterNames()) {
    const DesignParameter p = ParseDesignParameter(name);
    const double value = GetDesignParameter(base, p);
    CHECK(GetDesignParameter(WithDesignParameter(base, p, 1.3 * value), p) ==
          Approx(1.3 * value).epsilon(1e-14));
  }
  // The RCI ratio moves the right clearance only.
  const TwoPointParams rci = WithDesignParameter(base, DesignParameter::kRciRatio, 1.25);
  CHECK(rci.Rci(0) == Approx(100.0));
  CHECK(rci.Rci(1) == Approx(125.0));
  CHECK(rci.clearance[1] == Approx(0.3048e-3));
  // Stator damping scales both supports.
  const TwoPointParams damped = WithDesignParameter(base, DesignParameter::kStatorDamping, 500.0);
  CHECK(damped.support_damping[0] == Approx(500.0));
  CHECK(damped.support_damping[1] == Approx(500.0));
  CHECK_THROWS_WITH(WithDesignParameter(base, DesignParameter::kFriction, -0.1),
                    Catch::Contains("friction = -0.1: must be finite and ≥ 0"));
  CHECK_THROWS_WITH(WithDesignParameter(base, DesignParameter::kSupportStiffness, 0.0),
                    Catch::Contains("support_stiffness = 0: must be finite and > 0"));
  CHECK_THROWS_WITH(WithDesignParameter(base, DesignParameter::kRciRatio, kNaN),
                    Catch::Contains("rci_ratio = nan"));
  CHECK_THROWS_WITH(ParseDesignParameter("mu"), Catch::Contains("parameter = \"mu\": must be one of"));
}

TEST_CASE("the stick to slip curve in friction follows the closed form's mu_req = mu crossing",
          "[design][event_curve]") {
  const TwoPointParams params = ExactThesisA();
  const Found event = ThesisAStickToSlip();
  RotatingWaveDesignProblem problem(params, DesignParameter::kFriction);
  StartAt(problem, event);
  ContinuationOptions options;
  options.bounds.lambda_min = 0.3;
  options.bounds.lambda_max = 0.7;
  options.step.max = 0.05;
  options.detect.branch_points = false;
  const Branch curve = ContinueEventCurve(problem, *event.point, options);
  INFO(curve.BriefReport());
  REQUIRE(curve.Size() > 10);
  CHECK(curve.status == BranchStatus::kReachedLambdaBound);
  CHECK(curve.Lambda().minCoeff() == Approx(0.3));
  CHECK(curve.Lambda().maxCoeff() == Approx(0.7));
  CHECK(problem.SecondParameter() == 0.5);  // restored
  // Independent oracle at a few points of the curve: the closed form with that μ crosses μ_req = μ
  // at the curve's precession (the event of the branch set is at 1e-13 of it at μ = 0.5).
  const Vector mu = curve.Lambda();
  const Vector hz = curve.Measure("precession_hz");
  for (Index i : {Index(0), curve.Size() / 3, 2 * curve.Size() / 3, curve.Size() - 1}) {
    const double crossing = MapMuCrossingHz(WithDesignParameter(params, DesignParameter::kFriction, mu(i)), hz(i));
    INFO("μ = " << mu(i) << ": curve " << hz(i) << " Hz, closed form " << crossing << " Hz");
    CHECK(std::abs(hz(i) - crossing) <= 1e-8 * crossing);
  }
  // And the branch set recomputed at an interior μ of the curve has its event on the curve.
  const Index mid = curve.Size() / 3;
  const auto again = ComputeRotatingWaveBranches(
      TwoPointStructure(WithDesignParameter(params, DesignParameter::kFriction, mu(mid))),
      FrictionLawKind::kExact, SpeedRange(20, 120));
  const Found there = StickToSlip(again, hz(mid));
  REQUIRE(there.point != nullptr);
  CHECK(std::abs(there.point->lambda - curve.Measure("lambda")(mid)) <= 1e-8 * there.point->lambda);
}

TEST_CASE("an event curve in stator damping matches branch sets recomputed along it",
          "[design][event_curve]") {
  const TwoPointParams params = ExactThesisA();
  const Found event = ThesisAStickToSlip();
  RotatingWaveDesignProblem problem(params, DesignParameter::kStatorDamping);
  StartAt(problem, event);
  ContinuationOptions options;
  options.bounds.lambda_min = 150.0;
  options.bounds.lambda_max = 600.0;
  options.step.max = 0.05;
  options.detect.branch_points = false;
  const Branch curve = ContinueEventCurve(problem, *event.point, options);
  INFO(curve.BriefReport());
  REQUIRE(curve.Size() > 5);
  const Vector c = curve.Lambda();
  const Vector speed = curve.Measure("lambda");
  for (Index i : {Index(1), curve.Size() - 2}) {
    const auto again = ComputeRotatingWaveBranches(
        TwoPointStructure(WithDesignParameter(params, DesignParameter::kStatorDamping, c(i))),
        FrictionLawKind::kExact, SpeedRange(20, 120));
    const Found there = StickToSlip(again, curve.Measure("precession_hz")(i));
    INFO("c = " << c(i) << " N·s/m");
    REQUIRE(there.point != nullptr);
    CHECK(std::abs(there.point->lambda - speed(i)) <= 1e-8 * speed(i));
  }
}

// The tanh-law Mode 1 whirl's Hopf point nearest `rpm` (converged), in a branch set.
Found Mode1Hopf(const std::vector<RotatingWaveBranch>& branches, double rpm) {
  Found best;
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf || !p.converged) continue;
      if (best.point == nullptr || std::abs(p.lambda - rpm * kRadPerSecondPerRpm) <
                                       std::abs(best.point->lambda - rpm * kRadPerSecondPerRpm)) {
        best = {&b.branch, &p};
      }
    }
  }
  return best;
}

TEST_CASE("the Hopf curve of the tanh Mode 1 whirl in friction matches branch sets recomputed on it",
          "[design][hopf]") {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  const auto base = ComputeRotatingWaveBranches(TwoPointStructure(WithoutImbalance(params)),
                                                FrictionLawKind::kTanh, SpeedRange(20, 100));
  // Where the speed-up whirl loses its stability (51.685 rpm at μ = 0.5).
  const Found hopf = Mode1Hopf(base, 51.685);
  REQUIRE(hopf.point != nullptr);
  CHECK(RadPerSecondToRpm(hopf.point->lambda) == Approx(51.685).epsilon(0).margin(1e-3));
  RotatingWaveDesignProblem problem(params, DesignParameter::kFriction);
  StartAt(problem, hopf);
  ContinuationOptions options;
  options.bounds.lambda_min = 0.4;
  options.bounds.lambda_max = 0.6;
  options.step.max = 0.2;
  options.detect.branch_points = false;
  for (const int direction : {-1, +1}) {
    options.direction = direction;
    problem.SetSecondParameter(0.5);
    StartAt(problem, hopf);
    const Branch curve = ContinueHopfCurve(problem, *hopf.point, options);
    INFO(curve.BriefReport());
    REQUIRE(curve.status == BranchStatus::kReachedLambdaBound);
    CHECK(problem.SecondParameter() == 0.5);  // restored
    // The rest of the spectrum is stable along it: the whirl loses its stability there.
    for (const BranchPoint& p : curve.points) CHECK(p.num_unstable == 0);
    // The branch set at the curve's end has its Hopf point where the curve says.
    const double mu = curve.points.back().lambda;
    const double speed = curve.Measure("lambda")(curve.Size() - 1);
    const auto again = ComputeRotatingWaveBranches(
        TwoPointStructure(WithoutImbalance(WithDesignParameter(params, DesignParameter::kFriction, mu))),
        FrictionLawKind::kTanh, SpeedRange(20, 100));
    const Found there = Mode1Hopf(again, RadPerSecondToRpm(speed));
    INFO("μ = " << mu << ": curve " << RadPerSecondToRpm(speed) << " rpm");
    REQUIRE(there.point != nullptr);
    CHECK(std::abs(there.point->lambda - speed) <= 1e-7 * speed);
    CHECK(std::abs(there.point->frequency - curve.Measure("hopf_frequency")(curve.Size() - 1)) <=
          1e-6 * there.point->frequency);
  }
}

TEST_CASE("a map's grid rows computed apart and assembled give the same map", "[design][map]") {
  // What `rubcont map` under mpirun (or with threads) does: rows of different grid values on
  // different processes, assembled in any order.
  HysteresisMapOptions options;
  options.parameter = DesignParameter::kFriction;
  options.eta_min = 0.4;
  options.eta_max = 0.6;
  options.eta_points = 4;
  options.speed_points = 101;
  options.branches = SpeedRange(20, 120);
  options.continue_curves = false;
  const HysteresisMap whole = ComputeHysteresisMap(ExactThesisA(), options);
  std::vector<MapGridRow> rows = ComputeMapGrid(ExactThesisA(), options, {3, 1});
  for (MapGridRow& row : ComputeMapGrid(ExactThesisA(), options, {2, 0})) rows.push_back(row);
  const HysteresisMap assembled = AssembleHysteresisMap(ExactThesisA(), options, rows, 0.0);
  CHECK(assembled.stable_count == whole.stable_count);
  CHECK(assembled.patterns == whole.patterns);
  REQUIRE(assembled.pattern_counts.size() == whole.pattern_counts.size());
  for (size_t p = 0; p < whole.pattern_counts.size(); ++p) {
    CHECK(assembled.pattern_counts[p] == whole.pattern_counts[p]);
  }
  REQUIRE(assembled.points.size() == whole.points.size());
  for (size_t q = 0; q < whole.points.size(); ++q) {
    CHECK(assembled.points[q].eta == whole.points[q].eta);
    CHECK(assembled.points[q].speed == whole.points[q].speed);
    CHECK(assembled.points[q].label == whole.points[q].label);
  }
  CHECK(assembled.grid_branches == whole.grid_branches);
  // Over two threads: the same map.
  HysteresisMapOptions threaded = options;
  threaded.threads = 2;
  const HysteresisMap two = ComputeHysteresisMap(ExactThesisA(), threaded);
  CHECK(two.stable_count == whole.stable_count);
  CHECK(two.points.size() == whole.points.size());
  CHECK(two.patterns == whole.patterns);
  // Each grid value exactly once.
  std::vector<MapGridRow> missing(rows.begin(), rows.end() - 1);
  CHECK_THROWS_WITH(AssembleHysteresisMap(ExactThesisA(), options, missing, 0.0),
                    Catch::Contains("3 rows for a grid of 4"));
  std::vector<MapGridRow> twice = rows;
  twice.back() = rows.front();
  CHECK_THROWS_WITH(AssembleHysteresisMap(ExactThesisA(), options, twice, 0.0),
                    Catch::Contains("repeated"));
  CHECK_THROWS_WITH(ComputeMapGrid(ExactThesisA(), options, {4}), Catch::Contains("index 4 outside"));
}

TEST_CASE("the friction map of case A(a): regions from the branch sets agree with the curves",
          "[design][map]") {
  HysteresisMapOptions options;
  options.parameter = DesignParameter::kFriction;
  options.eta_min = 0.4;
  options.eta_max = 0.6;
  options.eta_points = 3;
  options.speed_points = 201;
  options.branches = SpeedRange(20, 120);
  const HysteresisMap map = ComputeHysteresisMap(ExactThesisA(), options);
  INFO(map.BriefReport());
  CHECK(map.failures.empty());
  REQUIRE(map.stable_count.rows() == 3);
  REQUIRE(map.stable_count.cols() == 201);
  CHECK(map.base_value == 0.5);
  // Mode 1 at μ = 0.5: one stable whirl below the stick → slip event (50.689 rpm), none between it
  // and the non-smooth fold where the whip's right contact sticks again (65.913 rpm), one above.
  const auto mode1 = std::find(map.patterns.begin(), map.patterns.end(), "mode1");
  REQUIRE(mode1 != map.patterns.end());
  const Eigen::MatrixXi& count = map.pattern_counts[mode1 - map.patterns.begin()];
  auto at_rpm = [&](double rpm) {
    Index j = 0;
    while (j + 1 < map.speed.size() && map.speed(j + 1) <= rpm * kRadPerSecondPerRpm) ++j;
    return j;
  };
  CHECK(count(1, at_rpm(40.0)) == 1);
  CHECK(count(1, at_rpm(58.0)) == 0);
  CHECK(count(1, at_rpm(100.0)) == 1);
  // Over all families several states coexist (Mode 2 and single-contact whirls are stable too).
  CHECK(map.stable_count(1, at_rpm(40.0)) >= 2);
  // Every grid special point that is an event lies on a continued curve of the same label: the
  // curve's speed at that μ (interpolated) matches to the interpolation error.
  int matched = 0;
  for (const MapPoint& p : map.points) {
    if (p.type != SpecialPointType::kEvent || p.eta == map.base_value) continue;
    for (const MapCurve& c : map.curves) {
      if (c.label != p.label || c.curve.Size() < 2) continue;
      const Vector eta = c.curve.Lambda();
      const Vector speed = c.curve.Measure("lambda");
      for (Index i = 0; i + 1 < eta.size(); ++i) {
        if ((eta(i) - p.eta) * (eta(i + 1) - p.eta) > 0.0 || eta(i) == eta(i + 1)) continue;
        const double w = (p.eta - eta(i)) / (eta(i + 1) - eta(i));
        const double s = speed(i) + w * (speed(i + 1) - speed(i));
        if (std::abs(s - p.speed) <= 2e-3 * p.speed) ++matched;
      }
    }
  }
  CHECK(matched >= 4);
  // The curves were all continued to both ends of the μ range.
  for (const MapCurve& c : map.curves) {
    INFO(c.name << " " << c.label << ": " << c.curve.message);
    CHECK(!IsFailure(c.curve.status));
  }
}

TEST_CASE("hysteresis map options are validated by name", "[design][map][failure]") {
  HysteresisMapOptions options;
  options.branches = SpeedRange(20, 120);
  options.parameter = DesignParameter::kFriction;
  options.eta_min = -0.1;
  options.eta_max = 0.6;
  CHECK_THROWS_WITH(ComputeHysteresisMap(ExactThesisA(), options),
                    Catch::Contains("HysteresisMapOptions.eta_min = -0.1"));
  options.eta_min = 0.6;
  options.eta_max = 0.4;
  CHECK_THROWS_WITH(ComputeHysteresisMap(ExactThesisA(), options),
                    Catch::Contains("HysteresisMapOptions.eta_max = 0.4"));
  options.eta_min = 0.4;
  options.eta_max = 0.6;
  options.eta_points = 1;
  CHECK_THROWS_WITH(ComputeHysteresisMap(ExactThesisA(), options),
                    Catch::Contains("HysteresisMapOptions.eta_points = 1"));
}

TEST_CASE("an event curve stops where the parameter leaves its physical range",
          "[design][event_curve][failure]") {
  // Continuing the stick → slip point in friction down to μ = 0: the curve ends on the bound with
  // a status (friction would turn negative past it), and η is restored.
  const TwoPointParams params = ExactThesisA();
  const Found event = ThesisAStickToSlip();
  RotatingWaveDesignProblem problem(params, DesignParameter::kFriction);
  StartAt(problem, event);
  CHECK_THROWS_WITH(problem.SetSecondParameter(-0.01), Catch::Contains("friction = -0.01"));
  CHECK(problem.SecondParameter() == 0.5);
  ContinuationOptions options;
  options.bounds.lambda_min = 0.05;
  options.bounds.lambda_max = 0.55;
  options.detect.branch_points = false;
  const Branch curve = ContinueEventCurve(problem, *event.point, options);
  INFO(curve.BriefReport());
  CHECK(!IsFailure(curve.status));
  CHECK(curve.Lambda().minCoeff() >= 0.05 - 1e-12);
  CHECK(problem.SecondParameter() == 0.5);
  // A fold point handed to the event continuation is refused by name.
  SpecialPoint fold = *event.point;
  fold.type = SpecialPointType::kFold;
  CHECK_THROWS_WITH(ContinueEventCurve(problem, fold), Catch::Contains("not an event"));
}

TEST_CASE("the stator damping that closes the Mode 2 whirl-whip gap, by the engine and by Ipopt",
          "[design][map][fold_optimization]") {
  // The Mode 2 whirl's stick → slip event (79.9 rpm) and its whip's slip → stick event (89.9 rpm)
  // move together as the stator damping grows, and meet where both event curves turn back in c:
  // the smallest damping for which the speed-up and speed-down jumps of the family coincide.
  HysteresisMapOptions options;
  options.parameter = DesignParameter::kStatorDamping;
  options.eta_min = 250.0;
  options.eta_max = 1500.0;
  options.eta_points = 2;
  options.speed_points = 11;
  options.branches = SpeedRange(20, 120);
  const HysteresisMap map = ComputeHysteresisMap(ExactThesisA(), options);
  std::vector<const CurveExtremum*> mode2;
  for (const MapCurve& c : map.curves) {
    UNSCOPED_INFO(c.name << " " << c.pattern << " " << c.label << " from " << c.start_speed
                         << ": " << c.curve.BriefReport() << ", " << c.extrema.size() << " extrema");
    if (c.pattern != "mode2") continue;
    for (const CurveExtremum& e : c.extrema) mode2.push_back(&e);
  }
  REQUIRE(mode2.size() >= 2);
  for (const CurveExtremum* e : mode2) {
    INFO("engine c = " << e->engine_eta << ", Ipopt: " << e->ipopt.message);
    REQUIRE(e->ipopt.Solved());
    CHECK(e->sense == +1);
    CHECK(std::abs(e->ipopt.lambda - e->engine_eta) <= 1e-8 * e->engine_eta);
    CHECK(std::abs(e->ipopt_speed - e->engine_speed) <= 1e-6 * e->engine_speed);
  }
  // Both curves (whirl's and whip's event) turn at the same point: the gap closes there.
  CHECK(mode2[0]->engine_eta == Approx(mode2[1]->engine_eta).epsilon(1e-8));
  CHECK(mode2[0]->engine_speed == Approx(mode2[1]->engine_speed).epsilon(1e-6));
  CHECK(mode2[0]->engine_eta > 1000.0);
  CHECK(mode2[0]->engine_eta < 1500.0);
}

TEST_CASE("the design problem at eta equals a rotating-wave problem built with that parameter",
          "[design][parameters]") {
  const TwoPointParams params = ExactThesisA();
  const Found event = ThesisAStickToSlip();
  const Vector& u = event.point->u;
  const double omega = event.point->lambda;
  for (const std::string& name : DesignParameterNames()) {
    const DesignParameter p = ParseDesignParameter(name);
    RotatingWaveDesignProblem design(params, p);
    const std::vector<ContactMode> modes = ModesAt(*event.branch, *event.point, design.Contacts());
    const double eta = 1.1 * GetDesignParameter(params, p);
    design.SetModes(modes);
    design.SetPhaseReference(u);
    design.SetSecondParameter(eta);
    RotatingWaveProblem fresh(TwoPointStructure(WithDesignParameter(params, p, eta)), FrictionLawKind::kExact);
    fresh.SetModes(modes);
    fresh.SetPhaseReference(u);
    Vector F_design, F_fresh;
    design.Residual(u, omega, F_design);
    fresh.Residual(u, omega, F_fresh);
    INFO(name);
    CHECK((F_design - F_fresh).lpNorm<Eigen::Infinity>() <= 1e-12 * std::max(1.0, F_fresh.lpNorm<Eigen::Infinity>()));
    Matrix J_design, J_fresh;
    design.Jacobian(u, omega, J_design);
    fresh.Jacobian(u, omega, J_fresh);
    CHECK((J_design - J_fresh).lpNorm<Eigen::Infinity>() <= 1e-12 * J_fresh.lpNorm<Eigen::Infinity>());
    // The margins are scaled by the problem's force scale, which the design problem keeps from
    // the scene (support stiffness sets it): equal up to that factor, so equal in sign.
    const Vector m_design = design.EventFunctions(u, omega), m_fresh = fresh.EventFunctions(u, omega);
    if (p != DesignParameter::kSupportStiffness) {
      CHECK((m_design - m_fresh).lpNorm<Eigen::Infinity>() <= 1e-12);
    }
    for (Index i = 0; i < m_fresh.size(); ++i) {
      if (std::abs(m_fresh(i)) > 1e-9) CHECK((m_design(i) > 0.0) == (m_fresh(i) > 0.0));
    }
    // Back at the scene's value the residual vanishes again (the base is not drifted).
    design.SetSecondParameter(GetDesignParameter(params, p));
    Vector F_back;
    design.Residual(u, omega, F_back);
    CHECK(F_back.cwiseQuotient(design.ResidualScale()).lpNorm<Eigen::Infinity>() <= 1e-9);
  }
  // A structure of another shape is refused.
  RotatingWaveDesignProblem design(params, DesignParameter::kFriction);
  TwoPointParams single = params;
  RubStructure three = TwoPointStructure(single);
  three.contacts.pop_back();
  CHECK_THROWS_WITH(design.SetStructure(three), Catch::Contains("must have 4 and 2 like the problem's"));
}

TEST_CASE("the event curve problem's Jacobian and eta derivative match finite differences",
          "[design][event_curve]") {
  const TwoPointParams params = ExactThesisA();
  const Found event = ThesisAStickToSlip();
  RotatingWaveDesignProblem problem(params, DesignParameter::kStatorDamping);
  StartAt(problem, event);
  const std::vector<std::string> names = problem.EventNames();
  const int k = static_cast<int>(std::find(names.begin(), names.end(), event.point->label) - names.begin());
  EventCurveProblem curve(problem, k, event.point->u, event.point->lambda);
  CHECK(curve.event_name() == event.point->label);
  // The symmetric rotor's other contact reaches μ at the same point: a partner, not monitored.
  // (Which of the two the branch meets first is decided by rounding.)
  const std::string other = event.point->label == "left stick to slip+" ? "right stick to slip+"
                                                                          : "left stick to slip+";
  CHECK_THAT(event.point->label, Catch::Matchers::EndsWith(" stick to slip+"));
  CHECK(curve.PartnerMargins() == std::vector<std::string>{other});
  const Vector U = Joined(event.point->u, event.point->lambda);
  const double eta = 324.9;
  Vector G;
  curve.Residual(U, eta, G);
  CHECK(G.cwiseQuotient(curve.ResidualScale()).lpNorm<Eigen::Infinity>() <= 1e-8);
  Matrix DG;
  curve.Jacobian(U, eta, DG);
  const Vector s = curve.Scale();
  for (Index j = 0; j < U.size(); ++j) {
    const double h = 1e-5 * s(j);
    Vector Up = U, Um = U;
    Up(j) += h;
    Um(j) -= h;
    Vector Gp, Gm;
    curve.Residual(Up, eta, Gp);
    curve.Residual(Um, eta, Gm);
    const Vector column = (Gp - Gm) / (2.0 * h);
    INFO("column " << j);
    CHECK((column - DG.col(j)).cwiseQuotient(curve.ResidualScale()).lpNorm<Eigen::Infinity>() * s(j) <=
          1e-5 * std::max(1.0, DG.col(j).cwiseQuotient(curve.ResidualScale()).lpNorm<Eigen::Infinity>() * s(j)));
  }
  Vector dG;
  curve.DfDlambda(U, eta, dG);
  Vector Gp, Gm;
  const double h = 1e-3;
  curve.Residual(U, eta + h, Gp);
  curve.Residual(U, eta - h, Gm);
  CHECK((dG - (Gp - Gm) / (2.0 * h)).cwiseQuotient(curve.ResidualScale()).lpNorm<Eigen::Infinity>() <=
        1e-6 * std::max(1.0, dG.cwiseQuotient(curve.ResidualScale()).lpNorm<Eigen::Infinity>()));
  // Outside the physical range the curve problem returns NaN instead of throwing.
  curve.Residual(U, -1.0, G);
  CHECK(!G.allFinite());
}

}  // namespace
}  // namespace rubcont
