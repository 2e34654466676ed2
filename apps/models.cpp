#include "apps/models.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/analytic_stage.h"
#include "apps/orbits_stage.h"
#include "models/flexible.h"
#include "models/jeffcott.h"

namespace rubcont {

namespace {

std::string TwoPointDerived(const Scene& scene) {
  const TwoPointParams& p = scene.two_point;
  return fmt::format(
      "derived:\n  a = l_g/l = {:.6g}{}\n  b = l_sg/l_s = {:.6g}\n  RCI_L = R_L/C_L = {:.6g}, "
      "RCI_R = R_R/C_R = {:.6g}\n",
      p.a(), p.a() > 1.0 || p.a() < 0.0 ? " (overhung)" : "", p.b(), p.Rci(0), p.Rci(1));
}

std::string JeffcottDerived(const Scene& scene) {
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(scene.jeffcott);
  return fmt::format(
      "derived:\n  RCI = R/C = {:.6g}\n  rotor alone {:.6g} Hz, stator alone {:.6g} Hz, "
      "pinned together {:.6g} Hz\n",
      scene.jeffcott.R / scene.jeffcott.C, f.rotor_hz, f.stator_hz, f.combined_hz);
}

// A textbook model with a known answer (models/textbook.h), for checking the tool: the stage
// "orbits" only, continued in `parameter`.
ModelEntry Textbook(ModelKind kind, std::string name, std::string parameter, StageRunner orbits) {
  ModelEntry m;
  m.kind = kind;
  m.name = std::move(name);
  m.stages = m.default_stages = {Stage::kOrbits};
  m.sections = {m.name};  // [<name>] and [<name>.orbits]
  m.orbits = std::move(orbits);
  m.orbits_figure = "orbits";
  m.parameter = std::move(parameter);
  return m;
}

std::vector<ModelEntry> MakeModels() {
  std::vector<ModelEntry> models;

  ModelEntry two_point;  // rigid rotor and rigid stator touching at two planes (Kumar 2010)
  two_point.kind = ModelKind::kTwoPoint;
  two_point.name = "two_point";
  two_point.stages = {Stage::kAnalytic, Stage::kBranches, Stage::kOrbits, Stage::kTori,
                      Stage::kSweep, Stage::kLoop};
  two_point.default_stages = {Stage::kAnalytic, Stage::kBranches};
  two_point.sections = {"rotor", "stator", "contact", "imbalance", "center_damper", "flexible",
                        "analysis.sweep", "analysis.orbits", "analysis.tori", "analysis.loop"};
  two_point.structure = [](const Scene& s) {
    return s.flexible.enabled ? FlexibleRubOf(s).structure : TwoPointStructure(s.two_point);
  };
  two_point.wave_friction = [](const Scene& s) { return s.two_point.friction_law.kind; };
  two_point.analytic = RunTwoPointAnalytic;
  two_point.analytic_skipped = [](const Scene& s) {
    return s.flexible.enabled && !s.flexible.rotor_supports.empty()
               ? std::string("the rigid model's rotor has no bearings; this scene's has "
                             "[[flexible.rotor_supports]]")
               : std::string();
  };
  two_point.orbits = RunRubOrbits;
  two_point.orbits_figure = "rub_orbits";
  two_point.derived = TwoPointDerived;
  models.push_back(two_point);

  ModelEntry jeffcott;  // single-contact Jeffcott rotor with an elastic stator (Black, Crandall)
  jeffcott.kind = ModelKind::kJeffcott;
  jeffcott.name = "jeffcott";
  jeffcott.stages = jeffcott.default_stages = {Stage::kAnalytic, Stage::kBranches};
  jeffcott.sections = {"jeffcott"};
  jeffcott.structure = [](const Scene& s) { return JeffcottStructure(s.jeffcott); };
  jeffcott.wave_friction = [](const Scene& s) { return s.jeffcott.friction_law.kind; };
  jeffcott.analytic = RunJeffcottAnalytic;
  jeffcott.derived = JeffcottDerived;
  models.push_back(jeffcott);

  models.push_back(Textbook(ModelKind::kDuffing, "duffing", "frequency", RunDuffingOrbits));
  models.push_back(
      Textbook(ModelKind::kStuartLandau, "stuart_landau", "lambda", RunStuartLandauOrbits));
  models.push_back(Textbook(ModelKind::kVanDerPol, "van_der_pol", "mu", RunVanDerPolOrbits));
  models.push_back(Textbook(ModelKind::kForcedVanDerPol, "forced_van_der_pol", "frequency",
                            RunForcedVanDerPolOrbits));
  return models;
}

}  // namespace

BodyShaft ListedBody(const std::string& name, const std::vector<ShaftRow>& rows,
                     const std::vector<Disk>& disks, const std::array<int, 2>& contact_stations) {
  BodyShaft body;
  body.shaft.name = name;
  for (const ShaftRow& row : rows) {
    ShaftElement e = row.section;
    e.length = row.section.length / row.elements;
    body.shaft.elements.insert(body.shaft.elements.end(), static_cast<std::size_t>(row.elements), e);
  }
  body.shaft.disks = disks;
  body.contact_stations = contact_stations;
  if (body.contact_stations[1] < 0) body.contact_stations[1] = body.shaft.Nodes() - 1;
  return body;
}

FlexibleRubModel FlexibleModelOf(const Scene& scene) {
  const FlexibleSettings& f = scene.flexible;
  const TwoPointParams& p = scene.two_point;
  auto section = [&](double outer, double inner) {
    ShaftElement e;
    e.outer_diameter = outer;
    e.inner_diameter = inner;
    e.youngs_modulus = f.youngs_modulus;
    e.shear_modulus = f.shear_modulus;
    e.density = f.density;
    return e;
  };
  Validate(p);
  // Each body listed, or uniform as FlexibleTwoPoint's uniform form makes it.
  const BodyShaft rotor =
      f.RotorListed()
          ? ListedBody("rotor", f.rotor_shaft, f.rotor_disks, f.rotor_contact_stations)
          : UniformRotor(p, section(f.rotor_outer_diameter, f.rotor_inner_diameter), f.elements);
  const BodyShaft stator =
      f.StatorListed()
          ? ListedBody("stator", f.stator_shaft, f.stator_disks, f.stator_contact_stations)
          : UniformStator(p, section(f.stator_outer_diameter, f.stator_inner_diameter), f.elements);
  FlexibleRubModel model = FlexibleTwoPoint(p, rotor, stator, f.modes);
  for (const SupportRow& r : f.rotor_supports) {
    model.beams.springs.push_back({0, r.station, -1, 0, r.stiffness, r.damping});
  }
  model.modal_damping = f.modal_damping;
  model.gyroscopic = f.gyroscopic;
  return model;
}

MatrixRubModel MatrixModelOf(const Scene& scene) {
  const FlexibleSettings& f = scene.flexible;
  const MatrixSettings& m = f.matrices;
  const TwoPointParams& p = scene.two_point;
  MatrixRubModel model;
  model.full = m.full;
  for (std::size_t side = 0; side < 2; ++side) {
    model.contacts.push_back({side == 0 ? "left" : "right", m.rotor_contact_coordinates[side],
                              m.stator_contact_coordinates[side],
                              {p.clearance[side], p.radius[side]}});
  }
  model.modes = f.modes;
  model.modal_damping = f.modal_damping;
  model.gyroscopic = f.gyroscopic;
  model.law = ContactLawOf(p);
  model.imbalance = p.imbalance;
  model.imbalance_coordinate = m.imbalance_coordinate;
  return model;
}

MatrixRubModel FlexibleMatricesOf(const Scene& scene) {
  return scene.flexible.matrices.enabled ? MatrixModelOf(scene)
                                         : AssembledMatrices(FlexibleModelOf(scene));
}

FlexibleRub FlexibleRubOf(const Scene& scene) { return BuildMatrixRub(FlexibleMatricesOf(scene)); }

bool ModelEntry::Has(Stage stage) const {
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

bool ModelEntry::HasSection(const std::string& section) const {
  if (section.empty() || section == "analysis") return true;  // every model's
  for (const std::string& own : sections)
    if (section == own || section.rfind(own + ".", 0) == 0) return true;
  return false;
}

const std::vector<ModelEntry>& Models() {
  static const std::vector<ModelEntry> models = MakeModels();
  return models;
}

const ModelEntry& ModelOf(ModelKind kind) {
  for (const ModelEntry& m : Models())
    if (m.kind == kind) return m;
  // Every ModelKind has an entry (tests/apps/models_test.cpp): a missing one is a broken invariant.
  fmt::print(stderr, "rubcont: internal error: model kind {} has no entry in Models()\n",
             static_cast<int>(kind));
  std::abort();
}

const ModelEntry& ModelOf(const Scene& scene) { return ModelOf(scene.model); }

std::string ModelsWith(Stage stage) {
  std::string names;
  for (const ModelEntry& m : Models()) {
    if (!m.Has(stage)) continue;
    names += (names.empty() ? "\"" : ", \"") + m.name + "\"";
  }
  return names;
}

const char* ToString(ModelKind model) { return ModelOf(model).name.c_str(); }

}  // namespace rubcont
