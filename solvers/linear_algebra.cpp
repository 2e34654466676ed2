#include "solvers/linear_algebra.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/SVD>

namespace rubcont {

LogDeterminant LogDeterminantOf(const Eigen::PartialPivLU<Matrix>& lu) {
  LogDeterminant result;
  const Matrix& lu_matrix = lu.matrixLU();
  int sign = static_cast<int>(lu.permutationP().determinant());
  double log_abs = 0.0;
  for (Index i = 0; i < lu_matrix.rows(); ++i) {
    const double pivot = lu_matrix(i, i);
    if (pivot == 0.0 || !std::isfinite(pivot)) {
      result.sign = 0;
      result.log_abs = -INFINITY;
      return result;
    }
    if (pivot < 0.0) sign = -sign;
    log_abs += std::log(std::abs(pivot));
  }
  result.sign = sign;
  result.log_abs = log_abs;
  return result;
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

}  // namespace rubcont
