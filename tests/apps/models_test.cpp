#include "apps/models.h"

#include <set>
#include <string>

#include <catch2/catch.hpp>

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

}  // namespace
}  // namespace rubcont
