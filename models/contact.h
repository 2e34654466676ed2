// One rub contact: Hunt–Crossley normal force and Coulomb friction (docs/theory.md §4, thesis Eqs. 43–45).
//
// Planar vectors are (x, y) pairs of the complex coordinate x + j y. For relative position
// d = u_r − u_s of the rotor axis with respect to the stator at the contact plane and its rate ḋ:
//   ρ = |d|, n = d/ρ, t = j n = (−n_y, n_x)        normal and tangent (counter-clockwise)
//   δ = ρ − C, δ̇ = nᵀḋ                              penetration and its rate
//   N = max(0, k1 δ + k2 δ² + c_nl δ̇ δ) if δ > 0, else 0
//   V = ω R + tᵀḋ                                    slip velocity of the rotor surface over the stator
//   F = μ N σ(V)                                     σ = tanh(V/ε) or sgn(V); in stick, F is given
//   f = −N n − F t                                   force on the rotor (the stator gets −f)
// With F > 0 the friction force −F t points clockwise: it drives backward precession u ∝ e^{−jΩt}.
// For circular backward precession V = ωR − Ω|d|, so rolling (V = 0) is Ω = ωR/|d| ≈ (R/C)·ω.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace rubcont {

using Vector2 = Eigen::Vector2d;
using Matrix2 = Eigen::Matrix2d;
using RowVector2 = Eigen::RowVector2d;

// How the tangential force is obtained.
enum class FrictionMode {
  kRegularized,   // F = μ N tanh(V/ε)
  // The modes below belong to piecewise formulations (rotating waves with contact and stick/slip
  // events): they hold the contact closed, with the normal law continued past δ = 0 (N < 0 there);
  // the formulation's contact-loss margin δ ≥ 0 decides where that is valid.
  kRegularizedHeld,  // F = μ N tanh(V/ε), the contact held closed
  kSlipPositive,  // F = +μ N (exact Coulomb, sliding with V > 0)
  kSlipNegative,  // F = −μ N (exact Coulomb, sliding with V < 0)
  kStick,         // F is an unknown supplied by the caller (exact Coulomb, V = 0 enforced elsewhere)
  kInactive,      // no force whatever the penetration: a contact held open by a piecewise
                  // formulation (its validity margin, penetration ≤ 0, is checked elsewhere)
};

// Material law shared by the contacts of a scene. The defaults are the thesis's contact (Kumar
// 2010, Eq. 46 and §3.3; μ of Table 1) and the regularization ε rubcont uses; the model parameter
// structs (TwoPointParams, JeffcottParams) take theirs from here.
struct ContactLaw {
  double stiffness = 1.75e11;    // k1 [N/m] > 0
  double stiffness2 = 0.0;       // k2 [N/m²] ≥ 0
  double damping = 1.75e5;       // c_nl [N·s/m²] ≥ 0 (Hunt–Crossley: damping force c_nl δ̇ δ)
  double friction = 0.5;         // μ [-] ≥ 0
  double velocity_scale = 1e-3;  // ε [m/s] > 0, of tanh(V/ε) in kRegularized mode
};

// Geometry of one contact (defaults: the thesis's RCI 100, R = 38.1 mm).
struct ContactGeometry {
  double clearance = 3.81e-4;  // C [m] > 0, radial
  double radius = 38.1e-3;     // R [m] > 0, rotor radius at the contact
};

// Everything a caller may want at one evaluation. Derivatives are filled only when requested and
// are zero when there is no contact (δ ≤ 0 or the clamped N = 0).
struct ContactEvaluation {
  bool touching = false;           // N > 0
  double penetration = 0.0;        // δ [m] (negative: gap)
  double penetration_rate = 0.0;   // δ̇ [m/s]
  double normal_force = 0.0;       // N [N] ≥ 0
  double slip_velocity = 0.0;      // V [m/s]
  double friction_force = 0.0;     // F [N]
  Vector2 normal = Vector2::Zero();   // n (zero when ρ = 0)
  Vector2 tangent = Vector2::Zero();  // t = j n
  Vector2 force = Vector2::Zero();    // f on the rotor [N]

  // ∂/∂d and ∂/∂ḋ (row vectors / 2×2), ∂/∂ω, ∂f/∂F (stick mode).
  RowVector2 dN_dd = RowVector2::Zero(), dN_dddot = RowVector2::Zero();
  RowVector2 dV_dd = RowVector2::Zero(), dV_dddot = RowVector2::Zero();
  Matrix2 df_dd = Matrix2::Zero(), df_dddot = Matrix2::Zero();
  Vector2 df_domega = Vector2::Zero();
  Vector2 df_dF = Vector2::Zero();
};

// Evaluates the contact at relative position d [m] and rate ḋ [m/s] for spin ω [rad/s].
// `stick_force` is F [N] in FrictionMode::kStick and ignored otherwise. The derivative members of
// `out` are set only with `with_derivatives` (otherwise left as they were).
void EvaluateContact(const ContactLaw& law, const ContactGeometry& geometry, double omega,
                     const Vector2& d, const Vector2& ddot, FrictionMode mode, double stick_force,
                     bool with_derivatives, ContactEvaluation& out);

// The force on the rotor alone, in FrictionMode::kRegularized, for time marching (millions of
// calls per simulated second): `force` and `touching` of EvaluateContact by the same operations in
// the same order — bit for bit its values — without what only EvaluateContact's callers read.
// Returns whether the contact touches (N > 0); sets `force` only then.
inline bool RegularizedContactForce(const ContactLaw& law, const ContactGeometry& geometry,
                                    double omega, const Vector2& d, const Vector2& ddot,
                                    Vector2& force) {
  const double rho = d.norm();
  const double delta = rho - geometry.clearance;
  if (!(delta > 0.0)) return false;
  const Vector2 n = d / rho;
  const Vector2 t(-n.y(), n.x());
  const double delta_dot = n.dot(ddot);
  const double normal = law.stiffness * delta + law.stiffness2 * delta * delta +
                        law.damping * delta_dot * delta;
  if (!(normal > 0.0)) return false;
  const double slip_velocity = omega * geometry.radius + t.dot(ddot);
  const double friction_force = law.friction * normal * std::tanh(slip_velocity / law.velocity_scale);
  force = -normal * n - friction_force * t;
  return true;
}

}  // namespace rubcont
