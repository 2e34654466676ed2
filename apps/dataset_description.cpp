#include "apps/dataset_description.h"

#include <regex>
#include <utility>

#include "sweeps/rub_sweep.h"
#include "waves/rotating_wave.h"

namespace rubcont {
namespace {

using Kind = DatasetDescription::Kind;

// A rule: the dataset's name matches `name` (the whole last path component) and, when `place` is
// not empty, its path matches `place` somewhere.
struct Rule {
  std::regex name;
  std::regex place;
  bool has_place = false;
  DatasetDescription description;
};

// The per-contact suffix of a measure: normal_force_left, slip_velocity_max_contact, …
const std::string kContact = "(_(left|right|contact))?";

DatasetDescription Unit(std::string unit) { return {Kind::kUnit, std::move(unit), {}, {}}; }
DatasetDescription Dimensionless() { return {Kind::kDimensionless, {}, {}, {}}; }
DatasetDescription Context() { return {Kind::kContext, {}, {}, {}}; }
DatasetDescription Flag(std::vector<int> values, std::string meanings) {
  return {Kind::kFlag, {}, std::move(values), std::move(meanings)};
}

// The words of an enum's ToString for the codes first … last, as flag meanings (CF: no blanks in
// a word).
template <class Enum>
DatasetDescription EnumFlag(Enum first, Enum last, const char* (*to_string)(Enum)) {
  std::vector<int> values;
  std::string meanings;
  for (int v = static_cast<int>(first); v <= static_cast<int>(last); ++v) {
    values.push_back(v);
    std::string word = to_string(static_cast<Enum>(v));
    for (char& c : word) c = c == ' ' ? '_' : c;
    meanings += (meanings.empty() ? "" : " ") + word;
  }
  return Flag(std::move(values), std::move(meanings));
}

std::vector<Rule> MakeRules() {
  std::vector<Rule> rules;
  auto add = [&rules](const std::string& name, DatasetDescription d,
                      const std::string& place = "") {
    rules.push_back({std::regex(name), std::regex(place.empty() ? "." : place), !place.empty(),
                     std::move(d)});
  };
  // Coded integers first: their names would otherwise match a quantity's pattern.
  add("stable|branch_stable|stable_before|stable_after",
      Flag({-1, 0, 1}, "not_computed unstable stable"));
  add("mode_(left|right|contact)",
      EnumFlag(ContactMode::kFree, ContactMode::kSlipNegative,
               static_cast<const char* (*)(ContactMode)>(ToString)));
  add("regime" + kContact, EnumFlag(RubRegime::kUnknown, RubRegime::kWhip,
                                   static_cast<const char* (*)(RubRegime)>(ToString)));
  add("region", Flag({-1, 0, 1, 2}, "not_computed no_stable_circular_state "
                                    "one_stable_circular_state coexisting_stable_circular_states"));
  add("converged", Flag({0, 1}, "guess converged"));
  add("nonsmooth_fold", Flag({0, 1}, "smooth nonsmooth_fold"));
  add("through_pole", Flag({0, 1}, "not_through_pole through_pole"));
  add("settled", Flag({0, 1}, "not_settled settled"));
  add("trusted", Flag({0, 1}, "untrusted trusted"));
  add("reached|failed|missing", Flag({0, 1}, "no yes"));
  add("direction", Flag({-1, 1}, "decreasing increasing"));

  // Quantities by the unit their name ends in.
  add(".*(^|_)rpm" + kContact, Unit("rpm"));
  add(".*_hz" + kContact, Unit("Hz"));
  add(".*_deg", Unit("degree"));
  add(".*(_s|seconds|_time)" + kContact, Unit("s"));
  add("period", Unit("s"), "^/(orbits|tori|loop/orbits)/");
  add("frequency_change", Unit("Hz"));  // a sweep's last window-to-window |Δf| of the BP
  // Quantities by what they are.
  add("(min_|max_|section_)?(normal_force|friction_force)(_min|_max)?" + kContact, Unit("N"));
  add("slip_velocity(_min|_max)?" + kContact, Unit("m/s"));
  add("(max_|section_)?penetration(_max)?" + kContact, Unit("m"));
  add("(orbit_radius|precession_amplitude|spectrum_magnitude)" + kContact, Unit("m"));
  add("leading_growth_rate|escape_rate|rate|rate_lower|rate_upper", Unit("1/s"));
  add("exponents|standard_errors", Unit("1/s"), "^/attractor/");
  add("[0-9]+", Unit("1/s"), "^/attractor/running/");  // running estimates of the exponents
  add("rotation|angle", Unit("rad"));
  // The parameter of a map, and the fit's parameters and targets: their units are the run's.
  add("eta|ipopt_eta", Context());

  // Dimensionless: ratios, counts, scaled quantities, codes, text and mixed columns.
  add("(mu_required|mu_ratio|slip_ratio|contact_fraction)" + kContact, Dimensionless());
  add("unstable_count|stable_count|point_index|newton_iterations|steps|rhs_evaluations|"
      "jacobian_evaluations|linear_solver_setups|error_test_failures|convergence_failures|"
      "windows|intermittent_windows|escapes|stayed|untrusted|copies|escape_stretch|branch|"
      "zero_exponents|positive_exponents|section_period|unknown|multiplier|.*_column",
      Dimensionless());
  add("arclength|residual_norm|last_correction|lyapunov|spectrum_change|critical_real|"
      "critical_imag|multipliers_real|multipliers_imag|max_multiplier_modulus|"
      "unresolved_multiplier|rotation_number|asymmetry|defect|invariance_error|fourier_tail|"
      "largest_exponent|exponent_tolerance|exponents|line_(k|l|ratio)" + kContact + "|"
      "predicted_leave_probability|leave_probability|table_damping_ratio|"
      "thesis_damping_ratio|correlation|objective_rise|residuals",
      Dimensionless());
  // Columns whose units differ from entry to entry (a fit's parameters and targets, a state).
  add("values|global_values|lower|upper|standard_deviation|target_values|predicted|"
      "uncertainties|unknowns|state|max_x[0-9]+|min_x[0-9]+", Dimensionless());
  // Text.
  add("type|label|note|piece|status|message|contact|kind|matched_side|bifurcation|motion|"
      "rate_status|ipopt_status|failures|parameter_names|target_names|pattern|table_case|"
      "untrusted|cause|interval|level|evidence|decisions|log|limit",
      Dimensionless());
  // The textbook models are nondimensional: their parameter, state measures and period.
  add("lambda|mu|frequency|period|amplitude_x|max_x|min_x|max_v|min_v|mean_radius|"
      "closed_form_(radius|period|multiplier)_error",
      Dimensionless(), "^/branches/periodic_orbits/");
  // A torus's circle radius, in scaled state units (InvariantCircleProblem::Radius).
  add("radius", Dimensionless(), "^/tori/");
  // The K each torus's circle was solved with (a count).
  add("harmonics", Dimensionless(), "^/tori/");
  return rules;
}

}  // namespace

DatasetDescription DescribeDataset(const std::string& path) {
  static const std::vector<Rule> rules = MakeRules();
  const std::string name = path.substr(path.rfind('/') + 1);
  for (const Rule& rule : rules) {
    if (!std::regex_match(name, rule.name)) continue;
    if (rule.has_place && !std::regex_search(path, rule.place)) continue;
    return rule.description;
  }
  return {};
}

std::string DesignParameterUnits(DesignParameter parameter) {
  const std::string unit = UnitOf(parameter);
  if (unit == "-") return "1";
  std::string units;  // UDUNITS writes a product with a blank: N·s/m → N s/m
  for (std::size_t i = 0; i < unit.size(); ++i) {
    if (unit.compare(i, std::string("·").size(), "·") == 0) {
      units += ' ';
      i += std::string("·").size() - 1;
    } else {
      units += unit[i];
    }
  }
  return units;
}

}  // namespace rubcont
