// apps/ross_import.h: a ROSS rotor file (tests/apps/ross/rotor.toml, written in the format
// ross.Rotor.save writes) as a scene. The oracle is the same rotor written by hand as rows
// (tests/apps/ross/rotor_by_hand.toml): the same matrices, so the same L1 points; and every
// element the rows cannot hold refused by name and rule.
#include "apps/ross_import.h"

#include <fstream>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "apps/models.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "cli_support.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

using Catch::Contains;
using testing::TempDir;

constexpr const char* kRoss = "tests/apps/ross/rotor.toml";
constexpr const char* kBase = "tests/apps/ross/base.toml";
constexpr const char* kByHand = "tests/apps/ross/rotor_by_hand.toml";

struct Imported {
  int exit_code = -1;
  std::string text, err;
};

Imported Import(const std::string& ross_file, std::array<int, 2> stations = {1, 5}) {
  ImportRossRequest request;
  request.ross_file = ross_file;
  request.base_scene = kBase;
  request.contact_stations = stations;
  std::ostringstream out, err;
  Imported result;
  result.exit_code = ImportRossCommand(request, out, err);
  result.text = out.str();
  result.err = err.str();
  return result;
}

TEST_CASE("import-ross: the ROSS rotor is the rotor written by hand", "[ross_import]") {
  const RossRotor rotor = ReadRossRotor(kRoss);
  CHECK(rotor.version == "2.3.0");
  REQUIRE(rotor.shaft.size() == 6);
  CHECK(rotor.shaft[2].section.inner_diameter == 0.01);
  CHECK(rotor.shaft[2].section.shear_modulus == 81.2e9);
  REQUIRE(rotor.disks.size() == 2);  // the point mass at node 1, the disk at node 3
  CHECK(rotor.disks[0].node == 1);
  CHECK(rotor.disks[0].diametral_inertia == 0.0);
  CHECK(rotor.disks[1].polar_inertia == 0.06);
  REQUIRE(rotor.supports.size() == 3);  // bearings at 0 and 6, the seal (constant over frequency) at 5
  CHECK(rotor.supports[1].station == 5);
  CHECK(rotor.supports[1].stiffness == 1e5);
  CHECK(rotor.supports[1].damping == 50.0);

  const Imported imported = Import(kRoss);
  REQUIRE(imported.exit_code == 0);
  const Scene a = ParseScene(imported.text, "imported", "imported");
  const Scene b = LoadScene(kByHand);
  // The bearings leave the rigid closed form out.
  CHECK(a.analysis.stages == std::vector<Stage>{Stage::kBranches});
  CHECK_THAT(imported.text, Contains("# Stage \"analytic\" left out: the rigid model's rotor has no "
                                     "bearings"));
  CHECK(a.two_point.rotor_mass == b.two_point.rotor_mass);
  CHECK(a.two_point.rotor_inertia == b.two_point.rotor_inertia);
  const MatrixRubModel ma = FlexibleMatricesOf(a), mb = FlexibleMatricesOf(b);
  CHECK(ma.full.mass == mb.full.mass);
  CHECK(ma.full.damping == mb.full.damping);
  CHECK(ma.full.stiffness == mb.full.stiffness);
  CHECK(ma.full.gyroscopic == mb.full.gyroscopic);
  const RubStructure sa = StructureOf(a), sb = StructureOf(b);
  CHECK(sa.mass == sb.mass);
  CHECK(sa.stiffness == sb.stiffness);
  CHECK(sa.damping == sb.damping);
  CHECK(sa.gyroscopic == sb.gyroscopic);
  // And so the L1 points (exact friction, 20–200 rpm).
  const auto wa = ComputeRotatingWaveBranches(sa, FrictionLawOf(a), BranchOptionsOf(a));
  const auto wb = ComputeRotatingWaveBranches(sb, FrictionLawOf(b), BranchOptionsOf(b));
  REQUIRE(wa.size() == wb.size());
  REQUIRE(!wa.empty());
  for (std::size_t i = 0; i < wa.size(); ++i) {
    REQUIRE(wa[i].branch.special_points.size() == wb[i].branch.special_points.size());
    for (std::size_t k = 0; k < wa[i].branch.special_points.size(); ++k) {
      const double la = wa[i].branch.special_points[k].lambda;
      CHECK(std::abs(la - wb[i].branch.special_points[k].lambda) <= 1e-10 * la);
    }
  }
}

TEST_CASE("import-ross: what the rows cannot hold is refused, naming the element and the rule",
          "[ross_import]") {
  TempDir dir;
  const std::string good = testing::Slurp(kRoss);
  // In the element whose table header is `anchor`, `from` replaced by `to`: the message.
  struct Case {
    std::string anchor, from, to, message;
  };
  const std::vector<Case> cases = {
      {"[\"BearingElement_Bearing 1\"]", "kyy = [ 10000000.0,]", "kyy = [ 8000000.0,]",
       "[\"BearingElement_Bearing 1\"] anisotropic (kxx = 10000000, kyy = 8000000, cxx = 100, "
       "cyy = 100): rubcont's supports act alike in x and y"},
      {"[\"BearingElement_Bearing 0\"]", "kxy = [ 0,]", "kxy = [ 2500.0,]",
       "[\"BearingElement_Bearing 0\"] kxy = 2500: cross-coupled: rubcont's supports are "
       "isotropic springs and dashpots"},
      {"[\"SealElement_Seal 0\"]", "kxx = [ 100000.0, 100000.0,]", "kxx = [ 100000.0, 120000.0,]",
       "[\"SealElement_Seal 0\"] kxx: varies with frequency (2 values, 100000 … 120000): "
       "rubcont's supports have constant coefficients"},
      {"[\"ShaftElement_ShaftElement 4\"]", "odr = 0.05", "odr = 0.04",
       "[\"ShaftElement_ShaftElement 4\"] tapered (idl = 0.0, idr = 0.0, odl = 0.05, odr = 0.04): "
       "rubcont's elements are uniform"},
      {"[\"ShaftElement_ShaftElement 1\"]", "shear_effects = true", "shear_effects = false",
       "[\"ShaftElement_ShaftElement 1\"] shear_effects: must be true"},
      {"[\"ShaftElement_ShaftElement 3\".material]", "G_s = 81200000000.0", "nu = 0.3",
       "[\"ShaftElement_ShaftElement 3\".material] Poisson: missing"},
      {"[\"BearingElement_Bearing 0\"]", "[\"BearingElement_Bearing 0\"]",
       "[\"BallBearingElement_Bearing 0\"]",
       "[\"BallBearingElement_Bearing 0\"] class BallBearingElement: not one rubcont reads"},
      {"[\"ShaftElement_ShaftElement 5\"]", "n = 5", "n = 4",
       "[\"ShaftElement_ShaftElement 5\"] n = 4: [\"ShaftElement_ShaftElement 4\"] starts at "
       "node 4 too"},
      {"[\"DiskElement_Disk 0\"]", "n = 3", "n = 7",
       "[\"DiskElement_Disk 0\"] n = 7: must be a node of the shaft (0 to 6)"},
  };
  for (const Case& c : cases) {
    INFO(c.anchor << ": " << c.from << " → " << c.to);
    std::string text = good;
    const std::size_t at = text.find(c.from, text.find(c.anchor));
    REQUIRE(at != std::string::npos);
    text.replace(at, c.from.size(), c.to);
    const testing::fs::path file = dir.path / "rotor.toml";
    std::ofstream(file) << text;
    const Imported imported = Import(file.string());
    CHECK(imported.exit_code == 2);
    CHECK_THAT(imported.err, Contains(c.message));
  }
  // The contacts must be nodes of the rotor; the scene it makes must load.
  CHECK_THAT(Import(kRoss, {1, 7}).err, Contains("--contact-stations 1 7: must be ROSS nodes"));
}

TEST_CASE("import-ross --out writes the scene, and rotor supports rule out stage analytic",
          "[ross_import]") {
  TempDir dir;
  const std::string out = (dir.path / "ross_rotor.toml").string();
  const testing::Outcome o = testing::RubcontNoPython(std::string("scene import-ross ") + kRoss +
                                                      " --base " + kBase +
                                                      " --contact-stations 1 5 --out " + out);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.err, Contains("wrote " + out + " (6 shaft elements, 2 disks, 3 supports)"));
  const Scene scene = LoadScene(out);
  CHECK(scene.name == "ross_rotor");
  CHECK(scene.flexible.rotor_supports.size() == 3);
  // A scene that lists the stage anyway is told why it does not apply.
  std::string text = testing::Slurp(kByHand);
  text.replace(text.find("stages = [\"branches\"]"), 21, "stages = [\"analytic\", \"branches\"]");
  CHECK_THROWS_WITH(ParseScene(text, "by_hand.toml", "by_hand"),
                    Contains("analysis.stages = [\"analytic\", \"branches\"]: \"analytic\" (L0) does "
                             "not apply: the rigid model's rotor has no bearings"));
}

}  // namespace
}  // namespace rubcont
