#include "solvers/constants.h"
#include "solvers/linear_algebra.h"

#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/QR>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

TEST_CASE("the log-determinant from an LU matches the determinant, sign included",
          "[linear_algebra]") {
  Matrix A(3, 3);
  A << 0.0, 2.0, 1.0,  //
      1.0, -1.0, 0.5,  //
      3.0, 0.0, -2.0;
  const Eigen::PartialPivLU<Matrix> lu(A);
  const LogDeterminant det = LogDeterminantOf(lu);
  const double exact = A.determinant();
  CHECK(det.sign == (exact > 0 ? 1 : -1));
  CHECK(std::exp(det.log_abs) == Approx(std::abs(exact)).epsilon(1e-13));
  // Swapping two rows flips the sign.
  Matrix B = A;
  B.row(0).swap(B.row(2));
  CHECK(LogDeterminantOf(Eigen::PartialPivLU<Matrix>(B)).sign == -det.sign);
  // Far beyond the range of double, the logarithm is still exact.
  const Matrix big = 1e3 * Matrix::Identity(200, 200);
  const LogDeterminant huge = LogDeterminantOf(Eigen::PartialPivLU<Matrix>(big));
  CHECK(huge.sign == 1);
  CHECK(huge.log_abs == Approx(200 * std::log(1e3)).epsilon(1e-14));
}

TEST_CASE("null vectors of a wide matrix with a two-dimensional kernel", "[linear_algebra]") {
  // Rows span the complement of {(1, 1, 0, 0), (0, 0, 1, -1)} in R⁴ (rank 2 of 3 rows).
  Matrix A(3, 4);
  A << 1.0, -1.0, 0.0, 0.0,  //
      0.0, 0.0, 1.0, 1.0,    //
      1.0, -1.0, 2.0, 2.0;
  const NullVectors null = SmallestSingularVectors(A, 2);
  REQUIRE(null.right.cols() == 2);
  CHECK((A * null.right).norm() <= 1e-14);
  CHECK((null.right.transpose() * null.right - Eigen::Matrix2d::Identity()).norm() <= 1e-14);
  CHECK(null.singular_values(0) <= 1e-14);  // rank-deficient: the smallest σ vanishes
  CHECK((A.transpose() * null.left.col(0)).norm() <= 1e-14);
}

TEST_CASE("the smallest singular pair of a nearly singular square matrix", "[linear_algebra]") {
  Matrix A = Matrix::Identity(3, 3);
  A(2, 2) = 1e-9;
  const NullVectors null = SmallestSingularVectors(A, 1);
  CHECK(null.singular_values(0) == Approx(1e-9));
  CHECK(std::abs(null.right(2, 0)) == Approx(1.0));
  CHECK(std::abs(null.left(2, 0)) == Approx(1.0));
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

TEST_CASE("DenseLu solves and gives the determinant below and above its unblocked limit",
          "[linear_algebra]") {
  const Index n = GENERATE(Index(1), Index(5), Index(17), DenseLu::kUnblockedLimit + 12);
  std::srand(7);
  const Matrix A = Matrix::Random(n, n) + 0.5 * Matrix::Identity(n, n);
  const Vector b = Vector::Random(n);
  DenseLu lu;
  lu.Compute(A);
  Vector x;
  lu.Solve(b, x);
  CHECK((A * x - b).norm() <= 1e-12 * (A.norm() * x.norm() + b.norm()));
  const Eigen::PartialPivLU<Matrix> reference(A);
  const LogDeterminant det = lu.Determinant();
  const LogDeterminant expected = LogDeterminantOf(reference);
  CHECK(det.sign == expected.sign);
  CHECK(det.log_abs == Approx(expected.log_abs).epsilon(1e-12).margin(1e-12));
  CHECK(lu.PivotRatio() > 0.0);
  // The same object refactors another matrix of the same size.
  Matrix B = A;
  B.row(0).swap(B.row(n > 1 ? 1 : 0));
  lu.Compute(B);
  CHECK(lu.Determinant().sign == (n > 1 ? -det.sign : det.sign));
}

TEST_CASE("DenseLu reports an exactly singular matrix through its pivots", "[linear_algebra]") {
  Matrix A(3, 3);
  A << 1, 2, 3,  //
      2, 4, 6,   //
      1, 0, 1;
  DenseLu lu;
  lu.Compute(A);
  CHECK(lu.PivotRatio() <= 1e-16);
  CHECK(lu.Determinant().sign == 0);
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// Balancing is an exact similarity (powers of two): it must change no eigenvalue. Where it matters
// (the close pair of the rub whip's state matrix, scattered by ±2.5 s⁻¹ without it) is tested in
// tests/waves/rotating_wave_branches_test.cpp.
TEST_CASE("balanced eigenvalues of a graded matrix are its eigenvalues", "[linear_algebra]") {
  // Known spectrum: pairs −0.5 ± 700i, −4 ± 276i, −13 ± 1320i and reals 730, −2e5, −3e5, mixed
  // by an orthogonal similarity, then scaled by D = diag(10^k), k from −6 to 6: the spread of a
  // stiff contact model's state matrix (positions ~1e-4 m, forces ~1e3 N).
  const std::vector<std::pair<double, double>> pairs = {{-0.5, 700.0}, {-4.0, 276.0}, {-13.0, 1320.0}};
  const std::vector<double> reals = {730.0, -2e5, -3e5};
  const Index n = 2 * static_cast<Index>(pairs.size()) + static_cast<Index>(reals.size());
  Matrix T = Matrix::Zero(n, n);
  Index i = 0;
  for (const auto& [re, im] : pairs) {
    T(i, i) = T(i + 1, i + 1) = re;
    T(i, i + 1) = -im;
    T(i + 1, i) = im;
    i += 2;
  }
  for (double r : reals) T(i, i) = r, ++i;
  const Matrix Q = Eigen::HouseholderQR<Matrix>(Matrix::Random(n, n)).householderQ();
  Vector d(n);
  for (Index k = 0; k < n; ++k) d(k) = std::pow(10.0, -6.0 + 12.0 * k / (n - 1));
  const Matrix A = d.cwiseInverse().asDiagonal() * (Q * T * Q.transpose()) * d.asDiagonal();
  ComplexVector values;
  REQUIRE(BalancedEigenvalues(A, values));
  REQUIRE(values.size() == n);
  auto distance_to_nearest = [&](std::complex<double> expected) {
    double best = kInfinity;
    for (Index k = 0; k < n; ++k) best = std::min(best, std::abs(values(k) - expected));
    return best;
  };
  for (const auto& [re, im] : pairs) {
    CHECK(distance_to_nearest({re, im}) < 1e-9 * std::abs(std::complex<double>(re, im)));
    // The real part, which decides stability, to far better than its own size.
    double closest_re = 0.0, best = kInfinity;
    for (Index k = 0; k < n; ++k) {
      if (std::abs(values(k) - std::complex<double>(re, im)) < best) {
        best = std::abs(values(k) - std::complex<double>(re, im));
        closest_re = values(k).real();
      }
    }
    CHECK(std::abs(closest_re - re) < 1e-6);
  }
  for (double r : reals) CHECK(distance_to_nearest({r, 0.0}) < 1e-9 * std::abs(r));
  CHECK_THROWS_AS(BalancedEigenvalues(Matrix::Zero(2, 3), values), std::invalid_argument);
}

}  // namespace
}  // namespace rubcont
