#include "studies/flexible_thesis.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include <fmt/core.h>
#include <nlopt.hpp>

#include "models/units.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

constexpr double kBearingStiffness = 4.5e8;  // the thesis's "very stiff bearing" [N/m]
constexpr double kBearingDamping = 2.1e4;    // [N·s/m]

ShaftElement Steel(double outer, double inner) {
  ShaftElement e;
  e.outer_diameter = outer;
  e.inner_diameter = inner;
  e.youngs_modulus = 2.0684e11;
  e.shear_modulus = 7.929e10;
  e.density = 7833.0;
  return e;
}

// The first three forward modes of the assembled beams.
ThreeModes FirstThree(const BeamModel& beams) {
  const std::vector<StructureMode> modes = WhirlModes(Assemble(beams), 0.0, {});
  if (modes.size() < 3) throw std::runtime_error("fewer than three modes of positive frequency");
  ThreeModes out;
  for (std::size_t i = 0; i < 3; ++i) {
    out.hz[i] = modes[i].frequency_hz;
    out.damping_ratio[i] = modes[i].damping_ratio;
  }
  return out;
}

}  // namespace

ThreeModes XltrcPinnedModes(const FlexibleRubModel& model) {
  BeamModel beams = model.beams;
  for (const FlexibleContact& c : model.contacts) {
    beams.springs.push_back({c.rotor_shaft, c.rotor_node, c.stator_shaft, c.stator_node,
                             kBearingStiffness, kBearingDamping});
  }
  return FirstThree(beams);
}

ThreeModes XltrcStatorModes(const FlexibleRubModel& model) {
  const int stator = model.contacts.front().stator_shaft;
  BeamModel beams;
  beams.shafts = {model.beams.shafts[static_cast<std::size_t>(stator)]};
  for (Spring spring : model.beams.springs) {
    if (spring.shaft != stator || spring.other_shaft >= 0) continue;  // the supports only
    spring.shaft = 0;
    beams.springs.push_back(spring);
  }
  return FirstThree(beams);
}

std::array<TwoPointParams, 3> ThesisCases() {
  std::array<TwoPointParams, 3> cases{ThesisCaseAa(), ThesisCaseAa(), ThesisCaseCa()};
  cases[1].rotor_mass_center = 0.22;
  cases[1].rotor_inertia = 0.04;
  return cases;
}

ThesisTableTargets ThesisTables() {
  ThesisTableTargets t;
  t.pinned[0] = {{87.9, 133.8, 595.1}, {0.019, 0.029, 0.009}};
  t.pinned[1] = {{86.9, 127.9, 709.8}, {0.019, 0.028, 0.013}};
  t.pinned[2] = {{82.4, 115.4, 701.3}, {0.018, 0.025, 0.005}};
  t.stator = {{105.4, 143.0, 8232.9}, {0.023, 0.031, 0.0}};
  return t;
}

FlexibleRubModel ThesisGeometry::Model(const TwoPointParams& params, int modes) const {
  return FlexibleTwoPoint(params, rotor, stator, elements, modes);
}

namespace {

std::string GeometryText(const ThesisGeometry& g) {
  return fmt::format("rotor {:.2f} mm outer, bore ratio {:.3f}; stator {:.2f} mm outer, {:.2f} mm bore",
                     1e3 * g.rotor.outer_diameter, g.rotor.inner_diameter / g.rotor.outer_diameter,
                     1e3 * g.stator.outer_diameter, 1e3 * g.stator.inner_diameter);
}

}  // namespace

ThesisGeometryFit EvaluateThesisGeometry(const ThesisGeometry& geometry,
                                         const std::array<TwoPointParams, 3>& cases) {
  const ThesisTableTargets targets = ThesisTables();
  ThesisGeometryFit out;
  out.geometry = geometry;
  for (std::size_t c = 0; c < 3; ++c) {
    const FlexibleRubModel model = geometry.Model(cases[c], 0);
    out.pinned[c] = XltrcPinnedModes(model);
    out.objective += std::pow(std::log(out.pinned[c].hz[2] / targets.pinned[c].hz[2]), 2);
    if (c == 0) out.stator = XltrcStatorModes(model);  // the same stator in every case
  }
  out.objective += std::pow(std::log(out.stator.hz[2] / targets.stator.hz[2]), 2);
  out.message = fmt::format("{}; Σ(ln f/f_thesis)² = {:.3g} over the four bending modes",
                            GeometryText(geometry), out.objective);
  return out;
}

ThesisGeometryFit FitThesisGeometry(const std::array<TwoPointParams, 3>& cases) {
  const double bore = 2.0 * (cases[0].radius[0] + cases[0].clearance[0]);
  // x = (rotor outer diameter [m], rotor bore / outer, stator outer diameter [m]).
  auto geometry_of = [&](const std::vector<double>& x) {
    ThesisGeometry g;
    g.rotor = Steel(x[0], x[1] * x[0]);
    g.stator = Steel(x[2], bore);
    return g;
  };
  int evaluations = 0;
  std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& x) {
    ++evaluations;
    try {
      return EvaluateThesisGeometry(geometry_of(x), cases).objective;
    } catch (const std::invalid_argument&) {
      return 1e3;  // a body the shaft cannot be completed to
    }
  };
  nlopt::opt opt(nlopt::LN_BOBYQA, 3);
  // The box keeps the shafts inside sensible sizes; where a body cannot be completed (a shaft
  // heavier than it, or a disk of negative inertia) a point costs 1e3, which BOBYQA steers away
  // from.
  opt.set_lower_bounds({0.02, 0.3, bore + 0.005});
  opt.set_upper_bounds({0.09, 0.95, 0.2});
  opt.set_xtol_rel(1e-8);
  opt.set_maxeval(400);
  opt.set_min_objective(
      [](const std::vector<double>& x, std::vector<double>&, void* data) {
        return (*static_cast<std::function<double(const std::vector<double>&)>*>(data))(x);
      },
      &objective);
  std::vector<double> x = {0.05, 0.8, 0.13};
  double j = 0.0;
  int result = 0;
  try {
    result = static_cast<int>(opt.optimize(x, j));
  } catch (const nlopt::roundoff_limited&) {
    result = static_cast<int>(nlopt::ROUNDOFF_LIMITED);
  }
  ThesisGeometryFit fit = EvaluateThesisGeometry(geometry_of(x), cases);
  fit.evaluations = evaluations;
  fit.nlopt_result = result;
  fit.message += fmt::format(" in {} evaluations (NLopt {})", evaluations, result);
  return fit;
}

FlexibilityEffect CompareRigidFlexible(const RubStructure& rigid, const RubStructure& flexible,
                                       FrictionLawKind law,
                                       const RotatingWaveBranchOptions& options) {
  FlexibilityEffect out;
  out.rigid_coordinates = rigid.Coordinates();
  out.flexible_coordinates = flexible.Coordinates();
  auto start = SteadyClock::now();
  const std::vector<RotatingWaveBranch> a = ComputeRotatingWaveBranches(rigid, law, options);
  out.rigid_seconds = SecondsSince(start);
  start = SteadyClock::now();
  const std::vector<RotatingWaveBranch> b = ComputeRotatingWaveBranches(flexible, law, options);
  out.flexible_seconds = SecondsSince(start);
  auto label_of = [](const SpecialPoint& p) {
    return p.type == SpecialPointType::kEvent ? p.label : std::string(ToString(p.type));
  };
  // The label without contact names: where both contacts switch at once (a symmetric rotor) which
  // one the event names is a matter of round-off.
  auto anonymous = [&](std::string label) {
    for (const RubContact& c : rigid.contacts) {
      for (std::size_t at = label.find(c.name); at != std::string::npos; at = label.find(c.name)) {
        label.replace(at, c.name.size(), "*");
      }
    }
    return label;
  };
  // Each set's special points once (the same point may end two pieces or lie on two branches).
  struct Found {
    std::string pattern, label;
    SpecialPointType type;
    double rpm, hz, frequency;
  };
  auto points_of = [&](const std::vector<RotatingWaveBranch>& branches) {
    std::vector<Found> points;
    for (const RotatingWaveBranch& branch : branches) {
      const std::string pattern = PatternName(branch.normals);
      for (std::size_t i = 0; i < branch.branch.special_points.size(); ++i) {
        const SpecialPoint& p = branch.branch.special_points[i];
        const Found f{pattern, label_of(p), p.type, RadPerSecondToRpm(p.lambda),
                      branch.SpecialPrecessionHz(i), p.frequency};
        const bool known = std::any_of(points.begin(), points.end(), [&](const Found& g) {
          return g.pattern == f.pattern && g.label == f.label &&
                 std::abs(g.rpm - f.rpm) < 1e-6 * f.rpm;
        });
        if (!known) points.push_back(f);
      }
    }
    return points;
  };
  const std::vector<Found> from = points_of(a), to = points_of(b);
  // Pairs of the same kind within 10 % of the speed, at a distance |Δrpm|/rpm, plus for Hopf
  // points |ln| of the ratio of the critical eigenvalues' frequencies (within a factor 1.5): the
  // flexible modes add Hopf points of their own (A(a) tanh's Mode 1 whirl has them at 51.369 rpm,
  // 214 Hz, 51.609 rpm, 568 Hz, and 51.724 rpm, 2142 Hz, for the rigid 51.685 rpm, 242 Hz, and
  // 51.899 rpm, 579 Hz: the nearest speed alone took the third for the first). Then one to one,
  // nearest pairs first; a rigid point left without a partner is not found.
  struct Pair {
    double distance;
    std::size_t rigid, flexible;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < from.size(); ++i) {
    for (std::size_t j = 0; j < to.size(); ++j) {
      const Found &p = from[i], &q = to[j];
      if (p.pattern != q.pattern || p.type != q.type || anonymous(p.label) != anonymous(q.label) ||
          !(std::abs(q.rpm - p.rpm) < 0.1 * p.rpm)) {
        continue;
      }
      double distance = std::abs(q.rpm - p.rpm) / p.rpm;
      if (p.type == SpecialPointType::kHopf && p.frequency > 0.0 && q.frequency > 0.0) {
        const double log_ratio = std::abs(std::log(q.frequency / p.frequency));
        if (log_ratio > std::log(1.5)) continue;
        distance += log_ratio;
      }
      pairs.push_back({distance, i, j});
    }
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& x, const Pair& y) { return x.distance < y.distance; });
  for (const Found& p : from) out.points.push_back({p.pattern, p.label, p.rpm, p.hz});
  std::vector<bool> taken(to.size(), false);
  for (const Pair& pair : pairs) {
    MovedPoint& moved = out.points[pair.rigid];
    if (moved.found || taken[pair.flexible]) continue;
    taken[pair.flexible] = true;
    moved.found = true;
    moved.flexible_rpm = to[pair.flexible].rpm;
    moved.flexible_hz = to[pair.flexible].hz;
  }
  std::sort(out.points.begin(), out.points.end(), [](const MovedPoint& x, const MovedPoint& y) {
    return x.rigid_rpm < y.rigid_rpm;
  });
  return out;
}

}  // namespace rubcont
