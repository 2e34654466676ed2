// The "tori" stage, run as a user runs it: `rubcont run` on case C(a) writes /tori with the
// modulated family and the tori born at its Neimark–Sacker point (a short family: the committed
// scene's numerics on 4 harmonics and 1 step). One step, not two: the second ends near 48.75 rpm,
// where K = 4's Fourier tail (0.0067 there) lies near the 0.01 that ends a family as broken down,
// and is rounding noise of the ill-conditioned circle (issue 53): the same first torus (ρ equal to
// 8 digits) has tails 2.9e-4 and 3.9e-4 under Gauss's full and Schur-complement stage solves, which
// are the same linear algebra; the second run's next torus broke down at 48.710 rpm.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

using testing::Outcome;
using testing::RunQuiet;
using testing::SceneWithAnalysis;
using testing::Slurp;
using testing::TempDir;

// `text` written as <dir>/<name>.toml and run by `rubcont run --quiet` into dir.
TEST_CASE("rubcont run scenes/thesis_C_a_tori.toml, short: the tori born at the modulated whip's "
          "Neimark-Sacker point, their frequencies and stability in /tori",
          "[tori][cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_C_a_tori.toml");
  text = text.substr(0, text.find("[analysis.orbits]"));
  text += "[analysis.orbits]\nhopf_points = 1\nmax_steps = 6\n"
          "[analysis.tori]\nharmonics = 4\nmax_steps = 1\nlyapunov_iterates = 8\nsamples = 8\n";
  const Outcome run = RunQuiet(dir, "ca_tori", text);
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
  CHECK(birth == Approx(48.667).epsilon(0).margin(0.01));
  const double rho0 = file.ReadDoubleAttribute(group, "birth_rotation_number");
  CHECK(rho0 == Approx(0.443).epsilon(0).margin(0.005));
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  REQUIRE(rpm.size() == 2);
  const auto rho = file.ReadDoubles(group + "/rotation_number");
  const auto f1 = file.ReadDoubles(group + "/first_hz");
  const auto f2 = file.ReadDoubles(group + "/second_hz");
  const auto carrier = file.ReadDoubles(group + "/carrier_hz");
  const auto left = file.ReadDoubles(group + "/line_hz_left");
  const auto stable = file.ReadInts(group + "/stable");
  const auto unstable = file.ReadInts(group + "/unstable_count");
  const auto largest = file.ReadDoubles(group + "/largest_exponent");
  const auto tolerance = file.ReadDoubles(group + "/exponent_tolerance");
  REQUIRE(stable.size() == rpm.size());
  REQUIRE(unstable.size() == rpm.size());
  // The engine's columns as every branch group has them, with the special points (none here:
  // the family ends at its step limit).
  CHECK(file.ReadDoubles(group + "/arclength").size() == rpm.size());
  CHECK(file.ReadStrings(group + "/special_points/type").empty());
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    CHECK(rpm[i] > birth);
    // Stability from the Lyapunov spectrum: stable with no exponent above the tolerance,
    // unstable with at least one, undecided (−1) when the largest lies within it.
    INFO("torus " << i << ": largest exponent " << largest[i] << " ± " << tolerance[i]);
    CHECK(stable[i] == (largest[i] < -tolerance[i] ? 1 : largest[i] > tolerance[i] ? 0 : -1));
    if (stable[i] == 1) CHECK(unstable[i] == 0);
    if (stable[i] == 0) CHECK(unstable[i] >= 1);
    if (stable[i] == -1) CHECK(unstable[i] == -1);
    CHECK(f2[i] == Approx(rho[i] * f1[i]).epsilon(1e-12));
    // Near the orbit's modulation at the point (136.22 Hz), falling with speed (133.9 Hz 0.085 rpm on).
    CHECK(f1[i] == Approx(136.22).epsilon(0.02));
    CHECK(carrier[i] == Approx(79.285).epsilon(0).margin(0.01));
    CHECK(left[i] == Approx(carrier[i] + f1[i]).epsilon(1e-9));  // its (0, −1) sideband
  }
  CHECK(file.ReadMatrix(group + "/exponents").rows() == 2);
  // The circles, reopenable: 16 states × 9 Fourier columns, then ρ, T and φ.
  const Matrix unknowns = file.ReadMatrix(group + "/unknowns");
  REQUIRE(unknowns.rows() == 2);
  CHECK(unknowns.cols() == 16 * 9 + 3);
  CHECK(unknowns(0, 16 * 9) == Approx(rho[0]).epsilon(1e-14));
  CHECK(1.0 / unknowns(0, 16 * 9 + 1) == Approx(f1[0]).epsilon(1e-12));
  // Each torus's K, and no refinement in K (max_harmonics 0).
  CHECK(file.ReadDoubles(group + "/harmonics") == std::vector<double>{4.0, 4.0});
  CHECK(file.ReadDoublesAttribute(group, "refinement_speeds_rpm").empty());
  CHECK(file.ReadDoublesAttribute(group, "refinement_to_harmonics").empty());
  CHECK(file.ReadStringAttribute(group, "convergence_note").empty());
  CHECK(file.ReadDoubleAttribute("/tori/orbits/branch1_hopf2", "hopf_precession_hz") ==
        Approx(79.2834).epsilon(0).margin(1e-4));
}

TEST_CASE("rubcont run, [analysis.tori.transient] at 49 rpm on C(a): the torus a transient "
          "settles on past the 2:5 tongue, continued both ways, in /tori/transient_down and _up",
          "[tori][cli]") {
  TempDir dir;
  // No modulated orbits: only the transient's tori (K = 8; K = 4 fits no circle to its points).
  const std::string text = SceneWithAnalysis(
      "scenes/thesis_C_a_tori.toml",
      "[analysis]\nstages = [\"tori\"]\nspeed_range_rpm = [20.0, 52.0]\n"
      "[analysis.tori]\nneimark_sacker = \"skip\"\nlyapunov_iterates = 1\nsamples = 4\n"
      "[analysis.tori.transient]\nspeed_rpm = 49.0\nharmonics = 8\nmax_steps = 1\n");
  const Outcome run = RunQuiet(dir, "ca_transient", text);
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("through the torus a transient settles on at 49 rpm"));
  CHECK_THAT(run.out, Contains("[tori] transient at 49 rpm, 8 s from rest and a 1 N·s impulse"));
  const ResultReader file(dir.path / "ca_transient" / "ca_transient.h5");
  CHECK_FALSE(file.Exists("/tori/orbits"));  // neimark_sacker = "skip"
  CHECK_THAT(file.ReadStringAttribute("/tori", "numerics"), Contains("8 harmonics (17 points)"));
  double previous_rho = 0.0;
  for (const std::string side : {"down", "up"}) {
    const std::string group = "/tori/transient_" + side;
    INFO(group);
    REQUIRE(file.Exists(group));
    CHECK(file.ReadStringAttribute(group, "parent") == "transient");
    CHECK_FALSE(file.HasAttribute(group, "birth_speed_rpm"));  // no Neimark–Sacker point
    CHECK(file.ReadStringAttribute(group, "end") == "reached the step limit");
    CHECK_THAT(file.ReadStringAttribute(group, "numerics"), Contains("CVODES BDF"));
    CHECK(file.ReadDoubleAttribute(group, "transient_speed_rpm") == 49.0);
    CHECK(file.ReadDoubleAttribute(group, "transient_settled") == 1.0);
    // The torus on the transient's points: one modulation period per section, ρ between the 2:5
    // tongue and 3/8 (measured 0.37964, f₁ = 129.602 Hz, carrier 79.2833 Hz; the transient's
    // precession 79.2793 Hz by Dormand–Prince over its last 0.5 s).
    CHECK(file.ReadDoubleAttribute(group, "start_laps") == 1.0);
    const double rho0 = file.ReadDoubleAttribute(group, "start_rotation_number");
    // Solved by BDF on the transient's points, then again under the orbits' Gauss mesh, the
    // families' map (ModulatedTorusOptions::final_collocation_intervals): the same torus, ρ
    // moved by the maps' difference.
    CHECK_THAT(file.ReadStringAttribute(group, "start_message"),
               Contains("then under Gauss collocation on 400 intervals per period"));
    REQUIRE(file.HasAttribute(group, "start_first_map_rotation_number"));
    CHECK(std::abs(file.ReadDoubleAttribute(group, "start_first_map_rotation_number") - rho0) < 5e-3);
    // Not refined in K (max_harmonics = 0): one entry, the first circle's.
    CHECK(file.ReadDoublesAttribute(group, "start_in_k_harmonics") == std::vector<double>{8.0});
    CHECK(file.ReadDoublesAttribute(group, "start_in_k_rotation_numbers") ==
          std::vector<double>{rho0});
    CHECK(file.ReadDoublesAttribute(group, "start_in_k_fourier_tails") ==
          std::vector<double>{file.ReadDoubleAttribute(group, "start_fourier_tail")});
    CHECK(file.ReadDoublesAttribute(group, "start_in_k_images") == std::vector<double>{0.0});
    CHECK(rho0 > 3.0 / 8.0);
    CHECK(rho0 < 2.0 / 5.0);
    CHECK(file.ReadDoubleAttribute(group, "start_first_hz") ==
          Approx(129.60).epsilon(0).margin(0.05));
    const double carrier0 = file.ReadDoubleAttribute(group, "start_carrier_hz");
    CHECK(std::abs(carrier0 - file.ReadDoubleAttribute(group, "frame_precession_hz")) < 0.01);
    const auto rpm = file.ReadDoubles(group + "/speed_rpm");
    const auto rho = file.ReadDoubles(group + "/rotation_number");
    const auto f1 = file.ReadDoubles(group + "/first_hz");
    const auto f2 = file.ReadDoubles(group + "/second_hz");
    const auto carrier = file.ReadDoubles(group + "/carrier_hz");
    const auto stable = file.ReadInts(group + "/stable");
    REQUIRE(rpm.size() == 2);
    REQUIRE(stable.size() == 2);
    // Both families start on the same corrected torus at 49 rpm and leave it on their own side,
    // ρ falling as speed rises (towards 2/5 going down, towards 3/8 going up).
    CHECK(rpm[0] == Approx(49.0).epsilon(1e-12));
    if (side == "down") {
      previous_rho = rho[0];
      CHECK(rpm[1] < rpm[0]);
      CHECK(rho[1] > rho[0]);
    } else {
      // Corrected again at its start: the same torus to the corrector's tolerance (1e-8).
      CHECK(rho[0] == Approx(previous_rho).epsilon(1e-8));
      CHECK(rpm[1] > rpm[0]);
      CHECK(rho[1] < rho[0]);
    }
    for (std::size_t i = 0; i < rpm.size(); ++i) {
      CHECK(rho[i] > 3.0 / 8.0);
      CHECK(rho[i] < 2.0 / 5.0);
      CHECK(f2[i] == Approx(rho[i] * f1[i]).epsilon(1e-12));
      CHECK(carrier[i] == Approx(carrier0).epsilon(0).margin(0.01));
    }
    const Matrix unknowns = file.ReadMatrix(group + "/unknowns");
    CHECK(unknowns.rows() == 2);
    CHECK(unknowns.cols() == 16 * 17 + 3);
  }
}

TEST_CASE("rubcont run, [analysis.orbits.transient] on C(b)'s tori: the tori born at the "
          "Neimark-Sacker point of the family through the transient's orbit",
          "[tori][cli]") {
  // C(b)'s whip at 53 rpm (stable) loses stability at 53.953 rpm (arg mu / 2 pi = 0.2402; 1600
  // intervals, scenes/thesis_C_b_tori_53.toml): no Hopf point's family reaches it. Here on 400
  // intervals, K = 8 in the chart and two tori.
  TempDir dir;
  const std::string text = SceneWithAnalysis(
      "scenes/thesis_C_b_tori.toml",
      "[analysis]\nstages = [\"tori\"]\nspeed_range_rpm = [53.0, 54.1]\n"
      "[analysis.sweep]\nintegrator = \"bdf\"\n"
      "[analysis.orbits]\nhopf_points = 0\n"
      "[analysis.orbits.transient]\nspeed_rpm = 53.0\nmax_steps = 20\n"
      "[analysis.tori]\ncoordinates = \"chart\"\nmax_steps = 2\nlyapunov_iterates = 8\n"
      "samples = 8\n");
  const Outcome run = RunQuiet(dir, "cb_orbit_tori", text);
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("from the Neimark–Sacker points of the modulated orbits born at 0 "
                               "of the 0 Hopf points bounding a stable rotating wave and of the "
                               "family through the orbit a transient settles on at 53 rpm"));
  CHECK_THAT(run.out, Contains("orbit_transient_ns1: born at 53.95"));
  const ResultReader file(dir.path / "cb_orbit_tori" / "cb_orbit_tori.h5");
  REQUIRE(file.Exists("/tori/orbits/orbit_transient"));
  CHECK(file.ReadDoubleAttribute("/tori/orbits/orbit_transient", "transient_speed_rpm") == 53.0);
  const std::string group = "/tori/orbit_transient_ns1";
  REQUIRE(file.Exists(group));
  CHECK(file.ReadStringAttribute(group, "parent") == "orbit_transient");
  const double birth = file.ReadDoubleAttribute(group, "birth_speed_rpm");
  CHECK(birth == Approx(53.953).epsilon(0).margin(0.01));
  const double rho0 = file.ReadDoubleAttribute(group, "birth_rotation_number");
  CHECK(rho0 == Approx(0.2403).epsilon(0).margin(0.002));
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  const auto rho = file.ReadDoubles(group + "/rotation_number");
  REQUIRE(rpm.size() == 3);
  // Born small: the tori's rotation numbers stay near the multiplier's angle, their speeds near
  // the point.
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    CHECK(rpm[i] == Approx(53.953).epsilon(0).margin(0.1));
    CHECK(rho[i] == Approx(rho0).epsilon(0).margin(0.005));
  }
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
  // Nothing left to compute; a transient outside the speed range, too short for the sweep's
  // windows, with too many periods per section.
  text = Slurp("scenes/thesis_C_a_tori.toml");
  text = text.substr(0, text.find("[analysis.tori]"));
  std::ofstream(scene) << text << "[analysis.tori]\nneimark_sacker = \"skip\"\n";
  const Outcome nothing = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(nothing.exit_code == 2);
  CHECK_THAT(nothing.err, Contains("analysis.tori.neimark_sacker = \"skip\": leaves the stage "
                                   "\"tori\" nothing to compute: give [analysis.tori.transient]"));
  std::ofstream(scene) << text << "[analysis.tori.transient]\nspeed_rpm = 60.0\nseconds = 0.1\nlaps = 65\n";
  const Outcome outside = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(outside.exit_code == 2);
  CHECK_THAT(outside.err, Contains("analysis.tori.transient.speed_rpm = 60.0: must lie in "
                                   "analysis.speed_range_rpm = [20.0, 52.0]"));
  CHECK_THAT(outside.err, Contains("analysis.tori.transient.seconds = 0.1: must be at least "
                                   "(settle_windows + 1)·settle_window of [analysis.sweep] = 0.75 s"));
  CHECK_THAT(outside.err, Contains("analysis.tori.transient.laps = 65: must be at most 64"));
  // The orbits' transient, whose family's Neimark-Sacker points the stage follows, under the
  // same rules where the stage "orbits" does not run.
  const std::string both = "stages = [\"orbits\", \"tori\"]";
  REQUIRE(text.find(both) != std::string::npos);
  text.replace(text.find(both), both.size(), "stages = [\"tori\"]");
  std::ofstream(scene) << text << "[analysis.orbits.transient]\nspeed_rpm = 60.0\n";
  const Outcome orbits =
      testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(orbits.exit_code == 2);
  CHECK_THAT(orbits.err, Contains("analysis.orbits.transient.speed_rpm = 60.0: must lie in "
                                  "analysis.speed_range_rpm = [20.0, 52.0]"));
}

TEST_CASE("centre_orbits in [analysis.tori]: \"follow\" (the default) continues the orbits a "
          "family shrinks onto over the range, \"to_point\" stops them at their Neimark-Sacker "
          "point, another value is exit 2 naming the key",
          "[tori][cli]") {
  std::string text = Slurp("scenes/thesis_C_a_tori.toml");
  text = text.substr(0, text.find("[analysis.tori]")) + "[analysis.tori]\n";
  const auto stops = [&text](const std::string& keys) {
    const Scene scene = ParseScene(text + keys, "centre_orbits", "centre_orbits");
    const RubTorusOptions options = TorusOptionsOf(scene);
    // The orbits' own range and engine, as the scene's [analysis.orbits] gives them.
    CHECK(options.centre_orbits.lambda_max == options.tori.lambda_max);
    CHECK(options.centre_orbits.continuation.bounds.max_steps == scene.analysis.orbits.max_steps);
    return options.centre_orbits.stop_at_neimark_sacker;
  };
  CHECK_FALSE(stops(""));
  CHECK_FALSE(stops("centre_orbits = \"follow\"\n"));
  CHECK(stops("centre_orbits = \"to_point\"\n"));

  TempDir dir;
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << text << "centre_orbits = \"onward\"\n";
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("analysis.tori.centre_orbits = \"onward\": must be one of "
                               "\"follow\", \"to_point\""));
}

}  // namespace
}  // namespace rubcont
