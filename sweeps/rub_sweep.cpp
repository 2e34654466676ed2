#include "sweeps/rub_sweep.h"
#include "models/units.h"
#include "solvers/constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/core.h>

namespace rubcont {

namespace {

// Why a record is untrusted whose contact penetrates `depth` (beyond the limit).
std::string TooDeep(const RubContact& contact, double depth, double max_penetration) {
  return fmt::format(
      "the {} contact penetrates {:.3g} m, {:.3g} × its clearance (limit {:g}): beyond the small "
      "overlap of the contact law, or an integration that let the rotor sink into the stator",
      contact.name, depth, depth / contact.geometry.clearance, max_penetration);
}

}  // namespace

RubSweepObservables::RubSweepObservables(RubFixedFrame& system) : system_(system) {}

int RubSweepObservables::Channels() const {
  return static_cast<int>(system_.structure().contacts.size());
}

std::string RubSweepObservables::ChannelName(int channel) const {
  return system_.structure().contacts.at(static_cast<std::size_t>(channel)).name;
}

std::string RubSweepObservables::MeasureName(int measure) const {
  switch (measure) {
    case kSlipVelocityMeasure: return "slip_velocity";
    case kNormalForceMeasure: return "normal_force";
    case kPenetrationMeasure: return "penetration";
  }
  throw std::invalid_argument(fmt::format("RubSweepObservables: measure {} does not exist", measure));
}

void RubSweepObservables::Observe(double /*t*/, ConstVectorRef x, SweepObservation& out) {
  const std::vector<ContactEvaluation> contacts = system_.Contacts(x);
  const auto& structure = system_.structure();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const RubContact& c = structure.contacts[k];
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    const Index i = static_cast<Index>(k);
    out.signal(i) = std::complex<double>(x(r) - x(s), x(r + 1) - x(s + 1));
    out.active[k] = contacts[k].touching ? 1 : 0;
    out.measures(i, kSlipVelocityMeasure) = contacts[k].slip_velocity;
    out.measures(i, kNormalForceMeasure) = contacts[k].normal_force;
    out.measures(i, kPenetrationMeasure) = contacts[k].penetration;
  }
}

Vector RubImpulseIncrement(const RubStructure& structure, double impulse) {
  if (!(impulse >= 0.0) || !std::isfinite(impulse)) {
    throw std::invalid_argument(
        fmt::format("RubImpulseIncrement: impulse = {} N·s: must be finite and non-negative", impulse));
  }
  const Index n = structure.Coordinates();
  const Vector dv = structure.mass.ldlt().solve(structure.imbalance_weights * impulse);
  Vector dx = Vector::Zero(4 * n);
  for (Index i = 0; i < n; ++i) dx(2 * n + 2 * i) = dv(i);  // x components of the velocities
  return dx;
}

SweepOptions LongSettleOptions(double omega, double dwell) {
  SweepOptions options;
  options.parameters = {omega};
  options.dwell = dwell;
  options.window = 0.5;
  options.analysis_length = 1.0;
  options.integrator.max_order = 2;
  options.integrator.relative_tolerance = options.integrator.absolute_tolerance = 1e-6;
  options.integrator.max_steps = 100000000;
  return options;
}

RubSettledSpeed SettleAtSpeed(const RubStructure& structure, const SweepOptions& options,
                              double impulse) {
  if (options.parameters.size() != 1) {
    throw std::invalid_argument(fmt::format(
        "SettleAtSpeed: options.parameters holds {} speeds: must hold exactly one",
        options.parameters.size()));
  }
  RubFixedFrame system(structure);
  RubSweepObservables observables(system);
  SweepStepper stepper(system, observables, options, RubImpulseIncrement(structure, impulse));
  stepper.Step();
  RubSettledSpeed out;
  out.state = stepper.state();
  out.point = stepper.points().back();
  out.precession_hz = out.point.channels.empty() ? kNaN : -out.point.channels[0].peak.frequency;
  out.settled = out.point.status == SweepPointStatus::kSettled;
  return out;
}

double SpeedCount(double from_rpm, double to_rpm, double step_rpm) {
  if (!std::isfinite(from_rpm) || !std::isfinite(to_rpm) || !(from_rpm > 0.0) || !(to_rpm > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "SpeedSchedule: from {} rpm to {} rpm: both must be positive and finite", from_rpm, to_rpm));
  }
  if (!(step_rpm > 0.0) || !std::isfinite(step_rpm)) {
    throw std::invalid_argument(
        fmt::format("SpeedSchedule: step = {} rpm: must be positive and finite", step_rpm));
  }
  return std::floor(std::abs(to_rpm - from_rpm) / step_rpm + 1e-9) + 1.0;
}

std::vector<double> SpeedSchedule(double from_rpm, double to_rpm, double step_rpm) {
  const double count = SpeedCount(from_rpm, to_rpm, step_rpm);
  const double sign = to_rpm >= from_rpm ? 1.0 : -1.0;
  std::vector<double> speeds;
  speeds.reserve(static_cast<std::size_t>(count));
  for (long i = 0; i < static_cast<long>(count); ++i) {
    speeds.push_back(from_rpm + sign * step_rpm * static_cast<double>(i));
  }
  return speeds;
}

const char* ToString(RubRegime regime) {
  switch (regime) {
    case RubRegime::kUnknown: return "unknown";
    case RubRegime::kNoContact: return "no_contact";
    case RubRegime::kIntermittent: return "intermittent";
    case RubRegime::kWhirl: return "whirl";
    case RubRegime::kWhip: return "whip";
  }
  return "?";
}

std::optional<RubRegime> RubRegimeNamed(const std::string& name) {
  for (RubRegime r : {RubRegime::kUnknown, RubRegime::kNoContact, RubRegime::kIntermittent, RubRegime::kWhirl,
                      RubRegime::kWhip}) {
    if (name == ToString(r)) return r;
  }
  return std::nullopt;
}

const char* ToString(RubJumpKind kind) {
  switch (kind) {
    case RubJumpKind::kWhirlToWhip: return "whirl_to_whip";
    case RubJumpKind::kWhipToWhirl: return "whip_to_whirl";
    case RubJumpKind::kContactLost: return "contact_lost";
    case RubJumpKind::kContactRegained: return "contact_regained";
    case RubJumpKind::kFrequencyJump: return "frequency_jump";
  }
  return "?";
}

void Validate(const RubRegimeOptions& o) {
  if (!(o.rolling_slip_tolerance > 0.0 && o.rolling_slip_tolerance < 1.0)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.rolling_slip_tolerance = {}: must lie in (0, 1)", o.rolling_slip_tolerance));
  }
  if (!(o.rolling_micro_slip >= 0.0) || !std::isfinite(o.rolling_micro_slip)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.rolling_micro_slip = {}: must be finite and non-negative", o.rolling_micro_slip));
  }
  if (!(o.whirl_tolerance >= 0.0 && o.whirl_tolerance < 1.0)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.whirl_tolerance = {}: must lie in [0, 1)", o.whirl_tolerance));
  }
  if (!(o.frequency_jump_hz > 0.0) || !std::isfinite(o.frequency_jump_hz)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.frequency_jump_hz = {}: must be positive and finite", o.frequency_jump_hz));
  }
  if (!(o.max_penetration > 0.0) || !std::isfinite(o.max_penetration)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.max_penetration = {}: must be positive and finite", o.max_penetration));
  }
  if (!(o.min_contact_fraction >= 0.0 && o.min_contact_fraction <= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "RubRegimeOptions.min_contact_fraction = {}: must lie in [0, 1]", o.min_contact_fraction));
  }
}

RubSweepRegimes ClassifySweep(const RubStructure& structure, const std::vector<SweepPoint>& points,
                              const RubRegimeOptions& options) {
  Validate(options);
  const std::size_t m = structure.contacts.size();
  RubSweepRegimes out;
  out.regime.assign(m, std::vector<RubRegime>(points.size(), RubRegime::kUnknown));
  out.precession_hz.assign(m, std::vector<double>(points.size(), kNaN));
  out.slip_ratio.assign(m, std::vector<double>(points.size(), kNaN));
  out.untrusted.assign(points.size(), "");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& p = points[i];
    if (p.status == SweepPointStatus::kIntegrationFailure || p.channels.size() != m) continue;
    const double rotation_hz = RadPerSecondToHz(p.parameter);
    for (std::size_t k = 0; k < m; ++k) {
      const ChannelSummary& c = p.channels[k];
      if (c.measures.size() <= static_cast<std::size_t>(kSlipVelocityMeasure)) {
        throw std::invalid_argument(fmt::format(
            "ClassifySweep: point {} ({} rpm), contact {}: {} measures, the slip velocity (measure {}) "
            "is missing", i, RadPerSecondToRpm(p.parameter), k, c.measures.size(), kSlipVelocityMeasure));
      }
      const double bp = c.peak.found ? -c.peak.frequency : kNaN;
      out.precession_hz[k][i] = bp;
      const ContactGeometry& g = structure.contacts[k].geometry;
      if (c.measures.size() > static_cast<std::size_t>(kPenetrationMeasure) &&
          c.measures[kPenetrationMeasure].max > options.max_penetration * g.clearance && out.untrusted[i].empty()) {
        out.untrusted[i] = TooDeep(structure.contacts[k], c.measures[kPenetrationMeasure].max,
                                   options.max_penetration);
      }
      const double rolling_hz = g.radius / g.clearance * rotation_hz;
      if (!(c.active_fraction > 0.0) || !(bp > 0.0)) {
        out.regime[k][i] = RubRegime::kNoContact;
        continue;
      }
      const double slip_ratio =
          std::abs(c.measures[kSlipVelocityMeasure].mean) / (g.radius * std::abs(p.parameter));
      out.slip_ratio[k][i] = slip_ratio;
      if (c.active_fraction < options.min_contact_fraction) {
        out.regime[k][i] = RubRegime::kIntermittent;
        continue;
      }
      const double largest_rolling_slip =
          std::max(options.rolling_slip_tolerance * g.radius * std::abs(p.parameter),
                   options.rolling_micro_slip * structure.law.velocity_scale);
      const bool rolls = std::abs(c.measures[kSlipVelocityMeasure].mean) <= largest_rolling_slip &&
                         std::abs(bp - rolling_hz) <= options.whirl_tolerance * rolling_hz;
      out.regime[k][i] = rolls ? RubRegime::kWhirl : RubRegime::kWhip;
    }
  }
  // Jumps between successive classified speeds.
  for (std::size_t k = 0; k < m; ++k) {
    std::size_t last = points.size();  // the previous classified point
    for (std::size_t i = 0; i < points.size(); ++i) {
      const RubRegime now = out.regime[k][i];
      if (now == RubRegime::kUnknown) continue;
      if (last < points.size()) {
        const RubRegime before = out.regime[k][last];
        RubSweepJump jump;
        jump.contact = static_cast<int>(k);
        jump.speed_from_rpm = RadPerSecondToRpm(points[last].parameter);
        jump.speed_to_rpm = RadPerSecondToRpm(points[i].parameter);
        jump.precession_from_hz = before == RubRegime::kNoContact ? kNaN : out.precession_hz[k][last];
        jump.precession_to_hz = now == RubRegime::kNoContact ? kNaN : out.precession_hz[k][i];
        jump.settled = points[last].status == SweepPointStatus::kSettled &&
                       points[i].status == SweepPointStatus::kSettled;
        jump.trusted = out.untrusted[last].empty() && out.untrusted[i].empty();
        // Intermittent contact counts as lost contact for the jumps.
        const auto lost = [](RubRegime r) {
          return r == RubRegime::kNoContact || r == RubRegime::kIntermittent;
        };
        bool found = true;
        if (lost(before) && lost(now)) {
          found = false;
        } else if (before == now) {  // whirl → whirl or whip → whip: off both trends?
          const double before_hz = out.precession_hz[k][last], now_hz = out.precession_hz[k][i];
          const double off_whip_trend = std::abs(now_hz - before_hz);
          const double off_whirl_trend =
              std::abs(now_hz - before_hz * points[i].parameter / points[last].parameter);
          found = std::min(off_whip_trend, off_whirl_trend) > options.frequency_jump_hz;
          jump.kind = RubJumpKind::kFrequencyJump;
        } else if (lost(before)) {
          jump.kind = RubJumpKind::kContactRegained;
        } else if (lost(now)) {
          jump.kind = RubJumpKind::kContactLost;
        } else {
          jump.kind = now == RubRegime::kWhip ? RubJumpKind::kWhirlToWhip : RubJumpKind::kWhipToWhirl;
        }
        if (found) out.jumps.push_back(jump);
      }
      last = i;
    }
  }
  // Schedule order, then contact.
  std::stable_sort(out.jumps.begin(), out.jumps.end(), [&](const RubSweepJump& a, const RubSweepJump& b) {
    const bool up = points.size() < 2 || points.back().parameter >= points.front().parameter;
    if (a.speed_to_rpm != b.speed_to_rpm) return up ? a.speed_to_rpm < b.speed_to_rpm : a.speed_to_rpm > b.speed_to_rpm;
    return a.contact < b.contact;
  });
  return out;
}

std::string Describe(const RubStructure& structure, const ArrivalTarget& target) {
  const std::string what = std::isfinite(target.precession_above_hz)
                               ? fmt::format("precession above {:g} Hz", target.precession_above_hz)
                               : std::string(ToString(target.regime));
  switch (target.contacts) {
    case ArrivalContacts::kEvery: return what + " on every contact";
    case ArrivalContacts::kAny: return what + " on any contact";
    case ArrivalContacts::kOne: break;
  }
  return fmt::format("{} on the {} contact", what, structure.contacts.at(static_cast<std::size_t>(target.contact)).name);
}

bool Arrived(const RubSweepRegimes& regimes, std::size_t point, const ArrivalTarget& target) {
  const int contacts = static_cast<int>(regimes.regime.size());
  const bool by_precession = std::isfinite(target.precession_above_hz);
  auto there = [&](int k) {
    const auto c = static_cast<std::size_t>(k);
    return by_precession ? regimes.precession_hz[c][point] > target.precession_above_hz
                         : regimes.regime[c][point] == target.regime;
  };
  int in_target = 0;
  for (int k = 0; k < contacts; ++k) in_target += there(k) ? 1 : 0;
  switch (target.contacts) {
    case ArrivalContacts::kEvery: return in_target == contacts;
    case ArrivalContacts::kAny: return in_target > 0;
    case ArrivalContacts::kOne: return there(target.contact);
  }
  return false;
}

std::vector<RubArrival> RubArrivals(const RubStructure& structure,
                                    const std::vector<EnsembleCopy>& copies, const ArrivalTarget& target,
                                    const RubRegimeOptions& options) {
  const int contacts = static_cast<int>(structure.contacts.size());
  if (target.contacts == ArrivalContacts::kOne && (target.contact < 0 || target.contact >= contacts)) {
    throw std::invalid_argument(fmt::format("RubArrivals: contact {} of {}", target.contact, contacts));
  }
  std::vector<RubArrival> out;
  out.reserve(copies.size());
  for (const EnsembleCopy& copy : copies) {
    RubArrival a;
    a.failed = copy.failed;
    a.regimes = ClassifySweep(structure, copy.points, options);
    double t = 0.0;
    for (std::size_t i = 0; i < copy.points.size(); ++i) {
      t += copy.points[i].simulated_time;
      if (copy.points[i].status == SweepPointStatus::kIntegrationFailure) break;
      if (!a.reached && a.untrusted.empty()) a.untrusted = a.regimes.untrusted[i];
      if (Arrived(a.regimes, i, target) && !a.reached) {
        a.reached = true;
        a.time = t;
        a.point = static_cast<int>(i);
      }
    }
    a.simulated = t;
    out.push_back(std::move(a));
  }
  return out;
}

std::string UntrustedSection(const RubStructure& structure,
                             const std::vector<RubSectionPoint>& points, double max_penetration) {
  const RubSectionPoint* deepest = nullptr;
  double share = max_penetration;
  for (const RubSectionPoint& p : points) {
    const RubContact& contact = structure.contacts[static_cast<std::size_t>(p.contact)];
    if (p.penetration > share * contact.geometry.clearance) {
      deepest = &p;
      share = p.penetration / contact.geometry.clearance;
    }
  }
  if (deepest == nullptr) return "";
  return TooDeep(structure.contacts[static_cast<std::size_t>(deepest->contact)],
                 deepest->penetration, max_penetration);
}

SampledSection RubPenetrations(RubFixedFrame& system, double interval) {
  SampledSection section;
  section.count = static_cast<int>(system.structure().contacts.size());
  section.interval = interval;
  section.function = [&system](ConstVectorRef x, VectorRef values) {
    const std::vector<ContactEvaluation> contacts = system.Contacts(x);
    for (std::size_t k = 0; k < contacts.size(); ++k) values(static_cast<Index>(k)) = contacts[k].penetration;
  };
  return section;
}

std::vector<RubSectionPoint> RubSectionMaxima(RubFixedFrame& system,
                                              const std::vector<SectionExtremum>& extrema) {
  const std::size_t contacts = system.structure().contacts.size();
  std::vector<std::vector<const SectionExtremum*>> channels(contacts);
  for (const SectionExtremum& e : extrema) channels[static_cast<std::size_t>(e.channel)].push_back(&e);
  std::vector<RubSectionPoint> out;
  for (std::size_t k = 0; k < contacts; ++k) {
    std::vector<double> penetration;
    for (const SectionExtremum* e : channels[k]) penetration.push_back(e->value);
    for (std::size_t i : ExcursionMaxima(penetration, 0.0)) {
      const SectionExtremum& e = *channels[k][i];
      const ContactEvaluation contact = system.Contacts(e.x)[k];
      out.push_back({e.channel, e.t, e.value, contact.normal_force});
    }
  }
  std::sort(out.begin(), out.end(), [](const RubSectionPoint& a, const RubSectionPoint& b) { return a.t < b.t; });
  return out;
}

int RubSectionPeriod(const RubStructure& structure, const std::vector<RubSectionPoint>& section) {
  constexpr int kMaxPeriod = 8;
  int period = 0;
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    std::vector<double> force;
    for (const RubSectionPoint& p : section) {
      if (p.contact == static_cast<int>(k)) force.push_back(p.normal_force);
    }
    if (force.empty()) continue;
    double mean = 0.0;
    for (double f : force) mean += std::abs(f) / static_cast<double>(force.size());
    const int p = SectionPeriod(force, kRubSectionTolerance * mean, kMaxPeriod);
    if (p == 0) return 0;
    period = std::max(period, p);
  }
  return period;
}

std::string RubMotion(const RubStructure& structure, const AttractorResult& result,
                      const std::vector<RubSectionPoint>& section) {
  if (result.status != AttractorStatus::kMeasured) return "unknown (integration failure)";
  const int period = RubSectionPeriod(structure, section);
  const int k = static_cast<int>(result.exponents.size());
  if (result.positive > 0) {
    return period > 0 ? "unsettled (a positive exponent on a periodic section: a transient)" : "chaotic";
  }
  if (result.zero == k) return fmt::format("at least {} frequencies (all {} exponents zero)", k, k);
  if (structure.imbalance == 0.0) {
    switch (result.zero) {
      case 0: return "equilibrium";
      case 1: return "rotating wave";
      case 2:
        return period > 1 ? fmt::format("relative periodic orbit, period {} in the section", period)
                          : "relative periodic orbit";
      case 3:
        return period > 0 ? "relative periodic orbit near a bifurcation (a third exponent ≈ 0)"
                          : "relative 2-torus";
      default: break;
    }
  }
  return fmt::format("{} frequencies", result.zero);
}

}  // namespace rubcont
