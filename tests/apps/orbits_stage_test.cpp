// The "orbits" stage, run as a user runs it: `rubcont run scenes/<model>.toml` of the textbook
// scenes writes /branches/periodic_orbits with Floquet stability and special points; of a rotor
// scene, /orbits with the modulated whirl and whip; a bad scene exits with code 2 naming the key,
// the value and the rule.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "cli_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include "apps/hdf5_file.h"
#include "apps/orbits_stage.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "solvers/constants.h"
#include "tests/shooting/duffing_harmonic_balance.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

using testing::Outcome;
using testing::Slurp;
using testing::TempDir;

TEST_CASE("rubcont run scenes/duffing.toml: the resonance curve with both folds at the "
          "harmonic-balance frequencies, the middle branch unstable",
          "[orbits][cli]") {
  TempDir dir;
  const Outcome run = testing::RubcontNoPython("run scenes/duffing.toml --quiet --out " + dir.path.string());
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("[orbits] L2 periodic orbits of duffing"));
  const ResultReader file(dir.path / "duffing" / "duffing.h5");
  const std::string group = "/branches/periodic_orbits";
  CHECK(file.ReadStringAttribute(group, "kind") == "periodic_orbit");
  CHECK(file.ReadStringAttribute(group, "orbit_kind") == "forced");
  CHECK(file.ReadStringAttribute(group, "parameter_name") == "frequency");
  CHECK(file.ReadStringAttribute(group, "status") == "reached a λ bound");
  CHECK(file.ReadStringAttribute("/", "level") == "L2");
  const auto w = file.ReadDoubles(group + "/frequency");
  REQUIRE(w.size() > 10);
  CHECK(w.front() == 0.5);
  CHECK(w.back() == Approx(2.5).epsilon(0).margin(1e-9));

  // Both folds, against the harmonic balance's (tests/shooting/duffing_harmonic_balance.h).
  DuffingParams params;
  const testing::DuffingHarmonicBalance balance(params, 25);
  std::vector<double> hb;
  for (const auto& guess : testing::DuffingHarmonicBalance::OneTermFolds(params, 0.5, 2.5)) {
    const auto fold = balance.LocateFold(balance.FirstHarmonic(guess.amplitude, guess.phase),
                                         guess.frequency);
    REQUIRE(fold.newton.Converged());
    hb.push_back(fold.frequency);
  }
  REQUIRE(hb.size() == 2);
  const auto types = file.ReadStrings(group + "/special_points/type");
  const auto folds = file.ReadDoubles(group + "/special_points/frequency");
  REQUIRE(types == std::vector<std::string>{"fold", "fold"});
  CHECK(folds[0] ==
        Approx(hb[1]).epsilon(0).margin(1e-8));  // the upper fold comes first along the branch
  CHECK(folds[1] == Approx(hb[0]).epsilon(0).margin(1e-8));
  CHECK(file.ReadInts(group + "/special_points/converged") == std::vector<int>{1, 1});

  // Stability: stable, then one multiplier outside the unit circle between the folds, then stable.
  const auto index = file.ReadInts(group + "/special_points/point_index");
  const auto stable = file.ReadInts(group + "/stable");
  const auto largest = file.ReadDoubles(group + "/max_multiplier_modulus");
  const Matrix real = file.ReadMatrix(group + "/multipliers_real");
  REQUIRE(real.rows() == static_cast<Index>(w.size()));
  REQUIRE(real.cols() == 2);
  for (std::size_t i = 0; i < w.size(); ++i) {
    const bool middle = static_cast<int>(i) > index[0] && static_cast<int>(i) <= index[1];
    CHECK(stable[i] == (middle ? 0 : 1));
    CHECK((largest[i] > 1.0) == middle);
  }
}

TEST_CASE("The Duffing scene's orbits integrator key: Gauss collocation puts both folds within "
          "1e-12 of harmonic balance, the model's explicit pair at its tolerance not, and a bad "
          "name is exit 2 naming the key",
          "[orbits][cli]") {
  DuffingParams params;
  const testing::DuffingHarmonicBalance balance(params, 25);
  std::vector<double> hb;
  for (const auto& guess : testing::DuffingHarmonicBalance::OneTermFolds(params, 0.5, 2.5)) {
    hb.push_back(balance.LocateFold(balance.FirstHarmonic(guess.amplitude, guess.phase),
                                    guess.frequency).frequency);
  }
  REQUIRE(hb.size() == 2);
  std::sort(hb.begin(), hb.end(), std::greater<double>());  // the upper fold first, as the branch
  TempDir dir;
  const std::string committed = Slurp("scenes/duffing.toml");
  const std::string gauss_key = "integrator = \"gauss\"";
  REQUIRE(committed.find(gauss_key) != std::string::npos);
  // The largest distance of the two folds from harmonic balance, for the scene with `integrator`.
  auto fold_error = [&](const std::string& integrator) {
    std::string text = committed;
    text.replace(text.find(gauss_key), gauss_key.size(), "integrator = \"" + integrator + "\"");
    const fs::path scene = dir.path / (integrator + ".toml");
    std::ofstream(scene) << text;
    const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --quiet --no-figures --out " +
                                                 (dir.path / integrator).string());
    INFO(run.out << run.err);
    REQUIRE(run.exit_code == 0);
    const ResultReader file(dir.path / integrator / "duffing" / "duffing.h5");  // name = "duffing"
    const auto folds = file.ReadDoubles("/branches/periodic_orbits/special_points/frequency");
    REQUIRE(folds.size() == 2);
    return std::max(std::abs(folds[0] - hb[0]), std::abs(folds[1] - hb[1]));
  };
  // Measured: Gauss s = 4 on 40 intervals 3.7e-14 and 2.8e-13; Fehlberg 8(7) at rtol = atol =
  // 1e-10 2.4e-11 and 4.3e-13.
  CHECK(fold_error("gauss") < 1e-12);
  CHECK(fold_error("explicit") > 1e-12);
  CHECK(fold_error("model") > 1e-12);

  std::string bad = committed;
  bad.replace(bad.find(gauss_key), gauss_key.size(), "integrator = \"rk4\"");
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << bad;
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("duffing.orbits.integrator = \"rk4\""));
}

TEST_CASE("rubcont run scenes/stuart_landau.toml: orbits, periods and multipliers as in closed form",
          "[orbits][cli]") {
  TempDir dir;
  const Outcome run = testing::RubcontNoPython("run scenes/stuart_landau.toml --quiet --out " + dir.path.string());
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  const ResultReader file(dir.path / "stuart_landau" / "stuart_landau.h5");
  const std::string group = "/branches/periodic_orbits";
  CHECK(file.ReadStringAttribute(group, "orbit_kind") == "autonomous");
  const auto lambda = file.ReadDoubles(group + "/lambda");
  REQUIRE(lambda.size() > 5);
  CHECK(lambda.front() == 0.05);
  CHECK(lambda.back() == Approx(1.5).epsilon(0).margin(1e-9));  // the bound is located on arclength
  // The closed-form comparison the stage writes, recomputed here from the raw columns.
  const auto radius = file.ReadDoubles(group + "/mean_radius");
  const auto period = file.ReadDoubles(group + "/period");
  const Matrix real = file.ReadMatrix(group + "/multipliers_real");
  const Matrix imag = file.ReadMatrix(group + "/multipliers_imag");
  REQUIRE(real.cols() == 1);  // the trivial multiplier is deflated
  const double omega = 1.0, gamma = 0.5;  // scenes/stuart_landau.toml
  for (std::size_t i = 0; i < lambda.size(); ++i) {
    const double T = kTwoPi / std::abs(omega - gamma * lambda[i]);
    CHECK(radius[i] == Approx(std::sqrt(lambda[i])).epsilon(0).margin(1e-7));
    CHECK(period[i] == Approx(T).epsilon(1e-8));
    CHECK(real(static_cast<Index>(i), 0) ==
          Approx(std::exp(-2 * lambda[i] * T)).epsilon(0).margin(1e-7));
    CHECK(imag(static_cast<Index>(i), 0) == 0.0);
  }
  for (int s : file.ReadInts(group + "/stable")) CHECK(s == 1);
  CHECK(file.ReadStrings(group + "/special_points/type").empty());
  CHECK(file.ReadDoubles(group + "/closed_form_radius_error").size() == lambda.size());
}

TEST_CASE("rubcont run scenes/van_der_pol.toml: a stable cycle from harmonic to relaxation "
          "oscillations by multiple shooting",
          "[orbits][cli]") {
  TempDir dir;
  const Outcome run = testing::RubcontNoPython("run scenes/van_der_pol.toml --quiet --out " + dir.path.string());
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  const ResultReader file(dir.path / "van_der_pol" / "van_der_pol.h5");
  const std::string group = "/branches/periodic_orbits";
  CHECK(file.ReadDoubleAttribute(group, "segments") == 8.0);
  const auto mu = file.ReadDoubles(group + "/mu");
  const auto period = file.ReadDoubles(group + "/period");
  const auto max_x = file.ReadDoubles(group + "/max_x");
  REQUIRE(mu.size() > 5);
  CHECK(mu.back() == Approx(20.0).epsilon(0).margin(1e-9));
  // Near-harmonic at μ = 0.2 (T → 2π, amplitude → 2), relaxation at μ = 20: T = (3 − 2 ln 2) μ
  // + 7.014 μ^(−1/3) + O(ln μ / μ) (Dorodnitsyn), amplitude → 2.
  CHECK(period.front() == Approx(kTwoPi).epsilon(0.01));
  CHECK(period.back() == Approx((3 - 2 * std::log(2.0)) * 20 + 7.014 * std::pow(20.0, -1.0 / 3)).epsilon(0.02));
  for (double a : max_x) CHECK(a == Approx(2.0).epsilon(0.02));
  for (int s : file.ReadInts(group + "/stable")) CHECK(s == 1);
}

TEST_CASE("a bad textbook scene exits with code 2, naming the key, the value and the rule",
          "[orbits][cli]") {
  TempDir dir;
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << "model = \"duffing\"\n[duffing]\ndamping = 0.05\nstiffness = 1.0\n"
                          "cubic = 1.0\nforce = \"large\"\nfrequency_range = [0.5, 2.5]\n"
                          "[duffing.orbits]\nsegments = 0\n";
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("duffing.force = \"large\": must be a number"));
  CHECK_THAT(run.err, Contains("duffing.orbits.segments = 0: must be from 1 to 1000"));
  // `rubcont branches` on a textbook scene: the stage does not apply.
  std::ofstream(scene) << "model = \"duffing\"\n[duffing]\ndamping = 0.05\nstiffness = 1.0\n"
                          "cubic = 1.0\nforce = 0.3\nfrequency_range = [0.5, 2.5]\n";
  const Outcome branches = testing::RubcontNoPython("branches " + scene.string() + " --out " +
                                   (dir.path / "b.h5").string());
  CHECK(branches.exit_code == 2);
  CHECK_THAT(branches.err, Contains("stage \"analytic\" does not apply to model \"duffing\""));
}

// Case A(a) with the contact stiffness lowered to 1.75e8 N/m (seconds instead of minutes; see
// tests/shooting/rub_orbits_test.cpp), over 40–70 rpm, with `extra` appended to [analysis].
std::string SoftCaseAa(const std::string& extra) {
  std::string text = Slurp("scenes/thesis_A_a.toml");
  text = text.substr(0, text.find("[analysis]"));
  const std::string k1 = "stiffness = 1.75e11";
  REQUIRE(text.find(k1) != std::string::npos);
  text.replace(text.find(k1), k1.size(), "stiffness = 1.75e8");
  return text + "[analysis]\nstages = [\"orbits\"]\nspeed_range_rpm = [40.0, 70.0]\n" + extra;
}

TEST_CASE("rubcont run on a rotor scene with stage orbits: the tanh rotating waves and the "
          "modulated orbits born at the Mode 1 whirl's Hopf point",
          "[orbits][cli][rub_orbits]") {
  TempDir dir;
  const fs::path scene = dir.path / "soft.toml";
  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = 1\nmax_steps = 2\n");
  const Outcome run =
      testing::RubcontNoPython("run " + scene.string() + " --quiet --out " + dir.path.string());
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("[orbits] L2 modulated orbits"));
  CHECK_THAT(run.out, Contains("from 1 of the 3 Hopf points bounding a stable rotating wave"));
  // The default numerics named, the followed Hopf point classified by its first Lyapunov
  // coefficient (its orbits are born stable above it), and the orbits' checks printed.
  CHECK_THAT(run.out, Contains("Gauss collocation of order 8 on 400 intervals per period"));
  CHECK_THAT(run.out, Contains("stable below  l1 -"));
  CHECK_THAT(run.out, Contains(": supercritical"));
  CHECK_THAT(run.out, Contains("check: largest defect"));
  const ResultReader file(dir.path / "soft" / "soft.h5");
  CHECK(file.ReadStringAttribute("/", "level") == "L2");
  CHECK(file.ReadStringAttribute("/orbits", "friction_law") == "tanh");
  CHECK(file.ReadStringAttribute("/orbits", "numerics") ==
        "4 segments, Gauss collocation of order 8 on 400 intervals per period");
  CHECK_FALSE(file.Children("/orbits/rotating_waves").empty());
  std::vector<std::string> orbits;
  for (const std::string& name : file.Children("/orbits")) {
    if (name != "rotating_waves") orbits.push_back(name);
  }
  REQUIRE(orbits.size() == 1);
  const std::string group = "/orbits/" + orbits.front();
  CHECK(file.ReadStringAttribute(group, "orbit_kind") == "relative");
  CHECK(file.ReadStringAttribute(group, "parameter_name") == "speed_rpm");
  const double hopf_rpm = file.ReadDoubleAttribute(group, "hopf_speed_rpm");
  const double hopf_hz = file.ReadDoubleAttribute(group, "hopf_precession_hz");
  CHECK(hopf_rpm == Approx(53.66).epsilon(0).margin(0.05));
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  const auto carrier = file.ReadDoubles(group + "/precession_hz");
  const auto stable = file.ReadInts(group + "/stable");
  REQUIRE(rpm.size() == 3);
  const auto defect = file.ReadDoubles(group + "/defect");
  REQUIRE(defect.size() == rpm.size());
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    CHECK(defect[i] < 1e-6);
    CHECK(rpm[i] > hopf_rpm);
    CHECK(carrier[i] == Approx(hopf_hz).epsilon(1e-4));
    CHECK(stable[i] == 1);
  }
  // The branch the Hopf point lies on is one of the rotating waves written beside the orbits.
  CHECK(file.Exists("/orbits/rotating_waves/" + file.ReadStringAttribute(group, "hopf_branch")));
  // Penetrations of about N/k1 ≈ 1e-5 m: within the default limit, 0.1 × the clearance
  // (3.81e-4 m), and beyond a limit of 1e-3 × it.
  const auto depth = file.ReadDoubles(group + "/max_penetration_left");
  REQUIRE(depth.size() == rpm.size());
  for (double d : depth) {
    CHECK(d > 0.0);
    CHECK(d < 0.1 * 3.81e-4);
    CHECK(d > 1e-3 * 3.81e-4);
  }
  CHECK(file.ReadStrings(group + "/untrusted") == std::vector<std::string>(rpm.size(), ""));
  CHECK_THAT(run.out, !Contains("untrusted"));

  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = 1\nmax_steps = 2\n"
                                     "[analysis.sweep]\nmax_penetration = 1e-3\n");
  const Outcome strict =
      testing::RubcontNoPython("run " + scene.string() + " --quiet --out " + dir.path.string());
  INFO(strict.out << strict.err);
  REQUIRE(strict.exit_code == 0);
  CHECK_THAT(strict.out, Contains("note: 3 of 3 orbits untrusted, the first at") &&
                             Contains("contact penetrates") && Contains("(limit 0.001)"));
  const ResultReader marked(dir.path / "soft" / "soft.h5");
  for (const std::string& why : marked.ReadStrings(group + "/untrusted")) {
    CHECK_THAT(why, Contains("× its clearance (limit 0.001)"));
  }
}

TEST_CASE("orbits from a transient, C(a) at 49.4 rpm: [analysis.orbits.transient] solves the whip "
          "locked at 1:3 as an orbit of three modulation periods and continues it to its period "
          "doubling, in /orbits/transient", "[orbits][cli][rub_orbits]") {
  // L3's verdicts (results/thesis_C_a/attractor_49_50rpm): an orbit at 49.3–49.6 rpm, chaos from
  // 49.7; bench/locked_whip_bench follows the same family between folds at 49.24472 and 58.65088
  // rpm, with its first period doubling at 49.47091 rpm (measured).
  TempDir dir;
  const Outcome run = testing::RunQuiet(
      dir, "ca_locked",
      testing::SceneWithAnalysis(
          "scenes/thesis_C_a_tori.toml",
          "[analysis]\nstages = [\"orbits\"]\nspeed_range_rpm = [49.35, 49.5]\n"
          "[analysis.orbits]\nhopf_points = 0\nmax_steps = 3\n"
          "[analysis.orbits.transient]\nspeed_rpm = 49.4\nlaps = 3\nmax_steps = 10\n"));
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("from 0 of the"));
  CHECK_THAT(run.out,
             Contains("[orbits] transient at 49.4 rpm, 8 s from rest and a 1 N·s impulse"));
  CHECK_THAT(run.out, Contains("its orbit (3 modulation periods): T = "));
  const ResultReader file(dir.path / "ca_locked" / "ca_locked.h5");
  const std::string group = "/orbits/transient";
  REQUIRE(file.Exists(group));
  CHECK(file.ReadStringAttribute(group, "orbit_kind") == "relative");
  CHECK(file.ReadDoubleAttribute(group, "laps") == 3.0);
  CHECK(file.ReadDoubleAttribute(group, "transient_speed_rpm") == 49.4);
  CHECK(file.ReadDoubleAttribute(group, "transient_settled") == 1.0);
  // Three modulation periods of the slip (125.66 Hz), the carrier the transient's precession.
  CHECK(3.0 / file.ReadDoubleAttribute(group, "start_period") ==
        Approx(125.66).epsilon(0).margin(0.05));
  CHECK(std::abs(file.ReadDoubleAttribute(group, "start_carrier_hz") -
                 file.ReadDoubleAttribute(group, "frame_precession_hz")) < 0.01);
  // Both ways from 49.4 rpm: stable below the period doubling, which is located between L3's
  // orbit and its chaos.
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  const auto stable = file.ReadInts(group + "/stable");
  REQUIRE(rpm.size() >= 4);
  CHECK(*std::min_element(rpm.begin(), rpm.end()) < 49.4);
  CHECK(*std::max_element(rpm.begin(), rpm.end()) > 49.47);
  const auto types = file.ReadStrings(group + "/special_points/type");
  const auto at = file.ReadDoubles(group + "/special_points/speed_rpm");
  REQUIRE(types.size() == 1);
  CHECK(types[0] == "period doubling");
  CHECK(at[0] == Approx(49.4709).epsilon(0).margin(1e-3));
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    INFO(rpm[i] << " rpm");
    CHECK(stable[i] == (rpm[i] < at[0] ? 1 : 0));
  }
  // The doubled orbits born there (branch_points = "follow"), six modulation periods each.
  REQUIRE(file.Exists("/orbits/transient_pd1"));
  CHECK(file.ReadStringAttribute("/orbits/transient_pd1", "parent") == "transient");
  // Side branches take [analysis.orbits] max_steps (3), the family the transient's (10).
  CHECK(file.ReadDoubles("/orbits/transient_pd1/speed_rpm").size() <= 4);
  CHECK(rpm.size() <= 2 * 10 + 1);
}

TEST_CASE("orbits from a transient, C(b) at 64 rpm: the whip L3 reads as period 3 in the section "
          "is an orbit of one modulation period, stable down to a Neimark-Sacker point next to "
          "its fold", "[orbits][cli][rub_orbits]") {
  // scenes/thesis_C_b_whip_64.toml on 1600 intervals (measured): T = 9.3552946 ms, a fold at
  // 58.0544 rpm and Neimark-Sacker points at 58.0590 and 58.1349 rpm, stable from the latter;
  // L3's third and fourth exponents at 64 rpm -7.20 +- 0.42 and -7.19 +- 0.18 1/s. Here on 800.
  TempDir dir;
  const Outcome run = testing::RunQuiet(
      dir, "cb_whip",
      testing::SceneWithAnalysis(
          "scenes/thesis_C_b_whip_64.toml",
          "[analysis]\nstages = [\"orbits\"]\nspeed_range_rpm = [57.95, 64.2]\n"
          "[analysis.sweep]\nexplicit_tolerance = 1e-9\n"
          "[analysis.orbits]\nhopf_points = 0\ncollocation_intervals = 800\n"
          "predictor = \"curved\"\nbranch_points = \"mark\"\nat_grazing = \"stop\"\n"
          "[analysis.orbits.transient]\nspeed_rpm = 64.0\nmax_steps = 60\n"));
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("its orbit (1 modulation period): T = "));
  const ResultReader file(dir.path / "cb_whip" / "cb_whip.h5");
  const std::string group = "/orbits/transient";
  REQUIRE(file.Exists(group));
  CHECK(1.0 / file.ReadDoubleAttribute(group, "start_period") ==
        Approx(106.89).epsilon(0).margin(0.05));
  const auto types = file.ReadStrings(group + "/special_points/type");
  const auto at = file.ReadDoubles(group + "/special_points/speed_rpm");
  double fold = 0.0, upper_ns = 0.0;
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (types[i] == "fold") fold = at[i];
    if (types[i] == "Neimark-Sacker") upper_ns = std::max(upper_ns, at[i]);
  }
  CHECK(fold == Approx(58.0544).epsilon(0).margin(5e-3));
  CHECK(upper_ns == Approx(58.1349).epsilon(0).margin(5e-3));
  // Stable only above the upper point, on the side through the transient's orbit; there the
  // multipliers give L3's exponents at 64 rpm.
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  const auto stable = file.ReadInts(group + "/stable");
  const auto largest = file.ReadDoubles(group + "/max_multiplier_modulus");
  const auto period = file.ReadDoubles(group + "/period");
  bool stable_at_64 = false;
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    INFO(rpm[i] << " rpm");
    if (stable[i] == 1) CHECK(rpm[i] > upper_ns);
    if (rpm[i] == 64.0) {
      stable_at_64 = stable[i] == 1;
      CHECK(std::log(largest[i]) / period[i] == Approx(-7.2).epsilon(0).margin(0.45));
    }
  }
  CHECK(stable_at_64);
}

TEST_CASE("orbits from a transient, C(a) at 74 rpm: the whip a transient from rest reaches "
          "inside the 3:7 tongue is locked at 19:45, a stable orbit of 45 modulation periods",
          "[orbits][cli][rub_orbits]") {
  // The reference is time marching's (bench/section_return_bench 74 2000 a dopri 1e-9 rest,
  // results/bench/section_return.txt): settled from rest as this stage settles, the section of
  // one modulation period (line 124.2208 Hz) comes back after 45 periods to 8.2e-6, turning by
  // 19/45 per period. scenes/thesis_C_a_locked_74.toml on 1600 intervals: stable from a period
  // doubling at 73.9307 rpm to a fold at 74.0708 rpm, largest multiplier 0.304 at 74 rpm. Here
  // on 800 (400 fails in the guess's first integration), one step each way (measured 0.470,
  // 0.305 and 0.230 at 73.982, 74 and 74.017 rpm).
  TempDir dir;
  const Outcome run = testing::RunQuiet(
      dir, "ca_19_45",
      testing::SceneWithAnalysis(
          "scenes/thesis_C_a_locked_74.toml",
          "[analysis]\nstages = [\"orbits\"]\nspeed_range_rpm = [70.0, 79.0]\n"
          "[analysis.sweep]\nexplicit_tolerance = 1e-9\n"
          "[analysis.orbits]\nhopf_points = 0\ncollocation_intervals = 800\n"
          "predictor = \"curved\"\nbranch_points = \"mark\"\n"
          "[analysis.orbits.transient]\nspeed_rpm = 74.0\nlaps = 45\nsearch_seconds = 4.0\n"
          "max_steps = 1\n"));
  INFO(run.out << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("its orbit (45 modulation periods): T = "));
  const ResultReader file(dir.path / "ca_19_45" / "ca_19_45.h5");
  const std::string group = "/orbits/transient";
  REQUIRE(file.Exists(group));
  CHECK(45.0 / file.ReadDoubleAttribute(group, "start_period") ==
        Approx(124.2208).epsilon(0).margin(0.001));
  const auto rpm = file.ReadDoubles(group + "/speed_rpm");
  const auto stable = file.ReadInts(group + "/stable");
  const auto largest = file.ReadDoubles(group + "/max_multiplier_modulus");
  REQUIRE(rpm.size() == 3);
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    INFO(rpm[i] << " rpm");
    CHECK(stable[i] == 1);
    if (rpm[i] == 74.0) {
      CHECK(largest[i] > 0.2);
      CHECK(largest[i] < 0.4);
    }
  }
}

// An [analysis.orbits] switch `key` with the choices `off`, `on` (in the schema's order): read into
// `field` of the family's options, `default_on` when not given, false with `off`, true with `on`;
// any other value is exit 2 naming the key, the value and the choices, and writes nothing.
void CheckOrbitsSwitch(const std::string& key, const std::string& off, const std::string& on,
                       bool default_on, bool PeriodicOrbitBranchOptions::*field) {
  const auto read = [&](const std::string& keys) {
    const Scene scene =
        ParseScene(SoftCaseAa("[analysis.orbits]\nhopf_points = 1\n" + keys), key, key);
    return RubOrbitOptionsOf(scene).orbits.*field;
  };
  CHECK(read("") == default_on);
  CHECK_FALSE(read(key + " = \"" + off + "\"\n"));
  CHECK(read(key + " = \"" + on + "\"\n"));

  TempDir dir;
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = 1\n" + key + " = \"halt\"\n");
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("analysis.orbits." + key + " = \"halt\": must be one of \"" + off +
                               "\", \"" + on + "\""));
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == 1);  // the scene
}

TEST_CASE("at_grazing in [analysis.orbits]: \"stop\" ends each family at its first grazing, "
          "\"continue\" (the default) goes on, another value is exit 2 naming the key",
          "[orbits][cli]") {
  CheckOrbitsSwitch("at_grazing", "continue", "stop", false,
                    &PeriodicOrbitBranchOptions::stop_at_grazing);
}

TEST_CASE("defect_check in [analysis.orbits]: \"on\" (the default) keeps the orbits' defect check, "
          "\"off\" leaves it out, another value is exit 2 naming the key",
          "[orbits][cli]") {
  CheckOrbitsSwitch("defect_check", "off", "on", true, &PeriodicOrbitBranchOptions::defect_check);
}

TEST_CASE("the orbits' check counts the orbits whose defect check could not integrate, and compares "
          "the others with the limit",
          "[orbits]") {
  const RubStructure structure;  // no contacts: no penetration to judge
  auto report = [&](const std::vector<double>& defects) {
    Branch branch;
    branch.measure_names = {"defect"};
    for (double d : defects) {
      BranchPoint p;
      p.measures = Vector::Constant(1, d);
      branch.points.push_back(p);
    }
    TempDir dir;
    ResultWriter writer(dir.path / "checks.h5");
    writer.CreateGroup("/orbits");
    std::ostringstream out;
    ReportOrbitChecks(branch, "/orbits", OrbitTrust{structure, 0.1}, writer, out);
    return out.str();
  };
  const std::string some = report({2e-8, kNaN, 3e-5});
  CHECK_THAT(some, Contains("check: largest defect 3.0e-05 (Dormand–Prince at 1e-12) of 2 orbits"));
  CHECK_THAT(some, Contains("an orbit's defect 3.0e-05 exceeds 1e-05"));
  CHECK_THAT(some, Contains("the defect check could not integrate 1 of 3 orbits"));
  const std::string none = report({kNaN, kNaN});
  CHECK_THAT(none, Contains("check: no defect measured"));
  CHECK_THAT(none, !Contains("exceeds"));
  CHECK_THAT(none, Contains("could not integrate 2 of 2 orbits"));
  const std::string fine = report({2e-8, 4e-7});
  CHECK_THAT(fine, Contains("check: largest defect 4.0e-07 (Dormand–Prince at 1e-12)\n"));
  CHECK_THAT(fine, !Contains("note:"));
}

TEST_CASE("stage orbits on a Jeffcott scene, or a bad [analysis.orbits] key, exits with code 2",
          "[orbits][cli]") {
  TempDir dir;
  const fs::path scene = dir.path / "bad.toml";
  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = 0\n");
  const Outcome run = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("analysis.orbits.hopf_points = 0: leaves the stage \"orbits\" "
                               "nothing to compute: give [analysis.orbits.transient]"));
  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = -1\n");
  const Outcome negative =
      testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(negative.exit_code == 2);
  CHECK_THAT(negative.err, Contains("analysis.orbits.hopf_points = -1: must be from 0 to 1000"));
  std::ofstream(scene) << SoftCaseAa("[analysis.orbits]\nhopf_points = 0\n"
                                     "[analysis.orbits.transient]\nspeed_rpm = 300.0\nlaps = 65\n"
                                     "seconds = 0.5\n");
  const Outcome transient =
      testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(transient.exit_code == 2);
  CHECK_THAT(transient.err, Contains("analysis.orbits.transient.laps = 65: must be at most 64"));
  CHECK_THAT(transient.err, Contains("analysis.orbits.transient.speed_rpm = 300.0: must lie in "
                                     "analysis.speed_range_rpm"));
  CHECK_THAT(transient.err, Contains("analysis.orbits.transient.seconds = 0.5: must be at least "
                                     "(settle_windows + 1)·settle_window"));
  std::string jeffcott = Slurp("scenes/jeffcott.toml");
  jeffcott = jeffcott.substr(0, jeffcott.find("[analysis]"));
  std::ofstream(scene) << jeffcott << "[analysis]\nstages = [\"orbits\"]\n";
  const Outcome wrong = testing::RubcontNoPython("run " + scene.string() + " --out " + dir.path.string());
  CHECK(wrong.exit_code == 2);
  CHECK_THAT(wrong.err, Contains("\"orbits\" does not apply to model \"jeffcott\""));
}

}  // namespace
}  // namespace rubcont
