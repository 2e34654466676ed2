// The scene loader: a TOML file read against the schema (apps/scene_schema.h), the rules that tie
// keys together checked, every problem reported at once (SceneError).
#include "apps/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "apps/models.h"
#include "apps/scene_schema.h"
#include "apps/structure_file.h"
#include "sweeps/escape_design.h"

namespace rubcont {
namespace {

using namespace schema;

// ---------------------------------------------------------------------------------------------
// Rules.

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
    case Rule::kCoordinatePair: {
      const auto& pair = std::get<std::array<std::int64_t, 2>>(value);
      for (std::int64_t n : pair)
        if (n < 0 || n > kMaxStation) return fmt::format("each must be from 0 to {}", kMaxStation);
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
    // Which form [flexible] takes decides which of its keys apply (KeySpec::relevant).
    scene.flexible.matrices.enabled = ModelOf(scene).HasSection("flexible") &&
                                      present_sections_.count("flexible.matrices") > 0;

    for (const KeySpec& spec : Schema()) {
      if (!OfModel(spec, scene)) {
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
        ModelOf(scene).HasSection("flexible") && present_sections_.count("flexible") > 0;
    scene.analysis.tori.transient.enabled = present_sections_.count("analysis.tori.transient") > 0;
    scene.analysis.orbits.transient.enabled =
        present_sections_.count("analysis.orbits.transient") > 0;
    if (scene.flexible.enabled && problems_.empty()) CheckFlexible(scene);
    if (problems_.empty()) CheckSweep(scene);
    if (problems_.empty()) CheckOrbits(scene);
    if (problems_.empty()) CheckTori(scene);
    if (problems_.empty()) CheckLoop(scene);
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
      if (!ModelOf(scene).HasSection(Parent(spec.path))) {
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
    const std::string supports = "flexible." + body + "_supports";
    const std::vector<SupportRow>& support_rows = rotor ? f.rotor_supports : f.stator_supports;
    const std::vector<std::string> station_arrays = {disks, supports};
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
    for (std::size_t i = 0; i < support_rows.size(); ++i) {
      if (support_rows[i].station > last)
        RowProblem(supports, i, "station", fmt::format("must name a station of the listed {} "
                                                       "shaft (0 to {})", body, last));
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

  // [flexible.matrices]: no listed rows beside it; the file read (relative to the scene's
  // directory) and its matrices checked; the imbalance's coordinate resolved.
  void CheckMatrices(Scene& scene) {
    MatrixSettings& m = scene.flexible.matrices;
    for (const auto& [path, rows] : arrays_) {
      if (path.rfind("flexible.", 0) == 0)
        Problem(*rows, fmt::format("[[{}]]: not with [flexible.matrices], which gives the whole "
                                   "structure", path));
    }
    if (!problems_.empty()) return;
    try {
      const std::filesystem::path given(m.file);
      std::filesystem::path file = given;
      std::error_code no_file;
      if (given.is_relative() && std::filesystem::is_regular_file(source_, no_file))
        file = std::filesystem::path(source_).parent_path() / given;
      m.file = std::filesystem::absolute(file).lexically_normal().string();
      m.full = ReadStructuralMatrices(m.file);
    } catch (const std::exception& e) {  // the reader's rules, and the file system's reasons
      KeyProblem(scene, "flexible.matrices.file", e.what());
      return;
    }
    if (m.imbalance_coordinate < 0) m.imbalance_coordinate = m.rotor_contact_coordinates[0];
    const int n = static_cast<int>(m.full.Coordinates());
    auto check_range = [&](const std::string& key, std::vector<int> given) {
      for (int i : given)
        if (i >= n) {
          KeyProblem(scene, key, fmt::format("must index the matrices' {} coordinates (0 to {})",
                                             n, n - 1));
          return;
        }
    };
    check_range("flexible.matrices.rotor_contact_coordinates",
                {m.rotor_contact_coordinates[0], m.rotor_contact_coordinates[1]});
    check_range("flexible.matrices.stator_contact_coordinates",
                {m.stator_contact_coordinates[0], m.stator_contact_coordinates[1]});
    check_range("flexible.matrices.imbalance_coordinate", {m.imbalance_coordinate});
    const std::array<int, 4> contacts = {m.rotor_contact_coordinates[0], m.rotor_contact_coordinates[1],
                                         m.stator_contact_coordinates[0], m.stator_contact_coordinates[1]};
    for (std::size_t i = 0; i < contacts.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (contacts[i] == contacts[j]) {
          KeyProblem(scene, i < 2 ? "flexible.matrices.rotor_contact_coordinates"
                                  : "flexible.matrices.stator_contact_coordinates",
                     fmt::format("coordinate {} is given twice among the four contact coordinates: "
                                 "each contact joins its own rotor and stator coordinates",
                                 contacts[i]));
          return;
        }
  }

  // [flexible]: the rules that tie keys together, then whether the bodies can be built (a shaft
  // lighter than its body, a disk of positive inertia, modes the interior has).
  void CheckFlexible(Scene& scene) {
    const FlexibleSettings& f = scene.flexible;
    if (f.matrices.enabled) {
      CheckMatrices(scene);
      if (problems_.empty()) CheckBuild(scene);
      return;
    }
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
    const ModelEntry& model = ModelOf(scene);
    if (model.analytic_skipped && RunsStage(scene, Stage::kAnalytic) &&
        !model.analytic_skipped(scene).empty()) {
      std::vector<Stage>& stages = scene.analysis.stages;
      if (nodes_.count("analysis.stages") == 0) {  // the defaults: the ones that apply
        stages.erase(std::find(stages.begin(), stages.end(), Stage::kAnalytic));
      } else {
        KeyProblem(scene, "analysis.stages",
                   "\"analytic\" (L0) does not apply: " + model.analytic_skipped(scene));
      }
    }
    SupplyRigidData(scene);
    if (!problems_.empty()) return;
    CheckBuild(scene);
  }

  // Whether the flexible structure builds, each failure at the key it names.
  void CheckBuild(const Scene& scene) {
    try {
      FlexibleRubOf(scene);
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
      if (scene.flexible.matrices.enabled) {
        KeyProblem(scene, "flexible.matrices.file",
                   fmt::format("cannot be reduced at the contact coordinates: {}", e.what()));
      } else {
        problems_.push_back(fmt::format("{}: [flexible]: {}", source_, e.what()));
      }
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
    if (!RunsStage(scene, Stage::kOrbits) || !ModelOf(scene).HasSection("analysis.orbits")) return;
    if (o.adapt_mesh && o.integrator != OrbitIntegrator::kGauss)
      KeyProblem(scene, "analysis.orbits.mesh",
                 "\"adapted\" needs analysis.orbits.integrator = \"gauss\" (BDF has no mesh)");
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
    if (t.transient.laps > kMaxLaps)
      KeyProblem(scene, "analysis.tori.transient.laps", fmt::format("must be at most {}", kMaxLaps));
    if (!RunsStage(scene, Stage::kTori)) return;
    if (!t.from_neimark_sacker && !t.transient.enabled)
      KeyProblem(scene, "analysis.tori.neimark_sacker",
                 "leaves the stage \"tori\" nothing to compute: give [analysis.tori.transient]");
    if (t.transient.enabled)
      CheckTransient(scene, "analysis.tori.transient", t.transient.speed_rpm, t.transient.seconds);
    // The tori of [analysis.orbits.transient]'s family (CheckOrbits says it where "orbits" runs).
    const RubOrbitsSettings::Transient& o = scene.analysis.orbits.transient;
    if (t.from_neimark_sacker && o.enabled && !RunsStage(scene, Stage::kOrbits))
      CheckTransient(scene, "analysis.orbits.transient", o.speed_rpm, o.seconds);
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

  // [analysis.loop] against what the escape design takes (sweeps/escape_design.h).
  void CheckLoop(const Scene& scene) {
    const LoopSettings& l = scene.analysis.loop;
    const EscapeDesignOptions design;
    if (l.max_copy_seconds < design.min_duration)
      KeyProblem(scene, "analysis.loop.max_copy_seconds",
                 fmt::format("must be at least {} s (the escape design's shortest copy)", design.min_duration));
    if (l.copies > 1000) KeyProblem(scene, "analysis.loop.copies", "must be at most 1000");
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

}  // namespace

const char* ToString(OrbitIntegrator integrator) {
  switch (integrator) {
    case OrbitIntegrator::kGauss: return "gauss";
    case OrbitIntegrator::kBdf: return "bdf";
  }
  return "unknown";
}

const char* ToString(TextbookIntegrator integrator) {
  switch (integrator) {
    case TextbookIntegrator::kModel: return "model";
    case TextbookIntegrator::kExplicit: return "explicit";
    case TextbookIntegrator::kBdf: return "bdf";
    case TextbookIntegrator::kGauss: return "gauss";
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
    case Stage::kLoop: return "loop";
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
    case Stage::kLoop: return Level::kL3;  // the highest it may escalate to
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

}  // namespace rubcont
