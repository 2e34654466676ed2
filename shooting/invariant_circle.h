// Quasi-periodic motion on a 2-torus, as an invariant circle of the stroboscopic map (Schilder,
// Osinga & Vogt 2005, SIAM J. Appl. Dyn. Syst. 4: "Continuation of quasi-periodic invariant tori"),
// a continuation problem F(u, λ) = 0 (continuation/problem.h). First step of the tori (issue 16):
// forced systems ẋ = f(t, x), f T-periodic in t (T = OdeSystem::ForcingPeriod() at λ), whose map
// P(x) = x(T; 0, x) carries a 2-torus of the flow into itself as a closed curve.
//
// The circle u(θ), θ ∈ [0, 2π), is a truncated Fourier series with K harmonics,
//     u(θ) = a₀ + Σ_{k=1..K} (a_k cos kθ + b_k sin kθ)        (a_k, b_k ∈ Rⁿ),
// and invariance means that P moves it along itself by a rigid rotation ρ (the rotation number):
//     P(u(θ)) = u(θ + 2πρ),
// collocated at the N = 2K + 1 points θ_j = 2πj/N. The circle is only defined up to θ ↦ θ + c: one
// phase condition fixes that, the scaled mean of ⟨u(θ_j) − u_ref(θ_j), u_ref′(θ_j)⟩ over j (AUTO's
// integral condition on the circle). Unknowns u = [a₀, a₁, b₁, …, a_K, b_K, ρ] (n(2K + 1) + 1);
// equations: n N + 1. Why Fourier points rather than a 2-D collocation: the map is integrated by
// the same error-controlled integrators as the orbits (N independent trajectories of one forcing
// period, with sensitivities), the circle of a smooth torus converges spectrally in K, and the
// growth of the last harmonic measures the loss of smoothness that precedes breakdown.
//
// Where ρ is rational (phase locking) no rigid rotation conjugates the map on the circle and the
// Fourier series stops converging: measure "fourier_tail" (the last harmonic's size against the
// largest) grows; "invariance_error" is the defect |P(u(θ)) − u(θ + 2πρ)| (scaled) half-way
// between the collocation points.
//
// Stability, two ways. (1) CircleMultipliers: the linearized map carries a perturbation v of the
// circle to w(θ + 2πρ) = ∂P(u(θ)) v(θ); in Fourier coefficients that is Λ = Ê⁻¹ diag(M_j) E (E, Ê:
// the basis at θ_j and at θ_j + 2πρ; M_j the monodromy of point j). For a torus whose linearization
// is reducible its eigenvalues come in clusters of 2K + 1 of one modulus (1 along the circle, the
// normal multipliers across it), but the pair of each cluster that belongs to the last harmonic is
// polluted by the truncation (measured: 0.96–0.998 instead of 1 on the clocked Stuart–Landau
// torus, 1.003 on the forced van der Pol one) and the clusters of a non-reducible torus spread
// (0.46–0.68 for that van der Pol torus): a diagnostic, not a verdict. (2) Lyapunov: the exponents
// of the map along an orbit on the circle, by QR of the tangent maps (Benettin et al. 1980), the one
// nearest 0 the tangent's, whose distance from 0 states the estimate's accuracy: the verdict.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "continuation/problem.h"
#include "solvers/ode.h"

namespace rubcont {

class InvariantCircleProblem : public Problem {
 public:
  // `system` must be forced (ForcingPeriod() > 0 at its parameter); K ≥ 1 harmonics.
  InvariantCircleProblem(std::shared_ptr<OdeSystem> system, int harmonics,
                         const IntegratorOptions& options = {});

  int harmonics() const { return harmonics_; }
  Index states() const { return n_; }

  // Unknowns from coefficients (n × (2K + 1): columns a₀, a₁, b₁, …) and ρ.
  Vector Pack(const Matrix& coefficients, double rho) const;
  Matrix Coefficients(const Vector& u) const;
  double RotationNumber(const Vector& u) const { return u(u.size() - 1); }
  // u(θ) for the circle held in u.
  Vector PointAt(const Vector& u, double theta) const;

  // The phase condition's reference circle (its coefficients are taken from u). Set at the
  // start; PointAccepted moves it to every accepted point.
  void SetPhaseReference(const Vector& u);

  // The event "circle breaks down": the Fourier tail (measure "fourier_tail") reaches this. Past
  // it the collocation equations still have solutions, but they are no invariant circles
  // (measured on the forced van der Pol torus continued into 1:1 locking: the tail grows from
  // 1e-10 to 0.13 and the invariance error between the points to 0.3); the branch ends there with
  // the event as its reason. Default 1e-6.
  void SetMaxFourierTail(double tail);

  Index Dimension() const override;
  void Residual(const Vector& u, double lambda, Vector& F) override;
  void Jacobian(const Vector& u, double lambda, Matrix& J) override;
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override;
  Vector Scale() const override;
  double LambdaScale() const override;
  Vector ResidualScale() const override;
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& u, double lambda) override;
  void PointAccepted(const Vector& u, double lambda) override;
  std::vector<std::string> EventNames() const override;
  Vector EventFunctions(const Vector& u, double lambda) override;

  // The moduli of Λ's eigenvalues, largest first (see above); empty when an integration failed.
  std::vector<double> CircleMultipliers(const Vector& u, double lambda);

  // Lyapunov exponents of the map (per forcing period), largest first, from `iterates` steps of
  // the orbit of u(0) with QR of the tangent maps. `tangent` indexes the one nearest 0 (along the
  // circle); stable when every other is below −tolerance, tolerance = max(10 |tangent exponent|,
  // 1e-6): the tangent exponent's distance from its exact 0 is the estimate's error.
  struct TorusStability {
    bool valid = false;          // an integration failed
    Vector exponents;            // n, per forcing period
    Index tangent = 0;
    double tolerance = 0.0;
    bool stable = false;
  };
  TorusStability LyapunovStability(const Vector& u, double lambda, int iterates = 200);

  // The defect max_j |P(u(ϑ_j)) − u(ϑ_j + 2πρ)| ./ scale at ϑ_j = θ_j + π/N.
  double InvarianceError(const Vector& u, double lambda);

  // A first circle from points of one orbit of the map, x_{k+1} = P(x_k) (n × m, m ≥ 2K + 2),
  // lying on a circle that winds once around its centroid in the plane of its two leading
  // principal directions: each point's angle there gives θ_k, ρ is the mean angle advance per
  // iterate (in [0, 1); the plane's orientation decides between ρ and 1 − ρ, the same torus
  // traversed the other way), and the coefficients are fitted by least squares in θ. Throws
  // std::invalid_argument when the points do not wind (a locked or non-circular set).
  Vector CircleFromOrbit(const Matrix& points) const;

 private:
  struct Integrated {
    bool ok = false;
    Matrix ends;                  // n × N: P(u(θ_j))
    std::vector<Matrix> stms;     // M_j (with sensitivities)
    Matrix dpdp;                  // n × N: ∂P/∂λ (with sensitivities)
  };
  // The collocation point θ_j = 2πj/N.
  double Node(Index j) const;
  // Basis row [1, cos θ, sin θ, …, cos Kθ, sin Kθ] and its θ-derivative.
  Vector Basis(double theta) const;
  Vector BasisDerivative(double theta) const;
  double FourierTail(const Vector& u) const;
  // The phase condition Σ_j ⟨w_j, u(θ_j) − u_ref(θ_j)⟩: w_j = u_ref′(θ_j) ./ scale² over the RMS of
  // u_ref′ ./ scale (n × N).
  Matrix PhaseWeights() const;
  const Integrated& Integrate(const Vector& u, double lambda, bool sensitivities);
  double PeriodAt(double lambda);

  std::shared_ptr<OdeSystem> system_;
  int harmonics_;
  Index n_;
  Index points_;  // N = 2K + 1
  IntegratorOptions options_;
  Vector scale_;  // the system's state scale
  Matrix reference_;  // n × (2K + 1)
  double max_tail_ = 1e-6;
  Vector cached_u_;
  double cached_lambda_ = 0.0;
  bool cached_sensitivities_ = false;
  Integrated cached_;
};

}  // namespace rubcont
