#include "continuation/equilibrium_problem.h"

#include "continuation/lyapunov.h"

#include <algorithm>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

namespace rubcont {

EquilibriumProblem::EquilibriumProblem(OdeSystem& system)
    : system_(system), lambda_scale_(std::max(std::abs(system.Parameter()), 1.0)) {
  if (system.ForcingPeriod() != 0.0) {
    throw std::invalid_argument(fmt::format(
        "EquilibriumProblem: the system is forced (ForcingPeriod() = {}): it has no equilibria",
        system.ForcingPeriod()));
  }
}

void EquilibriumProblem::Residual(const Vector& u, double lambda, Vector& F) {
  system_.SetParameter(lambda);
  F.resize(u.size());
  system_.Rhs(0.0, u, F);
}

void EquilibriumProblem::Jacobian(const Vector& u, double lambda, Matrix& J) {
  system_.SetParameter(lambda);
  J.resize(u.size(), u.size());
  system_.JacobianX(0.0, u, J);
}

void EquilibriumProblem::DfDlambda(const Vector& u, double lambda, Vector& dF) {
  system_.SetParameter(lambda);
  dF.resize(u.size());
  system_.DfDparameter(0.0, u, dF);
}

Spectrum EquilibriumProblem::Stability(const Vector& u, double lambda) {
  Matrix J;
  Jacobian(u, lambda, J);
  Spectrum spectrum;
  spectrum.kind = SpectrumKind::kEigenvalues;
  spectrum.values = J.eigenvalues();
  std::sort(spectrum.values.data(), spectrum.values.data() + spectrum.values.size(),
            [](const std::complex<double>& a, const std::complex<double>& b) {
              return a.real() > b.real();
            });
  spectrum.valid = spectrum.values.allFinite();
  return spectrum;
}

LyapunovCoefficient EquilibriumProblem::FirstLyapunov(const Vector& u, double lambda,
                                                      std::complex<double> critical) {
  return FirstLyapunovCoefficient(*this, u, lambda, 1e-3, critical);
}

}  // namespace rubcont
