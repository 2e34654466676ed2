#include "shooting/rub_orbits.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"

namespace rubcont {

namespace {

// The fixed-frame state of every sample, and the contact quantities there.
struct FixedFrameOrbit {
  std::vector<Vector> states;
  std::vector<std::vector<ContactEvaluation>> contacts;
};

class OrbitInFixedFrame {
 public:
  explicit OrbitInFixedFrame(const RubRotatingFrame& frame)
      : frame_(frame), fixed_(frame.structure()) {}

  FixedFrameOrbit Evaluate(const OrbitSamples& orbit) {
    FixedFrameOrbit out;
    fixed_.SetParameter(orbit.parameter);
    for (Index j = 0; j < orbit.times.size(); ++j) {
      out.states.push_back(frame_.ToFixedFrame(orbit.times(j), orbit.states.col(j)));
      out.contacts.push_back(fixed_.Contacts(out.states.back()));
    }
    return out;
  }
  double CarrierHz(const OrbitSamples& orbit) const {
    return RadPerSecondToHz(frame_.CarrierPrecession(orbit.period, orbit.rotation));
  }
  const RubStructure& structure() const { return frame_.structure(); }

 private:
  RubRotatingFrame frame_;
  RubFixedFrame fixed_;
};

// Backward precession rate −Im(ḋ/d) [rad/s] of contact c's relative displacement at a fixed-frame
// state; 0 at d = 0.
double Precession(const RubStructure& structure, std::size_t c, const Vector& x) {
  const Index n = structure.Coordinates();
  const Index r = 2 * structure.contacts[c].rotor, s = 2 * structure.contacts[c].stator;
  const std::complex<double> d(x(r) - x(s), x(r + 1) - x(s + 1));
  const std::complex<double> v(x(2 * n + r) - x(2 * n + s), x(2 * n + r + 1) - x(2 * n + s + 1));
  return std::abs(d) > 0.0 ? -(v / d).imag() : 0.0;
}

enum class ContactQuantity { kPrecessionHz, kNormalForce, kPenetration };

OrbitMeasure ContactExtreme(std::shared_ptr<OrbitInFixedFrame> view, std::size_t c, bool maximum,
                            ContactQuantity quantity, std::string name) {
  return {std::move(name), [view, c, maximum, quantity](const OrbitSamples& orbit) {
            const FixedFrameOrbit fixed = view->Evaluate(orbit);
            double extreme = maximum ? -kInfinity : kInfinity;
            for (std::size_t j = 0; j < fixed.states.size(); ++j) {
              double value = 0.0;
              switch (quantity) {
                case ContactQuantity::kPrecessionHz:
                  value = RadPerSecondToHz(Precession(view->structure(), c, fixed.states[j]));
                  break;
                case ContactQuantity::kNormalForce: value = fixed.contacts[j][c].normal_force; break;
                case ContactQuantity::kPenetration: value = fixed.contacts[j][c].penetration; break;
              }
              extreme = maximum ? std::max(extreme, value) : std::min(extreme, value);
            }
            return extreme;
          }};
}

}  // namespace

std::vector<OrbitMeasure> RubOrbitMeasures(const RubRotatingFrame& frame, bool defect_check) {
  auto view = std::make_shared<OrbitInFixedFrame>(frame);
  std::vector<OrbitMeasure> measures;
  measures.push_back(
      {"precession_hz", [view](const OrbitSamples& orbit) { return view->CarrierHz(orbit); }});
  measures.push_back(
      {"modulation_hz", [](const OrbitSamples& orbit) { return 1.0 / orbit.period; }});
  // The orbit checked by an explicit Dormand–Prince 5(4) at 1e-12 (state only): what a fixed
  // collocation mesh cannot see in itself. Decision: explicit, not the CVODES BDF ≤ 2 at 1e-11 it
  // replaced (until 2026-11-30), which damps the lightly damped contact modes the Gauss orbit
  // carries and erred by its own error: on A(a)'s whip family to its grazing (bench/
  // whip_family_bench, curved, adapted 400 intervals, one run, 58 orbits) BDF ≤ 2 gave 1.0e-8 –
  // 3.6e-8 on the 12 orbits whose defect under Dormand–Prince at 1e-12 is 1.4e-11 – 7.0e-9, and
  // 1.1 – 92 times less than it on 41 of the 42 whose defect is 1.5e-7 – 1.9e-5 (1.5 times more
  // on one; Dormand–Prince at 1e-10 the same to 2 % there), and cost 18 s of the family's 50
  // against 0.9 s. Its own error at 1e-12 is of the order of 3e-10 (the flexible A(a)'s first 13
  // orbits: largest 2.8e-10, against 1.2e-11 at 1e-13).
  if (defect_check) {
    IntegratorOptions check;
    check.method = IntegrationMethod::kDormandPrince;
    check.relative_tolerance = check.absolute_tolerance = 1e-12;
    check.max_steps = 2000000;
    measures.push_back(PeriodicityDefect(std::make_shared<RubRotatingFrame>(frame), check));
  }
  if (frame.HasMirrorSymmetry()) {
    measures.push_back(MirrorAsymmetry(std::make_shared<RubRotatingFrame>(frame)));
  }
  const auto& contacts = frame.structure().contacts;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const std::string& name = contacts[c].name;
    measures.push_back(ContactExtreme(view, c, false, ContactQuantity::kPrecessionHz,
                                      "min_precession_hz_" + name));
    measures.push_back(ContactExtreme(view, c, true, ContactQuantity::kPrecessionHz,
                                      "max_precession_hz_" + name));
    measures.push_back(ContactExtreme(view, c, false, ContactQuantity::kNormalForce,
                                      "min_normal_force_" + name));
    measures.push_back(ContactExtreme(view, c, true, ContactQuantity::kNormalForce,
                                      "max_normal_force_" + name));
    measures.push_back(ContactExtreme(view, c, true, ContactQuantity::kPenetration,
                                      "max_penetration_" + name));
  }
  return measures;
}

std::vector<std::string> UntrustedOrbits(const Branch& branch, const RubStructure& structure,
                                         double max_penetration) {
  std::vector<std::string> untrusted(branch.points.size());
  for (const RubContact& contact : structure.contacts) {
    const Index k = branch.MeasureIndex("max_penetration_" + contact.name);
    const double clearance = contact.geometry.clearance;
    for (std::size_t i = 0; i < branch.points.size(); ++i) {
      const double depth = branch.points[i].measures(k);
      if (!untrusted[i].empty() || !(depth > max_penetration * clearance)) continue;
      untrusted[i] = fmt::format(
          "the {} contact penetrates {:.3g} m, {:.3g} × its clearance (limit {:g}): beyond the "
          "small overlap of the contact law",
          contact.name, depth, depth / clearance, max_penetration);
    }
  }
  return untrusted;
}

std::function<double(ConstVectorRef)> ContactPenetration(const RubStructure& structure,
                                                         std::size_t c) {
  auto fixed = std::make_shared<const RubFixedFrame>(structure);
  return [fixed, c](ConstVectorRef x) {
    Vector h(fixed->SwitchingCount());
    fixed->SwitchingFunctions(0.0, x, h);
    return h(static_cast<Index>(c));
  };
}

std::vector<OrbitTestFunction> RubGrazingTests(const RubStructure& structure) {
  std::vector<OrbitTestFunction> tests;
  for (std::size_t c = 0; c < structure.contacts.size(); ++c) {
    const auto penetration = ContactPenetration(structure, c);
    const std::string& name = structure.contacts[c].name;
    tests.push_back(Grazing(penetration, GrazingSide::kLiftOff, "lift_off_" + name));
    tests.push_back(Grazing(penetration, GrazingSide::kTouchdown, "touchdown_" + name));
  }
  return tests;
}

std::vector<RubHopfStart> StableBoundaryHopfPoints(const std::vector<RotatingWaveBranch>& branches,
                                                   Index coordinates) {
  std::vector<RubHopfStart> starts;
  for (const RotatingWaveBranch& b : branches) {
    const std::vector<BranchPoint>& points = b.branch.points;
    for (std::size_t i = 0; i < b.branch.special_points.size(); ++i) {
      const SpecialPoint& p = b.branch.special_points[i];
      if (p.type != SpecialPointType::kHopf || !p.converged || !BoundsStablePiece(b.branch, p)) {
        continue;
      }
      // The special point lies between points[index] and points[index + 1].
      const auto k = static_cast<std::size_t>(p.index);
      const BranchPoint *low = &points[k], *high = &points[k + 1];
      if (low->lambda > high->lambda) std::swap(low, high);
      const double slack = 1e-9 * std::max(1.0, std::abs(p.lambda));
      if (p.lambda < low->lambda - slack || p.lambda > high->lambda + slack) continue;
      RubHopfStart start;
      start.branch = b.name;
      start.special_point = i;
      start.speed = p.lambda;
      start.precession = p.u(2 * coordinates);
      start.modulation = p.frequency;
      start.stable_below = low->num_unstable == 0;
      // Mirror images are located separately: equal to the location's precision, not bit for bit.
      const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::abs(b); };
      const bool mirror = std::any_of(starts.begin(), starts.end(), [&](const RubHopfStart& s) {
        return near(s.speed, start.speed) && near(s.precession, start.precession) &&
               near(s.modulation, start.modulation);
      });
      if (!mirror) starts.push_back(start);
    }
  }
  std::sort(starts.begin(), starts.end(),
            [](const RubHopfStart& a, const RubHopfStart& b) { return a.speed < b.speed; });
  return starts;
}

std::vector<OrbitMeasure> RubFamilyMeasures(const RubRotatingFrame& frame,
                                            const ShootingOptions& shooting, int laps,
                                            bool defect_check) {
  std::vector<OrbitMeasure> measures = RubOrbitMeasures(frame, defect_check);
  const IntegratorOptions& integrator = shooting.integrator;
  if (integrator.method == IntegrationMethod::kGaussCollocation) {
    measures.push_back(UnresolvedMultiplier(
        std::make_shared<RubRotatingFrame>(frame), integrator.collocation_stages,
        JoinedIntegrator(integrator, static_cast<long>(shooting.segments) * laps)
            .collocation_steps));
  }
  return measures;
}

namespace {

// The side branches of result.orbits (ContinueModulatedOrbits with switch_at_branch_points).
void FollowSideBranches(RubRotatingFrame& frame, const PeriodicOrbitBranchOptions& options,
                        const StepCallback& on_step, RubModulatedOrbits& result) {
  const std::vector<SpecialPoint>& special = result.orbits.branch.special_points;
  for (std::size_t k = 0; k < special.size(); ++k) {
    // A branch point not located to tolerance is still tried on a mirror-symmetric rotor: the
    // symmetry fixes the new direction, and ComputeBranchSwitch says when the point is too far.
    if (special[k].type != SpecialPointType::kBranchPoint ||
        !(special[k].converged || frame.HasMirrorSymmetry())) {
      continue;
    }
    // The far end of a bubble already followed from its near end: not again.
    const double lambda = special[k].lambda;
    const bool reached = std::any_of(
        result.switches.begin(), result.switches.end(),
        [lambda](const OrbitBranchSwitch& s) { return s.RejoinedNear(lambda); });
    if (reached) continue;
    result.switches.push_back(
        ContinueOrbitsFromBranchPoint(frame, result.orbits, k, options, on_step));
  }
  for (std::size_t k = 0; k < special.size(); ++k) {
    if (special[k].type != SpecialPointType::kPeriodDoubling || !special[k].converged ||
        !BoundsStablePiece(result.orbits.branch, special[k])) {
      continue;
    }
    PeriodicOrbitBranchOptions doubled = options;
    doubled.measures = RubFamilyMeasures(frame, options.shooting, 2, options.defect_check);
    result.doublings.push_back(
        ContinueOrbitsFromPeriodDoubling(frame, result.orbits, k, doubled, 1e-3, on_step));
  }
}

void RequireBalanced(const char* function, const RubStructure& structure) {
  if (structure.imbalance != 0.0) {
    throw std::invalid_argument(fmt::format(
        "{}: imbalance = {} kg·m: the co-rotating frame needs a balanced rotor (the imbalance "
        "turns forward, the frame backward)", function, structure.imbalance));
  }
}

}  // namespace

RubModulatedOrbits ContinueModulatedOrbits(const RubStructure& structure,
                                           const std::vector<RotatingWaveBranch>& branches,
                                           const RubHopfStart& start, HopfOrbitOptions options,
                                           bool switch_at_branch_points) {
  RequireBalanced("ContinueModulatedOrbits", structure);
  const auto branch = std::find_if(branches.begin(), branches.end(),
                                   [&](const RotatingWaveBranch& b) { return b.name == start.branch; });
  if (branch == branches.end() || start.special_point >= branch->branch.special_points.size() ||
      branch->branch.special_points[start.special_point].type != SpecialPointType::kHopf) {
    throw std::invalid_argument(fmt::format(
        "ContinueModulatedOrbits: no Hopf point {} on a branch named \"{}\"", start.special_point,
        start.branch));
  }
  const SpecialPoint& p = branch->branch.special_points[start.special_point];
  const Index nc = structure.Coordinates();
  RubRotatingFrame frame(structure, start.precession, start.speed);
  // The rotating wave as an equilibrium of the frame: its positions, at rest.
  SpecialPoint hopf = p;
  hopf.u = Vector::Zero(4 * nc);
  hopf.u.head(2 * nc) = p.u.head(2 * nc);
  options.kind = OrbitKind::kRelative;
  if (options.orbits.measures.empty()) {
    options.orbits.measures =
        RubFamilyMeasures(frame, options.orbits.shooting, 1, options.orbits.defect_check);
  }
  options.orbits.test_functions = RubGrazingTests(structure);
  RubModulatedOrbits result;
  result.hopf = start;
  result.orbits = ContinueOrbitsFromHopf(frame, hopf, options);
  if (switch_at_branch_points) FollowSideBranches(frame, options.orbits, options.on_step, result);
  return result;
}

RubTransientOrbits ContinueTransientOrbits(const RubStructure& structure, double omega,
                                           double frame_rate, const Vector& fixed_state,
                                           const ModulatedOrbitOptions& start,
                                           PeriodicOrbitBranchOptions options,
                                           int family_max_steps, bool switch_at_branch_points) {
  RequireBalanced("ContinueTransientOrbits", structure);
  RubTransientOrbits result;
  result.start = SolveModulatedOrbit(structure, omega, frame_rate, fixed_state, start);
  if (!result.start.converged) return result;
  RubRotatingFrame frame(structure, frame_rate, omega);
  options.shooting = start.shooting;
  options.measures = RubFamilyMeasures(frame, options.shooting, 1, options.defect_check);
  options.test_functions = RubGrazingTests(structure);
  PeriodicOrbitBranchOptions family = options;
  family.stop_round_closed_curve = true;
  family.continuation.bounds.max_steps = family_max_steps;
  result.family.orbits =
      ContinuePeriodicOrbits(frame, OrbitKind::kRelative, StartOf(result.start, omega), family);
  if (switch_at_branch_points) FollowSideBranches(frame, options, options.on_step, result.family);
  return result;
}

OrbitPeriodDoubling ContinueTransientDoubling(const RubStructure& structure,
                                              const RubTransientOrbits& orbits,
                                              std::size_t special_point,
                                              PeriodicOrbitBranchOptions options) {
  RequireBalanced("ContinueTransientDoubling", structure);
  if (!orbits.start.converged) {
    throw std::invalid_argument(
        "ContinueTransientDoubling: the start did not converge: there is no family to double");
  }
  const PeriodicOrbitBranch& family = orbits.family.orbits;
  RubRotatingFrame frame(structure, orbits.start.frame_rate, family.start_lambda);
  options.shooting = family.shooting;
  options.measures = RubFamilyMeasures(frame, family.shooting, 2, options.defect_check);
  options.test_functions = RubGrazingTests(structure);
  return ContinueOrbitsFromPeriodDoubling(frame, family, special_point, options, 1e-3,
                                          options.on_step);
}

}  // namespace rubcont
