#include "solvers/floquet.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"

namespace rubcont {

const char* ToString(FloquetMethod method) {
  switch (method) {
    case FloquetMethod::kPeriodicSchur: return "periodic Schur (orthogonal iteration)";
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
  return ComplexVector::Constant(n, std::complex<double>(kNaN, kNaN));
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

// 2^e applied to a modulus, with e clamped to what ldexp can take (it over- and underflows
// gracefully to inf and 0).
double ScaleByPowerOfTwo(double modulus, long exponent) {
  return std::ldexp(modulus, static_cast<int>(std::clamp(exponent, -100000L, 100000L)));
}

// Eigenvalues of 2^extra_exponent · B_{N−1} ⋯ B_0 for small square blocks whose eigenvalues have
// similar moduli (a complex pair, or values the orthogonal iteration did not separate). The running
// product is renormalized by powers of two so that it neither over- nor underflows.
ComplexVector SmallProductEigenvalues(const std::vector<Matrix>& blocks, long extra_exponent) {
  const Index b = blocks[0].rows();
  Matrix product = Matrix::Identity(b, b);
  long exponent = extra_exponent;
  for (const Matrix& block : blocks) {
    product = block * product;
    const double norm = product.norm();
    if (norm == 0.0) return ComplexVector::Zero(b);
    int e = 0;
    std::frexp(norm, &e);
    product *= std::ldexp(1.0, -e);
    exponent += e;
  }
  ComplexVector values = StandardEigenvalues(product);
  for (Index k = 0; k < values.size(); ++k) {
    const double modulus = std::abs(values(k));
    values(k) = modulus > 0.0
                    ? std::polar(ScaleByPowerOfTwo(modulus, exponent), std::arg(values(k)))
                    : std::complex<double>(0.0);
  }
  return values;
}

// Periodic orthogonal iteration (unshifted periodic QR): Q_{i+1} R_i = M_i Q_i around the cycle,
// then Q_0 ← Q_N. The coupling between the leading j and the trailing n − j columns, ‖Z(j+1:, :j)‖
// with Z = Q_0ᵀ Q_N, decays like |μ_{j+1}/μ_j| per sweep. The iteration stops when every coupling
// is below kSplit (the columns split there) or decays by less than kSlowDecay over a window of
// sweeps (moduli within a factor ≈ 2.4, or a complex pair: kept together as one block, whose
// eigenvalues the small block product gives accurately because their moduli are close).
ComplexVector PeriodicSchurEigenvalues(const std::vector<Matrix>& factors) {
  constexpr int kMaxSweeps = 200;
  constexpr int kWindow = 8;
  constexpr double kSplit = 1e-13;      // coupling small enough to treat as zero
  constexpr double kSlowDecay = 1e-3;   // decay over a window slower than this: keep as a block
  const Index N = static_cast<Index>(factors.size());
  const Index n = factors[0].rows();
  if (n == 0) return ComplexVector();
  // Factors normalized by powers of two (exact), their exponents summed.
  std::vector<Matrix> M(N);
  long total_exponent = 0;
  for (Index i = 0; i < N; ++i) {
    const double norm = factors[i].norm();
    int e = 0;
    if (norm > 0.0) std::frexp(norm, &e);
    M[i] = factors[i] * std::ldexp(1.0, -e);
    total_exponent += e;
  }
  std::vector<Matrix> R(N);
  Matrix Q0 = Matrix::Identity(n, n), Q(n, n), Z = Matrix::Identity(n, n);
  std::vector<double> coupling(std::max<Index>(n - 1, 0), 0.0), history(coupling.size(), 1.0);
  for (int sweep = 1; sweep <= kMaxSweeps; ++sweep) {
    Q = Q0;
    for (Index i = 0; i < N; ++i) {
      Eigen::HouseholderQR<Matrix> qr(M[i] * Q);
      Q = qr.householderQ() * Matrix::Identity(n, n);
      R[i] = qr.matrixQR().triangularView<Eigen::Upper>();
      // Positive diagonal: Q is then a continuous function of the iteration (no sign flips), so
      // that Z converges to ±1 on the diagonal (2×2 rotations for complex pairs).
      for (Index j = 0; j < n; ++j) {
        if (R[i](j, j) < 0.0) {
          R[i].row(j) *= -1.0;
          Q.col(j) *= -1.0;
        }
      }
    }
    Z = Q0.transpose() * Q;
    Q0 = Q;
    for (Index j = 0; j + 1 < n; ++j) {
      coupling[j] = Z.bottomLeftCorner(n - j - 1, j + 1).norm();
    }
    if (std::all_of(coupling.begin(), coupling.end(), [&](double c) { return c < kSplit; })) {
      break;
    }
    if (sweep % kWindow == 0) {
      bool settled = true;
      for (std::size_t j = 0; j < coupling.size(); ++j) {
        if (coupling[j] >= kSplit && coupling[j] < kSlowDecay * history[j]) settled = false;
      }
      if (settled) break;
      history = coupling;
    }
  }
  // The cycle in the bases of the last sweep: T_i = R_i (i < N−1) and T_{N−1} = Z R_{N−1}, block
  // upper triangular up to the couplings.
  R[N - 1] = Z * R[N - 1];
  ComplexVector values(n);
  Index start = 0;
  for (Index j = 0; j < n; ++j) {
    if (j + 1 < n && !(coupling[j] < kSplit)) continue;  // the block goes on
    const Index size = j + 1 - start;
    if (size == 1) {
      // μ = Π T_i(j,j) · 2^{Σ exponents}, accumulated in logarithms: no over- or underflow
      // before the final exp.
      double log_modulus = static_cast<double>(total_exponent) * std::log(2.0);
      double sign = 1.0;
      for (Index i = 0; i < N; ++i) {
        const double d = R[i](j, j);
        log_modulus += std::log(std::abs(d));  // −inf for d = 0: μ = 0
        if (d < 0.0) sign = -sign;
      }
      values(j) = sign * std::exp(log_modulus);
    } else {
      std::vector<Matrix> blocks(N);
      for (Index i = 0; i < N; ++i) blocks[i] = R[i].block(start, start, size, size);
      values.segment(start, size) = SmallProductEigenvalues(blocks, total_exponent);
    }
    start = j + 1;
  }
  return values;
}

// FloquetResult::resolution: ε·Π‖M_i‖_F for the methods that form the product (or are measured to
// lose as much), summed in logarithms so that 40 factors of 1e8 do not overflow on the way.
double Resolution(const std::vector<Matrix>& factors, FloquetMethod method) {
  if (method == FloquetMethod::kPeriodicSchur) return 0.0;
  double log_norm = std::log(std::numeric_limits<double>::epsilon());
  for (const Matrix& M : factors) log_norm += std::log(M.norm());
  return log_norm > std::log(std::numeric_limits<double>::max()) ? kInfinity
                                                                   : std::exp(log_norm);
}

}  // namespace

ComplexVector ProductEigenvalues(const std::vector<Matrix>& factors, FloquetMethod method) {
  CheckFactors(factors);
  for (const Matrix& M : factors) {
    if (!M.allFinite()) return NotANumber(factors[0].rows());
  }
  if (factors.size() == 1) return SortedByModulus(StandardEigenvalues(factors[0]));
  if (method == FloquetMethod::kPeriodicSchur) {
    return SortedByModulus(PeriodicSchurEigenvalues(factors));
  }
  if (method == FloquetMethod::kProduct) {
    Matrix product = factors[0];
    for (std::size_t i = 1; i < factors.size(); ++i) product = factors[i] * product;
    return SortedByModulus(StandardEigenvalues(product));
  }
  return SortedByModulus(PencilEigenvalues(factors));
}

int FloquetResult::Unresolved() const {
  int count = 0;
  for (Index i = 0; i < multipliers.size(); ++i) count += std::abs(multipliers(i)) < resolution ? 1 : 0;
  return count;
}

FloquetResult FloquetMultipliers(const std::vector<Matrix>& factors,
                                 const std::vector<Matrix>& trivial_bases, FloquetMethod method) {
  CheckFactors(factors);
  const std::size_t N = factors.size();
  const Index n = factors[0].rows();
  FloquetResult result;
  if (!trivial_bases.empty() && trivial_bases.size() != N) {
    throw std::invalid_argument(fmt::format(
        "FloquetMultipliers: {} trivial bases for {} factors: give none or one per factor",
        trivial_bases.size(), N));
  }
  const Index k = trivial_bases.empty() ? 0 : trivial_bases[0].cols();
  for (std::size_t i = 0; i < trivial_bases.size(); ++i) {
    if (trivial_bases[i].rows() != n || trivial_bases[i].cols() != k || k < 1 || k >= n) {
      throw std::invalid_argument(fmt::format(
          "FloquetMultipliers: trivial_bases[{}] is {}×{}; all must be {}×k with 1 ≤ k < {} "
          "(k = {} from trivial_bases[0])",
          i, trivial_bases[i].rows(), trivial_bases[i].cols(), n, n, k));
    }
  }
  for (std::size_t i = 0; i < N; ++i) {
    if (!factors[i].allFinite() || (k > 0 && !trivial_bases[i].allFinite())) {
      result.multipliers = NotANumber(n - k);
      return result;
    }
  }
  if (k == 0) {
    result.multipliers = ProductEigenvalues(factors, method);
    result.resolution = Resolution(factors, method);
    result.valid = result.multipliers.allFinite();
    return result;
  }
  // Q_i = [U_i W_i], orthonormal, from a Householder QR of the trivial basis. A direction that
  // vanishes (f = 0 at an equilibrium, g ∥ f at a relative equilibrium) cannot be deflated: the
  // orbit is degenerate there and its multipliers are not defined by this construction.
  std::vector<Matrix> Q(N);
  for (std::size_t i = 0; i < N; ++i) {
    Eigen::HouseholderQR<Matrix> qr(trivial_bases[i]);
    const double largest = trivial_bases[i].cwiseAbs().maxCoeff();
    for (Index j = 0; j < k; ++j) {
      if (!(std::abs(qr.matrixQR()(j, j)) > 1e-12 * largest)) {
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
  result.resolution = Resolution(reduced_factors, method);
  result.valid = result.multipliers.allFinite() && result.trivial.allFinite();
  return result;
}

}  // namespace rubcont
