// The scene schema, shared by the three files of the scene (apps/scene.h is their API):
//   apps/scene_schema.cpp  the rows: one KeySpec per key, one TableArraySpec per [[table array]],
//                          built section by section, with the queries on them;
//   apps/scene.cpp         the loader: reads a TOML file against the rows, checks the rules that
//                          tie keys together, and reports every problem at once;
//   apps/scene_format.cpp  values as TOML literals, the resolved scene, `rubcont scene check`'s
//                          listing and the key reference (`rubcont scene keys`).
// Which model a section belongs to is the model registry's (ModelEntry::sections,
// apps/models.h): the rows say nothing of models.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include <toml++/toml.h>

#include "apps/scene.h"

namespace rubcont::schema {

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
  kCoordinatePair,        // integer pair, each 0 … kMaxStation (coordinates of a matrix file)
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

constexpr int kMaxLaps = 64;  // ModulatedOrbitOptions::laps

// The stages a scene may list, as it names them.
inline const std::vector<std::string> kImplementedStages = {"analytic", "branches", "orbits",
                                                            "tori", "sweep", "loop"};

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
  // [analysis.sweep] keys that only classify finished speeds (the regime and jump rules of
  // sweeps/rub_sweep.h): a sweep file with other values holds the same integrations.
  bool reclassifies = false;
  // Added after results were committed, with a default that keeps what runs did before it: a
  // stored scene that leaves it to its default describes the same run (AddedAtOlderBehaviour).
  bool added_at_older_behaviour = false;
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

// A table array ([[path]]): a list of rows, as rotordynamics input lists shaft segments, disks and
// supports. Each row key is a KeySpec (type, unit, rule, required or default, doc; its set and get
// unused: the table array's own). `set` stores the rows read — each the keys it gives — after
// every plain key, so a row's default may be a [flexible] key; `get` gives the rows back with every
// key resolved (ResolvedSceneToml).
using Row = std::map<std::string, Value>;

struct TableArraySpec {
  std::string path;  // "flexible.rotor_shaft"
  std::string doc;   // what one row is
  std::vector<KeySpec> keys;
  std::function<void(Scene&, const std::vector<Row>&)> set;
  std::function<std::vector<Row>(const Scene&)> get;
};

// The rows, in the order the documentation and the resolved scene list them (scene_schema.cpp).
const std::vector<KeySpec>& Schema();
const std::vector<TableArraySpec>& TableArrays();
// Sections in schema order ("" is the top level; every prefix of a section is one).
std::vector<std::string> Sections();
bool IsSection(const std::string& path);
const KeySpec* FindKey(const std::string& path);         // null: no such key
const TableArraySpec* FindTableArray(const std::string& path);

// "rotor.mass" → "mass" and "rotor".
std::string LastComponent(const std::string& path);
std::string Parent(const std::string& path);

// Whether the scene's model has the key's section (the registry's ModelEntry::HasSection).
bool OfModel(const KeySpec& spec, const Scene& scene);
bool RunsStage(const Scene& scene, Stage stage);
// Sub-tables whose absence means "not computed", not "computed with the defaults": their keys are
// resolved only when the table is given.
bool IsOptionalSubsection(const std::string& section);
// A key of [analysis.tori] or of its sub-table [analysis.tori.transient].
bool IsToriKey(const KeySpec& spec);

// Values as text (scene_format.cpp). A float as the shortest TOML literal that reads back as the
// same double; for people (`human`): 10 significant digits, exponent notation for large and small
// magnitudes (1.75e+11).
std::string FormatFloat(double x, bool human = false);
std::string Quote(const std::string& text);  // a TOML basic string, escaped
std::string FormatValue(const Value& value, bool human = false);
// A value of the file as the user would write it back (the shortest round-trip for floats).
std::string FormatNode(const toml::node& node);
std::string UnitSuffix(const KeySpec& spec);                  // " (kg)", or "" without a unit
std::string JoinQuoted(const std::vector<std::string>& names);  // "a", "b"
std::string TypeName(const KeySpec& spec);                    // "a number", "an integer", …

}  // namespace rubcont::schema
