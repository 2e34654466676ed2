#include "continuation/lyapunov.h"

#include <cmath>
#include <complex>
#include <tuple>

#include <catch2/catch.hpp>
#include <Eigen/Dense>

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// The Hopf normal form ż = (μ + iω) z + (σ + iβ) z|z|², z = x + iy, parameter μ; optionally seen
// through the near-identity change of coordinates x = y + Q(y, y) (quadratic, identity linear
// part), which leaves the coefficient unchanged but gives the system quadratic terms, so that
// every term of the formula is exercised. The coefficient at μ = 0 is 2σ/ω (⟨q, q⟩ = 1).
class NormalForm : public Problem {
 public:
  NormalForm(double omega, double sigma, double beta, bool transformed)
      : omega_(omega), sigma_(sigma), beta_(beta), transformed_(transformed) {}
  Index Dimension() const override { return 2; }
  void Residual(const Vector& u, double mu, Vector& F) override {
    if (!transformed_) {
      F = Field(u, mu);
      return;
    }
    // ẏ = (I + DQ(y))⁻¹ f(y + Q(y, y)), Q(y, y) = (0.3 y0² − 0.5 y0 y1, 0.7 y1² + 0.2 y0 y1).
    const Vector x = u + Q(u);
    Eigen::Matrix2d dq;
    dq << 0.6 * u(0) - 0.5 * u(1), -0.5 * u(0), 0.2 * u(1), 1.4 * u(1) + 0.2 * u(0);
    F = (Eigen::Matrix2d::Identity() + dq).partialPivLu().solve(Field(x, mu));
  }

 private:
  static Vector Q(const Vector& y) {
    Vector q(2);
    q << 0.3 * y(0) * y(0) - 0.5 * y(0) * y(1), 0.7 * y(1) * y(1) + 0.2 * y(0) * y(1);
    return q;
  }
  Vector Field(const Vector& x, double mu) const {
    const double r2 = x.squaredNorm();
    Vector f(2);
    f << mu * x(0) - omega_ * x(1) + (sigma_ * x(0) - beta_ * x(1)) * r2,
        omega_ * x(0) + mu * x(1) + (sigma_ * x(1) + beta_ * x(0)) * r2;
    return f;
  }
  double omega_, sigma_, beta_;
  bool transformed_;
};

TEST_CASE("First Lyapunov coefficient of the Hopf normal form, both signs, with and without "
          "quadratic terms", "[lyapunov]") {
  for (const bool transformed : {false, true}) {
    for (const double sigma : {-1.3, 0.7}) {
      CAPTURE(transformed, sigma);
      NormalForm problem(2.0, sigma, 0.4, transformed);
      const LyapunovCoefficient c = FirstLyapunovCoefficient(problem, Vector::Zero(2), 0.0);
      INFO(c.message);
      REQUIRE(c.valid);
      // The Jacobian is the default central difference (step 6e-6): ω and Re to about 1e-10.
      CHECK(c.omega == Approx(2.0).epsilon(1e-9));
      CHECK(std::abs(c.real_part) < 1e-9);
      CHECK(c.l1 == Approx(2.0 * sigma / 2.0).epsilon(1e-5));
    }
  }
}

// Stuart–Landau (models/textbook.h) at its Hopf point λ = 0: ż = (λ + iω)z − (1 + iγ)|z|²z,
// supercritical, l1 = −2/ω; embedded with a decoupled stable direction ẇ = −w that the formula
// must leave out.
class StuartLandauWithDamping : public Problem {
 public:
  Index Dimension() const override { return 3; }
  void Residual(const Vector& u, double lambda, Vector& F) override {
    const double omega = 5.0, gamma = 0.8, r2 = u(0) * u(0) + u(1) * u(1);
    F.resize(3);
    F << lambda * u(0) - omega * u(1) - (u(0) - gamma * u(1)) * r2,
        omega * u(0) + lambda * u(1) - (u(1) + gamma * u(0)) * r2, -u(2) + u(0) * u(1);
  }
};

TEST_CASE("First Lyapunov coefficient of Stuart-Landau with a stable direction is supercritical",
          "[lyapunov]") {
  StuartLandauWithDamping problem;
  const LyapunovCoefficient c = FirstLyapunovCoefficient(problem, Vector::Zero(3), 0.0);
  INFO(c.message);
  REQUIRE(c.valid);
  CHECK(c.omega == Approx(5.0).epsilon(1e-10));
  CHECK(c.l1 == Approx(-2.0 / 5.0).epsilon(1e-5));
}

// ż = iωz + σz|z|² with a rotation-symmetric third direction that does not move (ẇ = 0): the
// Jacobian has a zero eigenvalue besides the pair, as a relative equilibrium's does.
class WithSymmetryZero : public Problem {
 public:
  Index Dimension() const override { return 3; }
  void Residual(const Vector& u, double, Vector& F) override {
    const double r2 = u(0) * u(0) + u(1) * u(1);
    F.resize(3);
    F << -u(1) - u(0) * r2, u(0) - u(1) * r2, 0.0 * u(2);
  }
};

TEST_CASE("A Jacobian with a zero eigenvalue besides the Hopf pair gives no coefficient, and says "
          "why", "[lyapunov]") {
  WithSymmetryZero problem;
  const LyapunovCoefficient c = FirstLyapunovCoefficient(problem, Vector::Zero(3), 0.0);
  CHECK_FALSE(c.valid);
  CHECK_THAT(c.message, Contains("zero eigenvalue besides the Hopf pair"));
}

// A rotating wave in its co-rotating frame: z = 1, w = 0 of
//   ż = z (1 − |z|² + ρ|w|²) + iκ|w|² z,    ẇ = (μ + iω) w + (σ + iβ) w|w|² + η (|z|² − 1) w,
// equivariant under z ↦ e^{iφ} z (generator (z, w) ↦ (iz, 0)). The Jacobian has the group's zero
// eigenvalue; |w|² drifts the phase of z (κ: the slice removes it) and pushes its radius out
// (|z|² − 1 = ρ|w|² on the centre manifold), which feeds back into w through η: the reduced
// normal form has the cubic coefficient σ + ηρ + i(…), so l1 = 2(σ + ηρ)/ω.
class ModulatedWave : public Problem {
 public:
  ModulatedWave(double sigma, double rho, double eta) : sigma_(sigma), rho_(rho), eta_(eta) {}
  Index Dimension() const override { return 4; }
  void Residual(const Vector& u, double mu, Vector& F) override {
    const std::complex<double> z(u(0), u(1)), w(u(2), u(3));
    const double z2 = std::norm(z), w2 = std::norm(w);
    const std::complex<double> i(0.0, 1.0);
    const std::complex<double> dz = z * (1.0 - z2 + rho_ * w2) + i * kappa_ * w2 * z;
    const std::complex<double> dw = (mu + i * omega_) * w + (sigma_ + i * beta_) * w * w2 + eta_ * (z2 - 1.0) * w;
    F.resize(4);
    F << dz.real(), dz.imag(), dw.real(), dw.imag();
  }
  static Vector Generator(const Vector& u) {
    Vector g(4);
    g << -u(1), u(0), 0.0, 0.0;
    return g;
  }
  double omega_ = 3.0, beta_ = 0.3, kappa_ = 0.7;

 private:
  double sigma_, rho_, eta_;
};

TEST_CASE("First Lyapunov coefficient of a rotating wave's Hopf point, on the slice", "[lyapunov]") {
  const Vector x0 = (Vector(4) << 1.0, 0.0, 0.0, 0.0).finished();
  for (const auto& [sigma, rho, eta] : {std::tuple{-0.5, 0.8, 1.5}, std::tuple{-0.5, 0.8, -1.0},
                                        std::tuple{0.4, 0.0, 2.0}}) {
    CAPTURE(sigma, rho, eta);
    ModulatedWave problem(sigma, rho, eta);
    // The full system: the group's zero eigenvalue stops the plain formula.
    CHECK_FALSE(FirstLyapunovCoefficient(problem, x0, 0.0).valid);
    const LyapunovCoefficient c =
        FirstLyapunovCoefficientOfRelativeEquilibrium(problem, x0, 0.0, ModulatedWave::Generator);
    INFO(c.message);
    REQUIRE(c.valid);
    CHECK(c.omega == Approx(3.0).epsilon(1e-9));
    CHECK(c.l1 == Approx(2.0 * (sigma + eta * rho) / 3.0).epsilon(1e-5));
  }
}

}  // namespace
}  // namespace rubcont
