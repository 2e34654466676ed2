#include "apps/scene.h"
#include "models/two_point_params.h"
#include "solvers/constants.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// A complete, valid scene (thesis case A(a)); each rule test breaks one thing in it.
const std::string kValid = R"(description = "test"

[rotor]
mass = 9.99
inertia = 0.029
contact_span = 0.29
mass_center = 0.145

[stator]
mass = 21.44
inertia = 0.206
span = 0.27
mass_center = 0.135
stiffness = [4.70e6, 4.70e6]
damping = [324.9, 324.9]

[contact]
clearance = [3.81e-4, 3.81e-4]
radius = [38.1e-3, 38.1e-3]
friction = 0.5
stiffness = 1.75e11
stiffness2 = 0.0
damping = 1.75e5

[center_damper]
damping = 52.0
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

Scene Parse(const std::string& text) { return ParseScene(text, "scene.toml", "scene"); }

// The resolved TOML without its first line (which names the source file).
std::string Body(const std::string& resolved) { return resolved.substr(resolved.find('\n') + 1); }

// The problems the loader reports for `text` (empty when it loads).
std::vector<std::string> Problems(const std::string& text) {
  try {
    Parse(text);
  } catch (const SceneError& e) {
    return e.problems();
  }
  return {};
}

std::string OnlyProblem(const std::string& text) {
  const auto problems = Problems(text);
  REQUIRE(problems.size() == 1);
  return problems[0];
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST_CASE("A valid scene loads with its values and documented defaults", "[scene]") {
  const Scene scene = Parse(kValid);
  CHECK(scene.name == "scene");
  CHECK(scene.model == ModelKind::kTwoPoint);
  CHECK(scene.two_point.rotor_mass == 9.99);
  CHECK(scene.two_point.support_stiffness[1] == 4.70e6);
  CHECK(scene.two_point.clearance[0] == 3.81e-4);
  CHECK(scene.two_point.center_damping == 52.0);
  CHECK(scene.two_point.imbalance == 0.0);  // [imbalance] absent: no imbalance
  CHECK(scene.two_point.friction_law.kind == FrictionLawKind::kExact);
  CHECK(scene.two_point.friction_law.velocity_scale == 1e-3);
  CHECK(scene.analysis.stages == std::vector<Stage>({Stage::kAnalytic, Stage::kBranches}));
  CHECK(scene.analysis.analytic.min_precession_hz == 1.0);
  CHECK(scene.analysis.analytic.max_precession_hz == 200.0);
  CHECK(scene.analysis.analytic.precession_points == 4000);
  for (const char* key : {"name", "model", "imbalance.mass_radius", "analysis.stages"})
    CHECK(std::find(scene.defaulted_keys.begin(), scene.defaulted_keys.end(), key) != scene.defaulted_keys.end());
  CHECK(std::find(scene.defaulted_keys.begin(), scene.defaulted_keys.end(), "rotor.mass") == scene.defaulted_keys.end());
}

TEST_CASE("Rule: TOML syntax errors give line and column", "[scene]") {
  const std::string problem = OnlyProblem(Replace(kValid, "inertia = 0.029", "inertia = = 0.029"));
  CHECK_THAT(problem, Contains("scene.toml:5:"));
  CHECK_THAT(problem, Contains("TOML syntax error"));
}

TEST_CASE("Rule: an unknown key is rejected with the closest known key", "[scene]") {
  const auto problems = Problems(Replace(kValid, "mass = 9.99", "mas = 9.99"));
  REQUIRE(problems.size() == 2);  // the misspelt key, and the key it was meant to be is missing
  CHECK(problems[0] == "scene.toml:4:1: rotor.mas: unknown key; did you mean rotor.mass?");
  CHECK_THAT(problems[1], Contains("rotor.mass: missing"));
  // A known key in the wrong section.
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nclearance = 1.0\n"),
             Contains("analysis.clearance: unknown key; did you mean contact.clearance?"));
  // Nothing close: the section's keys are listed.
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nwhatever_you_like = 1\n"),
             Contains("(known in [analysis]: stages, precession_range_hz, precession_points, speed_range_rpm, [analysis.sweep], [analysis.orbits], [analysis.tori], [analysis.loop])"));
}

TEST_CASE("Rule: an unknown section is rejected with the closest known section", "[scene]") {
  CHECK_THAT(OnlyProblem(kValid + "[centre_damper]\ndamping = 1.0\n"),
             Contains("[centre_damper]: unknown section; did you mean [center_damper]?"));
}

TEST_CASE("Rule: a missing required key is named with its meaning and unit", "[scene]") {
  CHECK_THAT(OnlyProblem(Replace(kValid, "mass = 9.99\n", "")),
             Contains("scene.toml: rotor.mass: missing; required — m_r: rotor mass. [kg]"));
  // A whole section missing: every one of its keys.
  const std::string no_stator = Replace(kValid,
      "[stator]\nmass = 21.44\ninertia = 0.206\nspan = 0.27\nmass_center = 0.135\n"
      "stiffness = [4.70e6, 4.70e6]\ndamping = [324.9, 324.9]\n", "");
  CHECK(Problems(no_stator).size() == 6);
}

TEST_CASE("Rule: an optional component's section, once present, needs its key", "[scene]") {
  CHECK_THAT(OnlyProblem(Replace(kValid, "damping = 52.0", "")),
             Contains("center_damper.damping: missing; required when [center_damper] is present"));
  // Absent section: no damper.
  const Scene scene = Parse(Replace(kValid, "[center_damper]\ndamping = 52.0\n", ""));
  CHECK(scene.two_point.center_damping == 0.0);
}

TEST_CASE("Rule: wrong types are rejected, integers are fine where floats are expected", "[scene]") {
  CHECK(OnlyProblem(Replace(kValid, "mass = 9.99", "mass = \"heavy\"")) ==
        "scene.toml:4:8: rotor.mass = \"heavy\": must be a number (kg)");
  CHECK(Parse(Replace(kValid, "mass = 9.99", "mass = 10")).two_point.rotor_mass == 10.0);
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nprecession_points = 4000.5\n"),
             Contains("analysis.precession_points = 4000.5: must be an integer"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "stiffness = [4.70e6, 4.70e6]", "stiffness = [4.70e6]")),
             Contains("stator.stiffness = [4700000.0]: must be an array of two numbers (N/m)"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "stiffness = [4.70e6, 4.70e6]", "stiffness = 4.70e6")),
             Contains("must be an array of two numbers (N/m)"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nstages = \"analytic\"\n"),
             Contains("analysis.stages = \"analytic\": must be an array of strings"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis.stages]\nfirst = \"analytic\"\n"),
             Contains("analysis.stages is a table: must be a value"));
  CHECK_THAT(OnlyProblem("imbalance = 3.4e-5\n" + kValid),
             Contains("must be a table [imbalance]"));
}

TEST_CASE("Rule: non-finite values are rejected", "[scene]") {
  CHECK_THAT(OnlyProblem(Replace(kValid, "mass = 9.99", "mass = nan")),
             Contains("rotor.mass = nan: must be finite (kg)"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "mass_center = 0.145", "mass_center = inf")),
             Contains("rotor.mass_center = inf: must be finite (m)"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "damping = [324.9, 324.9]", "damping = [324.9, -inf]")),
             Contains("right value must be finite (N·s/m)"));
}

TEST_CASE("Rule: non-physical values name key, value and rule", "[scene]") {
  CHECK(OnlyProblem(Replace(kValid, "mass = 9.99", "mass = -1")) ==
        "scene.toml:4:8: rotor.mass = -1: must be positive (kg)");
  CHECK_THAT(OnlyProblem(Replace(kValid, "clearance = [3.81e-4, 3.81e-4]", "clearance = [3.81e-4, 0.0]")),
             Contains("contact.clearance = [0.000381, 0.0]: right value must be positive (m)"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "friction = 0.5", "friction = -0.1")),
             Contains("contact.friction = -0.1: must be non-negative"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "damping = [324.9, 324.9]", "damping = [-1, 324.9]")),
             Contains("left value must be non-negative (N·s/m)"));
  CHECK_THAT(OnlyProblem(Replace(kValid, "span = 0.27", "span = 0")),
             Contains("stator.span = 0: must be positive (m)"));
  // Zero is physical where the rule is ≥ 0, and an overhung mass centre is fine.
  CHECK(Parse(Replace(kValid, "friction = 0.5", "friction = 0")).two_point.friction == 0.0);
  CHECK(Parse(Replace(kValid, "mass_center = 0.145", "mass_center = 0.35")).two_point.a() > 1.0);
}

TEST_CASE("Rule: ranges must increase and start above zero", "[scene]") {
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nprecession_range_hz = [200, 1]\n"),
             Contains("analysis.precession_range_hz = [200, 1]: inverted range: must be increasing (0 < low < high) (Hz)"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nprecession_range_hz = [0, 100]\n"),
             Contains("low end must be positive"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nprecession_points = 1\n"),
             Contains("analysis.precession_points = 1: must be from 2 to 1000000"));
}

TEST_CASE("Rule: unknown model names list the known ones", "[scene]") {
  CHECK_THAT(OnlyProblem("model = \"jefcott\"\n" + kValid),
             Contains("scene.toml:1:9: model = \"jefcott\": must be one of \"two_point\", \"jeffcott\""));
}

TEST_CASE("Jeffcott scenes: their own section, the other model's keys rejected", "[scene]") {
  const std::string jeffcott = ReadFile("scenes/jeffcott.toml");
  const Scene scene = ParseScene(jeffcott, "scene.toml", "x");
  CHECK(scene.model == ModelKind::kJeffcott);
  CHECK(scene.jeffcott.k_s == 5.0e6);
  CHECK_THAT(OnlyProblem(jeffcott + "[rotor]\nmass = 9.99\n"),
             Contains("rotor.mass: not a key of model \"jeffcott\""));
  CHECK_THAT(OnlyProblem(Replace(jeffcott, "k_s = 5.0e6\n", "")),
             Contains("jeffcott.k_s: missing; required"));
  CHECK_THAT(OnlyProblem(Replace(jeffcott, "C = 3.81e-4", "C = 0.0")),
             Contains("jeffcott.C = 0.0: must be positive (m)"));
}

TEST_CASE("Rule: stages must be known, named once, and at least one", "[scene]") {
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nstages = [\"analytik\"]\n"),
             Contains("\"analytik\" is not a stage (implemented: \"analytic\", \"branches\", "
                      "\"orbits\", \"tori\", \"sweep\", \"loop\")"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nstages = [\"analytic\", \"analytic\"]\n"),
             Contains("\"analytic\" is listed twice"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis]\nstages = []\n"), Contains("must name at least one stage"));
}

// A textbook scene: the Duffing oscillator of scenes/duffing.toml, without its optional keys.
const std::string kDuffing = R"(model = "duffing"

[duffing]
damping = 0.05
stiffness = 1.0
cubic = 1.0
force = 0.3
frequency_range = [0.5, 2.5]
)";

TEST_CASE("Textbook models: their own sections, the orbits stage by default, start in range",
          "[scene]") {
  const Scene duffing = Parse(kDuffing);
  CHECK(duffing.model == ModelKind::kDuffing);
  CHECK(duffing.duffing.force == 0.3);
  CHECK(duffing.orbits.parameter_range == std::array<double, 2>{0.5, 2.5});
  CHECK(duffing.orbits.start == 0.5);  // the low end by default
  CHECK(duffing.orbits.segments == 1);
  CHECK(duffing.analysis.stages == std::vector<Stage>{Stage::kOrbits});
  CHECK(Body(ResolvedSceneToml(ParseScene(ResolvedSceneToml(duffing), "x", "x"))) ==
        Body(ResolvedSceneToml(duffing)));
  CHECK(Parse(kDuffing + "[duffing.orbits]\nstart = 1.5\nsegments = 4\n").orbits.start == 1.5);

  // Keys of one model are not keys of another; the rotor sections are not textbook ones.
  CHECK_THAT(OnlyProblem(kDuffing + "[van_der_pol]\nmu_range = [1.0, 2.0]\n"),
             Contains("van_der_pol.mu_range: not a key of model \"duffing\""));
  CHECK_THAT(OnlyProblem(kDuffing + "[rotor]\nmass = 9.99\n"),
             Contains("rotor.mass: not a key of model \"duffing\""));
  CHECK_THAT(OnlyProblem(Replace(kDuffing, "force = 0.3\n", "")),
             Contains("duffing.force: missing; required"));
  // Values: key, value and rule.
  CHECK_THAT(OnlyProblem(Replace(kDuffing, "[0.5, 2.5]", "[2.5, 0.5]")),
             Contains("duffing.frequency_range = [2.5, 0.5]: inverted range: must be increasing"));
  CHECK_THAT(OnlyProblem(Replace(kDuffing, "damping = 0.05", "damping = -0.05")),
             Contains("duffing.damping = -0.05: must be non-negative"));
  CHECK_THAT(OnlyProblem(kDuffing + "[duffing.orbits]\nstart = 3.0\n"),
             Contains("duffing.orbits.start = 3.0: must lie in duffing.frequency_range = [0.5, 2.5]"));
  CHECK_THAT(OnlyProblem(kDuffing + "[duffing.orbits]\nsegments = 0\n"),
             Contains("duffing.orbits.segments = 0: must be from 1 to 1000"));
  CHECK_THAT(OnlyProblem(kDuffing + "[duffing.orbits]\ntolerance = 1.5\n"),
             Contains("duffing.orbits.tolerance = 1.5: must lie strictly between 0 and 1"));
  CHECK_THAT(OnlyProblem(kDuffing + "[duffing.orbits]\nsegments = 2.0\n"),
             Contains("duffing.orbits.segments = 2.0: must be an integer"));
  // Stages that do not fit the model.
  CHECK_THAT(OnlyProblem(kDuffing + "[analysis]\nstages = [\"branches\"]\n"),
             Contains("analysis.stages = [\"branches\"]: \"branches\" does not apply to model "
                      "\"duffing\", whose stages are \"orbits\"; \"branches\" is a stage of "
                      "\"two_point\", \"jeffcott\""));
  // Model two_point has it too (the modulated orbits), with [analysis.orbits]; the Jeffcott
  // rotor does not (tests/apps/orbits_stage_test.cpp).
  const Scene rotor = Parse(kValid + "[analysis]\nstages = [\"orbits\"]\n[analysis.orbits]\n"
                                     "hopf_points = 3\nmax_steps = 7\n");
  REQUIRE(rotor.analysis.stages.size() == 1);
  CHECK(rotor.analysis.stages[0] == Stage::kOrbits);
  CHECK(rotor.analysis.orbits.hopf_points == 3);
  CHECK(rotor.analysis.orbits.max_steps == 7);
  CHECK(rotor.analysis.orbits.segments == 4);
  CHECK(rotor.analysis.orbits.tolerance == 1e-7);

  // And the tori born from them, with [analysis.tori].
  const Scene tori = Parse(kValid + "[analysis]\nstages = [\"orbits\", \"tori\"]\n[analysis.tori]\n"
                                    "harmonics = 6\nmax_fourier_tail = 1e-3\n");
  REQUIRE(tori.analysis.stages.size() == 2);
  CHECK(tori.analysis.stages[1] == Stage::kTori);
  CHECK(tori.analysis.tori.harmonics == 6);
  CHECK(tori.analysis.tori.max_fourier_tail == 1e-3);
  CHECK(tori.analysis.tori.max_steps == 40);
  CHECK_THAT(OnlyProblem(kValid + "[analysis.tori]\nsamples = 3\n"),
             Contains("analysis.tori.samples = 3: must be at least 4"));
  CHECK_THAT(OnlyProblem(kValid + "[analysis.tori]\nmax_fourier_tail = 1.0\n"),
             Contains("analysis.tori.max_fourier_tail = 1.0: must lie strictly between 0 and 1"));
  CHECK_THAT(OnlyProblem(kDuffing + "[analysis]\nstages = [\"tori\"]\n"),
             Contains("\"tori\" does not apply to model \"duffing\""));

  const Scene stuart_landau =
      Parse("model = \"stuart_landau\"\n[stuart_landau]\nomega = 1.0\nlambda_range = [0.1, 1.0]\n");
  CHECK(stuart_landau.stuart_landau.gamma == 0.0);  // optional
  CHECK(stuart_landau.orbits.start == 0.1);
  CHECK_THAT(OnlyProblem("model = \"van_der_pol\"\n"), Contains("van_der_pol.mu_range: missing"));
  CHECK_THAT(OnlyProblem("model = \"duffin\"\n"),
             Contains("model = \"duffin\": must be one of \"two_point\", \"jeffcott\", \"duffing\", "
                      "\"stuart_landau\", \"van_der_pol\""));
}

TEST_CASE("Rule: the friction law kind is one of its choices", "[scene]") {
  CHECK_THAT(OnlyProblem(kValid + "[contact.friction_law]\nkind = \"coulomb\"\n"),
             Contains("contact.friction_law.kind = \"coulomb\": must be one of \"exact\", \"tanh\""));
  CHECK(Parse(kValid + "[contact.friction_law]\nkind = \"tanh\"\nvelocity_scale = 2e-3\n")
            .two_point.friction_law.kind == FrictionLawKind::kTanh);
  CHECK_THAT(OnlyProblem(kValid + "[contact.friction_law]\nvelocity_scale = 0.0\n"),
             Contains("velocity_scale = 0.0: must be positive (m/s)"));
}

TEST_CASE("Rule: scene names are safe directory names", "[scene]") {
  CHECK_THAT(OnlyProblem("name = \"my scene\"\n" + kValid), Contains("name = \"my scene\": must be 1–100 characters"));
  CHECK_THAT(OnlyProblem("name = \"../up\"\n" + kValid), Contains("must be 1–100 characters"));
  // Default from a file name that is not a valid scene name.
  CHECK_THROWS_WITH(ParseScene(kValid, "my scene.toml", "my scene"),
                    Contains("name (from the file name) = \"my scene\""));
  CHECK(Parse("name = \"A.b-c_1\"\n" + kValid).name == "A.b-c_1");
}

TEST_CASE("All problems of a file are reported at once", "[scene]") {
  std::string text = Replace(kValid, "mass = 9.99", "mass = -1");
  text = Replace(text, "friction = 0.5", "friction = -2");
  text += "[analysis]\nstage = [\"analytic\"]\n";
  const auto problems = Problems(text);
  REQUIRE(problems.size() == 3);
  CHECK_THAT(problems[0], Contains("analysis.stage: unknown key; did you mean analysis.stages?"));
}

TEST_CASE("A missing file is a scene error", "[scene]") {
  CHECK_THROWS_WITH(LoadScene("no/such/scene.toml"), Contains("no/such/scene.toml: no such file"));
}

TEST_CASE("The resolved TOML reproduces the scene", "[scene]") {
  const Scene scene = Parse(Replace(kValid, "mass = 9.99", "mass = 10"));
  const std::string resolved = ResolvedSceneToml(scene);
  const Scene again = ParseScene(resolved, "resolved.toml", "other");
  CHECK(again.name == "scene");
  CHECK(again.two_point.rotor_mass == 10.0);
  CHECK(Body(ResolvedSceneToml(again)) == Body(resolved));
  CHECK(again.defaulted_keys.empty());  // every key is written out
  CHECK_THAT(resolved, Contains("stiffness = 175000000000.0"));
}

const std::string kFlexible = R"(
[flexible]
rotor_outer_diameter = 0.04718
rotor_inner_diameter = 0.03161
stator_outer_diameter = 0.13722
stator_inner_diameter = 0.07696
youngs_modulus = 2.0684e11
shear_modulus = 7.929e10
density = 7833.0
)";

TEST_CASE("[flexible]: level L4 from the rigid scene's data, resolved only when present",
          "[scene]") {
  const Scene rigid = Parse(kValid);
  CHECK_FALSE(rigid.flexible.enabled);
  CHECK_THAT(ResolvedSceneToml(rigid), !Contains("[flexible]"));
  const Scene flexible = Parse(kValid + kFlexible);
  REQUIRE(flexible.flexible.enabled);
  CHECK(flexible.flexible.rotor_outer_diameter == 0.04718);
  CHECK(flexible.flexible.modes == 4);  // defaults
  CHECK(flexible.flexible.elements == 8);
  CHECK(flexible.flexible.gyroscopic);
  const std::string resolved = ResolvedSceneToml(flexible);
  CHECK_THAT(resolved, Contains("[flexible]"));
  const Scene again = ParseScene(resolved, "resolved.toml", "other");
  CHECK(again.flexible.enabled);
  CHECK(Body(ResolvedSceneToml(again)) == Body(resolved));
  const Scene off = Parse(kValid + kFlexible + "modes = 6\ngyroscopic = \"off\"\n");
  CHECK(off.flexible.modes == 6);
  CHECK_FALSE(off.flexible.gyroscopic);
}

TEST_CASE("Rule: [flexible] names the key, value and rule of a shaft that cannot be built",
          "[scene]") {
  CHECK(OnlyProblem(Replace(kValid + kFlexible, "rotor_inner_diameter = 0.03161",
                            "rotor_inner_diameter = 0.05")) ==
        "scene.toml:30:24: flexible.rotor_inner_diameter = 0.05: must be below "
        "flexible.rotor_outer_diameter = 0.04718 m");
  CHECK_THAT(OnlyProblem(Replace(kValid + kFlexible, "shear_modulus = 7.929e10",
                                 "shear_modulus = 7.929e9")),
             Contains("flexible.shear_modulus = 7929000000.0: gives the Poisson ratio E/(2G) − 1 = 12.04: "
                      "must lie in (−1, 0.5]"));
  CHECK_THAT(OnlyProblem(Replace(kValid + kFlexible, "rotor_outer_diameter = 0.04718",
                                 "rotor_outer_diameter = 0.1")),
             Contains("flexible.rotor_outer_diameter = 0.1: rotor shaft: 16.06 kg over 0.29 m is "
                      "not lighter than the body (9.99 kg): take a thinner section"));
  CHECK_THAT(OnlyProblem(kValid + kFlexible + "modes = 900\n"),
             Contains("flexible.modes = 900: the interior has only"));
  CHECK_THAT(OnlyProblem(Replace(kValid + kFlexible, "density = 7833.0\n", "")),
             Contains("flexible.density: missing; required when [flexible] is present"));
  // Only model two_point has it.
  CHECK_THAT(Problems("model = \"van_der_pol\"\n[van_der_pol]\nmu_range = [0.2, 2.0]\n" +
                      kFlexible)[0],
             Contains("not a key of model \"van_der_pol\""));
}

// A listed rotor: one 0.29 m segment in 8 elements with a disk at its middle; [rotor] without the
// rigid-body data the rows supply.
const std::string kListedRotor = R"(
[[flexible.rotor_shaft]]
length = 0.29
outer_diameter = 0.04801
inner_diameter = 0.03281
elements = 8

[[flexible.rotor_disks]]
station = 4
mass = 7.7983
diametral_inertia = 0.013177
polar_inertia = 0.026353
)";

std::string WithoutRigidRotor(const std::string& text) {
  return Replace(text, "mass = 9.99\ninertia = 0.029\ncontact_span = 0.29\nmass_center = 0.145\n", "");
}

TEST_CASE("[flexible] lists: shaft segments, disks and supports by station supply the rigid data",
          "[scene]") {
  const std::string uniform_stator = R"(
[flexible]
stator_outer_diameter = 0.13722
stator_inner_diameter = 0.07696
youngs_modulus = 2.0684e11
shear_modulus = 7.929e10
density = 7833.0
)";
  const Scene scene = Parse(WithoutRigidRotor(kValid) + uniform_stator + kListedRotor);
  REQUIRE(scene.flexible.RotorListed());
  CHECK_FALSE(scene.flexible.StatorListed());
  REQUIRE(scene.flexible.rotor_shaft.size() == 1);
  CHECK(scene.flexible.rotor_shaft[0].elements == 8);
  CHECK(scene.flexible.rotor_shaft[0].section.youngs_modulus == 2.0684e11);  // [flexible]'s
  CHECK(scene.flexible.rotor_contact_stations == std::array<int, 2>{0, 8});  // first and last
  // The shaft: 0.29 m of π(D² − d²)/4 at 7833 kg/m³ = 2.1916 kg, plus the disk; centre 0.145 m.
  const double shaft = 7833.0 * kPi * (0.04801 * 0.04801 - 0.03281 * 0.03281) / 4 * 0.29;
  CHECK(scene.two_point.rotor_mass == Approx(shaft + 7.7983).epsilon(1e-14));
  CHECK(scene.two_point.contact_span == Approx(0.29).epsilon(1e-14));
  CHECK(scene.two_point.rotor_mass_center == Approx(0.145).epsilon(1e-14));
  CHECK(scene.two_point.rotor_inertia ==
        Approx(shaft * (0.29 * 0.29 / 12 + (0.04801 * 0.04801 + 0.03281 * 0.03281) / 16) + 0.013177)
            .epsilon(1e-12));
  CHECK(scene.supplied_keys == std::vector<std::string>{"rotor.mass", "rotor.contact_span",
                                                        "rotor.mass_center", "rotor.inertia"});
  // Resolved, the rows come back with every key and the supplied data as values: the same scene.
  const std::string resolved = ResolvedSceneToml(scene);
  CHECK_THAT(resolved, Contains("[[flexible.rotor_shaft]]\nlength = 0.29\nouter_diameter = 0.04801\n"
                                "inner_diameter = 0.03281\nyoungs_modulus = 206840000000.0\n"
                                "shear_modulus = 79290000000.0\ndensity = 7833.0\nelements = 8\n"));
  CHECK_THAT(resolved, !Contains("rotor_outer_diameter"));
  CHECK_THAT(resolved, Contains("rotor_contact_stations = [0, 8]"));
  const Scene again = ParseScene(resolved, "resolved.toml", "other");
  CHECK(again.two_point.rotor_mass == scene.two_point.rotor_mass);
  CHECK(Body(ResolvedSceneToml(again)) == Body(resolved));

  // A segment's own material; ν instead of G.
  const Scene own = Parse(WithoutRigidRotor(kValid) + uniform_stator +
                          Replace(kListedRotor, "elements = 8\n",
                                  "elements = 8\nyoungs_modulus = 1.1e11\npoisson_ratio = 0.34\n"));
  CHECK(own.flexible.rotor_shaft[0].section.youngs_modulus == 1.1e11);
  CHECK(own.flexible.rotor_shaft[0].section.shear_modulus == Approx(1.1e11 / 2.68).epsilon(1e-15));

  // Supports by station supply [stator]'s stiffness and damping.
  const std::string supports = R"(
[[flexible.stator_shaft]]
length = 0.27
outer_diameter = 0.13722
inner_diameter = 0.07696
elements = 4

[[flexible.stator_disks]]
station = 2
mass = 0.0017262
diametral_inertia = 0.042597

[[flexible.stator_supports]]
station = 0
stiffness = 4.0e6

[[flexible.stator_supports]]
station = 4
stiffness = 5.0e6
damping = 300.0

[[flexible.stator_supports]]
station = 4
stiffness = 1.0e5
)";
  const std::string listed_stator =
      Replace(uniform_stator, "stator_outer_diameter = 0.13722\nstator_inner_diameter = 0.07696\n", "");
  const Scene both = Parse(
      Replace(Replace(WithoutRigidRotor(kValid),
                      "mass = 21.44\ninertia = 0.206\nspan = 0.27\nmass_center = 0.135\n"
                      "stiffness = [4.70e6, 4.70e6]\ndamping = [324.9, 324.9]\n", ""),
              "[stator]\n", "") +
      listed_stator + kListedRotor + supports);
  CHECK(both.two_point.support_stiffness == std::array<double, 2>{4.0e6, 5.1e6});
  CHECK(both.two_point.support_damping == std::array<double, 2>{0.0, 300.0});
  CHECK(both.two_point.stator_span == Approx(0.27).epsilon(1e-14));
  CHECK(both.two_point.stator_mass_center == Approx(0.135).epsilon(1e-12));
  CHECK_THAT(ResolvedSceneToml(both), !Contains("elements = 8\n\n[flexible"));  // no uniform key
  CHECK_THAT(ResolvedSceneToml(both), !Contains("\nelements = 8\nmodes"));
}

TEST_CASE("Rule: [flexible] lists name the row, key, value and rule", "[scene]") {
  const std::string material = "\n[flexible]\nstator_outer_diameter = 0.13722\n"
                               "stator_inner_diameter = 0.07696\nyoungs_modulus = 2.0684e11\n"
                               "shear_modulus = 7.929e10\ndensity = 7833.0\n";
  const std::string base = WithoutRigidRotor(kValid) + material;
  CHECK_NOTHROW(Parse(base + kListedRotor));
  // Given, the rigid data must agree with the rows.
  const std::vector<std::string> disagree = Problems(kValid + material + kListedRotor);
  REQUIRE(disagree.size() == 2);  // the rounded disk: mass and inertia differ, span and centre agree
  CHECK_THAT(disagree[0], Contains("rotor.mass = 9.99: the shaft listed in [[flexible.rotor_shaft]] "
                                   "gives 9.989986537 kg: must agree to 1e-6, or leave rotor.mass "
                                   "out to take the shaft's"));
  CHECK_THAT(disagree[1], Contains("rotor.inertia = 0.029: the shaft listed in "
                                   "[[flexible.rotor_shaft]] gives 0.02900026306 kg·m²"));
  CHECK_THAT(OnlyProblem(base + kListedRotor + "[[flexible.rotor_shaft]]\nlength = 0.1\n"),
             Contains("flexible.rotor_shaft[1].outer_diameter: missing; required — Outer diameter. [m]"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "elements = 8", "element = 8")),
             Contains("flexible.rotor_shaft[0].element: unknown key (known in "
                      "[[flexible.rotor_shaft]]: length, outer_diameter"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "inner_diameter = 0.03281",
                                        "inner_diameter = 0.05")),
             Contains("flexible.rotor_shaft[0].inner_diameter = 0.05: must be below "
                      "outer_diameter = 0.04801 m"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "length = 0.29", "length = -0.29")),
             Contains("flexible.rotor_shaft[0].length = -0.29: must be positive (m)"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "elements = 8",
                                        "elements = 8\nshear_modulus = 8e10\npoisson_ratio = 0.3")),
             Contains("flexible.rotor_shaft[0].poisson_ratio = 0.3: give shear_modulus or "
                      "poisson_ratio, not both"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "elements = 8", "elements = 8\npoisson_ratio = 0.7")),
             Contains("flexible.rotor_shaft[0].poisson_ratio = 0.7: gives the Poisson ratio "
                      "E/(2G) − 1 = 0.7: must lie in (−1, 0.5]"));
  CHECK_THAT(OnlyProblem(base + Replace(kListedRotor, "station = 4", "station = 9")),
             Contains("flexible.rotor_disks[0].station = 9: must name a station of the listed "
                      "rotor shaft (0 to 8)"));
  CHECK_THAT(OnlyProblem(base + kListedRotor + "\n[[flexible.stator_disks]]\nstation = 1\nmass = 1.0\n"),
             Contains("[[flexible.stator_disks]]: stations number a listed shaft: add "
                      "[[flexible.stator_shaft]] rows (a uniform stator gets its disk from [stator])"));
  // A key of the other form.
  CHECK_THAT(OnlyProblem(base + "rotor_outer_diameter = 0.05\n" + kListedRotor),
             Contains("flexible.rotor_outer_diameter = 0.05: not used: [[flexible.rotor_shaft]] "
                      "lists the rotor's shaft"));
  CHECK_THAT(OnlyProblem(kValid + material + "rotor_outer_diameter = 0.04801\nstator_contact_stations = [0, 8]\n"),
             Contains("flexible.stator_contact_stations = [0, 8]: not used: stations number a "
                      "listed shaft: add [[flexible.stator_shaft]] rows"));
  CHECK_THAT(OnlyProblem(base + "rotor_contact_stations = [2, 9]\n" + kListedRotor),
             Contains("flexible.rotor_contact_stations = [2, 9]: must name stations of the listed "
                      "shaft (0 to 8)"));
  CHECK_THAT(OnlyProblem(base + "rotor_contact_stations = [3, 3]\n" + kListedRotor),
             Contains("flexible.rotor_contact_stations = [3, 3]: must be stations 0 ≤ left < right"));
  // c_d acts at the mid-span of the contacts: stations 1 and 8 leave none there.
  CHECK_THAT(OnlyProblem(base + "rotor_contact_stations = [1, 8]\n" + kListedRotor),
             Contains("rotor shaft: center_damping = 52 N·s/m acts at the mid-span of the "
                      "contacts, 0.126875 m from the left one, where the shaft has no station (the "
                      "nearest, 4, is 0.0181 m away)"));
  CHECK_THAT(OnlyProblem(kValid + kFlexible + "rotor_shaft = 3\n"),
             Contains("flexible.rotor_shaft = 3: must be rows [[flexible.rotor_shaft]] (an array "
                      "of tables)"));
  CHECK_THAT(Problems("model = \"van_der_pol\"\n[van_der_pol]\nmu_range = [0.2, 2.0]\n" + kListedRotor)[0],
             Contains("[[flexible.rotor_shaft]]: not a table of model \"van_der_pol\""));
}

TEST_CASE("Every scene file in scenes/ loads, with the thesis's Table 1 values", "[scene]") {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator("scenes")) {
    if (entry.path().extension() != ".toml") continue;
    INFO(entry.path());
    const Scene scene = LoadScene(entry.path());
    CHECK(scene.name == (entry.path().stem() == "default" ? "default" : entry.path().stem().string()));
    CHECK(Body(ResolvedSceneToml(ParseScene(ResolvedSceneToml(scene), "x", "x"))) == Body(ResolvedSceneToml(scene)));
    ++count;
  }
  CHECK(count >= 11);
  // The library's cases are the scenes' (the tests and benches build them from ThesisCase*).
  for (const auto& [file, params] : {std::pair{"scenes/thesis_A_a.toml", ThesisCaseAa()},
                                     std::pair{"scenes/thesis_C_a.toml", ThesisCaseCa()},
                                     std::pair{"scenes/thesis_C_b.toml", ThesisCaseCb()},
                                     std::pair{"scenes/thesis_C_c.toml", ThesisCaseCc()}}) {
    INFO(file);
    const TwoPointParams& loaded = LoadScene(file).two_point;
    CHECK(loaded.rotor_mass_center == params.rotor_mass_center);
    CHECK(loaded.rotor_inertia == params.rotor_inertia);
    CHECK(loaded.center_damping == params.center_damping);
    CHECK(loaded.clearance == params.clearance);
  }
  const Scene c_b = LoadScene("scenes/thesis_C_b.toml");
  CHECK(c_b.two_point.rotor_mass_center == 0.26);
  CHECK(c_b.two_point.rotor_inertia == 0.07);
  CHECK(c_b.two_point.Rci(0) == Approx(100.0));
  CHECK(c_b.two_point.Rci(1) == Approx(125.0));
  CHECK(LoadScene("scenes/thesis_B_c.toml").two_point.Rci(0) == Approx(125.0));
  CHECK(LoadScene("scenes/thesis_A_a_imbalance.toml").two_point.imbalance == 3.43e-5);
  CHECK(LoadScene("scenes/thesis_A_a.toml").two_point.imbalance == 0.0);
  CHECK(LoadScene("scenes/overhung_beyond_right.toml").two_point.a() > 1.0);
}

TEST_CASE("The built-in default scene is scenes/default.toml", "[scene]") {
  CHECK(std::string(DefaultSceneToml()) == ReadFile("scenes/default.toml"));
  const Scene scene = DefaultScene();
  CHECK(scene.name == "default");
  CHECK(scene.two_point.a() == Approx(0.5));
  CHECK(scene.two_point.Rci(0) == Approx(100.0));
  CHECK(scene.two_point.Rci(1) == Approx(100.0));
}

TEST_CASE("scenes/README.md embeds the key reference generated from the schema", "[scene]") {
  const std::string readme = ReadFile("scenes/README.md");
  const std::string begin = "<!-- BEGIN KEYS: generated by `rubcont scene keys`; do not edit by hand -->\n";
  const std::string end = "<!-- END KEYS -->";
  const auto from = readme.find(begin);
  const auto to = readme.find(end);
  REQUIRE(from != std::string::npos);
  REQUIRE(to != std::string::npos);
  INFO("regenerate with: build/rubcont scene keys, and paste between the markers");
  CHECK(readme.substr(from + begin.size(), to - from - begin.size()) == SceneKeysMarkdown());
}

TEST_CASE("scene check prints every resolved value with its unit", "[scene]") {
  const std::string text = DescribeScene(Parse(kValid));
  CHECK_THAT(text, Contains("rotor.mass                             = 9.99 kg\n"));
  CHECK_THAT(text, Contains("contact.stiffness                      = 1.75e+11 N/m\n"));
  CHECK_THAT(text, Contains("imbalance.mass_radius                  = 0 kg·m"));
  CHECK_THAT(text, Contains("(default)"));
  CHECK_THAT(text, Contains("RCI_L = R_L/C_L = 100"));
}

TEST_CASE("The result's level is the highest of its stages, in whatever order the scene lists them",
          "[scene]") {
  CHECK(HighestLevel({}) == Level::kL0);
  CHECK(HighestLevel({Stage::kAnalytic}) == Level::kL0);
  CHECK(HighestLevel({Stage::kAnalytic, Stage::kBranches}) == Level::kL1);
  // Orbits (L2) listed before branches (L1): the branches do not lower the level.
  CHECK(HighestLevel({Stage::kOrbits, Stage::kBranches}) == Level::kL2);
  CHECK(HighestLevel({Stage::kSweep, Stage::kOrbits, Stage::kBranches}) == Level::kL3);
  CHECK(std::string(ToString(HighestLevel({Stage::kOrbits, Stage::kAnalytic}))) == "L2");
}

// Every default is written once (the initializers of the Scene's structs, which the schema reads):
// for every model, a scene that leaves an optional key out resolves it to the value the key
// reference (scenes/README.md) documents.
TEST_CASE("The [analysis.sweep] keys come from one list: values in order, and the rules a resume "
          "may change", "[scene]") {
  const Scene scene = ParseScene(kValid, "test.toml", "test");
  const auto values = SweepKeyValues(scene);
  REQUIRE(values.size() == 21);
  CHECK(values.front().first == "up_range_rpm");
  CHECK(std::get<std::vector<double>>(values.front().second) == std::vector<double>{20.0, 258.0});
  CHECK(values[4].first == "settle_window");
  CHECK(std::get<std::vector<double>>(values[4].second) == std::vector<double>{0.25});
  CHECK(values[12].first == "integrator");
  CHECK(std::get<std::string>(values[12].second) == "explicit");
  CHECK(values[15].first == "explicit_tolerance");
  CHECK(values.back().first == "max_penetration");
  // The five regime and jump rules, and nothing else, are copied.
  Scene changed = scene;
  changed.analysis.sweep.rolling_slip_tolerance = 0.1;
  changed.analysis.sweep.rolling_micro_slip = 3.0;
  changed.analysis.sweep.whirl_tolerance = 0.2;
  changed.analysis.sweep.frequency_jump_hz = 9.0;
  changed.analysis.sweep.max_penetration = 0.5;
  changed.analysis.sweep.dwell = 3.0;
  Scene copy = scene;
  CopySweepRules(changed, copy);
  CHECK(copy.analysis.sweep.rolling_slip_tolerance == 0.1);
  CHECK(copy.analysis.sweep.rolling_micro_slip == 3.0);
  CHECK(copy.analysis.sweep.whirl_tolerance == 0.2);
  CHECK(copy.analysis.sweep.frequency_jump_hz == 9.0);
  CHECK(copy.analysis.sweep.max_penetration == 0.5);
  CHECK(copy.analysis.sweep.dwell == scene.analysis.sweep.dwell);
}

TEST_CASE("Every documented default is the value a scene without the key gets, for every model",
          "[scene]") {
  // The key reference: full key → its default literal, for the rows "optional; default `X`" and
  // "required in [s]; section absent: `X`" (rows with a described default are left out).
  std::map<std::string, std::string> documented;
  std::istringstream keys(SceneKeysMarkdown());
  std::string line, section;
  while (std::getline(keys, line)) {
    if (line.rfind("### [", 0) == 0) section = line.substr(5, line.size() - 6) + ".";
    if (line.rfind("### Top level", 0) == 0) section.clear();
    if (line.rfind("| `", 0) != 0) continue;
    const std::string key = section + line.substr(3, line.find('`', 3) - 3);
    for (const std::string marker : {"| optional; default `", "; section absent: `"}) {
      const auto at = line.find(marker);
      if (at == std::string::npos) continue;
      const auto begin = at + marker.size(), end = line.find("` |", begin);
      if (end != std::string::npos && line.find('`', begin) == end) documented[key] = line.substr(begin, end - begin);
    }
  }
  REQUIRE(documented.size() > 30);

  // One scene per model with only its required keys.
  const std::string two_point = Replace(kValid, "[center_damper]\ndamping = 52.0\n", "");
  const std::string jeffcott = R"(model = "jeffcott"
[jeffcott]
m_r = 10.0
k_r = 1.0e6
c_r = 100.0
m_s = 20.0
k_s = 5.0e6
c_s = 300.0
C = 3.81e-4
R = 38.1e-3
mu = 0.3
contact_stiffness = 1.75e11
contact_damping = 1.75e5
)";
  const std::string stuart_landau = "model = \"stuart_landau\"\n[stuart_landau]\nomega = 1.0\n"
                                    "lambda_range = [0.1, 1.0]\n";
  const std::string van_der_pol = "model = \"van_der_pol\"\n[van_der_pol]\nmu_range = [0.2, 2.0]\n";
  int compared = 0;
  for (const std::string& text : {two_point, jeffcott, kDuffing, stuart_landau, van_der_pol}) {
    const Scene scene = Parse(text);
    std::istringstream resolved(ResolvedSceneToml(scene));
    std::string prefix;
    while (std::getline(resolved, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (line[0] == '[') {
        prefix = line.substr(1, line.size() - 2) + ".";
        continue;
      }
      const auto eq = line.find(" = ");
      const std::string key = prefix + line.substr(0, eq);
      const auto found = documented.find(key);
      if (found == documented.end()) continue;  // required, or a default described in words
      const auto& defaulted = scene.defaulted_keys;
      if (std::find(defaulted.begin(), defaulted.end(), key) == defaulted.end()) continue;  // given
      CAPTURE(ToString(scene.model), key);
      CHECK(line.substr(eq + 3) == found->second);
      ++compared;
    }
  }
  CHECK(compared > 60);
}
}  // namespace
}  // namespace rubcont
