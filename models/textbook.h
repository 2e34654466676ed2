// Textbook systems with known answers, for checking integration, shooting, Floquet stability and
// (later) continuation against closed forms or independent computations:
//   DuffingOscillator     ẍ + c ẋ + k x + β x³ = F cos(w t)      parameter w  (forced, period 2π/w)
//   StuartLandauOscillator ż = (λ + iω) z − (1 + iγ)|z|² z        parameter λ  (Hopf normal form)
//   VanDerPolOscillator   ẍ − μ (1 − x²) ẋ + x = 0               parameter μ  (stiff for large μ)
//   ForcedVanDerPolOscillator ẍ − μ (1 − x²) ẋ + x = F cos(w t)  parameter w  (entrainment, tori)
//   LorenzSystem          ẋ = σ(y − x), ẏ = x(ρ − z) − y, ż = xy − βz   parameter ρ  (chaos)
//   SoftImpactOscillator  ẍ + c ẋ + x + k max(0, x − g) = F cos(w t)   parameter w  (grazing)
//   AutonomousSoftImpactOscillator  the same, forced by a limit cycle   (grazing, autonomous)
// All are dimensionless; "time" below means the model's time unit.
#pragma once

#include <vector>

#include "solvers/ode_system.h"

namespace rubcont {

struct DuffingParams {
  double damping = 0.05;   // c > 0, viscous damping coefficient (1/time)
  double stiffness = 1.0;  // k, linear stiffness (1/time²); natural frequency √k
  double cubic = 1.0;      // β, cubic stiffness (hardening for β > 0) (1/(time²·length²))
  double force = 0.3;      // F, forcing amplitude (length/time²)
  double frequency = 1.4;  // w > 0, forcing frequency (rad/time): the continuation parameter
};

// Throws std::invalid_argument naming the field (non-finite values, damping < 0, frequency ≤ 0).
void Validate(const DuffingParams& params);

// State (x, ẋ). ForcingPeriod() = 2π/w.
class DuffingOscillator : public OdeSystem {
 public:
  explicit DuffingOscillator(const DuffingParams& params = {});
  const DuffingParams& params() const { return params_; }

  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.frequency; }
  void SetParameter(double w) override { params_.frequency = w; }
  // ∂f/∂w = (0, −F t sin(w t)).
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  double ForcingPeriod() const override;
  std::string StateName(Index i) const override { return i == 0 ? "x" : "v"; }

 private:
  DuffingParams params_;
};

struct StuartLandauParams {
  double lambda = 0.5;  // λ, linear growth rate: the continuation parameter (Hopf point at λ = 0)
  double omega = 1.0;   // ω, linear frequency (rad/time)
  double gamma = 0.0;   // γ, amplitude–frequency coupling ("shear")
};

// Throws std::invalid_argument naming a non-finite field.
void Validate(const StuartLandauParams& params);

// State (x, y) = (Re z, Im z):
//   ẋ = λ x − ω y − r² (x − γ y),   ẏ = ω x + λ y − r² (γ x + y),   r² = x² + y².
// For λ > 0 the periodic orbit is the circle r = √λ traversed at angular velocity ω − γλ
// (period T = 2π/|ω − γλ|); its Floquet multipliers are 1 (phase) and e^{−2λT} (the radial
// exponent: d/dr (λr − r³) = −2λ at r² = λ). It is stable for λ > 0 and, being a rotating wave of
// the SO(2) symmetry z → e^{iφ} z, it is declared here with that symmetry.
class StuartLandauOscillator : public OdeSystem {
 public:
  explicit StuartLandauOscillator(const StuartLandauParams& params = {});
  const StuartLandauParams& params() const { return params_; }

  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.lambda; }
  void SetParameter(double lambda) override { params_.lambda = lambda; }
  // ∂f/∂λ = (x, y).
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;

  bool HasRotationSymmetry() const override { return true; }
  // (x, y) ← rotation by φ counter-clockwise (z ← e^{iφ} z).
  void Rotate(double phi, VectorRef x) const override;
  // g = (−y, x).
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override;

  // Closed forms of the periodic orbit at the current λ (> 0).
  double OrbitRadius() const;          // √λ
  double AngularVelocity() const;      // ω − γλ
  double Period() const;               // 2π / |ω − γλ|
  double NontrivialMultiplier() const; // e^{−2λT}

 private:
  StuartLandauParams params_;
};

struct VanDerPolParams {
  // μ, nonlinear damping: the continuation parameter. μ > 0: an attracting limit cycle (relaxation
  // oscillation for μ ≫ 1); μ < 0 is the same system in reversed time, whose cycle (the μ > 0 cycle
  // run backwards, same period) repels with multiplier e^{+|log μ₂|}: a test of unstable orbits.
  double mu = 1.0;
};

// Throws std::invalid_argument (μ not finite).
void Validate(const VanDerPolParams& params);

// State (x, ẋ). The limit cycle has amplitude ≈ 2 and period ≈ (3 − 2 ln 2) μ for μ ≫ 1, with
// |ẋ| up to about 4μ/3 during the fast jumps; StateScale() is (2, max(2, 4|μ|/3)) accordingly.
// Liouville: the nontrivial multiplier is exp ∮ μ (1 − x²) dt (≈ e^{−2.886 μ²} for μ ≫ 1).
class VanDerPolOscillator : public OdeSystem {
 public:
  explicit VanDerPolOscillator(const VanDerPolParams& params = {});
  const VanDerPolParams& params() const { return params_; }

  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.mu; }
  void SetParameter(double mu) override { params_.mu = mu; }
  // ∂f/∂μ = (0, (1 − x²) ẋ).
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  Vector StateScale() const override;
  std::string StateName(Index i) const override { return i == 0 ? "x" : "v"; }

 private:
  VanDerPolParams params_;
};

struct ForcedVanDerPolParams {
  double mu = 0.2;         // μ, nonlinear damping (the free cycle: amplitude ≈ 2, frequency ≈ 1)
  double force = 0.1;      // F, forcing amplitude (length/time²)
  double frequency = 1.0;  // w > 0, forcing frequency (rad/time): the continuation parameter
};

// Throws std::invalid_argument naming the field (non-finite values, frequency ≤ 0).
void Validate(const ForcedVanDerPolParams& params);

// State (x, ẋ); ForcingPeriod() = 2π/w. Near w = 1 the free cycle locks to the forcing (1:1
// entrainment: a periodic orbit of period 2π/w); at the edges of the locking interval a pair of
// Floquet multipliers leaves the unit circle (Neimark–Sacker) or the locked orbit meets a saddle
// (fold), and outside it the response is quasi-periodic: an invariant torus, which no periodic
// orbit describes. A small model of the two-frequency motion of the rub's modulated whips.
class ForcedVanDerPolOscillator : public OdeSystem {
 public:
  explicit ForcedVanDerPolOscillator(const ForcedVanDerPolParams& params = {});
  const ForcedVanDerPolParams& params() const { return params_; }

  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.frequency; }
  void SetParameter(double w) override { params_.frequency = w; }
  // ∂f/∂w = (0, −F t sin(w t)).
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  double ForcingPeriod() const override;
  Vector StateScale() const override;
  std::string StateName(Index i) const override { return i == 0 ? "x" : "v"; }

 private:
  ForcedVanDerPolParams params_;
};

struct LorenzParams {
  double sigma = 10.0;
  double rho = 28.0;          // the parameter
  double beta = 8.0 / 3.0;
};

// Throws std::invalid_argument naming a non-finite field.
void Validate(const LorenzParams& params);

// State (x, y, z). At the classic (10, 28, 8/3) the attractor is chaotic with Lyapunov exponents
// 0.9056, 0, −14.5723 (Sprott, Chaos and Time-Series Analysis, 2003, Table A.1); their sum is the
// constant trace −(σ + 1 + β) = −13.6667 for every trajectory. StateScale() is (10, 10, 20), the
// attractor's size.
class LorenzSystem : public OdeSystem {
 public:
  explicit LorenzSystem(const LorenzParams& params = {});
  Index Dimension() const override { return 3; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.rho; }
  void SetParameter(double rho) override { params_.rho = rho; }
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;  // (0, x, 0)
  Vector StateScale() const override;

 private:
  LorenzParams params_;
};

struct SoftImpactParams {
  double damping = 0.1;     // c ≥ 0 (1/time); the free natural frequency is 1
  double stiffness = 10.0;  // k ≥ 0, of the one-sided spring (the stop), per unit mass (1/time²)
  double gap = 1.0;         // g > 0, the stop's distance from the rest position (length)
  double force = 0.5;       // F, forcing amplitude (length/time²)
  double frequency = 0.5;   // w > 0, forcing frequency (rad/time): the continuation parameter
};

// Throws std::invalid_argument naming the field (non-finite values, damping or stiffness < 0,
// gap or frequency ≤ 0).
void Validate(const SoftImpactParams& params);

// The impacting (soft-stop) oscillator, a one-degree-of-freedom model of a rotor that reaches its
// stator: ẍ + c ẋ + x + k max(0, x − g) = F cos(w t). State (x, ẋ); ForcingPeriod() = 2π/w. The
// vector field is continuous at the stop x = g with a jump k in its derivative, like the rub's
// linear contact spring. While the motion stays off the stop it is the linear response
// x = a cos(w t − ψ), a = F / √((1 − w²)² + (c w)²), so the periodic orbit grazes the stop where
// a(w) = g: w² the roots of s² − (2 − c²) s + 1 − (F/g)² = 0 (FreeAmplitude, GrazingFrequencies).
class SoftImpactOscillator : public OdeSystem {
 public:
  explicit SoftImpactOscillator(const SoftImpactParams& params = {});
  const SoftImpactParams& params() const { return params_; }

  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.frequency; }
  void SetParameter(double w) override { params_.frequency = w; }
  // ∂f/∂w = (0, −F t sin(w t)).
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  double ForcingPeriod() const override;
  Vector StateScale() const override;  // (g, g)
  // h = x − g, the stop's penetration.
  int SwitchingCount() const override { return 1; }
  void SwitchingFunctions(double t, ConstVectorRef x, VectorRef h) const override;
  std::string StateName(Index i) const override { return i == 0 ? "x" : "v"; }

  // The amplitude a(w) of the linear response at the current w.
  double FreeAmplitude() const;
  // (x, ẋ) at t = 0 of the linear response x = (F/D) cos(w t − ψ), D = √((1 − w²)² + (c w)²),
  // tan ψ = c w / (1 − w²): the periodic orbit's start while it stays off the stop.
  Vector FreeState() const;
  // The forcing frequencies at which the linear response grazes the stop, ascending: none when
  // F/g is below the response's smallest gain, else one or two.
  std::vector<double> GrazingFrequencies() const;

 private:
  SoftImpactParams params_;
};

// The soft impact oscillator made autonomous: the forcing F p comes from a stable limit cycle
// ṗ = p(1 − p² − q²) − w q, q̇ = q(1 − p² − q²) + w p, on which p = cos(w t + θ). State
// (x, v, p, q); its periodic orbits are SoftImpactOscillator's shifted by θ/w, with period 2π/w
// (kAutonomous shooting, for what needs an autonomous system: segment boundaries on the stop,
// ShootingOptions::event_boundaries). Switching function h = x − g; StateScale (g, g, 1, 1).
class AutonomousSoftImpactOscillator : public OdeSystem {
 public:
  explicit AutonomousSoftImpactOscillator(const SoftImpactParams& params = {});
  const SoftImpactParams& params() const { return params_; }

  Index Dimension() const override { return 4; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return params_.frequency; }
  void SetParameter(double w) override { params_.frequency = w; }
  Vector StateScale() const override;
  int SwitchingCount() const override { return 1; }
  void SwitchingFunctions(double t, ConstVectorRef x, VectorRef h) const override;
  std::string StateName(Index i) const override;

 private:
  SoftImpactParams params_;
};

// ---------------------------------------------------------------------------------------------
// The first orbit of each model's "orbits" stage: where a transient starts and how long it runs to
// settle onto the attracting orbit at the model's current parameter (shooting/orbit_branches.h's
// SettleForced and SettleOnCycle run it; tests/models/textbook_test.cpp checks each against the
// closed form where there is one). The closed forms themselves are the oscillators' (Stuart–Landau:
// OrbitRadius, Period, NontrivialMultiplier; soft impact: FreeState).

// A forced system's start: the state at forcing phase 0, and the forcing periods to settle over.
struct ForcedStart {
  Vector x0;
  int periods = 0;
};
// An autonomous system's start: a state, and the time to settle over (model time units).
struct CycleStart {
  Vector x0;
  double duration = 0.0;
};

// Duffing at w = params.frequency: the linear response x = A cos(w t − ψ), A = F/√((k − w²)² +
// (c w)²), tan ψ = c w/(k − w²) (the periodic orbit itself when β = 0), settled for about 20/c time
// units (at most 2000 forcing periods; none without damping).
ForcedStart DuffingStart(const DuffingParams& params);
// Stuart–Landau at λ = params.lambda > 0, from (1, 0): the radius relaxes at rate 2λ and the phase
// turns at about ω, so 20/λ time units and 40 turns.
CycleStart StuartLandauStart(const StuartLandauParams& params);
// Van der Pol at μ = params.mu > 0, from (2, 0), the cycle's amplitude: its period is ≈ 2π for
// small μ and ≈ (3 − 2 ln 2) μ for large μ; it attracts within a few periods for μ ≳ 1 and at
// rate ≈ μ for small μ, so 40 periods and 20/μ time units.
CycleStart VanDerPolStart(const VanDerPolParams& params);
// Forced van der Pol at w = params.frequency, from the free cycle's amplitude (2, 0), settled for
// about 40/μ time units (at most 2000 forcing periods). A locked response's phase relaxes more
// slowly than that suggests (at about F/(2r): at μ = 0.2, F = 0.1, w = 1 its 32 periods bring the
// start 70 times closer to the locked orbit), close enough for the shooting's Newton.
ForcedStart ForcedVanDerPolStart(const ForcedVanDerPolParams& params);

}  // namespace rubcont
