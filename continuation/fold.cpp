#include "continuation/fold.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

FoldProblem::FoldProblem(Problem& inner, const Vector& u, double lambda)
    : inner_(inner),
      n_(inner.Dimension()),
      has_eta_(inner.HasSecondParameter()),
      s_(inner.Scale()),
      r_inv_(inner.ResidualScale().cwiseInverse()),
      s_lambda_(inner.LambdaScale()) {
  if (u.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "FoldProblem: u has {} entries; the inner problem's Dimension() = {}", u.size(), n_));
  }
  Matrix J;
  inner_.Jacobian(u, lambda, J);
  const Matrix J_scaled = r_inv_.asDiagonal() * J * s_.asDiagonal();
  const NullVectors null = SmallestSingularVectors(J_scaled, 1);
  c_ = null.right.col(0);
  b_ = null.left.col(0);
  v_.resize(n_);
  w_.resize(n_);
  M_.resize(n_ + 1, n_ + 1);
}

void FoldProblem::SetEta(double eta) {
  if (has_eta_ && inner_.SecondParameter() != eta) {
    inner_.SetSecondParameter(eta);
    cached_ = false;
  }
}

void FoldProblem::Evaluate(const Vector& U, double eta) {
  SetEta(eta);
  if (cached_ && U == cached_U_ && eta == cached_eta_) return;
  inner_.Jacobian(U.head(n_), U(n_), J_);
  M_.topLeftCorner(n_, n_).noalias() = r_inv_.asDiagonal() * J_ * s_.asDiagonal();
  M_.topRightCorner(n_, 1) = b_;
  M_.bottomLeftCorner(1, n_) = c_.transpose();
  M_(n_, n_) = 0.0;
  lu_.compute(M_);
  Vector e = Vector::Zero(n_ + 1);
  e(n_) = 1.0;
  const Vector vg = lu_.solve(e);
  const Vector wg = lu_.transpose().solve(e);
  v_ = vg.head(n_);
  g_ = vg(n_);
  w_ = wg.head(n_);
  cached_ = true;
  cached_U_ = U;
  cached_eta_ = eta;
}

double FoldProblem::DifferenceStep(const Vector& U, const Vector& direction) const {
  // U ± h·(s .* direction) moves the scaled state by ±h·direction.
  const double scaled_size = U.head(n_).cwiseQuotient(s_).lpNorm<Eigen::Infinity>();
  return CentralDifferenceStep(scaled_size, 1.0) /
         std::max(direction.lpNorm<Eigen::Infinity>(), 1e-300);
}

void FoldProblem::Residual(const Vector& U, double eta, Vector& G) {
  SetEta(eta);
  Vector F;
  inner_.Residual(U.head(n_), U(n_), F);
  Evaluate(U, eta);
  G.resize(n_ + 1);
  G.head(n_) = F;
  G(n_) = g_;
}

void FoldProblem::Jacobian(const Vector& U, double eta, Matrix& DG) {
  Evaluate(U, eta);
  const Vector u = U.head(n_);
  const double lambda = U(n_);
  Vector F_lambda;
  inner_.DfDlambda(u, lambda, F_lambda);
  DG.resize(n_ + 1, n_ + 1);
  DG.topLeftCorner(n_, n_) = J_;
  DG.topRightCorner(n_, 1) = F_lambda;
  // g_u = −(d/dt) F_u(u + tṽ)ᵀ w̃ and g_λ = −w̃ᵀ (d/dt) F_λ(u + tṽ), central differences.
  const Vector w_tilde = w_.cwiseProduct(r_inv_);
  const Vector v_tilde = v_.cwiseProduct(s_);
  const double h = DifferenceStep(U, v_);
  Matrix J_plus, J_minus;
  Vector F_lambda_plus, F_lambda_minus;
  inner_.Jacobian(u + h * v_tilde, lambda, J_plus);
  inner_.Jacobian(u - h * v_tilde, lambda, J_minus);
  inner_.DfDlambda(u + h * v_tilde, lambda, F_lambda_plus);
  inner_.DfDlambda(u - h * v_tilde, lambda, F_lambda_minus);
  DG.bottomLeftCorner(1, n_) = -((J_plus - J_minus).transpose() * w_tilde / (2.0 * h)).transpose();
  DG(n_, n_) = -w_tilde.dot(F_lambda_plus - F_lambda_minus) / (2.0 * h);
}

void FoldProblem::DfDlambda(const Vector& U, double eta, Vector& dG) {
  if (!has_eta_) {
    throw std::logic_error(
        "FoldProblem::DfDlambda: the inner problem has no second parameter to continue in");
  }
  Evaluate(U, eta);
  const Vector u = U.head(n_);
  const double lambda = U(n_);
  Vector F_eta, F_eta_plus, F_eta_minus;
  inner_.DfDeta(u, lambda, F_eta);
  const Vector w_tilde = w_.cwiseProduct(r_inv_);
  const Vector v_tilde = v_.cwiseProduct(s_);
  const double h = DifferenceStep(U, v_);
  inner_.DfDeta(u + h * v_tilde, lambda, F_eta_plus);
  inner_.DfDeta(u - h * v_tilde, lambda, F_eta_minus);
  dG.resize(n_ + 1);
  dG.head(n_) = F_eta;
  dG(n_) = -w_tilde.dot(F_eta_plus - F_eta_minus) / (2.0 * h);
}

Vector FoldProblem::Scale() const { return Joined(s_, s_lambda_); }

double FoldProblem::LambdaScale() const {
  return has_eta_ ? inner_.SecondParameterScale() : 1.0;
}

Vector FoldProblem::ResidualScale() const { return Joined(r_inv_.cwiseInverse(), 1.0); }

std::vector<std::string> FoldProblem::MeasureNames() const {
  std::vector<std::string> names{"lambda"};
  for (const std::string& name : inner_.MeasureNames()) names.push_back(name);
  return names;
}

Vector FoldProblem::Measures(const Vector& U, double eta) {
  SetEta(eta);
  const Vector inner_measures = inner_.Measures(U.head(n_), U(n_));
  Vector measures(1 + inner_measures.size());
  measures(0) = U(n_);
  measures.tail(inner_measures.size()) = inner_measures;
  return measures;
}

void FoldProblem::UpdateBorders(const Vector& U, double eta) {
  Evaluate(U, eta);
  const double v_norm = v_.norm();
  const double w_norm = w_.norm();
  if (!(v_norm > 0.0) || !(w_norm > 0.0) || !std::isfinite(v_norm) || !std::isfinite(w_norm)) {
    return;  // keep the old borders: the bordered matrix was singular here
  }
  c_ = v_ / v_norm;
  b_ = w_ / w_norm;
  cached_ = false;
}

double FoldProblem::TestValue(const Vector& U, double eta) {
  Evaluate(U, eta);
  return g_;
}

const Vector& FoldProblem::RightNullVector(const Vector& U, double eta) {
  Evaluate(U, eta);
  return v_;
}

const Vector& FoldProblem::LeftNullVector(const Vector& U, double eta) {
  Evaluate(U, eta);
  return w_;
}

double FoldProblem::CuspCoefficient(const Vector& U, double eta) {
  Evaluate(U, eta);
  const Vector v_unit = v_ / v_.norm();
  const Vector w_unit = w_ / w_.norm();
  const Vector v_tilde = v_unit.cwiseProduct(s_);
  const Vector w_tilde = w_unit.cwiseProduct(r_inv_);
  const Vector u = U.head(n_);
  const double lambda = U(n_);
  const double h = DifferenceStep(U, v_unit);
  Matrix J_plus, J_minus;
  inner_.Jacobian(u + h * v_tilde, lambda, J_plus);
  inner_.Jacobian(u - h * v_tilde, lambda, J_minus);
  // ½ ŵᵀ D²F̂(v̂, v̂) = ½ w̃ᵀ (d/dt)[F_u(u + tṽ) ṽ].
  return 0.5 * w_tilde.dot((J_plus - J_minus) * v_tilde) / (2.0 * h);
}

Vector FoldProblem::EventFunctions(const Vector& U, double eta) {
  SetEta(eta);
  return inner_.EventFunctions(U.head(n_), U(n_));
}

Vector FoldProblem::TestFunctions(const Vector& U, double eta) {
  return Vector::Constant(1, CuspCoefficient(U, eta));
}

FoldLocation LocateFold(Problem& problem, const Vector& u_guess, double lambda_guess,
                        const LocationOptions& options) {
  Validate(options);
  FoldProblem fold(problem, u_guess, lambda_guess);
  const double eta = problem.HasSecondParameter() ? problem.SecondParameter() : 0.0;
  const Index m = fold.Dimension();
  const Vector scale = fold.Scale();
  const Vector residual_inverse = fold.ResidualScale().cwiseInverse();
  Vector U = Joined(u_guess, lambda_guess);
  Vector G;
  Matrix DG;
  Eigen::PartialPivLU<Matrix> lu(m);
  FoldLocation result;
  double last_step = kInfinity;
  for (int iteration = 0;; ++iteration) {
    fold.Residual(U, eta, G);
    const double residual = G.cwiseProduct(residual_inverse).lpNorm<Eigen::Infinity>();
    result.residual_norm = residual;
    result.test_value = G(m - 1);
    if (!std::isfinite(residual)) {
      result.message = "non-finite residual";
      break;
    }
    if (iteration > 0 && residual <= options.residual_tolerance &&
        last_step <= options.step_tolerance) {
      result.converged = true;
      break;
    }
    if (iteration >= options.max_iterations) {
      result.message = fmt::format("no convergence in {} iterations (residual {:.3e}, step {:.3e})",
                                   iteration, residual, last_step);
      break;
    }
    fold.Jacobian(U, eta, DG);
    const Matrix scaled = residual_inverse.asDiagonal() * DG * scale.asDiagonal();
    lu.compute(scaled);
    if (!(lu.rcond() > 1e-14)) {
      result.message = "singular minimally augmented Jacobian";
      break;
    }
    const Vector delta = lu.solve(-G.cwiseProduct(residual_inverse));
    last_step = delta.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(last_step)) {
      result.message = "non-finite Newton step";
      break;
    }
    U += delta.cwiseProduct(scale);
    result.iterations = iteration + 1;
    result.last_correction = last_step;
    fold.UpdateBorders(U, eta);
  }
  result.u = U.head(m - 1);
  result.lambda = U(m - 1);
  return result;
}

Branch ContinueFoldCurve(Problem& problem, const SpecialPoint& fold,
                         const ContinuationOptions& options, const StepCallback& callback) {
  if (!problem.HasSecondParameter()) {
    throw std::invalid_argument(
        "ContinueFoldCurve: the problem has no second parameter (HasSecondParameter() is false)");
  }
  if (fold.type != SpecialPointType::kFold) {
    throw std::invalid_argument(fmt::format(
        "ContinueFoldCurve: the special point is a {}, not a fold", ToString(fold.type)));
  }
  const SecondParameterGuard restore(problem);  // the curve problem moves η
  FoldProblem fold_problem(problem, fold.u, fold.lambda);
  return Continue(fold_problem, Joined(fold.u, fold.lambda), restore.eta(), options,
                  callback);
}

}  // namespace rubcont
