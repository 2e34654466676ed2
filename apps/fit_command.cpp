#include "apps/fit_command.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <toml++/toml.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/guarded.h"
#include "apps/plan_check.h"
#include "apps/hdf5_file.h"
#include "apps/ranks.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "solvers/parallel.h"
#include "studies/identification.h"

namespace rubcont {

namespace {

struct FitSpec {
  std::vector<FitParameter> parameters;
  std::vector<IdentificationTarget> targets;
  IdentificationOptions options;
};

// Reads and checks a targets file; every problem is collected and reported at once.
class TargetsReader {
 public:
  explicit TargetsReader(std::string source) : source_(std::move(source)) {}

  FitSpec Read(const toml::table& root) {
    FitSpec spec;
    for (const auto& [key, node] : root) {
      const std::string k(key.str());
      if (k != "parameter" && k != "target" && k != "fit") {
        Problem(node, k, "", "not a key of a targets file (parameter, target, fit)");
      }
    }
    ReadParameters(root, spec);
    ReadTargets(root, spec);
    ReadFit(root, spec);
    if (!problems_.empty()) throw SceneError(problems_);
    return spec;
  }

 private:
  void Problem(const toml::node& node, const std::string& key, const std::string& value,
               const std::string& rule) {
    const auto& where = node.source().begin;
    problems_.push_back(fmt::format("{}:{}:{}: {}{}: {}", source_, where.line, where.column, key,
                                    value.empty() ? "" : " = " + value, rule));
  }
  void Missing(const toml::node& table, const std::string& key) {
    Problem(table, key, "", "missing (required)");
  }

  static std::string Text(const toml::node& node) {
    if (auto str = node.value<std::string>()) return "\"" + *str + "\"";
    std::ostringstream s;
    node.visit([&s](const auto& n) { s << n; });
    return s.str();
  }

  std::optional<double> Number(const toml::table& t, const std::string& key, const std::string& path,
                               bool required) {
    const toml::node* node = t.get(key);
    if (!node) {
      if (required) Missing(t, path);
      return std::nullopt;
    }
    const std::optional<double> v = node->value<double>();
    if (!v || !std::isfinite(*v)) {
      Problem(*node, path, Text(*node), "must be a finite number");
      return std::nullopt;
    }
    return v;
  }
  std::optional<std::string> String(const toml::table& t, const std::string& key,
                                    const std::string& path, bool required) {
    const toml::node* node = t.get(key);
    if (!node) {
      if (required) Missing(t, path);
      return std::nullopt;
    }
    const std::optional<std::string> v = node->value<std::string>();
    if (!v) Problem(*node, path, Text(*node), "must be a string");
    return v;
  }
  void OnlyKeys(const toml::table& t, const std::string& path, const std::vector<std::string>& keys) {
    for (const auto& [key, node] : t) {
      const std::string k(key.str());
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) {
        Problem(node, path + "." + k, "", fmt::format("unknown key (allowed: {})", fmt::join(keys, ", ")));
      }
    }
  }
  const toml::array* Tables(const toml::table& root, const std::string& key) {
    const toml::node* node = root.get(key);
    if (!node) {
      Problem(root, key, "", fmt::format("missing: give at least one [[{}]]", key));
      return nullptr;
    }
    const toml::array* array = node->as_array();
    if (!array || !array->is_array_of_tables() || array->empty()) {
      Problem(*node, key, "", fmt::format("must be one or more [[{}]] tables", key));
      return nullptr;
    }
    return array;
  }

  void ReadParameters(const toml::table& root, FitSpec& spec) {
    const toml::array* array = Tables(root, "parameter");
    if (!array) return;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::table& t = *array->get(i)->as_table();
      const std::string path = fmt::format("parameter[{}]", i);
      OnlyKeys(t, path, {"name", "range"});
      FitParameter p;
      bool ok = true;
      if (const auto name = String(t, "name", path + ".name", true)) {
        try {
          p.parameter = ParseDesignParameter(*name);
        } catch (const std::invalid_argument&) {
          Problem(*t.get("name"), path + ".name", "\"" + *name + "\"",
                  fmt::format("must be one of {}", fmt::join(DesignParameterNames(), ", ")));
          ok = false;
        }
      } else {
        ok = false;
      }
      const toml::node* range = t.get("range");
      const toml::array* r = range ? range->as_array() : nullptr;
      if (!range) {
        Missing(t, path + ".range");
        ok = false;
      } else if (!r || r->size() != 2 || !r->get(0)->value<double>() || !r->get(1)->value<double>()) {
        Problem(*range, path + ".range", Text(*range), "must be [lower, upper], two numbers");
        ok = false;
      } else {
        p.lower = *r->get(0)->value<double>();
        p.upper = *r->get(1)->value<double>();
        if (ok && !InPhysicalRange(p.parameter, p.lower)) {
          Problem(*range, path + ".range", Text(*range),
                  fmt::format("lower must lie in the physical range of {} ({} {} {})",
                              ToString(p.parameter), LowerLimitIncluded(p.parameter) ? "≥" : ">",
                              LowerLimit(p.parameter), UnitOf(p.parameter)));
          ok = false;
        } else if (!(std::isfinite(p.upper) && p.upper > p.lower)) {
          Problem(*range, path + ".range", Text(*range), "upper must be finite and exceed lower");
          ok = false;
        }
      }
      if (ok) spec.parameters.push_back(p);
    }
  }

  void ReadTargets(const toml::table& root, FitSpec& spec) {
    const toml::array* array = Tables(root, "target");
    if (!array) return;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::table& t = *array->get(i)->as_table();
      const std::string path = fmt::format("target[{}]", i);
      OnlyKeys(t, path, {"family", "event", "quantity", "value", "uncertainty"});
      IdentificationTarget target;
      bool ok = true;
      if (const auto family = String(t, "family", path + ".family", true)) {
        const std::vector<std::string> families{"mode1", "mode2", "left_only", "right_only", "single"};
        if (std::find(families.begin(), families.end(), *family) == families.end()) {
          Problem(*t.get("family"), path + ".family", "\"" + *family + "\"",
                  "must be mode1, mode2, left_only, right_only or single");
          ok = false;
        }
        target.pattern = *family;
      } else {
        ok = false;
      }
      if (const auto event = String(t, "event", path + ".event", true)) {
        if (event->empty()) {
          Problem(*t.get("event"), path + ".event", "\"\"", "must name the event (e.g. \"stick to slip+\")");
          ok = false;
        }
        target.event_label = *event;
      } else {
        ok = false;
      }
      if (const auto quantity = String(t, "quantity", path + ".quantity", true)) {
        if (*quantity == "speed_rpm") {
          target.quantity = TargetQuantity::kSpeedRpm;
        } else if (*quantity == "precession_hz") {
          target.quantity = TargetQuantity::kPrecessionHz;
        } else {
          Problem(*t.get("quantity"), path + ".quantity", "\"" + *quantity + "\"",
                  "must be speed_rpm or precession_hz");
          ok = false;
        }
      } else {
        ok = false;
      }
      if (const auto value = Number(t, "value", path + ".value", true)) {
        if (*value <= 0.0) {
          Problem(*t.get("value"), path + ".value", Text(*t.get("value")), "must be positive");
          ok = false;
        }
        target.value = *value;
      } else {
        ok = false;
      }
      if (const auto u = Number(t, "uncertainty", path + ".uncertainty", true)) {
        if (*u <= 0.0) {
          Problem(*t.get("uncertainty"), path + ".uncertainty", Text(*t.get("uncertainty")),
                  "must be positive");
          ok = false;
        }
        target.scale = *u;
      } else {
        ok = false;
      }
      if (ok) spec.targets.push_back(target);
    }
  }

  void ReadFit(const toml::table& root, FitSpec& spec) {
    const toml::node* node = root.get("fit");
    if (!node) return;
    const toml::table* t = node->as_table();
    if (!t) {
      Problem(*node, "fit", Text(*node), "must be a table [fit]");
      return;
    }
    OnlyKeys(*t, "fit", {"global", "global_evaluations", "local_evaluations", "local_starts",
                         "residual_tolerance"});
    if (const auto global = String(*t, "global", "fit.global", false)) {
      if (*global == "direct_l") {
        spec.options.global = GlobalMethod::kDirectL;
      } else if (*global == "crs2") {
        spec.options.global = GlobalMethod::kCrs2;
      } else if (*global == "multistart") {
        spec.options.global = GlobalMethod::kMultiStart;
      } else {
        Problem(*t->get("global"), "fit.global", "\"" + *global + "\"",
                "must be direct_l, crs2 or multistart");
      }
    }
    for (const auto& [key, field] : {std::pair{"global_evaluations", &spec.options.global_evaluations},
                                     std::pair{"local_evaluations", &spec.options.local_evaluations},
                                     std::pair{"local_starts", &spec.options.local_starts}}) {
      const toml::node* n = t->get(key);
      if (!n) continue;
      const std::optional<int64_t> v = n->value_exact<int64_t>();
      if (!v || *v < 1 || *v > 100000) {
        Problem(*n, std::string("fit.") + key, Text(*n), "must be an integer in 1 … 100000");
      } else {
        *field = static_cast<int>(*v);
      }
    }
    if (const auto tol = Number(*t, "residual_tolerance", "fit.residual_tolerance", false)) {
      if (*tol <= 0.0) {
        Problem(*t->get("residual_tolerance"), "fit.residual_tolerance", Text(*t->get("residual_tolerance")),
                "must be positive");
      } else {
        spec.options.residual_tolerance = *tol;
      }
    }
  }

  std::string source_;
  std::vector<std::string> problems_;
};

FitSpec LoadTargets(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw SceneError({fmt::format("{}: cannot read the targets file", file)});
  std::stringstream buffer;
  buffer << in.rdbuf();
  toml::table root;
  try {
    root = toml::parse(buffer.str(), file);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw SceneError({fmt::format("{}:{}:{}: TOML syntax error: {}", file, where.line, where.column,
                                  e.description())});
  }
  return TargetsReader(file).Read(root);
}

// The fit's batches shared out over the ranks — job i on rank i mod N, over `threads` threads
// there — and gathered at every rank, so that every rank goes on with the same values. A job that
// throws on one rank is rethrown on every rank.
BatchRunner RankBatchRunner(const Ranks& ranks, int threads) {
  return [&ranks, threads](int n, const std::function<std::vector<double>(int)>& job) {
    std::vector<int> mine;
    for (int i = ranks.rank(); i < n; i += ranks.size()) mine.push_back(i);
    std::vector<std::vector<double>> values(mine.size());
    std::string error;
    try {
      ParallelFor(static_cast<int>(mine.size()), threads,
                  [&](int j) { values[static_cast<size_t>(j)] = job(mine[static_cast<size_t>(j)]); });
    } catch (const std::exception& e) {
      error = e.what();
    }
    Packer packer;
    packer.Put(error);
    for (size_t j = 0; error.empty() && j < mine.size(); ++j) {
      packer.Put(static_cast<int32_t>(mine[j]));
      packer.Put(static_cast<uint64_t>(values[j].size()));
      for (double v : values[j]) packer.Put(v);
    }
    const std::vector<std::string> parts = ranks.AllGather(packer.str());
    std::vector<std::vector<double>> results(static_cast<size_t>(n));
    for (size_t r = 0; r < parts.size(); ++r) {
      Unpacker unpacker(parts[r]);
      const std::string failed = unpacker.GetString();
      if (!failed.empty()) throw std::runtime_error(fmt::format("rank {}: {}", r, failed));
      while (!unpacker.done()) {
        std::vector<double>& v = results.at(static_cast<size_t>(unpacker.Get<int32_t>()));
        v.resize(static_cast<size_t>(unpacker.Get<uint64_t>()));
        for (double& x : v) x = unpacker.Get<double>();
      }
    }
    return results;
  };
}

}  // namespace

int FitCommand(const FitRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(request.scene_file);
    if (Ranks::World().rank() == 0) WarnUnitMistakes(scene, err);  // once under mpirun
    TwoPointParamsOf(scene, "rubcont fit");
    FitSpec spec = LoadTargets(request.targets_file);
    spec.options.branches = BranchOptionsOf(scene);

    const Ranks& ranks = Ranks::World();
    const bool shared = request.over_ranks && ranks.size() > 1;
    const bool root = !shared || ranks.rank() == 0;
    const int threads = ThreadsOption(request.threads);
    const std::filesystem::path file = request.out_file
                                           ? std::filesystem::path(*request.out_file)
                                           : std::filesystem::path("results") / scene.name / "fit.h5";
    if (root) PrepareToWrite(file);
    const bool talk = root && !request.quiet;
    if (talk) {
      fmt::print(err, "rubcont: [fit] {} parameters, {} targets, {} + {} evaluations of a branch set "
                 "({}; {} thread(s){}) ...\n",
                 spec.parameters.size(), spec.targets.size(), spec.options.global_evaluations,
                 spec.options.local_evaluations, ToString(spec.options.global), threads,
                 shared ? fmt::format(" on each of {} ranks", ranks.size()) : "");
      if (shared && spec.options.global != GlobalMethod::kMultiStart) {
        fmt::print(err, "rubcont: [fit] {} chooses one evaluation at a time: its global stage runs "
                   "on every rank alike, only the sensitivities are shared (global = \"multistart\" "
                   "shares the population)\n", ToString(spec.options.global));
      }
      err.flush();
    }
    const IdentificationResult r = Identify(
        scene.two_point, spec.targets, spec.parameters, spec.options,
        shared ? RankBatchRunner(ranks, threads) : ThreadBatchRunner(threads),
        [&](const std::string& line) {
          if (!talk) return;
          fmt::print(err, "rubcont: [fit] {}\n", line);
          err.flush();
        });
    if (!root) return r.Fitted() ? kExitSuccess : kExitFailure;

    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(Level::kL1));
    writer.SetAttribute("/", "status", r.Fitted() ? "success" : "failure");
    writer.CreateGroup("/fit");
    writer.SetAttribute("/fit", "status", ToString(r.status));
    writer.SetAttribute("/fit", "message", r.message);
    writer.SetAttribute("/fit", "objective", r.objective);
    writer.SetAttribute("/fit", "global_objective", r.global_objective);
    writer.SetAttribute("/fit", "evaluations",
                        static_cast<double>(r.global_evaluations + r.local_evaluations));
    writer.SetAttribute("/fit", "global_method", ToString(spec.options.global));
    writer.SetAttribute("/fit", "local_runs", static_cast<double>(r.local_runs));
    writer.SetAttribute("/fit", "seconds", r.seconds);
    std::vector<std::string> names, target_names;
    std::vector<double> lower, upper, target_values, scales;
    std::vector<int> missing;
    for (const FitParameter& p : spec.parameters) {
      names.emplace_back(ToString(p.parameter));
      lower.push_back(p.lower);
      upper.push_back(p.upper);
    }
    for (std::size_t i = 0; i < spec.targets.size(); ++i) {
      target_names.push_back(spec.targets[i].Name());
      target_values.push_back(spec.targets[i].value);
      scales.push_back(spec.targets[i].scale);
      missing.push_back(i < r.missing.size() && r.missing[i] ? 1 : 0);
    }
    writer.WriteStrings("/fit/parameter_names", names);
    writer.WriteDoubles("/fit/values", r.parameters);
    writer.WriteDoubles("/fit/global_values", r.global_parameters);
    writer.WriteDoubles("/fit/lower", lower);
    writer.WriteDoubles("/fit/upper", upper);
    writer.WriteDoubles("/fit/standard_deviation", r.standard_deviation);
    writer.WriteDoubles("/fit/objective_rise", r.objective_rise);
    Matrix correlation(r.correlation.size(), r.correlation.size());
    for (std::size_t a = 0; a < r.correlation.size(); ++a) {
      for (std::size_t b = 0; b < r.correlation.size(); ++b) correlation(a, b) = r.correlation[a][b];
    }
    writer.WriteMatrix("/fit/correlation", correlation);
    writer.WriteStrings("/fit/target_names", target_names);
    writer.WriteDoubles("/fit/target_values", target_values);
    writer.WriteDoubles("/fit/predicted", r.predicted);
    writer.WriteDoubles("/fit/residuals", r.residuals);
    writer.WriteDoubles("/fit/uncertainties", scales);
    writer.WriteInts("/fit/missing", missing);
    writer.Commit();

    fmt::print(out, "scene {} from {}, targets from {}\n[fit] {}: {}\n", scene.name, scene.source,
               request.targets_file, ToString(r.status), r.message);
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      fmt::print(out, "  {:<18} = {:<14.10g} ± {:.3g} {} (global stage {:.6g}; J rises by {:.3g} for ±1 %)\n",
                 names[k], r.parameters[k], r.standard_deviation[k], UnitOf(spec.parameters[k].parameter),
                 r.global_parameters[k], r.objective_rise[k]);
    }
    for (std::size_t i = 0; i < spec.targets.size() && i < r.predicted.size(); ++i) {
      fmt::print(out, "  {:<40} target {:<12.6f} model {:<12.6f} residual {:+.3g} uncertainties\n",
                 target_names[i], target_values[i], r.predicted[i], r.residuals[i]);
    }
    fmt::print(out, "wrote {}\n", file.string());
    if (r.status == IdentificationStatus::kFailed) {
      fmt::print(err, "rubcont: numerical failure: {}\n", r.message);
    } else if (!r.Fitted()) {
      fmt::print(err, "rubcont: the fit did not reproduce the targets: {}\n", r.message);
    }
    return r.Fitted() ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
