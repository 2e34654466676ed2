#include "continuation/hopf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/SVD>
#include <fmt/core.h>

#include "continuation/lyapunov.h"
#include "solvers/constants.h"
#include "solvers/finite_difference.h"

namespace rubcont {

HopfProblem::HopfProblem(Problem& inner, const Vector& u, double lambda,
                         std::complex<double> critical)
    : inner_(inner),
      n_(inner.Dimension()),
      s_(inner.Scale()),
      r_(inner.ResidualScale()),
      s_lambda_(inner.LambdaScale()),
      omega0_(critical.imag()),
      reference_first_(critical),
      reference_second_(std::conj(critical)) {
  if (!inner.HasStability() || !inner.HasSecondParameter()) {
    throw std::invalid_argument(
        "HopfProblem: the inner problem needs a stability operator and a second parameter");
  }
  if (!(omega0_ > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "HopfProblem: the critical eigenvalue {} + {}i has no positive imaginary part",
        critical.real(), critical.imag()));
  }
  if (u.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "HopfProblem: u has {} entries; the inner problem's Dimension() = {}", u.size(), n_));
  }
  const Spectrum spectrum = inner.Stability(u, lambda);
  radius_ = omega0_;
  if (spectrum.valid) radius_ = std::max(radius_, spectrum.values.cwiseAbs().maxCoeff());
  const LyapunovCoefficient l1 = inner.FirstLyapunov(u, lambda, critical);
  l1_reference_ = l1.valid ? std::abs(l1.l1) : 0.0;
}

void HopfProblem::SetEta(double eta) {
  if (inner_.SecondParameter() != eta) inner_.SetSecondParameter(eta);
}

HopfProblem::Pair HopfProblem::Evaluate(const Vector& U, double eta) {
  SetEta(eta);
  Pair pair;
  const Spectrum spectrum = inner_.Stability(U.head(n_), U(n_));
  const Index m = spectrum.values.size();
  if (!spectrum.valid || m < 2) return pair;
  auto nearest = [&](std::complex<double> target, Index skip) {
    Index best = -1;
    for (Index i = 0; i < m; ++i) {
      if (i == skip) continue;
      if (best < 0 || std::abs(spectrum.values(i) - target) <
                          std::abs(spectrum.values(best) - target)) {
        best = i;
      }
    }
    return best;
  };
  const Index a = nearest(reference_first_, -1);
  const Index b = nearest(reference_second_, a);
  pair.first = spectrum.values(a);
  pair.second = spectrum.values(b);
  pair.h = 0.5 * (pair.first + pair.second).real();
  pair.kappa = (pair.first * pair.second).real();
  pair.rest.kind = spectrum.kind;
  pair.rest.trivial_removed = spectrum.trivial_removed;
  pair.rest.values.resize(m - 2);
  for (Index i = 0, j = 0; i < m; ++i) {
    if (i != a && i != b) pair.rest.values(j++) = spectrum.values(i);
  }
  pair.rest.valid = true;
  pair.valid = std::isfinite(pair.h) && std::isfinite(pair.kappa);
  return pair;
}

double HopfProblem::ScaledSum(const Vector& U, double eta) {
  const Pair pair = Evaluate(U, eta);
  return pair.valid ? pair.h / radius_ : kNaN;
}

void HopfProblem::Residual(const Vector& U, double eta, Vector& G) {
  SetEta(eta);
  Vector F;
  inner_.Residual(U.head(n_), U(n_), F);
  G.resize(n_ + 1);
  G.head(n_) = F;
  G(n_) = ScaledSum(U, eta);
}

void HopfProblem::Jacobian(const Vector& U, double eta, Matrix& DG) {
  SetEta(eta);
  const Vector u = U.head(n_);
  const double lambda = U(n_);
  Matrix J;
  Vector F_lambda;
  inner_.Jacobian(u, lambda, J);
  inner_.DfDlambda(u, lambda, F_lambda);
  DG.resize(n_ + 1, n_ + 1);
  DG.topLeftCorner(n_, n_) = J;
  DG.topRightCorner(n_, 1) = F_lambda;
  // ∂h/∂u by central differences along the right singular vectors V_k of the scaled F̂_u, with the
  // step kCentralDifferenceStep / max(1, σ_k): the stiff contact's directions (σ ~ 5e4 on case
  // A(a)) are where the spectrum is nonlinear on the scale of the penetration, far below the
  // position scale. Measured there, on a coordinate basis: partial derivatives of ±2.8e4 (scaled)
  // that change by 0.3 % from steps 1e-9 to 1e-7 and change sign at 1e-5 cancel in the physical
  // directions to O(1), and Newton stalled at a rate of 0.97 per iteration.
  const Matrix J_scaled = r_.cwiseInverse().asDiagonal() * J * s_.asDiagonal();
  const Eigen::JacobiSVD<Matrix> svd(J_scaled, Eigen::ComputeFullV);
  Vector row_scaled = Vector::Zero(n_);
  for (Index k = 0; k < n_; ++k) {
    const Vector direction = svd.matrixV().col(k);
    const double t = kCentralDifferenceStep / std::max(1.0, svd.singularValues()(k));
    Vector Up = U, Um = U;
    Up.head(n_) += t * direction.cwiseProduct(s_);
    Um.head(n_) -= t * direction.cwiseProduct(s_);
    row_scaled += (ScaledSum(Up, eta) - ScaledSum(Um, eta)) / (2.0 * t) * direction;
  }
  DG.bottomLeftCorner(1, n_) = row_scaled.cwiseQuotient(s_).transpose();
  const double step = CentralDifferenceStep(lambda, s_lambda_);
  Vector Up = U, Um = U;
  Up(n_) += step;
  Um(n_) -= step;
  DG(n_, n_) = (ScaledSum(Up, eta) - ScaledSum(Um, eta)) / (2.0 * step);
}

void HopfProblem::DfDlambda(const Vector& U, double eta, Vector& dG) {
  SetEta(eta);
  Vector F_eta;
  inner_.DfDeta(U.head(n_), U(n_), F_eta);
  const double step = CentralDifferenceStep(eta, inner_.SecondParameterScale());
  const double plus = ScaledSum(U, eta + step);
  const double minus = ScaledSum(U, eta - step);
  SetEta(eta);
  dG.resize(n_ + 1);
  dG.head(n_) = F_eta;
  dG(n_) = (plus - minus) / (2.0 * step);
}

Vector HopfProblem::Scale() const { return Joined(s_, s_lambda_); }

Vector HopfProblem::ResidualScale() const { return Joined(r_, 1.0); }

Spectrum HopfProblem::Stability(const Vector& U, double eta) { return Evaluate(U, eta).rest; }

std::vector<std::string> HopfProblem::MeasureNames() const {
  std::vector<std::string> names{"lambda", "hopf_frequency"};
  for (const std::string& name : inner_.MeasureNames()) names.push_back(name);
  return names;
}

Vector HopfProblem::Measures(const Vector& U, double eta) {
  const Pair pair = Evaluate(U, eta);
  const Vector inner_measures = inner_.Measures(U.head(n_), U(n_));
  Vector measures(2 + inner_measures.size());
  measures(0) = U(n_);
  measures(1) = pair.valid && pair.kappa > 0.0 ? std::sqrt(pair.kappa) : kNaN;
  measures.tail(inner_measures.size()) = inner_measures;
  return measures;
}

Vector HopfProblem::EventFunctions(const Vector& U, double eta) {
  SetEta(eta);
  return inner_.EventFunctions(U.head(n_), U(n_));
}

Vector HopfProblem::TestFunctions(const Vector& U, double eta) {
  const Pair pair = Evaluate(U, eta);
  Vector tests = Vector::Constant(2, kNaN);
  if (!pair.valid) return tests;
  tests(0) = pair.kappa / (omega0_ * omega0_);
  // l1 where the inner problem computes it to 1 % of its value where the curve starts
  // (AgreesTo; NaN otherwise: no sign change is seen across such a point), of the pair's member
  // with Im > 0; on neutral saddles (κ < 0) none.
  if (pair.kappa > 0.0 && l1_reference_ > 0.0) {
    const std::complex<double> critical = pair.first.imag() > 0.0 ? pair.first : pair.second;
    const LyapunovCoefficient l1 = inner_.FirstLyapunov(U.head(n_), U(n_), critical);
    if (std::isfinite(l1.l1) && AgreesTo(l1, l1_reference_)) tests(1) = l1.l1;
  }
  return tests;
}

void HopfProblem::PointAccepted(const Vector& U, double eta) {
  SetEta(eta);
  inner_.PointAccepted(U.head(n_), U(n_));  // e.g. a rotating wave's phase reference
  const Pair pair = Evaluate(U, eta);
  if (!pair.valid) return;
  reference_first_ = pair.first;
  reference_second_ = pair.second;
}

Branch ContinueHopfCurve(Problem& problem, const SpecialPoint& hopf,
                         const ContinuationOptions& options, const StepCallback& callback) {
  if (!problem.HasSecondParameter() || !problem.HasStability()) {
    throw std::invalid_argument(
        "ContinueHopfCurve: the problem needs a second parameter and a stability operator");
  }
  if (hopf.type != SpecialPointType::kHopf) {
    throw std::invalid_argument(fmt::format(
        "ContinueHopfCurve: the special point is a {}, not a Hopf point", ToString(hopf.type)));
  }
  const SecondParameterGuard restore(problem);  // the curve problem moves η
  HopfProblem hopf_problem(problem, hopf.u, hopf.lambda, hopf.critical_value);
  ContinuationOptions run = options;
  run.detect.stability = true;  // the rest of the spectrum: zero-Hopf and double-Hopf points
  Branch curve = Continue(hopf_problem, Joined(hopf.u, hopf.lambda), restore.eta(), run,
                          callback);
  // The rest of the spectrum crossing the axis on a Hopf curve: codimension-two points.
  for (SpecialPoint& sp : curve.special_points) {
    if (sp.type == SpecialPointType::kHopf) {
      sp.type = SpecialPointType::kDoubleHopf;
      sp.note = fmt::format("a second pair crosses the imaginary axis at ±{:.6g}i", sp.frequency);
    } else if (sp.type == SpecialPointType::kRealEigenvalueCrossing) {
      sp.type = SpecialPointType::kZeroHopf;
      sp.note = "a real eigenvalue crosses 0 beside the Hopf pair";
    }
  }
  return curve;
}

}  // namespace rubcont
