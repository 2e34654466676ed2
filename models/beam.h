// Level L4: flexible rotors and stators from Timoshenko beam finite elements (shear deformation,
// rotary inertia, gyroscopic moments), rigid disks and linear springs, on complex coordinates as
// the rigid model (docs/theory.md §2): every node carries a displacement u = x + j y and a rotation
// ψ = ψ_xz + j ψ_yz of its cross-section, ψ_xz turning the section like dx/dz and ψ_yz like dy/dz.
// For an axisymmetric shaft on isotropic supports the real matrices act identically on x and y,
// and the spin ω (about +z) adds the gyroscopic term once, in complex form:
//     M ü + (C − jωG) u̇ + K u = f,
// with G real symmetric (a disk's polar inertia on its rotation; the shaft's distributed one).
// Forward whirl u ∝ e^{jνt} stiffens by ωνG, backward whirl softens: the gyroscopic splitting.
//
// Global coordinates: the shafts in order, two per node, (u_0, ψ_0, u_1, ψ_1, …), so shaft s node
// i component c (0: displacement, 1: rotation) is BeamModel::Coordinate(s, i, c).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "solvers/types.h"

namespace rubcont {

// A uniform hollow circular shaft segment between two nodes.
struct ShaftElement {
  double length = 0.0;          // L [m] > 0
  double outer_diameter = 0.0;  // D [m] > 0
  double inner_diameter = 0.0;  // d [m], 0 ≤ d < D
  double youngs_modulus = 0.0;  // E [Pa] > 0
  double shear_modulus = 0.0;   // G [Pa] > 0, with E/(2G) − 1 = ν in (−1, 0.5]
  double density = 0.0;         // ρ [kg/m³] ≥ 0 (0: a massless shaft)

  double Area() const;          // A = π(D² − d²)/4
  double AreaMoment() const;    // I = π(D⁴ − d⁴)/64, about a diameter (the polar one is 2I)
  double Poisson() const { return youngs_modulus / (2.0 * shear_modulus) - 1.0; }
  // Cowper's (1966) shear coefficient of a hollow circle, m = d/D:
  // κ = 6(1+ν)(1+m²)² / ((7+6ν)(1+m²)² + (20+12ν)m²); 6(1+ν)/(7+6ν) for a solid one.
  double ShearCoefficient() const;
  // Φ = 12EI/(κGAL²), the ratio of shear to bending flexibility (0: Euler–Bernoulli).
  double ShearParameter() const;
};

// One plane's matrices in the order (u_1, ψ_1, u_2, ψ_2): Przemieniecki's Timoshenko element with
// cubic interpolation consistent with Φ (exact static deflections under end loads):
// stiffness, translational + rotary mass, and G = 2 × the rotary mass (polar = 2 × diametral
// inertia of a circular section).
struct BeamElementMatrices {
  Eigen::Matrix4d mass;
  Eigen::Matrix4d stiffness;
  Eigen::Matrix4d gyroscopic;
};
BeamElementMatrices TimoshenkoElement(const ShaftElement& element);

// A rigid disk (or any lumped mass) at a node: mass on u, diametral inertia on ψ, polar inertia in G.
struct Disk {
  int node = 0;
  double mass = 0.0;               // [kg] ≥ 0
  double diametral_inertia = 0.0;  // I_d [kg·m²] ≥ 0, about a diameter through the node
  double polar_inertia = 0.0;      // I_p [kg·m²] ≥ 0
};

// A shaft: its elements end to end along z from z = 0 (node i at the sum of the first i lengths)
// and the disks on its nodes.
struct Shaft {
  std::string name;
  std::vector<ShaftElement> elements;
  std::vector<Disk> disks;

  int Nodes() const { return static_cast<int>(elements.size()) + 1; }
  std::vector<double> NodePositions() const;  // z of each node [m]
};

// A translational spring and dashpot from a shaft's node to ground (other_shaft < 0) or to a node
// of another (or the same) shaft: supports, bearings, a stator's pedestals.
struct Spring {
  int shaft = 0;
  int node = 0;
  int other_shaft = -1;  // < 0: ground
  int other_node = 0;
  double stiffness = 0.0;  // [N/m] ≥ 0
  double damping = 0.0;    // [N·s/m] ≥ 0
};

// The real symmetric matrices of M ü + (C − jωG) u̇ + K u = f on complex coordinates.
struct StructuralMatrices {
  Matrix mass;
  Matrix damping;
  Matrix stiffness;
  Matrix gyroscopic;
  Index Coordinates() const { return mass.rows(); }
};

struct BeamModel {
  std::vector<Shaft> shafts;
  std::vector<Spring> springs;

  // Index of shaft s, node i, component c (0: u, 1: ψ) in the global coordinates.
  Index Coordinate(int shaft, int node, int component) const;
  Index Coordinates() const;
  // Throws std::invalid_argument naming the first entry that breaks its rule above, e.g.
  // "shafts[0].elements[3].inner_diameter = 0.05: must be below outer_diameter (0.04 m)".
  void Validate() const;
};

// Assembles the shafts' elements and disks and the springs (validated first).
StructuralMatrices Assemble(const BeamModel& model);

// The eigenvalues s of (s²M + s(C − jωG) + K) v = 0 at spin ω [rad/s] with the coordinates `held`
// fixed at zero (pinned or clamped ends), sorted by imaginary part: s = σ + jν is a whirl at ν
// (> 0 forward, < 0 backward) growing at σ. Throws std::invalid_argument if M is not positive
// definite on the other coordinates (a massless node left free).
ComplexVector WhirlEigenvalues(const StructuralMatrices& matrices, double spin,
                               const std::vector<Index>& held);

// The whirl modes of those eigenvalues: for each s = σ + jν with ν > 0 (forward whirl; backward
// ones, ν < 0, with `backward`), its frequency |ν|/2π [Hz] and damping ratio −σ/|s|, ascending.
struct StructureMode {
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
};
std::vector<StructureMode> WhirlModes(const StructuralMatrices& matrices, double spin,
                                      const std::vector<Index>& held, bool backward = false);

}  // namespace rubcont
