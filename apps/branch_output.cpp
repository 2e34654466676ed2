#include "apps/branch_output.h"

#include <cmath>

namespace rubcont {

namespace {

constexpr double kRpmPerRadPerSecond = 60.0 / (2.0 * M_PI);

}  // namespace

void WriteRotatingWaveBranches(ResultWriter& writer, const std::vector<RotatingWaveBranch>& branches,
                               FrictionLawKind law, const std::array<double, 2>& speed_range_rpm,
                               const std::string& root) {
  writer.CreateGroup(root);
  writer.SetAttribute(root, "level", "L1");
  writer.SetAttribute(root, "friction_law", law == FrictionLawKind::kExact ? "exact" : "tanh");
  writer.WriteDoubles(root + "/speed_range_rpm",
                      std::vector<double>{speed_range_rpm[0], speed_range_rpm[1]});
  for (const RotatingWaveBranch& b : branches) {
    const std::string group = root + "/" + b.name;
    const Branch& branch = b.branch;
    writer.CreateGroup(group);
    writer.SetAttribute(group, "kind", "rotating_wave");
    writer.SetAttribute(group, "mode", PatternName(b.normals));
    writer.SetAttribute(group, "level", "L1");
    writer.SetAttribute(group, "family", b.family);
    writer.SetAttribute(group, "status", ToString(branch.status));
    writer.SetAttribute(group, "message", branch.message);
    writer.SetAttribute(group, "summary", branch.BriefReport());

    const std::size_t n = branch.points.size();
    std::vector<double> speed(n), arclength(n), growth(n);
    std::vector<int> stable(n), unstable(n);
    std::vector<std::string> piece(n);
    for (std::size_t i = 0; i < n; ++i) {
      const BranchPoint& p = branch.points[i];
      speed[i] = p.lambda * kRpmPerRadPerSecond;
      arclength[i] = p.arclength;
      unstable[i] = p.num_unstable;
      stable[i] = p.num_unstable < 0 ? -1 : (p.num_unstable == 0 ? 1 : 0);
      growth[i] = p.spectrum.values.size() > 0 ? p.spectrum.values.real().maxCoeff() : std::nan("");
      piece[i] = p.piece;
    }
    writer.WriteDoubles(group + "/speed_rpm", speed);
    writer.WriteInts(group + "/stable", stable);
    writer.WriteInts(group + "/unstable_count", unstable);
    writer.WriteDoubles(group + "/leading_growth_rate", growth);
    writer.WriteDoubles(group + "/arclength", arclength);
    writer.WriteStrings(group + "/piece", piece);
    for (const std::string& name : branch.measure_names) {
      writer.WriteDoubles(group + "/" + name, branch.Measure(name));
    }

    const std::string sp = group + "/special_points";
    std::vector<std::string> type, label, note;
    std::vector<double> sp_speed, sp_precession, residual, correction, frequency;
    std::vector<int> converged, non_smooth, index;
    for (std::size_t i = 0; i < branch.special_points.size(); ++i) {
      const SpecialPoint& p = branch.special_points[i];
      type.push_back(ToString(p.type));
      label.push_back(p.label);
      sp_speed.push_back(p.lambda * kRpmPerRadPerSecond);
      sp_precession.push_back(b.SpecialPrecessionHz(i));
      residual.push_back(p.residual_norm);
      correction.push_back(p.last_correction);
      note.push_back(p.note);
      frequency.push_back(p.frequency / (2.0 * M_PI));
      converged.push_back(p.converged ? 1 : 0);
      non_smooth.push_back(p.nonsmooth_fold ? 1 : 0);
      index.push_back(static_cast<int>(p.index));
    }
    writer.CreateGroup(sp);
    writer.WriteStrings(sp + "/type", type);
    writer.WriteStrings(sp + "/label", label);
    writer.WriteDoubles(sp + "/speed_rpm", sp_speed);
    writer.WriteDoubles(sp + "/precession_hz", sp_precession);
    writer.WriteInts(sp + "/converged", converged);
    writer.WriteDoubles(sp + "/residual_norm", residual);
    writer.WriteDoubles(sp + "/last_correction", correction);
    writer.WriteStrings(sp + "/note", note);
    writer.WriteDoubles(sp + "/frequency_hz", frequency);
    writer.WriteInts(sp + "/nonsmooth_fold", non_smooth);
    writer.WriteInts(sp + "/point_index", index);
    for (std::size_t m = 0; m < branch.measure_names.size(); ++m) {
      if (branch.measure_names[m] == "precession_hz") continue;  // written above
      std::vector<double> column;
      for (const SpecialPoint& p : branch.special_points) {
        column.push_back(static_cast<Index>(m) < p.measures.size() ? p.measures(m) : std::nan(""));
      }
      writer.WriteDoubles(sp + "/" + branch.measure_names[m], column);
    }
  }
}

}  // namespace rubcont
