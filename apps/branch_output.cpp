#include "apps/branch_output.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "apps/level.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {

namespace {

}  // namespace

void WriteBranchPointColumns(ResultWriter& writer, const std::string& group, const Branch& branch,
                             const ParameterColumn& parameter) {
  const std::size_t n = branch.points.size();
  std::vector<double> lambda(n), arclength(n);
  std::vector<int> stable(n), unstable(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BranchPoint& p = branch.points[i];
    lambda[i] = p.lambda * parameter.factor;
    arclength[i] = p.arclength;
    unstable[i] = p.num_unstable;
    stable[i] = p.StableFlag();
  }
  writer.WriteDoubles(group + "/" + parameter.name, lambda);
  writer.SetDimensionScales(group, parameter.name);  // xarray: the parameter is the coordinate
  writer.WriteInts(group + "/stable", stable);
  writer.WriteInts(group + "/unstable_count", unstable);
  writer.WriteDoubles(group + "/arclength", arclength);
  for (const std::string& name : branch.measure_names) {
    writer.WriteDoubles(group + "/" + name, branch.Measure(name));
  }
}

void WriteSpecialPointColumns(ResultWriter& writer, const std::string& group, const Branch& branch,
                              const ParameterColumn& parameter) {
  std::vector<std::string> type, label, note;
  std::vector<double> lambda, residual, correction, lyapunov;
  std::vector<int> converged, index;
  for (const SpecialPoint& p : branch.special_points) {
    type.push_back(ToString(p.type));
    label.push_back(p.label);
    note.push_back(p.note);
    lambda.push_back(p.lambda * parameter.factor);
    residual.push_back(p.residual_norm);
    correction.push_back(p.last_correction);
    lyapunov.push_back(p.lyapunov);
    converged.push_back(p.converged ? 1 : 0);
    index.push_back(static_cast<int>(p.index));
  }
  writer.CreateGroup(group);
  writer.WriteStrings(group + "/type", type);
  writer.WriteStrings(group + "/label", label);
  writer.WriteDoubles(group + "/" + parameter.name, lambda);
  writer.SetDimensionScales(group, parameter.name);
  writer.WriteInts(group + "/converged", converged);
  writer.WriteDoubles(group + "/residual_norm", residual);
  writer.WriteDoubles(group + "/last_correction", correction);
  writer.WriteDoubles(group + "/lyapunov", lyapunov);
  writer.WriteStrings(group + "/note", note);
  writer.WriteInts(group + "/point_index", index);
  for (std::size_t m = 0; m < branch.measure_names.size(); ++m) {
    std::vector<double> column;
    for (const SpecialPoint& p : branch.special_points) {
      column.push_back(static_cast<Index>(m) < p.measures.size() ? p.measures(m) : kNaN);
    }
    writer.WriteDoubles(group + "/" + branch.measure_names[m], column);
  }
}

std::string LyapunovText(const SpecialPoint& point) {
  if (!std::isfinite(point.lyapunov)) return "";
  return fmt::format("  l1 {:.3g}: {}", point.lyapunov,
                     point.lyapunov < 0.0 ? "supercritical" : "subcritical");
}

void WriteRotatingWaveBranches(ResultWriter& writer, const std::vector<RotatingWaveBranch>& branches,
                               FrictionLawKind law, const std::array<double, 2>& speed_range_rpm,
                               const std::string& root) {
  const ParameterColumn speed{"speed_rpm", kRpmPerRadPerSecond};
  writer.CreateGroup(root);
  writer.SetAttribute(root, "level", ToString(Level::kL1));
  writer.SetAttribute(root, "friction_law", law == FrictionLawKind::kExact ? "exact" : "tanh");
  writer.WriteDoubles(root + "/speed_range_rpm",
                      std::vector<double>{speed_range_rpm[0], speed_range_rpm[1]});
  for (const RotatingWaveBranch& b : branches) {
    const std::string group = root + "/" + b.name;
    const Branch& branch = b.branch;
    writer.CreateGroup(group);
    writer.SetAttribute(group, "kind", "rotating_wave");
    writer.SetAttribute(group, "mode", PatternName(b.normals));
    writer.SetAttribute(group, "level", ToString(Level::kL1));
    writer.SetAttribute(group, "family", b.family);
    writer.SetAttribute(group, "status", ToString(branch.status));
    writer.SetAttribute(group, "message", branch.message);
    writer.SetAttribute(group, "summary", branch.BriefReport());

    WriteBranchPointColumns(writer, group, branch, speed);
    std::vector<double> growth;
    std::vector<std::string> piece;
    for (const BranchPoint& p : branch.points) {
      growth.push_back(p.spectrum.values.size() > 0 ? p.spectrum.values.real().maxCoeff() : kNaN);
      piece.push_back(p.piece);
    }
    writer.WriteDoubles(group + "/leading_growth_rate", growth);
    writer.WriteStrings(group + "/piece", piece);

    const std::string sp = group + "/special_points";
    WriteSpecialPointColumns(writer, sp, branch, speed);
    std::vector<double> frequency;
    std::vector<int> non_smooth;
    for (const SpecialPoint& p : branch.special_points) {
      frequency.push_back(RadPerSecondToHz(p.frequency));
      non_smooth.push_back(p.nonsmooth_fold ? 1 : 0);
    }
    writer.WriteDoubles(sp + "/frequency_hz", frequency);
    writer.WriteInts(sp + "/nonsmooth_fold", non_smooth);
  }
}

}  // namespace rubcont
