#include "shooting/modulated_orbit.h"
#include "shooting/modulated_torus.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/units.h"
#include "shooting/orbit_branches.h"
#include "shooting/rub_orbits.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// The scene's time-marching model at one speed from rest plus a 1 N·s impulse, settled by 0.5 s
// windows (the modulated whip needs more than the sweeps' 0.75 s from rest).
RubSettledSpeed Settle(const TwoPointParams& params, double rpm, double dwell = 3.0) {
  return SettleAtSpeed(TwoPointStructure(params), LongSettleOptions(RpmToRadPerSecond(rpm), dwell),
                       1.0);
}

ModulatedOrbitOptions ModulatedOptions(double tolerance) {
  ModulatedOrbitOptions o;
  o.shooting.integrator.relative_tolerance = o.shooting.integrator.absolute_tolerance = tolerance;
  o.shooting.integrator.max_steps = 2000000;
  o.shooting.sensitivities_in_residual = true;
  o.newton.residual_tolerance = o.newton.step_tolerance = 100 * tolerance;
  o.newton.max_iterations = 10;
  return o;
}

TEST_CASE("case A(a) at 60 rpm: the modulated whip is a relative periodic orbit whose dominant "
          "precession is the sweep's, 0.1 Hz below the circular whip's", "[modulated_orbit]") {
  const TwoPointParams params = ThesisCaseAa();  // the tanh law at ε = 1e-3 m/s, as the sweeps
  const RubSettledSpeed transient = Settle(params, 60.0);
  REQUIRE(transient.settled);
  const ModulatedOrbit orbit = SolveModulatedOrbit(TwoPointStructure(params), RpmToRadPerSecond(60.0),
                                                   HzToRadPerSecond(transient.precession_hz),
                                                   transient.state, ModulatedOptions(1e-6));
  INFO(orbit.message);
  REQUIRE(orbit.converged);
  // Measured: T = 4.7667 ms (the Hopf point's 2π/1519.6 = 4.135 ms at 51.68 rpm, growing with
  // speed), φ = −4e-5 rad: the orbit turns with the frame set at the sweep's precession.
  CHECK(orbit.period > 4.5e-3);
  CHECK(orbit.period < 5.0e-3);
  CHECK(std::abs(orbit.rotation) < 1e-2);
  CHECK(orbit.dominant_harmonic == 0);
  CHECK(orbit.dominant_hz == orbit.carrier_hz);
  // The sweep's refined peak over 1 s agrees to 0.005 Hz (measured 0.0014 Hz).
  CHECK(std::abs(orbit.dominant_hz - transient.precession_hz) < 5e-3);
  // The modulation (sidebands 0.049 of the carrier) moves the precession 0.107 Hz below the
  // circular whip's, which turns at the closed form's μ crossing.
  double crossing_hz = 0.0;
  for (const Transition& t : ComputeAnalyticCurve(params, CircularMode::kMode1).transitions) {
    if (t.type == TransitionType::kMuCrossing && t.direction > 0) {
      crossing_hz = t.precession_hz;
      break;
    }
  }
  CHECK(crossing_hz - orbit.dominant_hz > 0.05);
  CHECK(orbit.sideband_ratio > 0.01);
  CHECK(orbit.sideband_ratio < 0.2);
}

TEST_CASE("case C(a) at 60 rpm: a modulation with two frequencies is no relative periodic orbit: "
          "shooting for one reports that it did not converge", "[modulated_orbit][failure]") {
  // Measured (sweep spectra at 49.5–60 rpm): the left contact carries lines at −79 ± 121 Hz, the
  // right at −79 ± 325 Hz; 325/121 is not an integer, so no period T fits both.
  const TwoPointParams params = ThesisCaseCa();
  // 3 s from rest is not enough here: the modulation still moves from 123.3 to 124.4 Hz over the
  // next 0.8 s (measured), and the torus's first points need it steady.
  const RubSettledSpeed transient = Settle(params, 60.0, 8.0);
  const ModulatedOrbit orbit = SolveModulatedOrbit(TwoPointStructure(params), RpmToRadPerSecond(60.0),
                                                   HzToRadPerSecond(transient.precession_hz),
                                                   transient.state, ModulatedOptions(1e-6));
  INFO(orbit.message);
  CHECK_FALSE(orbit.converged);
  CHECK_FALSE(orbit.newton.Converged());
  CHECK_THAT(orbit.message, Contains("Newton from the transient's orbit"));
  CHECK(std::isnan(orbit.dominant_hz));

  // Nor is it an invariant circle of R_{−φ} Φ_T at one modulation period T (124.37 Hz; measured):
  // the points x(kT) fall into 5 clusters (their sequence's strongest line is at 0.4 = 2/5 per
  // iterate, and every line of the fixed-frame spectrum found is a multiple of 124.37/5 = 24.87
  // Hz), and every fifth point turns by ρ = 0.4375 ≈ 7/16 to 1e-5: a torus cut five times by that
  // section, next to the 7:16 resonance (docs/levels/l2_orbits_tori.md). With one period per
  // section the solver says so instead of fitting a circle.
  ModulatedTorusOptions one;
  one.laps = 1;
  const ModulatedTorus cut = SolveModulatedTorus(TwoPointStructure(params), RpmToRadPerSecond(60.0),
                                                 HzToRadPerSecond(transient.precession_hz),
                                                 transient.state, one);
  INFO(cut.message);
  CHECK_FALSE(cut.converged);
  CHECK_THAT(cut.message, Contains("are no circle"));
  CHECK_THAT(cut.message, Contains("≈ 2/5: the section may cut the torus 5 times"));
  CHECK(std::abs(1.0 / cut.search_period - 124.37) < 0.1);
  // Left to choose (laps = 0), it takes the sections of 5 periods the points name, and there
  // they lie on one circle; its rotation number in the map's own angles is 7/16 or 1 − 7/16 (the
  // same torus, the circle traversed the other way, by the principal plane's orientation):
  // measured 0.4382 here (K = 8, the default search), 0.5617–0.5627 with K = 16 and 4 s searches.
  // (Newton is not run to the end: at K = 16 its Jacobian turned singular at that resonance's
  // edge, measured.)
  ModulatedTorusOptions automatic;
  automatic.newton.max_iterations = 1;
  automatic.lyapunov_iterates = 0;
  const ModulatedTorus five = SolveModulatedTorus(TwoPointStructure(params), RpmToRadPerSecond(60.0),
                                                  HzToRadPerSecond(transient.precession_hz),
                                                  transient.state, automatic);
  INFO(five.message);
  CHECK(five.laps == 5);
  CHECK_THAT(five.message, Contains("Newton from the transient's circle (5 × T"));
  const auto frame = std::make_shared<RubRotatingFrame>(TwoPointStructure(params),
                                                        HzToRadPerSecond(transient.precession_hz),
                                                        RpmToRadPerSecond(60.0));
  const InvariantCircleProblem circle(frame, automatic.harmonics, OrbitKind::kRelative);
  const double rho = circle.RotationNumber(five.u);
  CHECK(std::min(std::abs(rho - 7.0 / 16.0), std::abs(rho - 9.0 / 16.0)) < 2e-3);
}

TEST_CASE("case C(a) at 49 rpm, past the 2:5 tongue: the torus a transient settles on, solved by "
          "BDF on one period per section", "[modulated_orbit][torus]") {
  // Its continuation both ways (ContinueTransientTori) runs in tests/apps/tori_stage_test.cpp,
  // through the scene key that calls it, at K = 8.
  const TwoPointParams params = ThesisCaseCa();
  const RubSettledSpeed transient = Settle(params, 49.0, 8.0);
  REQUIRE(transient.settled);
  const ModulatedTorusOptions start = SettledTransientStart(16);
  const ModulatedTorus torus =
      SolveModulatedTorus(TwoPointStructure(params), RpmToRadPerSecond(49.0),
                          HzToRadPerSecond(transient.precession_hz), transient.state, start);
  INFO(torus.message);
  REQUIRE(torus.converged);
  // One period per section: the points of the map lie on one circle (measured ρ = 0.37893,
  // f₁ = 129.558 Hz, f₂ = 49.093 Hz, carrier 79.2833 Hz, the Fourier tail 0.013 at K = 16):
  // between the 2:5 tongue (48.851–48.876 rpm) and 3/8.
  CHECK(torus.laps == 1);
  CHECK(torus.rotation_number > 3.0 / 8.0);
  CHECK(torus.rotation_number < 2.0 / 5.0);
  CHECK(torus.first_hz == Approx(129.56).epsilon(0).margin(0.05));
  CHECK(torus.second_hz == Approx(torus.rotation_number * torus.first_hz));
  CHECK(torus.fourier_tail < 0.05);
  // The carrier is the transient's precession, which the sweep's spectrum found independently
  // (measured 0.0012 Hz apart).
  CHECK(std::abs(torus.carrier_hz - transient.precession_hz) < 0.01);
}

TEST_CASE(
    "case C(c) at 64 rpm, its left contact pressed by nanometres: the torus's circle "
    "converges in the contact chart, not in the state, and refines to K = 16",
    "[modulated_orbit][torus]") {
  // The stiff direction that breaks the circle in x (docs/studies/attractors.md): the left
  // contact is pressed by 0.5–2.5 nm (1.75e11 N/m) while the rotor moves by micrometres, so a
  // circle of 8 harmonics fitted in x puts its points tens of nanometres off the contact surface
  // and the map from them opens and closes the contact: the Jacobian is singular. In the contact
  // chart (gap and gap rate coordinates of their own) the same points, the same map (Gauss, 800
  // intervals per modulation period) converge.
  const TwoPointParams params = ThesisCaseCc();
  const RubSettledSpeed transient = Settle(params, 64.0, 8.0);
  REQUIRE(transient.settled);
  ModulatedTorusOptions start = SettledTransientStart(8);
  start.collocation_intervals = 800;
  auto solve = [&](CircleCoordinates coordinates) {
    start.coordinates = coordinates;
    return SolveModulatedTorus(TwoPointStructure(params), RpmToRadPerSecond(64.0),
                               HzToRadPerSecond(transient.precession_hz), transient.state, start);
  };
  const ModulatedTorus in_state = solve(CircleCoordinates::kState);
  INFO(in_state.message);
  CHECK(!in_state.converged);
  // In the chart, refined in K up to 16 from the K = 8 circle's images under the map (the
  // earlier start, a circle fitted to the transient's orbit, met a singular Jacobian at K = 16).
  start.max_harmonics = 16;
  const ModulatedTorus torus = solve(CircleCoordinates::kChart);
  INFO(torus.message);
  REQUIRE(torus.converged);
  CHECK(torus.harmonics == 16);
  REQUIRE(torus.by_harmonics.size() == 2);
  CHECK(torus.by_harmonics[0].harmonics == 8);
  CHECK(torus.by_harmonics[1].rotation_number == torus.rotation_number);
  // Measured K = 8: ρ 0.3053237 (tail 0.0022), K = 16: 0.3054948 (tail 0.0030, invariance error
  // 0.004): the circle still resolves the torus coarsely, so ρ moved by 1.7e-4.
  const auto folded = [](double rho) { return std::min(rho, 1.0 - rho); };
  CHECK(folded(torus.by_harmonics[0].rotation_number) == Approx(0.30532).margin(1e-4));
  CHECK(std::abs(folded(torus.rotation_number) - folded(torus.by_harmonics[0].rotation_number)) <
        1e-3);
  // (ρ or 1 − ρ: the circle's other orientation.) Measured f₁ = 139.150 Hz (K = 8: 139.161),
  // carrier 79.2123 Hz: the carrier the transient's precession (79.2118 Hz), found by the sweep's
  // spectrum.
  CHECK(torus.first_hz == Approx(139.16).epsilon(0).margin(0.05));
  CHECK(std::abs(torus.carrier_hz - transient.precession_hz) < 0.01);
  // Invariant under an independent map: CVODES BDF ≤ 5 at 1e-11 moves the K = 16 circle's points
  // by 2.6e-5 (scaled; as much as Gauss on 1600 intervals does: the 800-interval mesh's own
  // error), against 2.7e-9 under its own map.
  const auto frame = std::make_shared<RubRotatingFrame>(TwoPointStructure(params),
                                                        torus.frame_rate, RpmToRadPerSecond(64.0));
  IntegratorOptions bdf;
  bdf.relative_tolerance = bdf.absolute_tolerance = 1e-11;
  bdf.max_steps = 20000000;
  InvariantCircleProblem circle(frame, torus.harmonics, OrbitKind::kRelative, bdf,
                                CircleCoordinates::kChart);
  circle.SetPhaseReference(torus.u);
  Vector F;
  circle.Residual(torus.u, RpmToRadPerSecond(64.0), F);
  CHECK(F.cwiseQuotient(circle.ResidualScale()).lpNorm<Eigen::Infinity>() < 1e-4);
}

// A whip locked at p:laps shot on Gauss collocation of order 8: `segments` segments over the
// orbit, `steps` steps each; the search `search_seconds` long; Newton to 1e-8.
ModulatedOrbitOptions LockedOrbitOptions(int laps, int segments, long steps, double search_seconds) {
  ModulatedOrbitOptions options;
  options.laps = laps;
  options.search_duration = search_seconds;
  options.shooting.segments = segments;
  options.shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  options.shooting.integrator.collocation_stages = 4;
  options.shooting.integrator.collocation_steps = steps;
  options.newton.residual_tolerance = options.newton.step_tolerance = 1e-8;
  return options;
}

TEST_CASE("case C(a) at 49.4 rpm: the whip locked at 1:3 is a stable orbit of three modulation "
          "periods, stable from the tongue's edge (a fold) to a period doubling",
          "[modulated_orbit][torus]") {
  // The references are L3's, independent of shooting (results/thesis_C_a/attractor_49_50rpm:
  // Lyapunov exponents of the speed-up whip): a relative 2-torus at 49.1 and 49.2 rpm, a relative
  // periodic orbit (two zero exponents, the next −8 to −9 per s) at 49.3–49.6 rpm, chaotic from
  // 49.7 rpm. One modulation period later the transient's state is 7e-3 of itself away from its
  // start, three periods later 2.5e-5 (measured).
  const TwoPointParams params = ThesisCaseCa();
  const RubStructure structure = TwoPointStructure(params);
  const double omega = RpmToRadPerSecond(49.4);
  const RubSettledSpeed transient = Settle(params, 49.4, 8.0);
  REQUIRE(transient.settled);
  const ModulatedOrbitOptions options = LockedOrbitOptions(3, 6, 200, 1.0);
  const ModulatedOrbit orbit = SolveModulatedOrbit(structure, omega, HzToRadPerSecond(transient.precession_hz),
                                                   transient.state, options);
  INFO(orbit.message);
  REQUIRE(orbit.converged);
  CHECK(orbit.laps == 3);
  CHECK_THAT(orbit.message, Contains("(3 modulation periods)"));
  // Three periods of the slip's modulation (measured 125.66 Hz), the carrier the transient's.
  CHECK(3.0 / orbit.period == Approx(125.66).epsilon(0).margin(0.05));
  CHECK(std::abs(orbit.carrier_hz - transient.precession_hz) < 0.01);

  // Its family over 49.2–49.5 rpm: the stable orbit the transient found, a fold below it (the
  // 1:3 tongue's edge, between L3's torus at 49.2 and orbit at 49.3 rpm), a period doubling above
  // it (between L3's orbit at 49.3 and its chaos at 49.7 rpm); measured 49.24472 and 49.47091 rpm.
  // Located to the corrector's tolerance, not the engine's 1e-11 (over 49.15–49.55 rpm at 1e-11
  // the test took 121 s alone, so 60.5 s: measured).
  RubRotatingFrame frame(structure, orbit.frame_rate, omega);
  PeriodicOrbitBranchOptions family_options;
  family_options.lambda_min = RpmToRadPerSecond(49.2);
  family_options.lambda_max = RpmToRadPerSecond(49.5);
  family_options.shooting = options.shooting;
  family_options.continuation.corrector.residual_tolerance = 1e-8;
  family_options.continuation.location.residual_tolerance = 1e-8;
  family_options.continuation.location.step_tolerance = 1e-8;
  family_options.continuation.step.initial = 0.01;
  family_options.continuation.bounds.max_steps = 200;
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(frame, OrbitKind::kRelative, StartOf(orbit, omega), family_options);
  const Branch& b = family.branch;
  INFO(b.BriefReport());
  REQUIRE(b.points.front().StableFlag() >= 0);
  std::vector<double> folds, doublings;
  for (const SpecialPoint& p : b.special_points) {
    if (!p.converged) continue;
    if (p.type == SpecialPointType::kFold) folds.push_back(RadPerSecondToRpm(p.lambda));
    if (p.type == SpecialPointType::kPeriodDoubling) doublings.push_back(RadPerSecondToRpm(p.lambda));
  }
  REQUIRE(folds.size() == 1);
  REQUIRE(doublings.size() == 1);
  CHECK(folds[0] > 49.2);
  CHECK(folds[0] < 49.3);
  CHECK(doublings[0] > 49.3);
  CHECK(doublings[0] < 49.7);
  // Stable only between them (the saddle orbits past the fold lie there too, unstable).
  for (const BranchPoint& p : b.points) {
    if (p.StableFlag() != 1) continue;
    const double rpm = RadPerSecondToRpm(p.lambda);
    INFO("a stable orbit at " << rpm << " rpm");
    CHECK(rpm > folds[0] - 1e-4);
    CHECK(rpm < doublings[0] + 1e-4);
  }
  CHECK(std::count_if(b.points.begin(), b.points.end(),
                      [](const BranchPoint& p) { return p.StableFlag() == 1; }) >= 3);
}

TEST_CASE("case C(a) at 75 rpm: the whip locked at 3:7 is a stable orbit of seven modulation "
          "periods, its period the time-marched section's",
          "[modulated_orbit][torus]") {
  // The reference is time marching's (bench/section_return_bench at 75 rpm, Dormand–Prince at
  // 1e-9, results/bench/section_return.txt): the section of one modulation period, line
  // 124.4780 Hz, comes back after 7 periods to 3e-9 (scaled): a stable orbit of 7 periods.
  // The search continues the transient under Dormand–Prince (search_integrator): under the
  // shooting's default, BDF ≤ 2 at 1e-7, the stage's guess of 7T here came out 0.27 % long and
  // Newton failed.
  const TwoPointParams params = ThesisCaseCa();
  const RubStructure structure = TwoPointStructure(params);
  const double omega = RpmToRadPerSecond(75.0);
  const RubSettledSpeed transient = Settle(params, 75.0, 8.0);
  REQUIRE(transient.settled);
  ModulatedOrbitOptions options = LockedOrbitOptions(7, 7, 800, 4.0);
  IntegratorOptions dormand_prince;
  dormand_prince.method = IntegrationMethod::kDormandPrince;
  dormand_prince.relative_tolerance = dormand_prince.absolute_tolerance = 1e-9;
  dormand_prince.max_steps = 100000000;
  options.search_integrator = dormand_prince;
  const ModulatedOrbit orbit = SolveModulatedOrbit(
      structure, omega, HzToRadPerSecond(transient.precession_hz), transient.state, options);
  INFO(orbit.message);
  REQUIRE(orbit.converged);
  CHECK_THAT(orbit.message, Contains("(7 modulation periods)"));
  CHECK(7.0 / orbit.period == Approx(124.4780).epsilon(0).margin(0.001));
  RubRotatingFrame frame(structure, orbit.frame_rate, omega);
  ShootingProblem problem(frame, OrbitKind::kRelative, options.shooting);
  const Spectrum spectrum = problem.Stability(orbit.u, omega);
  REQUIRE(spectrum.valid);
  CHECK(std::abs(spectrum.values(0)) < 0.9);  // measured 0.7654
  CHECK(std::abs(spectrum.values(0)) > 0.5);
}

TEST_CASE("modulated orbit inputs outside their rules are rejected by name", "[modulated_orbit]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  const Vector x = Vector::Zero(s.States());
  ModulatedOrbitOptions o;
  o.search_duration = 0.0;
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, x, o), Contains("search_duration = 0"));
  o = {};
  o.search_rate = 100.0;
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, x, o), Contains("search_rate = 100"));
  o = {};
  o.harmonics = -1;
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, x, o), Contains("harmonics = -1"));
  o = {};
  o.search_integrator = IntegratorOptions{};
  o.search_integrator->relative_tolerance = -1.0;
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, x, o), Contains("relative_tolerance = -1"));
  o = {};
  o.laps = 0;
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, x, o), Contains("laps = 0: must be in 1 … 64"));
  CHECK_THROWS_WITH(StartOf(ModulatedOrbit{}, 6.0), Contains("did not converge"));
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, -1.0, x, {}), Contains("frame_rate = -1"));
  CHECK_THROWS_WITH(SolveModulatedOrbit(s, 6.0, 500.0, Vector::Zero(3), {}), Contains("3 entries"));
  // No modulation: a rotor at rest has a constant slip velocity.
  const ModulatedOrbit still = SolveModulatedOrbit(s, 6.0, 500.0, x, {});
  CHECK_FALSE(still.converged);
  CHECK_THAT(still.message, Contains("no modulation"));
  // Its family from a transient: no start, no family, the start's message kept.
  PeriodicOrbitBranchOptions family;
  family.lambda_min = 5.0;
  family.lambda_max = 7.0;
  const RubTransientOrbits none = ContinueTransientOrbits(s, 6.0, 500.0, x, {}, family, 10);
  CHECK_FALSE(none.start.converged);
  CHECK_THAT(none.start.message, Contains("no modulation"));
  CHECK(none.family.orbits.branch.points.empty());
  TwoPointParams unbalanced = ThesisCaseAa();
  unbalanced.imbalance = 3.43e-5;
  CHECK_THROWS_WITH(
      ContinueTransientOrbits(TwoPointStructure(unbalanced), 6.0, 500.0, x, {}, family, 10),
      Contains("ContinueTransientOrbits: imbalance = 3.43e-05 kg·m"));
}

TEST_CASE("modulated torus inputs outside their rules are rejected by name", "[modulated_orbit][torus]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  const Vector x = Vector::Zero(s.States());
  ModulatedTorusOptions o;
  o.harmonics = 0;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("harmonics = 0"));
  o = {};
  o.iterates = 10;  // K = 8 needs ≥ 18
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("iterates = 10: must be 0"));
  o = {};
  o.laps = 65;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("laps = 65: must be 0"));
  o = {};
  o.collocation_intervals = -1;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("collocation_intervals = -1"));
  o = {};
  o.final_collocation_intervals = -1;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o),
                    Contains("final_collocation_intervals = -1: must be ≥ 0"));
  o = {};
  o.approach = -1.0;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("approach = -1"));
  o = {};
  o.max_harmonics = 1001;  // the scene's rule: 0 … 1000
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o),
                    Contains("max_harmonics = 1001: must be in 0 … 1000"));
  o = {};
  o.refinement_images = {3, 0};
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o),
                    Contains("refinement_images = {3, 0}: must be one or more counts in 1 … 100"));
  o.refinement_images.clear();
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("refinement_images = {}"));
  o = {};
  o.search_rate = 10.0;
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, x, o), Contains("ModulatedTorusOptions.search_rate = 10"));
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, -1.0, x), Contains("frame_rate = -1"));
  CHECK_THROWS_WITH(SolveModulatedTorus(s, 6.0, 500.0, Vector::Zero(3)), Contains("3 entries"));
  TwoPointParams imbalanced = ThesisCaseAa();
  imbalanced.imbalance = 1e-4;
  CHECK_THROWS_WITH(SolveModulatedTorus(TwoPointStructure(imbalanced), 6.0, 500.0, x),
                    Contains("imbalance"));
  // No modulation: a rotor at rest has a constant slip velocity.
  o = {};
  o.approach = 0.0;
  const ModulatedTorus still = SolveModulatedTorus(s, 6.0, 500.0, x, o);
  CHECK_FALSE(still.converged);
  CHECK_THAT(still.message, Contains("no modulation"));
  CHECK(std::isnan(still.search_period));
}

}  // namespace
}  // namespace rubcont
