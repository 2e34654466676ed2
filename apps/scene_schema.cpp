#include "apps/scene_schema.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include <fmt/format.h>

#include "apps/models.h"

// The schema: one row per key, built section by section in the order the key reference and the
// resolved scene list them; every default is the initializer of its Scene field.

namespace rubcont::schema {
namespace {

// Field accessors: a function returning a reference into the Scene. get() calls it on a
// const Scene through const_cast only to form the reference; it never writes.
template <class T>
using Field = T& (*)(Scene&);

// A key bound to a field of the Scene. Its default (Presence::kOptional, kRequiredInSection) is the
// field's initializer: BuildSchema reads them from a default-constructed Scene.
template <class T, class Stored = T>
KeySpec Make(std::string key, ValueType type, std::string unit, Rule rule, Presence presence,
             std::string doc, Field<T> field) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = type;
  spec.unit = std::move(unit);
  spec.rule = rule;
  spec.presence = presence;
  spec.doc = std::move(doc);
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
               std::function<std::string(const Scene&)> get) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = ValueType::kString;
  spec.rule = Rule::kChoice;
  spec.presence = Presence::kOptional;
  spec.doc = std::move(doc);
  spec.choices = std::move(choices);
  spec.set = [set](Scene& x, const Value& v) { set(x, std::get<std::string>(v)); };
  spec.get = [get](const Scene& x) { return Value(get(x)); };
  return spec;
}

// An optional key of two `choices` held as a bool: the one named `on` sets the field, the other
// clears it.
KeySpec Switch(std::string key, std::string doc, std::vector<std::string> choices, std::string on,
               Field<bool> field) {
  const std::string off = choices.at(choices.at(0) == on ? 1 : 0);
  return Choice(
      std::move(key), std::move(doc), std::move(choices),
      [field, on](Scene& x, const std::string& name) { field(x) = name == on; },
      [field, on, off](const Scene& x) { return field(const_cast<Scene&>(x)) ? on : off; });
}

using Rows = std::vector<Row>;

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

// The top level: name, description, model.
void TopLevelKeys(std::vector<KeySpec>& s) {
  s.push_back(Make<std::string>("name", ValueType::kString, "", Rule::kSceneName,
                                Presence::kOptional,
                                "Scene name: the output goes to `<out>/<name>/`.",
                                [](Scene& x) -> std::string& { return x.name; }));
  s.back().default_text = "the file stem";
  s.push_back(Make<std::string>("description", ValueType::kString, "", Rule::kText,
                                Presence::kOptional,
                                "Free text, kept in the result file.",
                                [](Scene& x) -> std::string& { return x.description; }));
  s.push_back(Choice(
      "model", "Which model the scene describes; each model has its own sections.", ModelNames(),
      [](Scene& x, const std::string& name) { x.model = ModelFromName(name); },
      [](const Scene& x) { return std::string(ToString(x.model)); }));
}

// [rotor]: model two_point's rigid rotor.
void RotorKeys(std::vector<KeySpec>& s) {
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
}

// [stator]: its elastically supported rigid stator.
void StatorKeys(std::vector<KeySpec>& s) {
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
}

// [contact] and [contact.friction_law]: the two contacts.
void ContactKeys(std::vector<KeySpec>& s) {
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
}

// [imbalance], [center_damper]: optional components; an absent section means none.
void ComponentKeys(std::vector<KeySpec>& s) {
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
}
// A number of [flexible]; one required in the section states "the rigid model" as its default
// (an absent section means the rigid model). `uniform` names the body whose uniform form it
// describes ("rotor", "stator"; "" for both forms): a key a listed body does not use.
void FlexibleNumber(std::vector<KeySpec>& s, const std::string& key, std::string unit, Rule rule,
                    std::string doc, Field<double> field, Presence presence,
                    const std::string& uniform = "") {
  s.push_back(Make<double>("flexible." + key, ValueType::kFloat, std::move(unit), rule, presence,
                           std::move(doc), field));
  if (presence == Presence::kRequiredInSection) s.back().default_text = "the rigid model";
  if (uniform.empty()) return;
  s.back().relevant = [uniform](const Scene& x) {
    return uniform == "rotor" ? x.flexible.RotorUniform() : x.flexible.StatorUniform();
  };
  s.back().irrelevant_reason = "[[flexible." + uniform + "_shaft]] lists the " + uniform +
                               "'s shaft, or [flexible.matrices] gives the whole structure";
}

// A key of the shafts (material, elements, stations): not one of a structure from matrices.
void NotWithMatrices(KeySpec& spec, std::function<bool(const Scene&)> relevant,
                     const std::string& reason) {
  spec.relevant = [relevant](const Scene& x) {
    return !x.flexible.matrices.enabled && (!relevant || relevant(x));
  };
  spec.irrelevant_reason = reason.empty() ? "[flexible.matrices] gives the whole structure"
                                          : reason + ", or [flexible.matrices] gives the whole "
                                                     "structure";
}

// [flexible] (level L4, optional; an absent section means the rigid model): the uniform shafts'
// sections and the material.
void FlexibleShaftKeys(std::vector<KeySpec>& s) {
  const Presence in_section = Presence::kRequiredInSection, optional = Presence::kOptional;
  FlexibleNumber(s, "rotor_outer_diameter", "m", Rule::kPositive,
                 "Outer diameter of the rotor's shaft across the contact span (a disk completes "
                 "the rotor to [rotor]'s mass, mass centre and inertia). Not with "
                 "[[flexible.rotor_shaft]].",
                 [](Scene& x) -> double& { return x.flexible.rotor_outer_diameter; }, in_section,
                 "rotor");
  FlexibleNumber(s, "rotor_inner_diameter", "m", Rule::kNonNegative,
                 "Its bore (0: solid); below rotor_outer_diameter.",
                 [](Scene& x) -> double& { return x.flexible.rotor_inner_diameter; }, optional,
                 "rotor");
  FlexibleNumber(s, "stator_outer_diameter", "m", Rule::kPositive,
                 "Outer diameter of the stator's tube across its span (a disk completes it to "
                 "[stator]'s mass, mass centre and inertia). Not with [[flexible.stator_shaft]].",
                 [](Scene& x) -> double& { return x.flexible.stator_outer_diameter; }, in_section,
                 "stator");
  FlexibleNumber(s, "stator_inner_diameter", "m", Rule::kNonNegative,
                 "Its bore; below stator_outer_diameter.",
                 [](Scene& x) -> double& { return x.flexible.stator_inner_diameter; }, in_section,
                 "stator");
  FlexibleNumber(s, "youngs_modulus", "Pa", Rule::kPositive,
                 "E of both shafts (of the listed segments that give none).",
                 [](Scene& x) -> double& { return x.flexible.youngs_modulus; }, in_section);
  FlexibleNumber(s, "shear_modulus", "Pa", Rule::kPositive,
                 "G of both shafts (of the listed segments that give none); the Poisson ratio "
                 "E/(2G) − 1 must lie in (−1, 0.5].",
                 [](Scene& x) -> double& { return x.flexible.shear_modulus; }, in_section);
  FlexibleNumber(s, "density", "kg/m³", Rule::kNonNegative,
                 "ρ of both shafts (of the listed segments that give none).",
                 [](Scene& x) -> double& { return x.flexible.density; }, in_section);
  for (std::size_t i = s.size() - 3; i < s.size(); ++i) NotWithMatrices(s[i], nullptr, "");
  s.push_back(Make<int, std::int64_t>(
      "flexible.elements", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "Timoshenko elements per uniform shaft (nodes are added at the mid-span, the mass "
      "centre and the disk).",
      [](Scene& x) -> int& { return x.flexible.elements; }));
  NotWithMatrices(
      s.back(),
      [](const Scene& x) { return !x.flexible.RotorListed() || !x.flexible.StatorListed(); },
      "both shafts are listed ([[flexible.rotor_shaft]], [[flexible.stator_shaft]])");
}

// A pair of integers bound to a std::array<int, 2> of the Scene (stations, coordinates).
KeySpec IntegerPair(std::string key, Rule rule, Presence presence, std::string doc,
                    std::function<std::array<int, 2>&(Scene&)> field) {
  KeySpec spec;
  spec.key = std::move(key);
  spec.type = ValueType::kIntegerPair;
  spec.unit = "-";
  spec.rule = rule;
  spec.presence = presence;
  spec.doc = std::move(doc);
  spec.set = [field](Scene& x, const Value& v) {
    const auto& pair = std::get<std::array<std::int64_t, 2>>(v);
    field(x) = {static_cast<int>(pair[0]), static_cast<int>(pair[1])};
  };
  spec.get = [field](const Scene& x) {
    const std::array<int, 2>& pair = field(const_cast<Scene&>(x));
    return Value(std::array<std::int64_t, 2>{pair[0], pair[1]});
  };
  return spec;
}

// [flexible]: the contact stations of the listed shafts.
void FlexibleStationKeys(std::vector<KeySpec>& s) {
  for (const std::string body : {"rotor", "stator"}) {
    KeySpec stations = IntegerPair(
        "flexible." + body + "_contact_stations", Rule::kStationPair, Presence::kOptional,
        "The stations of the listed " + body + " shaft at the left and right contacts.",
        [body](Scene& x) -> std::array<int, 2>& {
          return body == "rotor" ? x.flexible.rotor_contact_stations
                                 : x.flexible.stator_contact_stations;
        });
    stations.default_text = "the first and last stations";
    stations.relevant = [body](const Scene& x) {
      return body == "rotor" ? x.flexible.RotorListed() : x.flexible.StatorListed();
    };
    stations.irrelevant_reason = "stations number a listed shaft: add [[flexible." + body +
                                 "_shaft]] rows (with [flexible.matrices]: "
                                 "flexible.matrices." + body + "_contact_coordinates)";
    s.push_back(stations);
  }
}

// [flexible]: the Craig–Bampton reduction and what it keeps.
void FlexibleReductionKeys(std::vector<KeySpec>& s) {
  s.push_back(Make<int, std::int64_t>(
      "flexible.modes", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "Fixed-interface modes kept by the Craig–Bampton reduction (the contact displacements "
      "stay physical).",
      [](Scene& x) -> int& { return x.flexible.modes; }));
  FlexibleNumber(s, "modal_damping", "-", Rule::kNonNegative, "ζ of the kept modes.",
                 [](Scene& x) -> double& { return x.flexible.modal_damping; }, Presence::kOptional);
  s.push_back(Choice(
      "flexible.gyroscopic",
      "\"on\": the polar inertias' gyroscopic moments (−jωG u̇); \"off\": none, as the rigid "
      "model.",
      {"on", "off"}, [](Scene& x, const std::string& v) { x.flexible.gyroscopic = v == "on"; },
      [](const Scene& x) { return std::string(x.flexible.gyroscopic ? "on" : "off"); }));
}

// [flexible.matrices]: the whole flexible structure as an FE model's matrices in a file.
void FlexibleMatrixKeys(std::vector<KeySpec>& s) {
  s.push_back(Make<std::string>(
      "flexible.matrices.file", ValueType::kString, "", Rule::kText, Presence::kRequiredInSection,
      "The structure's matrices: an HDF5 file (`.h5`) with datasets `mass`, `damping`, "
      "`stiffness`, `gyroscopic` (n × n), or a directory with MatrixMarket files `mass.mtx`, "
      "`damping.mtx`, `stiffness.mtx`, `gyroscopic.mtx`; relative to the scene's directory "
      "(the resolved scene gives it absolute). One plane's real symmetric matrices of M ü + "
      "(C − jωG) u̇ + K u = f on complex coordinates (docs/levels/l4_flexible.md); "
      "`rubcont scene matrices` writes a scene's.",
      [](Scene& x) -> std::string& { return x.flexible.matrices.file; }));
  for (const std::string body : {"rotor", "stator"}) {
    s.push_back(IntegerPair(
        "flexible.matrices." + body + "_contact_coordinates", Rule::kCoordinatePair,
        Presence::kRequiredInSection,
        "The " + body + "'s displacement coordinates (rows of the matrices, from 0) at the left "
        "and right contacts.",
        [body](Scene& x) -> std::array<int, 2>& {
          return body == "rotor" ? x.flexible.matrices.rotor_contact_coordinates
                                 : x.flexible.matrices.stator_contact_coordinates;
        }));
  }
  s.push_back(Make<int, std::int64_t>(
      "flexible.matrices.imbalance_coordinate", ValueType::kInteger, "-", Rule::kStation,
      Presence::kOptional, "The displacement coordinate [imbalance]'s force acts on.",
      [](Scene& x) -> int& { return x.flexible.matrices.imbalance_coordinate; }));
  s.back().default_text = "the left rotor contact's";
  for (std::size_t i = s.size() - 4; i + 1 < s.size(); ++i) s[i].default_text = "the shafts'";
  for (std::size_t i = s.size() - 4; i < s.size(); ++i) {
    s[i].relevant = [](const Scene& x) { return x.flexible.matrices.enabled; };
    s[i].irrelevant_reason = "[flexible.matrices] is absent";
  }
}

// [jeffcott]: the single-contact model, in Black's and Crandall's symbols.
void JeffcottKeys(std::vector<KeySpec>& s) {
  const auto jeffcott = [&s](std::string key, std::string unit, Rule rule, std::string doc,
                             Field<double> field, Presence presence = Presence::kRequired) {
    s.push_back(Make<double>("jeffcott." + key, ValueType::kFloat, std::move(unit), rule,
                             presence, std::move(doc), field));
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
  s.push_back(Choice(
      "jeffcott.friction_law",
      "Friction law of the rotating waves: \"exact\" (stick/slip) or \"tanh\".", {"exact", "tanh"},
      [](Scene& x, const std::string& name) {
        x.jeffcott.friction_law.kind =
            name == "tanh" ? FrictionLawKind::kTanh : FrictionLawKind::kExact;
      },
      [](const Scene& x) {
        const bool tanh = x.jeffcott.friction_law.kind == FrictionLawKind::kTanh;
        return std::string(tanh ? "tanh" : "exact");
      }));
  jeffcott("velocity_scale", "m/s", Rule::kPositive,
           "ε of tanh(V/ε) (time marching, shooting, and rotating waves when friction_law = "
           "\"tanh\").",
           [](Scene& x) -> double& { return x.jeffcott.friction_law.velocity_scale; },
           Presence::kOptional);
}

// Textbook models (models/textbook.h): [<model>] with the model's coefficients and the range of
// its continuation parameter, [<model>.orbits] with the numerics of the "orbits" stage.

// A coefficient of a textbook model: <model>.<key>.
void TextbookNumber(std::vector<KeySpec>& s, ModelKind model, const std::string& key,
                    std::string doc, Field<double> field, Rule rule = Rule::kFinite,
                    Presence presence = Presence::kRequired) {
  s.push_back(Make<double>(std::string(ToString(model)) + "." + key, ValueType::kFloat, "-", rule,
                           presence, std::move(doc), field));
}

// <model>.<parameter>_range and [<model>.orbits], the parameter as its entry names it.
void TextbookOrbitsKeys(std::vector<KeySpec>& s, ModelKind model, std::string range_doc) {
  const std::string& parameter = ModelOf(model).parameter;
  s.push_back(Make<std::array<double, 2>>(
      std::string(ToString(model)) + "." + parameter + "_range", ValueType::kFloatPair, "-",
      Rule::kIncreasingPositive, Presence::kRequired, std::move(range_doc),
      [](Scene& x) -> std::array<double, 2>& { return x.orbits.parameter_range; }));
  const std::string prefix = std::string(ToString(model)) + ".orbits.";
  s.push_back(Make<double>(
      prefix + "start", ValueType::kFloat, "-", Rule::kPositive, Presence::kOptional,
      "Parameter of the first orbit; the branch is continued both ways from it to the ends "
      "of `" + parameter + "_range`.",
      [](Scene& x) -> double& { return x.orbits.start; }));
  s.back().default_text = "the low end of `" + parameter + "_range`";
  s.push_back(Make<int, std::int64_t>(
      prefix + "segments", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "Shooting segments: 1 single shooting, more for multiple shooting.",
      [](Scene& x) -> int& { return x.orbits.segments; }));
  s.push_back(Make<double>(
      prefix + "tolerance", ValueType::kFloat, "-", Rule::kOpenUnit, Presence::kOptional,
      "Integrator tolerance (relative = absolute, on scaled states) of every segment.",
      [](Scene& x) -> double& { return x.orbits.tolerance; }));
  s.push_back(Make<int, std::int64_t>(
      prefix + "max_steps", ValueType::kInteger, "-", Rule::kSteps, Presence::kOptional,
      "Continuation steps allowed each way from the start.",
      [](Scene& x) -> int& { return x.orbits.max_steps; }));
  s.push_back(Choice(
      prefix + "integrator",
      "\"model\" (the model's own: \"explicit\" for duffing and stuart_landau, \"bdf\" for the van "
      "der Pol oscillators), \"explicit\" (Fehlberg 8(7) under error control), \"bdf\" (CVODES BDF) "
      "or \"gauss\" (Gauss–Legendre collocation of order 8 on collocation_intervals per period, "
      "its state-transition matrix the exact derivative of the discrete map; the transient that "
      "finds the first orbit keeps the model's own). On the forced Duffing branch \"gauss\" with 40 "
      "intervals locates both folds to 4e-14 and 1.4e-13 of harmonic balance at a fifth of "
      "\"explicit\"'s CPU (bench/duffing_branch_bench.cpp).",
      {"model", "explicit", "bdf", "gauss"},
      [](Scene& x, const std::string& name) {
        x.orbits.integrator = name == "explicit" ? TextbookIntegrator::kExplicit
                              : name == "bdf"    ? TextbookIntegrator::kBdf
                              : name == "gauss"  ? TextbookIntegrator::kGauss
                                                 : TextbookIntegrator::kModel;
      },
      [](const Scene& x) { return std::string(ToString(x.orbits.integrator)); }));
  s.push_back(Make<int, std::int64_t>(
      prefix + "collocation_intervals", ValueType::kInteger, "-", Rule::kSteps, Presence::kOptional,
      "integrator = \"gauss\": mesh intervals per period, shared evenly by the segments (rounded "
      "up to a multiple of segments).",
      [](Scene& x) -> int& { return x.orbits.collocation_intervals; }));
}

// [duffing], [duffing.orbits].
void DuffingKeys(std::vector<KeySpec>& s) {
  const ModelKind duffing = ModelKind::kDuffing;
  TextbookNumber(s, duffing, "damping", "c of ẍ + c ẋ + k x + β x³ = F cos(w t).",
                 [](Scene& x) -> double& { return x.duffing.damping; }, Rule::kNonNegative);
  TextbookNumber(s, duffing, "stiffness", "k: linear stiffness.",
                 [](Scene& x) -> double& { return x.duffing.stiffness; });
  TextbookNumber(s, duffing, "cubic", "β: cubic stiffness (> 0 hardening).",
                 [](Scene& x) -> double& { return x.duffing.cubic; });
  TextbookNumber(s, duffing, "force", "F: forcing amplitude.",
                 [](Scene& x) -> double& { return x.duffing.force; });
  TextbookOrbitsKeys(
      s, duffing,
      "[low, high]: forcing frequency w, the continuation parameter (forcing period 2π/w).");
}

// [stuart_landau], [stuart_landau.orbits].
void StuartLandauKeys(std::vector<KeySpec>& s) {
  const ModelKind stuart_landau = ModelKind::kStuartLandau;
  TextbookNumber(s, stuart_landau, "omega",
                 "ω of ż = (λ + iω) z − (1 + iγ)|z|² z: linear frequency.",
                 [](Scene& x) -> double& { return x.stuart_landau.omega; });
  TextbookNumber(s, stuart_landau, "gamma",
                 "γ: amplitude–frequency coupling; the orbit turns at ω − γλ.",
                 [](Scene& x) -> double& { return x.stuart_landau.gamma; }, Rule::kFinite,
                 Presence::kOptional);
  TextbookOrbitsKeys(s, stuart_landau,
                     "[low, high]: growth rate λ, the continuation parameter (the orbit r = √λ "
                     "exists for λ > 0; Hopf point at 0).");
}

// [forced_van_der_pol], [forced_van_der_pol.orbits].
void ForcedVanDerPolKeys(std::vector<KeySpec>& s) {
  const ModelKind forced = ModelKind::kForcedVanDerPol;
  TextbookNumber(s, forced, "mu", "μ of ẍ − μ (1 − x²) ẋ + x = F cos(w t): nonlinear damping.",
                 [](Scene& x) -> double& { return x.forced_van_der_pol.mu; });
  TextbookNumber(s, forced, "force", "F: forcing amplitude.",
                 [](Scene& x) -> double& { return x.forced_van_der_pol.force; });
  TextbookOrbitsKeys(s, forced,
                     "[low, high]: forcing frequency w, the continuation parameter (forcing "
                     "period 2π/w); the free cycle turns at about 1.");
}

// [van_der_pol]: the range of μ, its only coefficient; [van_der_pol.orbits].
void VanDerPolKeys(std::vector<KeySpec>& s) {
  TextbookOrbitsKeys(s, ModelKind::kVanDerPol,
                     "[low, high]: μ of ẍ − μ (1 − x²) ẋ + x = 0, the continuation parameter "
                     "(relaxation oscillations for μ ≫ 1: use several segments).");
}

// [analysis] stages: what `rubcont run` computes, in the order given (each model's default
// stages are its registry entry's).
void StagesKey(std::vector<KeySpec>& s) {
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
               "speed-down sweeps of [analysis.sweep]), \"loop\" (the hysteresis loop explained: "
               "every jump of a run with [analysis.sweep]'s schedule, its cause and how sure; L1 "
               "first, L3 where it must; [analysis.loop]) — model two_point.";
  stages.default_text = "`[\"analytic\", \"branches\"]`; `[\"orbits\"]` for the textbook models";
  stages.choices = kImplementedStages;
  stages.set = [](Scene& x, const Value& v) {
    x.analysis.stages.clear();
    for (const std::string& name : std::get<std::vector<std::string>>(v)) {
      if (name == "analytic") x.analysis.stages.push_back(Stage::kAnalytic);
      if (name == "sweep") x.analysis.stages.push_back(Stage::kSweep);
      if (name == "branches") x.analysis.stages.push_back(Stage::kBranches);
      if (name == "orbits") x.analysis.stages.push_back(Stage::kOrbits);
      if (name == "tori") x.analysis.stages.push_back(Stage::kTori);
      if (name == "loop") x.analysis.stages.push_back(Stage::kLoop);
    }
  };
  stages.get = [](const Scene& x) {
    std::vector<std::string> names;
    for (Stage stage : x.analysis.stages) names.push_back(ToString(stage));
    return Value(names);
  };
  s.push_back(stages);
}

// [analysis]: the analytic grid (the library's AnalyticOptions, held as such in the scene) and
// the speed range of the continuation branches.
void AnalysisRangeKeys(std::vector<KeySpec>& s) {
  KeySpec range;
  range.key = "analysis.precession_range_hz";
  range.type = ValueType::kFloatPair;
  range.unit = "Hz";
  range.rule = Rule::kIncreasingPositive;
  range.presence = Presence::kOptional;
  range.doc = "[low, high]: precession-frequency range of the analytic curves.";
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
  s.push_back(Make<int, std::int64_t>(
      "analysis.precession_points", ValueType::kInteger, "-", Rule::kGridPoints,
      Presence::kOptional,
      "Grid points of the analytic curves; transitions are located to machine precision between "
      "them.",
      [](Scene& x) -> int& { return x.analysis.analytic.precession_points; }));
  s.push_back(Make<std::array<double, 2>>(
      "analysis.speed_range_rpm", ValueType::kFloatPair, "rpm", Rule::kIncreasingPositive,
      Presence::kOptional,
      "[low, high]: running-speed range of the continuation branches.",
      [](Scene& x) -> std::array<double, 2>& { return x.analysis.speed_range_rpm; }));
}

// [analysis.sweep]: the time-marching sweeps (level L3, Kumar 2010 §3.5; sweeps/rub_sweep.h).
// Every key is optional.
void SweepRange(std::vector<KeySpec>& s, const char* key, const char* doc,
                Field<std::array<double, 2>> field) {
  s.push_back(Make<std::array<double, 2>>(key, ValueType::kFloatPair, "rpm",
                                          Rule::kIncreasingPositive, Presence::kOptional, doc,
                                          field));
}
void SweepNumber(std::vector<KeySpec>& s, const char* key, const char* unit, Rule rule,
                 const char* doc, Field<double> field) {
  s.push_back(Float(key, unit, rule, doc, field, Presence::kOptional));
}
// A rule that only classifies finished speeds (KeySpec::reclassifies).
void SweepRule(std::vector<KeySpec>& s, const char* key, const char* unit, Rule rule,
               const char* doc, Field<double> field) {
  SweepNumber(s, key, unit, rule, doc, field);
  s.back().reclassifies = true;
}

// [analysis.sweep]: the speeds, the settle test and the analysed signals.
void SweepScheduleKeys(std::vector<KeySpec>& s) {
  SweepRange(s, "analysis.sweep.up_range_rpm",
             "[low, high]: the speed-up sweep runs from low to high.",
             [](Scene& x) -> std::array<double, 2>& { return x.analysis.sweep.up_range_rpm; });
  SweepRange(s, "analysis.sweep.down_range_rpm",
             "[low, high]: the speed-down sweep runs from high to low.",
             [](Scene& x) -> std::array<double, 2>& { return x.analysis.sweep.down_range_rpm; });
  SweepNumber(s, "analysis.sweep.speed_step_rpm", "rpm", Rule::kPositive,
              "Speed step; each speed continues from the state the previous one ended in.",
              [](Scene& x) -> double& { return x.analysis.sweep.speed_step_rpm; });
  SweepNumber(s, "analysis.sweep.dwell", "s", Rule::kPositive,
              "Longest simulated time per speed (whole settle windows); ≥ (settle_windows + 1)·"
              "settle_window.", [](Scene& x) -> double& { return x.analysis.sweep.dwell; });
  SweepNumber(s, "analysis.sweep.settle_window", "s", Rule::kPositive,
              "Window length of the settle test: successive windows are compared.",
              [](Scene& x) -> double& { return x.analysis.sweep.settle_window; });
  s.push_back(Make<int, std::int64_t>(
      "analysis.sweep.settle_windows", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "A speed has settled when this many successive window pairs agree (spectra and dominant "
      "frequencies); else it runs to the dwell and is flagged.",
      [](Scene& x) -> int& { return x.analysis.sweep.settle_windows; }));
  SweepNumber(s, "analysis.sweep.spectrum_tolerance", "-", Rule::kOpenUnit,
              "Agreeing windows: relative L2 distance of their two-sided amplitude spectra.",
              [](Scene& x) -> double& { return x.analysis.sweep.spectrum_tolerance; });
  SweepNumber(s, "analysis.sweep.frequency_tolerance_hz", "Hz", Rule::kPositive,
              "Agreeing windows: change of each contact's dominant (BP) frequency.",
              [](Scene& x) -> double& { return x.analysis.sweep.frequency_tolerance_hz; });
  SweepNumber(s, "analysis.sweep.analysis_length", "s", Rule::kPositive,
              "The last stretch of each speed that is analysed (spectrum, BP, slip velocity); "
              "≤ (settle_windows + 1)·settle_window.",
              [](Scene& x) -> double& { return x.analysis.sweep.analysis_length; });
  SweepNumber(s, "analysis.sweep.sample_rate_hz", "Hz", Rule::kPositive,
              "Sampling rate of the analysed signals (dense output of the integrator).",
              [](Scene& x) -> double& { return x.analysis.sweep.sample_rate_hz; });
  SweepNumber(s, "analysis.sweep.spectrum_max_hz", "Hz", Rule::kPositive,
              "Spectra are stored for −this … +this (the waterfall); ≤ sample_rate_hz/2.",
              [](Scene& x) -> double& { return x.analysis.sweep.spectrum_max_hz; });
  SweepNumber(s, "analysis.sweep.impulse", "N·s", Rule::kNonNegative,
              "Impulse on the rotor at its mass-centre plane along +x at the start of each "
              "direction (rotor centred and at rest): a translation at impulse/m_r.",
              [](Scene& x) -> double& { return x.analysis.sweep.impulse; });
}

// [analysis.sweep]: the integrator.
void SweepIntegratorKeys(std::vector<KeySpec>& s) {
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
  SweepNumber(s, "analysis.sweep.relative_tolerance", "-", Rule::kOpenUnit,
              "CVODES BDF (order ≤ 2, analytic Jacobian): relative local error tolerance.",
              [](Scene& x) -> double& { return x.analysis.sweep.relative_tolerance; });
  SweepNumber(s, "analysis.sweep.absolute_tolerance", "-", Rule::kOpenUnit,
              "Absolute tolerance, in units of each state's scale (clearance; clearance × the "
              "fastest support frequency).",
              [](Scene& x) -> double& { return x.analysis.sweep.absolute_tolerance; });
  SweepNumber(s, "analysis.sweep.explicit_tolerance", "-", Rule::kOpenUnit,
              "rtol = atol (scaled states) of Dormand–Prince where integrator is \"explicit\" or "
              "\"auto\". An explicit pair at its stability limit keeps up contact chatter that has "
              "died out unless the tolerance is tight: measured on A(a) from 20 rpm, chatter to "
              "32 rpm at 1e-7, none from 24 rpm at 1e-8 (as BDF and ERK at 1e-9).",
              [](Scene& x) -> double& { return x.analysis.sweep.explicit_tolerance; });
}

// [analysis.sweep]: the regime and jump rules (sweeps/rub_sweep.h RubRegimeOptions).
void SweepRuleKeys(std::vector<KeySpec>& s) {
  SweepRule(s, "analysis.sweep.rolling_slip_tolerance", "-", Rule::kOpenUnit,
            "A contact whirls (rolls) when its mean slip velocity in contact |V| ≤ this·R·ω (the "
            "surface speed) or ≤ rolling_micro_slip·velocity_scale, and its BP passes the "
            "whirl_tolerance check; otherwise it whips (slips).",
            [](Scene& x) -> double& { return x.analysis.sweep.rolling_slip_tolerance; });
  SweepRule(s, "analysis.sweep.rolling_micro_slip", "-", Rule::kNonNegative,
            "The tanh law's micro-slip of rolling, in units of velocity_scale ε (V = "
            "ε·atanh(μ_req/μ) ≤ ε while μ_req ≤ 0.76 μ): |V| up to this·ε counts as rolling at "
            "any speed. 0: the surface-speed rule alone.",
            [](Scene& x) -> double& { return x.analysis.sweep.rolling_micro_slip; });
  SweepRule(s, "analysis.sweep.whirl_tolerance", "-", Rule::kOpenUnit,
            "The frequency check of a rolling contact: |BP − f_roll| ≤ this·f_roll, f_roll = "
            "RCI·(speed in rev/s).",
            [](Scene& x) -> double& { return x.analysis.sweep.whirl_tolerance; });
  SweepRule(s, "analysis.sweep.frequency_jump_hz", "Hz", Rule::kPositive,
            "Between successive speeds, a BP change larger than this from both trends (BP "
            "constant, BP ∝ speed) is a jump even when the regime stays the same.",
            [](Scene& x) -> double& { return x.analysis.sweep.frequency_jump_hz; });
  SweepRule(s, "analysis.sweep.max_penetration", "-", Rule::kPositive,
            "A speed whose largest penetration at a contact passes this share of its clearance "
            "is untrusted (the contact laws are those of a small overlap; an integration that lets "
            "the rotor sink into the stator): its regime is still read, the file says why, and "
            "its jumps are marked. The orbits stage marks its orbits by the same rule.",
            [](Scene& x) -> double& { return x.analysis.sweep.max_penetration; });
}

// [analysis.orbits]: the modulated whirl and whip of model two_point (level L2,
// shooting/rub_orbits.h).
void RubOrbitsKeys(std::vector<KeySpec>& s) {
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
  s.push_back(Switch(
      "analysis.orbits.branch_points",
      "\"follow\": the other branch through each located branch point of a family is followed "
      "(one of the two mirror images where the point breaks a left–right symmetric rotor's "
      "symmetry), and the period-doubled orbits from each period doubling where the family loses "
      "or gains stability; \"mark\": located and reported only.",
      {"follow", "mark"}, "follow",
      [](Scene& x) -> bool& { return x.analysis.orbits.follow_branch_points; }));
  s.push_back(Switch(
      "analysis.orbits.at_grazing",
      "\"continue\": a family goes on past a located grazing (where a contact starts to open: the "
      "fixed Gauss mesh then creeps in shrinking steps, A(a) 87 orbits and 640 s of CPU past "
      "132.5 rpm to a corrector failure); \"stop\": each family, side branches included, ends at "
      "its first located grazing with the status \"ended at a grazing\" (not a failure; the "
      "grazing orbit is its last; docs/levels/l2_orbits_tori.md).",
      {"continue", "stop"}, "stop",
      [](Scene& x) -> bool& { return x.analysis.orbits.stop_at_grazing; }));
  s.back().added_at_older_behaviour = true;
  s.push_back(Switch(
      "analysis.orbits.predictor",
      "Where the continuation's corrector starts each orbit: \"tangent\", along the family's "
      "tangent; \"curved\", on the parabola through the previous orbit tangent to the family at "
      "the last (an error of third order in the step instead of second: fewer Newton iterations "
      "and longer steps; A(a)'s whip family from its Hopf point to its grazing in 59 orbits and "
      "0.17 of the CPU, docs/performance.md). The landmarks are located to the same tolerances "
      "either way, but the steps differ and with them the sampled ones (grazing).",
      {"tangent", "curved"}, "curved",
      [](Scene& x) -> bool& { return x.analysis.orbits.curved_predictor; }));
  s.back().added_at_older_behaviour = true;
  s.push_back(Switch(
      "analysis.orbits.mesh",
      "Gauss collocation's mesh: \"uniform\", collocation_intervals equal steps per period; "
      "\"adapted\", the same number of steps moved at every third orbit to equidistribute the "
      "collocation error's monitor (AUTO-07p's adaptation): steps shorten where the orbit changes "
      "fast (A(a)'s period doubling at 400 intervals 0.001–0.004 rpm from the 1600-interval "
      "uniform mesh's in two runs, where the uniform 400 are 0.03 rpm off; docs/performance.md).",
      {"uniform", "adapted"}, "adapted",
      [](Scene& x) -> bool& { return x.analysis.orbits.adapt_mesh; }));
  s.back().added_at_older_behaviour = true;
  s.push_back(Switch(
      "analysis.orbits.defect_check",
      "\"on\": every orbit of every family (and every special point) is integrated again over its "
      "period by an explicit Dormand–Prince 5(4) at 1e-12 and its periodicity defect stored "
      "(measure \"defect\"; the summary notes one above 1e-5: the mesh does not resolve the "
      "orbit) — 3 % of the CPU of A(a)'s whip family to its grazing (one run, "
      "docs/performance.md); \"off\": no such check, the continuation's own work (AUTO-07p's).",
      {"off", "on"}, "on", [](Scene& x) -> bool& { return x.analysis.orbits.defect_check; }));
  s.back().added_at_older_behaviour = true;
}

// [analysis.orbits.transient]: the orbits through the orbit a settled transient lies on.
void RubOrbitsTransientKeys(std::vector<KeySpec>& s) {
  s.push_back(Float(
      "analysis.orbits.transient.speed_rpm", "rpm", Rule::kPositive,
      "Running speed of the transient: one speed of the scene's sweep model "
      "([analysis.sweep]: integrator, windows, impulse) run from rest and the impulse "
      "for `seconds`; the relative periodic orbit it settles on (of `laps` modulation "
      "periods) is solved there and its family continued towards lower and higher "
      "speed over speed_range_rpm with [analysis.orbits]' shooting (by the stage \"orbits\", "
      "and by the stage \"tori\" for the tori from its Neimark–Sacker points); inside "
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
  s.push_back(Float(
      "analysis.orbits.transient.search_seconds", "s", Rule::kPositive,
      "How long the settled transient runs on, with the sweep's integrator, before its orbit is "
      "shot: the state at the end is Newton's first guess, the stretch's dominant line of the slip "
      "velocity its modulation period. A whip that settles by the windows' measure while still "
      "drawing in needs longer (C(a) at 75 rpm, the orbit locked at 3:7: 4 s).",
      [](Scene& x) -> double& { return x.analysis.orbits.transient.search_seconds; },
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

}

// [analysis.tori]: the whips modulated at two frequencies (level L2, shooting/rub_tori.h).
void ToriKeys(std::vector<KeySpec>& s) {
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.harmonics", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "K: Fourier harmonics of each torus's invariant circle (2K + 1 points, each integrated over "
      "one modulation period with [analysis.orbits]' integrator and mesh).",
      [](Scene& x) -> int& { return x.analysis.tori.harmonics; }));
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.max_harmonics", ValueType::kInteger, "-", Rule::kCountOrNone,
      Presence::kOptional,
      "Convergence in K along each family: while 2K stays within this, a circle whose Fourier "
      "tail reaches 1e-4 is solved again with 2K harmonics (from its points mapped three times "
      "by the torus's map, ten where Newton fails from there) and the family goes on at 2K from "
      "it; at the finest K the tail's bound is max_fourier_tail again (breakdown, locking). 0: "
      "`harmonics` throughout. The circles are written at the finest K, each torus's own K in "
      "the column `harmonics` (shooting/torus_branches.h).",
      [](Scene& x) -> int& { return x.analysis.tori.max_harmonics; }));
  s.back().added_at_older_behaviour = true;
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
  s.push_back(Switch(
      "analysis.tori.neimark_sacker",
      "\"follow\": the tori born at the Neimark–Sacker points of the modulated orbits of "
      "[analysis.orbits] — the Hopf points' families, and the family through the orbit of "
      "[analysis.orbits.transient] where that is given (C(b)'s whip at 53 rpm, "
      "scenes/thesis_C_b_tori_53.toml); \"skip\": no modulated orbits and none of those tori — "
      "only the tori of [analysis.tori.transient], which must then be given.",
      {"follow", "skip"}, "follow",
      [](Scene& x) -> bool& { return x.analysis.tori.from_neimark_sacker; }));
  s.push_back(Switch(
      "analysis.tori.coordinates",
      "The coordinates of each torus's circle: \"state\", the Fourier series in the state; "
      "\"chart\", in the contact chart — each contact's gap |d| − C, angle and their rates as "
      "coordinates of their own (shooting/invariant_circle.h) — with the transient's first "
      "circle solved by Gauss collocation on [analysis.orbits]' mesh instead of CVODES BDF. For "
      "contacts pressed by nanometres: C(c) at 64 rpm, K = 8, the state's circle met a singular "
      "Jacobian, the chart's converged in 3 Newton iterations (CVODES BDF stalled at |F| ≈ 2e-4; "
      "tests/shooting/modulated_orbit_test.cpp).",
      {"state", "chart"}, "chart",
      [](Scene& x) -> bool& { return x.analysis.tori.contact_chart; }));
  s.back().added_at_older_behaviour = true;
  s.push_back(Switch(
      "analysis.tori.centre_orbits",
      "Where a torus family shrinks onto a periodic orbit (its end at a Neimark–Sacker point of "
      "that orbit), the orbit is solved through the last circle's centre and continued in the "
      "direction the family moved: \"follow\", on over speed_range_rpm to its own end (the whip "
      "a supercritical point hands the motion to: its stability, special points and a contact's "
      "lift-off located, [analysis.orbits]' engine and max_steps); \"to_point\", only until the "
      "Neimark–Sacker point is located.",
      {"follow", "to_point"}, "follow",
      [](Scene& x) -> bool& { return x.analysis.tori.centre_orbits_onward; }));
}

// [analysis.loop]: the loop study (studies/loop.h). Every key is optional.
void LoopKeys(std::vector<KeySpec>& s) {
  s.push_back(Float("analysis.loop.budget", "G work units", Rule::kPositive,
                    "The work of the whole loop (the waves and the run first, then the jumps they "
                    "leave open, the principal ones first), in G work units: one unit is one "
                    "explicit step of one state (a BDF step 4, a Gauss step 100), the same on "
                    "every machine and under any load; A(a)'s loop costs about 80 s of CPU per G "
                    "on the 2-core machine here. `rubcont loop --budget` overrides it.",
                    [](Scene& x) -> double& { return x.analysis.loop.budget; }, Presence::kOptional));
  s.push_back(Float("analysis.loop.target_width_rpm", "rpm", Rule::kPositive,
                    "A jump by chance (a chaotic whip's end) is measured until the 95 % interval "
                    "of the median speed a run leaves at is at most this wide.",
                    [](Scene& x) -> double& { return x.analysis.loop.target_width_rpm; },
                    Presence::kOptional));
  s.push_back(Make<int, std::int64_t>(
      "analysis.loop.copies", ValueType::kInteger, "-", Rule::kCount, Presence::kOptional,
      "Copies per ensemble of the escape design (sweeps/escape_design.h).",
      [](Scene& x) -> int& { return x.analysis.loop.copies; }));
  s.push_back(Float("analysis.loop.max_copy_seconds", "s", Rule::kPositive,
                    "The longest simulated time of one copy (where escape rates are small).",
                    [](Scene& x) -> double& { return x.analysis.loop.max_copy_seconds; },
                    Presence::kOptional));
}

// [analysis.tori.transient]: the tori through the torus a settled transient lies on.
void ToriTransientKeys(std::vector<KeySpec>& s) {
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
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.transient.max_harmonics", ValueType::kInteger, "-", Rule::kCountOrNone,
      Presence::kOptional,
      "Convergence in K: the transient's torus, solved with `harmonics`, is solved again with "
      "twice as many (from the solved circle's points mapped three times by the torus's map, "
      "ten where Newton fails from there; Newton damped) while its "
      "Fourier tail exceeds 1e-4 and 2K stays within this; each K's ρ, tail and invariance "
      "error in the summary. 0: `harmonics` only. Its families start with the finest K solved "
      "and are refined on along the way as analysis.tori.max_harmonics says, up to this.",
      [](Scene& x) -> int& { return x.analysis.tori.transient.max_harmonics; }));
  s.back().added_at_older_behaviour = true;
  s.push_back(Make<int, std::int64_t>(
      "analysis.tori.transient.laps", ValueType::kInteger, "-", Rule::kCountOrNone,
      Presence::kOptional,
      "Modulation periods per section of the transient's torus, at most 64; 0: chosen from the "
      "transient's points (one period, else the m periods their sequence's strongest line "
      "names, ≈ p/m). Where one-period points are no circle and name nothing, give m: C(b) at "
      "54.5 rpm cuts a one-period section twice (2).",
      [](Scene& x) -> int& { return x.analysis.tori.transient.laps; }));
  s.back().added_at_older_behaviour = true;
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
}

// ---------------------------------------------------------------------------------------------
// The table arrays of [flexible]: the listed shafts, their disks and the stator's supports.

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

// [[flexible.<body>_shaft]]: a listed shaft's segments.
TableArraySpec ShaftRows(const std::string& body) {
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
  return shaft;
}

// [[flexible.<body>_disks]]: the disks on a listed shaft's stations.
TableArraySpec DiskRows(const std::string& body) {
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
  return disks;
}

// [[flexible.<body>_supports]]: springs and dashpots from a listed shaft's stations to ground.
TableArraySpec SupportRows(const std::string& body) {
  const auto support_rows = [body](Scene& x) -> std::vector<SupportRow>& {
    return body == "rotor" ? x.flexible.rotor_supports : x.flexible.stator_supports;
  };
  TableArraySpec supports;
  supports.path = "flexible." + body + "_supports";
  supports.doc =
      body == "rotor"
          ? "A bearing: a spring and dashpot from a station of the listed rotor shaft to ground "
            "(isotropic, as `rubcont scene import-ross` brings a ROSS rotor's). The rigid model's "
            "rotor has none: a scene with them has no stage \"analytic\" (L0)."
          : "A spring and dashpot from a station of the listed stator shaft to ground. The "
            "rigid model holds its stator at the contacts: supports go on contact stations, "
            "and give [stator]'s stiffness and damping.";
  supports.keys = {
      RowKey("station", ValueType::kInteger, "-", Rule::kStation, "",
             body == "rotor" ? "Its station." : "A contact station."),
      RowKey("stiffness", ValueType::kFloat, "N/m", Rule::kNonNegative, "", "k."),
      RowKey("damping", ValueType::kFloat, "N·s/m", Rule::kNonNegative, "`0.0`", "c."),
  };
  supports.set = [support_rows](Scene& x, const Rows& given) {
    std::vector<SupportRow>& out = support_rows(x);
    out.clear();
    for (const Row& r : given) {
      out.push_back({static_cast<int>(RowNumber(r, "station", 0.0)), RowNumber(r, "stiffness", 0.0),
                     RowNumber(r, "damping", 0.0)});
    }
  };
  supports.get = [support_rows](const Scene& x) {
    Rows out;
    for (const SupportRow& r : support_rows(const_cast<Scene&>(x))) {
      out.push_back({{"station", std::int64_t{r.station}}, {"stiffness", r.stiffness},
                     {"damping", r.damping}});
    }
    return out;
  };
  return supports;
}

std::vector<TableArraySpec> BuildTableArrays() {
  return {ShaftRows("rotor"), DiskRows("rotor"), SupportRows("rotor"), ShaftRows("stator"),
          DiskRows("stator"), SupportRows("stator")};
}

std::vector<KeySpec> BuildSchema() {
  std::vector<KeySpec> s;
  TopLevelKeys(s);
  RotorKeys(s);
  StatorKeys(s);
  ContactKeys(s);
  ComponentKeys(s);
  FlexibleShaftKeys(s);
  FlexibleStationKeys(s);
  FlexibleReductionKeys(s);
  FlexibleMatrixKeys(s);
  JeffcottKeys(s);
  DuffingKeys(s);
  StuartLandauKeys(s);
  ForcedVanDerPolKeys(s);
  VanDerPolKeys(s);
  StagesKey(s);
  AnalysisRangeKeys(s);
  SweepScheduleKeys(s);
  SweepIntegratorKeys(s);
  SweepRuleKeys(s);
  RubOrbitsKeys(s);
  RubOrbitsTransientKeys(s);
  ToriKeys(s);
  LoopKeys(s);
  ToriTransientKeys(s);
  // Every default is the initializer of its Scene field (and the structs inside it): written once.
  const Scene defaults;
  for (KeySpec& spec : s)
    if (spec.presence != Presence::kRequired) spec.default_value = spec.get(defaults);
  return s;
}

}  // namespace

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

const std::vector<TableArraySpec>& TableArrays() {
  static const std::vector<TableArraySpec> arrays = BuildTableArrays();
  return arrays;
}

const TableArraySpec* FindTableArray(const std::string& path) {
  for (const TableArraySpec& spec : TableArrays())
    if (spec.path == path) return &spec;
  return nullptr;
}

std::string LastComponent(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::string Parent(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

bool OfModel(const KeySpec& spec, const Scene& scene) {
  return ModelOf(scene).HasSection(spec.Section());
}

bool RunsStage(const Scene& scene, Stage stage) {
  const std::vector<Stage>& stages = scene.analysis.stages;
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

bool IsOptionalSubsection(const std::string& section) {
  return section == "analysis.tori.transient" || section == "analysis.orbits.transient" ||
         section == "flexible.matrices";
}

bool IsToriKey(const KeySpec& spec) {
  const std::string section = spec.Section();
  return section == "analysis.tori" || section.rfind("analysis.tori.", 0) == 0;
}

}  // namespace rubcont::schema

namespace rubcont {

using namespace schema;

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

bool AddedAtOlderBehaviour(const std::string& key) {
  for (const KeySpec& spec : Schema())
    if (spec.key == key) return spec.added_at_older_behaviour;
  return false;
}

}  // namespace rubcont
