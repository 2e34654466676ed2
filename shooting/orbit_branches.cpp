#include "shooting/orbit_branches.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "continuation/continuation.h"

namespace rubcont {

namespace {

void Accumulate(ShootingStatistics& total, const ShootingStatistics& part) {
  total.residual_integrations += part.residual_integrations;
  total.sensitivity_integrations += part.sensitivity_integrations;
  total.steps += part.steps;
  total.cache_hits += part.cache_hits;
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
    const Vector u0 = problem.InitialGuess(start.x0, start.period, start.lambda);
    ContinuationOptions continuation = options.continuation;
    continuation.bounds.lambda_min = options.lambda_min;
    continuation.bounds.lambda_max = options.lambda_max;
    continuation.detect.stability = true;
    continuation.direction = direction;
    Branch branch = Continue(problem, u0, start.lambda, continuation);
    Accumulate(result.work, problem.statistics());
    return branch;
  };

  if (start.lambda <= options.lambda_min) {
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

}  // namespace rubcont
