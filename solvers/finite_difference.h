// Finite-difference Jacobians and the CheckJacobian test utility. This is the one place in rubcont
// where the difference step is chosen (kCentralDifferenceStep, CentralDifferenceStep); every
// analytic Jacobian is tested against these differences.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>

#include "solvers/types.h"

namespace rubcont {

// The relative step of every central difference in rubcont: of order ∛ε, where the truncation
// error O(h²) balances the round-off O(ε/h). Use √ε ≈ 1.5e-8 for forward differences.
inline constexpr double kCentralDifferenceStep = 6.0e-6;

// The central-difference step at x whose magnitude is at least `scale` (> 0): h = kCentral-
// DifferenceStep · max(|x|, scale). `scale` keeps the step meaningful where x ≈ 0 and when the
// unknowns have very different units (metres ~1e-4 beside forces ~1e3).
inline double CentralDifferenceStep(double x, double scale) {
  return kCentralDifferenceStep * std::max(std::abs(x), scale);
}

// f: R^n -> R^m, writing f(x) into its second argument (already sized m by the caller).
using VectorFunction = std::function<void(const Vector& x, Vector& f)>;

struct FiniteDifferenceOptions {
  // Relative step: h_i = relative_step · max(|x_i|, typical_i).
  double relative_step = kCentralDifferenceStep;
  bool central = true;  // central (2n evaluations, O(h²)) or forward (n evaluations, O(h))
};

// Fills J (m × n) with ∂f/∂x at x. `typical` (size n, optional, all > 0) is the magnitude each
// unknown is expected to have; it sets the step where x_i ≈ 0 and keeps steps meaningful when the
// unknowns have very different units (metres ~1e-4 beside forces ~1e3).
void FiniteDifferenceJacobian(const VectorFunction& f, const Vector& x, Index m, Matrix& J,
                              const FiniteDifferenceOptions& options = {},
                              const Vector* typical = nullptr);

// Derivative of f along direction v: (f(x + h v) − f(x − h v)) / 2h, with h relative to |x|·|v|.
void FiniteDifferenceDirectional(const VectorFunction& f, const Vector& x, const Vector& v, Index m,
                                 Vector& dfdv, const FiniteDifferenceOptions& options = {});

// Result of comparing an analytic Jacobian with central differences.
struct JacobianCheck {
  double max_error = 0.0;  // max over entries of |J_a − J_fd| / (|J_fd| + column_scale · atol)
  Index worst_row = -1;
  Index worst_col = -1;
  double analytic_value = 0.0;    // J_a at the worst entry
  double difference_value = 0.0;  // J_fd at the worst entry
  bool ok = false;                // max_error <= tolerance
};

// Compares `analytic` (m × n) with central differences of f at x. An entry's error is relative to
// the larger of |J_fd(i,j)| and `absolute_floor` times the largest |J_fd| in row i, so that entries
// that are zero up to round-off do not dominate.
JacobianCheck CheckJacobian(const VectorFunction& f, const Vector& x, const Matrix& analytic,
                            double tolerance, const Vector* typical = nullptr,
                            double absolute_floor = 1e-9);

}  // namespace rubcont
