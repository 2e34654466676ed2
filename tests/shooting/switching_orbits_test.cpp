// A family followed across its switching patterns (shooting/switching_orbits.h), on the soft impact
// oscillator made autonomous (models/textbook.h), whose free orbit grazes the stop at closed-form
// frequencies: from w = 0.5 (free) on its own mesh, on its switches between the grazing points,
// and free again to w = 2.
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "models/units.h"
#include "shooting/switching_orbits.h"
#include "solvers/newton.h"
#include "solvers/ode.h"

namespace rubcont {
namespace {

// The free linear response at the params' w, as the start of its autonomous orbit (forcing
// phase 0 at t = 0).
OrbitStart FreeStart(const SoftImpactParams& params) {
  const Vector free = SoftImpactOscillator(params).FreeState();
  OrbitStart start;
  start.x0 = (Vector(4) << free(0), free(1), 1.0, 0.0).finished();
  start.period = kTwoPi / params.frequency;
  start.lambda = params.frequency;
  start.valid = true;
  return start;
}

// Gauss collocation, 2 segments of 60 steps, over [lambda_min, lambda_max].
SwitchingOrbitOptions GaussAcross(double lambda_min, double lambda_max) {
  SwitchingOrbitOptions options;
  options.family.lambda_min = lambda_min;
  options.family.lambda_max = lambda_max;
  options.family.shooting.segments = 2;
  options.family.shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  options.family.shooting.integrator.collocation_steps = 60;
  options.family.shooting.sensitivities_in_residual = true;
  options.family.continuation.step.max = 0.5;
  return options;
}

TEST_CASE("soft impact oscillator across its switches: free, striking on its switches between the "
          "closed-form grazing frequencies, free again",
          "[switching][shooting][branch]") {
  SoftImpactParams params;
  params.damping = 0.3;
  params.stiffness = 1.0;
  params.frequency = 0.5;
  AutonomousSoftImpactOscillator system(params);
  const std::vector<double> grazing = SoftImpactOscillator(params).GrazingFrequencies();
  REQUIRE(grazing.size() == 2);
  const OrbitStart start = FreeStart(params);
  SwitchingOrbitOptions options = GaussAcross(0.5, 2.0);
  options.family.shooting.samples_per_segment = 256;  // the touchdown test's extremum
  options.family.test_functions = {Grazing([&](ConstVectorRef x) { return x(0) - params.gap; },
                                           GrazingSide::kTouchdown, "touchdown")};
  const SwitchingOrbitFamily family =
      ContinueAcrossSwitches(system, OrbitKind::kAutonomous, start, options);
  INFO(family.message);
  REQUIRE(family.pieces.size() == 3);
  for (const SwitchingOrbitPiece& piece : family.pieces) {
    CAPTURE(piece.end);
    CHECK(piece.family.branch.points.size() >= 3);
  }
  CHECK(family.pieces[0].switches == 0);
  CHECK(family.pieces[1].switches == 2);
  CHECK(family.pieces[2].switches == 0);
  CHECK(family.pieces[2].family.branch.status == BranchStatus::kReachedLambdaBound);
  CHECK(family.pieces[2].family.branch.points.back().lambda == Approx(2.0));

  // The free family's touchdown, located by its test function, and the striking family's end,
  // where its contact phase vanishes: both at the closed form (measured 1.9e-10 and 1.7e-9, the
  // latter the engine's event location).
  const Branch& free = family.pieces[0].family.branch;
  const SpecialPoint* touchdown = nullptr;
  for (const SpecialPoint& p : free.special_points) {
    if (p.type == SpecialPointType::kGrazing) touchdown = &p;
  }
  REQUIRE(touchdown != nullptr);
  CHECK(touchdown->converged);
  CHECK(touchdown->lambda == Approx(grazing[0]).epsilon(0).margin(1e-8));
  const Branch& striking = family.pieces[1].family.branch;
  REQUIRE(striking.status == BranchStatus::kSwitchRefused);
  CHECK(striking.special_points.back().type == SpecialPointType::kEvent);
  CHECK(striking.special_points.back().lambda == Approx(grazing[1]).epsilon(0).margin(1e-8));
  CHECK(family.pieces[2].family.branch.points.front().lambda ==
        Approx(striking.points.back().lambda));

  // Off the stop outside, on it between (the free piece's last orbit is its first to cross).
  const auto max_x = [](const Branch& b, std::size_t i) {
    return b.points[i].measures(b.MeasureIndex("max_x"));
  };
  for (std::size_t i = 0; i + 1 < free.points.size(); ++i) CHECK(max_x(free, i) < params.gap);
  CHECK(max_x(free, free.points.size() - 1) > params.gap);
  for (std::size_t i = 0; i + 1 < striking.points.size(); ++i) {
    CHECK(max_x(striking, i) > params.gap);
  }
  const Branch& again = family.pieces[2].family.branch;
  for (std::size_t i = 1; i < again.points.size(); ++i) CHECK(max_x(again, i) < params.gap);

  // A striking orbit in the middle against the forced oscillator's, solved by CVODES at 1e-12
  // with restarts at the stop: its start against the forced orbit at the same forcing phase
  // (measured 4.8e-10 at w = 1.0118, 60 Gauss steps per segment).
  const BranchPoint& middle = striking.points[striking.points.size() / 2];
  SoftImpactParams at = params;
  at.frequency = middle.lambda;
  SoftImpactOscillator forced(at);
  ShootingOptions accurate;
  accurate.integrator.relative_tolerance = accurate.integrator.absolute_tolerance = 1e-12;
  ShootingProblem reference(forced, OrbitKind::kForced, accurate);
  const double phase = std::atan2(middle.u(3), middle.u(2)) / middle.lambda;
  // The forced orbit's state at t = 0 is the autonomous one's at forcing phase 0: start the guess
  // there by integrating the autonomous start back by its phase.
  OdeIntegrator back(forced, accurate.integrator);
  Vector x0(2);
  REQUIRE(back.Integrate(phase, middle.u.head(2), 0.0, x0).Succeeded());
  Vector v = reference.InitialGuess(x0, 0.0, middle.lambda);
  NewtonOptions newton;
  newton.residual_tolerance = newton.step_tolerance = 1e-11;
  const NewtonResult solved = NewtonSolve(
      [&](const Vector& u, Vector& F) { reference.Residual(u, middle.lambda, F); },
      [&](const Vector& u, Matrix& J) { reference.Jacobian(u, middle.lambda, J); }, v, newton,
      reference.Scale(), reference.ResidualScale());
  REQUIRE(solved.Converged());
  Vector shifted(2);
  REQUIRE(back.Integrate(0.0, v, phase, shifted).Succeeded());
  CAPTURE(middle.lambda, (shifted - middle.u.head(2)).lpNorm<Eigen::Infinity>());
  CHECK((shifted - middle.u.head(2)).lpNorm<Eigen::Infinity>() < 1e-8);
}

TEST_CASE("hardening soft impact oscillator across its switches: back free past the grazing fold, "
          "and a period doubling on switches doubled with its switches",
          "[switching][shooting][branch]") {
  SoftImpactParams params;  // c = 0.1, k = 10, F = 0.5: the striking orbits fold at w ≈ 1.41
  params.frequency = 0.3;
  AutonomousSoftImpactOscillator system(params);
  const std::vector<double> grazing = SoftImpactOscillator(params).GrazingFrequencies();
  REQUIRE(grazing.size() == 2);
  const OrbitStart start = FreeStart(params);
  const SwitchingOrbitOptions options = GaussAcross(0.3, 3.0);
  const SwitchingOrbitFamily family =
      ContinueAcrossSwitches(system, OrbitKind::kAutonomous, start, options);
  INFO(family.message);
  // Free, striking up to the fold and back to the upper grazing point, where the striking
  // orbits and the free ones both lie above it (a grazing fold): the free piece goes on upwards,
  // not back down into the striking range (measured: 3 pieces, to w = 3).
  REQUIRE(family.pieces.size() == 3);
  const Branch& striking = family.pieces[1].family.branch;
  CHECK(family.pieces[1].switches == 2);
  CHECK(striking.status == BranchStatus::kSwitchRefused);
  std::vector<double> folds, doublings;
  for (const SpecialPoint& p : striking.special_points) {
    if (p.type == SpecialPointType::kFold) folds.push_back(p.lambda);
    if (p.type == SpecialPointType::kPeriodDoubling) doublings.push_back(p.lambda);
  }
  REQUIRE(!folds.empty());
  CHECK(*std::max_element(folds.begin(), folds.end()) > 1.4);  // measured 1.409628
  // A fold at the grazing point, at the closed form (measured 1.218574 against 1.2185744; the
  // family turns once more just below it, at 1.218326).
  double nearest = folds.front();
  for (const double f : folds) {
    if (std::abs(f - grazing[1]) < std::abs(nearest - grazing[1])) nearest = f;
  }
  CHECK(nearest == Approx(grazing[1]).epsilon(0).margin(1e-5));
  const Branch& free = family.pieces[2].family.branch;
  CHECK(free.status == BranchStatus::kReachedLambdaBound);
  CHECK(free.points.back().lambda == Approx(3.0));
  CHECK(free.points[1].lambda > free.points[0].lambda);

  // Two period doublings on switches (measured 0.710932 and 0.855469); the doubled family from
  // the second has twice the segments and both impacts as boundaries, and ends where one of its
  // two impacts grazes (measured 0.852637).
  REQUIRE(doublings.size() == 2);
  std::size_t index = 0;
  for (std::size_t k = 0; k < striking.special_points.size(); ++k) {
    if (striking.special_points[k].type == SpecialPointType::kPeriodDoubling &&
        striking.special_points[k].lambda > 0.8) {
      index = k;
    }
  }
  PeriodicOrbitBranchOptions around = options.family;
  around.lambda_min = 0.6;
  around.lambda_max = 1.0;
  around.continuation.bounds.max_steps = 100;
  const OrbitPeriodDoubling doubled =
      ContinueOrbitsFromPeriodDoubling(system, family.pieces[1].family, index, around);
  INFO(doubled.message);
  REQUIRE(doubled.ok);
  CHECK(doubled.multiplier == Approx(-1.0).epsilon(0).margin(1e-4));
  CHECK(doubled.branch.shooting.segments == 2 * family.pieces[1].family.shooting.segments);
  CHECK(doubled.branch.shooting.event_boundaries.size() == 4);
  CHECK(doubled.branch.branch.status == BranchStatus::kSwitchRefused);
  CHECK(doubled.branch.branch.points.back().lambda < striking.special_points[index].lambda);
}

TEST_CASE("ContinueAcrossSwitches: options and kinds refused by name", "[switching][errors]") {
  AutonomousSoftImpactOscillator system;
  OrbitStart start;
  start.x0 = (Vector(4) << 0.5, 0.0, 1.0, 0.0).finished();
  start.period = kTwoPi / 0.5;
  start.lambda = 0.5;
  start.valid = true;
  SwitchingOrbitOptions options;
  options.family.lambda_min = 0.5;
  options.family.lambda_max = 2.0;
  options.direction = 0;
  CHECK_THROWS_WITH(ContinueAcrossSwitches(system, OrbitKind::kAutonomous, start, options),
                    "SwitchingOrbitOptions.direction = 0: must be +1 or -1");
  options.direction = 1;
  options.family.shooting.segments = 2;
  options.family.shooting.event_boundaries = {{1, 0}};
  CHECK_THROWS_WITH(ContinueAcrossSwitches(system, OrbitKind::kAutonomous, start, options),
                    Catch::Contains("event_boundaries: must be empty"));
  options.family.shooting.event_boundaries.clear();
  SoftImpactOscillator forced;
  CHECK_THROWS_WITH(ContinueAcrossSwitches(forced, OrbitKind::kForced, start, options),
                    Catch::Contains("kind kForced cannot have segment boundaries on switches"));
}

}  // namespace
}  // namespace rubcont
