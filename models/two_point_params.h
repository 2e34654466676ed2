// Physical parameters of the two-point rub model (docs/theory.md §2): a rigid rotor touching a
// rigid, elastically supported stator at two contact planes, L (z = 0) and R (z = l). SI units
// throughout. Arrays indexed [0] = left contact / station, [1] = right.
//
// Defaults. The physical values default to the thesis's case A(a) (Kumar 2010, Eq. 31, Table 1;
// the contact law's from models/contact.h), which a scene must nevertheless give in full; the
// optional parts default to what a scene that leaves them out means: no imbalance, no centre
// damper, the exact friction law for rotating waves. ThesisCaseAa() is the case as the thesis
// simulated it, with its centre damper. The scene schema (apps/scene.cpp) takes its documented
// defaults from these initializers: each default is written once.
#pragma once

#include <array>

#include "models/contact.h"

namespace rubcont {

enum class FrictionLawKind {
  kTanh,   // F = μ N tanh(V / ε): smooth, for time marching and shooting
  kExact,  // F = μ N sgn(V) with stick (V = 0, |F| ≤ μN): piecewise smooth, for rotating waves
};

struct FrictionLaw {
  // The law of the rotating waves (time marching and shooting always use tanh).
  FrictionLawKind kind = FrictionLawKind::kExact;
  double velocity_scale = ContactLaw{}.velocity_scale;  // ε [m/s] of tanh(V/ε); > 0
};

struct TwoPointParams {
  // Rotor (rigid, free–free; 4 DOF described by its displacements at the two contact planes).
  double rotor_mass = 9.99;            // m_r [kg] > 0
  double rotor_inertia = 0.029;        // I_r [kg·m²] > 0, transverse, about the mass centre
  double contact_span = 0.29;          // l [m] > 0, distance between the contact planes
  double rotor_mass_center = 0.145;    // l_g [m], mass centre from the left plane; a = l_g/l (> 1: overhung)

  // Stator (rigid, 4 DOF at its two stations, which are the contact stations).
  double stator_mass = 21.44;          // m_s [kg] > 0
  double stator_inertia = 0.206;       // I_s [kg·m²] > 0, transverse, about its mass centre
  double stator_span = 0.27;           // l_s [m] > 0, distance between the stations
  double stator_mass_center = 0.135;   // l_sg [m], mass centre from the left station; b = l_sg/l_s
  std::array<double, 2> support_stiffness{4.70e6, 4.70e6};  // k_L, k_R [N/m] > 0
  std::array<double, 2> support_damping{324.9, 324.9};      // c_L, c_R [N·s/m] ≥ 0

  // Contacts (Hunt–Crossley normal force, Coulomb friction).
  // C_L, C_R [m] > 0, radial; R_L, R_R [m] > 0, rotor radius at contact (RCI 100/100).
  std::array<double, 2> clearance{ContactGeometry{}.clearance, ContactGeometry{}.clearance};
  std::array<double, 2> radius{ContactGeometry{}.radius, ContactGeometry{}.radius};
  double friction = ContactLaw{}.friction;                   // μ [-] ≥ 0
  double contact_stiffness = ContactLaw{}.stiffness;         // k1 [N/m] > 0: N = k1 δ + k2 δ² + c_nl δ̇ δ
  double contact_stiffness2 = ContactLaw{}.stiffness2;       // k2 [N/m²] ≥ 0
  double contact_damping = ContactLaw{}.damping;             // c_nl [N·s/m²] ≥ 0
  FrictionLaw friction_law;

  double imbalance = 0.0;       // m_u e [kg·m] ≥ 0, at the mass-centre plane (3.43 g·cm = 3.43e-5)
  double center_damping = 0.0;  // c_d [N·s/m] ≥ 0, between rotor and stator mid-points (thesis: 52)

  double a() const { return rotor_mass_center / contact_span; }
  double b() const { return stator_mass_center / stator_span; }
  // Radius-to-clearance ratio R_k / C_k of contact k.
  double Rci(int k) const { return radius[k] / clearance[k]; }
};

// The thesis's case A(a) as it simulated it (§3.7): the defaults above with the centre damper of
// 52 N·s/m (scenes/thesis_A_a.toml).
TwoPointParams ThesisCaseAa();

// The thesis's case C(a) (Table 1): case A(a) with the disk near the right contact — rotor inertia
// 0.07 kg·m², mass centre 0.26 m from the left contact (scenes/thesis_C_a.toml).
TwoPointParams ThesisCaseCa();
// Its RCI pairs 100 / 125 (C(b): the right clearance 0.3048 mm) and 125 / 100 (C(c): the left)
// (scenes/thesis_C_b.toml, thesis_C_c.toml).
TwoPointParams ThesisCaseCb();
TwoPointParams ThesisCaseCc();

// Throws std::invalid_argument naming the first field that breaks its rule above (e.g.
// "TwoPointParams.rotor_mass = -1: must be positive (kg)"); every value must also be finite.
void Validate(const TwoPointParams& p);

}  // namespace rubcont
