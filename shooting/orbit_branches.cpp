#include "shooting/orbit_branches.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include <fmt/format.h>

#include "continuation/continuation.h"

namespace rubcont {

namespace {

// κ applied to every segment start of u (T and φ are invariant).
Vector MirrorStarts(const OdeSystem& system, const ShootingProblem& problem, const Vector& u) {
  Vector mirrored = u;
  const Index n = problem.StateDimension();
  for (Index i = 0; i < problem.SegmentCount(); ++i) {
    VectorRef block = mirrored.segment(i * n, n);
    system.Mirror(block);
  }
  return mirrored;
}

// MirrorAsymmetryOf the segment starts of u.
double StartsAsymmetry(const OdeSystem& system, const ShootingProblem& problem, const Vector& u) {
  return MirrorAsymmetryOf(system, Eigen::Map<const Matrix>(u.data(), problem.StateDimension(),
                                                            problem.SegmentCount()));
}

// The κ-odd part (u − κu)/2 of the segment starts of u (or of a direction), scaled by the problem.
Vector OddPart(const OdeSystem& system, const ShootingProblem& problem, const Vector& u) {
  const Index states = problem.StateDimension() * problem.SegmentCount();
  return 0.5 * (u - MirrorStarts(system, problem, u)).head(states).cwiseQuotient(
                   problem.Scale().head(states));
}

}  // namespace

OrbitStart SettleOnCycle(OdeSystem& system, const Vector& x0, double duration, Index section_state,
                         const IntegratorOptions& integrator_options) {
  if (x0.size() != system.Dimension() || section_state < 0 ||
      section_state >= system.Dimension() || !(duration > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "SettleOnCycle: x0 has {} entries (system: {}), section_state = {}, duration = {}: need "
        "matching sizes, a state index and a positive duration",
        x0.size(), system.Dimension(), section_state, duration));
  }
  OrbitStart start;
  start.lambda = system.Parameter();
  OdeIntegrator integrator(system, integrator_options);
  EventOptions section;
  section.count = 1;
  section.directions = {-1};
  section.function = [section_state](double, ConstVectorRef x, VectorRef g) {
    g(0) = x(section_state);
  };
  integrator.SetEvents(section);
  Vector x1(x0.size());
  const IntegrationResult result = integrator.Integrate(0.0, x0, duration, x1);
  if (!result.Succeeded()) {
    start.message = "the settling integration failed: " + result.BriefReport();
    return start;
  }
  const auto& events = result.events;
  if (events.size() < 3) {
    start.message = fmt::format(
        "{} crossings of the section {} = 0 in {} time units: no cycle found (need 3)",
        events.size(), system.StateName(section_state), duration);
    return start;
  }
  const std::size_t k = events.size() - 1;
  const double last = events[k].t - events[k - 1].t;
  const double before = events[k - 1].t - events[k - 2].t;
  start.x0 = events[k].x;
  start.period = last;
  if (std::abs(last - before) > 1e-6 * last) {
    start.message = fmt::format(
        "the transient has not settled in {} time units: the last two periods are {} and {}",
        duration, before, last);
    return start;
  }
  start.valid = true;
  return start;
}

OrbitStart SettleForced(OdeSystem& system, const Vector& x0, int periods,
                        const IntegratorOptions& integrator_options) {
  const double T = system.ForcingPeriod();
  if (x0.size() != system.Dimension() || periods < 0 || !(T > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "SettleForced: x0 has {} entries (system: {}), periods = {}, forcing period {}: need "
        "matching sizes, periods ≥ 0 and a forced system",
        x0.size(), system.Dimension(), periods, T));
  }
  OrbitStart start;
  start.lambda = system.Parameter();
  start.period = T;
  start.x0 = x0;
  if (periods > 0) {
    OdeIntegrator integrator(system, integrator_options);
    // Period by period, so that the forcing phase is exactly 0 at the end of each.
    for (int k = 0; k < periods; ++k) {
      const IntegrationResult result = integrator.Integrate(k * T, start.x0, (k + 1) * T, start.x0);
      if (!result.Succeeded()) {
        start.message = "the settling integration failed: " + result.BriefReport();
        return start;
      }
    }
  }
  start.valid = true;
  return start;
}

void Validate(const PeriodicOrbitBranchOptions& options) {
  if (!std::isfinite(options.lambda_min) || !std::isfinite(options.lambda_max) ||
      !(options.lambda_min < options.lambda_max)) {
    throw std::invalid_argument(fmt::format(
        "PeriodicOrbitBranchOptions: lambda_min = {}, lambda_max = {}: must be finite with "
        "lambda_min < lambda_max",
        options.lambda_min, options.lambda_max));
  }
  if (options.direction < -1 || options.direction > 1) {
    throw std::invalid_argument(fmt::format(
        "PeriodicOrbitBranchOptions.direction = {}: must be -1, 0 (both ways) or +1",
        options.direction));
  }
  Validate(options.shooting);
  Validate(options.continuation);
}

PeriodicOrbitBranch ContinuePeriodicOrbits(OdeSystem& system, OrbitKind kind,
                                           const OrbitStart& start,
                                           const PeriodicOrbitBranchOptions& options) {
  Validate(options);
  if (!start.valid) {
    throw std::invalid_argument("ContinuePeriodicOrbits: no valid start: " + start.message);
  }
  if (!(start.lambda >= options.lambda_min && start.lambda <= options.lambda_max)) {
    throw std::invalid_argument(fmt::format(
        "ContinuePeriodicOrbits: the start's parameter {} is outside [{}, {}]", start.lambda,
        options.lambda_min, options.lambda_max));
  }
  PeriodicOrbitBranch result;
  result.kind = kind;
  result.state_dimension = system.Dimension();
  result.segments = options.shooting.segments;
  result.start_lambda = start.lambda;

  auto run = [&](int direction) {
    system.SetParameter(start.lambda);
    ShootingOptions shooting = options.shooting;
    shooting.refresh_phase_reference = kind != OrbitKind::kForced;
    ShootingProblem problem(system, kind, shooting);
    if (!options.measures.empty()) problem.SetMeasures(options.measures);
    problem.SetTestFunctions(options.test_functions);
    const Vector u0 = problem.InitialGuess(start.x0, start.period, start.lambda, start.rotation);
    result.shooting = shooting;
    result.shooting.period_scale = problem.PeriodScale();
    result.shooting.lambda_scale = problem.LambdaScale();
    ContinuationOptions continuation = OrbitContinuationOptions(options);
    continuation.direction = direction;
    Branch branch = Continue(problem, u0, start.lambda, continuation, options.on_step,
                             OrbitEndTest(options, start.lambda));
    result.work += problem.statistics();
    return branch;
  };

  if (options.direction != 0) {
    result.branch = run(options.direction);
  } else if (start.lambda <= options.lambda_min) {
    result.branch = run(+1);
  } else if (start.lambda >= options.lambda_max) {
    result.branch = run(-1);
  } else {
    const Branch backward = run(-1);
    // A closed curve (isola) followed round backwards already holds the forward run's points.
    if (backward.status == BranchStatus::kClosed) {
      result.branch = backward;
      return result;
    }
    const Branch forward = run(+1);
    if (backward.points.empty() || forward.points.empty()) {
      result.branch = forward.points.empty() ? backward : forward;
    } else {
      result.branch = JoinAtStart(backward, forward);
    }
  }
  return result;
}

OrbitStart OrbitStartAt(OdeSystem& system, OrbitKind kind, const ShootingOptions& shooting,
                        const BranchPoint& point) {
  ShootingProblem problem(system, kind, shooting);
  OrbitStart start;
  start.x0 = problem.SegmentStart(point.u, 0);
  start.period = problem.Period(point.u, point.lambda);
  start.rotation = problem.Rotation(point.u);
  start.lambda = point.lambda;
  start.valid = true;
  return start;
}

std::vector<double> DistinctFolds(const Branch& branch) {
  std::vector<double> folds;
  for (const SpecialPoint& p : branch.special_points) {
    if (p.type != SpecialPointType::kFold || !p.converged) continue;
    const bool seen = std::any_of(folds.begin(), folds.end(), [&](double f) {
      return std::abs(f - p.lambda) <= 1e-8 * std::max(std::abs(f), 1.0);
    });
    if (!seen) folds.push_back(p.lambda);
  }
  std::sort(folds.begin(), folds.end());
  return folds;
}

bool RoundClosedCurve(const Branch& branch, double start_lambda) {
  if (DistinctFolds(branch).size() < 2 || branch.points.size() < 2) return false;
  const double now = branch.points.back().lambda;
  const double before = branch.points[branch.points.size() - 2].lambda;
  return (now - start_lambda) * (before - start_lambda) <= 0.0;
}

EndTest EndAtNeimarkSacker() {
  return [](const Branch& branch) -> std::optional<BranchEnd> {
    const SpecialPoint* p = branch.FirstLocated(SpecialPointType::kNeimarkSacker);
    if (p == nullptr) return std::nullopt;
    return BranchEnd{BranchStatus::kStoppedByCaller,
                     fmt::format("the Neimark–Sacker point is located at λ = {:.9g}", p->lambda)};
  };
}

EndTest OrbitEndTest(const PeriodicOrbitBranchOptions& options, double start_lambda) {
  std::vector<EndTest> tests;
  if (options.stop_round_closed_curve) tests.push_back(EndRoundClosedCurve(start_lambda));
  if (options.stop_at_neimark_sacker) tests.push_back(EndAtNeimarkSacker());
  if (tests.empty()) return {};
  return [tests](const Branch& branch) -> std::optional<BranchEnd> {
    for (const EndTest& test : tests) {
      if (std::optional<BranchEnd> end = test(branch)) return end;
    }
    return std::nullopt;
  };
}

ContinuationOptions OrbitContinuationOptions(const PeriodicOrbitBranchOptions& options) {
  ContinuationOptions continuation = options.continuation;
  continuation.bounds.lambda_min = options.lambda_min;
  continuation.bounds.lambda_max = options.lambda_max;
  continuation.bounds.end_at_grazing = options.stop_at_grazing;
  continuation.detect.stability = true;
  return continuation;
}

EndTest EndRoundClosedCurve(double start_lambda) {
  return [start_lambda](const Branch& branch) -> std::optional<BranchEnd> {
    if (!RoundClosedCurve(branch, start_lambda)) return std::nullopt;
    const std::vector<double> folds = DistinctFolds(branch);
    return BranchEnd{BranchStatus::kClosed,
                     fmt::format("closed: round the curve through its folds at {:.9g} and {:.9g}",
                                 folds.front(), folds.back())};
  };
}

bool OrbitBranchSwitch::RejoinedNear(double lambda) const {
  const double lo = std::min(rejoined_between[0], rejoined_between[1]);
  const double hi = std::max(rejoined_between[0], rejoined_between[1]);
  return lambda >= lo - (hi - lo) && lambda <= hi + (hi - lo);  // false for NaN
}

OrbitBranchSwitch ContinueOrbitsFromBranchPoint(OdeSystem& system,
                                                const PeriodicOrbitBranch& family,
                                                std::size_t special_point,
                                                const PeriodicOrbitBranchOptions& options,
                                                const StepCallback& on_step) {
  Validate(options);
  const Branch& branch = family.branch;
  if (special_point >= branch.special_points.size() ||
      branch.special_points[special_point].type != SpecialPointType::kBranchPoint) {
    throw std::invalid_argument(fmt::format(
        "ContinueOrbitsFromBranchPoint: special point {} of {} is not a branch point",
        special_point, branch.special_points.size()));
  }
  SpecialPoint point = branch.special_points[special_point];
  const auto before = static_cast<std::size_t>(std::max<Index>(point.index, 0));
  const std::size_t after = std::min(before + 1, branch.points.size() - 1);
  OrbitBranchSwitch result;
  result.special_point = special_point;

  ShootingOptions shooting = family.shooting;
  shooting.refresh_phase_reference = family.kind != OrbitKind::kForced;
  system.SetParameter(point.lambda);
  ShootingProblem problem(system, family.kind, shooting);
  if (!options.measures.empty()) problem.SetMeasures(options.measures);
  problem.SetTestFunctions(options.test_functions);
  problem.SetPhaseReference(branch.points[before].u, branch.points[before].lambda);

  if (system.HasMirrorSymmetry()) {
    result.mirror_symmetric_orbit =
        StartsAsymmetry(system, problem, branch.points[before].u) <= OrbitBranchSwitch::kSymmetricOrbit &&
        StartsAsymmetry(system, problem, branch.points[after].u) <= OrbitBranchSwitch::kSymmetricOrbit;
    if (result.mirror_symmetric_orbit) {
      point.u = 0.5 * (point.u + MirrorStarts(system, problem, point.u));
    }
  }
  result.change = ComputeBranchSwitch(problem, point);
  if (!result.change.ok) {
    result.message = result.change.message;
    return result;
  }
  Vector odd_direction;  // the new direction's odd part, where there is a mirror symmetry
  if (system.HasMirrorSymmetry()) {
    odd_direction = OddPart(system, problem, result.change.du);
    result.direction_odd_part =
        odd_direction.norm() / result.change.du.cwiseQuotient(problem.Scale()).norm();
    result.breaks_mirror_symmetry = result.mirror_symmetric_orbit && result.direction_odd_part >= 0.9;
  }
  result.ok = true;

  const ContinuationOptions continuation = OrbitContinuationOptions(options);
  for (int side : {+1, -1}) {
    if (side < 0 && result.breaks_mirror_symmetry) break;
    problem.ResetStatistics();
    problem.SetPhaseReference(branch.points[before].u, branch.points[before].lambda);
    PeriodicOrbitBranch other;
    other.kind = family.kind;
    other.state_dimension = family.state_dimension;
    other.segments = family.segments;
    other.start_lambda = point.lambda;
    other.shooting = family.shooting;
    // A branch that breaks the symmetry ends where it meets the symmetric subspace again (at
    // another pitchfork, e.g. the far end of a bubble of asymmetric orbits): beyond it lies either
    // the symmetric family, already known, or the mirror image of the branch. Met when the orbit
    // is symmetric again, or when its odd part, projected on the switch direction's, changes sign.
    Continuation stepper(problem, continuation);
    stepper.StartFromBranchPoint(point, side);
    double largest_asymmetry = 0.0, previous_projection = 0.0;
    while (stepper.branch().status == BranchStatus::kRunning) {
      stepper.Step();
      const Branch& so_far = stepper.branch();
      if (on_step && !on_step(so_far)) stepper.Stop("stopped by the per-step callback");
      if (!result.breaks_mirror_symmetry || so_far.points.size() < 2) continue;
      const BranchPoint& last = so_far.points.back();
      const double asymmetry = StartsAsymmetry(system, problem, last.u);
      const double projection = odd_direction.dot(OddPart(system, problem, last.u));
      largest_asymmetry = std::max(largest_asymmetry, asymmetry);
      const bool symmetric_again = largest_asymmetry > 1e-3 &&
                                   asymmetry <= OrbitBranchSwitch::kSymmetricOrbit;
      const bool crossed = previous_projection * projection < 0.0;
      previous_projection = projection;
      if (so_far.status == BranchStatus::kRunning && (symmetric_again || crossed)) {
        stepper.Stop(fmt::format(
            "rejoined the symmetric orbits between λ = {:.10g} and {:.10g} ({}; largest "
            "asymmetry {:.1e} on the way)",
            so_far.points[so_far.points.size() - 2].lambda, last.lambda,
            crossed ? "the odd part changed sign: beyond lies the mirror image"
                    : fmt::format("asymmetry {:.1e}", asymmetry),
            largest_asymmetry));
        result.rejoined_between[0] = so_far.points[so_far.points.size() - 2].lambda;
        result.rejoined_between[1] = last.lambda;
      }
    }
    other.branch = stepper.TakeBranch();
    other.work = problem.statistics();
    result.branches.push_back(std::move(other));
  }
  return result;
}

OrbitPeriodDoubling ContinueOrbitsFromPeriodDoubling(OdeSystem& system,
                                                     const PeriodicOrbitBranch& family,
                                                     std::size_t special_point,
                                                     const PeriodicOrbitBranchOptions& options,
                                                     double amplitude,
                                                     const StepCallback& on_step) {
  Validate(options);
  const Branch& branch = family.branch;
  if (special_point >= branch.special_points.size() ||
      branch.special_points[special_point].type != SpecialPointType::kPeriodDoubling) {
    throw std::invalid_argument(fmt::format(
        "ContinueOrbitsFromPeriodDoubling: special point {} of {} is not a period doubling",
        special_point, branch.special_points.size()));
  }
  if (family.kind == OrbitKind::kForced) {
    throw std::invalid_argument(
        "ContinueOrbitsFromPeriodDoubling: the family's orbits are forced: a period-doubled "
        "forced orbit needs twice the forcing period, which the shooting problem does not set");
  }
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) {
    throw std::invalid_argument(fmt::format(
        "ContinueOrbitsFromPeriodDoubling: amplitude = {}: must be positive", amplitude));
  }
  const SpecialPoint& point = branch.special_points[special_point];
  OrbitPeriodDoubling result;
  result.special_point = special_point;

  // The family's return map at the point, and its eigenvector for −1.
  const OrbitReturnMap at = ReturnMapAt(system, family, point);
  if (!at.ok) {
    result.message = at.message;
    return result;
  }
  const Index n = at.map.rows(), N = static_cast<Index>(at.stms.size());
  const double period = at.period, phi = at.rotation;
  Matrix rotate = Matrix::Identity(n, n);
  for (Index j = 0; j < n; ++j) system.Rotate(phi, rotate.col(j));
  const Matrix& map = at.map;
  const Eigen::EigenSolver<Matrix> eigen(map);
  Index critical = -1;
  for (Index k = 0; k < n; ++k) {
    const std::complex<double> mu = eigen.eigenvalues()(k);
    if (std::abs(mu.imag()) > 1e-8 * std::abs(mu)) continue;
    if (critical < 0 || std::abs(mu.real() + 1.0) <
                            std::abs(eigen.eigenvalues()(critical).real() + 1.0)) {
      critical = k;
    }
  }
  if (critical < 0 || std::abs(eigen.eigenvalues()(critical).real() + 1.0) > 0.1) {
    result.message = "the return map has no real multiplier within 0.1 of −1 at the point";
    return result;
  }
  result.multiplier = eigen.eigenvalues()(critical).real();
  const Vector scale = system.StateScale();
  Vector v = eigen.eigenvectors().col(critical).real();
  v /= v.cwiseQuotient(scale).norm();

  // The orbit run twice, and the direction [v_i; −R_φ v_i].
  Matrix starts(n, 2 * N), direction(n, 2 * N);
  for (Index i = 0; i < N; ++i) {
    const Vector x = at.starts.col(i);
    starts.col(i) = x;
    starts.col(N + i) = rotate * x;
    direction.col(i) = v;
    direction.col(N + i) = -(rotate * v);
    v = at.stms[static_cast<std::size_t>(i)] * v;
  }
  ShootingOptions doubled = family.shooting;
  doubled.refresh_phase_reference = true;
  doubled.segments = 2 * N;
  // The point's own mesh run twice (its event boundaries where they moved), each event boundary
  // in both halves; a uniform mesh stays uniform.
  if (!family.shooting.mesh.empty() || !family.shooting.event_boundaries.empty()) {
    doubled.mesh.clear();
    for (const double tau : at.mesh) doubled.mesh.push_back(0.5 * tau);
    for (std::size_t k = 1; k < at.mesh.size(); ++k) {
      doubled.mesh.push_back(0.5 + 0.5 * at.mesh[k]);
    }
  }
  for (const ShootingOptions::EventBoundary& event : family.shooting.event_boundaries) {
    doubled.event_boundaries.push_back({event.boundary + static_cast<int>(N), event.surface});
  }
  if (family.shooting.period_scale > 0.0) doubled.period_scale = 2.0 * family.shooting.period_scale;
  ShootingProblem problem(system, family.kind, doubled);
  if (!options.measures.empty()) problem.SetMeasures(options.measures);
  problem.SetTestFunctions(options.test_functions);
  const Vector twice = problem.Pack(starts, 2.0 * period, 2.0 * phi);
  problem.SetPhaseReference(twice, point.lambda);
  const Vector du = problem.Pack(direction, 0.0, 0.0).cwiseQuotient(problem.Scale());

  const ContinuationOptions continuation = OrbitContinuationOptions(options);
  // A start too far off the orbit for the flow (a stiff contact pressed in further than the
  // integrator survives) is tried again ten and a hundred times closer: the same doubled orbits.
  std::string failed;
  for (int attempt = 0; attempt < kDoublingStartAttempts; ++attempt, amplitude /= 10.0) {
    Continuation stepper(problem, continuation);
    const Vector u0 = twice + amplitude * problem.Pack(direction, 0.0, 0.0);
    if (stepper.StartWithTangent(u0, point.lambda, du, 0.0) == StepResult::kFailed &&
        attempt + 1 < kDoublingStartAttempts) {
      failed += fmt::format("{}the start at amplitude {:g} failed ({})", failed.empty() ? "" : "; ",
                            amplitude, stepper.branch().message);
      continue;
    }
    result.amplitude = amplitude;
    result.message = failed.empty() ? "" : failed + fmt::format("; amplitude {:g} used", amplitude);
    // The ends options ask for (stop_at_grazing, in `continuation`: A(a)'s doubled whip crept 290
    // orbits past its grazing on a fixed mesh without it).
    result.branch = FamilyOf(problem, doubled, point.lambda,
                             RunToEnd(stepper, on_step, OrbitEndTest(options, point.lambda)));
    break;
  }
  result.ok = true;
  return result;
}

PeriodicOrbitBranch FamilyOf(const ShootingProblem& problem, const ShootingOptions& shooting,
                             double start_lambda, Branch branch) {
  PeriodicOrbitBranch family;
  family.kind = problem.kind();
  family.state_dimension = problem.StateDimension();
  family.segments = static_cast<int>(problem.SegmentCount());
  family.start_lambda = start_lambda;
  family.shooting = shooting;
  family.shooting.period_scale = problem.PeriodScale();
  family.shooting.lambda_scale = problem.LambdaScale();
  family.work = problem.statistics();
  family.branch = std::move(branch);
  return family;
}

OrbitReturnMap ReturnMapAt(OdeSystem& system, const PeriodicOrbitBranch& family,
                           const SpecialPoint& point) {
  OrbitReturnMap at;
  ShootingOptions shooting = family.shooting;
  shooting.refresh_phase_reference = true;
  system.SetParameter(point.lambda);
  ShootingProblem problem(system, family.kind, shooting);
  const Index n = problem.StateDimension(), N = problem.SegmentCount();
  at.stms = problem.SegmentMonodromies(point.u, point.lambda);
  if (at.stms.size() != static_cast<std::size_t>(N)) {
    at.message = "the segment STMs could not be integrated at the point: " +
                 problem.LastFailure().BriefReport();
    return at;
  }
  at.starts.resize(n, N);
  for (Index i = 0; i < N; ++i) at.starts.col(i) = problem.SegmentStart(point.u, i);
  at.mesh = problem.Mesh(point.u);
  at.period = problem.Period(point.u, point.lambda);
  at.rotation = problem.Rotation(point.u);
  Matrix unrotate = Matrix::Identity(n, n);
  for (Index j = 0; j < n; ++j) system.Rotate(-at.rotation, unrotate.col(j));
  at.map = Matrix::Identity(n, n);
  for (const Matrix& M : at.stms) at.map = M * at.map;
  at.map = unrotate * at.map;
  at.ok = true;
  return at;
}

bool BoundsStablePiece(const Branch& branch, const SpecialPoint& p) {
  if (p.index < 0 || static_cast<std::size_t>(p.index) + 1 >= branch.points.size()) return false;
  const BranchPoint& before = branch.points[static_cast<std::size_t>(p.index)];
  const BranchPoint& after = branch.points[static_cast<std::size_t>(p.index) + 1];
  if (before.num_unstable < 0 || after.num_unstable < 0) return false;
  return (before.num_unstable == 0) != (after.num_unstable == 0);
}

}  // namespace rubcont
