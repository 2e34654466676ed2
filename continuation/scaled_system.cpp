#include "continuation/scaled_system.h"

#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"

namespace rubcont {

ScaledSystem::ScaledSystem(Problem& problem, BranchStatistics* statistics)
    : problem_(problem), statistics_(statistics) {
  Refresh();
}

void ScaledSystem::Refresh() {
  n_ = problem_.Dimension();
  if (n_ < 1) {
    throw std::invalid_argument(
        fmt::format("Problem::Dimension() = {}: must be at least 1", n_));
  }
  scale_ = problem_.Scale();
  residual_scale_ = problem_.ResidualScale();
  lambda_scale_ = problem_.LambdaScale();
  if (scale_.size() != n_ || !(scale_.array() > 0.0).all() || !scale_.allFinite()) {
    throw std::invalid_argument(fmt::format(
        "Problem::Scale() has {} entries (min {}): must have Dimension() = {} positive finite "
        "entries",
        scale_.size(), scale_.size() > 0 ? scale_.minCoeff() : 0.0, n_));
  }
  if (residual_scale_.size() != n_ || !(residual_scale_.array() > 0.0).all() ||
      !residual_scale_.allFinite()) {
    throw std::invalid_argument(fmt::format(
        "Problem::ResidualScale() has {} entries (min {}): must have Dimension() = {} positive "
        "finite entries",
        residual_scale_.size(), residual_scale_.size() > 0 ? residual_scale_.minCoeff() : 0.0,
        n_));
  }
  if (!(lambda_scale_ > 0.0) || !std::isfinite(lambda_scale_)) {
    throw std::invalid_argument(fmt::format(
        "Problem::LambdaScale() = {}: must be positive and finite", lambda_scale_));
  }
  residual_inverse_ = residual_scale_.cwiseInverse();
  u_.resize(n_);
  F_.resize(n_);
  J_.resize(n_, n_);
  dF_.resize(n_);
}

void ScaledSystem::ToScaled(const Vector& u, double lambda, Vector& x) const {
  x.resize(n_ + 1);
  x.head(n_) = u.cwiseQuotient(scale_);
  x(n_) = lambda / lambda_scale_;
}

void ScaledSystem::ToUnscaled(const Vector& x, Vector& u, double& lambda) const {
  u = x.head(n_).cwiseProduct(scale_);
  lambda = x(n_) * lambda_scale_;
}

Vector ScaledSystem::ScaledDirection(const Vector& du, double dlambda) const {
  Vector d(n_ + 1);
  d.head(n_) = du.cwiseQuotient(scale_);
  d(n_) = dlambda / lambda_scale_;
  return d;
}

bool ScaledSystem::Residual(const Vector& x, Vector& F) {
  u_.noalias() = x.head(n_).cwiseProduct(scale_);
  const double lambda = x(n_) * lambda_scale_;
  problem_.Residual(u_, lambda, F_);
  if (statistics_ != nullptr) ++statistics_->residual_evaluations;
  if (F_.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "Problem::Residual returned {} equations; Dimension() = {}", F_.size(), n_));
  }
  F.resize(n_);
  F.noalias() = F_.cwiseProduct(residual_inverse_);
  return F.allFinite();
}

bool ScaledSystem::Jacobian(const Vector& x, Matrix& DF) {
  u_.noalias() = x.head(n_).cwiseProduct(scale_);
  const double lambda = x(n_) * lambda_scale_;
  problem_.Jacobian(u_, lambda, J_);
  problem_.DfDlambda(u_, lambda, dF_);
  if (statistics_ != nullptr) ++statistics_->jacobian_evaluations;
  if (J_.rows() != n_ || J_.cols() != n_ || dF_.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "Problem::Jacobian returned {} × {} and DfDlambda {} entries; Dimension() = {}",
        J_.rows(), J_.cols(), dF_.size(), n_));
  }
  DF.resize(n_, n_ + 1);
  DF.leftCols(n_).noalias() = residual_inverse_.asDiagonal() * J_ * scale_.asDiagonal();
  DF.col(n_).noalias() = dF_.cwiseProduct(residual_inverse_) * lambda_scale_;
  return DF.allFinite();
}

const char* ToString(CorrectorStatus status) {
  switch (status) {
    case CorrectorStatus::kConverged: return "converged";
    case CorrectorStatus::kMaxIterations: return "iteration limit reached";
    case CorrectorStatus::kSingular: return "singular bordered Jacobian";
    case CorrectorStatus::kDiverged: return "diverged";
    case CorrectorStatus::kNonFinite: return "non-finite residual or Jacobian";
  }
  return "unknown";
}

BorderedCorrector::BorderedCorrector(ScaledSystem& system, const CorrectorOptions& options)
    : system_(system), options_(options) {
  Resize();
}

void BorderedCorrector::Resize() {
  const Index n = system_.n();
  F_.resize(n);
  DF_.resize(n, n + 1);
  A_.resize(n + 1, n + 1);
  rhs_.resize(n + 1);
  delta_.resize(n + 1);
}

bool BorderedCorrector::Factor(const Vector& border) {
  const Index n = system_.n();
  A_.topRows(n) = DF_;
  A_.row(n) = border.transpose();
  lu_.Compute(A_);
  // Singular to working precision when a pivot is negligible against the largest one.
  return lu_.PivotRatio() > options_.min_pivot_ratio;
}

void BorderedCorrector::SolveTangent(Vector& tangent) {
  const Index n = system_.n();
  rhs_.setZero();
  rhs_(n) = 1.0;
  lu_.Solve(rhs_, tangent);
  tangent /= tangent.norm();
}

namespace {
constexpr int kMaxResidualHalvings = 4;  // of a Newton step whose end has no finite residual
}  // namespace

CorrectorStatus BorderedCorrector::Correct(const Vector& x_ref, const Vector& border,
                                           double sigma, const Vector& guess,
                                           CorrectedPoint& out, bool accept_singular_solution) {
  const Index n = system_.n();
  out.x = guess;
  out.iterations = 0;
  out.step_norm = 0.0;
  if (!system_.Residual(out.x, F_)) return CorrectorStatus::kNonFinite;
  out.residual_norm = F_.lpNorm<Eigen::Infinity>();
  const double initial_norm = std::max(out.residual_norm, options_.residual_tolerance);
  for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
    if (!system_.Jacobian(out.x, DF_)) return CorrectorStatus::kNonFinite;
    const double constraint = sigma - border.dot(out.x - x_ref);
    if (!Factor(border)) {
      if (accept_singular_solution && out.residual_norm <= options_.residual_tolerance &&
          std::abs(constraint) <= options_.step_tolerance) {
        out.tangent = border;
        out.det.sign = 0;
        out.det.log_abs = -kInfinity;
        return CorrectorStatus::kConverged;
      }
      return CorrectorStatus::kSingular;
    }
    rhs_.head(n) = -F_;
    rhs_(n) = constraint;
    lu_.Solve(rhs_, delta_);
    if (!delta_.allFinite()) return CorrectorStatus::kNonFinite;
    out.x += delta_;
    out.iterations = iteration;
    // A Newton step that leaves the residual's domain (a shooting problem's integration failing
    // on the way: C(a)'s torus at 49 rpm, corrected by Gauss collocation from BDF's solution) is
    // halved until the residual is finite again, at most kMaxResidualHalvings times.
    bool finite = system_.Residual(out.x, F_);
    for (int halving = 0; !finite && halving < kMaxResidualHalvings; ++halving) {
      delta_ *= 0.5;
      out.x -= delta_;
      finite = system_.Residual(out.x, F_);
    }
    if (!finite) return CorrectorStatus::kNonFinite;
    out.step_norm = delta_.lpNorm<Eigen::Infinity>();
    const double previous_norm = out.residual_norm;
    out.residual_norm = F_.lpNorm<Eigen::Infinity>();
    // The round-off floor of an ill-conditioned system: the residual is already below tolerance
    // and a further correction no longer halves it, so the correction is noise (as NewtonSolve).
    const bool at_floor = previous_norm <= options_.residual_tolerance &&
                          out.residual_norm > 0.5 * previous_norm;
    if (out.residual_norm <= options_.residual_tolerance &&
        (out.step_norm <= options_.step_tolerance || at_floor)) {
      SolveTangent(out.tangent);
      out.det = lu_.Determinant();
      return CorrectorStatus::kConverged;
    }
    if (out.residual_norm > options_.divergence_factor * initial_norm) {
      return CorrectorStatus::kDiverged;
    }
  }
  return CorrectorStatus::kMaxIterations;
}

bool BorderedCorrector::TangentAt(const Vector& x, const Vector& border, Vector& tangent,
                                  LogDeterminant& det) {
  if (!system_.Jacobian(x, DF_)) return false;
  if (!Factor(border)) return false;
  SolveTangent(tangent);
  det = lu_.Determinant();
  return true;
}

}  // namespace rubcont
