#include "apps/orbit_output.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace rubcont {

namespace {

const char* OrbitKindName(OrbitKind kind) {
  switch (kind) {
    case OrbitKind::kAutonomous: return "autonomous";
    case OrbitKind::kForced: return "forced";
    case OrbitKind::kRelative: return "relative";
  }
  return "?";
}

}  // namespace

void WritePeriodicOrbitBranch(ResultWriter& writer, const std::string& name,
                              const PeriodicOrbitBranch& orbits, const ParameterColumn& parameter,
                              const std::string& root) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  writer.CreateGroup(root);
  writer.SetAttribute(root, "level", "L2");
  writer.SetAttribute(root, "parameter_name", parameter.name);
  const std::string group = root + "/" + name;
  const Branch& branch = orbits.branch;
  writer.CreateGroup(group);
  writer.SetAttribute(group, "kind", "periodic_orbit");
  writer.SetAttribute(group, "orbit_kind", OrbitKindName(orbits.kind));
  writer.SetAttribute(group, "level", "L2");
  writer.SetAttribute(group, "parameter_name", parameter.name);
  writer.SetAttribute(group, "segments", static_cast<double>(orbits.segments));
  writer.SetAttribute(group, "status", ToString(branch.status));
  writer.SetAttribute(group, "message", branch.message);
  writer.SetAttribute(group, "summary", branch.BriefReport());

  const std::size_t n = branch.points.size();
  Index multipliers = 0;
  for (const BranchPoint& p : branch.points) multipliers = std::max(multipliers, p.spectrum.values.size());
  std::vector<double> lambda(n), arclength(n), largest(n);
  std::vector<int> stable(n), unstable(n), iterations(n);
  Matrix real = Matrix::Constant(static_cast<Index>(n), multipliers, kNaN);
  Matrix imag = real;
  for (std::size_t i = 0; i < n; ++i) {
    const BranchPoint& p = branch.points[i];
    lambda[i] = p.lambda * parameter.factor;
    arclength[i] = p.arclength;
    unstable[i] = p.num_unstable;
    stable[i] = p.num_unstable < 0 ? -1 : (p.num_unstable == 0 ? 1 : 0);
    iterations[i] = p.newton_iterations;
    const ComplexVector& values = p.spectrum.values;
    largest[i] = values.size() > 0 ? values.cwiseAbs().maxCoeff() : kNaN;
    for (Index k = 0; k < values.size(); ++k) {
      real(static_cast<Index>(i), k) = values(k).real();
      imag(static_cast<Index>(i), k) = values(k).imag();
    }
  }
  writer.WriteDoubles(group + "/" + parameter.name, lambda);
  writer.WriteInts(group + "/stable", stable);
  writer.WriteInts(group + "/unstable_count", unstable);
  writer.WriteDoubles(group + "/max_multiplier_modulus", largest);
  writer.WriteMatrix(group + "/multipliers_real", real);
  writer.WriteMatrix(group + "/multipliers_imag", imag);
  writer.WriteDoubles(group + "/arclength", arclength);
  writer.WriteInts(group + "/newton_iterations", iterations);
  for (const std::string& measure : branch.measure_names) {
    writer.WriteDoubles(group + "/" + measure, branch.Measure(measure));
  }

  const std::string sp = group + "/special_points";
  std::vector<std::string> type, label, note;
  std::vector<double> sp_lambda, residual, correction, critical_real, critical_imag, angle;
  std::vector<int> converged, index;
  for (const SpecialPoint& p : branch.special_points) {
    type.push_back(ToString(p.type));
    label.push_back(p.label);
    note.push_back(p.note);
    sp_lambda.push_back(p.lambda * parameter.factor);
    residual.push_back(p.residual_norm);
    correction.push_back(p.last_correction);
    critical_real.push_back(p.critical_value.real());
    critical_imag.push_back(p.critical_value.imag());
    angle.push_back(p.type == SpecialPointType::kNeimarkSacker ? p.frequency : kNaN);
    converged.push_back(p.converged ? 1 : 0);
    index.push_back(static_cast<int>(p.index));
  }
  writer.CreateGroup(sp);
  writer.WriteStrings(sp + "/type", type);
  writer.WriteStrings(sp + "/label", label);
  writer.WriteDoubles(sp + "/" + parameter.name, sp_lambda);
  writer.WriteInts(sp + "/converged", converged);
  writer.WriteDoubles(sp + "/residual_norm", residual);
  writer.WriteDoubles(sp + "/last_correction", correction);
  writer.WriteDoubles(sp + "/critical_real", critical_real);
  writer.WriteDoubles(sp + "/critical_imag", critical_imag);
  writer.WriteDoubles(sp + "/angle", angle);
  writer.WriteStrings(sp + "/note", note);
  writer.WriteInts(sp + "/point_index", index);
  for (std::size_t m = 0; m < branch.measure_names.size(); ++m) {
    std::vector<double> column;
    for (const SpecialPoint& p : branch.special_points) {
      column.push_back(static_cast<Index>(m) < p.measures.size() ? p.measures(m) : kNaN);
    }
    writer.WriteDoubles(sp + "/" + branch.measure_names[m], column);
  }
}

}  // namespace rubcont
