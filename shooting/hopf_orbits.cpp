#include "shooting/hopf_orbits.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

#include "continuation/continuation.h"
#include "solvers/constants.h"

namespace rubcont {

PeriodicOrbitBranch ContinueOrbitsFromHopf(OdeSystem& system, const SpecialPoint& hopf,
                                           const HopfOrbitOptions& options) {
  Validate(options.orbits);
  const Index n = system.Dimension();
  if (hopf.type != SpecialPointType::kHopf || hopf.u.size() != n || !(hopf.frequency > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "ContinueOrbitsFromHopf: need a Hopf point of this system's equilibria (type {}, {} "
        "unknowns for {} states, frequency {})",
        ToString(hopf.type), hopf.u.size(), n, hopf.frequency));
  }
  if (!(options.amplitude > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "HopfOrbitOptions.amplitude = {}: must be positive", options.amplitude));
  }
  const double lambda = hopf.lambda, omega = hopf.frequency;
  system.SetParameter(lambda);
  Matrix J(n, n);
  system.JacobianX(0.0, hopf.u, J);
  Eigen::ComplexEigenSolver<Matrix> eigen(J);
  Index k = 0;
  for (Index i = 1; i < n; ++i) {
    if (std::abs(eigen.eigenvalues()(i) - std::complex<double>(0.0, omega)) <
        std::abs(eigen.eigenvalues()(k) - std::complex<double>(0.0, omega))) {
      k = i;
    }
  }
  const std::complex<double> critical = eigen.eigenvalues()(k);
  if (std::abs(critical - std::complex<double>(0.0, omega)) > 1e-3 * omega) {
    throw std::invalid_argument(fmt::format(
        "ContinueOrbitsFromHopf: no eigenvalue near i·{} at λ = {} (closest {}{:+}i)", omega,
        lambda, critical.real(), critical.imag()));
  }
  // v with ‖Re v ./ scale‖ = 1 (its phase chosen so that Re v is as long as it gets).
  const Vector scale = system.StateScale();
  ComplexVector v = eigen.eigenvectors().col(k);
  const ComplexVector scaled = v.cwiseQuotient(scale.cast<std::complex<double>>());
  const std::complex<double> square = scaled.transpose() * scaled;  // Σ v_i², for the phase
  v *= std::exp(std::complex<double>(0.0, -0.5 * std::arg(square)));
  v /= v.real().cwiseQuotient(scale).norm();

  // The linear orbit at amplitude a: segment starts x_H + a Re(v e^{iωt_i}), T = 2π/ω.
  ShootingOptions shooting = options.orbits.shooting;
  shooting.refresh_phase_reference = true;
  if (shooting.period_scale <= 0.0) shooting.period_scale = kTwoPi / omega;
  if (options.kind == OrbitKind::kForced) {
    throw std::invalid_argument("HopfOrbitOptions.kind = kForced: Hopf orbits are autonomous");
  }
  ShootingProblem problem(system, options.kind, shooting);
  if (!options.orbits.measures.empty()) problem.SetMeasures(options.orbits.measures);
  problem.SetTestFunctions(options.orbits.test_functions);
  const double period = kTwoPi / omega;
  const int segments = shooting.segments;
  Matrix starts(n, segments), directions(n, segments);
  for (int i = 0; i < segments; ++i) {
    const double t = period * (shooting.mesh.empty() ? static_cast<double>(i) / segments
                                                     : shooting.mesh[static_cast<std::size_t>(i)]);
    const Vector shape = (v * std::exp(std::complex<double>(0.0, omega * t))).real();
    directions.col(i) = shape;
    starts.col(i) = hopf.u + options.amplitude * shape;
  }
  const Vector u0 = problem.Pack(starts, period, 0.0);
  problem.SetPhaseReference(u0, lambda);
  const Vector du = problem.Pack(directions, 0.0, 0.0).cwiseQuotient(problem.Scale());

  Continuation stepper(problem, OrbitContinuationOptions(options.orbits));
  PeriodicOrbitBranch result;
  result.kind = options.kind;
  result.state_dimension = n;
  result.segments = segments;
  result.start_lambda = lambda;
  result.shooting = shooting;
  result.shooting.lambda_scale = problem.LambdaScale();
  stepper.StartWithTangent(u0, lambda, du, 0.0);
  result.branch = RunToEnd(stepper, options.on_step, OrbitEndTest(options.orbits, lambda));
  result.work = problem.statistics();
  return result;
}

}  // namespace rubcont
