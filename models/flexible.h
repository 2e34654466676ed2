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

// The two-point model (TwoPointParams) made flexible: a uniform rotor shaft across the contact span
// [0, l] and a uniform stator shaft across [0, l_s], each of the section and material given (the
// sections' `length` is ignored), cut into about `elements` elements with nodes at the mid-span,
// the mass centre and the disk; on each a rigid disk that makes up the rest of the body's mass,
// mass-centre position and transverse inertia about the mass centre, so that the rigid-body data
// equal the rigid model's exactly (the disk sits where the remaining mass must put the mass
// centre; where that is past a contact plane, the shaft goes on to it). Disk polar inertia 2 I_d
// (a thin disk). Supports (k, c) at the stator's contact stations, the centre damper between the
// shafts' mid-span nodes, the imbalance at the rotor's mass-centre node, contacts "left" (z = 0)
// and "right" (z = l, z = l_s) with the rigid model's geometry and law. Throws std::invalid_argument when a shaft is heavier than its body or leaves
// its disk a negative inertia (a thinner section is needed), naming which.
FlexibleRubModel FlexibleTwoPoint(const TwoPointParams& params, const ShaftElement& rotor_section,
                                  const ShaftElement& stator_section, int elements, int modes);

// Natural modes of a rub structure out of contact (`pinned` false) or with every contact pinned
// (rotor and stator coordinates of each contact moving together, as the thesis's Tables 2–3 list
// "rotor–stator pinned"), at spin ω [rad/s] with damping, as WhirlModes (models/beam.h) gives
// them: forward whirl (backward with `backward`), ascending.
std::vector<StructureMode> StructureModes(const RubStructure& structure, bool pinned, double spin = 0.0,
                                      bool backward = false);

}  // namespace rubcont
