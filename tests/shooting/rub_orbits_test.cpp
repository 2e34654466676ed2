// The modulated whip of case A(a): relative periodic orbits born at the Hopf point where the tanh
// Mode 1 whirl loses stability, continued in speed (shooting/rub_orbits.h). The contact stiffness
// is lowered to k1 = 1.75e8 N/m (from 1.75e11) to keep the test at a few seconds: the nearly
// undamped contact mode sets the cost of the sensitivities (bench/modulated_whip_bench.cpp); the
// whirl, its Hopf point and the orbits born there are qualitatively the same (53.66 rpm instead
// of 51.68 rpm, modulation 1508 rad/s instead of 1520 rad/s). The last test keeps the thesis's
// stiffness and shoots with Gauss collocation, which does not pay for that mode (3–4 s).
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "solvers/newton.h"
#include "solvers/ode.h"
#include "tests/shooting/traced_newton.h"

namespace rubcont {
namespace {

struct ModulatedWhip {
  RubStructure structure;
  RubModulatedOrbits result;
};

// The orbits born at case A(a)'s first Hopf point bounding a stable whirl (tanh law), 4 segments,
// continued in [40 rpm, rpm_max] with `integrator` (and `measures`, when given; without the defect
// check when asked).
RubModulatedOrbits ContinueCaseAa(const RubStructure& structure, double rpm_max,
                                  const IntegratorOptions& integrator, int max_steps,
                                  std::vector<OrbitMeasure> measures = {},
                                  bool defect_check = true) {
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(40);
  options.search.speed_max = RpmToRadPerSecond(70);
  options.search.precession_max = HzToRadPerSecond(200);
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options);
  const auto starts = StableBoundaryHopfPoints(branches, structure.Coordinates());
  REQUIRE_FALSE(starts.empty());
  HopfOrbitOptions hopf;
  hopf.amplitude = 1e-3;
  hopf.orbits.lambda_min = RpmToRadPerSecond(40);
  hopf.orbits.lambda_max = RpmToRadPerSecond(rpm_max);
  hopf.orbits.shooting.segments = 4;
  hopf.orbits.shooting.integrator = integrator;
  hopf.orbits.shooting.sensitivities_in_residual = true;
  hopf.orbits.continuation.bounds.max_steps = max_steps;
  hopf.orbits.continuation.step.target_iterations = 5;
  hopf.orbits.measures = std::move(measures);
  hopf.orbits.defect_check = defect_check;
  return ContinueModulatedOrbits(structure, branches, starts.front(), hopf);
}

TwoPointParams CaseAaTanh() {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  return params;
}

// Gauss collocation on 50 steps per segment at 1e-9: the thesis's contact stiffness in seconds.
IntegratorOptions GaussOn50Steps() {
  IntegratorOptions gauss;
  gauss.method = IntegrationMethod::kGaussCollocation;
  gauss.collocation_steps = 50;
  gauss.relative_tolerance = gauss.absolute_tolerance = 1e-9;
  return gauss;
}

const ModulatedWhip& CaseAaModulatedWhip() {
  static const ModulatedWhip whip = [] {
    TwoPointParams params = CaseAaTanh();
    params.contact_stiffness = 1.75e8;
    ModulatedWhip w;
    w.structure = TwoPointStructure(params);
    IntegratorOptions bdf;
    bdf.relative_tolerance = bdf.absolute_tolerance = 1e-7;
    bdf.max_steps = 2000000;
    w.result = ContinueCaseAa(w.structure, 70, bdf, 3);
    return w;
  }();
  return whip;
}

TEST_CASE("case A(a): the modulated whip is born at the Mode 1 whirl's Hopf point with the whirl's "
          "precession as carrier and the critical frequency as modulation",
          "[rub_orbits][shooting][relative]") {
  const ModulatedWhip& whip = CaseAaModulatedWhip();
  const RubHopfStart& hopf = whip.result.hopf;
  // The first Hopf point bounding a stable piece: the Mode 1 whirl, stable below it.
  CHECK(hopf.stable_below);
  CHECK(RadPerSecondToRpm(hopf.speed) == Approx(53.66).epsilon(0).margin(0.05));
  CHECK(RadPerSecondToHz(hopf.precession) == Approx(84.48).epsilon(0).margin(0.05));
  const Branch& branch = whip.result.orbits.branch;
  INFO(branch.BriefReport() << " — " << branch.message);
  REQUIRE(branch.Size() == 4);
  const Vector period = branch.Measure("period"), carrier = branch.Measure("precession_hz");
  const Vector modulation = branch.Measure("modulation_hz");
  const Vector n_min = branch.Measure("min_normal_force_left");
  const Vector n_max = branch.Measure("max_normal_force_left");
  for (Index i = 0; i < branch.Size(); ++i) {
    const BranchPoint& p = branch.points[static_cast<std::size_t>(i)];
    CAPTURE(i, RadPerSecondToRpm(p.lambda));
    // Supercritical: the orbits exist where the whirl is unstable and are stable themselves.
    CHECK(p.lambda > hopf.speed);
    REQUIRE(p.spectrum.valid);
    CHECK(p.spectrum.trivial_removed == 2);
    CHECK(p.num_unstable == 0);
    CHECK(p.spectrum.values.cwiseAbs().maxCoeff() < 1.0);
    CHECK(modulation(i) == Approx(1.0 / period(i)).epsilon(1e-14));
    CHECK(n_max(i) > n_min(i));
    if (i > 0) CHECK(n_max(i) - n_min(i) > n_max(i - 1) - n_min(i - 1));
  }
  // At the Hopf point the period is 2π/ω of the critical pair and the carrier the whirl's
  // precession: both extrapolated linearly in speed from the first two orbits (period and carrier
  // change in proportion to the squared amplitude, i.e. to the speed past the Hopf point; the first
  // orbit alone is 0.25 % off in period).
  const double l0 = branch.points[0].lambda, l1 = branch.points[1].lambda;
  const auto at_hopf = [&](const Vector& y) {
    return y(0) + (hopf.speed - l0) * (y(1) - y(0)) / (l1 - l0);
  };
  CHECK(at_hopf(period) == Approx(kTwoPi / hopf.modulation).epsilon(5e-4));
  CHECK(at_hopf(carrier) == Approx(RadPerSecondToHz(hopf.precession)).epsilon(1e-8));
}

TEST_CASE("case A(a): integrated in the fixed frame, the modulated whip returns after one "
          "modulation period turned by the carrier's angle, as the relative orbit says",
          "[rub_orbits][shooting][relative]") {
  const ModulatedWhip& whip = CaseAaModulatedWhip();
  const Branch& branch = whip.result.orbits.branch;
  REQUIRE(branch.Size() == 4);
  const BranchPoint& p = branch.points.back();
  const Index n = whip.structure.States();
  const double T = branch.Measure("period")(3), phi = branch.Measure("rotation")(3);
  // x_0 of the first segment is the co-rotating state at t = 0, which is also the fixed-frame one.
  RubRotatingFrame frame(whip.structure, whip.result.hopf.precession, p.lambda);
  const Vector x0 = frame.ToFixedFrame(0.0, p.u.head(n));
  RubFixedFrame fixed(whip.structure, p.lambda);
  IntegratorOptions options;
  options.relative_tolerance = 1e-10;
  options.absolute_tolerance = 1e-10;
  options.max_steps = 2000000;
  OdeIntegrator integrator(fixed, options);
  Vector x(n);
  const IntegrationResult run = integrator.Integrate(0.0, x0, T, x);
  REQUIRE(run.status == IntegrationStatus::kSuccess);
  // u(T) = e^{−jΩ_f T} R_φ p(0): the fixed-frame state turned by φ − Ω_f T.
  Vector expected = x0;
  fixed.Rotate(phi - whip.result.hopf.precession * T, expected);
  const Vector scale = fixed.StateScale();
  CHECK((x - expected).cwiseQuotient(scale).lpNorm<Eigen::Infinity>() < 1e-5);
  // …and not back where it started: the carrier has turned it by ≈ 2.25 rad.
  CHECK((x - x0).cwiseQuotient(scale).lpNorm<Eigen::Infinity>() > 0.5);
}

TEST_CASE("case A(a): fixed-frame single-frequency shooting cannot converge on the modulated whip "
          "that relative-orbit shooting finds",
          "[rub_orbits][shooting][relative][failure]") {
  // x(T) = x(0) in the fixed frame, from a point of the modulated whip and its modulation period
  // (the carrier turns the state by ≈ 2.25 rad per period, so the motion is quasi-periodic):
  // Newton finds no periodic orbit near it and says so. Measured: the scaled residual goes 6.7,
  // 0.16, 0.79, 0.018, 1.2e-3, then the period turns negative and the backward integration of the
  // stiff contact blows up (a non-finite residual, with the integrator's reason); the relative
  // orbit it starts from solves its own problem to the integration tolerance (1e-7).
  const ModulatedWhip& whip = CaseAaModulatedWhip();
  const Branch& branch = whip.result.orbits.branch;
  REQUIRE(branch.Size() == 4);
  const BranchPoint& p = branch.points.back();
  const Index n = whip.structure.States();
  RubFixedFrame fixed(whip.structure, p.lambda);
  ShootingOptions options;
  options.segments = 4;
  options.integrator.relative_tolerance = 1e-7;
  options.integrator.absolute_tolerance = 1e-7;
  options.integrator.max_steps = 2000000;
  ShootingProblem problem(fixed, OrbitKind::kAutonomous, options);
  Vector u = problem.InitialGuess(p.u.head(n), branch.Measure("period")(3), p.lambda);
  const testing::TracedNewton traced =
      testing::NewtonWithSmallestResidual(problem, u, p.lambda, 10);
  INFO(traced.result.BriefReport());
  CHECK_FALSE(traced.result.Converged());
  if (traced.result.status == NewtonStatus::kNonFinite) {
    CHECK_FALSE(problem.LastFailure().Succeeded());
    CHECK_FALSE(problem.LastFailure().message.empty());
  }
  CHECK(traced.smallest_residual > 1e-4);
}


// At the thesis's stiffness, continued to 56 rpm (the engine places the last orbit on the bound),
// Gauss collocation on 200 intervals per period (the stage's default) against CVODES BDF with
// sensitivities at rtol 1e-9, whose numbers below were measured by
// bench/modulated_whip_methods_bench (results/bench/orbits/modulated_whip_methods.txt, 416 s CPU):
// modulation 211.935817185 Hz, carrier 84.4190240523 Hz, four largest multipliers of modulus
// 0.951578, 0.939902, 0.894430, 0.894430.
TEST_CASE("case A(a) at the thesis's contact stiffness: Gauss collocation reproduces the BDF "
          "reference orbit at 56 rpm, and its checks pass",
          "[rub_orbits][shooting][relative][gauss]") {
  const RubStructure structure = TwoPointStructure(CaseAaTanh());
  const IntegratorOptions gauss = GaussOn50Steps();
  const RubModulatedOrbits whip = ContinueCaseAa(structure, 56, gauss, 200);
  const Branch& b = whip.orbits.branch;
  REQUIRE(b.status == BranchStatus::kReachedLambdaBound);
  const Index last = b.Size() - 1;
  CHECK(b.points.back().lambda == Approx(RpmToRadPerSecond(56)).epsilon(1e-12));
  // Measured differences: 2.5e-10 and 9e-13 relative, multipliers 1e-9 (largest) and 2e-7.
  CHECK(b.Measure("modulation_hz")(last) == Approx(211.935817185).epsilon(1e-8));
  CHECK(b.Measure("precession_hz")(last) == Approx(84.4190240523).epsilon(1e-10));
  Vector moduli = b.points.back().spectrum.values.cwiseAbs();
  std::sort(moduli.data(), moduli.data() + moduli.size(), std::greater<double>());
  CHECK(moduli(0) == Approx(0.951578).epsilon(0).margin(2e-6));
  CHECK(moduli(1) == Approx(0.939902).epsilon(0).margin(2e-6));
  CHECK(moduli(2) == Approx(0.894430).epsilon(0).margin(2e-6));
  CHECK(b.points.back().num_unstable == 0);
  // The independent defect check and the unresolved contact modes (|λ|h ≈ 11 for the 85 kHz pair).
  for (Index i = 0; i <= last; ++i) {
    CHECK(b.Measure("defect")(i) < 1e-6);
    CHECK(b.Measure("unresolved_multiplier")(i) > 0.3);
    CHECK(b.Measure("unresolved_multiplier")(i) < 0.8);
  }
}

TEST_CASE("case A(a): the caller's own measures replace the family's default ones",
          "[rub_orbits][shooting][relative][gauss]") {
  const RubStructure structure = TwoPointStructure(CaseAaTanh());
  const IntegratorOptions gauss = GaussOn50Steps();
  int evaluations = 0;
  std::vector<OrbitMeasure> measures = {
      {"first_state", [&evaluations](const OrbitSamples& orbit) {
         ++evaluations;
         return orbit.states(0, 0);
       }}};
  const RubModulatedOrbits whip = ContinueCaseAa(structure, 70, gauss, 2, measures);
  const Branch& b = whip.orbits.branch;
  REQUIRE(b.Size() >= 2);
  CHECK(b.measure_names == std::vector<std::string>{"period", "rotation", "first_state"});
  CHECK(evaluations == static_cast<int>(b.points.size() + b.special_points.size()));
  for (const BranchPoint& p : b.points) CHECK(p.measures(2) == p.u(0));
  // Without them, the default ones (RubFamilyMeasures): the defect check among them.
  const RubModulatedOrbits defaults = ContinueCaseAa(structure, 70, gauss, 1);
  const auto& names = defaults.orbits.branch.measure_names;
  CHECK(std::find(names.begin(), names.end(), "defect") != names.end());
  CHECK(std::find(names.begin(), names.end(), "first_state") == names.end());
}

TEST_CASE("case A(a): without the defect check a family carries every other measure",
          "[rub_orbits][shooting][relative][gauss]") {
  const RubStructure structure = TwoPointStructure(CaseAaTanh());
  const RubModulatedOrbits checked = ContinueCaseAa(structure, 70, GaussOn50Steps(), 1);
  const RubModulatedOrbits unchecked = ContinueCaseAa(structure, 70, GaussOn50Steps(), 1, {}, false);
  std::vector<std::string> names = checked.orbits.branch.measure_names;
  const auto defect = std::find(names.begin(), names.end(), "defect");
  REQUIRE(defect != names.end());
  names.erase(defect);
  CHECK(unchecked.orbits.branch.measure_names == names);
  // The same orbits, measured alike but for the check.
  const Branch& a = checked.orbits.branch;
  const Branch& b = unchecked.orbits.branch;
  REQUIRE(a.Size() == b.Size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    CHECK(b.points[i].u == a.points[i].u);
    CHECK(b.points[i].measures(b.MeasureIndex("max_normal_force_left")) ==
          a.points[i].measures(a.MeasureIndex("max_normal_force_left")));
  }
}

// The check is the orbit's defect, not the check's own error: an orbit of the family with its
// start moved by 1e-6 (scaled) along each state in turn — the contact's lightly damped modes
// among the directions — has the defect a Dormand–Prince at 1e-13 finds, to 1 %. (The CVODES
// BDF ≤ 2 at 1e-11 the check was until 2026-11-30 is off by up to 14 % here: 1.030e-6 against
// 9.043e-7 along the first velocity, 5.398e-7 against 5.328e-7 along the first y.)
TEST_CASE("case A(a): the family's defect check measures the orbit's defect",
          "[rub_orbits][shooting][relative][gauss]") {
  const RubStructure structure = TwoPointStructure(CaseAaTanh());
  const RubModulatedOrbits whip = ContinueCaseAa(structure, 70, GaussOn50Steps(), 1);
  const Branch& b = whip.orbits.branch;
  REQUIRE(b.Size() >= 1);
  const RubRotatingFrame frame(structure, whip.hopf.precession, whip.hopf.speed);
  const std::vector<OrbitMeasure> measures = RubOrbitMeasures(frame);
  const auto check = std::find_if(measures.begin(), measures.end(),
                                  [](const OrbitMeasure& m) { return m.name == "defect"; });
  REQUIRE(check != measures.end());
  IntegratorOptions tight;
  tight.method = IntegrationMethod::kDormandPrince;
  tight.relative_tolerance = tight.absolute_tolerance = 1e-13;
  tight.max_steps = 2000000;
  const OrbitMeasure reference =
      PeriodicityDefect(std::make_shared<RubRotatingFrame>(frame), tight);
  RubRotatingFrame system = frame;
  ShootingProblem problem(system, OrbitKind::kRelative, whip.orbits.shooting);
  const BranchPoint& p = b.points.back();
  const OrbitSamples orbit = problem.Orbit(p.u, p.lambda);
  const Vector scale = frame.StateScale();
  for (Index k = 0; k < scale.size(); ++k) {
    OrbitSamples moved = orbit;
    moved.states(k, 0) += 1e-6 * scale(k);
    const double value = reference.evaluate(moved);
    INFO("state " << k << ": defect " << check->evaluate(moved) << ", reference " << value);
    CHECK(value > 1e-7);
    CHECK(check->evaluate(moved) == Approx(value).epsilon(0.01));
  }
}

}  // namespace
}  // namespace rubcont
