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
#pragma once

#include <cmath>
#include <complex>

#include "models/textbook.h"
#include "solvers/newton.h"

namespace rubcont {
namespace testing {

class DuffingHarmonicBalance {
 public:
  DuffingHarmonicBalance(const DuffingParams& params, int harmonics)
      : p_(params), H_(harmonics), M_(4 * harmonics + 2), basis_(M_, 2 * harmonics + 1) {
    for (int j = 0; j < M_; ++j) {
      const double theta = 2.0 * M_PI * j / M_;
      basis_(j, 0) = 1.0;
      for (int h = 1; h <= H_; ++h) {
        basis_(j, 2 * h - 1) = std::cos(h * theta);
        basis_(j, 2 * h) = std::sin(h * theta);
      }
    }
    // Discrete projection: a_0 = (1/M) Σ q_j, a_h = (2/M) Σ q_j cos hθ_j, b_h likewise.
    projection_ = basis_.transpose() * (2.0 / M_);
    projection_.row(0) *= 0.5;
    linear_ = Matrix::Zero(Size(), Size());
    linear_(0, 0) = p_.stiffness;
    for (int h = 1; h <= H_; ++h) {
      const double hw = h * p_.frequency;
      const int a = 2 * h - 1, b = 2 * h;
      linear_(a, a) = p_.stiffness - hw * hw;
      linear_(a, b) = p_.damping * hw;
      linear_(b, b) = p_.stiffness - hw * hw;
      linear_(b, a) = -p_.damping * hw;
    }
  }

  Index Size() const { return 2 * H_ + 1; }

  void Residual(const Vector& coefficients, Vector& R) const {
    const Vector x = basis_ * coefficients;
    R = linear_ * coefficients + projection_ * (p_.cubic * x.array().cube()).matrix();
    R(1) -= p_.force;
  }

  void Jacobian(const Vector& coefficients, Matrix& J) const {
    const Vector x = basis_ * coefficients;
    J = linear_ +
        projection_ * (3.0 * p_.cubic * x.array().square()).matrix().asDiagonal() * basis_;
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
  double Velocity0(const Vector& c) const {
    double v = 0.0;
    for (int h = 1; h <= H_; ++h) v += h * p_.frequency * c(2 * h);
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
  DuffingParams p_;
  int H_;
  int M_;
  Matrix basis_;       // M × (2H+1): basis functions at the sample phases
  Matrix projection_;  // (2H+1) × M: discrete Fourier projection
  Matrix linear_;      // (2H+1) × (2H+1): k − (hw)², ± c h w per harmonic
};

}  // namespace testing
}  // namespace rubcont
