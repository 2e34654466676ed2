#include "apps/plan_check.h"

#include <array>
#include <ostream>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/models.h"
#include "apps/scene_schema.h"
#include "apps/stage_options.h"
#include "models/scale_check.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

// A length key's values: one number or a pair.
std::vector<double> Numbers(const schema::Value& value) {
  if (const double* x = std::get_if<double>(&value)) return {*x};
  if (const auto* pair = std::get_if<std::array<double, 2>>(&value)) return {(*pair)[0], (*pair)[1]};
  return {};
}

std::string NumbersText(const std::vector<double>& numbers) {
  if (numbers.size() == 1) return schema::FormatFloat(numbers[0], true);
  return fmt::format("[{}, {}]", schema::FormatFloat(numbers[0], true), schema::FormatFloat(numbers[1], true));
}

// The scene's length keys (unit m) of its model, in schema order, with their values.
std::vector<std::pair<const schema::KeySpec*, std::vector<double>>> LengthKeys(const Scene& scene) {
  std::vector<std::pair<const schema::KeySpec*, std::vector<double>>> keys;
  for (const schema::KeySpec& spec : schema::Schema()) {
    if (spec.unit != "m" || !schema::OfModel(spec, scene) || (spec.relevant && !spec.relevant(scene))) continue;
    keys.emplace_back(&spec, Numbers(spec.get(scene)));
  }
  return keys;
}

// The length key of the scene that holds `value` (a contact's radius or clearance as the model's
// structure has it: contact.radius, jeffcott.R, ...); the model's own name for it otherwise.
std::string KeyHolding(const Scene& scene, double value, const std::string& otherwise) {
  for (const auto& [spec, numbers] : LengthKeys(scene)) {
    for (double x : numbers) {
      if (x == value) return spec->key;
    }
  }
  return otherwise;
}

}  // namespace

void CheckPlan(const std::vector<PlannedWork>& plan, bool force, std::ostream& err) {
  const std::string excess = ExcessiveWork(plan);
  if (excess.empty()) return;
  if (!force) throw std::invalid_argument(excess + "; --force to run it anyway");
  fmt::print(err, "rubcont: warning: {}; running it anyway (--force)\n", excess);
}

std::vector<std::string> UnitMistakes(const Scene& scene) {
  std::vector<std::string> mistakes;
  // Lengths first: a scene written in mm breaks every one of them, and the rules below only
  // repeat it. The first such key is named, the others counted.
  std::string first;
  int others = 0;
  for (const auto& [spec, numbers] : LengthKeys(scene)) {
    for (double x : numbers) {
      const std::string mistake = LengthScaleMistake(x);
      if (mistake.empty()) continue;
      if (first.empty()) {
        first = fmt::format("{} = {} m: {}", spec->key, NumbersText(numbers), mistake);
      } else {
        ++others;
      }
      break;
    }
  }
  if (!first.empty()) {
    mistakes.push_back(others == 0 ? first
                                   : fmt::format("{} ({} more length key{} outside the rotor lengths)",
                                                 first, others, others == 1 ? "" : "s"));
    return mistakes;
  }
  if (!ModelOf(scene).IsRub()) return mistakes;
  RubStructure structure;
  double knee = kNaN;
  try {
    structure = StructureOf(scene);
    knee = RollingKneeSpeed(structure);
  } catch (const std::invalid_argument&) {
    return mistakes;  // no valid structure (a mass that underflows M⁻¹): the stage says so itself
  }
  for (const RubContact& c : structure.contacts) {
    const std::string mistake = ClearanceRatioMistake(c.geometry.radius, c.geometry.clearance);
    if (mistake.empty()) continue;
    mistakes.push_back(fmt::format("{} = {} m at the {} contact: {}",
                                   KeyHolding(scene, c.geometry.radius, "radius"),
                                   schema::FormatFloat(c.geometry.radius, true), c.name, mistake));
    return mistakes;  // the speeds below follow from the same lengths
  }
  // The top speed of the ranges the commands run over: the branches', the sweeps'.
  const std::array<std::pair<const char*, std::array<double, 2>>, 3> ranges{{
      {"analysis.speed_range_rpm", scene.analysis.speed_range_rpm},
      {"analysis.sweep.up_range_rpm", scene.analysis.sweep.up_range_rpm},
      {"analysis.sweep.down_range_rpm", scene.analysis.sweep.down_range_rpm},
  }};
  double largest_radius = 0.0;
  for (const RubContact& c : structure.contacts) largest_radius = std::max(largest_radius, c.geometry.radius);
  for (const auto& [key, range] : ranges) {
    const std::string mistake = SurfaceSpeedMistake(largest_radius, RpmToRadPerSecond(range[1]));
    if (mistake.empty()) continue;
    mistakes.push_back(fmt::format("{} = {} rpm: {}", key, NumbersText({range[0], range[1]}), mistake));
    break;
  }
  const auto& range = scene.analysis.speed_range_rpm;
  const std::string mistake =
      SpeedRangeMistake(knee, RpmToRadPerSecond(range[0]), RpmToRadPerSecond(range[1]));
  if (!mistake.empty()) {
    mistakes.push_back(
        fmt::format("analysis.speed_range_rpm = {} rpm: {}", NumbersText({range[0], range[1]}), mistake));
  }
  return mistakes;
}

void WarnUnitMistakes(const Scene& scene, std::ostream& err) {
  for (const std::string& mistake : UnitMistakes(scene)) fmt::print(err, "rubcont: warning: {}\n", mistake);
}

}  // namespace rubcont
