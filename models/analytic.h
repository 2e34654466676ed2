// Level L0: the closed-form Mode 1 / Mode 2 circular orbits of the two-point rub model
// (Kumar 2010, §2.2–2.5, with the corrections of docs/theory.md §3), and the natural frequencies that
// organise them.
//
// A circular backward orbit precesses at Ω > 0: every displacement is u(t) = u0·e^{−jΩt}. Both
// contacts touch (|d_k| = C_k), and the contact normals are in phase (Mode 1, s = +1) or in
// antiphase (Mode 2, s = −1): d0 = S·C with S = diag(1, s), C = (C_L, C_R)ᵀ. With
//
//   Z(Ω) = K_s − Ω² M_s − jΩ C_s                   (stator dynamic stiffness, 2 × 2)
//   W(Ω) = M_r⁻¹ / Ω² − Z(Ω)⁻¹                     (relative receptance at the contacts)
//   f_d  = jΩ c_d w wᵀ d0,  w = (½, ½)ᵀ             (centre damper force on the rotor, amplitude)
//
// the rotor and stator equations of motion
//
//   −Ω² M_r r0 = −S P + f_d,      Z s0 = S P − f_d,      r0 − s0 = d0
//
// give the complex contact forces P_k = N_k + j F_k (normal force N pushes the rotor inward,
// friction F > 0 drives backward precession; force on the rotor f_k = −P_k n_k):
//
//   S P = W⁻¹ d0 + f_d,     i.e.  P = S W⁻¹ S C + S f_d,
//
// and the required friction coefficient μ_req,k = F_k / N_k. With c_d = 0 this is exactly the
// thesis's Eq. (26) / (42) (P = S W⁻¹ S C). Because d0 is real, f_d is purely imaginary: the
// damper changes the friction force only, ΔF_k = s_k Ω c_d (wᵀ d0) / 2, never N. The damper term
// vanishes in Mode 2 when C_L = C_R (wᵀ d0 = 0: the mid-point does not move relative to the stator).
//
// Reading the curve: contact needs N_k > 0; rolling without slipping at contact k needs
// 0 ≤ μ_req,k ≤ μ. Where N_k changes sign μ_req has a pole (±∞): such points are contact-loss
// boundaries, not transitions of μ, and are reported as such. Whip (slipping at precession locked
// near a coupled frequency) sits where μ_req = μ.
//
// Unequal radius-to-clearance ratios (RCI_L ≠ RCI_R). The forces above are exact for a circular
// Mode 1/2 orbit at Ω with any clearances. But rolling at contact k means Ω = RCI_k·ω, so rolling
// at both contacts needs RCI_L = RCI_R: with unequal RCIs at most one contact can roll and the
// other must slip, with μ_req = μ exactly at that contact. Moreover, a general circular orbit has a
// phase θ between the two contact normals other than 0 (Mode 1) or π (Mode 2); the closed form
// covers only those two. The rotating-wave level (L1, issue 4) finds the general ones; it starts
// from the amplitudes r0, s0 returned here.
//
// Units: SI inside (Ω in rad/s, forces in N, displacements in m); curve grids in Hz.
#pragma once

#include <array>
#include <complex>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "models/two_point_params.h"
#include "solvers/types.h"

namespace rubcont {

using Matrix2 = Eigen::Matrix2d;
using Vector2 = Eigen::Vector2d;
using ComplexVector2 = Eigen::Vector2cd;

// The two circular orbit families of the closed form.
enum class CircularMode {
  kMode1,          // contact normals in phase (s = +1): thesis §2.2
  kMode2,          // contact normals in antiphase (s = −1): thesis §2.4
  kSingleContact,  // one contact only (the Jeffcott rotor of models/jeffcott.h)
};

const char* ToString(CircularMode mode);  // "mode1" | "mode2" | "single"
// s of S = diag(1, s): +1 for Mode 1, −1 for Mode 2 (and for a single contact).
int ContactSign(CircularMode mode);

// Rotor mass matrix in the contact-plane coordinates u_r = (u_rL, u_rR) [kg]:
// M_r = m_r [[(1−a)², a(1−a)], [a(1−a), a²]] + (I_r / l²) [[1, −1], [−1, 1]], a = l_g / l.
// (The thesis prints +I/l² off the diagonal; −I/l² is correct: docs/theory.md §3.)
Matrix2 RotorMassMatrix(const TwoPointParams& p);
// Stator mass matrix in the station coordinates u_s = (u_sL, u_sR) [kg], same form with
// m_s, I_s, b = l_sg / l_s, l_s.
Matrix2 StatorMassMatrix(const TwoPointParams& p);
// K_s = diag(k_L, k_R) [N/m] and C_s = diag(c_L, c_R) [N·s/m].
Matrix2 SupportStiffnessMatrix(const TwoPointParams& p);
Matrix2 SupportDampingMatrix(const TwoPointParams& p);

// One undamped natural mode of a 2-DOF system K v = ω² M v.
struct NaturalMode {
  double frequency_hz = 0.0;  // ω / 2π [Hz]
  Vector2 shape;              // (v_L, v_R), scaled so that max |v| = 1 and the largest entry is > 0
};

// Undamped natural frequencies. Bounce and pitch are told apart by mode shape, not by ordering:
// bounce is the mode whose two stations move in phase (larger v_L·v_R / |v|²); by K-orthogonality
// the other one then moves in antiphase.
struct NaturalFrequencies {
  NaturalMode stator_bounce;  // stator alone on its supports: eig(M_s⁻¹ K_s)
  NaturalMode stator_pitch;
  NaturalMode pinned_bounce;  // rotor pinned to the stator at both contacts: eig((M_r + M_s)⁻¹ K_s)
  NaturalMode pinned_pitch;
};

// Throws std::invalid_argument (via Validate(p)) on non-physical parameters.
NaturalFrequencies ComputeNaturalFrequencies(const TwoPointParams& p);

// The circular orbit of one mode at one precession frequency Ω, all amplitudes relative to
// e^{−jΩt} with the left contact normal along +x at t = 0 (n_L = e^{−jΩt}, n_R = s·e^{−jΩt}).
struct CircularOrbit {
  double precession = 0.0;         // Ω [rad/s] > 0
  ComplexVector2 contact_force;    // P_k = N_k + j F_k [N]
  ComplexVector2 rotor_amplitude;  // r0 [m]: u_r(t) = r0·e^{−jΩt} at the contact planes
  ComplexVector2 stator_amplitude; // s0 [m]: u_s(t) = s0·e^{−jΩt} at the stator stations
  ComplexVector2 damper_force;     // f_d [N]: centre damper force on the rotor (generalized, L/R)

  double NormalForce(int k) const { return contact_force(k).real(); }    // N_k [N]
  double FrictionForce(int k) const { return contact_force(k).imag(); }  // F_k [N]
  double MuRequired(int k) const { return FrictionForce(k) / NormalForce(k); }  // μ_req,k [-]
};

// Throws std::invalid_argument on non-physical parameters or precession ≤ 0 / non-finite.
CircularOrbit SolveCircularOrbit(const TwoPointParams& p, CircularMode mode, double precession);

// What the curves are evaluated on: a uniform grid in precession frequency.
struct AnalyticOptions {
  double min_precession_hz = 1.0;    // lower end [Hz] > 0 (Ω = 0 is singular: M_r⁻¹/Ω²)
  double max_precession_hz = 200.0;  // upper end [Hz] > min_precession_hz
  int precession_points = 4000;      // grid points ≥ 2. Two transitions closer than the spacing
                                     // (max − min)/(points − 1) of the same kind may be missed.
};

// Throws std::invalid_argument naming the field, the value and the rule.
void Validate(const AnalyticOptions& options);

// A point where the character of a circular orbit family changes, located on the closed form.
enum class TransitionType {
  kMuCrossing,          // μ_req,k = +μ with N_k > 0: rolling ↔ slipping (whirl ↔ whip) boundary
  kNegativeMuCrossing,  // μ_req,k = −μ with N_k > 0: the other end of the stick range |F| ≤ μN
  kZeroMuCrossing,      // μ_req,k = 0 (F_k changes sign) with N_k > 0: the lower end of the
                        // thesis's whirl range 0 ≤ μ_req ≤ μ (Eq. 30); below it friction would
                        // have to oppose the backward precession
  kContactLoss,         // N_k: + → − as Ω increases (μ_req has a pole here)
  kContactRegain,       // N_k: − → + as Ω increases
};

// "mu_crossing" | "negative_mu_crossing" | "zero_mu_crossing" | "contact_loss" | "contact_regain"
const char* ToString(TransitionType type);

struct Transition {
  TransitionType type = TransitionType::kMuCrossing;
  int contact = 0;             // 0 = left, 1 = right
  double precession_hz = 0.0;  // located to a few ulps by Illinois regula falsi on the closed form
  // +1 when the quantity that crosses (μ_req for μ crossings, N for contact loss/regain) increases
  // with Ω, −1 when it decreases. A μ crossing with direction +1 is whirl → whip as Ω increases.
  int direction = 0;
  double normal_force = 0.0;   // N_k at the transition [N] (≈ 0 for contact loss / regain)
  // True only for an N sign change through a pole (|N| → ∞ instead of N → 0), which needs
  // undamped supports (c_L = c_R = 0): a resonance, not a smooth loss of contact.
  bool through_pole = false;
};

enum class AnalyticStatus {
  kSuccess,
  kNonFinite,  // the closed form gave NaN/Inf at some grid point (e.g. exactly on an undamped pole)
};

const char* ToString(AnalyticStatus status);

// One family (Mode 1 or 2) evaluated on the grid, with its located transitions.
struct AnalyticCurve {
  CircularMode mode = CircularMode::kMode1;
  Vector precession_hz;                // grid [Hz], size n
  std::array<Vector, 2> normal_force;  // N_L, N_R [N], size n each
  std::array<Vector, 2> friction_force;  // F_L, F_R [N]
  std::array<Vector, 2> mu_required;     // μ_req,L, μ_req,R [-] (±∞/NaN where N = 0)
  std::vector<Transition> transitions;   // sorted by frequency, then contact
  AnalyticStatus status = AnalyticStatus::kSuccess;
  std::string message;                   // why, when status ≠ kSuccess
  bool Succeeded() const { return status == AnalyticStatus::kSuccess; }
};

// Everything level L0 says about a scene.
struct AnalyticResult {
  NaturalFrequencies natural_frequencies;
  AnalyticCurve mode1;
  AnalyticCurve mode2;
  bool Succeeded() const { return mode1.Succeeded() && mode2.Succeeded(); }
};

// Evaluates N, F, μ_req of one mode on the grid and locates every transition on it: sign changes
// of F − μN, F + μN, F and N between neighbouring grid points are bracketed, then refined by
// Illinois regula falsi (solvers/scalar_root.h) to a few ulps; μ crossings are kept only where N > 0 (in contact). Throws
// std::invalid_argument on invalid parameters or options; numerical outcomes are a status.
AnalyticCurve ComputeAnalyticCurve(const TwoPointParams& p, CircularMode mode,
                                   const AnalyticOptions& options = {});

// Natural frequencies and both modes.
AnalyticResult ComputeAnalytic(const TwoPointParams& p, const AnalyticOptions& options = {});

// The same evaluation for any closed form: `contact_force(Ω)` returns P_k = N_k + jF_k of the
// first `contacts` (1 or 2) entries; entries of the curve beyond `contacts` stay empty. Throws
// std::invalid_argument on invalid options or a contact count outside 1…2.
AnalyticCurve ComputeClosedFormCurve(const std::function<ComplexVector2(double precession)>& contact_force,
                                     int contacts, double mu, CircularMode mode,
                                     const AnalyticOptions& options);

}  // namespace rubcont
