// Level L4: the rub model on flexible rotors and stators. A BeamModel (models/beam.h: Timoshenko
// shafts, disks, springs) with contacts between a rotor node and a stator node, reduced by
// Craig–Bampton (models/component_modes.h) with the contact displacements kept physical — as the
// thesis's XLTRC² models keep them (§3.1–3.2) — becomes a RubStructure, so every level above
// (rotating waves, orbits, sweeps) runs on it unchanged:
//     coordinates = (rotor at contact 0, rotor at contact 1, …, stator at contact 0, …,
//                    fixed-interface modes 1 … m),
// the same order as the rigid two-point model's (rotor_left, rotor_right, stator_left,
// stator_right). With m = 0 this is Guyan's condensation, which for rigid shafts is exactly the
// rigid model (the rigid limit, tested).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "models/beam.h"
#include "models/component_modes.h"
#include "models/contact.h"
#include "models/rub_model.h"
#include "models/two_point_params.h"

namespace rubcont {

struct FlexibleContact {
  std::string name;     // "left", "right", …
  int rotor_shaft = 0;  // the rotor's shaft and node at the contact plane
  int rotor_node = 0;
  int stator_shaft = 1;  // the stator's
  int stator_node = 0;
  ContactGeometry geometry;
};

struct FlexibleRubModel {
  BeamModel beams;
  std::vector<FlexibleContact> contacts;
  int modes = 4;  // fixed-interface modes kept (≥ 0)
  // Modal damping ratio ζ ≥ 0 of the kept modes: 2ζω_j on their diagonal of C (the springs'
  // dashpots act through the constraint modes as they are).
  double modal_damping = 0.0;
  bool gyroscopic = true;  // keep the polar inertias' −jωG u̇ (false: as the rigid model)
  ContactLaw law;
  double imbalance = 0.0;  // m_u e [kg·m] ≥ 0, at imbalance_shaft / imbalance_node
  int imbalance_shaft = 0;
  int imbalance_node = 0;
};

struct FlexibleRub {
  RubStructure structure;  // the reduced model, coordinates as above
  ModalReduction reduction;
  StructuralMatrices full;  // the assembled, unreduced matrices
};

// Throws std::invalid_argument naming the entry that breaks its rule (the beams' own rules, a
// contact node out of range or joining a shaft to itself, a coordinate shared by two contacts, more
// modes than the interior has, a negative ζ or imbalance).
FlexibleRub BuildFlexibleRub(const FlexibleRubModel& model);

// The same rub structure from any structural matrices (an FE model's, or a file's): contact k
// joins the displacement coordinates `rotor` and `stator` of the full matrices, reduced as above
// with those coordinates physical. BuildFlexibleRub assembles its beams and calls this.
struct MatrixContact {
  std::string name;  // "left", "right", …
  Index rotor = 0;   // the rotor's displacement coordinate at the contact plane
  Index stator = 1;  // the stator's
  ContactGeometry geometry;
};
struct MatrixRubModel {
  StructuralMatrices full;  // M, C, K, G of M ü + (C − jωG) u̇ + K u = f (CheckStructuralMatrices)
  std::vector<MatrixContact> contacts;
  int modes = 4;                   // fixed-interface modes kept (≥ 0)
  double modal_damping = 0.0;      // ζ ≥ 0 of the kept modes, as FlexibleRubModel's
  bool gyroscopic = true;          // keep −jωG u̇ (false: as the rigid model)
  ContactLaw law;
  double imbalance = 0.0;          // m_u e [kg·m] ≥ 0, on imbalance_coordinate
  Index imbalance_coordinate = 0;  // the displacement coordinate the imbalance force acts on
};
// The beam model assembled (models/beam.h Assemble) with its contacts' and imbalance's nodes as
// coordinates: what BuildFlexibleRub reduces, and what a matrix file of it holds. Throws as
// BuildFlexibleRub does for the beams' rules and nodes.
MatrixRubModel AssembledMatrices(const FlexibleRubModel& model);
// Throws std::invalid_argument naming the rule broken: the matrices' (CheckStructuralMatrices), a
// contact coordinate out of range or shared, a boundary that leaves the interior free to move
// rigidly, more modes than the interior has (ModelInputError "modes"), a negative ζ or imbalance.
FlexibleRub BuildMatrixRub(const MatrixRubModel& model);

// The rules any structure's matrices keep (FE input checked before it is reduced): all four
// square of one size n ≥ 1, finite, symmetric to 1e-10 of their largest entry; M, C and K
// positive semi-definite (eigenvalues ≥ −1e-10 of the largest; BuildMatrixRub asks the reduced M
// to be definite: a lumped model's massless rotations are condensed away, a massless contact is
// not). Throws std::invalid_argument naming the matrix ("mass", "damping", "stiffness",
// "gyroscopic") and the rule, e.g. "stiffness: not symmetric: entry (3, 5) − entry (5, 3) =
// 1e+03 (largest |entry| 2.8e+10): must agree to 1e-10 of it".
void CheckStructuralMatrices(const StructuralMatrices& matrices);

// One body of the two-point model as a shaft (models/beam.h: elements end to end from station 0,
// disks on stations) and the stations where it touches the other body, left and right.
struct BodyShaft {
  Shaft shaft;
  std::array<int, 2> contact_stations{};
};

// The rigid-body data of a body shaft, as the rigid two-point model states them: mass, the
// distance between its contact stations (the rotor's contact_span, the stator's span), the mass
// centre's distance from the left contact station, and the transverse inertia about the mass
// centre (the elements' translational and rotary inertia, the disks' diametral). These are exactly
// what the shaft's consistent mass matrix gives a rigid motion. Throws std::invalid_argument if the
// shaft breaks its rules (Shaft's, models/beam.h), a contact station is out of range, or the right
// one is not beyond the left one.
struct RigidBodyData {
  double mass = 0.0;         // [kg]
  double span = 0.0;         // [m]
  double mass_center = 0.0;  // [m] from the left contact station
  double inertia = 0.0;      // [kg·m²] about the mass centre
};
RigidBodyData RigidBodyOf(const BodyShaft& body);

// A uniform shaft of `section` (its `length` ignored) across the contacts' span [0, span] — and on
// past an end where the disk must sit beyond it — cut into about `elements` elements, with stations
// at both contacts, at the `extra` positions and at a rigid disk that makes up the rest of the
// body's mass, mass-centre position (from the left contact) and transverse inertia about the mass
// centre, so that RigidBodyOf gives the body's data exactly. Disk polar inertia 2 I_d (a thin
// disk). Throws ModelInputError (input "<name> section") when the shaft is heavier than the body
// or leaves its disk a negative inertia (a thinner section is needed).
BodyShaft UniformBody(const std::string& name, const ShaftElement& section, double span,
                      int elements, double mass, double inertia, double mass_center,
                      const std::vector<double>& extra);

// The two-point model (TwoPointParams) on flexible bodies: contacts "left" and "right" at the
// bodies' contact stations with the rigid model's geometry and law; supports (k, c) to ground at
// the stator's contact stations; the centre damper c_d between the rotor's and the stator's stations
// at the mid-span of their contacts (which each must have when c_d > 0); the imbalance at the
// rotor's station nearest its mass centre. The params' rigid-body data (masses, inertias, spans,
// mass centres) are not read: the shafts are the bodies (RigidBodyOf says what they are). Throws
// std::invalid_argument naming the rule broken.
FlexibleRubModel FlexibleTwoPoint(const TwoPointParams& params, const BodyShaft& rotor,
                                  const BodyShaft& stator, int modes);

// The two-point model's bodies as uniform shafts: UniformBody with the params' data, stations at
// the mid-span of the contacts (and the rotor's at its mass centre).
BodyShaft UniformRotor(const TwoPointParams& params, const ShaftElement& section, int elements);
BodyShaft UniformStator(const TwoPointParams& params, const ShaftElement& section, int elements);

// The two-point model made flexible with uniform sections (UniformRotor, UniformStator), so that
// the rigid-body data equal the params' exactly; then as above.
FlexibleRubModel FlexibleTwoPoint(const TwoPointParams& params, const ShaftElement& rotor_section,
                                  const ShaftElement& stator_section, int elements, int modes);

// Natural modes of a rub structure out of contact (`pinned` false) or with every contact pinned
// (rotor and stator coordinates of each contact moving together, as the thesis's Tables 2–3 list
// "rotor–stator pinned"), at spin ω [rad/s] with damping, as WhirlModes (models/beam.h) gives
// them: forward whirl (backward with `backward`), ascending.
std::vector<StructureMode> StructureModes(const RubStructure& structure, bool pinned, double spin = 0.0,
                                      bool backward = false);

}  // namespace rubcont
