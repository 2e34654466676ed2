#include "apps/map_command.h"

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/dataset_description.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/plan_check.h"
#include "apps/hdf5_file.h"
#include "apps/map_output.h"
#include "apps/ranks.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "models/units.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

std::string SpecialPointName(SpecialPointType type, bool nonsmooth_fold) {
  if (type == SpecialPointType::kEvent && nonsmooth_fold) return "non_smooth_fold";
  return ToString(type);
}

void Pack(Packer& p, const MapGridRow& row) {
  p.Put(static_cast<int64_t>(row.index));
  p.Put(static_cast<uint8_t>(row.failed));
  p.Put(static_cast<int32_t>(row.branches));
  auto ints = [&p](const std::vector<int>& v) {
    p.Put(static_cast<uint64_t>(v.size()));
    for (int x : v) p.Put(static_cast<int32_t>(x));
  };
  ints(row.stable_count);
  p.Put(static_cast<uint64_t>(row.pattern_counts.size()));
  for (const auto& [pattern, counts] : row.pattern_counts) {
    p.Put(pattern);
    ints(counts);
  }
  p.Put(static_cast<uint64_t>(row.points.size()));
  for (const MapPoint& m : row.points) {
    p.Put(m.eta);
    p.Put(m.speed);
    p.Put(m.precession_hz);
    p.Put(static_cast<int32_t>(m.type));
    p.Put(m.label);
    p.Put(static_cast<uint8_t>(m.nonsmooth_fold));
    p.Put(static_cast<int32_t>(m.branch));
    p.Put(static_cast<int32_t>(m.stable_before));
    p.Put(static_cast<int32_t>(m.stable_after));
  }
  p.Put(static_cast<uint64_t>(row.failures.size()));
  for (const std::string& f : row.failures) p.Put(f);
}

MapGridRow UnpackRow(Unpacker& u) {
  MapGridRow row;
  row.index = static_cast<Index>(u.Get<int64_t>());
  row.failed = u.Get<uint8_t>() != 0;
  row.branches = u.Get<int32_t>();
  auto ints = [&u] {
    std::vector<int> v(static_cast<size_t>(u.Get<uint64_t>()));
    for (int& x : v) x = u.Get<int32_t>();
    return v;
  };
  row.stable_count = ints();
  for (uint64_t n = u.Get<uint64_t>(); n > 0; --n) {
    std::string pattern = u.GetString();
    row.pattern_counts.emplace_back(std::move(pattern), ints());
  }
  for (uint64_t n = u.Get<uint64_t>(); n > 0; --n) {
    MapPoint m;
    m.eta = u.Get<double>();
    m.speed = u.Get<double>();
    m.precession_hz = u.Get<double>();
    m.type = static_cast<SpecialPointType>(u.Get<int32_t>());
    m.label = u.GetString();
    m.nonsmooth_fold = u.Get<uint8_t>() != 0;
    m.branch = u.Get<int32_t>();
    m.stable_before = u.Get<int32_t>();
    m.stable_after = u.Get<int32_t>();
    row.points.push_back(std::move(m));
  }
  for (uint64_t n = u.Get<uint64_t>(); n > 0; --n) row.failures.push_back(u.GetString());
  return row;
}

// The map with its grid shared out over the ranks of an MPI run (size 1: this process alone; the
// threads of each: HysteresisMapOptions::threads): rank r computes the grid values i ≡ r (mod N),
// rank 0 gathers the rows and computes the curves (not shared: they start from one branch set and
// are few). Empty on the other ranks.
std::optional<HysteresisMap> MapOnRanks(const Ranks& ranks, bool over_ranks,
                                        const TwoPointParams& params,
                                        const HysteresisMapOptions& options,
                                        const MapProgress& progress) {
  const SteadyClock::time_point start = SteadyClock::now();
  const int rank = over_ranks ? ranks.rank() : 0;
  const int size = over_ranks ? ranks.size() : 1;
  std::vector<Index> mine;
  for (Index i = rank; i < options.eta_points; i += size) mine.push_back(i);
  std::vector<MapGridRow> rows = ComputeMapGrid(params, options, mine, progress);
  if (size > 1) {
    Packer packer;
    for (const MapGridRow& row : rows) Pack(packer, row);
    const std::vector<std::string> parts = ranks.GatherToRoot(packer.str());
    if (rank != 0) return std::nullopt;
    rows.clear();
    for (const std::string& part : parts) {
      Unpacker unpacker(part);
      while (!unpacker.done()) rows.push_back(UnpackRow(unpacker));
    }
  }
  return AssembleHysteresisMap(params, options, std::move(rows), SecondsSince(start), progress);
}

}  // namespace

std::pair<double, double> DefaultMapRange(DesignParameter parameter, double base) {
  if (parameter == DesignParameter::kRciRatio) return {0.75 * base, 1.35 * base};
  if (base == 0.0) {
    const double typical = parameter == DesignParameter::kFriction ? 0.5
                           : parameter == DesignParameter::kCenterDamping ? 100.0
                                                                          : 500.0;
    return {0.0, 2.0 * typical};
  }
  return {0.5 * base, 1.5 * base};
}

void WriteHysteresisMap(ResultWriter& writer, const HysteresisMap& map, FrictionLawKind law) {
  const std::string group = std::string("/maps/") + ToString(map.parameter);
  writer.CreateGroup(group);
  writer.SetAttribute(group, "parameter", ToString(map.parameter));
  writer.SetAttribute(group, "unit", UnitOf(map.parameter));
  writer.SetAttribute(group, "base_value", map.base_value);
  writer.SetAttribute(group, "level", ToString(Level::kL1));
  writer.SetAttribute(group, "friction_law", law == FrictionLawKind::kExact ? "exact" : "tanh");
  writer.SetAttribute(group, "summary", map.BriefReport());
  writer.SetAttribute(group, "note", map.note);
  writer.SetAttribute(group, "grid_seconds", map.grid_seconds);
  writer.SetAttribute(group, "curve_seconds", map.curve_seconds);
  writer.SetAttribute(group, "region_codes",
                      "0: no stable circular rub state, 1: one, 2: two or more coexisting "
                      "(hysteresis); the no-rub state is not counted");
  // η's unit is the mapped parameter's (DatasetDescription::kContext).
  const std::string eta_units = DesignParameterUnits(map.parameter);
  auto write_eta = [&](const std::string& path, const auto& values) {
    writer.WriteDoubles(path, values);
    writer.SetUnits(path, eta_units);
  };
  write_eta(group + "/eta", map.eta);
  writer.WriteDoubles(group + "/speed_rpm", Vector(map.speed * kRpmPerRadPerSecond));
  // xarray: the counts and regions are a field over (eta, speed_rpm).
  writer.SetDimensionScales(group, "eta");
  Matrix count = map.stable_count.cast<double>();
  Matrix region = count;
  for (Index i = 0; i < region.rows(); ++i) {
    for (Index j = 0; j < region.cols(); ++j) {
      region(i, j) = count(i, j) < 0 ? -1.0 : static_cast<double>(static_cast<int>(map.Region(i, j)));
    }
  }
  writer.WriteMatrix(group + "/stable_count", count);
  writer.WriteMatrix(group + "/region", region);
  writer.NameSecondAxis(group + "/stable_count", "speed_rpm");
  writer.NameSecondAxis(group + "/region", "speed_rpm");
  for (std::size_t p = 0; p < map.patterns.size(); ++p) {
    writer.WriteMatrix(group + "/by_pattern/" + map.patterns[p] + "/stable_count",
                       map.pattern_counts[p].cast<double>());
  }

  const std::string points = group + "/points";
  writer.CreateGroup(points);
  std::vector<double> eta, speed, precession;
  std::vector<std::string> type, label;
  std::vector<int> nonsmooth, branch, before, after;
  for (const MapPoint& p : map.points) {
    eta.push_back(p.eta);
    speed.push_back(RadPerSecondToRpm(p.speed));
    precession.push_back(p.precession_hz);
    type.push_back(SpecialPointName(p.type, p.nonsmooth_fold));
    label.push_back(p.label);
    nonsmooth.push_back(p.nonsmooth_fold ? 1 : 0);
    branch.push_back(p.branch);
    before.push_back(p.stable_before);
    after.push_back(p.stable_after);
  }
  write_eta(points + "/eta", eta);
  writer.WriteDoubles(points + "/speed_rpm", speed);
  writer.WriteDoubles(points + "/precession_hz", precession);
  writer.WriteStrings(points + "/type", type);
  writer.WriteStrings(points + "/label", label);
  writer.WriteInts(points + "/nonsmooth_fold", nonsmooth);
  writer.WriteInts(points + "/branch", branch);
  writer.WriteInts(points + "/stable_before", before);
  writer.WriteInts(points + "/stable_after", after);

  writer.CreateGroup(group + "/curves");
  for (const MapCurve& c : map.curves) {
    const std::string g = group + "/curves/" + c.name;
    writer.CreateGroup(g);
    writer.SetAttribute(g, "kind", c.kind);
    writer.SetAttribute(g, "label", c.label);
    writer.SetAttribute(g, "piece", c.piece);
    writer.SetAttribute(g, "pattern", c.pattern);
    writer.SetAttribute(g, "branch", static_cast<double>(c.branch));
    writer.SetAttribute(g, "status", ToString(c.curve.status));
    writer.SetAttribute(g, "message", c.curve.message);
    writer.SetAttribute(g, "start_eta", c.start_eta);
    writer.SetAttribute(g, "start_speed_rpm", RadPerSecondToRpm(c.start_speed));
    writer.SetAttribute(g, "start_nonsmooth_fold", c.start_nonsmooth_fold ? 1.0 : 0.0);
    writer.SetAttribute(g, "fold_sense", static_cast<double>(c.fold_sense));
    writer.SetAttribute(g, "partner_margins", fmt::format("{}", fmt::join(c.partner_margins, "; ")));
    const bool has_points = !c.curve.points.empty();
    write_eta(g + "/eta", has_points ? c.curve.Lambda() : Vector());
    writer.WriteDoubles(g + "/speed_rpm",
                        has_points ? Vector(c.curve.Measure("lambda") * kRpmPerRadPerSecond) : Vector());
    writer.WriteDoubles(g + "/precession_hz",
                        has_points ? c.curve.Measure("precession_hz") : Vector());
    if (c.kind == "hopf") {
      writer.WriteDoubles(g + "/hopf_hz",
                          has_points ? Vector(c.curve.Measure("hopf_frequency").unaryExpr(
                                           [](double w) { return RadPerSecondToHz(w); }))
                                     : Vector());
      std::vector<int> stable;
      for (const BranchPoint& p : c.curve.points) {
        stable.push_back(p.StableFlag());
      }
      writer.WriteInts(g + "/stable", stable);
    }
    std::vector<std::string> sp_type, sp_label;
    std::vector<double> sp_eta, sp_speed;
    const auto& names = c.curve.measure_names;
    for (const SpecialPoint& sp : c.curve.special_points) {
      sp_type.push_back(ToString(sp.type));
      sp_label.push_back(sp.label);
      sp_eta.push_back(sp.lambda);
      double speed_rpm = kNaN;
      if (!names.empty() && names[0] == "lambda" && sp.measures.size() > 0) {
        speed_rpm = RadPerSecondToRpm(sp.measures(0));
      }
      sp_speed.push_back(speed_rpm);
    }
    std::vector<double> x_eta, x_speed, x_ipopt_eta, x_ipopt_speed;
    std::vector<std::string> x_status;
    for (const CurveExtremum& e : c.extrema) {
      x_eta.push_back(e.engine_eta);
      x_speed.push_back(RadPerSecondToRpm(e.engine_speed));
      x_ipopt_eta.push_back(e.ipopt.lambda);
      x_ipopt_speed.push_back(RadPerSecondToRpm(e.ipopt_speed));
      x_status.push_back(ToString(e.ipopt.status));
    }
    writer.CreateGroup(g + "/extrema");
    write_eta(g + "/extrema/eta", x_eta);
    writer.WriteDoubles(g + "/extrema/speed_rpm", x_speed);
    write_eta(g + "/extrema/ipopt_eta", x_ipopt_eta);
    writer.WriteDoubles(g + "/extrema/ipopt_speed_rpm", x_ipopt_speed);
    writer.WriteStrings(g + "/extrema/ipopt_status", x_status);
    writer.CreateGroup(g + "/special_points");
    writer.WriteStrings(g + "/special_points/type", sp_type);
    writer.WriteStrings(g + "/special_points/label", sp_label);
    write_eta(g + "/special_points/eta", sp_eta);
    writer.WriteDoubles(g + "/special_points/speed_rpm", sp_speed);
  }
  writer.WriteStrings(group + "/failures", map.failures);
}

int MapCommand(const MapRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const DesignParameter parameter = [&] {
      try {
        return ParseDesignParameter(request.parameter);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("--{}", e.what()));
      }
    }();
    const Scene scene = LoadScene(request.scene_file);
    const double base = GetDesignParameter(TwoPointParamsOf(scene, "rubcont map"), parameter);
    const auto [default_min, default_max] = DefaultMapRange(parameter, base);
    HysteresisMapOptions options;
    options.parameter = parameter;
    options.eta_min = request.eta_min.value_or(default_min);
    options.eta_max = request.eta_max.value_or(default_max);
    if (!InPhysicalRange(parameter, options.eta_min)) {
      throw std::invalid_argument(fmt::format(
          "--eta-min = {}: must lie in the physical range of {} ({} {} {})", options.eta_min,
          ToString(parameter), LowerLimitIncluded(parameter) ? "≥" : ">", LowerLimit(parameter),
          UnitOf(parameter)));
    }
    if (!(std::isfinite(options.eta_max) && options.eta_max > options.eta_min)) {
      throw std::invalid_argument(fmt::format("--eta-max = {}: must be finite and exceed --eta-min = {}",
                                              options.eta_max, options.eta_min));
    }
    if (request.eta_points < 2 || request.eta_points > 2000) {
      throw std::invalid_argument(
          fmt::format("--eta-points = {}: must be in 2 … 2000", request.eta_points));
    }
    options.threads = ThreadsOption(request.threads);
    if (request.speed_points < 2 || request.speed_points > 100000) {
      throw std::invalid_argument(
          fmt::format("--speed-points = {}: must be in 2 … 100000", request.speed_points));
    }
    options.eta_points = request.eta_points;
    options.speed_points = request.speed_points;
    if (Ranks::World().rank() == 0) WarnUnitMistakes(scene, err);  // once under mpirun
    CheckPlan({MapWork("--eta-points × --speed-points", fmt::format("{} × {}", request.eta_points, request.speed_points),
                        request.eta_points, request.speed_points)},
              request.force, err);
    options.branches = BranchOptionsOf(scene);

    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name /
                               (std::string("map_") + ToString(parameter) + ".h5");
    const std::filesystem::path out_dir = file.parent_path().empty() ? "." : file.parent_path();
    PrepareToWrite(file);

    const SteadyClock::time_point start = SteadyClock::now();
    const Ranks& ranks = Ranks::World();
    const MapProgress progress = [&](const std::string& stage, int done, int total) {
      if (request.quiet) return;
      fmt::print(err, "rubcont: [map] {}{} {}/{} ({:.1f} s)\n",
                 ranks.size() > 1 && request.over_ranks ? fmt::format("rank {}: ", ranks.rank()) : "", stage, done,
                 total, SecondsSince(start));
      err.flush();
    };
    const std::optional<HysteresisMap> shared = MapOnRanks(
        ranks, request.over_ranks && ranks.size() > 1, scene.two_point, options, progress);
    if (!shared) return kExitSuccess;  // a rank other than 0: rank 0 writes the map
    const HysteresisMap& map = *shared;

    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(Level::kL1));
    writer.SetAttribute("/", "status", map.failures.empty() ? "success" : "failure");
    WriteHysteresisMap(writer, map, scene.two_point.friction_law.kind);
    writer.Commit();

    fmt::print(out, "scene {} from {}\n[map] {}\n", scene.name, scene.source, map.BriefReport());
    if (!map.note.empty()) fmt::print(out, "[map] note: {}\n", map.note);
    for (const MapCurve& c : map.curves) {
      const Branch& b = c.curve;
      double lo = 0.0, hi = 0.0;
      if (!b.points.empty()) {
        const Vector eta = b.Lambda();
        lo = eta.minCoeff();
        hi = eta.maxCoeff();
      }
      fmt::print(out, "  {} {} \"{}\" from {:.3f} rpm at {} = {:g}: {} points, {} ∈ [{:g}, {:g}], "
                      "ended: {}\n",
                 c.name, c.kind, c.label, RadPerSecondToRpm(c.start_speed), ToString(parameter),
                 c.start_eta, b.points.size(), ToString(parameter), lo, hi, b.message);
      for (const SpecialPoint& sp : b.special_points) {
        if (sp.type == SpecialPointType::kFold) continue;  // printed with Ipopt's below
        fmt::print(out, "    {} at {} = {:.6g}, {:.3f} rpm\n", sp.Name(), ToString(parameter),
                   sp.lambda, sp.measures.size() > 0 ? RadPerSecondToRpm(sp.measures(0)) : 0.0);
      }
      for (const CurveExtremum& e : c.extrema) {
        fmt::print(out, "    turning point ({} {}): engine {} = {:.10g} at {:.6f} rpm; Ipopt {} = "
                        "{:.10g} at {:.6f} rpm ({}, {} iterations)\n",
                   e.sense > 0 ? "largest" : "smallest", ToString(parameter), ToString(parameter),
                   e.engine_eta, RadPerSecondToRpm(e.engine_speed), ToString(parameter),
                   e.ipopt.lambda, RadPerSecondToRpm(e.ipopt_speed), ToString(e.ipopt.status),
                   e.ipopt.iterations);
        if (!e.ipopt.Solved()) fmt::print(out, "      Ipopt: {}\n", e.ipopt.message);
      }
    }
    fmt::print(out, "wrote {}\n", file.string());
    if (request.figures) {
      const FigureOutcome figures = MakeFigures("map", file, out_dir, request.figure_format);
      if (figures.made) {
        fmt::print(out, "wrote figures (map) in {}\n", out_dir.string());
      } else {
        fmt::print(err, "rubcont: warning: {}\n", figures.warning);
      }
    }
    for (const std::string& f : map.failures) fmt::print(err, "rubcont: numerical failure: {}\n", f);
    return map.failures.empty() ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
