#include "apps/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <variant>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "apps/hdf5_file.h"
#include "apps/models.h"
#include "apps/version.h"

namespace rubcont {
namespace {

// ---------------------------------------------------------------------------------------------
// The schema: one row per key.

enum class ValueType {
  kFloat,       // TOML float or integer (1000 → 1000.0)
  kInteger,     // TOML integer only
  kString,
  kFloatPair,   // array of exactly two numbers
  kIntegerPair, // array of exactly two integers
  kStringList,  // array of strings
};

enum class Rule {
  kText,                  // any string
  kSceneName,             // 1–100 characters of [A-Za-z0-9_.-], not starting with '.'
  kChoice,                // one of KeySpec::choices
  kStages,                // non-empty list of implemented stage names, no repeats
  kFinite,                // any finite number
  kPositive,              // > 0 (each entry of a pair)
  kNonNegative,           // ≥ 0 (each entry of a pair)
  kIncreasingPositive,    // pair 0 < low < high
  kGridPoints,            // integer 2 … kMaxGridPoints
  kCount,                 // integer 1 … kMaxCount
  kCountOrNone,           // integer 0 … kMaxCount
  kSteps,                 // integer 1 … kMaxSteps
  kOpenUnit,              // 0 < x < 1
  kStation,               // integer 0 … kMaxStation
  kStationPair,           // integer pair 0 ≤ left < right ≤ kMaxStation
};

enum class Presence {
  kRequired,           // must be present
  kOptional,           // default applies when absent
  kRequiredInSection,  // must be present if its section is; an absent section means the default
};

constexpr std::int64_t kMaxGridPoints = 1000000;
constexpr std::int64_t kMaxCount = 1000;
constexpr std::int64_t kMaxSteps = 1000000;
constexpr std::int64_t kMaxStation = 100000;

using Value = std::variant<double, std::int64_t, std::string, std::array<double, 2>,
                           std::vector<std::string>, std::array<std::int64_t, 2>>;

struct KeySpec {
  std::string key;        // dotted path: "rotor.mass"
  ValueType type;
  std::string unit;       // SI unit; "-" dimensionless; "" not a quantity
  Rule rule;
  Presence presence;
  Value default_value;    // kOptional / kRequiredInSection: the field's value in Scene{}
  std::string default_text;  // how the docs state the default when it is not a literal
  std::string doc;        // one line: symbol and meaning
  std::vector<std::string> choices;       // kChoice
  std::optional<ModelKind> model;         // nullopt: common to every model
  // [analysis.sweep] keys that only classify finished speeds (the regime and jump rules of
  // sweeps/rub_sweep.h): a sweep file with other values holds the same integrations.
  bool reclassifies = false;
  // Whether the key describes the scene as loaded (null: always, given its model): a key of one
  // form of [flexible] is not one of the other's (given, it is a problem; it is not written out).
  std::function<bool(const Scene&)> relevant;
  std::string irrelevant_reason;  // why not, for the problem when it is given anyway
  std::function<void(Scene&, const Value&)> set;
  std::function<Value(const Scene&)> get;

  std::string Section() const {
    const auto dot = key.rfind('.');
    return dot == std::string::npos ? std::string() : key.substr(0, dot);
  }
};

// Field accessors: a function returning a reference into the Scene. get() calls it on a
// const Scene through const_cast only to form the reference; it never writes.
template <class T>
using Field = T& (*)(Scene&);

// A key bound to a field of the Scene. Its default (Presence::kOptional, kRequiredInSection) is the
// field's initializer: BuildSchema reads them from a default-constructed Scene.
template <class T, class Stored = T>
KeySpec Make(std::string key, ValueType type, std::string unit, Rule rule, Presence presence,
             std::string doc, Field<T> field, std::optional<ModelKind> model = ModelKind::kTwoPoint) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = type;
  spec.unit = std::move(unit);
  spec.rule = rule;
  spec.presence = presence;
  spec.doc = std::move(doc);
  spec.model = model;
  spec.set = [field](Scene& s, const Value& v) { field(s) = static_cast<T>(std::get<Stored>(v)); };
  spec.get = [field](const Scene& s) { return Value(static_cast<Stored>(field(const_cast<Scene&>(s)))); };
  return spec;
}

KeySpec Float(std::string key, std::string unit, Rule rule, std::string doc, Field<double> field,
              Presence presence = Presence::kRequired) {
  return Make<double>(std::move(key), ValueType::kFloat, std::move(unit), rule, presence,
                      std::move(doc), field);
}

KeySpec Pair(std::string key, std::string unit, Rule rule, std::string doc,
             Field<std::array<double, 2>> field) {
  return Make<std::array<double, 2>>(std::move(key), ValueType::kFloatPair, std::move(unit), rule,
                                     Presence::kRequired, std::move(doc), field);
}

// An optional key whose value is one of `choices` (text), read and written through `get`/`set`.
KeySpec Choice(std::string key, std::string doc, std::vector<std::string> choices,
               std::function<void(Scene&, const std::string&)> set,
               std::function<std::string(const Scene&)> get,
               std::optional<ModelKind> model = ModelKind::kTwoPoint) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = ValueType::kString;
  spec.rule = Rule::kChoice;
  spec.presence = Presence::kOptional;
  spec.doc = std::move(doc);
  spec.choices = std::move(choices);
  spec.model = model;
  spec.set = [set](Scene& x, const Value& v) { set(x, std::get<std::string>(v)); };
  spec.get = [get](const Scene& x) { return Value(get(x)); };
  return spec;
}

bool RunsStage(const Scene& scene, Stage stage) {
  const std::vector<Stage>& stages = scene.analysis.stages;
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

// A key of [analysis.tori] or of its sub-table [analysis.tori.transient].
// Sub-tables whose absence means "not computed", not "computed with the defaults": their keys are
// resolved only when the table is given.
bool IsOptionalSubsection(const std::string& section) {
  return section == "analysis.tori.transient" || section == "analysis.orbits.transient";
}

constexpr int kMaxLaps = 64;  // ModulatedOrbitOptions::laps

bool IsToriKey(const KeySpec& spec) {
  const std::string section = spec.Section();
  return section == "analysis.tori" || section.rfind("analysis.tori.", 0) == 0;
}

const std::vector<std::string> kImplementedStages = {"analytic", "branches", "orbits", "tori",
                                                     "sweep"};
std::vector<std::string> ModelNames() {
  std::vector<std::string> names;
  for (const ModelEntry& m : Models()) names.push_back(m.name);
  return names;
}

// `name` is one of ModelNames() (the schema's choice rule checked it).
ModelKind ModelFromName(const std::string& name) {
  for (const ModelEntry& m : Models())
    if (m.name == name) return m.kind;
  return ModelKind::kTwoPoint;
}

std::vector<KeySpec> BuildSchema() {
  std::vector<KeySpec> s;
  const auto kCommon = std::nullopt;

  // Top level.
  {
    KeySpec name = Make<std::string>("name", ValueType::kString, "", Rule::kSceneName,
                                     Presence::kOptional,
                                     "Scene name: the output goes to `<out>/<name>/`.",
                                     [](Scene& x) -> std::string& { return x.name; }, kCommon);
    name.default_text = "the file stem";
    s.push_back(name);
  }
  s.push_back(Make<std::string>("description", ValueType::kString, "", Rule::kText,
                                Presence::kOptional,
                                "Free text, kept in the result file.",
                                [](Scene& x) -> std::string& { return x.description; }, kCommon));
  s.push_back(Choice(
      "model", "Which model the scene describes; each model has its own sections.", ModelNames(),
      [](Scene& x, const std::string& name) { x.model = ModelFromName(name); },
      [](const Scene& x) { return std::string(ToString(x.model)); }, kCommon));

  // [rotor]
  s.push_back(Float("rotor.mass", "kg", Rule::kPositive, "m_r: rotor mass.",
                    [](Scene& x) -> double& { return x.two_point.rotor_mass; }));
  s.push_back(Float("rotor.inertia", "kg·m²", Rule::kPositive,
                    "I_r: transverse moment of inertia about the mass centre.",
                    [](Scene& x) -> double& { return x.two_point.rotor_inertia; }));
  s.push_back(Float("rotor.contact_span", "m", Rule::kPositive,
                    "l: distance from the left contact plane (z = 0) to the right one (z = l).",
                    [](Scene& x) -> double& { return x.two_point.contact_span; }));
  s.push_back(Float("rotor.mass_center", "m", Rule::kFinite,
                    "l_g: mass centre from the left contact plane; a = l_g/l > 1 is overhung "
                    "beyond the right contact, a < 0 beyond the left.",
                    [](Scene& x) -> double& { return x.two_point.rotor_mass_center; }));

  // [stator]
  s.push_back(Float("stator.mass", "kg", Rule::kPositive, "m_s: stator mass.",
                    [](Scene& x) -> double& { return x.two_point.stator_mass; }));
  s.push_back(Float("stator.inertia", "kg·m²", Rule::kPositive,
                    "I_s: transverse moment of inertia about its mass centre.",
                    [](Scene& x) -> double& { return x.two_point.stator_inertia; }));
  s.push_back(Float("stator.span", "m", Rule::kPositive,
                    "l_s: distance between the stator's two stations (supports and contacts).",
                    [](Scene& x) -> double& { return x.two_point.stator_span; }));
  s.push_back(Float("stator.mass_center", "m", Rule::kFinite,
                    "l_sg: mass centre from the left station; b = l_sg/l_s.",
                    [](Scene& x) -> double& { return x.two_point.stator_mass_center; }));
  s.push_back(Pair("stator.stiffness", "N/m", Rule::kPositive,
                   "[k_L, k_R]: support stiffness at each station.",
                   [](Scene& x) -> std::array<double, 2>& { return x.two_point.support_stiffness; }));
  s.push_back(Pair("stator.damping", "N·s/m", Rule::kNonNegative,
                   "[c_L, c_R]: support damping at each station.",
                   [](Scene& x) -> std::array<double, 2>& { return x.two_point.support_damping; }));

  // [contact]
  s.push_back(Pair("contact.clearance", "m", Rule::kPositive,
                   "[C_L, C_R]: radial clearance at each contact.",
                   [](Scene& x) -> std::array<double, 2>& { return x.two_point.clearance; }));
  s.push_back(Pair("contact.radius", "m", Rule::kPositive,
                   "[R_L, R_R]: rotor radius at each contact; RCI_k = R_k/C_k.",
                   [](Scene& x) -> std::array<double, 2>& { return x.two_point.radius; }));
  s.push_back(Float("contact.friction", "-", Rule::kNonNegative,
                    "μ: Coulomb friction coefficient available at both contacts.",
                    [](Scene& x) -> double& { return x.two_point.friction; }));
  s.push_back(Float("contact.stiffness", "N/m", Rule::kPositive,
                    "k1 of the normal force N = k1 δ + k2 δ² + c_nl δ̇ δ (Hunt–Crossley).",
                    [](Scene& x) -> double& { return x.two_point.contact_stiffness; }));
  s.push_back(Float("contact.stiffness2", "N/m²", Rule::kNonNegative, "k2 of the normal force.",
                    [](Scene& x) -> double& { return x.two_point.contact_stiffness2; }));
  s.push_back(Float("contact.damping", "N·s/m²", Rule::kNonNegative,
                    "c_nl of the normal force.",
                    [](Scene& x) -> double& { return x.two_point.contact_damping; }));

  // [contact.friction_law]
  s.push_back(Choice(
      "contact.friction_law.kind",
      "Friction law of the rotating waves: \"exact\" (stick/slip) or \"tanh\" (μN tanh(V/ε)). "
      "Not used by the analytic stage.",
      {"exact", "tanh"},
      [](Scene& x, const std::string& name) {
        x.two_point.friction_law.kind = name == "tanh" ? FrictionLawKind::kTanh : FrictionLawKind::kExact;
      },
      [](const Scene& x) {
        return std::string(x.two_point.friction_law.kind == FrictionLawKind::kTanh ? "tanh" : "exact");
      }));
  s.push_back(Float("contact.friction_law.velocity_scale", "m/s", Rule::kPositive,
                    "ε of tanh(V/ε): the friction regularization of time marching and shooting "
                    "(and of rotating waves when kind = \"tanh\"). Not used by the analytic stage.",
                    [](Scene& x) -> double& { return x.two_point.friction_law.velocity_scale; },
                    Presence::kOptional));

  // [imbalance], [center_damper]: optional components; an absent section means none.
  s.push_back(Float("imbalance.mass_radius", "kg·m", Rule::kNonNegative,
                    "m_u e: imbalance at the mass-centre plane (3.43 g·cm = 3.43e-5 kg·m). "
                    "Breaks the rotational symmetry; the analytic stage neglects it.",
                    [](Scene& x) -> double& { return x.two_point.imbalance; },
                    Presence::kRequiredInSection));
  s.push_back(Float("center_damper.damping", "N·s/m", Rule::kNonNegative,
                    "c_d: viscous damper between the rotor and stator mid-points (weights ½, ½). "
                    "The analytic stage includes it exactly; 0 gives the thesis's closed form.",
                    [](Scene& x) -> double& { return x.two_point.center_damping; },
                    Presence::kRequiredInSection));

  // [flexible]: level L4, optional; an absent section means the rigid model.
  {
    const auto flexible = [&s](std::string key, std::string unit, Rule rule, std::string doc,
                               Field<double> field, Presence presence) {
      KeySpec spec = Make<double>("flexible." + key, ValueType::kFloat, std::move(unit), rule,
                                  presence, std::move(doc), field);
      if (presence == Presence::kRequiredInSection) spec.default_text = "the rigid model";
      s.push_back(spec);
    };
    const Presence in_section = Presence::kRequiredInSection, optional = Presence::kOptional;
    const auto uniform_rotor = [](const Scene& x) { return !x.flexible.RotorListed(); };
    const auto uniform_stator = [](const Scene& x) { return !x.flexible.StatorListed(); };
    flexible("rotor_outer_diameter", "m", Rule::kPositive,
             "Outer diameter of the rotor's shaft across the contact span (a disk completes the "
             "rotor to [rotor]'s mass, mass centre and inertia). Not with [[flexible.rotor_shaft]].",
             [](Scene& x) -> double& { return x.flexible.rotor_outer_diameter; }, in_section);
    s.back().relevant = uniform_rotor;
    s.back().irrelevant_reason = "[[flexible.rotor_shaft]] lists the rotor's shaft";
    flexible("rotor_inner_diameter", "m", Rule::kNonNegative,
             "Its bore (0: solid); below rotor_outer_diameter.",
             [](Scene& x) -> double& { return x.flexible.rotor_inner_diameter; }, optional);
    s.back().relevant = uniform_rotor;
    s.back().irrelevant_reason = "[[flexible.rotor_shaft]] lists the rotor's shaft";
    flexible("stator_outer_diameter", "m", Rule::kPositive,
             "Outer diameter of the stator's tube across its span (a disk completes it to "
             "[stator]'s mass, mass centre and inertia). Not with [[flexible.stator_shaft]].",
             [](Scene& x) -> double& { return x.flexible.stator_outer_diameter; }, in_section);
    s.back().relevant = uniform_stator;
    s.back().irrelevant_reason = "[[flexible.stator_shaft]] lists the stator's shaft";
    flexible("stator_inner_diameter", "m", Rule::kNonNegative,
             "Its bore; below stator_outer_diameter.",
             [](Scene& x) -> double& { return x.flexible.stator_inner_diameter; }, in_section);
    s.back().relevant = uniform_stator;
    s.back().irrelevant_reason = "[[flexible.stator_shaft]] lists the stator's shaft";
    flexible("youngs_modulus", "Pa", Rule::kPositive,
             "E of both shafts (of the listed segments that give none).",
             [](Scene& x) -> double& { return x.flexible.youngs_modulus; }, in_section);
    flexible("shear_modulus", "Pa", Rule::kPositive,
             "G of both shafts (of the listed segments that give none); the Poisson ratio "
             "E/(2G) − 1 must lie in (−1, 0.5].",
             [](Scene& x) -> double& { return x.flexible.shear_modulus; }, in_section);
    flexible("density", "kg/m³", Rule::kNonNegative,
             "ρ of both shafts (of the listed segments that give none).",
             [](Scene& x) -> double& { return x.flexible.density; }, in_section);
    s.push_back(Make<int, std::int64_t>(
        "flexible.elements", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
        "Timoshenko elements per uniform shaft (nodes are added at the mid-span, the mass "
        "centre and the disk).",
        [](Scene& x) -> int& { return x.flexible.elements; }));
    s.back().relevant = [](const Scene& x) {
      return !x.flexible.RotorListed() || !x.flexible.StatorListed();
    };
    s.back().irrelevant_reason = "both shafts are listed ([[flexible.rotor_shaft]], "
                                 "[[flexible.stator_shaft]])";
    for (const std::string body : {"rotor", "stator"}) {
      KeySpec stations;
      stations.key = "flexible." + body + "_contact_stations";
      stations.type = ValueType::kIntegerPair;
      stations.unit = "-";
      stations.rule = Rule::kStationPair;
      stations.presence = Presence::kOptional;
      stations.default_text = "the first and last stations";
      stations.doc = "The stations of the listed " + body + " shaft at the left and right contacts.";
      stations.model = ModelKind::kTwoPoint;
      const auto field = [body](Scene& x) -> std::array<int, 2>& {
        return body == "rotor" ? x.flexible.rotor_contact_stations : x.flexible.stator_contact_stations;
      };
      stations.set = [field](Scene& x, const Value& v) {
        const auto& pair = std::get<std::array<std::int64_t, 2>>(v);
        field(x) = {static_cast<int>(pair[0]), static_cast<int>(pair[1])};
      };
      stations.get = [field](const Scene& x) {
        const std::array<int, 2>& pair = field(const_cast<Scene&>(x));
        return Value(std::array<std::int64_t, 2>{pair[0], pair[1]});
      };
      stations.relevant = [body](const Scene& x) {
        return body == "rotor" ? x.flexible.RotorListed() : x.flexible.StatorListed();
      };
      stations.irrelevant_reason = "stations number a listed shaft: add [[flexible." + body +
                                   "_shaft]] rows";
      s.push_back(stations);
    }
    s.push_back(Make<int, std::int64_t>(
        "flexible.modes", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
        "Fixed-interface modes kept by the Craig–Bampton reduction (the contact displacements "
        "stay physical).",
        [](Scene& x) -> int& { return x.flexible.modes; }));
    flexible("modal_damping", "-", Rule::kNonNegative, "ζ of the kept modes.",
             [](Scene& x) -> double& { return x.flexible.modal_damping; }, optional);
    s.push_back(Choice(
        "flexible.gyroscopic",
        "\"on\": the polar inertias' gyroscopic moments (−jωG u̇); \"off\": none, as the rigid "
        "model.",
        {"on", "off"}, [](Scene& x, const std::string& v) { x.flexible.gyroscopic = v == "on"; },
        [](const Scene& x) { return std::string(x.flexible.gyroscopic ? "on" : "off"); }));
  }

  // [jeffcott]: the single-contact model, in Black's and Crandall's symbols.
  {
    const auto jeffcott = [&s](std::string key, std::string unit, Rule rule, std::string doc,
                               Field<double> field, Presence presence = Presence::kRequired) {
      s.push_back(Make<double>("jeffcott." + key, ValueType::kFloat, std::move(unit), rule,
                               presence, std::move(doc), field, ModelKind::kJeffcott));
    };
    jeffcott("m_r", "kg", Rule::kPositive, "Rotor mass.",
             [](Scene& x) -> double& { return x.jeffcott.m_r; });
    jeffcott("k_r", "N/m", Rule::kPositive, "Rotor (shaft) stiffness.",
             [](Scene& x) -> double& { return x.jeffcott.k_r; });
    jeffcott("c_r", "N·s/m", Rule::kNonNegative, "Rotor damping.",
             [](Scene& x) -> double& { return x.jeffcott.c_r; });
    jeffcott("m_s", "kg", Rule::kPositive, "Stator mass.",
             [](Scene& x) -> double& { return x.jeffcott.m_s; });
    jeffcott("k_s", "N/m", Rule::kPositive, "Stator support stiffness.",
             [](Scene& x) -> double& { return x.jeffcott.k_s; });
    jeffcott("c_s", "N·s/m", Rule::kNonNegative, "Stator support damping.",
             [](Scene& x) -> double& { return x.jeffcott.c_s; });
    jeffcott("C", "m", Rule::kPositive, "Radial clearance.",
             [](Scene& x) -> double& { return x.jeffcott.C; });
    jeffcott("R", "m", Rule::kPositive, "Rotor radius at the contact; RCI = R/C.",
             [](Scene& x) -> double& { return x.jeffcott.R; });
    jeffcott("mu", "-", Rule::kNonNegative, "μ: Coulomb friction coefficient.",
             [](Scene& x) -> double& { return x.jeffcott.friction; });
    jeffcott("contact_stiffness", "N/m", Rule::kPositive,
             "k1 of the Hunt–Crossley normal force N = k1 δ + k2 δ² + c_nl δ̇ δ.",
             [](Scene& x) -> double& { return x.jeffcott.contact_stiffness; });
    jeffcott("contact_stiffness2", "N/m²", Rule::kNonNegative, "k2 of the normal force.",
             [](Scene& x) -> double& { return x.jeffcott.contact_stiffness2; },
             Presence::kOptional);
    jeffcott("contact_damping", "N·s/m²", Rule::kNonNegative, "c_nl of the normal force.",
             [](Scene& x) -> double& { return x.jeffcott.contact_damping; });
    jeffcott("imbalance", "kg·m", Rule::kNonNegative, "m_u e: imbalance on the rotor.",
             [](Scene& x) -> double& { return x.jeffcott.imbalance; }, Presence::kOptional);
    KeySpec kind;
    kind.key = "jeffcott.friction_law";
    kind.type = ValueType::kString;
    kind.rule = Rule::kChoice;
    kind.presence = Presence::kOptional;
    kind.doc = "Friction law of the rotating waves: \"exact\" (stick/slip) or \"tanh\".";
    kind.choices = {"exact", "tanh"};
    kind.model = ModelKind::kJeffcott;
    kind.set = [](Scene& x, const Value& v) {
      x.jeffcott.friction_law.kind =
          std::get<std::string>(v) == "tanh" ? FrictionLawKind::kTanh : FrictionLawKind::kExact;
    };
    kind.get = [](const Scene& x) {
      return Value(std::string(x.jeffcott.friction_law.kind == FrictionLawKind::kTanh ? "tanh" : "exact"));
    };
    s.push_back(kind);
    jeffcott("velocity_scale", "m/s", Rule::kPositive,
             "ε of tanh(V/ε) (time marching, shooting, and rotating waves when friction_law = "
             "\"tanh\").",
             [](Scene& x) -> double& { return x.jeffcott.friction_law.velocity_scale; },
             Presence::kOptional);
  }

  // Textbook models (models/textbook.h): [<model>] with the model's coefficients and the range of
  // its continuation parameter, [<model>.orbits] with the numerics of the "orbits" stage.
  {
    const auto number = [&s](ModelKind model, std::string key, std::string unit, Rule rule,
                             std::string doc, Field<double> field,
                             Presence presence = Presence::kRequired) {
      s.push_back(Make<double>(std::string(ToString(model)) + "." + key, ValueType::kFloat,
                               std::move(unit), rule, presence, std::move(doc), field, model));
    };
    // <model>.<parameter>_range and [<model>.orbits], the parameter as its entry names it.
    const auto range = [&s](ModelKind model, std::string doc) {
      s.push_back(Make<std::array<double, 2>>(
          std::string(ToString(model)) + "." + ModelOf(model).parameter + "_range",
          ValueType::kFloatPair, "-",
          Rule::kIncreasingPositive, Presence::kRequired, std::move(doc),
          [](Scene& x) -> std::array<double, 2>& { return x.orbits.parameter_range; }, model));
    };
    const auto orbits = [&s](ModelKind model) {
      const std::string& parameter = ModelOf(model).parameter;
      const std::string prefix = std::string(ToString(model)) + ".orbits.";
      KeySpec start = Make<double>(
          prefix + "start", ValueType::kFloat, "-", Rule::kPositive, Presence::kOptional,
          "Parameter of the first orbit; the branch is continued both ways from it to the ends "
          "of `" + parameter + "_range`.",
          [](Scene& x) -> double& { return x.orbits.start; }, model);
      start.default_text = "the low end of `" + parameter + "_range`";
      s.push_back(start);
      s.push_back(Make<int, std::int64_t>(
          prefix + "segments", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
          "Shooting segments: 1 single shooting, more for multiple shooting.",
          [](Scene& x) -> int& { return x.orbits.segments; }, model));
      s.push_back(Make<double>(
          prefix + "tolerance", ValueType::kFloat, "-", Rule::kOpenUnit, Presence::kOptional,
          "Integrator tolerance (relative = absolute, on scaled states) of every segment.",
          [](Scene& x) -> double& { return x.orbits.tolerance; }, model));
      s.push_back(Make<int, std::int64_t>(
          prefix + "max_steps", ValueType::kInteger, "-", Rule::kSteps, Presence::kOptional,
          "Continuation steps allowed each way from the start.",
          [](Scene& x) -> int& { return x.orbits.max_steps; }, model));
    };
    const ModelKind kDuffing = ModelKind::kDuffing;
    number(kDuffing, "damping", "-", Rule::kNonNegative, "c of ẍ + c ẋ + k x + β x³ = F cos(w t).",
           [](Scene& x) -> double& { return x.duffing.damping; });
    number(kDuffing, "stiffness", "-", Rule::kFinite, "k: linear stiffness.",
           [](Scene& x) -> double& { return x.duffing.stiffness; });
    number(kDuffing, "cubic", "-", Rule::kFinite, "β: cubic stiffness (> 0 hardening).",
           [](Scene& x) -> double& { return x.duffing.cubic; });
    number(kDuffing, "force", "-", Rule::kFinite, "F: forcing amplitude.",
           [](Scene& x) -> double& { return x.duffing.force; });
    range(kDuffing,
          "[low, high]: forcing frequency w, the continuation parameter (forcing period 2π/w).");
    orbits(kDuffing);

    const ModelKind kStuartLandau = ModelKind::kStuartLandau;
    number(kStuartLandau, "omega", "-", Rule::kFinite,
           "ω of ż = (λ + iω) z − (1 + iγ)|z|² z: linear frequency.",
           [](Scene& x) -> double& { return x.stuart_landau.omega; });
    number(kStuartLandau, "gamma", "-", Rule::kFinite,
           "γ: amplitude–frequency coupling; the orbit turns at ω − γλ.",
           [](Scene& x) -> double& { return x.stuart_landau.gamma; }, Presence::kOptional);
    range(kStuartLandau,
          "[low, high]: growth rate λ, the continuation parameter (the orbit r = √λ exists for "
          "λ > 0; Hopf point at 0).");
    orbits(kStuartLandau);

    const ModelKind kForcedVanDerPol = ModelKind::kForcedVanDerPol;
    number(kForcedVanDerPol, "mu", "-", Rule::kFinite,
           "μ of ẍ − μ (1 − x²) ẋ + x = F cos(w t): nonlinear damping.",
           [](Scene& x) -> double& { return x.forced_van_der_pol.mu; });
    number(kForcedVanDerPol, "force", "-", Rule::kFinite, "F: forcing amplitude.",
           [](Scene& x) -> double& { return x.forced_van_der_pol.force; });
    range(kForcedVanDerPol,
          "[low, high]: forcing frequency w, the continuation parameter (forcing period 2π/w); the "
          "free cycle turns at about 1.");
    orbits(kForcedVanDerPol);

    range(ModelKind::kVanDerPol,
          "[low, high]: μ of ẍ − μ (1 − x²) ẋ + x = 0, the continuation parameter (relaxation "
          "oscillations for μ ≫ 1: use several segments).");
    orbits(ModelKind::kVanDerPol);
  }

  // [analysis]
  {
    KeySpec stages;
    stages.key = "analysis.stages";
    stages.type = ValueType::kStringList;
    stages.rule = Rule::kStages;
    stages.presence = Presence::kOptional;
    stages.doc = "What `rubcont run` computes, in this order: \"analytic\" (L0 closed form), "
                 "\"branches\" (L1 rotating waves continued in speed) — models two_point and "
                 "jeffcott; \"orbits\" (L2 periodic orbits by shooting with Floquet stability: the "
                 "textbook models continued in their parameter; for model two_point the modulated "
                 "whirl and whip born at the Hopf points of the tanh-law rotating waves, continued "
                 "in speed, [analysis.orbits]); \"tori\" (L2 relative 2-tori of model two_point: "
                 "the whips modulated at two frequencies, born at the Neimark–Sacker points of "
                 "those modulated orbits, continued in speed, [analysis.tori]); \"sweep\" (L3: "
                 "the speed-up and "
                 "speed-down sweeps of [analysis.sweep]) — model two_point.";
    stages.default_text = "`[\"analytic\", \"branches\"]`; `[\"orbits\"]` for the textbook models";
    stages.choices = kImplementedStages;
    stages.model = kCommon;
    stages.set = [](Scene& x, const Value& v) {
      x.analysis.stages.clear();
      for (const std::string& name : std::get<std::vector<std::string>>(v)) {
        if (name == "analytic") x.analysis.stages.push_back(Stage::kAnalytic);
        if (name == "sweep") x.analysis.stages.push_back(Stage::kSweep);
        if (name == "branches") x.analysis.stages.push_back(Stage::kBranches);
        if (name == "orbits") x.analysis.stages.push_back(Stage::kOrbits);
        if (name == "tori") x.analysis.stages.push_back(Stage::kTori);
      }
    };
    stages.get = [](const Scene& x) {
      std::vector<std::string> names;
      for (Stage stage : x.analysis.stages) names.push_back(ToString(stage));
      return Value(names);
    };
    s.push_back(stages);
  }
  // The analytic grid is the library's AnalyticOptions, held as such in the scene.
  {
    KeySpec range;
    range.key = "analysis.precession_range_hz";
    range.type = ValueType::kFloatPair;
    range.unit = "Hz";
    range.rule = Rule::kIncreasingPositive;
    range.presence = Presence::kOptional;
    range.doc = "[low, high]: precession-frequency range of the analytic curves.";
    range.model = kCommon;
    range.set = [](Scene& x, const Value& v) {
      const auto& pair = std::get<std::array<double, 2>>(v);
      x.analysis.analytic.min_precession_hz = pair[0];
      x.analysis.analytic.max_precession_hz = pair[1];
    };
    range.get = [](const Scene& x) {
      return Value(std::array<double, 2>{x.analysis.analytic.min_precession_hz,
                                         x.analysis.analytic.max_precession_hz});
    };
    s.push_back(range);
  }
  s.push_back(Make<int, std::int64_t>(
      "analysis.precession_points", ValueType::kInteger, "-", Rule::kGridPoints,
      Presence::kOptional,
      "Grid points of the analytic curves; transitions are located to machine precision between "
      "them.",
      [](Scene& x) -> int& { return x.analysis.analytic.precession_points; }, kCommon));
  s.push_back(Make<std::array<double, 2>>(
      "analysis.speed_range_rpm", ValueType::kFloatPair, "rpm", Rule::kIncreasingPositive,
      Presence::kOptional,
      "[low, high]: running-speed range of the continuation branches.",
      [](Scene& x) -> std::array<double, 2>& { return x.analysis.speed_range_rpm; }, kCommon));

  // [analysis.sweep]: time-marching sweeps (level L3, Kumar 2010 §3.5; sweeps/rub_sweep.h).
  auto sweep_pair = [&](const char* key, const char* doc, Field<std::array<double, 2>> field) {
    s.push_back(Make<std::array<double, 2>>(key, ValueType::kFloatPair, "rpm",
                                            Rule::kIncreasingPositive, Presence::kOptional, doc,
                                            field));
  };
  auto sweep_float = [&](const char* key, const char* unit, Rule rule, const char* doc,
                         Field<double> field) {
    s.push_back(Float(key, unit, rule, doc, field, Presence::kOptional));
  };
  auto sweep_rule = [&](const char* key, const char* unit, Rule rule, const char* doc,
                        Field<double> field) {
    sweep_float(key, unit, rule, doc, field);
    s.back().reclassifies = true;
  };
  sweep_pair("analysis.sweep.up_range_rpm",
             "[low, high]: the speed-up sweep runs from low to high.",
             [](Scene& x) -> std::array<double, 2>& { return x.analysis.sweep.up_range_rpm; });
  sweep_pair("analysis.sweep.down_range_rpm",
             "[low, high]: the speed-down sweep runs from high to low.",
             [](Scene& x) -> std::array<double, 2>& { return x.analysis.sweep.down_range_rpm; });
  sweep_float("analysis.sweep.speed_step_rpm", "rpm", Rule::kPositive,
              "Speed step; each speed continues from the state the previous one ended in.",
              [](Scene& x) -> double& { return x.analysis.sweep.speed_step_rpm; });
  sweep_float("analysis.sweep.dwell", "s", Rule::kPositive,
              "Longest simulated time per speed (whole settle windows); ≥ (settle_windows + 1)·"
              "settle_window.", [](Scene& x) -> double& { return x.analysis.sweep.dwell; });
  sweep_float("analysis.sweep.settle_window", "s", Rule::kPositive,
              "Window length of the settle test: successive windows are compared.",
              [](Scene& x) -> double& { return x.analysis.sweep.settle_window; });
  s.push_back(Make<int, std::int64_t>(
      "analysis.sweep.settle_windows", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "A speed has settled when this many successive window pairs agree (spectra and dominant "
      "frequencies); else it runs to the dwell and is flagged.",
      [](Scene& x) -> int& { return x.analysis.sweep.settle_windows; }));
  sweep_float("analysis.sweep.spectrum_tolerance", "-", Rule::kOpenUnit,
              "Agreeing windows: relative L2 distance of their two-sided amplitude spectra.",
              [](Scene& x) -> double& { return x.analysis.sweep.spectrum_tolerance; });
  sweep_float("analysis.sweep.frequency_tolerance_hz", "Hz", Rule::kPositive,
              "Agreeing windows: change of each contact's dominant (BP) frequency.",
              [](Scene& x) -> double& { return x.analysis.sweep.frequency_tolerance_hz; });
  sweep_float("analysis.sweep.analysis_length", "s", Rule::kPositive,
              "The last stretch of each speed that is analysed (spectrum, BP, slip velocity); "
              "≤ (settle_windows + 1)·settle_window.",
              [](Scene& x) -> double& { return x.analysis.sweep.analysis_length; });
  sweep_float("analysis.sweep.sample_rate_hz", "Hz", Rule::kPositive,
              "Sampling rate of the analysed signals (dense output of the integrator).",
              [](Scene& x) -> double& { return x.analysis.sweep.sample_rate_hz; });
  sweep_float("analysis.sweep.spectrum_max_hz", "Hz", Rule::kPositive,
              "Spectra are stored for −this … +this (the waterfall); ≤ sample_rate_hz/2.",
              [](Scene& x) -> double& { return x.analysis.sweep.spectrum_max_hz; });
  sweep_float("analysis.sweep.impulse", "N·s", Rule::kNonNegative,
              "Impulse on the rotor at its mass-centre plane along +x at the start of each "
              "direction (rotor centred and at rest): a translation at impulse/m_r.",
              [](Scene& x) -> double& { return x.analysis.sweep.impulse; });
  s.push_back(Choice(
      "analysis.sweep.integrator",
      "\"explicit\" (Boost.Odeint Dormand–Prince 5(4)), \"bdf\" (CVODES BDF, order ≤ 2) or \"auto\" "
      "(BDF while every contact touches continuously, Dormand–Prince after a window in which a "
      "contact touched 0–90 % of the time). BDF is cheaper in continuous contact, but its damping "
      "of the contact modes can hold the rotor on an unstable rotating wave that Dormand–Prince "
      "leaves (cases A(b), B(b), B(c) below 52 rpm): results/README.md, \"Sweep integrators\".",
      {"bdf", "explicit", "auto"},
      [](Scene& x, const std::string& name) {
        x.analysis.sweep.integrator = name == "explicit" ? SweepIntegrator::kExplicit
                                      : name == "auto"   ? SweepIntegrator::kAuto
                                                         : SweepIntegrator::kBdf;
      },
      [](const Scene& x) { return std::string(ToString(x.analysis.sweep.integrator)); }));
  sweep_float("analysis.sweep.relative_tolerance", "-", Rule::kOpenUnit,
              "CVODES BDF (order ≤ 2, analytic Jacobian): relative local error tolerance.",
              [](Scene& x) -> double& { return x.analysis.sweep.relative_tolerance; });
  sweep_float("analysis.sweep.absolute_tolerance", "-", Rule::kOpenUnit,
              "Absolute tolerance, in units of each state's scale (clearance; clearance × the "
              "fastest support frequency).",
              [](Scene& x) -> double& { return x.analysis.sweep.absolute_tolerance; });
  sweep_float("analysis.sweep.explicit_tolerance", "-", Rule::kOpenUnit,
              "rtol = atol (scaled states) of Dormand–Prince where integrator is \"explicit\" or "
              "\"auto\". An explicit pair at its stability limit keeps up contact chatter that has "
              "died out unless the tolerance is tight: measured on A(a) from 20 rpm, chatter to "
              "32 rpm at 1e-7, none from 24 rpm at 1e-8 (as BDF and ERK at 1e-9).",
              [](Scene& x) -> double& { return x.analysis.sweep.explicit_tolerance; });
  sweep_rule("analysis.sweep.rolling_slip_tolerance", "-", Rule::kOpenUnit,
              "A contact whirls (rolls) when its mean slip velocity in contact |V| ≤ this·R·ω (the "
              "surface speed) or ≤ rolling_micro_slip·velocity_scale, and its BP passes the "
              "whirl_tolerance check; otherwise it whips (slips).",
              [](Scene& x) -> double& { return x.analysis.sweep.rolling_slip_tolerance; });
  sweep_rule("analysis.sweep.rolling_micro_slip", "-", Rule::kNonNegative,
              "The tanh law's micro-slip of rolling, in units of velocity_scale ε (V = "
              "ε·atanh(μ_req/μ) ≤ ε while μ_req ≤ 0.76 μ): |V| up to this·ε counts as rolling at "
              "any speed. 0: the surface-speed rule alone.",
              [](Scene& x) -> double& { return x.analysis.sweep.rolling_micro_slip; });
  sweep_rule("analysis.sweep.whirl_tolerance", "-", Rule::kOpenUnit,
              "The frequency check of a rolling contact: |BP − f_roll| ≤ this·f_roll, f_roll = "
              "RCI·(speed in rev/s).",
              [](Scene& x) -> double& { return x.analysis.sweep.whirl_tolerance; });
  sweep_rule("analysis.sweep.frequency_jump_hz", "Hz", Rule::kPositive,
              "Between successive speeds, a BP change larger than this from both trends (BP "
              "constant, BP ∝ speed) is a jump even when the regime stays the same.",
              [](Scene& x) -> double& { return x.analysis.sweep.frequency_jump_hz; });
  sweep_rule("analysis.sweep.max_penetration", "-", Rule::kPositive,
              "A speed whose largest penetration at a contact passes this share of its clearance "
              "is untrusted (the contact laws are those of a small overlap; an integration that lets "
              "the rotor sink into the stator): its regime is still read, the file says why, and "
              "its jumps are marked. The orbits stage marks its orbits by the same rule.",
              [](Scene& x) -> double& { return x.analysis.sweep.max_penetration; });

  // [analysis.orbits]: the modulated whirl and whip (level L2, shooting/rub_orbits.h).
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.hopf_points", ValueType::kInteger, "-", Rule::kCountOrNone,
      Presence::kOptional,
      "How many Hopf points to follow: those that bound a stable piece of a tanh-law rotating "
      "wave, in order of speed (mirror images once); 0: none, only the orbits of "
      "[analysis.orbits.transient], which must then be given.",
      [](Scene& x) -> int& { return x.analysis.orbits.hopf_points; }));
  s.push_back(Float("analysis.orbits.amplitude", "-", Rule::kOpenUnit,
                    "Amplitude of the first orbit off the rotating wave (scaled state units).",
                    [](Scene& x) -> double& { return x.analysis.orbits.amplitude; }, Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.segments", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional, "Shooting segments per modulation period (1: single shooting).",
      [](Scene& x) -> int& { return x.analysis.orbits.segments; }));
  s.push_back(Choice(
      "analysis.orbits.integrator",
      "\"gauss\" (Gauss–Legendre collocation of order 8 on a fixed mesh of collocation_intervals "
      "per period, its state-transition matrix the exact derivative of the discrete map) or "
      "\"bdf\" (CVODES BDF with sensitivities under error control, 50–70 times slower on the "
      "thesis's contact): results/README.md, \"Cost of the modulated whip\".",
      {"gauss", "bdf"},
      [](Scene& x, const std::string& name) {
        x.analysis.orbits.integrator = name == "bdf" ? OrbitIntegrator::kBdf : OrbitIntegrator::kGauss;
      },
      [](const Scene& x) { return std::string(ToString(x.analysis.orbits.integrator)); }));
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.collocation_intervals", ValueType::kInteger, "-", Rule::kSteps,
      Presence::kOptional,
      "Gauss collocation: mesh intervals per modulation period, shared evenly by the segments "
      "(rounded up to a multiple of segments).",
      [](Scene& x) -> int& { return x.analysis.orbits.collocation_intervals; }));
  s.push_back(Float("analysis.orbits.tolerance", "-", Rule::kOpenUnit,
                    "CVODES BDF tolerance (relative = absolute, on scaled states) of every segment; "
                    "with Gauss collocation its stage Newton stops at 1e-3 times this.",
                    [](Scene& x) -> double& { return x.analysis.orbits.tolerance; }, Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.max_steps", ValueType::kInteger, "-", Rule::kSteps, Presence::kOptional,
      "Continuation steps from each Hopf point, and from each branch point and period doubling "
      "followed.",
      [](Scene& x) -> int& { return x.analysis.orbits.max_steps; }));
  s.push_back(Choice(
      "analysis.orbits.branch_points",
      "\"follow\": the other branch through each located branch point of a family is followed "
      "(one of the two mirror images where the point breaks a left–right symmetric rotor's "
      "symmetry), and the period-doubled orbits from each period doubling where the family loses "
      "or gains stability; \"mark\": located and reported only.",
      {"follow", "mark"},
      [](Scene& x, const std::string& name) {
        x.analysis.orbits.follow_branch_points = name == "follow";
      },
      [](const Scene& x) {
        return std::string(x.analysis.orbits.follow_branch_points ? "follow" : "mark");
      }));

  // [analysis.orbits.transient]: the orbits through the orbit a settled transient lies on.
  s.push_back(Float(
      "analysis.orbits.transient.speed_rpm", "rpm", Rule::kPositive,
      "Running speed of the transient: one speed of the scene's sweep model "
      "([analysis.sweep]: integrator, windows, impulse) run from rest and the impulse "
      "for `seconds`; the relative periodic orbit it settles on (of `laps` modulation "
      "periods) is solved there and its family continued towards lower and higher "
      "speed over speed_range_rpm with [analysis.orbits]' shooting; inside "
      "analysis.speed_range_rpm.",
      [](Scene& x) -> double& { return x.analysis.orbits.transient.speed_rpm; },
      Presence::kRequiredInSection));
  s.back().default_text = "no transient";
  s.push_back(Float(
      "analysis.orbits.transient.seconds", "s", Rule::kPositive,
      "Length of the transient from rest and the impulse, at least "
      "(settle_windows + 1)·settle_window of [analysis.sweep] (C(a) at 49.4 rpm: 8 s).",
      [](Scene& x) -> double& { return x.analysis.orbits.transient.seconds; },
      Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.transient.laps", ValueType::kInteger, "-", Rule::kCount,
      Presence::kOptional,
      "Modulation periods per orbit, at most 64: 1 for a modulated whip; m for a two-frequency "
      "whip locked at p:m (C(a) at 49.4 rpm: 3, the 1:3 tongue), whose orbit closes only after m "
      "modulation periods. Each lap gets [analysis.orbits]' segments and mesh.",
      [](Scene& x) -> int& { return x.analysis.orbits.transient.laps; }));
  s.push_back(Make<int, std::int64_t>(
      "analysis.orbits.transient.max_steps", ValueType::kInteger, "-", Rule::kSteps,
      Presence::kOptional,
      "Continuation steps each way from the transient's orbit (a closed curve of locked orbits "
      "is followed once round and ends there).",
      [](Scene& x) -> int& { return x.analysis.orbits.transient.max_steps; }));

  // [analysis.tori]: the whips modulated at two frequencies (level L2, shooting/rub_tori.h).
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.harmonics", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "K: Fourier harmonics of each torus's invariant circle (2K + 1 points, each integrated over "
      "one modulation period with [analysis.orbits]' integrator and mesh).",
      [](Scene& x) -> int& { return x.analysis.tori.harmonics; }));
  s.push_back(Float("analysis.tori.amplitude", "-", Rule::kOpenUnit,
                    "Size of the first circle off the modulated orbit at its Neimark–Sacker point "
                    "(scaled state units).",
                    [](Scene& x) -> double& { return x.analysis.tori.amplitude; }, Presence::kOptional));
  s.push_back(Float("analysis.tori.max_fourier_tail", "-", Rule::kOpenUnit,
                    "A torus family ends where its circle's last harmonic reaches this share of "
                    "the largest: phase locking where the largest harmonic after the first is a q "
                    "with ρ near p/q, breakdown otherwise (shooting/torus_branches.h).",
                    [](Scene& x) -> double& { return x.analysis.tori.max_fourier_tail; },
                    Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.max_steps", ValueType::kInteger, "-", Rule::kSteps, Presence::kOptional,
      "Continuation steps from each Neimark–Sacker point.",
      [](Scene& x) -> int& { return x.analysis.tori.max_steps; }));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.lyapunov_iterates", ValueType::kInteger, "-", Rule::kCount,
      Presence::kOptional,
      "Iterates of each torus's map for its Lyapunov exponents (stability; the first quarter is "
      "not counted).",
      [](Scene& x) -> int& { return x.analysis.tori.lyapunov_iterates; }));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.samples", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "Instants per modulation period at which each torus is sampled for the lines of each "
      "contact's precession (≥ 4).",
      [](Scene& x) -> int& { return x.analysis.tori.samples; }));
  s.push_back(Choice(
      "analysis.tori.neimark_sacker",
      "\"follow\": the tori born at the Neimark–Sacker points of the modulated orbits of "
      "[analysis.orbits]; \"skip\": no modulated orbits and none of those tori — only the tori "
      "of [analysis.tori.transient], which must then be given.",
      {"follow", "skip"},
      [](Scene& x, const std::string& name) { x.analysis.tori.from_neimark_sacker = name == "follow"; },
      [](const Scene& x) {
        return std::string(x.analysis.tori.from_neimark_sacker ? "follow" : "skip");
      }));
  // [analysis.tori.transient]: the tori through the torus a settled transient lies on.
  s.push_back(Float("analysis.tori.transient.speed_rpm", "rpm", Rule::kPositive,
                    "Running speed of the transient: one speed of the scene's sweep model "
                    "([analysis.sweep]: integrator, windows, impulse) run from rest and the impulse "
                    "for `seconds`; the torus it settles on is solved there (its map by CVODES "
                    "BDF) and continued towards lower and higher speed over speed_range_rpm (the "
                    "map by [analysis.orbits]' integrator); inside analysis.speed_range_rpm.",
                    [](Scene& x) -> double& { return x.analysis.tori.transient.speed_rpm; },
                    Presence::kRequiredInSection));
  s.back().default_text = "no transient";
  s.push_back(Float("analysis.tori.transient.seconds", "s", Rule::kPositive,
                    "Length of the transient from rest and the impulse, at least "
                    "(settle_windows + 1)·settle_window of [analysis.sweep] (C(a) at 49 rpm: 8 s; "
                    "the torus then attracts for 4 s more before its points are taken).",
                    [](Scene& x) -> double& { return x.analysis.tori.transient.seconds; },
                    Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.transient.harmonics", ValueType::kInteger, "-", Rule::kCount,
      Presence::kOptional,
      "K of the transient's circles (2K + 1 points). C(a) at 49 rpm: K = 4 fits no circle to "
      "the transient's points; at K = 16 Newton met a singular Jacobian from the Dormand–Prince "
      "transient of the sweep's defaults (it converged from a BDF one: "
      "tests/shooting/modulated_orbit_test.cpp); K = 8 converged from both.",
      [](Scene& x) -> int& { return x.analysis.tori.transient.harmonics; }));
  s.push_back(Float("analysis.tori.transient.max_fourier_tail", "-", Rule::kOpenUnit,
                    "As analysis.tori.max_fourier_tail, for the transient's families (a torus far "
                    "from its birth is less smooth: C(a) at 49 rpm has a tail of 0.016 at K = 8).",
                    [](Scene& x) -> double& { return x.analysis.tori.transient.max_fourier_tail; },
                    Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.transient.max_steps", ValueType::kInteger, "-", Rule::kSteps,
      Presence::kOptional,
      "Continuation steps each way from the transient's torus (C(a) at 49 rpm, K = 8: 38 steps "
      "downwards took 1145 s, 10–15 s each until the family neared its turn at the 5:13 "
      "resonance, then up to 340 s).",
      [](Scene& x) -> int& { return x.analysis.tori.transient.max_steps; }));

  // Every default is the initializer of its Scene field (and the structs inside it): written once.
  const Scene defaults;
  for (KeySpec& spec : s)
    if (spec.presence != Presence::kRequired) spec.default_value = spec.get(defaults);
  return s;
}

const std::vector<KeySpec>& Schema() {
  static const std::vector<KeySpec> schema = BuildSchema();
  return schema;
}

// Sections in schema order ("" is the top level).
std::vector<std::string> Sections() {
  std::vector<std::string> sections;
  for (const KeySpec& spec : Schema()) {
    std::string section = spec.Section();
    // Every prefix of a section is a section too ("contact" for "contact.friction_law").
    std::vector<std::string> chain;
    for (std::string s = section; !s.empty();) {
      chain.push_back(s);
      const auto dot = s.rfind('.');
      s = dot == std::string::npos ? std::string() : s.substr(0, dot);
    }
    chain.push_back("");
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
      if (std::find(sections.begin(), sections.end(), *it) == sections.end()) sections.push_back(*it);
  }
  return sections;
}

bool IsSection(const std::string& path) {
  const auto sections = Sections();
  return !path.empty() && std::find(sections.begin(), sections.end(), path) != sections.end();
}

const KeySpec* FindKey(const std::string& path) {
  for (const KeySpec& spec : Schema())
    if (spec.key == path) return &spec;
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Table arrays ([[path]]): lists of rows, as rotordynamics input lists shaft segments, disks and
// supports. Each row key is a KeySpec (type, unit, rule, required or default, doc; its set, get and
// model unused: the table array's own apply). `set` stores the rows read — each the keys it gives —
// after every plain key, so a row's default may be a [flexible] key; `get` gives the rows back
// with every key resolved (ResolvedSceneToml).

using Row = std::map<std::string, Value>;

struct TableArraySpec {
  std::string path;  // "flexible.rotor_shaft"
  std::string doc;   // what one row is
  std::vector<KeySpec> keys;
  std::function<void(Scene&, const std::vector<Row>&)> set;
  std::function<std::vector<Row>(const Scene&)> get;
};

// A row key: required when `default_text` is empty, else optional with that default (markdown).
KeySpec RowKey(std::string key, ValueType type, std::string unit, Rule rule,
               std::string default_text, std::string doc) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = type;
  spec.unit = std::move(unit);
  spec.rule = rule;
  spec.presence = default_text.empty() ? Presence::kRequired : Presence::kOptional;
  spec.default_text = std::move(default_text);
  spec.doc = std::move(doc);
  return spec;
}

double RowNumber(const Row& row, const std::string& key, double otherwise) {
  const auto found = row.find(key);
  if (found == row.end()) return otherwise;
  if (const auto* n = std::get_if<std::int64_t>(&found->second)) return static_cast<double>(*n);
  return std::get<double>(found->second);
}

std::vector<TableArraySpec> BuildTableArrays() {
  std::vector<TableArraySpec> arrays;
  using Rows = std::vector<Row>;
  for (const std::string body : {"rotor", "stator"}) {
    const auto rows = [body](Scene& x) -> std::vector<ShaftRow>& {
      return body == "rotor" ? x.flexible.rotor_shaft : x.flexible.stator_shaft;
    };
    TableArraySpec shaft;
    shaft.path = "flexible." + body + "_shaft";
    shaft.doc = "One segment of the " + body + "'s shaft, left to right: a uniform hollow circle "
                "cut into `elements` equal Timoshenko elements. Stations are numbered from 0 at "
                "the first segment's left end, one more at each element's right end.";
    shaft.keys = {
        RowKey("length", ValueType::kFloat, "m", Rule::kPositive, "", "Segment length."),
        RowKey("outer_diameter", ValueType::kFloat, "m", Rule::kPositive, "", "Outer diameter."),
        RowKey("inner_diameter", ValueType::kFloat, "m", Rule::kNonNegative, "`0.0`",
               "Bore (0: solid); below outer_diameter."),
        RowKey("youngs_modulus", ValueType::kFloat, "Pa", Rule::kPositive,
               "flexible.youngs_modulus", "E."),
        RowKey("shear_modulus", ValueType::kFloat, "Pa", Rule::kPositive,
               "E/(2(1 + poisson_ratio)) with poisson_ratio, else flexible.shear_modulus",
               "G; with E the Poisson ratio E/(2G) − 1 must lie in (−1, 0.5]."),
        RowKey("poisson_ratio", ValueType::kFloat, "-", Rule::kFinite, "none (shear_modulus)",
               "ν in (−1, 0.5], instead of shear_modulus (not both)."),
        RowKey("density", ValueType::kFloat, "kg/m³", Rule::kNonNegative, "flexible.density",
               "ρ."),
        RowKey("elements", ValueType::kInteger, "-", Rule::kCount, "`1`",
               "Equal elements the segment is cut into."),
    };
    shaft.set = [rows](Scene& x, const Rows& given) {
      const FlexibleSettings& f = x.flexible;
      std::vector<ShaftRow>& out = rows(x);
      out.clear();
      for (const Row& r : given) {
        ShaftRow row;
        ShaftElement& e = row.section;
        e.length = RowNumber(r, "length", 0.0);
        e.outer_diameter = RowNumber(r, "outer_diameter", 0.0);
        e.inner_diameter = RowNumber(r, "inner_diameter", 0.0);
        e.youngs_modulus = RowNumber(r, "youngs_modulus", f.youngs_modulus);
        e.shear_modulus =
            r.count("poisson_ratio")
                ? e.youngs_modulus / (2.0 * (1.0 + RowNumber(r, "poisson_ratio", 0.0)))
                : RowNumber(r, "shear_modulus", f.shear_modulus);
        e.density = RowNumber(r, "density", f.density);
        row.elements = static_cast<int>(RowNumber(r, "elements", 1.0));
        out.push_back(row);
      }
    };
    shaft.get = [rows](const Scene& x) {
      Rows out;
      for (const ShaftRow& row : rows(const_cast<Scene&>(x))) {
        const ShaftElement& e = row.section;
        out.push_back({{"length", e.length}, {"outer_diameter", e.outer_diameter},
                       {"inner_diameter", e.inner_diameter}, {"youngs_modulus", e.youngs_modulus},
                       {"shear_modulus", e.shear_modulus}, {"density", e.density},
                       {"elements", std::int64_t{row.elements}}});
      }
      return out;
    };
    arrays.push_back(shaft);

    const auto disk_rows = [body](Scene& x) -> std::vector<Disk>& {
      return body == "rotor" ? x.flexible.rotor_disks : x.flexible.stator_disks;
    };
    TableArraySpec disks;
    disks.path = "flexible." + body + "_disks";
    disks.doc = "A rigid disk (or any lumped mass) on a station of the listed " + body + " shaft.";
    disks.keys = {
        RowKey("station", ValueType::kInteger, "-", Rule::kStation, "", "Its station."),
        RowKey("mass", ValueType::kFloat, "kg", Rule::kNonNegative, "", "Mass."),
        RowKey("diametral_inertia", ValueType::kFloat, "kg·m²", Rule::kNonNegative, "`0.0`",
               "I_d, about a diameter through the station."),
        RowKey("polar_inertia", ValueType::kFloat, "kg·m²", Rule::kNonNegative, "`0.0`",
               "I_p (gyroscopic moments)."),
    };
    disks.set = [disk_rows](Scene& x, const Rows& given) {
      std::vector<Disk>& out = disk_rows(x);
      out.clear();
      for (const Row& r : given) {
        out.push_back({static_cast<int>(RowNumber(r, "station", 0.0)), RowNumber(r, "mass", 0.0),
                       RowNumber(r, "diametral_inertia", 0.0), RowNumber(r, "polar_inertia", 0.0)});
      }
    };
    disks.get = [disk_rows](const Scene& x) {
      Rows out;
      for (const Disk& d : disk_rows(const_cast<Scene&>(x))) {
        out.push_back({{"station", std::int64_t{d.node}}, {"mass", d.mass},
                       {"diametral_inertia", d.diametral_inertia}, {"polar_inertia", d.polar_inertia}});
      }
      return out;
    };
    arrays.push_back(disks);
  }
  TableArraySpec supports;
  supports.path = "flexible.stator_supports";
  supports.doc = "A spring and dashpot from a station of the listed stator shaft to ground. The "
                 "rigid model holds its stator at the contacts: supports go on contact stations, "
                 "and give [stator]'s stiffness and damping.";
  supports.keys = {
      RowKey("station", ValueType::kInteger, "-", Rule::kStation, "", "A contact station."),
      RowKey("stiffness", ValueType::kFloat, "N/m", Rule::kNonNegative, "", "k."),
      RowKey("damping", ValueType::kFloat, "N·s/m", Rule::kNonNegative, "`0.0`", "c."),
  };
  supports.set = [](Scene& x, const Rows& given) {
    x.flexible.stator_supports.clear();
    for (const Row& r : given) {
      x.flexible.stator_supports.push_back({static_cast<int>(RowNumber(r, "station", 0.0)),
                                            RowNumber(r, "stiffness", 0.0),
                                            RowNumber(r, "damping", 0.0)});
    }
  };
  supports.get = [](const Scene& x) {
    Rows out;
    for (const SupportRow& r : x.flexible.stator_supports) {
      out.push_back({{"station", std::int64_t{r.station}}, {"stiffness", r.stiffness},
                     {"damping", r.damping}});
    }
    return out;
  };
  arrays.push_back(supports);
  return arrays;
}

const std::vector<TableArraySpec>& TableArrays() {
  static const std::vector<TableArraySpec> arrays = BuildTableArrays();
  return arrays;
}

const TableArraySpec* FindTableArray(const std::string& path) {
  for (const TableArraySpec& spec : TableArrays())
    if (spec.path == path) return &spec;
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Formatting values as TOML literals.

// TOML literal: the shortest text that reads back as the same double. For people (`human`):
// 10 significant digits, exponent notation for large and small magnitudes (1.75e+11).
std::string FormatFloat(double x, bool human = false) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (human) return fmt::format("{:.10g}", x);
  std::string text = fmt::format("{}", x);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

std::string Quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04X}", c);
        else out += c;
    }
  }
  return out + "\"";
}

std::string FormatValue(const Value& value, bool human = false) {
  struct Visitor {
    bool human;
    std::string operator()(double x) const { return FormatFloat(x, human); }
    std::string operator()(std::int64_t x) const { return std::to_string(x); }
    std::string operator()(const std::string& x) const { return Quote(x); }
    std::string operator()(const std::array<double, 2>& x) const {
      return "[" + FormatFloat(x[0], human) + ", " + FormatFloat(x[1], human) + "]";
    }
    std::string operator()(const std::vector<std::string>& x) const {
      std::string out = "[";
      for (std::size_t i = 0; i < x.size(); ++i) out += (i ? ", " : "") + Quote(x[i]);
      return out + "]";
    }
    std::string operator()(const std::array<std::int64_t, 2>& x) const {
      return fmt::format("[{}, {}]", x[0], x[1]);
    }
  };
  return std::visit(Visitor{human}, value);
}

// A value as the user would write it back (the shortest round-trip for floats).
std::string FormatNode(const toml::node& node) {
  if (const auto* f = node.as_floating_point()) return FormatFloat(f->get());
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* s = node.as_string()) return Quote(s->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = node.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < a->size(); ++i) out += (i ? ", " : "") + FormatNode(*a->get(i));
    return out + "]";
  }
  std::ostringstream out;  // dates, times, tables: toml++'s own form
  out << toml::node_view<const toml::node>(node);
  return out.str();
}

std::string UnitSuffix(const KeySpec& spec) {
  return spec.unit.empty() || spec.unit == "-" ? std::string() : " (" + spec.unit + ")";
}

// ---------------------------------------------------------------------------------------------
// Rules.

std::string JoinQuoted(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + Quote(names[i]);
  return out;
}

// `"a"`, `"b"` (markdown).
std::string JoinCode(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", `" : "`") + Quote(names[i]) + "`";
  return out;
}

// The rule as the key reference states it (markdown).
std::string RuleText(const KeySpec& spec) {
  switch (spec.rule) {
    case Rule::kText: return "any text";
    case Rule::kSceneName: return "1–100 of `A–Z a–z 0–9 _ . -`, not starting with `.`";
    case Rule::kChoice: return "one of " + JoinCode(spec.choices);
    case Rule::kStages: return "non-empty, no repeats, each one of " + JoinCode(spec.choices);
    case Rule::kFinite: return "finite";
    case Rule::kPositive: return spec.type == ValueType::kFloatPair ? "each > 0" : "> 0";
    case Rule::kNonNegative: return spec.type == ValueType::kFloatPair ? "each ≥ 0" : "≥ 0";
    case Rule::kIncreasingPositive: return "0 < low < high";
    case Rule::kGridPoints: return fmt::format("2 … {}", kMaxGridPoints);
    case Rule::kCount: return fmt::format("1 … {}", kMaxCount);
    case Rule::kCountOrNone: return fmt::format("0 … {}", kMaxCount);
    case Rule::kSteps: return fmt::format("1 … {}", kMaxSteps);
    case Rule::kOpenUnit: return "0 < x < 1";
    case Rule::kStation: return fmt::format("0 … {}", kMaxStation);
    case Rule::kStationPair: return fmt::format("0 ≤ left < right ≤ {}", kMaxStation);
  }
  return "";
}

// Returns the broken rule ("must be positive") or nothing.
std::optional<std::string> CheckNumber(double x, Rule rule) {
  if (!std::isfinite(x)) return "must be finite";
  if (rule == Rule::kPositive && !(x > 0.0)) return "must be positive";
  if (rule == Rule::kNonNegative && !(x >= 0.0)) return "must be non-negative";
  return std::nullopt;
}

std::optional<std::string> CheckRule(const KeySpec& spec, const Value& value) {
  switch (spec.rule) {
    case Rule::kText: return std::nullopt;
    case Rule::kSceneName: {
      const std::string& name = std::get<std::string>(value);
      const bool ok = !name.empty() && name.size() <= 100 && name[0] != '.' &&
                      std::all_of(name.begin(), name.end(), [](char c) {
                        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                               c == '.' || c == '-';
                      });
      if (!ok) return "must be 1–100 characters from A–Z a–z 0–9 _ . - and not start with \".\"";
      return std::nullopt;
    }
    case Rule::kChoice: {
      const std::string& choice = std::get<std::string>(value);
      if (std::find(spec.choices.begin(), spec.choices.end(), choice) == spec.choices.end())
        return "must be one of " + JoinQuoted(spec.choices);
      return std::nullopt;
    }
    case Rule::kStages: {
      const auto& names = std::get<std::vector<std::string>>(value);
      if (names.empty()) return std::string("must name at least one stage");
      std::set<std::string> seen;
      for (const std::string& name : names) {
        const bool implemented =
            std::find(kImplementedStages.begin(), kImplementedStages.end(), name) != kImplementedStages.end();
        if (!implemented)
          return Quote(name) + " is not a stage (implemented: " + JoinQuoted(kImplementedStages) + ")";
        if (!seen.insert(name).second) return Quote(name) + " is listed twice";
      }
      return std::nullopt;
    }
    case Rule::kFinite:
    case Rule::kPositive:
    case Rule::kNonNegative:
      if (spec.type == ValueType::kFloatPair) {
        const auto& pair = std::get<std::array<double, 2>>(value);
        for (int k = 0; k < 2; ++k)
          if (auto broken = CheckNumber(pair[k], spec.rule))
            return std::string(k == 0 ? "left" : "right") + " value " + *broken;
        return std::nullopt;
      }
      return CheckNumber(std::get<double>(value), spec.rule);
    case Rule::kIncreasingPositive: {
      const auto& pair = std::get<std::array<double, 2>>(value);
      if (!std::isfinite(pair[0]) || !std::isfinite(pair[1])) return "must be finite";
      if (!(pair[0] > 0.0)) return "low end must be positive (0 < low < high)";
      if (!(pair[1] > pair[0])) return "inverted range: must be increasing (0 < low < high)";
      return std::nullopt;
    }
    case Rule::kGridPoints: {
      const std::int64_t n = std::get<std::int64_t>(value);
      if (n < 2 || n > kMaxGridPoints) return fmt::format("must be from 2 to {}", kMaxGridPoints);
      return std::nullopt;
    }
    case Rule::kCount:
    case Rule::kSteps: {
      const std::int64_t n = std::get<std::int64_t>(value);
      const std::int64_t most = spec.rule == Rule::kCount ? kMaxCount : kMaxSteps;
      if (n < 1 || n > most) return fmt::format("must be from 1 to {}", most);
      return std::nullopt;
    }
    case Rule::kCountOrNone: {
      const std::int64_t n = std::get<std::int64_t>(value);
      if (n < 0 || n > kMaxCount) return fmt::format("must be from 0 to {}", kMaxCount);
      return std::nullopt;
    }
    case Rule::kOpenUnit: {
      const double x = std::get<double>(value);
      if (!std::isfinite(x)) return "must be finite";
      if (!(x > 0.0 && x < 1.0)) return "must lie strictly between 0 and 1";
      return std::nullopt;
    }
    case Rule::kStation: {
      const std::int64_t n = std::get<std::int64_t>(value);
      if (n < 0 || n > kMaxStation) return fmt::format("must be from 0 to {}", kMaxStation);
      return std::nullopt;
    }
    case Rule::kStationPair: {
      const auto& pair = std::get<std::array<std::int64_t, 2>>(value);
      if (pair[0] < 0 || pair[1] > kMaxStation || !(pair[0] < pair[1]))
        return fmt::format("must be stations 0 ≤ left < right ≤ {}", kMaxStation);
      return std::nullopt;
    }
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// Loading.

std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string LastComponent(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::string Parent(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

// "; did you mean rotor.mass?", or else what the enclosing section accepts.
std::string Suggestion(const std::string& path) {
  std::vector<std::string> candidates;
  for (const std::string& section : Sections())
    if (!section.empty()) candidates.push_back(section);
  for (const KeySpec& spec : Schema()) candidates.push_back(spec.key);
  for (const TableArraySpec& spec : TableArrays()) candidates.push_back(spec.path);
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const std::string& candidate : candidates) {
    std::size_t d = EditDistance(path, candidate);
    if (LastComponent(candidate) == LastComponent(path)) d = std::min<std::size_t>(d, 1);  // moved
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  const std::size_t limit = std::max<std::size_t>(2, path.size() / 3);
  if (best_distance <= limit) return "; did you mean " + (IsSection(best) ? "[" + best + "]" : best) + "?";
  const std::string section = Parent(path);
  std::vector<std::string> known;
  for (const KeySpec& spec : Schema())
    if (spec.Section() == section) known.push_back(LastComponent(spec.key));
  for (const std::string& s : Sections())
    if (!s.empty() && Parent(s) == section) known.push_back("[" + s + "]");
  std::string list;
  for (std::size_t i = 0; i < known.size(); ++i) list += (i ? ", " : "") + known[i];
  return " (known " + (section.empty() ? std::string("at the top level") : "in [" + section + "]") +
         ": " + list + ")";
}

class Loader {
 public:
  Loader(std::string source, std::string default_name)
      : source_(std::move(source)), default_name_(std::move(default_name)) {}

  Scene Load(std::string_view text) {
    toml::table root;
    try {
      root = toml::parse(text, source_);
    } catch (const toml::parse_error& e) {
      const auto& where = e.source().begin;
      throw SceneError({fmt::format("{}:{}:{}: TOML syntax error: {}", source_, where.line,
                                    where.column, e.description())});
    }
    Walk(root, "");

    Scene scene;
    scene.source = source_;
    // The model decides which keys apply; read it first.
    const std::optional<Value> model_value = Read(*FindKey("model"));
    if (nodes_.count("model") && !model_value) throw SceneError(problems_);  // rest is moot
    FindKey("model")->set(scene, model_value ? *model_value : FindKey("model")->default_value);
    // The rows first, so that a key can depend on which shafts are listed; stored again once the
    // [flexible] material their defaults come from is read.
    ReadTableArrays(scene);

    for (const KeySpec& spec : Schema()) {
      if (spec.model && *spec.model != scene.model) {
        if (nodes_.count(spec.key))
          Problem(*nodes_.at(spec.key), spec.key + ": not a key of model " +
                                            Quote(ToString(scene.model)));
        continue;
      }
      if (spec.relevant && !spec.relevant(scene)) {
        if (nodes_.count(spec.key))
          Problem(*nodes_.at(spec.key), fmt::format("{} = {}: not used: {}", spec.key,
                                                    FormatNode(*nodes_.at(spec.key)),
                                                    spec.irrelevant_reason));
        continue;
      }
      std::optional<Value> value = Read(spec);
      if (value) {
        spec.set(scene, *value);
        continue;
      }
      if (nodes_.count(spec.key)) continue;  // present but invalid: already reported
      if (SuppliedByListing(spec.key)) continue;  // CheckFlexible takes it from the shafts
      const bool section_present = present_sections_.count(spec.Section()) > 0;
      if (spec.presence == Presence::kRequired ||
          (spec.presence == Presence::kRequiredInSection && section_present)) {
        problems_.push_back(fmt::format(
            "{}: {}: missing; required{} — {}", source_, spec.key,
            spec.presence == Presence::kRequiredInSection
                ? " when [" + spec.Section() + "] is present"
                : std::string(),
            spec.doc + (spec.unit.empty() || spec.unit == "-" ? "" : " [" + spec.unit + "]")));
        continue;
      }
      if (spec.key == "name") {
        scene.name = default_name_;
        if (auto broken = CheckRule(spec, Value(default_name_)))
          problems_.push_back(fmt::format("{}: name (from the file name) = {}: {}; set name = \"...\"",
                                          source_, Quote(default_name_), *broken));
      } else {
        spec.set(scene, spec.default_value);
      }
      // The keys of an absent [flexible] are not defaults the scene runs with: it is rigid; nor
      // are [analysis.tori]'s of a scene without the stage (its stages precede it in the schema).
      if (spec.Section() == "flexible" && !section_present) continue;
      if (IsToriKey(spec) && !RunsStage(scene, Stage::kTori)) continue;
      if (IsOptionalSubsection(spec.Section()) && !section_present) continue;
      scene.defaulted_keys.push_back(spec.key);
    }
    for (const TableArraySpec& spec : TableArrays())
      if (rows_.count(spec.path)) spec.set(scene, rows_.at(spec.path));
    CheckStagesFitModel(scene);
    if (!ModelOf(scene).parameter.empty()) CheckOrbitsStart(scene);
    scene.flexible.enabled =
        scene.model == ModelKind::kTwoPoint && present_sections_.count("flexible") > 0;
    scene.analysis.tori.transient.enabled = present_sections_.count("analysis.tori.transient") > 0;
    scene.analysis.orbits.transient.enabled =
        present_sections_.count("analysis.orbits.transient") > 0;
    if (scene.flexible.enabled && problems_.empty()) CheckFlexible(scene);
    if (problems_.empty()) CheckSweep(scene);
    if (problems_.empty()) CheckOrbits(scene);
    if (problems_.empty()) CheckTori(scene);
    if (!problems_.empty()) throw SceneError(problems_);
    return scene;
  }

 private:
  // Where a key was given ("file:line:col"), or the file alone for a defaulted key.
  std::string Where(const std::string& key) const {
    const auto found = nodes_.find(key);
    if (found == nodes_.end()) return source_;
    const auto& begin = found->second->source().begin;
    return fmt::format("{}:{}:{}", source_, begin.line, begin.column);
  }

  // A scene without analysis.stages runs its model's default stages; one with it may list the
  // model's stages only (apps/models.cpp).
  void CheckStagesFitModel(Scene& scene) {
    const ModelEntry& model = ModelOf(scene);
    if (nodes_.count("analysis.stages") == 0) {
      scene.analysis.stages = model.default_stages;
      return;
    }
    for (Stage stage : scene.analysis.stages) {
      if (model.Has(stage)) continue;
      const std::string given = nodes_.count("analysis.stages")
                                    ? FormatNode(*nodes_.at("analysis.stages"))
                                    : FormatValue(FindKey("analysis.stages")->get(scene));
      std::vector<std::string> own;
      for (Stage s : model.stages) own.push_back(ToString(s));
      problems_.push_back(fmt::format(
          "{}: analysis.stages = {}: {} does not apply to model {}, whose stages are {}; {} is a "
          "stage of {}", Where("analysis.stages"), given, Quote(ToString(stage)),
          Quote(model.name), JoinQuoted(own), Quote(ToString(stage)), ModelsWith(stage)));
      return;
    }
  }

  // The first orbit's parameter: the low end of the range by default, else inside the range.
  void CheckOrbitsStart(Scene& scene) {
    const std::string model = ToString(scene.model);
    const std::string key = model + ".orbits.start";
    const auto& range = scene.orbits.parameter_range;
    if (nodes_.count(key) == 0) {
      scene.orbits.start = range[0];
      return;
    }
    if (scene.orbits.start < range[0] || scene.orbits.start > range[1]) {
      const std::string range_key = ModelOf(scene).parameter + "_range";
      problems_.push_back(fmt::format("{}: {} = {}: must lie in {}.{} = [{}, {}]", Where(key), key,
                                      FormatNode(*nodes_.at(key)), model, range_key,
                                      FormatFloat(range[0]), FormatFloat(range[1])));
    }
  }

  // The rows of every table array given, each key read by its row spec and its problems
  // reported.
  void ReadTableArrays(Scene& scene) {
    for (const TableArraySpec& spec : TableArrays()) {
      const auto found = arrays_.find(spec.path);
      if (found == arrays_.end()) continue;
      if (scene.model != ModelKind::kTwoPoint) {
        Problem(*found->second, fmt::format("[[{}]]: not a table of model {}", spec.path,
                                            Quote(ToString(scene.model))));
        continue;
      }
      std::string known;
      for (const KeySpec& k : spec.keys) known += (known.empty() ? "" : ", ") + k.key;
      // Rows with problems are kept too (without the keys that broke a rule): the body still
      // counts as listed, so its problems are not followed by those of the other form.
      std::vector<Row> rows;
      for (std::size_t i = 0; i < found->second->size(); ++i) {
        const toml::table& table = *found->second->get(i)->as_table();
        const std::string row_name = fmt::format("{}[{}]", spec.path, i);
        Row row;
        for (auto&& [key, node] : table) {
          const std::string name = row_name + "." + std::string(key.str());
          const auto k = std::find_if(spec.keys.begin(), spec.keys.end(),
                                      [&](const KeySpec& k) { return k.key == key.str(); });
          if (k == spec.keys.end()) {
            Problem(key.source(), fmt::format("{}: unknown key (known in [[{}]]: {})", name,
                                              spec.path, known));
          } else if (std::optional<Value> value = Read(*k, node, name)) {
            row[k->key] = *value;
          }
        }
        for (const KeySpec& k : spec.keys) {
          if (k.presence != Presence::kRequired || table.contains(k.key)) continue;
          Problem(table, fmt::format("{}.{}: missing; required — {}{}", row_name, k.key, k.doc,
                                     k.unit == "-" ? "" : " [" + k.unit + "]"));
        }
        rows.push_back(std::move(row));
      }
      rows_[spec.path] = rows;
      spec.set(scene, rows);
    }
  }

  // The [rotor]/[stator] keys a listed body's shafts supply (their rigid-body data), and the
  // table array that lists them.
  static const std::map<std::string, std::string>& SuppliedKeys() {
    static const std::map<std::string, std::string> keys = {
        {"rotor.mass", "flexible.rotor_shaft"},          {"rotor.inertia", "flexible.rotor_shaft"},
        {"rotor.contact_span", "flexible.rotor_shaft"},  {"rotor.mass_center", "flexible.rotor_shaft"},
        {"stator.mass", "flexible.stator_shaft"},        {"stator.inertia", "flexible.stator_shaft"},
        {"stator.span", "flexible.stator_shaft"},        {"stator.mass_center", "flexible.stator_shaft"},
        {"stator.stiffness", "flexible.stator_supports"}, {"stator.damping", "flexible.stator_supports"}};
    return keys;
  }
  bool SuppliedByListing(const std::string& key) const {
    const auto found = SuppliedKeys().find(key);
    return found != SuppliedKeys().end() && rows_.count(found->second) > 0;
  }

  // Reports `rule` at row `i` of table array `path`, at its key `key` (given).
  void RowProblem(const std::string& path, std::size_t i, const std::string& key,
                  const std::string& rule) {
    const toml::node& node = *arrays_.at(path)->get(i)->as_table()->get(key);
    Problem(node, fmt::format("{}[{}].{} = {}: {}", path, i, key, FormatNode(node), rule));
  }

  // A problem of a rule that ties keys together, reported at `key` (full name): where the file
  // gives it, or at its default.
  void KeyProblem(const Scene& scene, const std::string& key, const std::string& rule) {
    if (nodes_.count(key)) {
      Problem(*nodes_.at(key), fmt::format("{} = {}: {}", key, FormatNode(*nodes_.at(key)), rule));
    } else {
      problems_.push_back(fmt::format("{}: {} = {} (default): {}", source_, key,
                                      FormatValue(FindKey(key)->get(scene)), rule));
    }
  }
  void FlexibleProblem(const Scene& scene, const std::string& key, const std::string& rule) {
    KeyProblem(scene, "flexible." + key, rule);
  }

  // The rows of a listed body: sections, stations of disks, supports and contacts.
  void CheckListedBody(Scene& scene, const std::string& body) {
    FlexibleSettings& f = scene.flexible;
    const std::string shaft = "flexible." + body + "_shaft", disks = "flexible." + body + "_disks";
    const bool rotor = body == "rotor";
    const std::vector<ShaftRow>& rows = rotor ? f.rotor_shaft : f.stator_shaft;
    const std::vector<Disk>& disk_rows = rotor ? f.rotor_disks : f.stator_disks;
    std::vector<std::string> station_arrays = {disks};
    if (!rotor) station_arrays.push_back("flexible.stator_supports");
    if (rows.empty()) {
      for (const std::string& path : station_arrays) {
        if (arrays_.count(path) == 0) continue;
        Problem(*arrays_.at(path), fmt::format("[[{}]]: stations number a listed shaft: add [[{}]] "
                                               "rows (a uniform {} gets its disk from [{}])",
                                               path, shaft, body, body));
      }
      return;
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const ShaftElement& e = rows[i].section;
      if (!(e.inner_diameter < e.outer_diameter))
        RowProblem(shaft, i, "inner_diameter", fmt::format("must be below outer_diameter = {} m",
                                                           FormatFloat(e.outer_diameter)));
      const Row& given = rows_.at(shaft)[i];
      if (given.count("poisson_ratio") && given.count("shear_modulus")) {
        RowProblem(shaft, i, "poisson_ratio", "give shear_modulus or poisson_ratio, not both");
        continue;
      }
      const double nu = e.Poisson();
      if (nu > -1.0 && nu <= 0.5) continue;
      for (const std::string key : {"poisson_ratio", "shear_modulus", "youngs_modulus"}) {
        if (!given.count(key)) continue;
        RowProblem(shaft, i, key, fmt::format("gives the Poisson ratio E/(2G) − 1 = {:.4g}: must "
                                              "lie in (−1, 0.5]", nu));
        break;
      }
    }
    // The stations as ListedBody numbers them, the default right contact (-1) resolved to the last.
    std::array<int, 2>& contacts = rotor ? f.rotor_contact_stations : f.stator_contact_stations;
    const BodyShaft listed = ListedBody(body, rows, disk_rows, contacts);
    const int last = listed.shaft.Nodes() - 1;
    contacts = listed.contact_stations;
    if (contacts[1] > last)
      FlexibleProblem(scene, body + "_contact_stations",
                      fmt::format("must name stations of the listed shaft (0 to {})", last));
    for (std::size_t i = 0; i < disk_rows.size(); ++i) {
      if (disk_rows[i].node > last)
        RowProblem(disks, i, "station", fmt::format("must name a station of the listed {} shaft "
                                                    "(0 to {})", body, last));
    }
    if (rotor) return;
    for (std::size_t i = 0; i < f.stator_supports.size(); ++i) {
      const int station = f.stator_supports[i].station;
      if (station != contacts[0] && station != contacts[1])
        RowProblem("flexible.stator_supports", i, "station",
                   fmt::format("must be a contact station, {} or {} (flexible.stator_contact_"
                               "stations): the rigid model holds the stator there",
                               contacts[0], contacts[1]));
    }
  }

  // A listed body's rigid-body data into [rotor]/[stator]: taken where the file leaves the key
  // out, checked to 1e-6 (of the value; of the span for a mass centre) where it gives it.
  void SupplyRigidData(Scene& scene) {
    const FlexibleSettings& f = scene.flexible;
    TwoPointParams& p = scene.two_point;
    auto supply = [&](const std::string& key, double& field, double shafts, double scale,
                      const std::string& unit) {
      if (nodes_.count(key) == 0) {
        field = shafts;
        scene.supplied_keys.push_back(key);
      } else if (!(std::abs(field - shafts) <= 1e-6 * scale)) {
        Problem(*nodes_.at(key),
                fmt::format("{} = {}: the shaft listed in [[{}]] gives {:.10g} {}: must agree to "
                            "1e-6, or leave {} out to take the shaft's", key,
                            FormatNode(*nodes_.at(key)), SuppliedKeys().at(key), shafts, unit, key));
      }
    };
    auto body = [&](const std::string& name, const std::vector<ShaftRow>& rows,
                    const std::vector<Disk>& disks, const std::array<int, 2>& stations,
                    double& mass, double& span, double& mass_center, double& inertia,
                    const std::string& span_key) {
      if (rows.empty()) return;
      RigidBodyData d;
      try {
        d = RigidBodyOf(ListedBody(name, rows, disks, stations));
      } catch (const std::invalid_argument& e) {
        problems_.push_back(fmt::format("{}: [[flexible.{}_shaft]]: {}", source_, name, e.what()));
        return;
      }
      supply(name + ".mass", mass, d.mass, d.mass, "kg");
      supply(name + "." + span_key, span, d.span, d.span, "m");
      supply(name + ".mass_center", mass_center, d.mass_center, d.span, "m");
      supply(name + ".inertia", inertia, d.inertia, d.inertia, "kg·m²");
    };
    body("rotor", f.rotor_shaft, f.rotor_disks, f.rotor_contact_stations, p.rotor_mass,
         p.contact_span, p.rotor_mass_center, p.rotor_inertia, "contact_span");
    body("stator", f.stator_shaft, f.stator_disks, f.stator_contact_stations, p.stator_mass,
         p.stator_span, p.stator_mass_center, p.stator_inertia, "span");
    if (f.stator_supports.empty()) return;
    std::array<double, 2> stiffness{}, damping{};
    for (const SupportRow& r : f.stator_supports) {
      const std::size_t side = r.station == f.stator_contact_stations[0] ? 0 : 1;
      stiffness[side] += r.stiffness;
      damping[side] += r.damping;
    }
    auto supply_pair = [&](const std::string& key, std::array<double, 2>& field,
                           const std::array<double, 2>& supports, const std::string& unit) {
      const double scale = std::max(supports[0], supports[1]);
      if (nodes_.count(key) == 0) {
        field = supports;
        scene.supplied_keys.push_back(key);
      } else if (!(std::abs(field[0] - supports[0]) <= 1e-6 * scale &&
                   std::abs(field[1] - supports[1]) <= 1e-6 * scale)) {
        Problem(*nodes_.at(key),
                fmt::format("{} = {}: [[flexible.stator_supports]] give [{:.10g}, {:.10g}] {} at "
                            "the contact stations: must agree to 1e-6, or leave {} out to take "
                            "theirs", key, FormatNode(*nodes_.at(key)), supports[0], supports[1],
                            unit, key));
      }
    };
    supply_pair("stator.stiffness", p.support_stiffness, stiffness, "N/m");
    supply_pair("stator.damping", p.support_damping, damping, "N·s/m");
  }

  // [flexible]: the rules that tie keys together, then whether the bodies can be built (a shaft
  // lighter than its body, a disk of positive inertia, modes the interior has).
  void CheckFlexible(Scene& scene) {
    const FlexibleSettings& f = scene.flexible;
    if (!f.RotorListed() && !(f.rotor_inner_diameter < f.rotor_outer_diameter))
      FlexibleProblem(scene, "rotor_inner_diameter",
                      fmt::format("must be below flexible.rotor_outer_diameter = {} m",
                                  FormatFloat(f.rotor_outer_diameter)));
    if (!f.StatorListed() && !(f.stator_inner_diameter < f.stator_outer_diameter))
      FlexibleProblem(scene, "stator_inner_diameter",
                      fmt::format("must be below flexible.stator_outer_diameter = {} m",
                                  FormatFloat(f.stator_outer_diameter)));
    const double nu = f.youngs_modulus / (2.0 * f.shear_modulus) - 1.0;
    if (!(nu > -1.0 && nu <= 0.5))
      FlexibleProblem(scene, "shear_modulus", fmt::format("gives the Poisson ratio E/(2G) − 1 = "
                                                          "{:.4g}: must lie in (−1, 0.5]", nu));
    CheckListedBody(scene, "rotor");
    CheckListedBody(scene, "stator");
    if (!problems_.empty()) return;
    SupplyRigidData(scene);
    if (!problems_.empty()) return;
    try {
      BuildFlexibleRub(FlexibleModelOf(scene));
    } catch (const ModelInputError& e) {
      const std::string what = e.what();
      if (e.input() == "modes") {
        FlexibleProblem(scene, "modes", what.substr(what.find(": ") + 2));  // after "modes = N: "
      } else if (e.input() == "rotor section" || e.input() == "stator section") {
        FlexibleProblem(scene, e.input().substr(0, e.input().find(' ')) + "_outer_diameter", what);
      } else {
        problems_.push_back(fmt::format("{}: [flexible]: {}", source_, what));
      }
    } catch (const std::invalid_argument& e) {
      problems_.push_back(fmt::format("{}: [flexible]: {}", source_, e.what()));
    }
  }

  void Problem(const toml::source_region& region, const std::string& message) {
    const auto& where = region.begin;
    problems_.push_back(fmt::format("{}:{}:{}: {}", source_, where.line, where.column, message));
  }
  void Problem(const toml::node& node, const std::string& message) { Problem(node.source(), message); }

  // A transient's speed inside the scene's range and its length enough for the sweep's windows.
  void CheckTransient(const Scene& scene, const std::string& section, double speed_rpm,
                      double seconds) {
    const auto& range = scene.analysis.speed_range_rpm;
    if (speed_rpm < range[0] || speed_rpm > range[1])
      KeyProblem(scene, section + ".speed_rpm",
                 fmt::format("must lie in analysis.speed_range_rpm = [{}, {}]", FormatFloat(range[0]),
                             FormatFloat(range[1])));
    const SweepSettings& w = scene.analysis.sweep;
    const double shortest = (w.settle_windows + 1) * w.settle_window;
    if (seconds < shortest * (1.0 - 1e-12))
      KeyProblem(scene, section + ".seconds",
                 fmt::format("must be at least (settle_windows + 1)·settle_window of "
                             "[analysis.sweep] = {} s", shortest));
  }

  // Rules of [analysis.orbits] that tie keys together, each reported at the key it names.
  void CheckOrbits(const Scene& scene) {
    const RubOrbitsSettings& o = scene.analysis.orbits;
    if (o.transient.laps > kMaxLaps)
      KeyProblem(scene, "analysis.orbits.transient.laps",
                 fmt::format("must be at most {}", kMaxLaps));
    if (!RunsStage(scene, Stage::kOrbits) || scene.model != ModelKind::kTwoPoint) return;
    if (o.hopf_points == 0 && !o.transient.enabled)
      KeyProblem(
          scene, "analysis.orbits.hopf_points",
          "leaves the stage \"orbits\" nothing to compute: give [analysis.orbits.transient]");
    if (o.transient.enabled)
      CheckTransient(scene, "analysis.orbits.transient", o.transient.speed_rpm,
                     o.transient.seconds);
  }

  // Rules of [analysis.tori] that tie keys together, each reported at the key it names.
  void CheckTori(const Scene& scene) {
    const RubToriSettings& t = scene.analysis.tori;
    if (t.samples < 4) KeyProblem(scene, "analysis.tori.samples", "must be at least 4");
    if (!RunsStage(scene, Stage::kTori)) return;
    if (!t.from_neimark_sacker && !t.transient.enabled)
      KeyProblem(scene, "analysis.tori.neimark_sacker",
                 "leaves the stage \"tori\" nothing to compute: give [analysis.tori.transient]");
    if (t.transient.enabled)
      CheckTransient(scene, "analysis.tori.transient", t.transient.speed_rpm, t.transient.seconds);
  }

  void CheckSweep(const Scene& scene) {
    const SweepSettings& w = scene.analysis.sweep;
    const double shortest = (w.settle_windows + 1) * w.settle_window;
    if (w.dwell < shortest * (1.0 - 1e-12))
      KeyProblem(scene, "analysis.sweep.dwell",
                 fmt::format("must be at least (settle_windows + 1)·settle_window = {} s", shortest));
    if (w.analysis_length > shortest * (1.0 + 1e-12))
      KeyProblem(scene, "analysis.sweep.analysis_length",
                 fmt::format("must not exceed (settle_windows + 1)·settle_window = {} s (the shortest "
                             "run of a speed)", shortest));
    if (w.settle_window * w.sample_rate_hz < 15.5)
      KeyProblem(scene, "analysis.sweep.settle_window",
                 fmt::format("must hold at least 16 samples at sample_rate_hz = {}", w.sample_rate_hz));
    if (w.analysis_length * w.sample_rate_hz < 15.5)
      KeyProblem(scene, "analysis.sweep.analysis_length",
                 fmt::format("must hold at least 16 samples at sample_rate_hz = {}", w.sample_rate_hz));
    if (w.spectrum_max_hz > 0.5 * w.sample_rate_hz)
      KeyProblem(scene, "analysis.sweep.spectrum_max_hz",
                 fmt::format("must not exceed sample_rate_hz/2 = {} Hz (Nyquist)", 0.5 * w.sample_rate_hz));
  }

  // Records every value under its dotted path; reports unknown keys and misplaced tables.
  void Walk(const toml::table& table, const std::string& prefix) {
    for (auto&& [key, node] : table) {
      const std::string path = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
      if (const toml::table* sub = node.as_table()) {
        if (IsSection(path)) {
          present_sections_.insert(path);
          Walk(*sub, path);
        } else if (const KeySpec* spec = FindKey(path)) {
          Problem(node, fmt::format("{} is a table: must be a value ({}{})", path,
                                    TypeName(*spec), UnitSuffix(*spec)));
        } else {
          Problem(key.source(), "[" + path + "]: unknown section" + Suggestion(path));
        }
      } else if (FindKey(path) != nullptr) {
        nodes_[path] = &node;
      } else if (FindTableArray(path) != nullptr) {
        const toml::array* rows = node.as_array();
        if (rows != nullptr && rows->is_array_of_tables()) {
          arrays_[path] = rows;
        } else {
          Problem(node, fmt::format("{} = {}: must be rows [[{}]] (an array of tables)", path,
                                    FormatNode(node), path));
        }
      } else if (IsSection(path)) {
        Problem(node, fmt::format("{} = {}: must be a table [{}]", path, FormatNode(node), path));
      } else {
        Problem(key.source(), path + ": unknown key" + Suggestion(path));
      }
    }
  }

  static std::string TypeName(const KeySpec& spec) {
    switch (spec.type) {
      case ValueType::kFloat: return "a number";
      case ValueType::kInteger: return "an integer";
      case ValueType::kString: return "a string";
      case ValueType::kFloatPair: return "an array of two numbers";
      case ValueType::kIntegerPair: return "an array of two integers";
      case ValueType::kStringList: return "an array of strings";
    }
    return "";
  }

  static std::optional<double> Number(const toml::node& node) {
    if (const auto* f = node.as_floating_point()) return f->get();
    if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
    return std::nullopt;
  }

  // The value of `spec` if present, well typed and within its rule; problems are recorded.
  std::optional<Value> Read(const KeySpec& spec) {
    const auto found = nodes_.find(spec.key);
    if (found == nodes_.end()) return std::nullopt;
    return Read(spec, *found->second, spec.key);
  }

  // `node` read as `spec` says, named `name` in problems (a row's key: "flexible.rotor_shaft[2].length").
  std::optional<Value> Read(const KeySpec& spec, const toml::node& node, const std::string& name) {
    auto type_error = [&]() {
      Problem(node, fmt::format("{} = {}: must be {}{}", name, FormatNode(node), TypeName(spec),
                                UnitSuffix(spec)));
      return std::nullopt;
    };
    Value value;
    switch (spec.type) {
      case ValueType::kFloat: {
        const auto x = Number(node);
        if (!x) return type_error();
        value = *x;
        break;
      }
      case ValueType::kInteger: {
        const auto* i = node.as_integer();
        if (i == nullptr) return type_error();
        value = i->get();
        break;
      }
      case ValueType::kString: {
        const auto* s = node.as_string();
        if (s == nullptr) return type_error();
        value = s->get();
        break;
      }
      case ValueType::kFloatPair: {
        const auto* a = node.as_array();
        if (a == nullptr || a->size() != 2) return type_error();
        std::array<double, 2> pair{};
        for (int k = 0; k < 2; ++k) {
          const auto x = Number(*a->get(k));
          if (!x) return type_error();
          pair[k] = *x;
        }
        value = pair;
        break;
      }
      case ValueType::kStringList: {
        const auto* a = node.as_array();
        if (a == nullptr) return type_error();
        std::vector<std::string> list;
        for (const toml::node& element : *a) {
          const auto* s = element.as_string();
          if (s == nullptr) return type_error();
          list.push_back(s->get());
        }
        value = list;
        break;
      }
      case ValueType::kIntegerPair: {
        const auto* a = node.as_array();
        if (a == nullptr || a->size() != 2) return type_error();
        std::array<std::int64_t, 2> pair{};
        for (std::size_t k = 0; k < 2; ++k) {
          const auto* i = a->get(k)->as_integer();
          if (i == nullptr) return type_error();
          pair[k] = i->get();
        }
        value = pair;
        break;
      }
    }
    if (auto broken = CheckRule(spec, value)) {
      Problem(node, fmt::format("{} = {}: {}{}", name, FormatNode(node), *broken, UnitSuffix(spec)));
      return std::nullopt;
    }
    return value;
  }

  std::string source_;
  std::string default_name_;
  std::map<std::string, const toml::node*> nodes_;
  std::map<std::string, const toml::array*> arrays_;  // table arrays given
  std::map<std::string, std::vector<Row>> rows_;       // their rows: the keys read without problems
  std::set<std::string> present_sections_;
  std::vector<std::string> problems_;
};

std::string Join(const std::vector<std::string>& lines) {
  std::string out;
  for (std::size_t i = 0; i < lines.size(); ++i) out += (i ? "\n" : "") + lines[i];
  return out;
}

bool Applies(const KeySpec& spec, ModelKind model) { return !spec.model || *spec.model == model; }

// Whether a key belongs in the resolved scene: every key of its model, but [flexible] only when the
// scene has it (its absence, not its defaults, means the rigid model), and [analysis.tori] only
// when the scene runs the stage "tori" (the results of every other scene stay as they were).
bool Resolved(const KeySpec& spec, const Scene& scene) {
  return Applies(spec, scene.model) && (spec.Section() != "flexible" || scene.flexible.enabled) &&
         (!IsToriKey(spec) || RunsStage(scene, Stage::kTori)) &&
         (spec.Section() != "analysis.tori.transient" || scene.analysis.tori.transient.enabled) &&
         (spec.Section() != "analysis.orbits.transient" ||
          scene.analysis.orbits.transient.enabled) &&
         (!spec.relevant || spec.relevant(scene));
}

// The rows of the table arrays in `section` as TOML ([[path]] blocks), every key resolved.
std::string ResolvedRows(const Scene& scene, const std::string& section) {
  std::string out;
  for (const TableArraySpec& spec : TableArrays()) {
    if (Parent(spec.path) != section || scene.model != ModelKind::kTwoPoint) continue;
    for (const Row& row : spec.get(scene)) {
      out += "\n[[" + spec.path + "]]\n";
      for (const KeySpec& k : spec.keys)
        if (row.count(k.key)) out += k.key + " = " + FormatValue(row.at(k.key)) + "\n";
    }
  }
  return out;
}

std::string DocTypeName(const KeySpec& spec) {
  switch (spec.type) {
    case ValueType::kFloat: return "float";
    case ValueType::kInteger: return "integer";
    case ValueType::kString: return "string";
    case ValueType::kFloatPair:
      return spec.rule == Rule::kIncreasingPositive ? "[float, float]" : "[left, right] floats";
    case ValueType::kIntegerPair: return "[left, right] integers";
    case ValueType::kStringList: return "array of strings";
  }
  return "";
}

std::string PresenceText(const KeySpec& spec) {
  const std::string literal = spec.default_text.empty() ? "`" + FormatValue(spec.default_value) + "`"
                                                        : spec.default_text;
  switch (spec.presence) {
    case Presence::kRequired: return "required";
    case Presence::kOptional: return "optional; default " + literal;
    case Presence::kRequiredInSection:
      return "required in [" + spec.Section() + "]; section absent: " + literal;
  }
  return "";
}

std::string EscapeTable(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

const char* ToString(OrbitIntegrator integrator) {
  switch (integrator) {
    case OrbitIntegrator::kGauss: return "gauss";
    case OrbitIntegrator::kBdf: return "bdf";
  }
  return "unknown";
}

const char* ToString(SweepIntegrator integrator) {
  switch (integrator) {
    case SweepIntegrator::kBdf: return "bdf";
    case SweepIntegrator::kExplicit: return "explicit";
    case SweepIntegrator::kAuto: return "auto";
  }
  return "unknown";
}

const char* ToString(Stage stage) {
  switch (stage) {
    case Stage::kAnalytic: return "analytic";
    case Stage::kSweep: return "sweep";
    case Stage::kBranches: return "branches";
    case Stage::kOrbits: return "orbits";
    case Stage::kTori: return "tori";
  }
  return "?";
}

Level LevelOf(Stage stage) {
  switch (stage) {
    case Stage::kAnalytic: return Level::kL0;
    case Stage::kBranches: return Level::kL1;
    case Stage::kOrbits: return Level::kL2;
    case Stage::kTori: return Level::kL2;
    case Stage::kSweep: return Level::kL3;
  }
  return Level::kL0;
}

Level ResultLevel(const Scene& scene, Level computed) {
  return scene.flexible.enabled ? Level::kL4 : computed;
}

Level HighestLevel(const std::vector<Stage>& stages) {
  Level highest = Level::kL0;
  for (Stage stage : stages) highest = std::max(highest, LevelOf(stage));
  return highest;
}

SceneError::SceneError(std::vector<std::string> problems)
    : std::invalid_argument(Join(problems)), problems_(std::move(problems)) {}

Scene ParseScene(std::string_view toml_text, const std::string& source,
                 const std::string& default_name) {
  return Loader(source, default_name).Load(toml_text);
}

Scene LoadScene(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw SceneError({fmt::format("{}: is a directory, not a scene file", file.string())});
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::error_code ec;
    const char* why = std::filesystem::exists(file, ec) ? "cannot be read" : "no such file";
    throw SceneError({fmt::format("{}: {}", file.string(), why)});
  }
  std::ostringstream text;
  text << in.rdbuf();
  return ParseScene(text.str(), file.string(), file.stem().string());
}

Scene DefaultScene() { return ParseScene(DefaultSceneToml(), "<built-in default scene>", "default"); }

std::string ResolvedSceneToml(const Scene& scene) {
  std::string out = fmt::format(
      "# Scene \"{}\" as resolved by rubcont {} from {}: every key, defaults included.\n",
      scene.name, Version(), scene.source.empty() ? std::string("memory") : scene.source);
  for (const std::string& section : Sections()) {
    std::string body;
    for (const KeySpec& spec : Schema()) {
      if (spec.Section() != section || !Resolved(spec, scene)) continue;
      body += LastComponent(spec.key) + " = " + FormatValue(spec.get(scene)) + "\n";
    }
    if (body.empty()) continue;
    if (!section.empty()) out += "\n[" + section + "]\n";
    out += body + ResolvedRows(scene, section);
  }
  return out;
}

std::string DescribeScene(const Scene& scene) {
  std::string out;
  for (const KeySpec& spec : Schema()) {
    if (!Resolved(spec, scene)) continue;
    const bool defaulted = std::find(scene.defaulted_keys.begin(), scene.defaulted_keys.end(),
                                     spec.key) != scene.defaulted_keys.end();
    const bool supplied = std::find(scene.supplied_keys.begin(), scene.supplied_keys.end(),
                                    spec.key) != scene.supplied_keys.end();
    std::string value = FormatValue(spec.get(scene), true);
    if (!spec.unit.empty() && spec.unit != "-") value += " " + spec.unit;
    out += defaulted  ? fmt::format("  {:<38} = {:<28}  (default)\n", spec.key, value)
           : supplied ? fmt::format("  {:<38} = {:<28}  (from the listed shafts)\n", spec.key, value)
                      : fmt::format("  {:<38} = {}\n", spec.key, value);
  }
  for (const TableArraySpec& spec : TableArrays()) {
    if (scene.model != ModelKind::kTwoPoint) continue;
    const std::vector<Row> rows = spec.get(scene);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      std::string line;
      for (const KeySpec& k : spec.keys) {
        if (!rows[i].count(k.key)) continue;
        line += (line.empty() ? "" : ", ") + k.key + " " + FormatValue(rows[i].at(k.key), true) +
                (k.unit == "-" ? "" : " " + k.unit);
      }
      out += fmt::format("  {:<38}   {}\n", fmt::format("{}[{}]", spec.path, i), line);
    }
  }
  if (const ModelEntry& model = ModelOf(scene); model.derived) out += model.derived(scene);
  return out;
}

std::vector<std::pair<std::string, SweepKeyValue>> SweepKeyValues(const Scene& scene) {
  std::vector<std::pair<std::string, SweepKeyValue>> out;
  for (const KeySpec& spec : Schema()) {
    if (spec.Section() != "analysis.sweep") continue;
    const Value value = spec.get(scene);
    if (const auto* text = std::get_if<std::string>(&value)) {
      out.emplace_back(LastComponent(spec.key), *text);
      continue;
    }
    std::vector<double> numbers;
    if (const auto* x = std::get_if<double>(&value)) numbers = {*x};
    if (const auto* n = std::get_if<std::int64_t>(&value)) numbers = {static_cast<double>(*n)};
    if (const auto* pair = std::get_if<std::array<double, 2>>(&value)) numbers = {(*pair)[0], (*pair)[1]};
    if (numbers.empty()) {  // a broken invariant: every [analysis.sweep] key is a number, a pair or text
      fmt::print(stderr, "rubcont: internal error: [analysis.sweep] key {} has no attribute form\n", spec.key);
      std::abort();
    }
    out.emplace_back(LastComponent(spec.key), std::move(numbers));
  }
  return out;
}

void CopySweepRules(const Scene& from, Scene& to) {
  for (const KeySpec& spec : Schema())
    if (spec.reclassifies) spec.set(to, spec.get(from));
}

bool IsSweepRule(const std::string& key) {
  for (const KeySpec& spec : Schema())
    if (spec.key == key) return spec.reclassifies;
  return false;
}

std::string SceneKeysMarkdown() {
  std::string out;
  out += "Generated by `rubcont scene keys` from the schema that validates every scene.\n";
  for (const std::string& section : Sections()) {
    std::vector<const KeySpec*> keys;
    for (const KeySpec& spec : Schema())
      if (spec.Section() == section) keys.push_back(&spec);
    if (keys.empty()) continue;
    out += "\n### " + (section.empty() ? std::string("Top level") : "[" + section + "]") + "\n\n";
    auto table = [&out](const std::vector<const KeySpec*>& keys) {
      out += "| key | type | unit | rule | required / default | meaning |\n";
      out += "|---|---|---|---|---|---|\n";
      for (const KeySpec* spec : keys) {
        out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", LastComponent(spec->key),
                           DocTypeName(*spec), spec->unit.empty() || spec->unit == "-" ? "–" : spec->unit,
                           EscapeTable(RuleText(*spec)), EscapeTable(PresenceText(*spec)),
                           EscapeTable(spec->doc));
      }
    };
    table(keys);
    for (const TableArraySpec& rows : TableArrays()) {
      if (Parent(rows.path) != section) continue;
      out += "\n### [[" + rows.path + "]]\n\n" + rows.doc + " Optional; any number of rows.\n\n";
      std::vector<const KeySpec*> row_keys;
      for (const KeySpec& k : rows.keys) row_keys.push_back(&k);
      table(row_keys);
    }
  }
  return out;
}

void WriteSceneAttributes(ResultWriter& writer, const Scene& scene) {
  writer.SetAttribute("/", "rubcont_version", Version());
  writer.SetAttribute("/", "scene_name", scene.name);
  writer.SetAttribute("/", "scene_toml", ResolvedSceneToml(scene));
}

}  // namespace rubcont
