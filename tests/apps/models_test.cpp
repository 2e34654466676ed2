#include "apps/models.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "apps/stage_options.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

const std::vector<ModelKind> kEveryKind = {ModelKind::kTwoPoint, ModelKind::kJeffcott,
                                          ModelKind::kDuffing, ModelKind::kStuartLandau,
                                          ModelKind::kVanDerPol, ModelKind::kForcedVanDerPol};

TEST_CASE("Every model kind has one entry, and every entry can run each stage it lists", "[models]") {
  REQUIRE(Models().size() == kEveryKind.size());
  std::set<std::string> names;
  for (ModelKind kind : kEveryKind) {
    const ModelEntry& m = ModelOf(kind);
    CAPTURE(m.name);
    CHECK(m.kind == kind);
    CHECK(std::string(ToString(kind)) == m.name);
    CHECK(names.insert(m.name).second);
    REQUIRE_FALSE(m.stages.empty());
    for (Stage stage : m.default_stages) CHECK(m.Has(stage));
    CHECK(m.Has(Stage::kAnalytic) == static_cast<bool>(m.analytic));
    CHECK(m.Has(Stage::kOrbits) == static_cast<bool>(m.orbits));
    CHECK(m.Has(Stage::kOrbits) == !m.orbits_figure.empty());
    // Rotating waves and sweeps integrate a rub structure.
    if (m.Has(Stage::kBranches) || m.Has(Stage::kSweep)) {
      CHECK(m.IsRub());
      CHECK(static_cast<bool>(m.wave_friction));
    }
    CHECK(m.IsRub() == static_cast<bool>(m.wave_friction));
  }
}

// The sections of the key reference ("### [rotor]", "### [[flexible.rotor_shaft]]").
std::vector<std::string> ReferenceSections() {
  std::vector<std::string> sections;
  std::istringstream keys(SceneKeysMarkdown());
  for (std::string line; std::getline(keys, line);) {
    if (line.rfind("### [", 0) != 0) continue;
    const std::size_t open = line.find_first_not_of('[', 4), close = line.find(']');
    sections.push_back(line.substr(open, close - open));
  }
  return sections;
}

TEST_CASE("Every section of the schema is a model's, and every model's sections are the schema's",
          "[models]") {
  const std::vector<std::string> sections = ReferenceSections();
  REQUIRE(sections.size() > 20);
  for (const std::string& section : sections) {
    CAPTURE(section);
    int owners = 0;
    for (const ModelEntry& m : Models()) owners += m.HasSection(section) ? 1 : 0;
    // [analysis] itself is every model's; any other section belongs to one model.
    CHECK(owners == (section == "analysis" ? static_cast<int>(Models().size()) : 1));
  }
  for (const ModelEntry& m : Models()) {
    for (const std::string& own : m.sections) {
      CAPTURE(m.name, own);
      CHECK(std::find(sections.begin(), sections.end(), own) != sections.end());
    }
  }
  const ModelEntry& two_point = ModelOf(ModelKind::kTwoPoint);
  CHECK(two_point.HasSection("contact.friction_law"));
  CHECK(two_point.HasSection("analysis.orbits.transient"));
  CHECK(two_point.HasSection(""));
  CHECK_FALSE(two_point.HasSection("jeffcott"));
  CHECK_FALSE(two_point.HasSection("rotorx"));  // a prefix of the name is not a sub-table
  CHECK(ModelOf(ModelKind::kDuffing).HasSection("duffing.orbits"));
  CHECK_FALSE(ModelOf(ModelKind::kDuffing).HasSection("analysis.orbits"));
}

TEST_CASE("The scene of each model selects its entry, runs its default stages and is described",
          "[models]") {
  const std::vector<std::pair<std::string, ModelKind>> scenes = {
      {"scenes/default.toml", ModelKind::kTwoPoint},
      {"scenes/jeffcott.toml", ModelKind::kJeffcott},
      {"scenes/duffing.toml", ModelKind::kDuffing},
      {"scenes/stuart_landau.toml", ModelKind::kStuartLandau},
      {"scenes/van_der_pol.toml", ModelKind::kVanDerPol},
      {"scenes/forced_van_der_pol.toml", ModelKind::kForcedVanDerPol}};
  for (const auto& [file, kind] : scenes) {
    CAPTURE(file);
    const Scene scene = LoadScene(file);
    const ModelEntry& m = ModelOf(scene);
    CHECK(m.kind == kind);
    for (Stage stage : scene.analysis.stages) CHECK(m.Has(stage));
    if (m.IsRub()) {
      const RubStructure structure = StructureOf(scene);
      CHECK(structure.contacts.size() == (kind == ModelKind::kTwoPoint ? 2u : 1u));
      CHECK(FrictionLawOf(scene) == m.wave_friction(scene));
    } else {
      CHECK_THROWS_WITH(StructureOf(scene),
                        Contains("rotating waves need a rub model (two_point, jeffcott)"));
      CHECK_FALSE(m.parameter.empty());
    }
    if (m.derived) CHECK_THAT(DescribeScene(scene), Contains(m.derived(scene)));
  }
}

TEST_CASE("Sweeps and the two-point commands name the models they need", "[models]") {
  const Scene jeffcott = LoadScene("scenes/jeffcott.toml");
  CHECK_THROWS_WITH(SweepStructureOf(jeffcott),
                    Contains("the sweep stage needs a model that has it (\"two_point\")"));
  CHECK_THROWS_WITH(TwoPointParamsOf(jeffcott, "rubcont map"),
                    Contains("model = \"jeffcott\" in scene jeffcott: rubcont map needs the "
                             "two_point model"));
  CHECK(ModelsWith(Stage::kOrbits) ==
        "\"two_point\", \"duffing\", \"stuart_landau\", \"van_der_pol\", "
        "\"forced_van_der_pol\"");
}

TEST_CASE("[flexible]: a listed body written out element by element is the uniform body",
          "[models]") {
  // scenes/thesis_A_a_flexible.toml's uniform shafts (each completed by its disk) as rows, every
  // number to full precision, [rotor]/[stator] supplied by them: the same reduced structure.
  const Scene uniform = LoadScene("scenes/thesis_A_a_flexible.toml");
  const FlexibleRubModel model = FlexibleModelOf(uniform);
  std::string text = "[contact]\nclearance = [3.81e-4, 3.81e-4]\nradius = [38.1e-3, 38.1e-3]\n"
                     "friction = 0.5\nstiffness = 1.75e11\nstiffness2 = 0.0\ndamping = 1.75e5\n"
                     "[center_damper]\ndamping = 52.0\n"
                     "[flexible]\nyoungs_modulus = 2.0684e11\nshear_modulus = 7.929e10\n"
                     "density = 7833.0\n";
  for (std::size_t b = 0; b < 2; ++b) {
    const Shaft& shaft = model.beams.shafts[b];
    for (const ShaftElement& e : shaft.elements) {
      text += fmt::format("[[flexible.{}_shaft]]\nlength = {}\nouter_diameter = {}\n"
                          "inner_diameter = {}\n", shaft.name, e.length, e.outer_diameter,
                          e.inner_diameter);
    }
    for (const Disk& d : shaft.disks) {
      text += fmt::format("[[flexible.{}_disks]]\nstation = {}\nmass = {}\ndiametral_inertia = {}\n"
                          "polar_inertia = {}\n", shaft.name, d.node, d.mass, d.diametral_inertia,
                          d.polar_inertia);
    }
  }
  text += "[[flexible.stator_supports]]\nstation = 0\nstiffness = 4.70e6\ndamping = 324.9\n"
          "[[flexible.stator_supports]]\nstation = 8\nstiffness = 4.70e6\ndamping = 324.9\n";
  const Scene listed = ParseScene(text, "listed.toml", "listed");
  REQUIRE(listed.flexible.RotorListed());
  REQUIRE(listed.flexible.StatorListed());
  // The rigid data the rows supply are Eq. 31's.
  CHECK(listed.two_point.rotor_mass == Approx(9.99).epsilon(1e-13));
  CHECK(listed.two_point.rotor_inertia == Approx(0.029).epsilon(1e-12));
  CHECK(listed.two_point.stator_inertia == Approx(0.206).epsilon(1e-12));
  CHECK(listed.two_point.support_stiffness == uniform.two_point.support_stiffness);
  const RubStructure a = StructureOf(uniform), b = StructureOf(listed);
  REQUIRE(a.Coordinates() == b.Coordinates());
  CHECK((a.mass - b.mass).norm() <= 1e-13 * a.mass.norm());
  CHECK((a.stiffness - b.stiffness).norm() <= 1e-13 * a.stiffness.norm());
  CHECK((a.damping - b.damping).norm() <= 1e-13 * a.damping.norm());
  CHECK((a.gyroscopic - b.gyroscopic).norm() <= 1e-13 * a.gyroscopic.norm());
}

}  // namespace
}  // namespace rubcont
