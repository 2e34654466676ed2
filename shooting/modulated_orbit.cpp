#include "shooting/modulated_orbit.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/spectrum.h"

namespace rubcont {
namespace {

// An adaptive integrator for stretches and single periods: a fixed Gauss mesh is made for one
// segment of an orbit, so BDF ≤ 2 at the same tolerances replaces it.
IntegratorOptions Adaptive(IntegratorOptions options) {
  if (options.method == IntegrationMethod::kGaussCollocation) {
    options.method = IntegrationMethod::kBdf;
    options.max_order = 2;
  }
  return options;
}

}  // namespace

void ValidateModulationSearch(const std::string& owner, double duration, double rate) {
  if (!(duration > 0.0) || !std::isfinite(duration)) {
    throw std::invalid_argument(fmt::format(
        "{}.search_duration = {}: must be positive and finite (s)", owner, duration));
  }
  if (!(rate * duration >= 16.0)) {
    throw std::invalid_argument(fmt::format(
        "{}.search_rate = {} per s: must give at least 16 samples over search_duration = {} s",
        owner, rate, duration));
  }
}

std::complex<double> FirstContactGap(const RubStructure& structure, ConstVectorRef x) {
  const Index r = 2 * structure.contacts[0].rotor, s = 2 * structure.contacts[0].stator;
  return {x(r) - x(s), x(r + 1) - x(s + 1)};
}

ModulationSearch SearchModulation(RubRotatingFrame& frame, const Vector& fixed_state,
                                  const IntegratorOptions& integrator_options, double duration,
                                  double rate) {
  ModulationSearch search;
  const Vector x_start = frame.ToRotatingFrame(0.0, fixed_state);
  OdeIntegrator integrator(frame, Adaptive(integrator_options));
  const Index samples_count = static_cast<Index>(std::llround(duration * rate));
  const Vector times = Vector::LinSpaced(samples_count, 0.0, (samples_count - 1) / rate);
  Matrix stretch;
  const IntegrationResult result = integrator.Sample(0.0, x_start, times, stretch);
  if (!result.Succeeded()) {
    search.message = "integrating the stretch failed: " + result.BriefReport();
    return search;
  }
  RubFixedFrame fixed(frame.structure(), frame.Parameter());
  ComplexVector slip(samples_count);
  for (Index k = 0; k < samples_count; ++k) {
    slip(k) = fixed.Contacts(frame.ToFixedFrame(times(k), stretch.col(k)))[0].slip_velocity;
  }
  const SpectralPeak peak = DominantPeak(TwoSidedSpectrum(slip, rate), PeakSide::kPositive);
  // A swing below 1e-8 of the slip velocity is round-off: no modulation.
  if (!peak.found || !(peak.amplitude > 1e-8 * slip.cwiseAbs().maxCoeff())) {
    search.message = fmt::format("the slip velocity does not vary over {} s: no modulation to shoot",
                                 duration);
    return search;
  }
  search.found = true;
  search.period = 1.0 / peak.frequency;
  search.state = stretch.col(samples_count - 1);
  return search;
}

void Validate(const ModulatedOrbitOptions& options) {
  Validate(options.shooting);
  Validate(options.newton);
  ValidateModulationSearch("ModulatedOrbitOptions", options.search_duration, options.search_rate);
  if (options.search_integrator) Validate(*options.search_integrator);
  if (options.harmonics < 0) {
    throw std::invalid_argument(
        fmt::format("ModulatedOrbitOptions.harmonics = {}: must be ≥ 0", options.harmonics));
  }
  if (options.laps < 1 || options.laps > 64) {
    throw std::invalid_argument(
        fmt::format("ModulatedOrbitOptions.laps = {}: must be in 1 … 64", options.laps));
  }
}

void CheckModulationInputs(const std::string& solver, const RubStructure& structure, double omega,
                           double frame_rate, const Vector& fixed_state) {
  if (!(frame_rate > 0.0) || !(omega > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "{}: frame_rate = {}, omega = {}: both must be positive (rad/s)", solver, frame_rate, omega));
  }
  if (fixed_state.size() != structure.States()) {
    throw std::invalid_argument(fmt::format("{}: fixed_state has {} entries, the structure {}",
                                            solver, fixed_state.size(), structure.States()));
  }
}

ModulatedOrbit SolveModulatedOrbit(const RubStructure& structure, double omega, double frame_rate,
                                   const Vector& fixed_state, const ModulatedOrbitOptions& options) {
  Validate(options);
  CheckModulationInputs("SolveModulatedOrbit", structure, omega, frame_rate, fixed_state);
  ModulatedOrbit orbit;
  orbit.frame_rate = frame_rate;
  orbit.laps = options.laps;
  RubRotatingFrame frame(structure, frame_rate, omega);
  const IntegratorOptions search_integrator =
      Adaptive(options.search_integrator.value_or(options.shooting.integrator));
  const ModulationSearch search = SearchModulation(frame, fixed_state, search_integrator,
                                                   options.search_duration, options.search_rate);
  if (!search.found) {
    orbit.message = search.message;
    return orbit;
  }
  const double period = options.laps * search.period;
  const Vector& x0 = search.state;
  OdeIntegrator integrator(frame, search_integrator);
  Vector x_period(x0.size());
  const IntegrationResult turn = integrator.Integrate(0.0, x0, period, x_period);
  if (!turn.Succeeded()) {
    orbit.message = fmt::format("integrating {} period{} failed: {}", options.laps,
                                options.laps > 1 ? "s" : "", turn.BriefReport());
    return orbit;
  }
  const double phi = std::arg(FirstContactGap(structure, x_period) / FirstContactGap(structure, x0));

  ShootingProblem problem(frame, OrbitKind::kRelative, options.shooting);
  orbit.u = problem.InitialGuess(x0, period, omega, phi);
  if (!orbit.u.allFinite()) {
    orbit.message = "the initial guess's integration failed: " + problem.LastFailure().BriefReport();
    return orbit;
  }
  orbit.newton = NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, omega, F); },
                             [&](const Vector& v, Matrix& J) { problem.Jacobian(v, omega, J); },
                             orbit.u, options.newton, problem.Scale(), problem.ResidualScale());
  orbit.work = problem.statistics();
  if (!orbit.newton.Converged()) {
    orbit.message = fmt::format("Newton from the transient's orbit ({}T ≈ {:.6g} s, φ ≈ {:.4g}): {}",
                                options.laps > 1 ? fmt::format("{} × ", options.laps) : "",
                                period, phi, orbit.newton.BriefReport());
    return orbit;
  }
  orbit.period = problem.Period(orbit.u, omega);
  orbit.rotation = problem.Rotation(orbit.u);
  orbit.x0 = problem.SegmentStart(orbit.u, 0);
  orbit.carrier_hz = RadPerSecondToHz(frame.CarrierPrecession(orbit.period, orbit.rotation));

  // Fourier coefficients of q = e^{−jφt/T} d over one period (trapezoidal rule on the samples).
  const OrbitSamples samples = problem.Orbit(orbit.u, omega);
  if (!samples.valid) {
    orbit.message = "sampling the converged orbit failed: " + problem.LastFailure().BriefReport();
    return orbit;
  }
  const int K = options.harmonics;
  std::vector<std::complex<double>> c(static_cast<std::size_t>(2 * K + 1));
  const Index m = samples.times.size();
  const double T = orbit.period, phi_T = orbit.rotation / T;
  auto integrand = [&](Index i, int k) {
    const double t = samples.times(i);
    return std::polar(1.0, -phi_T * t - kTwoPi * k * t / T) *
           FirstContactGap(structure, samples.states.col(i));
  };
  for (int k = -K; k <= K; ++k) {
    std::complex<double> sum = 0.0;
    for (Index i = 0; i + 1 < m; ++i) {
      sum += 0.5 * (samples.times(i + 1) - samples.times(i)) * (integrand(i, k) + integrand(i + 1, k));
    }
    c[static_cast<std::size_t>(k + K)] = sum / T;
  }
  int best = 0;
  for (int k = -K; k <= K; ++k) {
    const double precession = frame_rate - phi_T - kTwoPi * k / T;
    if (precession > 0.0 && std::abs(c[static_cast<std::size_t>(k + K)]) >
                                std::abs(c[static_cast<std::size_t>(best + K)])) {
      best = k;
    }
  }
  double other = 0.0;
  for (int k = -K; k <= K; ++k) {
    if (k != best) other = std::max(other, std::abs(c[static_cast<std::size_t>(k + K)]));
  }
  orbit.dominant_harmonic = best;
  orbit.dominant_hz = RadPerSecondToHz(frame_rate - phi_T - kTwoPi * best / T);
  orbit.sideband_ratio = other / std::abs(c[static_cast<std::size_t>(best + K)]);
  orbit.converged = true;
  orbit.message = fmt::format(
      "T = {:.9g} s{}, φ = {:+.6g} rad, carrier {:.6f} Hz, dominant k = {} at {:.6f} Hz, largest "
      "other component {:.3g} of it; {}", T,
      options.laps > 1 ? fmt::format(" ({} modulation periods)", options.laps) : "", orbit.rotation,
      orbit.carrier_hz, best, orbit.dominant_hz, orbit.sideband_ratio, orbit.newton.BriefReport());
  return orbit;
}

OrbitStart StartOf(const ModulatedOrbit& orbit, double omega) {
  if (!orbit.converged) {
    throw std::invalid_argument("StartOf: the modulated orbit did not converge: " + orbit.message);
  }
  OrbitStart start;
  start.x0 = orbit.x0;
  start.period = orbit.period;
  start.rotation = orbit.rotation;
  start.lambda = omega;
  start.valid = true;
  return start;
}

}  // namespace rubcont
