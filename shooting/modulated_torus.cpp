#include "shooting/modulated_torus.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "models/units.h"
#include "shooting/modulated_orbit.h"
#include "solvers/constants.h"
#include "solvers/spectrum.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

constexpr int kSamplesPerPeriod = 16;

// Why points one period apart may be no circle although the motion is a torus: the section cuts
// it m times, and the points visit m arcs in turn. Then the sequence of contact 0's d(kT) has its
// strongest line at ν ≈ p/m cycles per iterate. Returns m (2 … 8) when ν is within 0.3 bins of
// such a fraction (the refined peak of a clean line is far closer), else 0, and the sentence that
// says so. A hint, not a verdict: an irrational ν lies that close to some p/m, m ≤ 8, about one
// time in five.
struct SectionCuts {
  int cuts = 0;
  std::string hint;  // "; …" or ""
};
SectionCuts SectionHint(const RubStructure& structure, const Matrix& points) {
  const Index m = points.cols();
  ComplexVector d(m);
  for (Index k = 0; k < m; ++k) d(k) = FirstContactGap(structure, points.col(k));
  const SpectralPeak peak = DominantPeak(TwoSidedSpectrum(d, 1.0), PeakSide::kAny);
  if (!peak.found) return {};
  const double nu = std::abs(peak.frequency), tolerance = 0.3 / static_cast<double>(m);
  for (int cuts = 2; cuts <= 8; ++cuts) {
    const double p = std::round(nu * cuts);
    if (p >= 1.0 && std::abs(nu - p / cuts) <= tolerance) {
      return {cuts, fmt::format("; their sequence's strongest line is at {:.4f} per period ≈ {}/{}: "
                                "the section may cut the torus {} times (then a section of {} "
                                "periods cuts it once)", nu, static_cast<int>(p), cuts, cuts, cuts)};
    }
  }
  return {};
}

// The map's integrator for sections of `laps` modulation periods: intervals × laps Gauss steps,
// or `integrator` where intervals = 0.
IntegratorOptions MapIntegrator(const IntegratorOptions& integrator, int intervals, int laps) {
  if (intervals == 0) return integrator;
  IntegratorOptions gauss = integrator;
  gauss.method = IntegrationMethod::kGaussCollocation;
  gauss.collocation_stages = 4;
  gauss.collocation_steps = intervals;
  return JoinedIntegrator(gauss, laps);
}

// "; " and where the circle's map failed, when it did (the cause of a non-finite residual).
std::string MapFailureNote(const InvariantCircleProblem& circle) {
  return circle.MapFailure().empty() ? std::string() : "; " + circle.MapFailure();
}

// The flow from `state` sampled `count` times, `step` apart from t = 0.
IntegrationResult SampleFlow(OdeSystem& system, const IntegratorOptions& options,
                             const Vector& state, Index count, double step, Matrix& samples) {
  OdeIntegrator integrator(system, options);
  return integrator.Sample(0.0, state,
                           Vector::LinSpaced(count, 0.0, static_cast<double>(count - 1) * step), samples);
}

// The orbit of P = R_{−φ} Φ_T from samples of the flow every T / stride: `count` points, the
// k-th sample of period kT turned back by −kφ.
Matrix MapOrbit(const OdeSystem& frame, const Matrix& samples, Index stride, Index count, double phi) {
  Matrix points(samples.rows(), count);
  for (Index k = 0; k < count; ++k) {
    points.col(k) = samples.col(k * stride);
    frame.Rotate(-static_cast<double>(k) * phi, points.col(k));
  }
  return points;
}

}  // namespace

void Validate(const ModulatedTorusOptions& options) {
  Validate(options.integrator);
  Validate(options.newton);
  ValidateModulationSearch("ModulatedTorusOptions", options.search_duration, options.search_rate);
  if (options.harmonics < 1 || options.harmonics > 500) {
    throw std::invalid_argument(
        fmt::format("ModulatedTorusOptions.harmonics = {}: must be in 1 … 500", options.harmonics));
  }
  if (options.iterates != 0 && options.iterates < 2 * options.harmonics + 2) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.iterates = {}: must be 0 (automatic) or ≥ 2K + 2 = {}",
        options.iterates, 2 * options.harmonics + 2));
  }
  if (!(options.approach >= 0.0) || !std::isfinite(options.approach)) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.approach = {}: must be finite and ≥ 0 (s)", options.approach));
  }
  if (options.lyapunov_iterates < 0) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.lyapunov_iterates = {}: must be ≥ 0", options.lyapunov_iterates));
  }
  if (options.collocation_intervals < 0) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.collocation_intervals = {}: must be ≥ 0 (0: the map by integrator)",
        options.collocation_intervals));
  }
  if (options.final_collocation_intervals < 0) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.final_collocation_intervals = {}: must be ≥ 0 (0: the first map "
        "throughout)", options.final_collocation_intervals));
  }
  // The families' rule (TorusBranchOptions::max_harmonics) and the scene's: the transient's families
  // are refined up to the same K.
  if (options.max_harmonics < 0 || options.max_harmonics > 1000) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.max_harmonics = {}: must be in 0 … 1000", options.max_harmonics));
  }
  ValidateRefinementImages("ModulatedTorusOptions.", options.refinement_images);
  if (!(options.converged_tail > 0.0 && options.converged_tail < 1.0)) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.converged_tail = {}: must be in (0, 1)", options.converged_tail));
  }
  if (options.laps < 0 || options.laps > 64) {
    throw std::invalid_argument(fmt::format(
        "ModulatedTorusOptions.laps = {}: must be 0 (automatic) or in 1 … 64", options.laps));
  }
}

ModulatedTorusOptions SettledTransientStart(int harmonics) {
  ModulatedTorusOptions start;
  start.harmonics = harmonics;
  start.approach = 4.0;
  start.search_duration = 4.0;
  start.newton.max_iterations = 30;
  // Steps that fail halved: C(a) at 60 rpm (chart, K = 16, sections of 5 periods) met a non-finite
  // residual after its first full step from |F| 7.1e-2; damped it converged in 5 iterations.
  start.newton.max_step_halvings = 8;
  start.lyapunov_iterates = 0;
  return start;
}

ModulatedTorus SolveModulatedTorus(const RubStructure& structure, double omega, double frame_rate,
                                   const Vector& fixed_state, const ModulatedTorusOptions& options) {
  Validate(options);
  CheckModulationInputs("SolveModulatedTorus", structure, omega, frame_rate, fixed_state);
  const SteadyClock::time_point start = SteadyClock::now();
  ModulatedTorus torus;
  torus.frame_rate = frame_rate;
  auto done = [&](std::string message) {
    torus.message = std::move(message);
    torus.seconds = SecondsSince(start);
    return torus;
  };
  auto frame = std::make_shared<RubRotatingFrame>(structure, frame_rate, omega);  // throws for an imbalance
  Vector approached = fixed_state;
  if (options.approach > 0.0) {
    RubFixedFrame fixed(structure, omega);
    OdeIntegrator integrator(fixed, options.integrator);
    const IntegrationResult result = integrator.Integrate(0.0, fixed_state, options.approach, approached);
    if (!result.Succeeded()) return done("integrating the approach failed: " + result.BriefReport());
  }
  const ModulationSearch search = SearchModulation(*frame, approached, options.integrator,
                                                   options.search_duration, options.search_rate);
  if (!search.found) return done(search.message);
  const double period = search.period;
  torus.search_period = period;

  // The orbit of P = R_{−φ̄} Φ_{mT} (m = laps): `iterates` m periods sampled 16 times per period,
  // d's phase unwrapped along the samples.
  const int iterates = options.iterates > 0 ? options.iterates : 4 * (2 * options.harmonics + 1);
  std::unique_ptr<InvariantCircleProblem> circle;
  auto first_circle = [&](int laps, Matrix& points) -> std::string {
    circle = std::make_unique<InvariantCircleProblem>(
        frame, options.harmonics, OrbitKind::kRelative,
        MapIntegrator(options.integrator, options.collocation_intervals, laps), options.coordinates);
    const Index stride = static_cast<Index>(laps) * kSamplesPerPeriod;
    const Index samples_count = static_cast<Index>(iterates) * stride + 1;
    Matrix samples;
    const IntegrationResult sampled = SampleFlow(*frame, options.integrator, search.state, samples_count,
                                                 period / kSamplesPerPeriod, samples);
    if (!sampled.Succeeded()) return "integrating the circle's first points failed: " + sampled.BriefReport();
    // φ̄: the least-squares slope of the unwrapped phase against time, per section. (The mean turn,
    // end minus start over the record, carries the phase's modulation over the record's length as
    // its error: at C(a), 60 rpm, 400 sections of 5 periods, the points then drifted along the
    // group orbit by 0.029 of their scale, against 0.006 with the slope.)
    Vector phase(samples_count);
    phase(0) = 0.0;
    for (Index i = 1; i < samples_count; ++i) {
      phase(i) = phase(i - 1) + std::arg(FirstContactGap(structure, samples.col(i)) /
                                         FirstContactGap(structure, samples.col(i - 1)));
    }
    const Vector index = Vector::LinSpaced(samples_count, 0.0, static_cast<double>(samples_count - 1));
    const Vector centred = index.array() - index.mean();
    const double phi = centred.dot(phase) / centred.squaredNorm() * laps * kSamplesPerPeriod;
    torus.laps = laps;
    torus.search_rotation = phi;
    points = MapOrbit(*frame, samples, stride, iterates, phi);
    try {
      torus.u = circle->CircleFromOrbit(points, laps * period, phi);
    } catch (const std::invalid_argument& e) {
      return fmt::format("the transient's points {} period{} apart (T ≈ {:.6g} s, φ ≈ {:.4g}) are "
                         "no circle: {}", laps, laps > 1 ? "s" : "", period, phi, e.what());
    }
    return "";
  };
  Matrix points;
  std::string failure = first_circle(options.laps > 0 ? options.laps : 1, points);
  if (!failure.empty()) {
    if (!points.size()) return done(failure);
    const SectionCuts cuts = SectionHint(structure, points);
    if (options.laps > 0 || cuts.cuts == 0) return done(failure + cuts.hint);
    const std::string retry = first_circle(cuts.cuts, points);
    if (!retry.empty()) return done(failure + cuts.hint + "; " + retry);
  }
  auto solve = [&](InvariantCircleProblem& problem, const NewtonOptions& newton) {
    problem.SetPhaseReference(torus.u);
    return NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, omega, F); },
                       [&](const Vector& v, Matrix& J) { problem.Jacobian(v, omega, J); }, torus.u,
                       newton, problem.Scale(), problem.ResidualScale());
  };
  auto record = [&](InvariantCircleProblem& problem) {
    const Vector measures = problem.Measures(torus.u, omega);
    torus.by_harmonics.push_back({problem.harmonics(), problem.RotationNumber(torus.u), measures(1),
                                  measures(2), torus.newton.iterations});
  };
  torus.newton = solve(*circle, options.newton);
  if (!torus.newton.Converged()) {
    return done(fmt::format("Newton from the transient's circle ({} × T ≈ {:.6g} s, φ ≈ {:.4g}, "
                            "ρ ≈ {:.4f}, K = {}): {}{}", torus.laps, period, torus.search_rotation,
                            circle->RotationNumber(torus.u), options.harmonics,
                            torus.newton.BriefReport(), MapFailureNote(*circle)));
  }
  // Damped: from another circle (coarser, or another map's) a full step can leave the contact's
  // manifold where the map's integration fails (C(c) at 64 rpm, K = 16: a non-finite residual
  // after the first step).
  NewtonOptions damped = options.newton;
  damped.max_step_halvings = std::max(damped.max_step_halvings, 8);
  // The map the torus is reported and refined under
  // (ModulatedTorusOptions::final_collocation_intervals).
  const bool switch_map =
      options.collocation_intervals == 0 && options.final_collocation_intervals > 0;
  const int intervals =
      switch_map ? options.final_collocation_intervals : options.collocation_intervals;
  std::string first_map;
  if (switch_map) {
    torus.first_map_rotation_number = circle->RotationNumber(torus.u);
    auto final_map = std::make_unique<InvariantCircleProblem>(
        frame, circle->harmonics(), OrbitKind::kRelative,
        MapIntegrator(options.integrator, intervals, torus.laps), options.coordinates);
    torus.newton = solve(*final_map, damped);
    if (!torus.newton.Converged()) {
      return done(fmt::format("Newton under Gauss collocation on {} intervals per period from the "
                              "first map's circle (ρ {:.8f}, K = {}): {}{}", intervals,
                              torus.first_map_rotation_number, circle->harmonics(),
                              torus.newton.BriefReport(), MapFailureNote(*final_map)));
    }
    circle = std::move(final_map);
    first_map = fmt::format("first solved under the transient's map, ρ {:.8f}, then under Gauss "
                            "collocation on {} intervals per period; ",
                            torus.first_map_rotation_number, intervals);
  }
  record(*circle);
  // Convergence in K: doubled from the solved circle while its tail says the series is short.
  std::string refinement;
  while (torus.by_harmonics.back().fourier_tail > options.converged_tail &&
         2 * circle->harmonics() <= options.max_harmonics) {
    auto finer = std::make_unique<InvariantCircleProblem>(
        frame, 2 * circle->harmonics(), OrbitKind::kRelative,
        MapIntegrator(options.integrator, intervals, torus.laps), options.coordinates);
    const CircleRefinement refined =
        RefineCircle(*circle, torus.u, omega, *finer, options.refinement_images, damped);
    if (!refined.converged) {
      refinement = fmt::format("; not refined to K = {}: {}", finer->harmonics(), refined.failures);
      break;
    }
    torus.u = refined.u;
    torus.newton = refined.newton;
    circle = std::move(finer);
    record(*circle);
    torus.by_harmonics.back().images = refined.images;
  }
  InvariantCircleProblem& problem = *circle;
  torus.harmonics = problem.harmonics();
  torus.period = problem.Period(torus.u, omega);
  torus.rotation = problem.Rotation(torus.u);
  torus.rotation_number = problem.RotationNumber(torus.u);
  torus.carrier_hz = RadPerSecondToHz(frame->CarrierPrecession(torus.period, torus.rotation));
  torus.first_hz = 1.0 / torus.period;
  torus.second_hz = torus.rotation_number / torus.period;
  torus.fourier_tail = torus.by_harmonics.back().fourier_tail;
  torus.invariance_error = torus.by_harmonics.back().invariance_error;
  if (options.lyapunov_iterates > 0) {
    torus.stability = problem.LyapunovStability(torus.u, omega, options.lyapunov_iterates);
  }
  torus.converged = true;
  std::string in_k;
  if (torus.by_harmonics.size() > 1) {
    in_k = "; in K:";
    for (const ModulatedTorus::AtHarmonics& k : torus.by_harmonics) {
      in_k += fmt::format(" K = {} ρ {:.8f} (tail {:.2g}, invariance error {:.2g}{}){}",
                          k.harmonics, k.rotation_number, k.fourier_tail, k.invariance_error,
                          k.images == 0   ? std::string()
                          : k.images == 1 ? std::string(", from 1 image")
                                          : fmt::format(", from {} images", k.images),
                          &k == &torus.by_harmonics.back() ? "" : ",");
    }
  }
  return done(fmt::format(
      "{}T = {:.9g} s, φ = {:+.6g} rad, ρ = {:.8f}: carrier {:.6f} Hz, modulation {:.6f} and {:.6f} "
      "Hz; K = {}, Fourier tail {:.2g}, invariance error {:.2g}{}{}; {}{}{}",
      torus.laps > 1 ? fmt::format("on the section of {} modulation periods: ", torus.laps) : "",
      torus.period, torus.rotation,
      torus.rotation_number, torus.carrier_hz, torus.first_hz, torus.second_hz, torus.harmonics,
      torus.fourier_tail, torus.invariance_error, in_k, refinement, first_map,
      torus.newton.BriefReport(),
      torus.stability.valid
          ? fmt::format("; {} (largest non-trivial exponent {:.3g} per period, tolerance {:.2g})",
                        torus.stability.Verdict(),
                        torus.stability.LargestNontrivial(), torus.stability.tolerance)
          : std::string()));
}

}  // namespace rubcont
