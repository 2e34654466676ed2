// apps/structure_file.h and [flexible.matrices]: an FE model's matrices brought in. The oracle is
// the listed-shaft scene the matrices come from: written out and read back, the same matrices
// must give the same reduced structure and the same L1 points, in both formats.
#include "apps/structure_file.h"

#include <fstream>
#include <string>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "apps/models.h"
#include "apps/scene.h"
#include "apps/scene_schema.h"
#include "apps/stage_options.h"
#include "cli_support.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

using Catch::Contains;
using testing::TempDir;

constexpr const char* kListed = "scenes/thesis_A_a_flexible_listed.toml";

// The listed scene with its [flexible] section replaced by [flexible.matrices] on `file`, its
// rigid data (which the listed shafts supplied) written out, the speeds narrowed to keep L1 short.
std::string MatrixScene(const Scene& listed, const std::string& file, const MatrixRubModel& m) {
  const TwoPointParams& p = listed.two_point;
  using schema::FormatFloat;
  return fmt::format(
      "[rotor]\nmass = {}\ninertia = {}\ncontact_span = {}\nmass_center = {}\n"
      "[stator]\nmass = {}\ninertia = {}\nspan = {}\nmass_center = {}\n"
      "stiffness = [4.70e6, 4.70e6]\ndamping = [324.9, 324.9]\n"
      "[contact]\nclearance = [3.81e-4, 3.81e-4]\nradius = [38.1e-3, 38.1e-3]\nfriction = 0.5\n"
      "stiffness = 1.75e11\nstiffness2 = 0.0\ndamping = 1.75e5\n"
      "[center_damper]\ndamping = 52.0\n"
      "[flexible]\nmodes = 4\n"
      "[flexible.matrices]\nfile = \"{}\"\nrotor_contact_coordinates = [{}, {}]\n"
      "stator_contact_coordinates = [{}, {}]\n"
      "[analysis]\nstages = [\"branches\"]\nspeed_range_rpm = [20.0, 120.0]\n",
      FormatFloat(p.rotor_mass), FormatFloat(p.rotor_inertia), FormatFloat(p.contact_span),
      FormatFloat(p.rotor_mass_center), FormatFloat(p.stator_mass), FormatFloat(p.stator_inertia),
      FormatFloat(p.stator_span), FormatFloat(p.stator_mass_center), file, m.contacts[0].rotor,
      m.contacts[1].rotor, m.contacts[0].stator, m.contacts[1].stator);
}

void CheckSameMatrix(const Matrix& a, const Matrix& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  CHECK((a - b).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("[flexible.matrices]: the listed shafts' matrices read back give the same L1 points",
          "[structure_file]") {
  Scene listed = LoadScene(kListed);
  listed.analysis.speed_range_rpm = {20.0, 120.0};
  const MatrixRubModel model = FlexibleMatricesOf(listed);
  const RubStructure expected = StructureOf(listed);
  const std::vector<RotatingWaveBranch> want =
      ComputeRotatingWaveBranches(expected, FrictionLawOf(listed), BranchOptionsOf(listed));
  std::size_t special = 0;
  for (const RotatingWaveBranch& b : want) special += b.branch.special_points.size();
  REQUIRE(special >= 4);  // the whirl's knee, Hopf points, folds: something to compare

  TempDir dir;
  for (const std::string name : {"matrices.h5", "matrices_mtx"}) {
    INFO(name);
    WriteStructuralMatrices(dir.path / name, model.full);
    const StructuralMatrices read = ReadStructuralMatrices(dir.path / name);
    CheckSameMatrix(read.mass, model.full.mass);
    CheckSameMatrix(read.damping, model.full.damping);
    CheckSameMatrix(read.stiffness, model.full.stiffness);
    CheckSameMatrix(read.gyroscopic, model.full.gyroscopic);
    // Relative to the scene file's directory.
    const testing::fs::path scene_file = dir.path / ("scene_" + name + ".toml");
    std::ofstream(scene_file) << MatrixScene(listed, name, model);
    const Scene scene = LoadScene(scene_file);
    REQUIRE(scene.flexible.matrices.enabled);
    CHECK(scene.flexible.matrices.file == (dir.path / name).string());
    CHECK(scene.flexible.matrices.imbalance_coordinate == model.contacts[0].rotor);
    const RubStructure got = StructureOf(scene);
    CheckSameMatrix(got.mass, expected.mass);
    CheckSameMatrix(got.stiffness, expected.stiffness);
    CheckSameMatrix(got.damping, expected.damping);
    CheckSameMatrix(got.gyroscopic, expected.gyroscopic);
    const std::vector<RotatingWaveBranch> branches =
        ComputeRotatingWaveBranches(got, FrictionLawOf(scene), BranchOptionsOf(scene));
    REQUIRE(branches.size() == want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      const auto& a = want[i].branch.special_points;
      const auto& b = branches[i].branch.special_points;
      REQUIRE(a.size() == b.size());
      for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].type == b[k].type);
        CHECK(std::abs(a[k].lambda - b[k].lambda) <= 1e-10 * std::abs(a[k].lambda));
        CHECK(std::abs(want[i].SpecialPrecessionHz(k) - branches[i].SpecialPrecessionHz(k)) <=
              1e-10 * std::abs(want[i].SpecialPrecessionHz(k)));
      }
    }
    // The resolved scene names the file as read, absolute, and loads again.
    const std::string resolved = ResolvedSceneToml(scene);
    CHECK_THAT(resolved, Contains("file = \"" + (dir.path / name).string() + "\""));
    CHECK(StructureOf(ParseScene(resolved, "resolved", "resolved")).mass == got.mass);
  }
}

TEST_CASE("[flexible.matrices]: every broken rule named with its key, value and rule",
          "[structure_file]") {
  TempDir dir;
  const Scene listed = LoadScene(kListed);
  const MatrixRubModel model = FlexibleMatricesOf(listed);
  auto problems = [&](const std::string& text) -> std::string {
    const testing::fs::path file = dir.path / "scene.toml";
    std::ofstream(file) << text;
    try {
      LoadScene(file);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  const std::string good = MatrixScene(listed, "m.h5", model);
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  // Missing file.
  CHECK_THAT(problems(good), Contains("flexible.matrices.file = \"m.h5\": " +
                                               (dir.path / "m.h5").string() +
                                               ": cannot be read: no such file or directory"));
  WriteStructuralMatrices(dir.path / "m.h5", model.full);
  REQUIRE(problems(good).empty());
  // Contact coordinate out of range, and one shared by two contacts.
  CHECK_THAT(problems(with("rotor_contact_coordinates = [0, 16]", "rotor_contact_coordinates = [0, 36]")),
             Contains("flexible.matrices.rotor_contact_coordinates = [0, 36]: must index "
                               "the matrices' 36 coordinates (0 to 35)"));
  CHECK_THAT(problems(with("stator_contact_coordinates = [18, 34]", "stator_contact_coordinates = [16, 34]")),
             Contains("flexible.matrices.stator_contact_coordinates = [16, 34]: coordinate "
                               "16 is given twice"));
  // The shafts' keys are not the matrices'.
  CHECK_THAT(problems(with("[flexible]\n", "[flexible]\ndensity = 7833.0\n")),
             Contains("flexible.density = 7833.0: not used: [flexible.matrices] gives the "
                               "whole structure"));
  // Shape, symmetry, definiteness: each names the matrix.
  auto broken = [&](const std::string& name, auto change) {
    StructuralMatrices m = model.full;
    change(m);
    WriteStructuralMatrices(dir.path / name, m);
    return problems(with("file = \"m.h5\"", "file = \"" + name + "\""));
  };
  CHECK_THAT(broken("shape.h5", [](StructuralMatrices& m) { m.damping = Matrix::Zero(35, 36); }),
             Contains("damping: is 35 × 36: must be 36 × 36, as the mass"));
  CHECK_THAT(broken("asymmetric_mtx", [](StructuralMatrices& m) { m.stiffness(3, 5) += 1e3; }),
             Contains("stiffness: not symmetric: entry (3, 5) − entry (5, 3) = 1e+03"));
  CHECK_THAT(broken("indefinite.h5", [](StructuralMatrices& m) { m.mass(2, 2) = -1.0; }),
             Contains("mass: not positive semi-definite: smallest eigenvalue"));
  // Contacts that move no mass: four grounded springs at the contacts, the one mass inside on
  // its own spring (K_ib = 0: the constraint modes move nothing).
  MatrixRubModel massless;
  massless.full = {Matrix::Zero(5, 5), Matrix::Zero(5, 5), Matrix::Identity(5, 5),
                   Matrix::Zero(5, 5)};
  massless.full.mass(4, 4) = 1.0;
  massless.contacts = {{"left", 0, 2, {}}, {"right", 1, 3, {}}};
  massless.modes = 1;
  CHECK_THROWS_WITH(BuildMatrixRub(massless),
                    Contains("mass: not positive definite on the contact coordinates and the kept "
                             "modes"));
  massless.full.mass.diagonal().setOnes();
  CHECK(BuildMatrixRub(massless).structure.Coordinates() == 5);
  // A malformed MatrixMarket line names the file and line.
  testing::fs::create_directories(dir.path / "bad_mtx");
  WriteStructuralMatrices(dir.path / "bad_mtx", model.full);
  std::ofstream(dir.path / "bad_mtx" / "gyroscopic.mtx")
      << "%%MatrixMarket matrix coordinate real general\n36 36 1\n37 1 1.0\n";
  CHECK_THAT(problems(with("file = \"m.h5\"", "file = \"bad_mtx\"")),
             Contains("gyroscopic.mtx:3: entry (37, 1): outside the 36 × 36 matrix"));
}

TEST_CASE("[flexible.matrices]: MatrixMarket symmetric and array files read as the whole matrix",
          "[structure_file]") {
  TempDir dir;
  const StructuralMatrices m{Matrix{{2.0, 0.5}, {0.5, 3.0}}, Matrix::Zero(2, 2),
                             Matrix{{4.0, -1.0}, {-1.0, 4.0}}, Matrix::Zero(2, 2)};
  WriteStructuralMatrices(dir.path, m);
  std::ofstream(dir.path / "mass.mtx")
      << "%%MatrixMarket matrix coordinate real symmetric\n% lower triangle\n2 2 3\n1 1 2\n2 1 0.5\n2 2 3\n";
  std::ofstream(dir.path / "stiffness.mtx")
      << "%%MatrixMarket matrix array real symmetric\n2 2\n4\n-1\n4\n";
  std::ofstream(dir.path / "damping.mtx") << "%%MatrixMarket matrix array real general\n2 2\n0\n0\n0\n0\n";
  const StructuralMatrices read = ReadStructuralMatrices(dir.path);
  CheckSameMatrix(read.mass, m.mass);
  CheckSameMatrix(read.stiffness, m.stiffness);
  CheckSameMatrix(read.damping, m.damping);
  std::ofstream(dir.path / "mass.mtx")
      << "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 2 0.5\n";
  CHECK_THROWS_WITH(ReadStructuralMatrices(dir.path),
                    Contains("mass.mtx:3: entry (1, 2): a symmetric file lists the lower "
                                      "triangle"));
}

TEST_CASE("rubcont scene matrices: writes a flexible scene's matrices, refuses a rigid one",
          "[structure_file]") {
  TempDir dir;
  const std::string out = (dir.path / "a.h5").string();
  testing::Outcome o =
      testing::RubcontNoPython(std::string("scene matrices ") + kListed + " --out " + out);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("[flexible.matrices]\nfile = \"" + out +
                                      "\"\nrotor_contact_coordinates = [0, 16]\n"
                                      "stator_contact_coordinates = [18, 34]\n"));
  CheckSameMatrix(ReadStructuralMatrices(out).stiffness,
                  FlexibleMatricesOf(LoadScene(kListed)).full.stiffness);
  o = testing::RubcontNoPython("scene matrices scenes/thesis_A_a.toml --out " + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("has no [flexible] section"));
}

}  // namespace
}  // namespace rubcont
