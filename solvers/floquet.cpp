#include "solvers/floquet.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/core.h>

namespace rubcont {

const char* ToString(FloquetMethod method) {
  switch (method) {
    case FloquetMethod::kPencil: return "block-cyclic pencil (QZ)";
    case FloquetMethod::kProduct: return "explicit product";
  }
  return "unknown";
}

namespace {

void CheckFactors(const std::vector<Matrix>& factors) {
  if (factors.empty()) throw std::invalid_argument("Floquet: no factors given");
  const Index n = factors[0].rows();
  for (std::size_t i = 0; i < factors.size(); ++i) {
    if (factors[i].rows() != n || factors[i].cols() != n) {
      throw std::invalid_argument(
          fmt::format("Floquet: factors[{}] is {}×{}; all factors must be {}×{}", i,
                      factors[i].rows(), factors[i].cols(), n, n));
    }
  }
}

// Decreasing modulus; ties (complex pairs) by decreasing imaginary part, for reproducible order.
ComplexVector SortedByModulus(const ComplexVector& values) {
  std::vector<Index> order(values.size());
  std::iota(order.begin(), order.end(), Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
    const double ma = std::abs(values(a)), mb = std::abs(values(b));
    if (ma != mb) return ma > mb;
    return values(a).imag() > values(b).imag();
  });
  ComplexVector sorted(values.size());
  for (Index i = 0; i < values.size(); ++i) sorted(i) = values(order[i]);
  return sorted;
}

ComplexVector NotANumber(Index n) {
  return ComplexVector::Constant(n, std::complex<double>(NAN, NAN));
}

ComplexVector StandardEigenvalues(const Matrix& M) {
  if (M.rows() == 0) return ComplexVector();
  Eigen::EigenSolver<Matrix> solver(M, false);
  if (solver.info() != Eigen::Success) return NotANumber(M.rows());
  return solver.eigenvalues();
}

// Finite eigenvalues of the block-cyclic pencil. Each factor is first divided by a power of two
// close to its norm, c_i (exact in floating point), so that every block of A is O(1) and every
// finite eigenvalue μ' = μ / Π c_i has |μ'| ≤ Π ‖M_i‖ / Π c_i ≈ 1. Then the finite eigenvalues have
// |β| ≳ |α| while the infinite ones have |β| ~ ε|α|: the n with the largest |β| / |(α, β)| are
// the finite ones, however large or small the multipliers are.
ComplexVector PencilEigenvalues(const std::vector<Matrix>& factors) {
  const Index N = static_cast<Index>(factors.size());
  const Index n = factors[0].rows();
  if (n == 0) return ComplexVector();
  const Index size = N * n;
  Matrix A = Matrix::Zero(size, size);
  Matrix B = Matrix::Zero(size, size);
  int total_exponent = 0;
  for (Index i = 0; i < N; ++i) {
    const double norm = factors[i].norm();
    int exponent = 0;
    if (norm > 0.0) std::frexp(norm, &exponent);
    total_exponent += exponent;
    A.block(i * n, i * n, n, n) = factors[i] * std::ldexp(1.0, -exponent);
    if (i + 1 < N) A.block(i * n, (i + 1) * n, n, n) = -Matrix::Identity(n, n);
  }
  B.block((N - 1) * n, 0, n, n) = Matrix::Identity(n, n);
  Eigen::GeneralizedEigenSolver<Matrix> solver(A, B, false);
  if (solver.info() != Eigen::Success) return NotANumber(n);
  const ComplexVector& alphas = solver.alphas();
  const Vector& betas = solver.betas();
  std::vector<Index> order(size);
  std::iota(order.begin(), order.end(), Index{0});
  auto finiteness = [&](Index k) {
    const double a = std::abs(alphas(k)), b = std::abs(betas(k));
    const double h = std::hypot(a, b);
    return h > 0.0 ? b / h : 0.0;
  };
  std::partial_sort(order.begin(), order.begin() + n, order.end(),
                    [&](Index a, Index b) { return finiteness(a) > finiteness(b); });
  ComplexVector values(n);
  for (Index k = 0; k < n; ++k) {
    const Index j = order[k];
    // μ = (α/β)·2^(Σ exponents); scale in two factors so that neither over- nor underflows early.
    const std::complex<double> ratio = alphas(j) / betas(j);
    const int half = total_exponent / 2;
    values(k) = ratio * std::ldexp(1.0, half) * std::ldexp(1.0, total_exponent - half);
  }
  return values;
}

}  // namespace

ComplexVector ProductEigenvalues(const std::vector<Matrix>& factors, FloquetMethod method) {
  CheckFactors(factors);
  for (const Matrix& M : factors) {
    if (!M.allFinite()) return NotANumber(factors[0].rows());
  }
  if (factors.size() == 1) return SortedByModulus(StandardEigenvalues(factors[0]));
  if (method == FloquetMethod::kProduct) {
    Matrix product = factors[0];
    for (std::size_t i = 1; i < factors.size(); ++i) product = factors[i] * product;
    return SortedByModulus(StandardEigenvalues(product));
  }
  return SortedByModulus(PencilEigenvalues(factors));
}

FloquetResult FloquetMultipliers(const std::vector<Matrix>& factors,
                                 const std::vector<Matrix>& trivial_bases, FloquetMethod method) {
  CheckFactors(factors);
  const std::size_t N = factors.size();
  const Index n = factors[0].rows();
  FloquetResult result;
  for (const Matrix& M : factors) {
    if (!M.allFinite()) {
      result.multipliers = NotANumber(n);
      return result;
    }
  }
  if (trivial_bases.empty()) {
    result.multipliers = ProductEigenvalues(factors, method);
    result.valid = result.multipliers.allFinite();
    return result;
  }
  if (trivial_bases.size() != N) {
    throw std::invalid_argument(fmt::format(
        "FloquetMultipliers: {} trivial bases for {} factors: give none or one per factor",
        trivial_bases.size(), N));
  }
  const Index k = trivial_bases[0].cols();
  for (std::size_t i = 0; i < N; ++i) {
    if (trivial_bases[i].rows() != n || trivial_bases[i].cols() != k || k < 1 || k >= n) {
      throw std::invalid_argument(fmt::format(
          "FloquetMultipliers: trivial_bases[{}] is {}×{}; all must be {}×k with 1 ≤ k < {} "
          "(k = {} from trivial_bases[0])",
          i, trivial_bases[i].rows(), trivial_bases[i].cols(), n, n, k));
    }
  }
  // Q_i = [U_i W_i], orthonormal, from a Householder QR of the trivial basis.
  std::vector<Matrix> Q(N);
  for (std::size_t i = 0; i < N; ++i) {
    Eigen::HouseholderQR<Matrix> qr(trivial_bases[i]);
    const auto R = qr.matrixQR().topLeftCorner(k, k).template triangularView<Eigen::Upper>();
    const double largest = trivial_bases[i].cwiseAbs().maxCoeff();
    for (Index j = 0; j < k; ++j) {
      // A direction that vanishes (f = 0 at an equilibrium, g ∥ f at a relative equilibrium)
      // cannot be deflated: the orbit is degenerate and its multipliers are not defined here.
      if (!(std::abs(R(j, j)) > 1e-12 * largest)) {
        result.multipliers = NotANumber(n - k);
        return result;
      }
    }
    Q[i] = qr.householderQ() * Matrix::Identity(n, n);
  }
  std::vector<Matrix> trivial_factors(N), reduced_factors(N);
  for (std::size_t i = 0; i < N; ++i) {
    const Matrix block = Q[(i + 1) % N].transpose() * factors[i] * Q[i];
    trivial_factors[i] = block.topLeftCorner(k, k);
    reduced_factors[i] = block.bottomRightCorner(n - k, n - k);
    const double norm = factors[i].norm();
    if (norm > 0.0) {
      result.invariance_defect =
          std::max(result.invariance_defect, block.bottomLeftCorner(n - k, k).norm() / norm);
    }
  }
  result.trivial = ProductEigenvalues(trivial_factors, method);
  result.multipliers = ProductEigenvalues(reduced_factors, method);
  result.valid = result.multipliers.allFinite() && result.trivial.allFinite();
  return result;
}

}  // namespace rubcont
