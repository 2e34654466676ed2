#include "apps/scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "apps/hdf5_file.h"
#include "apps/models.h"
#include "apps/scene_schema.h"
#include "apps/version.h"

// Formatting of the scene: values as TOML literals (for the resolved scene and the loader's
// messages), the resolved scene, `rubcont scene check`'s listing and the key reference.

namespace rubcont::schema {

// TOML literal: the shortest text that reads back as the same double. For people (`human`):
// 10 significant digits, exponent notation for large and small magnitudes (1.75e+11).
std::string FormatFloat(double x, bool human) {
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

std::string FormatValue(const Value& value, bool human) {
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

std::string JoinQuoted(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + Quote(names[i]);
  return out;
}

std::string TypeName(const KeySpec& spec) {
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

namespace {

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
    case Rule::kCoordinatePair: return fmt::format("each 0 … {}", kMaxStation);
  }
  return "";
}

// Whether a key belongs in the resolved scene: every key of its model, but [flexible] only when the
// scene has it (its absence, not its defaults, means the rigid model), and [analysis.tori] only
// when the scene runs the stage "tori" (the results of every other scene stay as they were).
bool Resolved(const KeySpec& spec, const Scene& scene) {
  return OfModel(spec, scene) && (spec.Section() != "flexible" || scene.flexible.enabled) &&
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
    if (Parent(spec.path) != section || !ModelOf(scene).HasSection(section)) continue;
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
}  // namespace rubcont::schema

namespace rubcont {

using namespace schema;

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
    if (!ModelOf(scene).HasSection(Parent(spec.path))) continue;
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
  writer.SetAttribute("/", "rubcont_git", GitDescribe());
  writer.SetAttribute("/", "scene_name", scene.name);
  writer.SetAttribute("/", "scene_toml", ResolvedSceneToml(scene));
}

}  // namespace rubcont
