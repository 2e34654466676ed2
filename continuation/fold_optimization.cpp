#include "continuation/fold_optimization.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/SVD>
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"

namespace rubcont {

namespace {

constexpr double kIpoptNoBound = 1e19;  // Ipopt's "no bound"

// The NLP in scaled variables x̂ = (û, λ̂) ∈ Rⁿ⁺¹ with n equality constraints F̂ = 0.
class FoldNlp : public Ipopt::TNLP {
 public:
  using Index = Ipopt::Index;  // class-scoped: file scope reaches a unity batch's next files
  using Number = Ipopt::Number;

  FoldNlp(Problem& problem, const Vector& u0, double lambda0,
          const FoldOptimizationOptions& options)
      : problem_(problem),
        n_(problem.Dimension()),
        s_(problem.Scale()),
        s_lambda_(problem.LambdaScale()),
        r_inv_(problem.ResidualScale().cwiseInverse()),
        options_(options) {
    x0_.resize(n_ + 1);
    x0_.head(n_) = u0.cwiseQuotient(s_);
    x0_(n_) = lambda0 / s_lambda_;
    solution_ = x0_;
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = static_cast<Index>(n_ + 1);
    m = static_cast<Index>(n_);
    nnz_jac_g = n * m;
    nnz_h_lag = n * (n + 1) / 2;
    index_style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = -kIpoptNoBound;
      x_u[i] = kIpoptNoBound;
    }
    if (std::isfinite(options_.lambda_min)) x_l[n - 1] = options_.lambda_min / s_lambda_;
    if (std::isfinite(options_.lambda_max)) x_u[n - 1] = options_.lambda_max / s_lambda_;
    for (Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                          bool init_lambda, Number*) override {
    if (!init_x || init_z || init_lambda) return false;
    for (Index i = 0; i < n; ++i) x[i] = x0_(i);
    return true;
  }

  bool eval_f(Index n, const Number* x, bool, Number& obj_value) override {
    obj_value = -options_.sense * x[n - 1];
    return true;
  }

  bool eval_grad_f(Index n, const Number*, bool, Number* grad_f) override {
    for (Index i = 0; i < n; ++i) grad_f[i] = 0.0;
    grad_f[n - 1] = -options_.sense;
    return true;
  }

  bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
    try {
      Vector F;
      problem_.Residual(Unscaled(x, n).head(n_), Unscaled(x, n)(n_), F);
      if (!F.allFinite()) return false;
      for (Index i = 0; i < m; ++i) g[i] = F(i) * r_inv_(i);
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index m, Index, Index* iRow, Index* jCol,
                  Number* values) override {
    if (values == nullptr) {
      Index k = 0;
      for (Index i = 0; i < m; ++i) {
        for (Index j = 0; j < n; ++j, ++k) {
          iRow[k] = i;
          jCol[k] = j;
        }
      }
      return true;
    }
    try {
      const Matrix J = ScaledJacobian(Unscaled(x, n));
      if (!J.allFinite()) return false;
      Index k = 0;
      for (Index i = 0; i < m; ++i) {
        for (Index j = 0; j < n; ++j, ++k) values[k] = J(i, j);
      }
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

  bool eval_h(Index n, const Number* x, bool, Number, Index m, const Number* lambda, bool, Index,
              Index* iRow, Index* jCol, Number* values) override {
    if (values == nullptr) {
      Index k = 0;
      for (Index i = 0; i < n; ++i) {
        for (Index j = 0; j <= i; ++j, ++k) {
          iRow[k] = i;
          jCol[k] = j;
        }
      }
      return true;
    }
    // H = Σ y_i ∇²F̂_i = ∂/∂x̂ (F̂'ᵀ y), column j from the Jacobians at x̂ ± h e_j. The objective
    // is linear: it adds nothing.
    try {
      Vector y(m);
      for (Index i = 0; i < m; ++i) y(i) = lambda[i];
      Vector xs(n);
      for (Index i = 0; i < n; ++i) xs(i) = x[i];
      Matrix H(n, n);
      for (Index j = 0; j < n; ++j) {
        const double h = CentralDifferenceStep(xs(j), 1.0);
        Vector xp = xs, xm = xs;
        xp(j) += h;
        xm(j) -= h;
        const Vector gp = ScaledJacobian(Unscale(xp)).transpose() * y;
        const Vector gm = ScaledJacobian(Unscale(xm)).transpose() * y;
        H.col(j) = (gp - gm) / (2.0 * h);
      }
      H = 0.5 * (H + H.transpose()).eval();
      if (!H.allFinite()) return false;
      Index k = 0;
      for (Index i = 0; i < n; ++i) {
        for (Index j = 0; j <= i; ++j, ++k) values[k] = H(i, j);
      }
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    solution_.resize(n);
    for (Index i = 0; i < n; ++i) solution_(i) = x[i];
  }

  // (u, λ) from the scaled x̂.
  Vector Unscale(const Vector& xs) const {
    Vector U(n_ + 1);
    U.head(n_) = xs.head(n_).cwiseProduct(s_);
    U(n_) = xs(n_) * s_lambda_;
    return U;
  }
  Vector Unscaled(const Number* x, Index n) const {
    Vector xs(n);
    for (Index i = 0; i < n; ++i) xs(i) = x[i];
    return Unscale(xs);
  }

  // [F̂_û F̂_λ̂] at U = (u, λ) (unscaled).
  Matrix ScaledJacobian(const Vector& U) {
    Matrix J;
    Vector dF;
    problem_.Jacobian(U.head(n_), U(n_), J);
    problem_.DfDlambda(U.head(n_), U(n_), dF);
    Matrix out(n_, n_ + 1);
    out.leftCols(n_) = r_inv_.asDiagonal() * J * s_.asDiagonal();
    out.col(n_) = r_inv_.cwiseProduct(dF) * s_lambda_;
    return out;
  }

  const Vector& solution() const { return solution_; }
  Vector s() const { return s_; }
  double s_lambda() const { return s_lambda_; }
  const Vector& r_inv() const { return r_inv_; }

 private:
  Problem& problem_;
  Eigen::Index n_;
  Vector s_;
  double s_lambda_;
  Vector r_inv_;
  FoldOptimizationOptions options_;
  Vector x0_;
  Vector solution_;
};

}  // namespace

void Validate(const FoldOptimizationOptions& o) {
  auto fail = [](const char* field, double value, const char* rule) {
    throw std::invalid_argument(
        fmt::format("FoldOptimizationOptions.{} = {}: {}", field, value, rule));
  };
  if (o.sense != 1 && o.sense != -1) fail("sense", o.sense, "must be +1 or -1");
  if (o.max_iterations < 1) fail("max_iterations", o.max_iterations, "must be at least 1");
  if (!(o.tolerance > 0.0)) fail("tolerance", o.tolerance, "must be positive");
  if (!(o.constraint_tolerance > 0.0)) {
    fail("constraint_tolerance", o.constraint_tolerance, "must be positive");
  }
  if (std::isnan(o.lambda_min)) fail("lambda_min", o.lambda_min, "must not be NaN");
  if (std::isnan(o.lambda_max)) fail("lambda_max", o.lambda_max, "must not be NaN");
  if (!(o.lambda_min < o.lambda_max)) fail("lambda_max", o.lambda_max, "must exceed lambda_min");
  if (!(o.singular_tolerance > 0.0 && o.singular_tolerance < 1.0)) {
    fail("singular_tolerance", o.singular_tolerance, "must be in (0, 1)");
  }
}

const char* ToString(FoldOptimizationStatus status) {
  switch (status) {
    case FoldOptimizationStatus::kSolved: return "solved";
    case FoldOptimizationStatus::kAtBound: return "at a bound of lambda (no fold in range)";
    case FoldOptimizationStatus::kNotSingular: return "converged, but not a fold";
    case FoldOptimizationStatus::kInfeasible: return "locally infeasible";
    case FoldOptimizationStatus::kMaxIterations: return "maximum iterations";
    case FoldOptimizationStatus::kFailed: return "failed";
  }
  return "?";
}

FoldOptimizationResult LocateFoldByOptimization(Problem& problem, const Vector& u0, double lambda0,
                                                const FoldOptimizationOptions& options) {
  Validate(options);
  if (u0.size() != problem.Dimension()) {
    throw std::invalid_argument(fmt::format(
        "LocateFoldByOptimization: u0 has {} entries; the problem's Dimension() = {}", u0.size(),
        problem.Dimension()));
  }
  FoldNlp* nlp_raw = new FoldNlp(problem, u0, lambda0, options);
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = nlp_raw;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
  app->Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
  app->Options()->SetNumericValue("acceptable_constr_viol_tol", options.constraint_tolerance);
  app->Options()->SetStringValue("nlp_scaling_method", "none");  // the problem's own scales
  if (options.hessian == FoldHessian::kLimitedMemory) {
    app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  }
  FoldOptimizationResult result;
  if (app->Initialize("") != Ipopt::Solve_Succeeded) {  // "": never read ./ipopt.opt
    result.message = "Ipopt could not be initialized";
    return result;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  result.ipopt_status = static_cast<int>(status);
  if (Ipopt::IsValid(app->Statistics())) result.iterations = app->Statistics()->IterationCount();
  const Eigen::Index n = problem.Dimension();
  const Vector U = nlp_raw->Unscale(nlp_raw->solution());
  result.u = U.head(n);
  result.lambda = U(n);

  // Independent checks at the returned point: the residual and the singularity of F̂_û. A failed
  // run may return a point where the problem cannot be evaluated (e.g. a parameter outside its
  // physical range): that is a failure, not an exception.
  try {
    Vector F;
    problem.Residual(result.u, result.lambda, F);
    result.residual_norm = F.cwiseProduct(nlp_raw->r_inv()).lpNorm<Eigen::Infinity>();
    const Matrix J_full = nlp_raw->ScaledJacobian(U);  // [F̂_û F̂_λ̂]
    const Vector sigma = Eigen::JacobiSVD<Matrix>(J_full.leftCols(n)).singularValues();
    const double full_norm = Eigen::JacobiSVD<Matrix>(J_full).singularValues()(0);
    result.singular_ratio = full_norm > 0.0 ? sigma(sigma.size() - 1) / full_norm : 0.0;
  } catch (const std::exception& e) {
    result.status = FoldOptimizationStatus::kFailed;
    result.residual_norm = kInfinity;
    result.message = fmt::format("Ipopt ended (status {}) at λ = {:.10g}, where the problem cannot "
                                 "be evaluated: {}", result.ipopt_status, result.lambda, e.what());
    return result;
  }

  const bool converged = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
  const double bound_tolerance = 1e-9 * std::max(1.0, std::abs(result.lambda));
  const bool at_bound = (std::isfinite(options.lambda_min) &&
                         result.lambda <= options.lambda_min + bound_tolerance) ||
                        (std::isfinite(options.lambda_max) &&
                         result.lambda >= options.lambda_max - bound_tolerance);
  if (converged && at_bound) {
    result.status = FoldOptimizationStatus::kAtBound;
    result.message = fmt::format(
        "the {} of λ on the solution manifold is the bound λ = {:.10g}: no fold in [{:.6g}, {:.6g}]",
        options.sense > 0 ? "largest value" : "smallest value", result.lambda, options.lambda_min,
        options.lambda_max);
  } else if (converged && result.singular_ratio <= options.singular_tolerance) {
    result.status = FoldOptimizationStatus::kSolved;
    result.message = fmt::format(
        "fold at λ = {:.12g} after {} Ipopt iterations: ‖F̂‖∞ = {:.2e}, σ_min(F̂_û)/‖[F̂_û F̂_λ̂]‖ = {:.2e}",
        result.lambda, result.iterations, result.residual_norm, result.singular_ratio);
  } else if (converged) {
    result.status = FoldOptimizationStatus::kNotSingular;
    result.message = fmt::format(
        "Ipopt converged at λ = {:.10g} but F_u is regular there (σ_min(F̂_û)/‖[F̂_û F̂_λ̂]‖ = {:.2e} > {:.1e}): "
        "not a fold", result.lambda, result.singular_ratio, options.singular_tolerance);
  } else if (status == Ipopt::Infeasible_Problem_Detected) {
    result.status = FoldOptimizationStatus::kInfeasible;
    result.message = fmt::format("Ipopt: locally infeasible near λ = {:.10g} (‖F̂‖∞ = {:.2e})",
                                 result.lambda, result.residual_norm);
  } else if (status == Ipopt::Maximum_Iterations_Exceeded) {
    result.status = FoldOptimizationStatus::kMaxIterations;
    result.message = fmt::format("Ipopt: {} iterations without convergence (λ = {:.10g})",
                                 result.iterations, result.lambda);
  } else {
    result.status = FoldOptimizationStatus::kFailed;
    result.message = fmt::format("Ipopt failed with status {} at λ = {:.10g}",
                                 result.ipopt_status, result.lambda);
  }
  return result;
}

}  // namespace rubcont
