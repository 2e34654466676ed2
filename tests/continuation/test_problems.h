// Toy problems with closed-form answers for the continuation tests: a Problem built from lambdas.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "continuation/lyapunov.h"
#include "continuation/problem.h"

namespace rubcont {
namespace testing {

// The eigenvalues of J as a valid Spectrum (the stability operator of a LambdaProblem).
inline Spectrum EigenvaluesOf(const Matrix& J) {
  Spectrum spectrum;
  spectrum.kind = SpectrumKind::kEigenvalues;
  spectrum.values = Eigen::EigenSolver<Matrix>(J).eigenvalues();
  spectrum.valid = true;
  return spectrum;
}

// F(u, λ) from lambdas; Jacobian and ∂F/∂λ analytic when given, else the Problem defaults
// (finite differences). Optional second parameter η, stability operator and scales.
class LambdaProblem : public Problem {
 public:
  using ResidualFn = std::function<void(const Vector& u, double lambda, double eta, Vector& F)>;
  using JacobianFn = std::function<void(const Vector& u, double lambda, double eta, Matrix& J)>;
  using DfDlambdaFn = std::function<void(const Vector& u, double lambda, double eta, Vector& dF)>;
  using StabilityFn = std::function<Spectrum(const Vector& u, double lambda, double eta)>;

  LambdaProblem(Index n, ResidualFn residual, JacobianFn jacobian = {},
                DfDlambdaFn dfdlambda = {})
      : n_(n),
        residual_(std::move(residual)),
        jacobian_(std::move(jacobian)),
        dfdlambda_(std::move(dfdlambda)),
        scale_(Vector::Ones(n)),
        residual_scale_(Vector::Ones(n)) {}

  Index Dimension() const override { return n_; }
  void Residual(const Vector& u, double lambda, Vector& F) override {
    F.resize(n_);
    residual_(u, lambda, eta_, F);
  }
  void Jacobian(const Vector& u, double lambda, Matrix& J) override {
    if (!jacobian_) return Problem::Jacobian(u, lambda, J);
    J.resize(n_, n_);
    jacobian_(u, lambda, eta_, J);
  }
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override {
    if (!dfdlambda_) return Problem::DfDlambda(u, lambda, dF);
    dF.resize(n_);
    dfdlambda_(u, lambda, eta_, dF);
  }
  Vector Scale() const override { return scale_; }
  double LambdaScale() const override { return lambda_scale_; }
  Vector ResidualScale() const override { return residual_scale_; }

  bool HasStability() const override { return static_cast<bool>(stability_); }
  Spectrum Stability(const Vector& u, double lambda) override {
    return stability_(u, lambda, eta_);
  }

  // The first Lyapunov coefficient of u' = F(u, λ) when EnableFirstLyapunov() was called,
  // else the Problem default (not computed).
  LyapunovCoefficient FirstLyapunov(const Vector& u, double lambda,
                                    std::complex<double> critical) override {
    if (!first_lyapunov_) return Problem::FirstLyapunov(u, lambda, critical);
    return FirstLyapunovCoefficient(*this, u, lambda, 1e-3, critical);
  }
  void EnableFirstLyapunov() { first_lyapunov_ = true; }

  bool HasSecondParameter() const override { return has_eta_; }
  double SecondParameter() const override { return eta_; }
  void SetSecondParameter(double eta) override { eta_ = eta; }

  std::vector<std::string> MeasureNames() const override { return measure_names_; }
  Vector Measures(const Vector& u, double lambda) override {
    return measures_ ? measures_(u, lambda) : Vector();
  }

  // Configuration.
  void SetScales(Vector scale, double lambda_scale, Vector residual_scale) {
    scale_ = std::move(scale);
    lambda_scale_ = lambda_scale;
    residual_scale_ = std::move(residual_scale);
  }
  void SetStability(StabilityFn stability) { stability_ = std::move(stability); }
  // Stability: the eigenvalues of the analytic Jacobian (equilibria of u' = F(u, λ)).
  void SetStabilityFromJacobian() {
    stability_ = [jacobian = jacobian_, n = n_](const Vector& u, double lambda, double eta) {
      Matrix J(n, n);
      jacobian(u, lambda, eta, J);
      return EigenvaluesOf(J);
    };
  }
  void EnableSecondParameter(double eta) {
    has_eta_ = true;
    eta_ = eta;
  }
  void SetMeasures(std::vector<std::string> names,
                   std::function<Vector(const Vector&, double)> measures) {
    measure_names_ = std::move(names);
    measures_ = std::move(measures);
  }

 private:
  Index n_;
  ResidualFn residual_;
  JacobianFn jacobian_;
  DfDlambdaFn dfdlambda_;
  StabilityFn stability_;
  Vector scale_;
  double lambda_scale_ = 1.0;
  Vector residual_scale_;
  bool has_eta_ = false;
  bool first_lyapunov_ = false;
  double eta_ = 0.0;
  std::vector<std::string> measure_names_;
  std::function<Vector(const Vector&, double)> measures_;
};

inline Vector Vec(std::initializer_list<double> values) {
  Vector v(static_cast<Index>(values.size()));
  Index i = 0;
  for (double x : values) v(i++) = x;
  return v;
}

}  // namespace testing
}  // namespace rubcont
