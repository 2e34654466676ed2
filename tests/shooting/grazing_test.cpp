// Grazing points of a periodic-orbit family, on the soft impact oscillator
// ẍ + c ẋ + x + k max(0, x − g) = F cos(w t) (models/textbook.h), whose free orbit is the linear
// response x = a(w) cos(w t − ψ) and grazes the stop where a(w) = g: closed-form frequencies.
// The family is continued in w from w = 0.5 (free) through the impacting resonance to w = 2
// (free again): both grazing points are located by the test function of Grazing
// (shooting/shooting.h), the family goes on through them, and the orbits between them strike the
// stop. The orbits past grazing are smooth only piecewise; how accurately a fixed Gauss mesh gets
// them is measured against CVODES under error control.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "models/textbook.h"
#include "models/units.h"
#include "shooting/orbit_branches.h"
#include "shooting/shooting.h"
#include "solvers/finite_difference.h"
#include "solvers/newton.h"
#include "solvers/ode.h"

namespace rubcont {
namespace {

ShootingOptions Cvodes() {
  ShootingOptions shooting;  // CVODES BDF, rtol = atol = 1e-10
  shooting.sensitivities_in_residual = true;
  return shooting;
}

ShootingOptions Gauss(long steps) {
  ShootingOptions shooting;
  shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  shooting.integrator.collocation_steps = steps;
  shooting.sensitivities_in_residual = true;
  return shooting;
}

// The damped soft impact oscillator whose family from w = 0.5 to 2 grazes twice.
SoftImpactParams DampedImpact() {
  SoftImpactParams params;
  params.damping = 0.3;
  params.stiffness = 1.0;
  return params;
}

// The branch's located grazing points, in order.
std::vector<SpecialPoint> GrazingPoints(const Branch& branch) {
  std::vector<SpecialPoint> grazing;
  for (const SpecialPoint& p : branch.special_points) {
    if (p.type == SpecialPointType::kGrazing) grazing.push_back(p);
  }
  return grazing;
}

// Newton on an orbit at w (any kind), to `tolerance`.
void SolveGrazing(ShootingProblem& problem, Vector& u, double w, double tolerance = 1e-12) {
  NewtonOptions newton;
  newton.residual_tolerance = tolerance;
  newton.step_tolerance = tolerance;
  const NewtonResult result =
      NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, w, F); },
                  [&](const Vector& v, Matrix& J) { problem.Jacobian(v, w, J); }, u, newton,
                  problem.Scale(), problem.ResidualScale());
  INFO(result.BriefReport());
  REQUIRE(result.Converged());
}

// The orbit at w from the free response's start (Newton; the start is exact off the stop).
Vector SolveOrbit(SoftImpactOscillator& system, ShootingProblem& problem, double w) {
  system.SetParameter(w);
  Vector u = problem.InitialGuess(system.FreeState(), 0.0, w);
  SolveGrazing(problem, u, w, 1e-11);
  return u;
}

OrbitTestFunction Touchdown(double gap) {
  return Grazing([gap](ConstVectorRef x) { return x(0) - gap; }, GrazingSide::kTouchdown,
                 "touchdown");
}

TEST_CASE("soft impact oscillator: the linear response grazes the stop at the closed-form "
          "frequencies",
          "[grazing][model]") {
  SoftImpactOscillator system;
  const std::vector<double> grazing = system.GrazingFrequencies();
  REQUIRE(grazing.size() == 2);
  // s² − 1.99 s + 0.75 = 0 for c = 0.1, F/g = 0.5.
  const double root = std::sqrt(1.99 * 1.99 - 3.0);
  CHECK(grazing[0] == Approx(std::sqrt(0.5 * (1.99 - root))).epsilon(1e-14));
  CHECK(grazing[1] == Approx(std::sqrt(0.5 * (1.99 + root))).epsilon(1e-14));
  for (const double w : grazing) {
    system.SetParameter(w);
    CHECK(system.FreeAmplitude() == Approx(system.params().gap).epsilon(1e-13));
  }
  SoftImpactParams weak;
  weak.force = 0.05;  // peak gain 1/c = 10: amplitude 0.5 < g at resonance
  CHECK(SoftImpactOscillator(weak).GrazingFrequencies().empty());
  SoftImpactParams bad;
  bad.gap = 0.0;
  CHECK_THROWS_WITH(SoftImpactOscillator(bad), "SoftImpactParams.gap = 0: must be positive");
}

TEST_CASE("grazing test function: the sampled extremum of a free orbit equals a − g, to "
          "the accuracy its samples allow",
          "[grazing][shooting]") {
  SoftImpactOscillator system;
  const double w = 0.6;
  system.SetParameter(w);
  const double exact = system.FreeAmplitude() - system.params().gap;
  // Both sides on the same orbit: max(x − g) = a − g and min(x + g) = g − a.
  const OrbitTestFunction lift_off =
      Grazing([](ConstVectorRef x) { return x(0) + 1.0; }, GrazingSide::kLiftOff, "lift_off");
  for (const int samples : {16, 64, 256}) {
    CAPTURE(samples);
    ShootingOptions shooting = Cvodes();
    shooting.samples_per_segment = samples;
    ShootingProblem problem(system, OrbitKind::kForced, shooting);
    problem.SetTestFunctions({Touchdown(system.params().gap), lift_off});
    REQUIRE(problem.TestFunctionNames() == std::vector<std::string>{"touchdown", "lift_off"});
    CHECK(problem.TestFunctionType(0) == SpecialPointType::kGrazing);
    const Vector u = SolveOrbit(system, problem, w);
    const Vector tests = problem.TestFunctions(u, w);
    // A parabola through three samples near the peak of a cos errs by O((wΔt)⁴): measured
    // 1.2e-4 at 16 samples, 2.1e-8 / 2.5e-8 at 64 and 1.5e-9 / 5.8e-9 at 256 (the last at the
    // integration's own error, rtol 1e-10).
    const double tolerance = samples == 16 ? 2e-4 : samples == 64 ? 1e-7 : 1e-8;
    CHECK(tests(0) == Approx(exact).epsilon(0).margin(tolerance));
    CHECK(tests(1) == Approx(-exact).epsilon(0).margin(tolerance));
  }
}

TEST_CASE("grazing test function: with Gauss collocation it reads 4 samples per collocation step "
          "however few the measures read",
          "[grazing][shooting]") {
  SoftImpactOscillator system;
  const double w = 0.6;
  system.SetParameter(w);
  const double exact = system.FreeAmplitude() - system.params().gap;
  ShootingOptions shooting = Gauss(64);
  shooting.samples_per_segment = 16;  // 1.2e-4 of error in the parabola's extremum (above)
  ShootingProblem problem(system, OrbitKind::kForced, shooting);
  problem.SetTestFunctions({Touchdown(system.params().gap)});
  CHECK(problem.TestSamplesPerSegment() == 4 * 64);
  const Vector u = SolveOrbit(system, problem, w);
  // The measures keep their 16 samples; the test function reads 256 (error 1.5e-9 above; Gauss of
  // order 8 on 64 steps adds less).
  CHECK(problem.Orbit(u, w).times.size() == 16 + 1);
  CHECK(problem.TestFunctions(u, w)(0) == Approx(exact).epsilon(0).margin(1e-8));
  CHECK(problem.TestOrbit(u, w).times.size() == 256 + 1);
  // Without Gauss collocation the test functions read the measures' samples.
  ShootingOptions cvodes = Cvodes();
  cvodes.samples_per_segment = 16;
  CHECK(ShootingProblem(system, OrbitKind::kForced, cvodes).TestSamplesPerSegment() == 16);
}

TEST_CASE("soft impact oscillator over w in [0.5, 2]: both grazing points located at the "
          "closed-form frequencies, the family continued through them, striking between",
          "[grazing][shooting][branch]") {
  const SoftImpactParams params = DampedImpact();
  SoftImpactOscillator system(params);
  const std::vector<double> expected = system.GrazingFrequencies();
  REQUIRE(expected.size() == 2);

  for (const long gauss_steps : {400L, 0L}) {
    CAPTURE(gauss_steps);
    ShootingOptions shooting = gauss_steps > 0 ? Gauss(gauss_steps) : Cvodes();
    shooting.samples_per_segment = 256;
    system.SetParameter(0.5);
    ShootingProblem problem(system, OrbitKind::kForced, shooting);
    problem.SetTestFunctions({Touchdown(params.gap)});
    const Vector u0 = problem.InitialGuess(system.FreeState(), 0.0, 0.5);

    ContinuationOptions options;
    options.bounds.lambda_min = 0.5;
    options.bounds.lambda_max = 2.0;
    options.detect.stability = true;
    options.step.max = 0.5;
    options.step.target_iterations = 5;
    const Branch branch = Continue(problem, u0, 0.5, options);
    INFO(branch.BriefReport() << " — " << branch.message);
    REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);

    const std::vector<SpecialPoint> grazing = GrazingPoints(branch);
    REQUIRE(grazing.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) {
      CAPTURE(k);
      const SpecialPoint& p = grazing[k];
      CHECK(p.converged);
      CHECK(p.label == "touchdown");
      // Located on the sampled extremum (256 samples: 4e-10 in amplitude; da/dw ≈ 2.5 and
      // −1.6 there) and the branch's location tolerance.
      CHECK(p.lambda == Approx(expected[k]).epsilon(0).margin(1e-8));
      // The orbit there is the linear response of amplitude g.
      system.SetParameter(p.lambda);
      const Vector free = system.FreeState();
      CHECK(p.u(0) == Approx(free(0)).epsilon(0).margin(1e-8));
      CHECK(p.u(1) == Approx(free(1)).epsilon(0).margin(1e-8));
    }
    // Between the grazing points the orbits strike the stop; outside they do not.
    const Vector touch = branch.Measure("max_x");
    for (Index i = 0; i < branch.Size(); ++i) {
      const double w = branch.points[i].lambda;
      const bool inside = i > grazing[0].index && i <= grazing[1].index;
      CAPTURE(w, touch(i));
      CHECK((touch(i) > params.gap) == inside);
    }
  }
}

TEST_CASE("stop_at_grazing: the family ends with status kGrazing at its first located grazing, "
          "the grazing orbit its last, where without it it goes on through both",
          "[grazing][shooting][branch]") {
  const SoftImpactParams params = DampedImpact();
  SoftImpactOscillator system(params);
  const std::vector<double> expected = system.GrazingFrequencies();
  REQUIRE(expected.size() == 2);
  system.SetParameter(0.5);
  OrbitStart start;
  start.x0 = system.FreeState();
  start.lambda = 0.5;
  start.valid = true;
  PeriodicOrbitBranchOptions options;
  options.lambda_min = 0.5;
  options.lambda_max = 2.0;
  options.shooting = Gauss(400);
  options.shooting.samples_per_segment = 256;
  options.test_functions = {Touchdown(params.gap)};
  options.continuation.step.max = 0.5;
  options.continuation.step.target_iterations = 5;
  for (const bool stop : {true, false}) {
    CAPTURE(stop);
    options.stop_at_grazing = stop;
    const PeriodicOrbitBranch family = ContinuePeriodicOrbits(system, OrbitKind::kForced, start, options);
    const Branch& branch = family.branch;
    INFO(branch.BriefReport() << " — " << branch.message);
    const std::vector<SpecialPoint> grazing = GrazingPoints(branch);
    if (!stop) {
      CHECK(branch.status == BranchStatus::kReachedLambdaBound);
      CHECK(grazing.size() == 2);
      continue;
    }
    REQUIRE(branch.status == BranchStatus::kGrazing);
    CHECK_FALSE(IsFailure(branch.status));
    REQUIRE(grazing.size() == 1);
    CHECK(grazing[0].converged);
    CHECK(grazing[0].lambda == Approx(expected[0]).epsilon(0).margin(1e-8));
    CHECK_THAT(branch.message, Catch::Contains("grazing touchdown"));
    // The step that met it is cut there: the last orbit is the grazing orbit, and nothing past
    // it is on the branch.
    CHECK(grazing[0].index + 2 == static_cast<Index>(branch.points.size()));
    CHECK(branch.points.back().lambda == grazing[0].lambda);
    CHECK(branch.points.back().u == grazing[0].u);
    for (const BranchPoint& p : branch.points) CHECK(p.lambda <= grazing[0].lambda);
    for (const SpecialPoint& p : branch.special_points) CHECK(p.lambda <= grazing[0].lambda);
  }
}

TEST_CASE("soft impact oscillator past grazing: a fixed Gauss mesh converges at a lower order "
          "on the striking orbit than on the free one",
          "[grazing][shooting][collocation]") {
  SoftImpactOscillator system;
  ShootingProblem reference_problem(system, OrbitKind::kForced, [] {
    ShootingOptions shooting = Cvodes();
    shooting.integrator.relative_tolerance = shooting.integrator.absolute_tolerance = 1e-13;
    return shooting;
  }());
  // w = 0.6: free (a = 0.78 g); w = 0.9: striking (the linear response would reach 2.6 g).
  for (const double w : {0.6, 0.9}) {
    CAPTURE(w);
    const Vector reference = SolveOrbit(system, reference_problem, w);
    std::vector<double> errors;
    for (const long steps : {25L, 50L, 100L, 200L}) {
      ShootingProblem problem(system, OrbitKind::kForced, Gauss(steps));
      const Vector u = SolveOrbit(system, problem, w);
      errors.push_back((u - reference).lpNorm<Eigen::Infinity>());
    }
    CAPTURE(errors);
    if (w < 0.7) {
      // Order 8: at the reference's own error (1e-12) from 25 steps on.
      CHECK(errors.front() < 1e-10);
    } else {
      // Two kinks per period inside mesh intervals: measured 9.8e-4, 3.0e-4, 3.1e-5, 1.2e-6,
      // order 3.2 over the range, uneven as the kinks move relative to the mesh.
      const double order = std::log2(errors.front() / errors.back()) / 3.0;
      CHECK(order > 2.5);
      CHECK(order < 4.5);
      CHECK(errors.back() > 1e-7);
    }
  }
}

// The striking orbit at w as an autonomous orbit of AutonomousSoftImpactOscillator, by Gauss
// collocation on 3·steps steps: with `events`, three segments of `steps` whose boundaries 1 and 2
// sit on the stop (touchdown and lift-off, their fractions unknowns; WithEventBoundaries places
// them), else one segment, uniform. Returns its largest error against the forced reference orbit
// (`reference`, x(0) of the forced orbit solved by CVODES at 1e-13): the state at its start
// against the reference's state at the same forcing phase, and its period against 2π/w.
double EventMeshError(double w, const Vector& reference, long steps, bool events) {
  SoftImpactParams params;
  params.frequency = w;
  AutonomousSoftImpactOscillator system(params);
  const double T = kTwoPi / w;
  // The orbit by single shooting on 3·steps uniform steps, from the forced reference's start
  // (forcing phase 0).
  ShootingOptions shooting = Gauss(3 * steps);
  ShootingProblem uniform(system, OrbitKind::kAutonomous, shooting);
  const Vector x0 = (Vector(4) << reference(0), reference(1), 1.0, 0.0).finished();
  Vector u = uniform.InitialGuess(x0, T, w);
  SolveGrazing(uniform, u, w);
  ShootingProblem* problem = &uniform;
  std::unique_ptr<ShootingProblem> on_stop;
  if (events) {
    // Its two crossings of the stop become boundaries: three segments of `steps` each.
    shooting.integrator.collocation_steps = steps;
    const EventMesh mesh = WithEventBoundaries(system, OrbitKind::kAutonomous, shooting, u, w);
    INFO(mesh.message);
    REQUIRE(mesh.ok);
    CHECK(mesh.zeros == 2);
    REQUIRE(mesh.options.event_boundaries.size() == 2);
    on_stop = std::make_unique<ShootingProblem>(system, OrbitKind::kAutonomous, mesh.options);
    problem = on_stop.get();
    u = problem->InitialGuess(uniform.SegmentStart(u, 0), uniform.Period(u, w), w);
    SolveGrazing(*problem, u, w);
    // The event rows and columns, and ∂/∂T from the discrete map's dxdt1, against differences.
    Matrix J;
    problem->Jacobian(u, w, J);
    const Vector scale = problem->Scale();
    // Entries below 1e-6 of their row's largest are compared against that floor: ∂p/∂T is ~1e-11
    // where the start's forcing phase is 0, at the differences' round-off (ε/h ≈ 2e-11 of the row;
    // measured errors up to 1.9e-5 of the floor there, 1.2e-6 elsewhere).
    const JacobianCheck check = CheckJacobian(
        [&](const Vector& v, Vector& F) { problem->Residual(v, w, F); }, u, J, 1e-4, &scale, 1e-6);
    CAPTURE(check.max_error, check.worst_row, check.worst_col);
    CHECK(check.ok);
  }
  // The forcing phase of the solution's start, and the forced reference's state there (backwards
  // from 0 when the phase is negative: no kink crossed on the way).
  SoftImpactOscillator forced(params);
  IntegratorOptions accurate;
  accurate.relative_tolerance = accurate.absolute_tolerance = 1e-13;
  OdeIntegrator integrator(forced, accurate);
  const double phase = std::atan2(u(3), u(2)) / w;
  Vector shifted(2);
  REQUIRE(integrator.Integrate(0.0, reference, phase, shifted)
              .Succeeded());
  const double state_error = std::max(std::abs(u(0) - shifted(0)), std::abs(u(1) - shifted(1)));
  return std::max(state_error, std::abs(problem->Period(u, w) - T) / T);
}

TEST_CASE("soft impact oscillator past grazing: segment boundaries on the stop give Gauss "
          "collocation back its order",
          "[grazing][shooting][collocation]") {
  const double w = 0.9;  // striking: the orbit crosses x = g twice per period
  SoftImpactOscillator forced;
  forced.SetParameter(w);
  ShootingProblem reference_problem(forced, OrbitKind::kForced, [] {
    ShootingOptions shooting = Cvodes();
    shooting.integrator.relative_tolerance = shooting.integrator.absolute_tolerance = 1e-13;
    return shooting;
  }());
  const Vector reference = SolveOrbit(forced, reference_problem, w);
  std::vector<double> uniform, events;
  for (const long steps : {4L, 8L, 16L, 32L}) {
    uniform.push_back(EventMeshError(w, reference, steps, false));
    events.push_back(EventMeshError(w, reference, steps, true));
  }
  CAPTURE(uniform, events);
  // On the stop: order 8 down to the reference's own error (measured 4.5e-7, 2.2e-9, 1.0e-11,
  // 1.4e-12 at 4, 8, 16, 32 steps per segment: orders 7.6 and 7.8, then the floor).
  CHECK(std::log2(events[0] / events[1]) > 7.0);
  CHECK(std::log2(events[1] / events[2]) > 7.0);
  CHECK(events[2] < 1e-10);
  // Uniform, 3·steps in one segment: the kinks inside mesh intervals (measured 7.7e-3, 9.7e-4,
  // 7.5e-4, 1.3e-4: order 2 over the range, uneven as the kinks move relative to the mesh).
  for (std::size_t k = 0; k < uniform.size(); ++k) CHECK(uniform[k] > 1e3 * events[k]);
  CHECK(std::log2(uniform.front() / uniform.back()) / 3.0 < 3.0);
}

TEST_CASE("soft impact oscillator on event boundaries: the striking family continued both ways "
          "ends where its contact shrinks to nothing, at the closed-form grazing frequencies",
          "[grazing][shooting][branch]") {
  SoftImpactParams params = DampedImpact();
  params.frequency = 0.9;
  AutonomousSoftImpactOscillator system(params);
  const std::vector<double> grazing = SoftImpactOscillator(params).GrazingFrequencies();
  REQUIRE(grazing.size() == 2);
  // The striking orbit at w = 0.9 on a uniform mesh, then its switches as boundaries.
  const double w = params.frequency;
  ShootingOptions shooting = Gauss(60);
  ShootingProblem uniform(system, OrbitKind::kAutonomous, shooting);
  const Vector free = SoftImpactOscillator(params).FreeState();
  Vector u = uniform.InitialGuess((Vector(4) << free(0), free(1), 1.0, 0.0).finished(),
                                  kTwoPi / w, w);
  SolveGrazing(uniform, u, w);
  const EventMesh mesh = WithEventBoundaries(system, OrbitKind::kAutonomous, shooting, u, w);
  INFO(mesh.message);
  REQUIRE(mesh.ok);
  REQUIRE(mesh.options.event_boundaries.size() == 2);
  ShootingProblem problem(system, OrbitKind::kAutonomous, mesh.options);
  Vector u0 = problem.InitialGuess(uniform.SegmentStart(u, 0), uniform.Period(u, w), w);
  SolveGrazing(problem, u0, w);
  for (const int side : {+1, -1}) {
    CAPTURE(side);
    ContinuationOptions options;
    options.bounds.lambda_min = 0.3;
    options.bounds.lambda_max = 2.0;
    options.direction = side;
    options.step.max = 0.05;
    const Branch branch = Continue(problem, u0, w, options);
    INFO(branch.BriefReport() << " — " << branch.message);
    // The phase between the two switches (segment 1) shrinks to nothing at grazing: located as
    // the event "switches_1_2", where the family ends. (The engine reports a branch point there
    // too: with the phase at zero length the second switch's equation is the first's, so orbits
    // with both boundaries at one crossing solve the equations as well and meet the family.)
    REQUIRE(branch.status == BranchStatus::kSwitchRefused);
    const SpecialPoint& end = branch.special_points.back();
    CHECK(end.type == SpecialPointType::kEvent);
    CHECK(end.label == "switches_1_2");
    CHECK(end.converged);
    // Measured 2.1e-10 and 1.3e-11 from the closed form.
    CHECK(end.lambda == Approx(grazing[side > 0 ? 1 : 0]).epsilon(0).margin(1e-9));
    const Vector margins = problem.EventFunctions(branch.points.back().u, end.lambda);
    REQUIRE(margins.size() == 1);  // segment 1; the other phase wraps round t = 0
    CHECK(std::abs(margins(0)) < 1e-6);
    // Every orbit before the end strikes: the phase has positive length.
    for (std::size_t i = 0; i + 1 < branch.points.size(); ++i) {
      const BranchPoint& p = branch.points[i];
      CHECK(problem.EventFunctions(p.u, p.lambda)(0) > 0.0);
    }
  }
}

TEST_CASE("event boundaries: refused by name on a forced orbit, at an end of the period, twice, or "
          "on a surface the system lacks",
          "[grazing][shooting][errors]") {
  SoftImpactOscillator forced;
  AutonomousSoftImpactOscillator autonomous;
  ShootingOptions shooting;
  shooting.segments = 3;
  shooting.event_boundaries = {{1, 0}};
  CHECK_THROWS_WITH(ShootingProblem(forced, OrbitKind::kForced, shooting),
                    "ShootingProblem: event_boundaries need kind kAutonomous or kRelative, not "
                    "kForced");
  shooting.event_boundaries = {{3, 0}};
  CHECK_THROWS_WITH(Validate(shooting),
                    "ShootingOptions.event_boundaries[0].boundary = 3: must lie in [1, "
                    "segments − 1 = 2]");
  shooting.event_boundaries = {{2, 0}, {2, 0}};
  CHECK_THROWS_WITH(Validate(shooting),
                    "ShootingOptions.event_boundaries[1].boundary = 2: already "
                    "event_boundaries[0]'s");
  shooting.event_boundaries = {{1, 1}};
  CHECK_THROWS_WITH(ShootingProblem(autonomous, OrbitKind::kAutonomous, shooting),
                    "ShootingProblem: event boundary 1 is on surface 1, but the system has 1 "
                    "switching functions");
  shooting.event_boundaries = {{1, 0}, {2, 0}};
  ShootingProblem problem(autonomous, OrbitKind::kAutonomous, shooting);
  CHECK(problem.Dimension() == 3 * 4 + 1 + 2);
  const Vector u = problem.Pack(Matrix::Ones(4, 3), 7.0);
  CHECK(problem.Mesh(u) == std::vector<double>{0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0});
}

}  // namespace
}  // namespace rubcont
