// A linear rotor–stator structure on complex coordinates with rub contacts, and its equations of
// motion in the fixed frame and in a frame precessing backwards at a rate Ω (docs/theory.md §2, §6).
//
// The structure has n_c complex coordinates u (rotor and stator displacements at chosen planes,
// and for flexible models section rotations and modal coordinates):
//     M ü + (C − jωG) u̇ + K u = Σ_k B_k f_k + b m_u e ω² e^{jωt}
// with real symmetric n_c × n_c matrices M, C, K, G acting identically on x and y, contact k acting
// between coordinates rotor(k) and stator(k) (B_k = e_rotor − e_stator), and imbalance weights b.
// The two-point rotor (4 coordinates: rotor L, R; stator L, R) and the single-contact Jeffcott
// rotor (2 coordinates) are both instances, so one implementation serves both.
//
// Real state layout (4 n_c entries): x = [q; v], q = (x_0, y_0, x_1, y_1, ...), v = q̇.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "models/contact.h"
#include "models/two_point_params.h"
#include "solvers/ode_system.h"

namespace rubcont {

struct RubContact {
  int rotor = 0;   // index of the rotor coordinate at the contact plane
  int stator = 1;  // index of the stator coordinate at the contact plane
  ContactGeometry geometry;
  std::string name;  // "left", "right", or "contact"
};

struct RubStructure {
  Matrix mass;       // M (n_c × n_c) [kg], symmetric positive definite
  Matrix damping;    // C (n_c × n_c) [N·s/m], symmetric positive semi-definite
  Matrix stiffness;  // K (n_c × n_c) [N/m], symmetric positive semi-definite
  // G (n_c × n_c) [kg·m²], symmetric, or empty for none: the spin ω adds −jωG u̇ to the damping
  // term (the polar inertia of flexible rotors, models/beam.h; the rigid model has none).
  Matrix gyroscopic;
  std::vector<RubContact> contacts;
  Vector imbalance_weights;  // b (n_c): generalized force per unit imbalance force m_u e ω²
  double imbalance = 0.0;    // m_u e [kg·m]
  ContactLaw law;
  std::vector<std::string> coordinate_names;  // n_c names, e.g. "rotor_left"

  Index Coordinates() const { return mass.rows(); }
  Index States() const { return 4 * mass.rows(); }
  // Throws std::invalid_argument naming the inconsistency (sizes, indices, non-symmetric M).
  void Validate() const;
};

// The contact law of a model's parameters: TwoPointParams and JeffcottParams name its fields alike
// (friction, contact_stiffness, contact_stiffness2, contact_damping, friction_law.velocity_scale).
template <class Params>
ContactLaw ContactLawOf(const Params& p) {
  ContactLaw law;
  law.stiffness = p.contact_stiffness;
  law.stiffness2 = p.contact_stiffness2;
  law.damping = p.contact_damping;
  law.friction = p.friction;
  law.velocity_scale = p.friction_law.velocity_scale;
  return law;
}

// The two-point model of docs/theory.md §2: coordinates (rotor L, rotor R, stator L, stator R),
// M = blkdiag(M_r, M_s), K = blkdiag(0, K_s), C = blkdiag(0, C_s) + c_d w wᵀ with
// w = (½, ½, −½, −½) (centre damper between the mid-points), imbalance b = ((1−a), a, 0, 0).
RubStructure TwoPointStructure(const TwoPointParams& params);

// The exchange of the structure's two contacts as a permutation of its coordinates (rotor and
// stator coordinate of contact 0 with those of contact 1, every other coordinate fixed), when the
// structure is invariant under it: M, C, K, the imbalance weights (to 1e-12 relative) and the two
// contacts' geometries equal after the exchange. Empty otherwise, and for any number of contacts
// but two. Case A(a) (a symmetric rotor, equal stator supports and RCIs) has it; A(b) does not.
std::vector<Index> ContactExchange(const RubStructure& structure);

// Planar helpers on the real layout.
inline Vector2 PlanarAt(const Vector& q, Index coordinate) {
  return Vector2(q(2 * coordinate), q(2 * coordinate + 1));
}

// Generalized contact forces on the structure and their derivatives, for given positions q and
// velocities v (2 n_c each), spin ω and per-contact friction modes (stick forces used in kStick).
struct ContactForces {
  Vector generalized;         // Σ_k B_k f_k (2 n_c)
  Matrix d_dq;                // ∂/∂q (2 n_c × 2 n_c)
  Matrix d_dv;                // ∂/∂v
  Vector d_domega;            // ∂/∂ω (2 n_c)
  Matrix d_dstick;            // ∂/∂F_k (2 n_c × contacts), non-zero for kStick contacts only
  std::vector<ContactEvaluation> contacts;
};
void EvaluateContactForces(const RubStructure& structure, double omega, ConstVectorRef q,
                           ConstVectorRef v, const std::vector<FrictionMode>& modes,
                           const Vector& stick_forces, bool with_derivatives, ContactForces& out);

// Circular backward precession u(t) = u0 e^{−jΩt} with each contact touching at exactly its
// clearance along a prescribed normal n_k (normalized here): the closed form generalizing the
// thesis's Mode 1 (all n_k equal) and Mode 2 (n_R = −n_L) to any phase between the contacts.
// n_k = 0 leaves contact k out (not touching: no force, no constraint; P_k = 0).
// Contact forces f_k = −P_k n_k with P_k = N_k + jF_k; D(Ω) = K − Ω²M − jΩC; D u0 = Σ B_k f_k;
// B_kᵀ u0 = C_k n_k. Imbalance is ignored; Hunt–Crossley compliance is not (|d_k| = C_k).
// Gyroscopic moments are too (they need the spin, which this closed form does not fix): for a
// structure with G it is a first guess, as the rotating-wave family search uses it.
struct RigidContactOrbit {
  double precession = 0.0;                     // Ω [rad/s] > 0
  std::vector<std::complex<double>> amplitude;  // u0 (n_c)
  std::vector<std::complex<double>> force;      // P_k = N_k + j F_k per contact
};
RigidContactOrbit SolveRigidContactOrbit(const RubStructure& structure, double precession,
                                 const std::vector<std::complex<double>>& normals);

// Fixed-frame equations of motion ẋ = f(t, x; ω), 4 n_c states, parameter ω [rad/s], friction
// regularized by tanh(V/ε) (the only law time marching can use). Non-autonomous when the
// structure has an imbalance (forcing period 2π/ω).
class RubFixedFrame : public OdeSystem {
 public:
  explicit RubFixedFrame(RubStructure structure, double omega = 0.0);

  Index Dimension() const override { return structure_.States(); }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return omega_; }
  void SetParameter(double omega) override { omega_ = omega; }
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  Vector StateScale() const override;
  double ForcingPeriod() const override;
  bool HasRotationSymmetry() const override { return structure_.imbalance == 0.0; }
  void Rotate(double phi, VectorRef x) const override;
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override;
  // κ = the exchange of the two contacts (ContactExchange), on positions and velocities.
  bool HasMirrorSymmetry() const override { return !exchange_.empty(); }
  void Mirror(VectorRef x) const override;
  // One per contact: its penetration δ = |d| − C [m], where the normal force switches on (a kink
  // of the vector field: N = k1 δ + … > 0 only for δ > 0). Invariant under Rotate.
  int SwitchingCount() const override { return static_cast<int>(structure_.contacts.size()); }
  void SwitchingFunctions(double t, ConstVectorRef x, VectorRef h) const override;
  // h_k = |d| − C along d + s ḋ: the radial motion's s |n·ḋ| to first order (ḋ: the positions'
  // entries of f), plus rounding.
  bool SwitchingIncrementBounds(double t, ConstVectorRef x, ConstVectorRef f, double s,
                                VectorRef bound) const override;
  // The contact chart: x with each contact's stator position and velocity replaced by the polar
  // form of the contact's relative displacement d = u_rotor − u_stator, (|d| − C, arg d), and of
  // its rate, (n·ḋ, t·ḋ) with n = d/|d|, t = j n: the radial gap and its rate, which a stiff
  // contact holds within nanometres (C(c) at 64 rpm: pressed by 0.5–2.5 nm) and nanometres per
  // contact period while the positions move by micrometres, become coordinates of their own
  // (OdeSystem::HasStateChart). The rates too: a K = 8 circle of C(c)'s torus interpolated ḋ
  // with errors of ~1.5e-3 m/s, which rings the contact (ω_c ~ 1e5 rad/s) by ~17 nm. Available
  // when every contact has its own stator coordinate that is no contact's rotor coordinate (the
  // rigid and the flexible models); |d| > 0 is needed (a whip's, where the chart matters). Scale:
  // the gap 1e-3 of the position's, the angle 1 rad, the rates the velocity's (with 1e-3 of it
  // for the gap's rate Newton's scaled Jacobian on C(c) at 64 rpm was singular, rcond < 1e-14).
  bool HasStateChart() const override { return chart_; }
  void ToChart(ConstVectorRef x, VectorRef y) const override;
  void FromChart(ConstVectorRef y, VectorRef x, Matrix* jacobian = nullptr) const override;
  Vector ChartScale() const override;
  std::vector<Index> ChartAngles() const override;

  const RubStructure& structure() const { return structure_; }
  // Contact quantities (N, V, F, δ, ...) at state x for the current ω.
  std::vector<ContactEvaluation> Contacts(ConstVectorRef x);

  // Friction modes used by Rhs / JacobianX, one per contact (default: all kRegularized). Exact
  // modes (kSlip*, kStick with the given stick forces [N]) serve linearizations of rotating waves;
  // time integration always uses kRegularized.
  void SetFrictionModes(std::vector<FrictionMode> modes, Vector stick_forces);
  // ∂ẋ/∂F_k (States() × contacts) at the state of the last JacobianX call: non-zero for kStick.
  Matrix StickForceJacobian() const;

 private:
  RubStructure structure_;
  double omega_;
  Matrix mass_inverse_;  // kron(M⁻¹, I₂)
  Matrix damping_;       // kron(C, I₂)
  Matrix stiffness_;     // kron(K, I₂)
  Matrix gyroscopic_;    // kron(G, [[0, −1], [1, 0]]): the load ω gyroscopic_ v of jωG u̇; empty for none
  std::vector<FrictionMode> modes_;
  Vector stick_forces_;
  bool regularized_ = true;  // every mode kRegularized: Rhs takes the time-marching path
  bool chart_ = false;       // HasStateChart (the structure's contacts allow it)
  ContactForces forces_;  // workspace
  // Rhs for N = n_c or Eigen::Dynamic (x and f: 4 n_c entries).
  template <int N>
  void Evaluate(double t, const double* x, double* f);
  // Rhs's accelerations (2 × n_c, coordinate by column) = load M⁻ᵀ − V (M⁻¹C)ᵀ − Q (M⁻¹K)ᵀ
  // (+ ω (−V_y, V_x)(M⁻¹G)ᵀ with gyroscopic moments), for N = n_c or Eigen::Dynamic; loads 2 × n_c.
  template <int N>
  void Accelerations(const double* x, const double* loads, double* acceleration) const;
  // Rhs: M⁻ᵀ, (M⁻¹C)ᵀ, (M⁻¹K)ᵀ (n_c × n_c) and its workspace, the load as 2 × n_c (Eigen::Dynamic).
  Matrix small_mass_inverse_transpose_, small_damping_rate_transpose_,
      small_stiffness_rate_transpose_, small_gyroscopic_rate_transpose_;
  Matrix load_;
  std::vector<Index> exchange_;  // ContactExchange(structure_)
};

// The same equations in the frame precessing backwards at the constant rate Ω_f,
// u = e^{−jΩ_f t} p:  p̈ = a(p, ṗ − jΩ_f p) + 2jΩ_f ṗ + Ω_f² p, a being the fixed-frame
// acceleration. Rotating waves are equilibria when Ω_f equals their precession; modulated whirl
// is a relative periodic orbit. Requires no imbalance (it would break the rotational symmetry).
class RubRotatingFrame : public OdeSystem {
 public:
  RubRotatingFrame(RubStructure structure, double frame_rate, double omega = 0.0);

  Index Dimension() const override { return fixed_.Dimension(); }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override;
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override;
  double Parameter() const override { return fixed_.Parameter(); }
  void SetParameter(double omega) override { fixed_.SetParameter(omega); }
  void DfDparameter(double t, ConstVectorRef x, VectorRef df) override;
  Vector StateScale() const override { return fixed_.StateScale(); }
  bool HasRotationSymmetry() const override { return true; }
  void Rotate(double phi, VectorRef x) const override { fixed_.Rotate(phi, x); }
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override {
    fixed_.RotationGenerator(x, g);
  }
  // The frame rotates every coordinate alike, so the contact exchange commutes with it.
  bool HasMirrorSymmetry() const override { return fixed_.HasMirrorSymmetry(); }
  void Mirror(VectorRef x) const override { fixed_.Mirror(x); }
  // The penetrations, as in the fixed frame (|d| is the same in both).
  int SwitchingCount() const override { return fixed_.SwitchingCount(); }
  void SwitchingFunctions(double t, ConstVectorRef x, VectorRef h) const override {
    fixed_.SwitchingFunctions(t, x, h);
  }
  // The same functions of x as in the fixed frame, so the same bound along x + s f.
  bool SwitchingIncrementBounds(double t, ConstVectorRef x, ConstVectorRef f, double s,
                                VectorRef bound) const override {
    return fixed_.SwitchingIncrementBounds(t, x, f, s, bound);
  }
  // The fixed frame's chart: d and its polar form are the same functions of x in both frames.
  bool HasStateChart() const override { return fixed_.HasStateChart(); }
  void ToChart(ConstVectorRef x, VectorRef y) const override { fixed_.ToChart(x, y); }
  void FromChart(ConstVectorRef y, VectorRef x, Matrix* jacobian = nullptr) const override {
    fixed_.FromChart(y, x, jacobian);
  }
  Vector ChartScale() const override { return fixed_.ChartScale(); }
  std::vector<Index> ChartAngles() const override { return fixed_.ChartAngles(); }

  void SetFrictionModes(std::vector<FrictionMode> modes, Vector stick_forces) {
    fixed_.SetFrictionModes(std::move(modes), std::move(stick_forces));
  }
  // ∂ẋ/∂F_k at the state of the last JacobianX call (the frame terms do not involve F).
  Matrix StickForceJacobian() const { return fixed_.StickForceJacobian(); }

  double frame_rate() const { return frame_rate_; }
  void set_frame_rate(double frame_rate) { frame_rate_ = frame_rate; }
  const RubStructure& structure() const { return fixed_.structure(); }
  // Mean backward precession [rad/s] in the fixed frame of a relative periodic orbit of this frame,
  // p(T) = R_φ p(0) (R_φ = e^{jφ}, Rotate): Ω_f − φ/T, the carrier of the modulated motion.
  double CarrierPrecession(double period, double rotation) const {
    return frame_rate_ - rotation / period;
  }
  // Fixed-frame state at time t from a rotating-frame state: u = e^{−jΩ_f t} p, u̇ = e^{−jΩ_f t}(ṗ − jΩ_f p).
  Vector ToFixedFrame(double t, ConstVectorRef x) const;
  // The inverse: the co-rotating state at time t of a fixed-frame state, p = e^{jΩ_f t} u,
  // ṗ = e^{jΩ_f t}(u̇ + jΩ_f u).
  Vector ToRotatingFrame(double t, ConstVectorRef u) const;

 private:
  RubFixedFrame fixed_;
  double frame_rate_;
  // The fixed-frame model's state (p, ṗ − jΩ p) at the co-rotating state x, into fixed_state_.
  void LoadFixedState(ConstVectorRef x);
  Vector fixed_state_;  // workspace
  Matrix fixed_jacobian_;
};

}  // namespace rubcont
