#include "solvers/linear_algebra.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "solvers/constants.h"

namespace rubcont {

namespace {

// det = permutation_sign · Π U_ii, in logarithms, from the U factor's diagonal.
template <class Derived>
LogDeterminant FromPivots(const Eigen::MatrixBase<Derived>& lu, int permutation_sign) {
  LogDeterminant result;
  int sign = permutation_sign;
  double log_abs = 0.0;
  for (Index i = 0; i < lu.rows(); ++i) {
    const double pivot = lu(i, i);
    if (pivot == 0.0 || !std::isfinite(pivot)) {
      result.sign = 0;
      result.log_abs = -kInfinity;
      return result;
    }
    if (pivot < 0.0) sign = -sign;
    log_abs += std::log(std::abs(pivot));
  }
  result.sign = sign;
  result.log_abs = log_abs;
  return result;
}

}  // namespace

LogDeterminant LogDeterminantOf(const Eigen::PartialPivLU<Matrix>& lu) {
  return FromPivots(lu.matrixLU(), static_cast<int>(lu.permutationP().determinant()));
}

void DenseLu::Compute(const Matrix& A) {
  if (A.rows() != A.cols()) {
    throw std::invalid_argument("DenseLu::Compute: A is " + std::to_string(A.rows()) + " × " +
                                std::to_string(A.cols()) + "; must be square");
  }
  n_ = A.rows();
  unblocked_ = n_ <= kUnblockedLimit;
  if (!unblocked_) {
    eigen_.compute(A);
    return;
  }
  lu_ = A;  // no allocation when the size is unchanged
  pivots_.resize(static_cast<size_t>(n_));
  for (Index k = 0; k < n_; ++k) {
    Index pivot = k;
    lu_.col(k).tail(n_ - k).cwiseAbs().maxCoeff(&pivot);
    pivot += k;
    pivots_[static_cast<size_t>(k)] = pivot;
    if (pivot != k) lu_.row(k).swap(lu_.row(pivot));
    const double diagonal = lu_(k, k);
    const Index rest = n_ - k - 1;
    if (diagonal == 0.0 || rest == 0) continue;  // a zero column: nothing to eliminate
    lu_.col(k).tail(rest) /= diagonal;
    lu_.bottomRightCorner(rest, rest).noalias() -=
        lu_.col(k).tail(rest) * lu_.row(k).tail(rest);
  }
}

void DenseLu::Solve(const Vector& b, Vector& x) const {
  if (!unblocked_) {
    x = eigen_.solve(b);
    return;
  }
  x = b;
  for (Index k = 0; k < n_; ++k) {
    const Index pivot = pivots_[static_cast<size_t>(k)];
    if (pivot != k) std::swap(x(k), x(pivot));
  }
  lu_.triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu_.triangularView<Eigen::Upper>().solveInPlace(x);
}

double DenseLu::PivotRatio() const {
  const auto pivots = (unblocked_ ? lu_ : eigen_.matrixLU()).diagonal().cwiseAbs();
  const double largest = pivots.maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return 0.0;
  return pivots.minCoeff() / largest;
}

LogDeterminant DenseLu::Determinant() const {
  if (!unblocked_) return LogDeterminantOf(eigen_);
  int sign = 1;
  for (Index k = 0; k < n_; ++k) {
    if (pivots_[static_cast<size_t>(k)] != k) sign = -sign;
  }
  return FromPivots(lu_.topLeftCorner(n_, n_), sign);
}

NullVectors SmallestSingularVectors(const Matrix& A, Index count) {
  const Index m = A.rows();
  const Index n = A.cols();
  if (m > n || count < 1 || count > n) {
    throw std::invalid_argument("SmallestSingularVectors: A is " + std::to_string(m) + " × " +
                                std::to_string(n) + " and count = " + std::to_string(count) +
                                "; need rows ≤ cols and 1 ≤ count ≤ cols");
  }
  // Eigen's SVD of a wide matrix returns n right singular vectors when asked for the full V; the
  // singular values come sorted in decreasing order, so the smallest are at the end.
  Eigen::BDCSVD<Matrix> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  NullVectors result;
  result.right = svd.matrixV().rightCols(count);
  // Reverse so that column 0 belongs to the smallest singular value (or an exact null direction).
  result.right = result.right.rowwise().reverse().eval();
  const Index left_count = std::min(count, m);
  result.left = svd.matrixU().rightCols(left_count).rowwise().reverse();
  result.singular_values = svd.singularValues().tail(left_count).reverse();
  return result;
}

bool BalancedEigenvalues(const Matrix& A, ComplexVector& values) {
  if (A.rows() != A.cols()) {
    throw std::invalid_argument("BalancedEigenvalues: the matrix is " + std::to_string(A.rows()) +
                                "×" + std::to_string(A.cols()) + ", not square");
  }
  Matrix B = A;
  const Index n = B.rows();
  // Scale row and column i by a power of two until their off-diagonal 1-norms are within a factor
  // of two (dgebal's loop: stop when no scaling reduces the norm sum by 5 %).
  bool converged = false;
  while (!converged) {
    converged = true;
    for (Index i = 0; i < n; ++i) {
      const double c = B.col(i).cwiseAbs().sum() - std::abs(B(i, i));
      const double r = B.row(i).cwiseAbs().sum() - std::abs(B(i, i));
      if (c == 0.0 || r == 0.0) continue;
      double f = 1.0;
      double cs = c;
      const double s = c + r;
      while (cs < r / 2.0) {
        cs *= 4.0;
        f *= 2.0;
      }
      while (cs >= r * 2.0) {
        cs /= 4.0;
        f /= 2.0;
      }
      if ((cs + r) / f < 0.95 * s) {  // c·f + r/f: the norms after column i ×f, row i ÷f
        converged = false;
        B.row(i) /= f;
        B.col(i) *= f;
      }
    }
  }
  Eigen::EigenSolver<Matrix> solver(B, false);
  if (solver.info() != Eigen::Success) return false;
  values = solver.eigenvalues();
  return true;
}

Matrix KronIdentity2(const Matrix& A) {
  Matrix out = Matrix::Zero(2 * A.rows(), 2 * A.cols());
  for (Index i = 0; i < A.rows(); ++i) {
    for (Index j = 0; j < A.cols(); ++j) {
      out(2 * i, 2 * j) = A(i, j);
      out(2 * i + 1, 2 * j + 1) = A(i, j);
    }
  }
  return out;
}

}  // namespace rubcont
