// The equilibria of an OdeSystem as a continuation problem: F(x, λ) = f(0, x; λ), the parameter the
// system's own (OdeSystem::SetParameter). Used to continue equilibria and locate their Hopf points
// (shooting/hopf_orbits.h), and as the field whose Hopf point's Lyapunov coefficient is computed
// (continuation/lyapunov.h; the rotating waves' co-rotating field, waves/rotating_wave.cpp).
#pragma once

#include "continuation/problem.h"
#include "solvers/ode_system.h"

namespace rubcont {

// F(x, λ) = f(0, x; λ) of an autonomous system; stability = eigenvalues of ∂f/∂x.
class EquilibriumProblem : public Problem {
 public:
  // The system must outlive the problem; it must be autonomous (ForcingPeriod() = 0).
  explicit EquilibriumProblem(OdeSystem& system);
  Index Dimension() const override { return system_.Dimension(); }
  void Residual(const Vector& u, double lambda, Vector& F) override;
  void Jacobian(const Vector& u, double lambda, Matrix& J) override;
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override;
  Vector Scale() const override { return system_.StateScale(); }
  Vector ResidualScale() const override { return system_.StateScale(); }
  double LambdaScale() const override { return lambda_scale_; }
  bool HasStability() const override { return true; }
  Spectrum Stability(const Vector& u, double lambda) override;
  // FirstLyapunovCoefficient (continuation/lyapunov.h) with its default step.
  LyapunovCoefficient FirstLyapunov(const Vector& u, double lambda,
                                    std::complex<double> critical) override;

 private:
  OdeSystem& system_;
  double lambda_scale_;
};

}  // namespace rubcont
