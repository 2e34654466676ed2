#include "shooting/modulated_orbit.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/spectrum.h"

namespace rubcont {
namespace {

// d = u_rotor − u_stator of contact 0, from a state [q; v] (real pairs).
std::complex<double> FirstContact(const RubStructure& structure, ConstVectorRef x) {
  const Index r = 2 * structure.contacts[0].rotor, s = 2 * structure.contacts[0].stator;
  return {x(r) - x(s), x(r + 1) - x(s + 1)};
}

}  // namespace

void Validate(const ModulatedOrbitOptions& options) {
  Validate(options.shooting);
  Validate(options.newton);
  if (!(options.search_duration > 0.0) || !std::isfinite(options.search_duration)) {
    throw std::invalid_argument(fmt::format(
        "ModulatedOrbitOptions.search_duration = {}: must be positive and finite (s)",
        options.search_duration));
  }
  if (!(options.search_rate * options.search_duration >= 16.0)) {
    throw std::invalid_argument(fmt::format(
        "ModulatedOrbitOptions.search_rate = {} per s: must give at least 16 samples over "
        "search_duration = {} s", options.search_rate, options.search_duration));
  }
  if (options.harmonics < 0) {
    throw std::invalid_argument(
        fmt::format("ModulatedOrbitOptions.harmonics = {}: must be ≥ 0", options.harmonics));
  }
}

ModulatedOrbit SolveModulatedOrbit(const RubStructure& structure, double omega, double frame_rate,
                                   const Vector& fixed_state, const ModulatedOrbitOptions& options) {
  Validate(options);
  if (!(frame_rate > 0.0) || !(omega > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "SolveModulatedOrbit: frame_rate = {}, omega = {}: both must be positive (rad/s)",
        frame_rate, omega));
  }
  if (fixed_state.size() != structure.States()) {
    throw std::invalid_argument(fmt::format("SolveModulatedOrbit: fixed_state has {} entries, the "
                                            "structure {}", fixed_state.size(), structure.States()));
  }
  ModulatedOrbit orbit;
  orbit.frame_rate = frame_rate;
  RubRotatingFrame frame(structure, frame_rate, omega);
  const Vector x_start = frame.ToRotatingFrame(0.0, fixed_state);

  // The modulation frequency: the dominant frequency of the slip velocity over the stretch, which
  // needs an adaptive integrator: a fixed Gauss mesh is made for one segment, not the stretch.
  IntegratorOptions search_options = options.shooting.integrator;
  if (search_options.method == IntegrationMethod::kGaussCollocation) {
    search_options.method = IntegrationMethod::kBdf;
    search_options.max_order = 2;
  }
  OdeIntegrator integrator(frame, search_options);
  const Index samples_count =
      static_cast<Index>(std::llround(options.search_duration * options.search_rate));
  const Vector times = Vector::LinSpaced(samples_count, 0.0,
                                         (samples_count - 1) / options.search_rate);
  Matrix stretch;
  const IntegrationResult search = integrator.Sample(0.0, x_start, times, stretch);
  if (!search.Succeeded()) {
    orbit.message = "integrating the stretch failed: " + search.BriefReport();
    return orbit;
  }
  RubFixedFrame fixed(structure, omega);
  ComplexVector slip(samples_count);
  for (Index k = 0; k < samples_count; ++k) {
    slip(k) = fixed.Contacts(frame.ToFixedFrame(times(k), stretch.col(k)))[0].slip_velocity;
  }
  const SpectralPeak peak = DominantPeak(TwoSidedSpectrum(slip, options.search_rate), PeakSide::kPositive);
  // A swing below 1e-8 of the slip velocity is round-off: no modulation.
  if (!peak.found || !(peak.amplitude > 1e-8 * slip.cwiseAbs().maxCoeff())) {
    orbit.message = fmt::format("the slip velocity does not vary over {} s: no modulation to shoot",
                                options.search_duration);
    return orbit;
  }
  const double period = 1.0 / peak.frequency;
  const Vector x0 = stretch.col(samples_count - 1);
  Vector x_period(x0.size());
  const IntegrationResult turn = integrator.Integrate(0.0, x0, period, x_period);
  if (!turn.Succeeded()) {
    orbit.message = "integrating one period failed: " + turn.BriefReport();
    return orbit;
  }
  const double phi = std::arg(FirstContact(structure, x_period) / FirstContact(structure, x0));

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
    orbit.message = fmt::format("Newton from the transient's orbit (T ≈ {:.6g} s, φ ≈ {:.4g}): {}",
                                period, phi, orbit.newton.BriefReport());
    return orbit;
  }
  orbit.period = problem.Period(orbit.u, omega);
  orbit.rotation = problem.Rotation(orbit.u);
  orbit.carrier_hz = frame.CarrierPrecession(orbit.period, orbit.rotation) / kTwoPi;

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
           FirstContact(structure, samples.states.col(i));
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
  orbit.dominant_hz = (frame_rate - phi_T - kTwoPi * best / T) / kTwoPi;
  orbit.sideband_ratio = other / std::abs(c[static_cast<std::size_t>(best + K)]);
  orbit.converged = true;
  orbit.message = fmt::format(
      "T = {:.9g} s, φ = {:+.6g} rad, carrier {:.6f} Hz, dominant k = {} at {:.6f} Hz, largest "
      "other component {:.3g} of it; {}", T, orbit.rotation, orbit.carrier_hz, best,
      orbit.dominant_hz, orbit.sideband_ratio, orbit.newton.BriefReport());
  return orbit;
}

}  // namespace rubcont
