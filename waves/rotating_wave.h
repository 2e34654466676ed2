// Rotating waves (relative equilibria) of a rub structure: circular backward whirl and whip.
//
// In the frame precessing backwards at Ω, u = e^{−jΩt} p, a circular orbit is an equilibrium
// p = const (docs/theory.md §6):
//     (K − Ω²M − jΩC) p = Σ_k B_k f_k(d_k, ḋ_k = −jΩ d_k; ω),
// 2 n_c real equations in the 2 n_c real unknowns of p and the unknown Ω, closed by a phase
// condition that removes the rotational symmetry: Im(Σ_k conj(d_ref,k) d_k) = 0 with the contact
// displacements d_ref of a reference solution (the start of the branch).
//
// Friction, per FrictionLawKind:
//  - kTanh: F = μN tanh(V/ε); unknowns u = [p, Ω]. Smooth while every contact stays touching or
//    free: contact loss and regain are events (margins δ_k and −δ_k; a free contact exerts no
//    force even where a trial point penetrates), because the normal force's kink at δ = 0 stalled
//    Newton (case A(a)'s one-contact whirls ended in corrector failures at 52.36 rpm, where the other
//    contact touches). The modes of touching contacts are slip±, by the side V points to.
//  - kExact: exact Coulomb, piecewise smooth. Each contact has a mode and an extra unknown F_k:
//      free  (no contact, δ < 0):        F_k = 0
//      stick (rolling, V = 0):           V_k = ωR_k − Ω|d_k| = 0, F_k free, valid while |F_k| ≤ μN_k
//      slip± (sliding, sgn V = ±1):      F_k = ±μN_k, valid while ±V_k > 0
//    unknowns u = [p, Ω, F_1..F_m]. When several contacts stick, the first one's closure is
//    V = 0 and the others' are V_k − V_first = 0, scaled by Ω·(force/k1): with rigid contacts
//    rolling at two contacts of equal RCI leaves the phase between them free, and only the
//    penetrations (~1e-8 m) fix it, so the raw closures V_k = 0 would be nearly parallel rows
//    (condition ~1e9) while their differences are well scaled.
//    The validity margins are the problem's event functions; at a
//    zero the continuation engine calls SwitchAt and the contact changes mode (stick ↔ slip,
//    contact loss / regain), so the whirl → whip transition is found without regularization.
//    Contacts in the same mode whose same margin vanishes at the event too (a symmetric rotor's
//    two contacts reach μ together) switch with it: one event, both contacts.
// The continuation parameter λ is the running speed ω [rad/s].
//
// Stability: eigenvalues of the 4 n_c × 4 n_c rotating-frame Jacobian at ṗ = 0, with the zero
// eigenvalue of the rotational symmetry deflated exactly (its eigenvector j p is known). For
// sticking contacts (exact law) the rolling condition V_k = 0 is a constraint on the motion with F_k
// its multiplier; the spectrum is that of the constrained linearization, y' = (I − G(HG)⁻¹H)A y on
// {H y = 0} (H = ∂V/∂y of the sticking contacts, G = ∂ẏ/∂F).
#pragma once

#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/lyapunov.h"
#include "continuation/problem.h"
#include "models/rub_model.h"
#include "solvers/newton.h"

namespace rubcont {

enum class ContactMode { kFree, kStick, kSlipPositive, kSlipNegative };

const char* ToString(ContactMode mode);

class RotatingWaveProblem : public Problem {
 public:
  RotatingWaveProblem(RubStructure structure, FrictionLawKind law);

  Index Dimension() const override;
  void Residual(const Vector& u, double omega, Vector& F) override;
  void Jacobian(const Vector& u, double omega, Matrix& J) override;
  void DfDlambda(const Vector& u, double omega, Vector& dF) override;
  Vector Scale() const override;
  double LambdaScale() const override { return speed_scale_; }
  Vector ResidualScale() const override;

  bool HasStability() const override { return true; }
  Spectrum Stability(const Vector& u, double omega) override;
  // 0.1 s⁻¹ (e-folding time 10 s, about 7 dwells of a thesis sweep of 1.5 s). With two contacts
  // rolling, rigid contacts would leave the phase between them free; compliance lets it drift at a
  // rate Ω ∂(N_R − N_L)/∂θ / (k1 C), of either sign, and any regularization of friction
  // (micro-slip) turns it strongly stable. Such modes are marginal, not instabilities an engineer
  // could observe. Measured over every branch point of the ten two-point scenes
  // (docs/studies/rotating_waves.md): the positive growth rates are either ≤ 0.010 s⁻¹ (this drift)
  // or ≥ 5.19 s⁻¹ (the 1.65 Hz whips of A(a), A(b)); the tolerance sits in that gap, 10× and 50×
  // from its edges (tests/waves/rotating_wave_branches_test.cpp checks the gap on A(a) and A(b)).
  double StabilityTolerance() const override { return 1e-1; }

  // precession_hz, normal_phase_deg (arg d_R / d_L), and per contact <name>:
  // normal_force_, friction_force_, slip_velocity_, penetration_, mu_ratio_, mode_
  // (mode code: 0 free, 1 stick, 2 slip+, 3 slip−; the regularized law reports 2/3 by sgn V).
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& u, double omega) override;

  std::vector<std::string> EventNames() const override;
  Vector EventFunctions(const Vector& u, double omega) override;
  bool SwitchAt(int event, Vector& u, double omega) override;
  std::string PieceLabel() const override;
  // Regularized law only: "<contact> knee", dΩ/dω / (R_k/C_k) − ½ per contact, located where it
  // changes sign. On a rolling whirl dΩ/dω = R/C, on a whip ≈ 0: the knee's midpoint is the smooth
  // counterpart of the exact law's stick → slip event and converges to it as ε → 0
  // (docs/studies/rotating_waves.md). (A fixed slip V = cε would not: there tanh = tanh(c), and the
  // point converges to the closed form's μ_req = tanh(c)·μ crossing instead, −0.8 % for c = 1.)
  std::vector<std::string> TestFunctionNames() const override;
  Vector TestFunctions(const Vector& u, double omega) override;
  // Moves the phase reference to the accepted point (the condition stays satisfied there), so
  // that it stays well posed however far the branch deforms the orbit.
  void PointAccepted(const Vector& u, double omega) override;

  // Unknowns from a rigid-contact circular orbit (SolveRigidContactOrbit, or the analytic Mode 1/2
  // solution): p = u0 with each touching rotor coordinate moved out by δ_k = N_k/k1, Ω, and
  // F_k = Im P_k (0 for free contacts). Also makes its contact displacements the phase reference.
  Vector FromRigidContactOrbit(const RigidContactOrbit& orbit);
  // Sets the phase reference from the contact displacements of u.
  void SetPhaseReference(const Vector& u);

  // The first Lyapunov coefficient at a Hopf point of a tanh-law branch: of the co-rotating
  // field at the point's Ω and ω, on the slice of the rotation group (continuation/lyapunov.h),
  // with finite-difference steps 1e-4 and 1e-5 of the state scale; negative: the modulated waves
  // born there are stable (supercritical). The exact law is not smooth (a sticking contact is a
  // constraint, slip a switch of the force law): not valid there, with that reason.
  LyapunovCoefficient FirstLyapunov(const Vector& u, double omega,
                                    std::complex<double> critical) override;

  // Solves F(u, ω) = 0 by Newton, then checks every contact's validity margin; while one is
  // violated, switches that contact's mode and solves again (an active-set iteration, at most 2
  // rounds per contact; the regularized law's margins are its contact events). Returns the final
  // Newton result; `consistent` tells whether all margins hold.
  struct StartResult {
    NewtonResult newton;
    bool consistent = false;
    int mode_changes = 0;
  };
  StartResult SolveConsistent(Vector& u, double omega, const NewtonOptions& options = {});

  // Replaces the structure's parameters (masses, stiffness, damping, contact law and geometry) for
  // design and identification studies (waves/rotating_wave_parameters.h), keeping the contact
  // modes, the phase reference and the scales: the scales describe typical magnitudes and stay
  // fixed so that a two-parameter continuation sees one scaled problem. Throws
  // std::invalid_argument when the new structure is invalid or has other coordinates or contacts.
  void SetStructure(RubStructure structure);

  void SetModes(const std::vector<ContactMode>& modes);
  const std::vector<ContactMode>& modes() const { return modes_; }
  FrictionLawKind law() const { return law_; }
  const RubStructure& structure() const { return structure_; }
  Index Contacts() const { return static_cast<Index>(structure_.contacts.size()); }

  // Readable pieces of u.
  double Precession(const Vector& u) const { return u(2 * structure_.Coordinates()); }
  std::vector<ContactEvaluation> EvaluateContacts(const Vector& u, double omega);

 private:
  // Contact forces at the rotating-wave state (q = p, v = −Ω j p) in the current modes.
  void Evaluate(const Vector& u, double omega, bool with_derivatives);
  std::vector<FrictionMode> FrictionModes() const;
  // The first sticking contact (exact law), or −1.
  Index ReferenceStick() const;
  // Validity margin of contact k, index i ∈ {0, 1, 2} (see EventNames()).
  double Margin(Index k, int i) const;
  // Changes contact k's mode across its margin i (forces_ evaluated at u); false if that margin
  // does not switch anything.
  bool SwitchContact(Index k, int i, Vector& u);

  RubStructure structure_;
  FrictionLawKind law_;
  std::vector<ContactMode> modes_;
  RubRotatingFrame frame_;      // for the stability operator
  Matrix mass_, damping_, stiffness_;  // kron(·, I₂)
  Vector phase_reference_;      // reference contact displacements (2 per contact), unit norm
  double position_scale_ = 0.0;
  double rate_scale_ = 0.0;     // typical Ω [rad/s]
  double force_scale_ = 0.0;    // typical contact force [N]
  double speed_scale_ = 0.0;    // typical ω [rad/s]
  ContactForces forces_;        // workspace from the last Evaluate
  Vector velocity_;             // v = −Ω j p
};

// Contact modes of the piece a special point was found on, from its measures mode_<contact> (the
// regularized law's touching contacts come back as slip±, which it reads as "in contact").
std::vector<ContactMode> ModesAt(const Branch& branch, const SpecialPoint& point, Index contacts);

}  // namespace rubcont
