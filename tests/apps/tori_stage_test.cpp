// The "tori" stage, run as a user runs it: `rubcont run` on case C(a) writes /tori with the
// modulated family and the tori born at its Neimark–Sacker point (a short family: the committed
// scene's numerics on 4 harmonics and 2 steps).
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

using testing::Outcome;
using testing::Slurp;
using testing::TempDir;

TEST_CASE("rubcont run scenes/thesis_C_a_tori.toml, short: the tori born at the modulated whip's "
          "Neimark-Sacker point, their frequencies and stability in /tori",
          "[tori][cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_C_a_tori.toml");
  text = text.substr(0, text.find("[analysis.orbits]"));
  text += "[analysis.orbits]\nhopf_points = 1\nmax_steps = 6\n"
          "[analysis.tori]\nharmonics = 4\nmax_steps = 2\nlyapunov_iterates = 8\nsamples = 8\n";
  const fs::path scene = dir.path / "ca_tori.toml";
  std::ofstream(scene) << text;
  const Outcome run =
      testing::RubcontNoPython("run " + scene.string() + " --quiet --out " + dir.path.string());
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("[tori] L2 relative 2-tori (invariant circles of 4 harmonics (9 points)"));
  CHECK_THAT(run.out, Contains("branch1_hopf2_ns1: born at 48.66"));
  CHECK_THAT(run.out, Contains("reached the step limit"));
  const ResultReader file(dir.path / "ca_tori" / "ca_tori.h5");
  CHECK(file.ReadStringAttribute("/", "level") == "L2");
  CHECK(file.ReadStringAttribute("/tori", "parameter_name") == "speed_rpm");
  CHECK_THAT(file.ReadStringAttribute("/tori", "numerics"),
             Contains("Gauss collocation of order 8 on 400 intervals per period"));
  CHECK(file.Exists("/tori/orbits/branch1_hopf2"));
  const std::string group = "/tori/branch1_hopf2_ns1";
  REQUIRE(file.Exists(group));
  CHECK(file.ReadStringAttribute(group, "parent") == "branch1_hopf2");
  CHECK(file.ReadStringAttribute(group, "end") == "reached the step limit");
  const double birth = file.ReadDoubleAttribute(group, "birth_speed_rpm");
  CHECK(birth == Approx(48.667).margin(0.01));
  const double rho0 = file.ReadDoubleAttribute(group, "birth_rotation_number");
  CHECK(rho0 == Approx(0.443).margin(0.005));
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  REQUIRE(rpm.size() == 3);
  const auto rho = file.ReadDoubles(group + "/rotation_number");
  const auto f1 = file.ReadDoubles(group + "/first_hz");
  const auto f2 = file.ReadDoubles(group + "/second_hz");
  const auto carrier = file.ReadDoubles(group + "/carrier_hz");
  const auto left = file.ReadDoubles(group + "/line_hz_left");
  const auto stable = file.ReadInts(group + "/stable");
  REQUIRE(stable.size() == rpm.size());
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    CHECK(rpm[i] > birth);
    CHECK(f2[i] == Approx(rho[i] * f1[i]).epsilon(1e-12));
    // Near the orbit's modulation at the point (136.22 Hz), falling with speed (133.9 Hz 0.085 rpm on).
    CHECK(f1[i] == Approx(136.22).epsilon(0.02));
    CHECK(carrier[i] == Approx(79.285).margin(0.01));
    CHECK(left[i] == Approx(carrier[i] + f1[i]).epsilon(1e-9));  // its (0, −1) sideband
    CHECK(stable[i] >= -1);
    CHECK(stable[i] <= 1);
  }
  CHECK(file.ReadMatrix(group + "/exponents").rows() == 3);
  // The circles, reopenable: 16 states × 9 Fourier columns, then ρ, T and φ.
  const Matrix unknowns = file.ReadMatrix(group + "/unknowns");
  REQUIRE(unknowns.rows() == 3);
  CHECK(unknowns.cols() == 16 * 9 + 3);
  CHECK(unknowns(0, 16 * 9) == Approx(rho[0]).epsilon(1e-14));
  CHECK(1.0 / unknowns(0, 16 * 9 + 1) == Approx(f1[0]).epsilon(1e-12));
  CHECK(file.ReadDoubleAttribute("/tori/orbits/branch1_hopf2", "hopf_precession_hz") ==
        Approx(79.2834).margin(1e-4));
}

TEST_CASE("stage tori on a textbook scene, or a bad [analysis.tori] key, exits with code 2",
          "[tori][cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_C_a_tori.toml");
  text = text.substr(0, text.find("[analysis.tori]")) + "[analysis.tori]\nharmonics = 0\n";
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << text;
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("analysis.tori.harmonics = 0: must be from 1 to 1000"));
  std::string duffing = Slurp("scenes/duffing.toml");
  duffing = duffing.substr(0, duffing.find("[analysis]"));
  std::ofstream(scene) << duffing << "[analysis]\nstages = [\"tori\"]\n";
  const Outcome wrong = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(wrong.exit_code == 2);
  CHECK_THAT(wrong.err, Contains("\"tori\" does not apply to model \"duffing\""));
}

}  // namespace
}  // namespace rubcont
