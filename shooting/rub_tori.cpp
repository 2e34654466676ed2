#include "shooting/rub_tori.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {

namespace {

using Complex = std::complex<double>;

// Contact c's relative displacement d = u_rotor − u_stator (complex) at a state of either frame.
Complex Displacement(const RubStructure& structure, std::size_t c, const Vector& x) {
  const Index r = 2 * structure.contacts[c].rotor, s = 2 * structure.contacts[c].stator;
  return {x(r) - x(s), x(r + 1) - x(s + 1)};
}

// Throws std::invalid_argument, before any family is computed, where TorusLines would after it.
void CheckSamples(const RubTorusOptions& options) {
  if (options.samples < 4) {
    throw std::invalid_argument(
        fmt::format("RubTorusOptions: samples = {}: must be at least 4", options.samples));
  }
}

// on_torus_step for the family numbered `index` (none where there is none).
StepCallback FamilyStep(const std::function<bool(std::size_t, const Branch&)>& on_torus_step,
                        std::size_t index) {
  if (!on_torus_step) return {};
  return [&on_torus_step, index](const Branch& b) { return on_torus_step(index, b); };
}

}  // namespace

RubTorusLines TorusLines(const RubRotatingFrame& frame, int harmonics, const Vector& u,
                         double lambda, const IntegratorOptions& integrator, int samples,
                         CircleCoordinates coordinates) {
  if (samples < 4) {
    throw std::invalid_argument(fmt::format("TorusLines: samples = {}: must be at least 4", samples));
  }
  auto system = std::make_shared<RubRotatingFrame>(frame);
  InvariantCircleProblem circle(system, harmonics, OrbitKind::kRelative, integrator, coordinates);
  const double period = circle.Period(u, lambda), phi = circle.Rotation(u);
  const double rho = circle.RotationNumber(u);
  const RubStructure& structure = frame.structure();
  const std::size_t contacts = structure.contacts.size();
  const Index points = 2 * harmonics + 1;
  RubTorusLines lines;
  lines.carrier_hz = RadPerSecondToHz(frame.CarrierPrecession(period, phi));
  lines.first_hz = 1.0 / period;
  lines.second_hz = rho / period;
  lines.contacts.assign(contacts, {});
  for (auto& c : lines.contacts) {
    c.min_normal_force = kInfinity;
    c.max_normal_force = -kInfinity;
  }

  // G at (θ_j + 2πρ s_m, s_m): d of R_{−φ s_m} Φ_{s_m T}(u(θ_j)), s_m = m / samples (sampled to
  // s = 1, so that a fixed mesh is the map's).
  Vector times(samples + 1);
  for (int m = 0; m <= samples; ++m) times(m) = period * m / samples;
  std::vector<Eigen::MatrixXcd> grid(contacts, Eigen::MatrixXcd(points, samples));
  OdeIntegrator integrator_(*system, integrator);
  RubFixedFrame fixed(structure);
  fixed.SetParameter(lambda);
  Matrix states;
  for (Index j = 0; j < points; ++j) {
    const double theta = kTwoPi * static_cast<double>(j) / static_cast<double>(points);
    if (!integrator_.Sample(0.0, circle.PointAt(u, theta), times, states).Succeeded()) return lines;
    for (int m = 0; m < samples; ++m) {
      const Vector x = states.col(m);
      const Complex back = std::polar(1.0, -phi * m / samples);
      const std::vector<ContactEvaluation> evaluated = fixed.Contacts(frame.ToFixedFrame(times(m), x));
      for (std::size_t c = 0; c < contacts; ++c) {
        grid[c](j, m) = back * Displacement(structure, c, x);
        lines.contacts[c].min_normal_force =
            std::min(lines.contacts[c].min_normal_force, evaluated[c].normal_force);
        lines.contacts[c].max_normal_force =
            std::max(lines.contacts[c].max_normal_force, evaluated[c].normal_force);
      }
    }
  }
  // c_{l,k}: over θ for each s_m (undoing the shear e^{il2πρ s_m}), then over s.
  for (std::size_t c = 0; c < contacts; ++c) {
    double carrier = 0.0, best = -1.0;
    for (int l = -harmonics; l <= harmonics; ++l) {
      Eigen::VectorXcd over_s(samples);
      for (int m = 0; m < samples; ++m) {
        Complex sum = 0.0;
        for (Index j = 0; j < points; ++j) {
          const double theta = kTwoPi * static_cast<double>(j) / static_cast<double>(points);
          sum += grid[c](j, m) * std::polar(1.0, -l * theta);
        }
        over_s(m) = sum / static_cast<double>(points) *
                    std::polar(1.0, -kTwoPi * l * rho * m / samples);
      }
      for (int k = -samples / 2 + 1; k < samples / 2; ++k) {
        Complex sum = 0.0;
        for (int m = 0; m < samples; ++m) sum += over_s(m) * std::polar(1.0, -kTwoPi * k * m / samples);
        const double amplitude = std::abs(sum) / samples;
        if (l == 0 && k == 0) {
          carrier = amplitude;
        } else if (amplitude > best) {
          best = amplitude;
          lines.contacts[c].line_l = l;
          lines.contacts[c].line_k = k;
        }
      }
    }
    RubTorusLines::Contact& out = lines.contacts[c];
    out.line_hz = lines.carrier_hz - (out.line_k + out.line_l * rho) / period;
    out.line_ratio = best / std::max(carrier, 1e-300);
  }
  lines.valid = true;
  return lines;
}

namespace {

// `tori` with on_exponents reporting to options.on_work for the family numbered `family`.
TorusBranchOptions ForFamily(TorusBranchOptions tori, const RubTorusOptions& options,
                             std::size_t family) {
  if (options.on_work) {
    tori.on_exponents = [&options, family](std::size_t i, std::size_t n) {
      options.on_work(family, "exponents", i, n);
    };
  }
  return tori;
}

// The lines of every torus of the family numbered `family`, `tori` (TorusLines at each point).
std::vector<RubTorusLines> LinesOf(const RubRotatingFrame& frame, const TorusBranch& tori,
                                   const TorusBranchOptions& options, const RubTorusOptions& rub,
                                   std::size_t family) {
  std::vector<RubTorusLines> lines;
  for (std::size_t i = 0; i < tori.branch.points.size(); ++i) {
    if (rub.on_work) rub.on_work(family, "lines", i, tori.branch.points.size());
    lines.push_back(TorusLines(frame, tori.SolvedHarmonics(i), tori.SolvedCircle(i),
                               tori.branch.points[i].lambda, options.integrator, rub.samples,
                               options.coordinates));
  }
  return lines;
}

// The orbits a family shrank onto (ContinueCentreOrbits with `orbits`, shot with `shooting`), or
// ok = false with the reason.
CentreOrbits CentresOf(const RubStructure& structure, const RubRotatingFrame& frame,
                       const TorusBranch& tori, const ShootingOptions& shooting,
                       PeriodicOrbitBranchOptions orbits, const StepCallback& step) {
  if (!tori.ok || tori.end != TorusEnd::kShrinks) {
    CentreOrbits none;
    none.message = "the family did not shrink onto its centre";
    return none;
  }
  orbits.shooting = shooting;
  orbits.measures = RubFamilyMeasures(frame, shooting, 1, orbits.defect_check);
  orbits.test_functions = RubGrazingTests(structure);
  orbits.stop_at_grazing = true;
  orbits.on_step = step;
  return ContinueCentreOrbits(std::make_shared<RubRotatingFrame>(frame), tori, orbits);
}

}  // namespace

std::vector<TorusGrazing> RubTorusGrazing(const RubStructure& structure) {
  std::vector<TorusGrazing> tests;
  for (std::size_t c = 0; c < structure.contacts.size(); ++c) {
    const auto penetration = ContactPenetration(structure, c);
    const std::string& name = structure.contacts[c].name;
    tests.push_back({penetration, GrazingSide::kLiftOff, "lift_off_" + name});
    tests.push_back({penetration, GrazingSide::kTouchdown, "touchdown_" + name});
  }
  return tests;
}

void ReadLiftOff(const RubStructure& structure, const std::vector<RubTorusLines>& lines,
                 TorusBranch& tori) {
  if (tori.end == TorusEnd::kGrazing && tori.branch.status == BranchStatus::kGrazing) {
    const SpecialPoint& grazing = tori.branch.special_points.back();
    tori.end_note = fmt::format(
        "the torus grazes, located: {} at {:.4f} rpm (ρ = {:.6f}), the family's last torus",
        grazing.label, RadPerSecondToRpm(grazing.lambda),
        grazing.measures(tori.branch.MeasureIndex("rotation_number")));
    return;
  }
  if (tori.end != TorusEnd::kFailed || lines.empty() || !lines.back().valid) return;
  const RubTorusLines& last = lines.back();
  for (std::size_t c = 0; c < last.contacts.size(); ++c) {
    const RubTorusLines::Contact& k = last.contacts[c];
    if (k.max_normal_force > 0.0 && k.min_normal_force <= kLiftOffForceShare * k.max_normal_force) {
      tori.end = TorusEnd::kGrazing;
      tori.end_note = fmt::format(
          "the {} contact lifts off at {:.4f} rpm: its least normal force {:.2g} N of {:.4g} N at "
          "most over the last torus, beyond which the corrector failed ({})",
          structure.contacts[c].name, RadPerSecondToRpm(tori.branch.points.back().lambda),
          k.min_normal_force, k.max_normal_force, tori.end_note);
      return;
    }
  }
}

namespace {

// The tori from each located Neimark–Sacker point of result.orbits.orbits (computed in `frame`)
// that bounds a stable piece of it, with their lines, locked orbits and centre orbits.
void FollowNeimarkSackerTori(const RubStructure& structure, const RubRotatingFrame& frame,
                             const RubTorusOptions& options,
                             const std::function<bool(std::size_t, const Branch&)>& on_torus_step,
                             RubModulatedTori& result) {
  const PeriodicOrbitBranch& family = result.orbits.orbits;
  // The map's integrator: the family's segments' mesh over one whole period.
  TorusBranchOptions tori = options.tori;
  tori.integrator = JoinedIntegrator(family.shooting.integrator, family.segments);
  tori.grazing = RubTorusGrazing(structure);
  const std::vector<SpecialPoint>& special = family.branch.special_points;
  for (std::size_t k = 0; k < special.size(); ++k) {
    if (special[k].type != SpecialPointType::kNeimarkSacker || !special[k].converged ||
        !BoundsStablePiece(family.branch, special[k])) {
      continue;
    }
    const std::size_t index = result.tori.size();
    const StepCallback step = FamilyStep(on_torus_step, index);
    result.tori.push_back(ContinueToriFromNeimarkSacker(std::make_shared<RubRotatingFrame>(frame),
                                                        family, k, ForFamily(tori, options, index),
                                                        step));
    result.lines.push_back(LinesOf(frame, result.tori.back(), tori, options, index));
    ReadLiftOff(structure, result.lines.back(), result.tori.back());
    const TorusBranch& ended = result.tori.back();
    LockedOrbits locked;
    if (ended.ok && ended.end == TorusEnd::kLocking && !ended.branch.points.empty()) {
      locked = ContinueLockedOrbits(std::make_shared<RubRotatingFrame>(frame), family, ended, tori,
                                    step);
    } else {
      locked.message = "the family did not end in phase locking";
    }
    result.locked.push_back(std::move(locked));
    result.centres.push_back(
        CentresOf(structure, frame, ended, family.shooting, options.centre_orbits, step));
  }
}

}  // namespace

RubModulatedTori ContinueModulatedTori(
    const RubStructure& structure, const std::vector<RotatingWaveBranch>& branches,
    const RubHopfStart& start, const HopfOrbitOptions& orbits, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step) {
  Validate(options.tori);
  CheckSamples(options);
  RubModulatedTori result;
  result.orbits = ContinueModulatedOrbits(structure, branches, start, orbits, false);
  // The frame the family was computed in (ContinueModulatedOrbits).
  FollowNeimarkSackerTori(structure, RubRotatingFrame(structure, start.precession, start.speed),
                          options, on_torus_step, result);
  return result;
}

RubModulatedTori ContinueTransientOrbitTori(
    const RubStructure& structure, const RubTransientOrbits& orbits, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step) {
  Validate(options.tori);
  CheckSamples(options);
  RubModulatedTori result;
  result.orbits = orbits.family;
  if (!orbits.start.converged) return result;
  // The frame ContinueTransientOrbits computed the family in.
  const RubRotatingFrame frame(structure, orbits.start.frame_rate,
                               orbits.family.orbits.start_lambda);
  FollowNeimarkSackerTori(structure, frame, options, on_torus_step, result);
  return result;
}

RubTransientTori ContinueTransientTori(
    const RubStructure& structure, double omega, double frame_rate, const Vector& fixed_state,
    const ModulatedTorusOptions& start, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step) {
  TorusBranchOptions tori = options.tori;
  tori.harmonics = start.harmonics;
  tori.coordinates = start.coordinates;
  Validate(tori);
  CheckSamples(options);
  RubTransientTori result;
  result.start = SolveModulatedTorus(structure, omega, frame_rate, fixed_state, start);
  if (!result.start.converged) return result;
  tori.harmonics = result.start.harmonics;  // refined in K (ModulatedTorusOptions::max_harmonics)
  tori.integrator = JoinedIntegrator(tori.integrator, result.start.laps);
  tori.grazing = RubTorusGrazing(structure);
  const RubRotatingFrame frame(structure, frame_rate, omega);
  for (const int direction : {-1, +1}) {
    tori.continuation.direction = direction;
    // Upwards from the downward family's first torus: the start corrected by `tori.integrator`
    // once (30–60 s on C(a) at 49 rpm), not twice.
    // (Its circle at the start's K: the downward family may have refined it further on.)
    const bool corrected = !result.tori.empty() && result.tori[0].ok &&
                           !result.tori[0].branch.points.empty();
    const std::size_t index = result.tori.size();
    result.tori.push_back(ContinueTori(
        std::make_shared<RubRotatingFrame>(frame), OrbitKind::kRelative,
        corrected ? result.tori[0].SolvedCircle(0) : result.start.u,
        corrected ? result.tori[0].branch.points.front().lambda : omega,
        ForFamily(tori, options, index), FamilyStep(on_torus_step, index)));
    result.lines.push_back(LinesOf(frame, result.tori.back(), tori, options, index));
    ReadLiftOff(structure, result.lines.back(), result.tori.back());
    ShootingOptions shooting = options.centre_orbits.shooting;
    shooting.segments *= result.start.laps;
    result.centres.push_back(CentresOf(structure, frame, result.tori.back(), shooting,
                                       options.centre_orbits, FamilyStep(on_torus_step, index)));
  }
  return result;
}

}  // namespace rubcont
