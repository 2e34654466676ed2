#include "models/flexible.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
#include <fmt/core.h>

namespace rubcont {
namespace {

void CheckContactNode(const BeamModel& beams, const std::string& key, int shaft, int node) {
  const int shafts = static_cast<int>(beams.shafts.size());
  if (shaft < 0 || shaft >= shafts) {
    throw std::invalid_argument(
        fmt::format("{}_shaft = {}: must name a shaft (0 to {})", key, shaft, shafts - 1));
  }
  const int nodes = beams.shafts[static_cast<std::size_t>(shaft)].Nodes();
  if (node < 0 || node >= nodes) {
    throw std::invalid_argument(fmt::format("{}_node = {}: must name a node of shafts[{}] (0 to {})",
                                            key, node, shaft, nodes - 1));
  }
}

}  // namespace

FlexibleRub BuildFlexibleRub(const FlexibleRubModel& model) {
  return BuildMatrixRub(AssembledMatrices(model));
}

MatrixRubModel AssembledMatrices(const FlexibleRubModel& model) {
  model.beams.Validate();
  if (model.contacts.empty()) {
    throw std::invalid_argument("contacts: at least one contact is needed");
  }
  CheckContactNode(model.beams, "imbalance", model.imbalance_shaft, model.imbalance_node);
  MatrixRubModel matrices;
  for (std::size_t k = 0; k < model.contacts.size(); ++k) {
    const FlexibleContact& c = model.contacts[k];
    const std::string key = fmt::format("contacts[{}].", k);
    CheckContactNode(model.beams, key + "rotor", c.rotor_shaft, c.rotor_node);
    CheckContactNode(model.beams, key + "stator", c.stator_shaft, c.stator_node);
    if (c.rotor_shaft == c.stator_shaft) {
      throw std::invalid_argument(fmt::format(
          "{}stator_shaft = {}: must differ from rotor_shaft (a contact joins two shafts)", key,
          c.stator_shaft));
    }
    matrices.contacts.push_back({c.name, model.beams.Coordinate(c.rotor_shaft, c.rotor_node, 0),
                                 model.beams.Coordinate(c.stator_shaft, c.stator_node, 0),
                                 c.geometry});
  }
  matrices.full = Assemble(model.beams);
  matrices.modes = model.modes;
  matrices.modal_damping = model.modal_damping;
  matrices.gyroscopic = model.gyroscopic;
  matrices.law = model.law;
  matrices.imbalance = model.imbalance;
  matrices.imbalance_coordinate =
      model.beams.Coordinate(model.imbalance_shaft, model.imbalance_node, 0);
  return matrices;
}

FlexibleRub BuildMatrixRub(const MatrixRubModel& model) {
  CheckStructuralMatrices(model.full);
  if (model.contacts.empty()) {
    throw std::invalid_argument("contacts: at least one contact is needed");
  }
  if (!(model.modal_damping >= 0.0) || !std::isfinite(model.modal_damping)) {
    throw std::invalid_argument(
        fmt::format("modal_damping = {}: must be finite and non-negative", model.modal_damping));
  }
  if (!(model.imbalance >= 0.0) || !std::isfinite(model.imbalance)) {
    throw std::invalid_argument(
        fmt::format("imbalance = {}: must be finite and non-negative (kg·m)", model.imbalance));
  }
  const Index n = model.full.Coordinates();
  auto check_coordinate = [&](const std::string& key, Index i) {
    if (i < 0 || i >= n) {
      throw std::invalid_argument(fmt::format(
          "{} = {}: must be a coordinate of the matrices (0 to {})", key, i, n - 1));
    }
  };
  check_coordinate("imbalance_coordinate", model.imbalance_coordinate);
  const Index m = static_cast<Index>(model.contacts.size());
  std::vector<Index> boundary(static_cast<std::size_t>(2 * m));
  for (Index k = 0; k < m; ++k) {
    const MatrixContact& c = model.contacts[static_cast<std::size_t>(k)];
    check_coordinate(fmt::format("contacts[{}].rotor", k), c.rotor);
    check_coordinate(fmt::format("contacts[{}].stator", k), c.stator);
    boundary[static_cast<std::size_t>(k)] = c.rotor;
    boundary[static_cast<std::size_t>(m + k)] = c.stator;
  }
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (boundary[i] == boundary[j]) {
        throw std::invalid_argument(fmt::format(
            "contacts[{}]: touches at a node another contact already uses", i % m));
      }
    }
  }
  FlexibleRub out;
  out.full = model.full;
  out.reduction = CraigBampton(out.full, boundary, model.modes);
  const StructuralMatrices reduced = out.reduction.Reduce(out.full);
  // A massless coordinate is condensed away by the constraint modes; a massless contact is not.
  const Eigen::LLT<Matrix> reduced_mass(reduced.mass);
  if (reduced_mass.info() != Eigen::Success) {
    throw std::invalid_argument(
        "mass: not positive definite on the contact coordinates and the kept modes: a contact "
        "coordinate moves no mass (neither its own nor, through its constraint mode, the "
        "interior's)");
  }

  RubStructure& s = out.structure;
  s.mass = reduced.mass;
  s.stiffness = reduced.stiffness;
  s.damping = reduced.damping;
  for (Index j = 0; j < model.modes; ++j) {
    s.damping(2 * m + j, 2 * m + j) +=
        2.0 * model.modal_damping * out.reduction.interface_frequencies(j);
  }
  if (model.gyroscopic) s.gyroscopic = reduced.gyroscopic;
  s.law = model.law;
  s.imbalance = model.imbalance;
  s.imbalance_weights = out.reduction.basis.row(model.imbalance_coordinate).transpose();
  for (Index k = 0; k < m; ++k) {
    const MatrixContact& c = model.contacts[static_cast<std::size_t>(k)];
    s.contacts.push_back(RubContact{static_cast<int>(k), static_cast<int>(m + k), c.geometry,
                                    c.name});
  }
  for (Index k = 0; k < m; ++k) s.coordinate_names.push_back("rotor_" + model.contacts[k].name);
  for (Index k = 0; k < m; ++k) s.coordinate_names.push_back("stator_" + model.contacts[k].name);
  for (Index j = 0; j < model.modes; ++j) s.coordinate_names.push_back(fmt::format("mode_{}", j + 1));
  s.Validate();
  return out;
}

void CheckStructuralMatrices(const StructuralMatrices& matrices) {
  const Index n = matrices.mass.rows();
  if (n < 1 || matrices.mass.cols() != n) {
    throw std::invalid_argument(fmt::format(
        "mass: is {} × {}: must be square with at least one coordinate", n, matrices.mass.cols()));
  }
  const std::array<std::pair<const char*, const Matrix*>, 4> all = {{
      {"mass", &matrices.mass}, {"damping", &matrices.damping},
      {"stiffness", &matrices.stiffness}, {"gyroscopic", &matrices.gyroscopic}}};
  for (const auto& [name, x] : all) {
    if (x->rows() != n || x->cols() != n) {
      throw std::invalid_argument(fmt::format("{}: is {} × {}: must be {} × {}, as the mass", name,
                                              x->rows(), x->cols(), n, n));
    }
    if (!x->allFinite()) throw std::invalid_argument(fmt::format("{}: has a NaN or infinite entry", name));
    const double largest = x->cwiseAbs().maxCoeff();
    Index row = 0, col = 0;
    const double asymmetry = (*x - x->transpose()).cwiseAbs().maxCoeff(&row, &col);
    if (row > col) std::swap(row, col);  // the upper entry first, whichever maxCoeff found
    if (asymmetry > 1e-10 * largest) {
      throw std::invalid_argument(fmt::format(
          "{}: not symmetric: entry ({}, {}) − entry ({}, {}) = {:.3g} (largest |entry| {:.3g}): "
          "must agree to 1e-10 of it",
          name, row, col, col, row, (*x)(row, col) - (*x)(col, row), largest));
    }
  }
  // Semi-definiteness from the eigenvalues (n is an FE model's few hundred coordinates): M may be
  // singular (massless rotations of lumped masses; BuildMatrixRub asks the reduced M to be definite).
  for (const auto& [name, x] : {all[0], all[1], all[2]}) {
    const Eigen::SelfAdjointEigenSolver<Matrix> eig(0.5 * (*x + x->transpose()),
                                                     Eigen::EigenvaluesOnly);
    const Vector& lambda = eig.eigenvalues();
    const double scale = lambda.cwiseAbs().maxCoeff();
    if (lambda.minCoeff() < -1e-10 * scale) {
      throw std::invalid_argument(fmt::format(
          "{}: not positive semi-definite: smallest eigenvalue {:.3g} (largest {:.3g}): must be "
          "≥ −1e-10 of the largest", name, lambda.minCoeff(), scale));
    }
  }
}

RigidBodyData RigidBodyOf(const BodyShaft& body) {
  const Shaft& shaft = body.shaft;
  BeamModel{{shaft}, {}}.Validate();
  const int nodes = shaft.Nodes();
  for (int side = 0; side < 2; ++side) {
    const int station = body.contact_stations[static_cast<std::size_t>(side)];
    if (station < 0 || station >= nodes) {
      throw std::invalid_argument(
          fmt::format("{} shaft: contact_stations[{}] = {}: must name a station (0 to {})",
                      shaft.name, side, station, nodes - 1));
    }
  }
  const std::vector<double> z = shaft.NodePositions();
  const double left = z[static_cast<std::size_t>(body.contact_stations[0])];
  const double right = z[static_cast<std::size_t>(body.contact_stations[1])];
  if (!(right > left)) {
    throw std::invalid_argument(fmt::format(
        "{} shaft: contact_stations = [{}, {}]: the right contact must lie beyond the left one",
        shaft.name, body.contact_stations[0], body.contact_stations[1]));
  }
  // Masses at their centres, then the parallel-axis sum about the common centre.
  struct Piece { double mass, z, own_inertia; };
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < shaft.elements.size(); ++i) {
    const ShaftElement& e = shaft.elements[i];
    const double mass = e.density * e.Area() * e.length;
    const double d2 = e.outer_diameter * e.outer_diameter + e.inner_diameter * e.inner_diameter;
    pieces.push_back({mass, z[i] + e.length / 2, mass * (e.length * e.length / 12 + d2 / 16)});
  }
  for (const Disk& d : shaft.disks) {
    pieces.push_back({d.mass, z[static_cast<std::size_t>(d.node)], d.diametral_inertia});
  }
  RigidBodyData out;
  double moment = 0.0;
  for (const Piece& p : pieces) {
    out.mass += p.mass;
    moment += p.mass * p.z;
  }
  if (!(out.mass > 0.0)) {
    throw std::invalid_argument(fmt::format("{} shaft: has no mass (its elements' density and its "
                                            "disks' masses are all 0)", shaft.name));
  }
  const double center = moment / out.mass;
  for (const Piece& p : pieces) {
    out.inertia += p.own_inertia + p.mass * (p.z - center) * (p.z - center);
  }
  out.span = right - left;
  out.mass_center = center - left;
  return out;
}

BodyShaft UniformBody(const std::string& name, const ShaftElement& section, double span,
                      int elements, double mass, double inertia, double mass_center,
                      const std::vector<double>& extra) {
  if (elements < 1) {
    throw std::invalid_argument(fmt::format("elements = {}: must be at least 1", elements));
  }
  const double line_mass = section.density * section.Area();  // [kg/m]
  // The shaft covers [a, b] ⊇ [0, span] and the disk at z_d, where the mass centre is l_g,
  // with a = min(0, z_d), b = max(span, z_d); a fixed-point iteration from [0, span] (the shaft
  // is lighter than the body, so each extension moves the disk less than the one before).
  double a = 0.0, b = span, disk_z = 0.0, shaft_mass = 0.0, disk_mass = 0.0;
  for (int iteration = 0;; ++iteration) {
    shaft_mass = line_mass * (b - a);
    disk_mass = mass - shaft_mass;
    if (!(disk_mass > 0.0)) {
      throw ModelInputError(name + " section", fmt::format(
          "{} shaft: {:.4g} kg over {:.4g} m is not lighter than the body ({:.4g} kg): take a "
          "thinner section", name, shaft_mass, b - a, mass));
    }
    // z_d = l_g + m_s (l_g − (a + b)/2)/m_d: no cancellation when the shaft weighs nearly all of
    // the body and its centre is the body's (the written-out (m l_g − m_s c)/m_d put a stator
    // tube's 1e-6 kg disk 1e-4 m off the centre and broke A(a)'s left–right symmetry).
    disk_z = mass_center + shaft_mass * (mass_center - (a + b) / 2) / disk_mass;
    const double next_a = std::min(0.0, disk_z), next_b = std::max(span, disk_z);
    if (std::abs(next_a - a) + std::abs(next_b - b) <= 1e-15 * span) break;
    if (iteration == 200) {
      throw ModelInputError(name + " section", fmt::format(
          "{} shaft: no disk position completes the body (the shaft's extension to reach it does "
          "not settle): take a thinner section", name));
    }
    a = next_a;
    b = next_b;
  }
  const double length = b - a;
  const double d2 = section.outer_diameter * section.outer_diameter +
                    section.inner_diameter * section.inner_diameter;
  const double shaft_inertia = shaft_mass * (length * length / 12 + d2 / 16) +
                               shaft_mass * std::pow((a + b) / 2 - mass_center, 2);
  const double disk_inertia =
      inertia - shaft_inertia - disk_mass * std::pow(disk_z - mass_center, 2);
  if (!(disk_inertia >= 0.0)) {
    throw ModelInputError(name + " section", fmt::format(
        "{} shaft: its transverse inertia leaves the disk {:.4g} kg·m²: take a thinner section", name,
        disk_inertia));
  }
  // The ends, the span's ends, the extra positions and the disk exactly; the even grid's nodes
  // where they are at least a quarter element from those (a sliver element would make the
  // stiffness ill-conditioned).
  std::vector<double> fixed = {a, 0.0, span, b, disk_z};
  fixed.insert(fixed.end(), extra.begin(), extra.end());
  const double h = length / elements;
  std::vector<double> z = fixed;
  for (int i = 1; i < elements; ++i) {
    const double x = a + h * i;
    if (std::all_of(fixed.begin(), fixed.end(), [&](double f) { return std::abs(f - x) >= h / 4; })) {
      z.push_back(x);
    }
  }
  std::sort(z.begin(), z.end());
  std::vector<double> nodes;
  for (double x : z) {
    if (nodes.empty() || x - nodes.back() > 1e-9 * span) nodes.push_back(x);
  }
  BodyShaft out;
  out.shaft.name = name;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    ShaftElement e = section;
    e.length = nodes[i + 1] - nodes[i];
    out.shaft.elements.push_back(e);
  }
  auto node_at = [&](double x) {
    const auto it = std::min_element(nodes.begin(), nodes.end(), [&](double p, double q) {
      return std::abs(p - x) < std::abs(q - x);
    });
    return static_cast<int>(it - nodes.begin());
  };
  out.contact_stations = {node_at(0.0), node_at(span)};
  out.shaft.disks = {{node_at(disk_z), disk_mass, disk_inertia, 2 * disk_inertia}};
  return out;
}

namespace {

// The station of `body` nearest z (from its left contact) and how far it is from z.
std::pair<int, double> NearestStation(const BodyShaft& body, double z) {
  const std::vector<double> nodes = body.shaft.NodePositions();
  const double target = nodes[static_cast<std::size_t>(body.contact_stations[0])] + z;
  int best = 0;
  for (int i = 1; i < body.shaft.Nodes(); ++i) {
    if (std::abs(nodes[static_cast<std::size_t>(i)] - target) <
        std::abs(nodes[static_cast<std::size_t>(best)] - target)) {
      best = i;
    }
  }
  return {best, std::abs(nodes[static_cast<std::size_t>(best)] - target)};
}

// The station at the mid-span of the body's contacts (`data` its RigidBodyOf), which c_d > 0 needs.
int MidSpanStation(const BodyShaft& body, const RigidBodyData& data, double center_damping) {
  const auto [station, distance] = NearestStation(body, data.span / 2);
  if (distance > 1e-9 * data.span) {
    throw std::invalid_argument(fmt::format(
        "{} shaft: center_damping = {} N·s/m acts at the mid-span of the contacts, {:.6g} m from "
        "the left one, where the shaft has no station (the nearest, {}, is {:.3g} m away)",
        body.shaft.name, center_damping, data.span / 2, station, distance));
  }
  return station;
}

}  // namespace

FlexibleRubModel FlexibleTwoPoint(const TwoPointParams& p, const BodyShaft& rotor,
                                  const BodyShaft& stator, int modes) {
  Validate(p);
  const RigidBodyData rotor_data = RigidBodyOf(rotor), stator_data = RigidBodyOf(stator);
  FlexibleRubModel model;
  model.beams.shafts = {rotor.shaft, stator.shaft};
  model.beams.springs = {
      {1, stator.contact_stations[0], -1, 0, p.support_stiffness[0], p.support_damping[0]},
      {1, stator.contact_stations[1], -1, 0, p.support_stiffness[1], p.support_damping[1]}};
  if (p.center_damping > 0.0) {
    model.beams.springs.push_back({0, MidSpanStation(rotor, rotor_data, p.center_damping), 1,
                                   MidSpanStation(stator, stator_data, p.center_damping), 0.0,
                                   p.center_damping});
  }
  model.contacts = {
      {"left", 0, rotor.contact_stations[0], 1, stator.contact_stations[0],
       {p.clearance[0], p.radius[0]}},
      {"right", 0, rotor.contact_stations[1], 1, stator.contact_stations[1],
       {p.clearance[1], p.radius[1]}}};
  model.modes = modes;
  model.law = ContactLawOf(p);
  model.imbalance = p.imbalance;
  model.imbalance_shaft = 0;
  model.imbalance_node = NearestStation(rotor, rotor_data.mass_center).first;
  return model;
}

BodyShaft UniformRotor(const TwoPointParams& p, const ShaftElement& section, int elements) {
  return UniformBody("rotor", section, p.contact_span, elements, p.rotor_mass, p.rotor_inertia,
                     p.rotor_mass_center, {p.contact_span / 2, p.rotor_mass_center});
}

BodyShaft UniformStator(const TwoPointParams& p, const ShaftElement& section, int elements) {
  return UniformBody("stator", section, p.stator_span, elements, p.stator_mass, p.stator_inertia,
                     p.stator_mass_center, {p.stator_span / 2});
}

FlexibleRubModel FlexibleTwoPoint(const TwoPointParams& p, const ShaftElement& rotor_section,
                                  const ShaftElement& stator_section, int elements, int modes) {
  Validate(p);
  return FlexibleTwoPoint(p, UniformRotor(p, rotor_section, elements),
                          UniformStator(p, stator_section, elements), modes);
}

std::vector<StructureMode> StructureModes(const RubStructure& structure, bool pinned, double spin,
                                      bool backward) {
  structure.Validate();
  const Index n = structure.Coordinates();
  // u = T v: pinning keeps each contact's rotor coordinate and sets its stator one equal to it.
  std::vector<Index> column(static_cast<std::size_t>(n), -1);
  if (pinned) {
    for (const RubContact& c : structure.contacts) column[static_cast<std::size_t>(c.stator)] = -2;
  }
  Index kept = 0;
  for (Index i = 0; i < n; ++i) {
    if (column[static_cast<std::size_t>(i)] == -1) column[static_cast<std::size_t>(i)] = kept++;
  }
  Matrix t = Matrix::Zero(n, kept);
  for (Index i = 0; i < n; ++i) {
    if (column[static_cast<std::size_t>(i)] >= 0) t(i, column[static_cast<std::size_t>(i)]) = 1.0;
  }
  if (pinned) {
    for (const RubContact& c : structure.contacts) {
      t(c.stator, column[static_cast<std::size_t>(c.rotor)]) = 1.0;
    }
  }
  const Matrix gyroscopic =
      structure.gyroscopic.size() != 0 ? structure.gyroscopic : Matrix::Zero(n, n);
  const StructuralMatrices m{t.transpose() * structure.mass * t,
                             t.transpose() * structure.damping * t,
                             t.transpose() * structure.stiffness * t,
                             t.transpose() * gyroscopic * t};
  return WhirlModes(m, spin, {}, backward);
}

}  // namespace rubcont
