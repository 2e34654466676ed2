#include "continuation/problem.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuation/lyapunov.h"
#include "solvers/finite_difference.h"

namespace rubcont {

const char* ToString(SpecialPointType type) {
  switch (type) {
    case SpecialPointType::kFold: return "fold";
    case SpecialPointType::kBranchPoint: return "branch point";
    case SpecialPointType::kHopf: return "Hopf";
    case SpecialPointType::kRealEigenvalueCrossing: return "real eigenvalue crossing";
    case SpecialPointType::kPeriodDoubling: return "period doubling";
    case SpecialPointType::kNeimarkSacker: return "Neimark-Sacker";
    case SpecialPointType::kMultiplierPlusOne: return "multiplier +1";
    case SpecialPointType::kEvent: return "event";
    case SpecialPointType::kCusp: return "cusp";
    case SpecialPointType::kTestFunction: return "test function";
    case SpecialPointType::kGrazing: return "grazing";
    case SpecialPointType::kBogdanovTakens: return "Bogdanov-Takens";
    case SpecialPointType::kZeroHopf: return "zero-Hopf";
    case SpecialPointType::kDoubleHopf: return "double Hopf";
    case SpecialPointType::kGeneralizedHopf: return "generalized Hopf";
  }
  return "unknown";
}

int Spectrum::UnstableCount(double tolerance) const {
  int count = 0;
  for (Index i = 0; i < values.size(); ++i) {
    if (kind == SpectrumKind::kEigenvalues ? values(i).real() > tolerance
                                           : std::abs(values(i)) > 1.0 + tolerance) {
      ++count;
    }
  }
  return count;
}

void Problem::Jacobian(const Vector& u, double lambda, Matrix& J) {
  const Vector typical = Scale();
  FiniteDifferenceJacobian([&](const Vector& x, Vector& F) { Residual(x, lambda, F); }, u,
                           Dimension(), J, {}, &typical);
}

void Problem::DfDlambda(const Vector& u, double lambda, Vector& dF) {
  const double h = CentralDifferenceStep(lambda, LambdaScale());
  Vector F_plus, F_minus;
  Residual(u, lambda + h, F_plus);
  Residual(u, lambda - h, F_minus);
  dF = (F_plus - F_minus) / (2.0 * h);
}

LyapunovCoefficient Problem::FirstLyapunov(const Vector& /*u*/, double /*lambda*/,
                                           std::complex<double> /*critical*/) {
  LyapunovCoefficient out;
  out.message = "not computed by this problem";
  return out;
}

Spectrum Problem::Stability(const Vector& /*u*/, double /*lambda*/) {
  throw std::logic_error("Problem::Stability called on a problem without a stability operator");
}

double Problem::SecondParameter() const {
  throw std::logic_error("Problem::SecondParameter called on a problem without a second parameter");
}

void Problem::SetSecondParameter(double /*eta*/) {
  throw std::logic_error(
      "Problem::SetSecondParameter called on a problem without a second parameter");
}

void Problem::DfDeta(const Vector& u, double lambda, Vector& dF) {
  const double eta = SecondParameter();
  const double h = CentralDifferenceStep(eta, SecondParameterScale());
  Vector F_plus, F_minus;
  SetSecondParameter(eta + h);
  Residual(u, lambda, F_plus);
  SetSecondParameter(eta - h);
  Residual(u, lambda, F_minus);
  SetSecondParameter(eta);
  dF = (F_plus - F_minus) / (2.0 * h);
}

Vector Joined(const Vector& u, double lambda) {
  Vector joined(u.size() + 1);
  joined.head(u.size()) = u;
  joined(u.size()) = lambda;
  return joined;
}

}  // namespace rubcont
