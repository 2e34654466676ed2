// Small dense linear-algebra helpers that know no model: determinant sign and magnitude from an
// LU factorization (for sign-change test functions), and null vectors from a singular value
// decomposition (for located singular points, where an LU is useless by construction).
#pragma once

#include <vector>

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

// LU factorization with partial pivoting, P A = L U, for the small dense systems of continuation
// (a bordered Jacobian of 2 to a few hundred unknowns), into storage that is reused between calls.
// Up to kUnblockedLimit unknowns it runs an unblocked right-looking elimination; above that it uses
// Eigen's blocked PartialPivLU. Eigen switches to its blocked algorithm above 16 unknowns, which
// for 17–40 costs up to 1.7× more than unblocked elimination (measured here: LU + solve 1.07 µs at
// n = 16, 1.83 µs at n = 17), and rotating-wave and small shooting problems live in that range.
class DenseLu {
 public:
  static constexpr Index kUnblockedLimit = 48;

  // Factors A (square). A zero pivot is not an error: the factors are kept and PivotRatio() is 0.
  void Compute(const Matrix& A);
  Index size() const { return n_; }
  // x = A⁻¹ b (x may alias b's storage only if it is the same object).
  void Solve(const Vector& b, Vector& x) const;
  // min |U_ii| / max |U_ii|: 0 for an exactly singular matrix, tiny for a numerically singular one.
  // Partial pivoting keeps |L_ij| ≤ 1, so the pivots carry the scale of the matrix.
  double PivotRatio() const;
  LogDeterminant Determinant() const;

 private:
  Index n_ = 0;
  bool unblocked_ = true;
  Matrix lu_;                          // unblocked: L (unit, below) and U
  std::vector<Index> pivots_;          // unblocked: row k was swapped with row pivots_[k]
  Eigen::PartialPivLU<Matrix> eigen_;  // blocked
};

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

// Eigenvalues of a real square matrix after balancing it by a diagonal similarity D⁻¹ A D with
// powers of two (Parlett & Reinsch 1969, LAPACK's dgebal without permutation: exact, it changes
// no eigenvalue). Eigen's EigenSolver does not balance. A model's state matrix mixes stiff contact
// terms (k/m ~ 1e10 s⁻²) with O(1) kinematic entries; unbalanced, the eigenvalue error is
// ε·‖A‖ ~ 1e-5 s⁻¹, and a close pair splits by √(ε‖A‖·|λ|) ~ 1 s⁻¹ (measured on the rub whip:
// a pair at Re ≈ −2.3 s⁻¹ scattered over ±2.5 s⁻¹, crossing the axis at random). Returns false if
// the QR iteration did not converge.
bool BalancedEigenvalues(const Matrix& A, ComplexVector& values);

// kron(A, I₂): the real 2n × 2n form of a real n × n matrix acting on n complex coordinates
// stored as (x, y) pairs.
Matrix KronIdentity2(const Matrix& A);

}  // namespace rubcont
