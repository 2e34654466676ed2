#include "apps/orbit_output.h"
#include "apps/level.h"
#include "solvers/constants.h"

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
  writer.CreateGroup(root);
  writer.SetAttribute(root, "level", ToString(Level::kL2));
  writer.SetAttribute(root, "parameter_name", parameter.name);
  const std::string group = root + "/" + name;
  const Branch& branch = orbits.branch;
  writer.CreateGroup(group);
  writer.SetAttribute(group, "kind", "periodic_orbit");
  writer.SetAttribute(group, "orbit_kind", OrbitKindName(orbits.kind));
  writer.SetAttribute(group, "level", ToString(Level::kL2));
  writer.SetAttribute(group, "parameter_name", parameter.name);
  writer.SetAttribute(group, "segments", static_cast<double>(orbits.segments));
  writer.SetAttribute(group, "status", ToString(branch.status));
  writer.SetAttribute(group, "message", branch.message);
  writer.SetAttribute(group, "summary", branch.BriefReport());

  WriteBranchPointColumns(writer, group, branch, parameter);
  Index multipliers = 0;
  for (const BranchPoint& p : branch.points) multipliers = std::max(multipliers, p.spectrum.values.size());
  const Index n = static_cast<Index>(branch.points.size());
  std::vector<double> largest;
  std::vector<int> iterations;
  Matrix real = Matrix::Constant(n, multipliers, kNaN);
  Matrix imag = real;
  for (Index i = 0; i < n; ++i) {
    const BranchPoint& p = branch.points[static_cast<std::size_t>(i)];
    iterations.push_back(p.newton_iterations);
    const ComplexVector& values = p.spectrum.values;
    largest.push_back(values.size() > 0 ? values.cwiseAbs().maxCoeff() : kNaN);
    for (Index k = 0; k < values.size(); ++k) {
      real(i, k) = values(k).real();
      imag(i, k) = values(k).imag();
    }
  }
  writer.WriteDoubles(group + "/max_multiplier_modulus", largest);
  writer.WriteMatrix(group + "/multipliers_real", real);
  writer.WriteMatrix(group + "/multipliers_imag", imag);
  writer.WriteInts(group + "/newton_iterations", iterations);

  const std::string sp = group + "/special_points";
  WriteSpecialPointColumns(writer, sp, branch, parameter);
  std::vector<double> critical_real, critical_imag, angle;
  for (const SpecialPoint& p : branch.special_points) {
    critical_real.push_back(p.critical_value.real());
    critical_imag.push_back(p.critical_value.imag());
    angle.push_back(p.type == SpecialPointType::kNeimarkSacker ? p.frequency : kNaN);
  }
  writer.WriteDoubles(sp + "/critical_real", critical_real);
  writer.WriteDoubles(sp + "/critical_imag", critical_imag);
  writer.WriteDoubles(sp + "/angle", angle);
}

}  // namespace rubcont
