#include "continuation/lyapunov.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <fmt/core.h>

namespace rubcont {
namespace {

using Complex = std::complex<double>;

// Derivatives of F(·, λ) at u along real directions, by central differences with steps relative
// to the problem's scale: each direction is normalized to ‖v ./ scale‖∞ = 1 before stepping.
class Derivatives {
 public:
  Derivatives(Problem& problem, const Vector& u, double lambda, double step)
      : problem_(problem), u_(u), lambda_(lambda), h_(step), scale_(problem.Scale()) {}

  // B(x, y): the mixed second derivative (symmetric bilinear).
  Vector B(const Vector& x, const Vector& y) {
    const double nx = Norm(x), ny = Norm(y);
    if (nx == 0.0 || ny == 0.0) return Vector::Zero(u_.size());
    const Vector a = h_ * x / nx, b = h_ * y / ny;
    const Vector d = F(u_ + a + b) - F(u_ + a - b) - F(u_ - a + b) + F(u_ - a - b);
    return d * (nx * ny / (4.0 * h_ * h_));
  }
  // C(v, v, v): the third derivative along v.
  Vector D(const Vector& v) {
    const double n = Norm(v);
    if (n == 0.0) return Vector::Zero(u_.size());
    const Vector a = h_ * v / n;
    const Vector d = F(u_ + 2.0 * a) - 2.0 * F(u_ + a) + 2.0 * F(u_ - a) - F(u_ - 2.0 * a);
    return d * (n * n * n / (2.0 * h_ * h_ * h_));
  }
  // B of complex arguments, by bilinearity.
  ComplexVector B(const ComplexVector& x, const ComplexVector& y) {
    const Vector xr = x.real(), xi = x.imag(), yr = y.real(), yi = y.imag();
    return (B(xr, yr) - B(xi, yi)).cast<Complex>() + Complex(0.0, 1.0) * (B(xr, yi) + B(xi, yr)).cast<Complex>();
  }
  // C(q, q, q̄) for q = a + ib: C(a,a,a) + C(a,b,b) + i[C(a,a,b) + C(b,b,b)], the mixed terms by
  // polarization: C(a,a,b) = [D(a+b) − D(a−b) − 2D(b)]/6, C(a,b,b) = [D(a+b) + D(a−b) − 2D(a)]/6.
  ComplexVector CqqQbar(const ComplexVector& q) {
    const Vector a = q.real(), b = q.imag();
    const Vector da = D(a), db = D(b), dp = D(a + b), dm = D(a - b);
    const Vector aab = (dp - dm - 2.0 * db) / 6.0, abb = (dp + dm - 2.0 * da) / 6.0;
    return (da + abb).cast<Complex>() + Complex(0.0, 1.0) * (aab + db).cast<Complex>();
  }

 private:
  double Norm(const Vector& v) const { return (v.array() / scale_.array()).abs().maxCoeff(); }
  Vector F(const Vector& u) {
    Vector f;
    problem_.Residual(u, lambda_, f);
    return f;
  }
  Problem& problem_;
  const Vector& u_;
  double lambda_;
  double h_;
  Vector scale_;
};

// The slice-reduced field of a relative equilibrium (see the header).
class SliceReduced : public Problem {
 public:
  SliceReduced(Problem& full, const Vector& x0, const std::function<Vector(const Vector&)>& generator)
      : full_(full), x0_(x0), generator_(generator), g_(generator(x0)) {
    // N: an orthonormal basis of g⊥, from the full QR decomposition of g.
    const Eigen::HouseholderQR<Matrix> qr(g_);
    const Matrix Q = qr.householderQ() * Matrix::Identity(g_.size(), g_.size());
    basis_ = Q.rightCols(g_.size() - 1);
    const Vector scale = full_.Scale();
    scale_ = (basis_.transpose() * scale.asDiagonal()).cwiseAbs().rowwise().maxCoeff();
  }
  Index Dimension() const override { return basis_.cols(); }
  void Residual(const Vector& y, double lambda, Vector& F) override {
    const Vector x = x0_ + basis_ * y;
    Vector f;
    full_.Residual(x, lambda, f);
    const Vector gx = generator_(x);
    const double drift = g_.dot(f) / g_.dot(gx);
    F = basis_.transpose() * (f - drift * gx);
  }
  Vector Scale() const override { return scale_; }
  double GroupDirectionNorm() const { return g_.norm(); }

 private:
  Problem& full_;
  const Vector& x0_;
  const std::function<Vector(const Vector&)>& generator_;
  Vector g_;
  Matrix basis_;
  Vector scale_;
};

}  // namespace

LyapunovCoefficient FirstLyapunovCoefficientOfRelativeEquilibrium(
    Problem& problem, const Vector& x0, double lambda,
    const std::function<Vector(const Vector&)>& generator, double step, std::complex<double> near) {
  SliceReduced reduced(problem, x0, generator);
  if (!(reduced.GroupDirectionNorm() > 0.0)) {
    LyapunovCoefficient out;
    out.message = "the group direction G x0 vanishes: x0 is a fixed point of the group, not a "
                  "relative equilibrium";
    return out;
  }
  return FirstLyapunovCoefficient(reduced, Vector::Zero(reduced.Dimension()), lambda, step, near);
}

bool AgreesTo(const LyapunovCoefficient& c, double scale) {
  return std::abs(c.l1 - c.l1_coarse) <=
         0.01 * std::max({std::abs(c.l1), std::abs(c.l1_coarse), scale});
}

LyapunovCoefficient FirstLyapunovCoefficient(Problem& problem, const Vector& u, double lambda,
                                             double step, std::complex<double> near) {
  LyapunovCoefficient out;
  Matrix A;
  problem.Jacobian(u, lambda, A);
  const Index n = A.rows();
  if (n < 2) {
    out.message = "fewer than two unknowns: no Hopf pair";
    return out;
  }
  Eigen::ComplexEigenSolver<Matrix> right(A);
  if (right.info() != Eigen::Success) {
    out.message = "the eigenvalue solver failed on the Jacobian";
    return out;
  }
  // The pair nearest `near`, or nearest the imaginary axis, among eigenvalues with Im > 0.
  const bool by_near = near != Complex(0.0, 0.0);
  auto distance = [&](Complex e) { return by_near ? std::abs(e - near) : std::abs(e.real()); };
  Index k = -1;
  for (Index i = 0; i < n; ++i) {
    const Complex e = right.eigenvalues()(i);
    if (e.imag() <= 0.0) continue;
    if (k < 0 || distance(e) < distance(right.eigenvalues()(k))) k = i;
  }
  if (k < 0) {
    out.message = "no complex eigenvalue pair: not a Hopf point";
    return out;
  }
  const Complex mu = right.eigenvalues()(k);
  out.omega = mu.imag();
  out.real_part = mu.real();
  const double size = right.eigenvalues().cwiseAbs().maxCoeff();
  for (Index i = 0; i < n; ++i) {
    const Complex e = right.eigenvalues()(i);
    if (i != k && std::abs(e - std::conj(mu)) > 1e-9 * size && std::abs(e) < 1e-9 * size) {
      out.message = fmt::format(
          "the Jacobian has a zero eigenvalue besides the Hopf pair (|λ| = {:.3g}): a continuous "
          "symmetry (e.g. a rotating wave); the coefficient needs the reduced system",
          std::abs(e));
      return out;
    }
  }
  const double omega = out.omega;
  ComplexVector q = right.eigenvectors().col(k);
  q /= q.norm();
  // p: Aᵀ p = −iω p, ⟨p, q⟩ = 1.
  Eigen::ComplexEigenSolver<Matrix> left(A.transpose());
  Index j = 0;
  for (Index i = 1; i < n; ++i)
    if (std::abs(left.eigenvalues()(i) - std::conj(mu)) < std::abs(left.eigenvalues()(j) - std::conj(mu))) j = i;
  ComplexVector p = left.eigenvectors().col(j);
  const Complex pq = p.dot(q);  // p̄ᵀ q
  if (std::abs(pq) < 1e-12 * p.norm()) {
    out.message = "the left and right eigenvectors are orthogonal: the pair is not simple";
    return out;
  }
  p /= std::conj(pq);

  const Eigen::PartialPivLU<Matrix> a_lu = A.partialPivLu();
  const ComplexMatrix shifted = Complex(0.0, 2.0 * omega) * ComplexMatrix::Identity(n, n) - A.cast<Complex>();
  const Eigen::PartialPivLU<ComplexMatrix> shifted_lu = shifted.partialPivLu();
  auto coefficient = [&](double h) {
    Derivatives d(problem, u, lambda, h);
    const ComplexVector qbar = q.conjugate();
    const Vector r = a_lu.solve(Vector(d.B(q, qbar).real()));  // B(q, q̄) = B(a,a) + B(b,b): real
    const ComplexVector s = shifted_lu.solve(d.B(q, q));
    const Complex value =
        p.dot(d.CqqQbar(q)) - 2.0 * p.dot(d.B(q, r.cast<Complex>())) + p.dot(d.B(qbar, s));
    return value.real() / (2.0 * omega);
  };
  out.l1_coarse = coefficient(step);
  out.l1 = coefficient(0.1 * step);
  if (!std::isfinite(out.l1) || !std::isfinite(out.l1_coarse)) {
    out.message = "the coefficient is not finite";
  } else if (!AgreesTo(out, 0.0)) {
    out.message = fmt::format("not converged in the finite-difference step: {:.4g} at h = {:g}, "
                              "{:.4g} at h = {:g}", out.l1_coarse, step, out.l1, 0.1 * step);
  } else {
    out.valid = true;
  }
  return out;
}

}  // namespace rubcont
