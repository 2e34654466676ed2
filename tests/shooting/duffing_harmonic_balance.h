// Harmonic balance for the forced Duffing oscillator, written for the tests as a computation that
// shares nothing with shooting (no time integration, no sensitivities):
//
//   ẍ + c ẋ + k x + β x³ = F cos(w t),   x(t) ≈ a_0 + Σ_{h=1}^{H} (a_h cos hθ + b_h sin hθ),  θ = w t.
//
// Galerkin projection onto the same harmonics. The linear part is exact in coefficient space; the
// cubic is evaluated at M = 4H + 2 equally spaced phases and projected back with the discrete
// Fourier sums, which is exact: x³ has harmonics up to 3H, and 3H + H < M avoids aliasing onto the
// retained ones. The periodic solution is analytic, so the coefficients decay geometrically and
// the truncation error falls below 1e-12 for H ≈ 25 (checked by comparing H with 2H).
//
// Folds of the response curve (LocateFold): the Moore–Spence extended system in (c, v, w),
//   R(c, w) = 0,   R_c(c, w) v = 0,   ℓᵀ v = 1,
// with the exact second derivatives (R is a polynomial in c and w), by Newton from the fold of the
// one-term balance (OneTermFolds): nothing of the continuation engine or of shooting is used.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <utility>
#include <vector>

#include "models/textbook.h"
#include "solvers/constants.h"
#include "solvers/newton.h"

namespace rubcont {
namespace testing {

class DuffingHarmonicBalance {
 public:
  DuffingHarmonicBalance(const DuffingParams& params, int harmonics)
      : p_(params), H_(harmonics), M_(4 * harmonics + 2), basis_(M_, 2 * harmonics + 1) {
    for (int j = 0; j < M_; ++j) {
      const double theta = kTwoPi * j / M_;
      basis_(j, 0) = 1.0;
      for (int h = 1; h <= H_; ++h) {
        basis_(j, 2 * h - 1) = std::cos(h * theta);
        basis_(j, 2 * h) = std::sin(h * theta);
      }
    }
    // Discrete projection: a_0 = (1/M) Σ q_j, a_h = (2/M) Σ q_j cos hθ_j, b_h likewise.
    projection_ = basis_.transpose() * (2.0 / M_);
    projection_.row(0) *= 0.5;
    linear_ = LinearPart(p_.frequency);
  }

  Index Size() const { return 2 * H_ + 1; }

  void Residual(const Vector& coefficients, Vector& R) const {
    ResidualAt(coefficients, linear_, R);
  }

  void Jacobian(const Vector& coefficients, Matrix& J) const {
    JacobianAt(coefficients, linear_, J);
  }

  // A fold of the response curve: coefficients, frequency w and the null vector of R_c there.
  struct Fold {
    Vector coefficients;
    Vector null_vector;
    double frequency = 0.0;
    NewtonResult newton;
  };

  // Newton on the extended system from the guess (coefficients, w); the null-vector guess is the
  // right singular vector of R_c's smallest singular value at the guess.
  Fold LocateFold(const Vector& coefficients, double frequency) const {
    const Index m = Size();
    Matrix J;
    JacobianAt(coefficients, LinearPart(frequency), J);
    Eigen::JacobiSVD<Matrix> svd(J, Eigen::ComputeFullV);
    Vector v = svd.matrixV().col(m - 1);
    const Vector ell = v;  // normalization ℓᵀv = 1 along the initial null vector
    Vector z(2 * m + 1);
    z << coefficients, v, frequency;
    auto residual = [&](const Vector& y, Vector& F) {
      const Vector c = y.head(m), n = y.segment(m, m);
      const Matrix L = LinearPart(y(2 * m));
      Vector R;
      Matrix Jc;
      ResidualAt(c, L, R);
      JacobianAt(c, L, Jc);
      F.resize(2 * m + 1);
      F << R, Jc * n, ell.dot(n) - 1.0;
    };
    auto jacobian = [&](const Vector& y, Matrix& D) {
      const Vector c = y.head(m), n = y.segment(m, m);
      const double w = y(2 * m);
      const Matrix L = LinearPart(w), Lw = LinearPartDw(w);
      Matrix Jc;
      JacobianAt(c, L, Jc);
      const Vector x = basis_ * c, xn = basis_ * n;
      D = Matrix::Zero(2 * m + 1, 2 * m + 1);
      D.block(0, 0, m, m) = Jc;
      D.block(0, 2 * m, m, 1) = Lw * c;
      // ∂(R_c n)/∂c = P diag(6β x ∘ (B n)) B.
      D.block(m, 0, m, m) =
          projection_ * (6.0 * p_.cubic * x.array() * xn.array()).matrix().asDiagonal() * basis_;
      D.block(m, m, m, m) = Jc;
      D.block(m, 2 * m, m, 1) = Lw * n;
      D.block(2 * m, m, 1, m) = ell.transpose();
    };
    NewtonOptions options;
    options.max_iterations = 40;
    options.residual_tolerance = 1e-13;
    options.step_tolerance = 1e-13;
    Fold fold;
    fold.newton = NewtonSolve(residual, jacobian, z, options);
    fold.coefficients = z.head(m);
    fold.null_vector = z.segment(m, m);
    fold.frequency = z(2 * m);
    return fold;
  }

  // The folds of the one-term balance: frequencies where two of the amplitudes of OneTermSolutions
  // merge (the cubic in A² has a double root), with that double amplitude and its phase, in
  // increasing frequency. Bisection on the number of solutions over [w_lo, w_hi], which must
  // bracket the bistable band.
  struct OneTermFold {
    double frequency = 0.0;
    double amplitude = 0.0;
    double phase = 0.0;
  };
  static std::vector<OneTermFold> OneTermFolds(DuffingParams p, double w_lo, double w_hi,
                                               int grid = 400) {
    auto count = [&p](double w) {
      p.frequency = w;
      return OneTermSolutions(p).size();
    };
    std::vector<OneTermFold> folds;
    for (int i = 0; i < grid; ++i) {
      double a = w_lo + (w_hi - w_lo) * i / grid, b = w_lo + (w_hi - w_lo) * (i + 1) / grid;
      const std::size_t na = count(a), nb = count(b);
      if (na == nb) continue;
      for (int k = 0; k < 200 && b - a > 1e-14; ++k) {
        const double mid = 0.5 * (a + b);
        (count(mid) == na ? a : b) = mid;
      }
      // The inner side has three solutions; the merging pair is the one closest together.
      p.frequency = na == 3 ? a : b;
      const auto s = OneTermSolutions(p);
      const std::size_t pair =
          std::abs(s[1].first - s[0].first) < std::abs(s[2].first - s[1].first) ? 0 : 1;
      folds.push_back({p.frequency, 0.5 * (s[pair].first + s[pair + 1].first),
                       0.5 * (s[pair].second + s[pair + 1].second)});
    }
    return folds;
  }

  // Newton from `coefficients` (overwritten).
  NewtonResult Solve(Vector& coefficients) const {
    NewtonOptions options;
    options.max_iterations = 40;
    options.residual_tolerance = 1e-13;
    options.step_tolerance = 1e-13;
    return NewtonSolve([this](const Vector& c, Vector& R) { Residual(c, R); },
                       [this](const Vector& c, Matrix& J) { Jacobian(c, J); }, coefficients,
                       options);
  }

  // Coefficients of the one-harmonic guess x = A cos(θ − ψ).
  Vector FirstHarmonic(double amplitude, double phase) const {
    Vector c = Vector::Zero(Size());
    c(1) = amplitude * std::cos(phase);
    c(2) = amplitude * std::sin(phase);
    return c;
  }

  // x(0) and ẋ(0) of the truncated series.
  double Displacement0(const Vector& c) const {
    double x = c(0);
    for (int h = 1; h <= H_; ++h) x += c(2 * h - 1);
    return x;
  }
  double Velocity0(const Vector& c) const { return Velocity0(c, p_.frequency); }
  double Velocity0(const Vector& c, double w) const {
    double v = 0.0;
    for (int h = 1; h <= H_; ++h) v += h * w * c(2 * h);
    return v;
  }
  static double FirstHarmonicAmplitude(const Vector& c) { return std::hypot(c(1), c(2)); }

  // The classic one-term balance: amplitudes A of x ≈ A cos(wt − ψ), the positive roots of
  // (9/16)β² A⁶ + (3/2)β(k − w²) A⁴ + ((k − w²)² + c²w²) A² − F² = 0 (a cubic in A²), with
  // tan ψ = c w / (k − w² + ¾ β A²). Returned in increasing amplitude, as (A, ψ) pairs.
  static std::vector<std::pair<double, double>> OneTermSolutions(const DuffingParams& p) {
    const double w = p.frequency, d = p.stiffness - w * w;
    Matrix companion = Matrix::Zero(3, 3);
    const double a3 = 9.0 / 16.0 * p.cubic * p.cubic, a2 = 1.5 * p.cubic * d,
                 a1 = d * d + p.damping * p.damping * w * w, a0 = -p.force * p.force;
    companion(0, 0) = -a2 / a3;
    companion(0, 1) = -a1 / a3;
    companion(0, 2) = -a0 / a3;
    companion(1, 0) = 1.0;
    companion(2, 1) = 1.0;
    Eigen::EigenSolver<Matrix> solver(companion, false);
    std::vector<std::pair<double, double>> solutions;
    for (Index i = 0; i < 3; ++i) {
      const std::complex<double> z = solver.eigenvalues()(i);
      if (std::abs(z.imag()) < 1e-12 && z.real() > 0.0) {
        const double A = std::sqrt(z.real());
        solutions.emplace_back(A, std::atan2(p.damping * w, d + 0.75 * p.cubic * A * A));
      }
    }
    std::sort(solutions.begin(), solutions.end());
    return solutions;
  }

 private:
  // The linear part at frequency w: k − (hw)² on the diagonal, ± c h w off it; and its w-derivative.
  Matrix LinearPart(double w) const {
    Matrix L = Matrix::Zero(Size(), Size());
    L(0, 0) = p_.stiffness;
    for (int h = 1; h <= H_; ++h) {
      const double hw = h * w;
      const int a = 2 * h - 1, b = 2 * h;
      L(a, a) = L(b, b) = p_.stiffness - hw * hw;
      L(a, b) = p_.damping * hw;
      L(b, a) = -p_.damping * hw;
    }
    return L;
  }
  Matrix LinearPartDw(double w) const {
    Matrix L = Matrix::Zero(Size(), Size());
    for (int h = 1; h <= H_; ++h) {
      const int a = 2 * h - 1, b = 2 * h;
      L(a, a) = L(b, b) = -2.0 * h * h * w;
      L(a, b) = p_.damping * h;
      L(b, a) = -p_.damping * h;
    }
    return L;
  }
  void ResidualAt(const Vector& c, const Matrix& L, Vector& R) const {
    const Vector x = basis_ * c;
    R = L * c + projection_ * (p_.cubic * x.array().cube()).matrix();
    R(1) -= p_.force;
  }
  void JacobianAt(const Vector& c, const Matrix& L, Matrix& J) const {
    const Vector x = basis_ * c;
    J = L + projection_ * (3.0 * p_.cubic * x.array().square()).matrix().asDiagonal() * basis_;
  }

  DuffingParams p_;
  int H_;
  int M_;
  Matrix basis_;       // M × (2H+1): basis functions at the sample phases
  Matrix projection_;  // (2H+1) × M: discrete Fourier projection
  Matrix linear_;      // (2H+1) × (2H+1): k − (hw)², ± c h w per harmonic
};

}  // namespace testing
}  // namespace rubcont
