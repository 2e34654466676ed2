// The single-contact Jeffcott rotor with an elastically supported stator (Black 1968,
// Crandall 1990): the classic one-contact rub scene, an instance of RubStructure with two complex
// coordinates (rotor, stator), and its closed-form contact force for circular backward precession.
#pragma once

#include <complex>

#include "models/analytic.h"
#include "models/rub_model.h"

namespace rubcont {

struct JeffcottParams {
  double m_r = 10.0;      // rotor mass [kg] > 0
  double k_r = 1.0e6;     // rotor (shaft) stiffness [N/m] > 0
  double c_r = 100.0;     // rotor damping [N·s/m] ≥ 0
  double m_s = 20.0;      // stator mass [kg] > 0
  double k_s = 5.0e6;     // stator support stiffness [N/m] > 0
  double c_s = 300.0;     // stator support damping [N·s/m] ≥ 0
  double C = ContactGeometry{}.clearance;  // radial clearance [m] > 0
  double R = ContactGeometry{}.radius;     // rotor radius at the contact [m] > 0
  double friction = 0.3;  // μ [-] ≥ 0
  // Hunt–Crossley as the two-point model: k1 [N/m] > 0, k2 [N/m²] ≥ 0, c_nl [N·s/m²] ≥ 0.
  double contact_stiffness = ContactLaw{}.stiffness;
  double contact_stiffness2 = ContactLaw{}.stiffness2;
  double contact_damping = ContactLaw{}.damping;
  FrictionLaw friction_law;
  double imbalance = 0.0;  // m_u e [kg·m] ≥ 0, on the rotor
};

// Coordinates (rotor, stator): M = diag(m_r, m_s), K = diag(k_r, k_s), C = diag(c_r, c_s), one
// contact joining them, imbalance acting on the rotor.
RubStructure JeffcottStructure(const JeffcottParams& params);

// Closed form for circular backward precession at Ω [rad/s] with rigid contact (|d| = C):
// D_r = k_r − Ω²m_r − jΩc_r, D_s likewise; combined receptance H = 1/D_r + 1/D_s; the contact
// force on the rotor is f = −(N + jF) n with N + jF = −C/H. Contact needs N > 0; rolling needs
// 0 ≤ μ_req = F/N ≤ μ (Black's U-shaped curve), at Ω = (R/C)·ω.
std::complex<double> JeffcottContactForce(const JeffcottParams& params, double precession);

struct JeffcottFrequencies {
  double rotor_hz = 0.0;     // √(k_r/m_r) / 2π
  double stator_hz = 0.0;    // √(k_s/m_s) / 2π
  double combined_hz = 0.0;  // √((k_r + k_s)/(m_r + m_s)) / 2π: rotor and stator pinned together
};
JeffcottFrequencies JeffcottNaturalFrequencies(const JeffcottParams& params);

// The closed form on the grid of `options`, with its transitions located as for the two-point
// model (CircularMode::kSingleContact; only entry 0 of the per-contact arrays is filled).
AnalyticCurve ComputeJeffcottCurve(const JeffcottParams& params, const AnalyticOptions& options);

}  // namespace rubcont
