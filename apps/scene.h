// Scene files (TOML): what a user asks rubcont to compute, in SI units (scenes/README.md).
//
// One schema table (apps/scene_schema.cpp: key, type, unit, rule, required/default, one-line doc)
// drives both the validation of every scene (the loader, apps/scene.cpp) and the key reference in
// scenes/README.md (`rubcont scene keys`, apps/scene_format.cpp), so the documentation cannot
// drift from what is checked. Every problem found is reported with the file, line and column, the
// key, the value given and the rule it breaks, e.g.
//   scene.toml:4:8: rotor.mass = -1: must be positive (kg)
// and all problems of a file are reported at once (SceneError).
//
// Adding a model: a ModelKind, its params struct in Scene, its rows under its own section in the
// schema, and its entry in apps/models.cpp (the model dispatch, which names its sections;
// docs/architecture.md, "Where to change what"); the loader rejects the keys of other models'
// sections. Adding a stage or an [analysis] key: a row in the schema and a field below.
#pragma once

#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "apps/level.h"
#include "models/analytic.h"
#include "models/beam.h"
#include "models/jeffcott.h"
#include "models/textbook.h"
#include "models/two_point_params.h"

namespace rubcont {

enum class ModelKind {
  kTwoPoint,  // "two_point": rigid rotor and rigid stator touching at two planes (docs/theory.md §2)
  kJeffcott,  // "jeffcott": single-contact Jeffcott rotor with an elastic stator (Black, Crandall)
  // Textbook problems with known answers (models/textbook.h), for checking the tool: stage
  // "orbits" only.
  kDuffing,       // "duffing": forced Duffing oscillator, continued in the forcing frequency w
  kStuartLandau,  // "stuart_landau": Hopf normal form, continued in the growth rate λ
  kVanDerPol,     // "van_der_pol": van der Pol oscillator, continued in μ
  kForcedVanDerPol,  // "forced_van_der_pol": entrainment and its loss, continued in w
};
// The scene's name of a model (apps/models.h holds what else each model has).
const char* ToString(ModelKind model);

// The stages `rubcont run` can perform, in the order the scene lists them.
enum class Stage {
  kAnalytic,  // "analytic": level L0, closed-form Mode 1 / Mode 2 (models/analytic.h)
  kSweep,     // "sweep": level L3, time-marching speed-up and speed-down sweeps (sweeps/rub_sweep.h)
  kBranches,  // "branches": level L1, rotating waves continued in speed (waves/rotating_wave_branches.h)
  kOrbits,    // "orbits": level L2, periodic orbits by shooting with Floquet stability: of a textbook
              // model continued in its parameter (shooting/orbit_branches.h), or the modulated
              // whirl and whip of model two_point continued in speed (shooting/rub_orbits.h)
  kTori,      // "tori": level L2, the relative 2-tori born at the Neimark–Sacker points of model
              // two_point's modulated whips, continued in speed (shooting/rub_tori.h)
  kLoop,      // "loop": the hysteresis loop explained, L1 first and L3 where it must (studies/loop.h)
};
const char* ToString(Stage stage);

// The level a stage computes at (apps/level.h).
Level LevelOf(Stage stage);
// The highest level among `stages` (L0 for none).
Level HighestLevel(const std::vector<Stage>& stages);

// Every section's defaults are the initializers below (and those of the model parameter structs):
// the schema (apps/scene_schema.cpp) documents and applies them from a default-constructed Scene.

// How the sweeps integrate (key `integrator`): CVODES BDF of order ≤ 2 throughout; Boost.Odeint's
// explicit Dormand–Prince 5(4) throughout; or BDF where the contacts touch continuously and
// Dormand–Prince where a contact touches part of the time (SweepOptions::intermittent_integrator).
enum class SweepIntegrator { kBdf, kExplicit, kAuto };
const char* ToString(SweepIntegrator integrator);

// [analysis.sweep]: the time-marching sweeps (Kumar 2010 §3.5). Units and rules in the schema.
struct SweepSettings {
  std::array<double, 2> up_range_rpm{20.0, 258.0};    // speed-up sweep: low → high [rpm]
  std::array<double, 2> down_range_rpm{20.0, 252.0};  // speed-down sweep: high → low [rpm]
  double speed_step_rpm = 2.0;        // [rpm]
  double dwell = 1.5;                 // longest simulated time per speed [s]
  double settle_window = 0.25;        // [s]
  int settle_windows = 2;             // successive agreeing window pairs
  double spectrum_tolerance = 0.05;   // relative spectral distance between windows
  double frequency_tolerance_hz = 0.25;
  double analysis_length = 0.5;       // [s] analysed at the end of each speed
  double sample_rate_hz = 4096.0;
  double spectrum_max_hz = 600.0;     // spectra kept for |f| ≤ this
  double impulse = 1.0;               // [N·s] at t = 0 of each direction
  SweepIntegrator integrator = SweepIntegrator::kExplicit;
  double relative_tolerance = 1e-6;   // CVODES BDF
  double absolute_tolerance = 1e-6;   // in units of each state's scale
  double explicit_tolerance = 1e-8;   // Dormand–Prince rtol = atol (scaled states)
  double rolling_slip_tolerance = 0.005;  // largest |V̄|/(Rω) of a rolling contact
  double rolling_micro_slip = 1.0;        // … or largest |V̄|/ε (the tanh law's micro-slip)
  double whirl_tolerance = 0.02;          // largest |BP − f_roll|/f_roll of a rolling contact
  double frequency_jump_hz = 3.0;
  double max_penetration = 0.1;           // largest δ/C of a trusted speed
};

// How the orbits stage integrates its shooting segments (key `integrator`): Gauss–Legendre
// collocation of order 8 on a fixed mesh, or CVODES BDF with sensitivities under error control
// (docs/studies/orbits.md, "Cost of the modulated whip").
enum class OrbitIntegrator { kGauss, kBdf };
const char* ToString(OrbitIntegrator integrator);

// [analysis.orbits]: the modulated whirl and whip of model two_point, born at Hopf points
// (shooting/rub_orbits.h).
struct RubOrbitsSettings {
  int hopf_points = 2;        // Hopf points followed, in order of speed (0: none)
  double amplitude = 1e-3;    // first orbit's amplitude (scaled state units), 0 < x < 1
  int segments = 4;           // shooting segments per modulation period (1: single shooting)
  OrbitIntegrator integrator = OrbitIntegrator::kGauss;
  int collocation_intervals = 400;  // Gauss mesh intervals per modulation period (all segments)
  double tolerance = 1e-7;    // CVODES BDF rtol = atol (scaled states); Gauss: its Newton's 1e-3·x
  int max_steps = 40;         // continuation steps from each Hopf point (and each branch point)
  bool follow_branch_points = true;  // follow the other branch through each located branch point
  // at_grazing = "stop": each family ends at its first located grazing (status "ended at a
  // grazing"; PeriodicOrbitBranchOptions::stop_at_grazing) instead of creeping past it on the fixed
  // mesh (A(a): 87 orbits and 640 s of CPU to a corrector failure, bench/whip_family_bench.cpp).
  bool stop_at_grazing = false;
  // predictor = "curved": the continuation's corrector starts from the parabola through the
  // previous orbit (StepOptions::curved_predictor): A(a)'s whip family from its Hopf point to its
  // grazing in 59 orbits instead of 279 (bench/whip_family_bench.cpp). "tangent" (the default):
  // the tangent line, as before the key.
  bool curved_predictor = false;
  // mesh = "adapted": Gauss's collocation_intervals move to equidistribute the error monitor of
  // every third orbit (ShootingOptions::adapt_mesh_every = 3, AUTO-07p's IAD): A(a)'s period
  // doubling 0.001–0.004 rpm from the 1600-interval reference at 400 intervals (two runs, the
  // tangent and the curved predictor), where the uniform mesh is 0.03 rpm off
  // (bench/whip_family_bench.cpp). "uniform" (the default): as before the key.
  bool adapt_mesh = false;
  // defect_check = "off": the orbits carry no independent check (each orbit integrated again by
  // Dormand–Prince at 1e-12: 3 % of A(a)'s whip family to its grazing, docs/performance.md;
  // PeriodicOrbitBranchOptions::defect_check). "on" (the default): as before the key.
  bool defect_check = true;
  // [analysis.orbits.transient]: the orbits through the relative periodic orbit a settled
  // transient lies on (ContinueTransientOrbits), for whips no Hopf point's family reaches.
  struct Transient {
    bool enabled = false;     // the section is given
    double speed_rpm = 49.4;  // required in the section, inside speed_range_rpm
    double seconds = 8.0;     // the transient from rest and the impulse [s]
    double search_seconds = 1.0;  // run on before the orbit is shot [s]
    int laps = 1;             // modulation periods per orbit, 1 … 64 (> 1: a locked whip)
    int max_steps = 40;       // continuation steps each way
  } transient;
};

// [analysis.tori]: the whips modulated at two frequencies, born at the Neimark–Sacker points of
// the modulated orbits of [analysis.orbits] (shooting/rub_tori.h).
struct RubToriSettings {
  int harmonics = 8;               // K of the invariant circle (2K + 1 points)
  int max_harmonics = 0;           // refined in K along the families up to this (0: harmonics)
  double amplitude = 1e-3;         // first circle's size (scaled state units), 0 < x < 1
  double max_fourier_tail = 1e-2;  // the breakdown / locking event, 0 < x < 1
  int max_steps = 40;              // continuation steps from each Neimark–Sacker point
  int lyapunov_iterates = 40;      // iterates of the map for each torus's Lyapunov exponents
  int samples = 64;                // instants per period for the lines of each contact
  bool from_neimark_sacker = true;  // neimark_sacker = "follow" (else "skip")
  bool contact_chart = false;       // coordinates = "chart" (else "state")
  bool centre_orbits_onward = true;  // centre_orbits = "follow" (else "to_point")
  // [analysis.tori.transient]: the tori through the torus a settled transient lies on
  // (ContinueTransientTori), for whips no Neimark–Sacker point of a computed family reaches.
  struct Transient {
    bool enabled = false;           // the section is given
    double speed_rpm = 49.0;        // required in the section, inside speed_range_rpm
    double seconds = 8.0;           // the transient from rest and the impulse [s]
    int harmonics = 8;              // K of its circles
    int max_harmonics = 0;          // refined in K up to this (0: harmonics only)
    int laps = 0;                   // modulation periods per section, 0 … 64 (0: automatic)
    double max_fourier_tail = 0.2;  // its families' breakdown / locking event
    int max_steps = 20;             // continuation steps each way
  } transient;
};

// [analysis.loop]: the loop study (studies/loop.h); its run's schedule is [analysis.sweep]'s.
struct LoopSettings {
  double budget = 4.0;             // [G work units] for the whole loop (studies/loop.h)
  double target_width_rpm = 4.0;   // the width asked of the whip end's median interval [rpm]
  int copies = 8;                  // copies per ensemble of the escape design
  double max_copy_seconds = 40.0;  // [s] the longest copy
};

// [analysis]: what to compute.
struct AnalysisOptions {
  std::vector<Stage> stages{Stage::kAnalytic, Stage::kBranches};  // the textbook models: orbits
  AnalyticOptions analytic;                              // precession_range_hz, precession_points
  SweepSettings sweep;
  std::array<double, 2> speed_range_rpm{20.0, 260.0};    // [rpm] branches, 0 < lo < hi
  RubOrbitsSettings orbits;
  RubToriSettings tori;
  LoopSettings loop;
};

// Periodic-orbit continuation of a textbook model: [<model>] <parameter>_range and
// [<model>.orbits] (the model's own sections; see scenes/README.md).
// The integrator of a textbook model's orbits ([<model>.orbits] integrator).
enum class TextbookIntegrator {
  kModel,     // the model's own: explicit for duffing and stuart_landau, bdf for the van der Pols
  kExplicit,  // ARKODE's explicit Fehlberg 8(7) under error control
  kBdf,       // CVODES BDF with sensitivities under error control
  kGauss,     // Gauss–Legendre collocation, s = 4 (order 8), on collocation_intervals per period
};
const char* ToString(TextbookIntegrator integrator);

struct TextbookOrbitsSettings {
  std::array<double, 2> parameter_range{0.5, 2.5};  // continuation parameter, model units, lo < hi
  double start = 0.0;           // parameter of the first orbit, in the range; 0: the low end
  int segments = 1;             // shooting segments (1: single shooting)
  double tolerance = 1e-10;     // integrator rtol = atol (scaled states); Gauss: its Newton's 1e-3·x
  int max_steps = 1000;         // continuation steps each way
  TextbookIntegrator integrator = TextbookIntegrator::kModel;
  // Gauss mesh intervals per period, shared by the segments (≥ 1). 40: the forced Duffing
  // branch's folds to 4e-14 and 1.4e-13 of harmonic balance (bench/duffing_branch_bench.cpp).
  int collocation_intervals = 40;
};

// [flexible] (model two_point, optional): the rotor and the stator as Timoshenko shafts, reduced
// by Craig–Bampton to the contact displacements and `modes` fixed-interface modes (level L4,
// models/flexible.h FlexibleTwoPoint). Absent: the rigid model. Each body is either
// - uniform: one section of the [flexible] material across its span, completed by a disk to the
//   rigid model's mass, mass centre and inertia ([rotor], [stator]); or
// - listed: shaft segments ([[flexible.rotor_shaft]]: length, diameters, material; each cut into
//   `elements` equal elements), disks and (stator) supports on its stations, as rotordynamics
//   input lists them. Its rigid-body data are then the shafts': [rotor]/[stator] may leave them
//   out (the loader fills them in, so L0 and the jump table's Mode 1/2 describe the same bodies) or
//   must agree with them to 1e-6.
// The required keys' initializers are the geometry `rubcont flexible` fits to the thesis's Tables
// 2–3 (scenes/thesis_*_flexible.toml); a scene must give them.
struct ShaftRow {       // one [[flexible.<body>_shaft]] row
  ShaftElement section;  // its length is the row's; material resolved from [flexible]'s defaults
  int elements = 1;      // equal elements it is cut into
};
// [flexible.matrices]: the whole flexible structure (rotor, stator, their supports and dampers) as
// an FE model's matrices, read from a file (apps/structure_file.h) and reduced by the same
// Craig–Bampton (models/flexible.h BuildMatrixRub). The contacts join the coordinates named here;
// [rotor], [stator] and [center_damper] describe only the rigid model (stage "analytic", L0).
struct MatrixSettings {
  bool enabled = false;  // the section is present
  std::string file;      // as resolved: absolute (the scene gives it relative to its own directory)
  std::array<int, 2> rotor_contact_coordinates{0, 0};   // [left, right], 0-based
  std::array<int, 2> stator_contact_coordinates{0, 0};  // [left, right]
  int imbalance_coordinate = -1;  // -1: the left rotor contact's
  StructuralMatrices full;        // read by the loader from `file`
};
struct SupportRow {  // one [[flexible.<body>_supports]] row: a spring and dashpot to ground
  int station = 0;
  double stiffness = 0.0;  // [N/m]
  double damping = 0.0;    // [N·s/m]
};
struct FlexibleSettings {
  bool enabled = false;  // the section is present
  double rotor_outer_diameter = 0.04801;   // [m] > 0 (uniform rotor)
  double rotor_inner_diameter = 0.0;       // [m] ≥ 0, below the outer one (0: solid)
  double stator_outer_diameter = 0.13722;  // [m] > 0 (uniform stator)
  double stator_inner_diameter = 0.07696;  // [m] ≥ 0, below the outer one
  double youngs_modulus = 2.0684e11;       // E [Pa] > 0 (listed rows' default)
  double shear_modulus = 7.929e10;         // G [Pa] > 0, E/(2G) − 1 in (−1, 0.5]
  double density = 7833.0;                 // ρ [kg/m³] ≥ 0
  int elements = 8;                        // per uniform shaft (about; nodes added at the disk etc.)
  int modes = 4;                           // fixed-interface modes kept
  double modal_damping = 0.0;              // ζ of the kept modes
  bool gyroscopic = true;                  // keep the polar inertias' −jωG u̇
  // Listed bodies (empty rows: uniform). Stations count from 0 at the first segment's left end.
  std::vector<ShaftRow> rotor_shaft, stator_shaft;
  std::vector<Disk> rotor_disks, stator_disks;  // Disk::node is the station
  std::vector<SupportRow> stator_supports;      // empty: [stator]'s supports at its contacts
  // The listed rotor's bearings to ground (a rotor from ROSS; the rigid model has none, so a scene
  // with them has no stage "analytic").
  std::vector<SupportRow> rotor_supports;
  MatrixSettings matrices;
  std::array<int, 2> rotor_contact_stations{0, -1};   // -1: the last station
  std::array<int, 2> stator_contact_stations{0, -1};

  bool RotorListed() const { return !rotor_shaft.empty(); }
  bool StatorListed() const { return !stator_shaft.empty(); }
  // Whether a body is uniform (neither listed nor in the matrices).
  bool RotorUniform() const { return !RotorListed() && !matrices.enabled; }
  bool StatorUniform() const { return !StatorListed() && !matrices.enabled; }
};

struct Scene {
  std::string name;         // names the output: results/<name>/; default: the file stem
  std::string description;  // free text
  ModelKind model = ModelKind::kTwoPoint;
  TwoPointParams two_point;  // the model description when model == kTwoPoint
  FlexibleSettings flexible; // model two_point's optional [flexible] section (level L4)
  JeffcottParams jeffcott;   // the model description when model == kJeffcott
  DuffingParams duffing;            // when model == kDuffing (frequency: see orbits)
  StuartLandauParams stuart_landau; // when model == kStuartLandau (lambda: see orbits)
  VanDerPolParams van_der_pol;      // when model == kVanDerPol (mu: see orbits)
  ForcedVanDerPolParams forced_van_der_pol;  // when model == kForcedVanDerPol (frequency: orbits)
  TextbookOrbitsSettings orbits;    // "orbits" stage of a textbook model: parameter range, numerics
  AnalysisOptions analysis;

  // Provenance, not part of the scene's content: where it was read from, and which keys the file
  // left out (their documented defaults apply).
  std::string source;
  std::vector<std::string> defaulted_keys;
  // The [rotor]/[stator] keys the file left out because listed shafts supply them.
  std::vector<std::string> supplied_keys;
};

// The level of a result file's root: `computed`, or L4 for a scene with [flexible] (whose rotor and
// stator are Timoshenko shafts whatever the method).
Level ResultLevel(const Scene& scene, Level computed);

// All problems of one scene file; what() joins them, one per line. Exit code 2 at the CLI.
class SceneError : public std::invalid_argument {
 public:
  explicit SceneError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

// Reads and validates a scene file. Throws SceneError (unreadable file, TOML syntax error with
// line and column, or any rule of the schema broken).
Scene LoadScene(const std::filesystem::path& file);

// Same, from text. `source` names it in messages; `default_name` is the name when the text sets
// none (LoadScene passes the file stem).
Scene ParseScene(std::string_view toml_text, const std::string& source,
                 const std::string& default_name);

// The built-in scene: scenes/default.toml, embedded at build time (disk at centre, RCI 100/100).
Scene DefaultScene();
const char* DefaultSceneToml();

// The resolved scene as TOML: every key of the model, defaults included, full precision. Parsing
// it again gives the same scene; result files store it (root attribute `scene_toml`).
std::string ResolvedSceneToml(const Scene& scene);

class ResultWriter;
// The root attributes every result file carries: rubcont_version, rubcont_git (the commit,
// apps/version.h), scene_name, scene_toml (the resolved scene, ResolvedSceneToml).
void WriteSceneAttributes(ResultWriter& writer, const Scene& scene);

// Human-readable listing of every resolved value with its unit (and "(default)" where the file
// did not set it), followed by derived quantities (a, b, RCI). For `rubcont scene check`.
std::string DescribeScene(const Scene& scene);

// The keys of [analysis.sweep] (their last component) with their values in `scene`, in schema
// order, numbers as one or two numbers, choices as text: the attributes of /sweeps/<direction>
// (apps/sweep_output.cpp).
using SweepKeyValue = std::variant<std::vector<double>, std::string>;
std::vector<std::pair<std::string, SweepKeyValue>> SweepKeyValues(const Scene& scene);
// Copies the [analysis.sweep] keys that only classify finished speeds (the regime and jump rules)
// from `from` into `to`: a sweep file that differs from a scene in these alone holds its
// integrations (checkpoints, `rubcont sweep --resume`).
void CopySweepRules(const Scene& from, Scene& to);
// Whether `key` (full dotted name) is one of those rules.
bool IsSweepRule(const std::string& key);
// Whether `key` was added after results were committed, with a default that keeps what runs did
// before it (KeySpec::added_at_older_behaviour: [analysis.orbits] at_grazing, predictor): a stored
// scene that leaves it to its default describes the same run (scripts/compare_results.py's
// SCENE_KEYS_ADDED lists the same keys, as the lines their defaults print).
bool AddedAtOlderBehaviour(const std::string& key);

// The key reference in markdown, generated from the schema: one table per section with key,
// type, unit, rule, required/default and meaning. scenes/README.md embeds it verbatim.
std::string SceneKeysMarkdown();

}  // namespace rubcont
