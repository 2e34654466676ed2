#include "solvers/finite_difference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "solvers/constants.h"

namespace rubcont {

namespace {

double StepFor(double x, double typical, double relative_step) {
  return relative_step * std::max(std::abs(x), typical);
}

}  // namespace

void FiniteDifferenceJacobian(const VectorFunction& f, const Vector& x, Index m, Matrix& J,
                              const FiniteDifferenceOptions& options, const Vector* typical) {
  const Index n = x.size();
  if (typical != nullptr && typical->size() != n) {
    throw std::invalid_argument("FiniteDifferenceJacobian: typical has size " +
                                std::to_string(typical->size()) + ", must equal x.size() = " +
                                std::to_string(n));
  }
  J.resize(m, n);
  Vector xp = x;
  Vector f_plus(m), f_minus(m);
  if (!options.central) f(x, f_minus);
  for (Index j = 0; j < n; ++j) {
    const double scale = typical != nullptr ? (*typical)(j) : 1.0;
    const double h = StepFor(x(j), scale, options.relative_step);
    xp(j) = x(j) + h;
    f(xp, f_plus);
    if (options.central) {
      xp(j) = x(j) - h;
      f(xp, f_minus);
      J.col(j) = (f_plus - f_minus) / (2.0 * h);
    } else {
      J.col(j) = (f_plus - f_minus) / h;
    }
    xp(j) = x(j);
  }
}

void FiniteDifferenceDirectional(const VectorFunction& f, const Vector& x, const Vector& v, Index m,
                                 Vector& dfdv, const FiniteDifferenceOptions& options) {
  const double v_norm = v.norm();
  dfdv.resize(m);
  if (v_norm == 0.0) {
    dfdv.setZero();
    return;
  }
  const double h = options.relative_step * std::max(1.0, x.norm() / v_norm);
  Vector f_plus(m), f_minus(m);
  f(x + h * v, f_plus);
  if (options.central) {
    f(x - h * v, f_minus);
    dfdv = (f_plus - f_minus) / (2.0 * h);
  } else {
    f(x, f_minus);
    dfdv = (f_plus - f_minus) / h;
  }
}

JacobianCheck CheckJacobian(const VectorFunction& f, const Vector& x, const Matrix& analytic,
                            double tolerance, const Vector* typical, double absolute_floor) {
  Matrix numeric;
  FiniteDifferenceJacobian(f, x, analytic.rows(), numeric, {}, typical);
  if (numeric.cols() != analytic.cols()) {
    throw std::invalid_argument("CheckJacobian: analytic Jacobian has " +
                                std::to_string(analytic.cols()) + " columns, x has " +
                                std::to_string(numeric.cols()) + " entries");
  }
  JacobianCheck check;
  for (Index i = 0; i < numeric.rows(); ++i) {
    const double row_scale = numeric.row(i).cwiseAbs().maxCoeff();
    for (Index j = 0; j < numeric.cols(); ++j) {
      const double denominator =
          std::max({std::abs(numeric(i, j)), absolute_floor * row_scale, 1e-300});
      const double error = std::abs(analytic(i, j) - numeric(i, j)) / denominator;
      if (!(error <= check.max_error)) {  // also catches NaN
        check.max_error = std::isnan(error) ? kInfinity : error;
        check.worst_row = i;
        check.worst_col = j;
        check.analytic_value = analytic(i, j);
        check.difference_value = numeric(i, j);
      }
    }
  }
  check.ok = check.max_error <= tolerance;
  return check;
}

}  // namespace rubcont
