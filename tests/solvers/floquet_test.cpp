#include "solvers/constants.h"
#include "solvers/floquet.h"

#include <cmath>
#include <complex>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

using Complex = std::complex<double>;

// A deterministic orthogonal matrix (QR of a fixed pseudo-random matrix).
Matrix Orthogonal(Index n, int seed) {
  Matrix A(n, n);
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j < n; ++j) A(i, j) = std::sin(1.3 * (i + 1) * (j + 2) + 0.7 * seed);
  }
  Eigen::HouseholderQR<Matrix> qr(A);
  return qr.householderQ() * Matrix::Identity(n, n);
}

// A cycle M_i = Q_{i+1} U_i Q_iᵀ (Q_N = Q_0) whose cores U_i are block upper triangular with the
// given diagonal blocks and O(1) entries above them: the eigenvalues of M_{N−1} ⋯ M_0 are those of
// the product of the diagonal blocks, known in closed form.
struct GradedCycle {
  std::vector<Matrix> factors;
};

GradedCycle MakeGradedCycle(Index N, double large, double rotation_radius, double angle,
                            double small) {
  const Index n = 4;
  GradedCycle cycle;
  std::vector<Matrix> Q(N + 1);
  for (Index i = 0; i < N; ++i) Q[i] = Orthogonal(n, static_cast<int>(i));
  Q[N] = Q[0];
  for (Index i = 0; i < N; ++i) {
    Matrix U = Matrix::Zero(n, n);
    U(0, 0) = large;
    U.block(1, 1, 2, 2) << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    U.block(1, 1, 2, 2) *= rotation_radius;
    U(3, 3) = small;
    for (Index r = 0; r < n; ++r) {
      for (Index c = r + 1; c < n; ++c) {
        if (!(r == 1 && c == 2)) U(r, c) = 0.5 + 0.3 * std::cos(1.0 * r + 2.0 * c + i);
      }
    }
    cycle.factors.push_back(Q[i + 1] * U * Q[i].transpose());
  }
  return cycle;
}

// The closed-form multipliers of that cycle, sorted by decreasing modulus.
ComplexVector GradedMultipliers(Index N, double large, double rotation_radius, double angle,
                                double small) {
  ComplexVector values(4);
  values(0) = std::pow(large, static_cast<double>(N));
  const double radius = std::pow(rotation_radius, static_cast<double>(N));
  values(1) = std::polar(radius, N * angle);
  values(2) = std::polar(radius, -N * angle);
  values(3) = std::pow(small, static_cast<double>(N));
  if (values(1).imag() < values(2).imag()) std::swap(values(1), values(2));
  return values;
}

double RelativeError(Complex computed, Complex exact) {
  return std::abs(computed - exact) / std::abs(exact);
}

TEST_CASE("periodic Schur: every multiplier of a graded cycle to relative accuracy, where the "
          "product loses all but the largest",
          "[floquet]") {
  // 20 factors: multipliers 10^20, a pair on the unit circle, and 10^-40.
  const Index N = 20;
  const double large = 10.0, radius = 1.0, angle = 0.3, small = 0.01;
  const GradedCycle cycle = MakeGradedCycle(N, large, radius, angle, small);
  const ComplexVector exact = GradedMultipliers(N, large, radius, angle, small);

  const ComplexVector schur = ProductEigenvalues(cycle.factors, FloquetMethod::kPeriodicSchur);
  for (Index k = 0; k < 4; ++k) {
    CAPTURE(k, schur(k), exact(k));
    CHECK(RelativeError(schur(k), exact(k)) < 1e-12);
  }

  const ComplexVector product = ProductEigenvalues(cycle.factors, FloquetMethod::kProduct);
  CHECK(RelativeError(product(0), exact(0)) < 1e-12);  // the dominant one survives ...
  // ... but the unit-circle pair and the small one drown in ε·10^20 ≈ 1e4: the stability verdict
  // (|μ| = 1 exactly here) is lost.
  CHECK(RelativeError(product(1), exact(1)) > 1.0);
  CHECK(RelativeError(product(3), exact(3)) > 0.5);

  // QZ on the block-cyclic pencil is backward stable for the pencil, not for each factor: measured
  // here, it loses the pair and the small multiplier just like the product.
  const ComplexVector pencil = ProductEigenvalues(cycle.factors, FloquetMethod::kPencil);
  CHECK(RelativeError(pencil(0), exact(0)) < 1e-10);
  CHECK(RelativeError(pencil(1), exact(1)) > 0.1);
  CHECK(RelativeError(pencil(3), exact(3)) > 0.5);
}

TEST_CASE("periodic Schur: complex pairs of extreme modulus and exactly singular factors",
          "[floquet]") {
  const Index N = 12;
  // |pair| = 1e3^12 = 1e36, small = 1e-6^12 = 1e-72.
  const GradedCycle cycle = MakeGradedCycle(N, 1e-1, 1e3, 0.2, 1e-6);
  const ComplexVector exact = GradedMultipliers(N, 1e-1, 1e3, 0.2, 1e-6);
  ComplexVector sorted_exact(4);
  sorted_exact << exact(1), exact(2), exact(0), exact(3);  // 1e36 pair, 1e-12, 1e-72
  const ComplexVector schur = ProductEigenvalues(cycle.factors, FloquetMethod::kPeriodicSchur);
  // Each factor Q U Qᵀ is itself formed with errors ε‖M_i‖ ≈ 1e-13, i.e. 1e-7 relative to its
  // smallest singular value 1e-6: the small multiplier can be no more accurate than
  // N·ε·cond(M_i) ≈ 12 · 2e-16 · 1e9 ≈ 3e-6. The others are limited by ε·cond ≈ 1e-12.
  for (Index k = 0; k < 3; ++k) {
    CAPTURE(k, schur(k), sorted_exact(k));
    CHECK(RelativeError(schur(k), sorted_exact(k)) < 1e-10);
  }
  CHECK(RelativeError(schur(3), sorted_exact(3)) < 1e-5);
  std::vector<Matrix> singular = cycle.factors;
  singular[3] = singular[3] * (Matrix::Identity(4, 4) - Matrix::Constant(4, 4, 0.25));  // rank 3
  const ComplexVector with_zero = ProductEigenvalues(singular, FloquetMethod::kPeriodicSchur);
  CHECK(with_zero.allFinite());
  CHECK(std::abs(with_zero(3)) < 1e-60);  // exactly 0 up to round-off in one factor
}

TEST_CASE("the three methods agree on a well-conditioned cycle, and on a single factor",
          "[floquet]") {
  std::vector<Matrix> factors;
  for (int i = 0; i < 5; ++i) {
    Matrix M(3, 3);
    M << 0.9, 0.2 * i, 0.1, -0.3, 0.8, 0.05 * i, 0.2, -0.1, 1.1;
    factors.push_back(M);
  }
  Matrix product = Matrix::Identity(3, 3);
  for (const Matrix& M : factors) product = M * product;
  Eigen::EigenSolver<Matrix> direct(product);
  const ComplexVector reference = direct.eigenvalues();
  for (FloquetMethod method :
       {FloquetMethod::kPeriodicSchur, FloquetMethod::kPencil, FloquetMethod::kProduct}) {
    CAPTURE(ToString(method));
    const ComplexVector values = ProductEigenvalues(factors, method);
    for (Index k = 0; k < 3; ++k) {
      double nearest = kInfinity;
      for (Index j = 0; j < 3; ++j) nearest = std::min(nearest, std::abs(values(k) - reference(j)));
      CHECK(nearest < 1e-12);
    }
    const ComplexVector single = ProductEigenvalues({factors[1]}, method);
    CHECK(single.size() == 3);
  }
}

TEST_CASE("an ill-conditioned product reports the multipliers it cannot resolve, and periodic Schur "
          "resolves them all", "[floquet][failure]") {
  // The graded cycle above: 10^20, a unit-circle pair, 10^-40. The product's answer for the pair
  // is round-off (the test above); here it is also said to be.
  const Index N = 20;
  const GradedCycle cycle = MakeGradedCycle(N, 10.0, 1.0, 0.3, 0.01);
  const FloquetResult product = FloquetMultipliers(cycle.factors, {}, FloquetMethod::kProduct);
  REQUIRE(product.valid);
  CAPTURE(product.resolution);
  CHECK(product.resolution > 1.0);  // ε·Π‖M_i‖ ≥ ε·10^20
  CHECK(product.Unresolved() == 3);  // the pair and 10^-40; the dominant 10^20 stands
  CHECK(std::abs(product.multipliers(0)) > product.resolution);
  const FloquetResult pencil = FloquetMultipliers(cycle.factors, {}, FloquetMethod::kPencil);
  CHECK(pencil.Unresolved() == 3);
  const FloquetResult schur = FloquetMultipliers(cycle.factors, {}, FloquetMethod::kPeriodicSchur);
  CHECK(schur.resolution == 0.0);
  CHECK(schur.Unresolved() == 0);
  // A well-conditioned cycle: nothing unresolved by any method.
  std::vector<Matrix> mild(5, (Matrix(2, 2) << 0.9, 0.1, -0.2, 0.8).finished());
  for (FloquetMethod method : {FloquetMethod::kProduct, FloquetMethod::kPencil, FloquetMethod::kPeriodicSchur}) {
    const FloquetResult r = FloquetMultipliers(mild, {}, method);
    CHECK(r.resolution < 1e-15);
    CHECK(r.Unresolved() == 0);
  }
}

TEST_CASE("deflation removes the trivial direction exactly, even when another multiplier is 1",
          "[floquet]") {
  // Cores with e_0 invariant (trivial multiplier Π 1 = 1) and a nontrivial multiplier that is
  // also exactly 1 (as at a fold), plus 0.5^N. "Remove the value closest to 1" cannot tell which
  // is which; deflating span{e_0} can.
  const Index N = 6, n = 3;
  std::vector<Matrix> factors;
  std::vector<Matrix> Q(N + 1);
  for (Index i = 0; i < N; ++i) Q[i] = Orthogonal(n, 10 + static_cast<int>(i));
  Q[N] = Q[0];
  for (Index i = 0; i < N; ++i) {
    Matrix U(3, 3);
    U << 1.0, 0.4, -0.2,
         0.0, (i % 2 == 0 ? 2.0 : 0.5), 0.3,
         0.0, 0.0, 0.5;
    factors.push_back(Q[i + 1] * U * Q[i].transpose());
  }
  std::vector<Matrix> trivial(N);  // the images of e_0 at every segment start
  for (Index i = 0; i < N; ++i) trivial[i] = Q[i].col(0);
  for (FloquetMethod method : {FloquetMethod::kPeriodicSchur, FloquetMethod::kProduct}) {
    CAPTURE(ToString(method));
    const FloquetResult result = FloquetMultipliers(factors, trivial, method);
    REQUIRE(result.valid);
    REQUIRE(result.trivial.size() == 1);
    REQUIRE(result.multipliers.size() == 2);
    CHECK(std::abs(result.trivial(0) - 1.0) < 1e-13);
    CHECK(std::abs(result.multipliers(0) - 1.0) < 1e-13);               // the "fold" multiplier
    CHECK(std::abs(result.multipliers(1) - std::pow(0.5, N)) < 1e-15);  // 0.5^6
    CHECK(result.invariance_defect < 1e-14);
  }
  // A trivial basis that is not invariant shows up in the defect.
  std::vector<Matrix> wrong = trivial;
  wrong[2] = Q[2].col(1);
  const FloquetResult result = FloquetMultipliers(factors, wrong);
  CHECK(result.invariance_defect > 1e-3);
}

TEST_CASE("Floquet arguments are checked", "[floquet]") {
  std::vector<Matrix> factors = {Matrix::Identity(2, 2), Matrix::Identity(3, 3)};
  CHECK_THROWS_WITH(ProductEigenvalues(factors, FloquetMethod::kPeriodicSchur),
                    Catch::Contains("factors[1]"));
  std::vector<Matrix> good = {Matrix::Identity(2, 2)};
  CHECK_THROWS_WITH(FloquetMultipliers(good, {Matrix::Ones(2, 2)}),
                    Catch::Contains("trivial_bases[0]"));
  CHECK_THROWS_WITH(FloquetMultipliers(good, {Matrix::Ones(2, 1), Matrix::Ones(2, 1)}),
                    Catch::Contains("2 trivial bases for 1 factors"));
  std::vector<Matrix> nan = {Matrix::Constant(2, 2, kNaN)};
  CHECK_FALSE(FloquetMultipliers(nan, {}).valid);
}

}  // namespace
}  // namespace rubcont
