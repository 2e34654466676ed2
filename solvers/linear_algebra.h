// Small dense linear-algebra helpers that know no model: determinant sign and magnitude from an
// LU factorization (for sign-change test functions), and null vectors from a singular value
// decomposition (for located singular points, where an LU is useless by construction).
#pragma once

#include <Eigen/LU>

#include "solvers/types.h"

namespace rubcont {

// det(A) = sign · exp(log_abs) for the matrix factored by `lu` (PartialPivLU stores P A = L U with
// unit L, so det A = det(P) · Π U_ii). Computed in logarithms: a product of a few hundred pivots
// over- or underflows long before the sign becomes meaningless. sign is 0 when a pivot is exactly 0
// (log_abs is then −∞).
struct LogDeterminant {
  int sign = 0;
  double log_abs = 0.0;
};
LogDeterminant LogDeterminantOf(const Eigen::PartialPivLU<Matrix>& lu);

// Approximate null vectors of a square or wide matrix A (m × n, m ≤ n) from its singular value
// decomposition A = U Σ Vᵀ. V has n columns: m belong to the singular values σ_1 ≥ … ≥ σ_m, the
// other n − m span directions that A annihilates exactly because it is wide. `right` holds the
// `count` last columns of V, smallest first (so for n = m + 1, right.col(0) is the exact kernel
// direction and right.col(1) belongs to σ_m); `left` holds the min(count, m) last columns of U,
// smallest first, with their singular values in `singular_values`. Cost O(n³): use it at located
// points, never inside a stepping loop.
struct NullVectors {
  Matrix right;
  Matrix left;
  Vector singular_values;  // smallest first; size min(count, m)
};
NullVectors SmallestSingularVectors(const Matrix& A, Index count);

}  // namespace rubcont
