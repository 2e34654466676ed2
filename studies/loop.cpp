#include "studies/loop.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "studies/whirl_limits.h"
#include "sweeps/ensemble.h"

namespace rubcont {

double ContactTimeShare(const SweepPoint& point, std::size_t k) {
  return point.channels.size() > k ? point.channels[k].active_fraction : kNaN;
}

namespace {

int DirectionSign(SweepDirection d) { return d == SweepDirection::kUp ? 1 : -1; }

// The run's schedule in one direction: the sweep's first speed to its last, step_rpm apart.
std::vector<double> ScheduleOf(const RubSweepOptions& sweep, double step_rpm) {
  const std::vector<double>& p = sweep.sweep.parameters;
  return SpeedSchedule(RadPerSecondToRpm(p.front()), RadPerSecondToRpm(p.back()), step_rpm);
}

// The fixed-frame state at t = 0 of the rotating wave with unknowns u = [p, Ω, …]
// (RotatingWaveProblem): u = p, u̇ = −jΩp.
Vector WaveState(const RubStructure& structure, const Vector& u) {
  const Index n = 2 * structure.Coordinates();
  RubRotatingFrame frame(structure, u(n));
  Vector x = Vector::Zero(2 * n);
  x.head(n) = u.head(n);
  return frame.ToFixedFrame(0.0, x);
}

// Whether the integrated `point` can be a wave's state, not only near its frequency: settled, and
// each contact touching (nearly) all the time or (nearly) never (`full`: the share that counts as
// all the time). A circular wave touches steadily or not at all, so a contact that touches part of
// the time is on none (the flexible A(a)'s left at 22 rpm, 0.21 of the time, matched a one-contact
// whirl's frequency; B(b)'s whip at 168 rpm, half of the time on each).
bool SteadyContacts(const RubStructure& structure, const SweepPoint& point, double full) {
  if (point.status != SweepPointStatus::kSettled) return false;
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    const double share = ContactTimeShare(point, k);
    if (!(share >= full || share <= 1.0 - full)) return false;
  }
  return true;
}

// The last schedule index before `limit_rpm` in the run's direction (strictly, by 1e-9 of a step),
// or −1.
int LastBefore(const std::vector<double>& schedule, double limit_rpm, int sign, double step) {
  int last = -1;
  for (std::size_t i = 0; i < schedule.size(); ++i) {
    if (sign * (limit_rpm - schedule[i]) > 1e-9 * step) last = static_cast<int>(i);
  }
  return last;
}

// Follows one direction of the run (studies/loop.h, "The run" and L1).
LoopRun Track(const RubStructure& structure, const std::vector<RotatingWaveBranch>& waves, const LoopOptions& o,
              SweepDirection direction, const LoopProgress& progress) {
  const double cpu_start = ThreadCpuSeconds();
  const int sign = DirectionSign(direction);
  RubSweepOptions sweep = direction == SweepDirection::kUp ? o.up : o.down;
  sweep.direction = direction;
  sweep.sweep.dwell = o.dwell;
  LoopRun run;
  run.direction = direction;
  run.schedule_rpm = ScheduleOf(sweep, o.step_rpm);
  const std::vector<double>& schedule = run.schedule_rpm;
  Vector state = RubImpulseIncrement(structure, sweep.impulse);
  std::size_t next = 0;  // the schedule index integrated next
  std::vector<double> done_speeds;  // [rad/s] of run.points, for the resumed stepper
  while (next < schedule.size()) {
    // A stepper over the speeds done and the rest of the schedule, resumed from `state` (so that
    // its choice of integrator sees the last speed done, as an uninterrupted sweep's does).
    sweep.sweep.parameters = done_speeds;
    for (std::size_t i = next; i < schedule.size(); ++i) sweep.sweep.parameters.push_back(RpmToRadPerSecond(schedule[i]));
    SweepRun stepper(structure, sweep, run.points, state);
    bool skipped = false;
    while (!stepper.stepper().Done() && !skipped) {
      stepper.stepper().Step();
      const SweepPoint& point = stepper.stepper().points().back();
      run.points.push_back(point);
      run.states.push_back(stepper.stepper().state());
      done_speeds.push_back(point.parameter);
      ++next;
      if (progress.speed) progress.speed(direction, RadPerSecondToRpm(point.parameter));
      if (stepper.stepper().Failed()) {
        run.message = fmt::format("the integration failed at {:g} rpm: {}", RadPerSecondToRpm(point.parameter),
                                  point.message);
        run.cpu_seconds = ThreadCpuSeconds() - cpu_start;
        run.regimes = ClassifySweep(structure, run.points, sweep.regimes);
        return run;
      }
      // L1: on a stable wave, move along it to the last speed before its stable stretch ends. The
      // waves are the balanced rotor's: an imbalanced one is forced off them at every speed, so
      // its run is integrated speed by speed (the waves still explain its jumps, as the sweep's
      // jump table does).
      if (structure.imbalance != 0.0) continue;
      if (!SteadyContacts(structure, point, 1.0 - o.barely_touching)) continue;
      const RubSweepRegimes regimes = ClassifySweep(structure, {point}, sweep.regimes);
      const WaveMatch match = MatchWave(structure, {point}, regimes, 0, waves, o.match);
      if (match.branch < 0 || match.stable != 1) continue;
      const RotatingWaveBranch& wave = waves[static_cast<std::size_t>(match.branch)];
      const WhirlLimit limit = StableLimitFrom(waves, match.branch, match.point, sign);
      double limit_rpm = 0.0;
      std::string why;
      if (limit.found) {
        limit_rpm = RadPerSecondToRpm(limit.speed);
        why = limit.point;
      } else if (limit.last >= 0) {
        // No special point: stable to the branch's end (or to where stability is lost without a
        // located point, which the tracker must then see for itself).
        limit_rpm = RadPerSecondToRpm(wave.branch.points[static_cast<std::size_t>(limit.last)].lambda);
        why = limit.reason;
      } else {
        continue;
      }
      // A special point along the stable stretch (a contact lost or regained, stick ↔ slip, a knee)
      // changes what a sweep reads there without a jump: the tracker must integrate across it, so
      // that the change is seen and attributed to it.
      for (const SpecialPoint& p : wave.branch.special_points) {
        const double rpm = RadPerSecondToRpm(p.lambda);
        const double here = RadPerSecondToRpm(point.parameter);
        if (sign * (rpm - here) > 0.0 && sign * (limit_rpm - rpm) > 0.0) {
          limit_rpm = rpm;
          why = p.Name();
        }
      }
      const int to = LastBefore(schedule, limit_rpm, sign, o.step_rpm);
      if (to <= static_cast<int>(next)) continue;  // nothing to save
      const Vector u = WhirlStateAt(waves, limit, RpmToRadPerSecond(schedule[static_cast<std::size_t>(to)]));
      if (u.size() == 0) continue;
      run.skips.push_back(LoopSkip{schedule[next - 1], schedule[static_cast<std::size_t>(to)], wave.name, why});
      state = WaveState(structure, u);
      next = static_cast<std::size_t>(to);
      skipped = true;
    }
  }
  run.regimes = ClassifySweep(structure, run.points, sweep.regimes);
  // A skip is a move along one stable wave: the two points on either side of it are the same state,
  // whatever the precession trend between them says.
  std::vector<RubSweepJump> kept;
  for (const RubSweepJump& j : run.regimes.jumps) {
    bool across = false;
    for (const LoopSkip& s : run.skips) {
      across = across || (std::abs(j.speed_from_rpm - s.from_rpm) < 1e-9 * o.step_rpm + 1e-9 &&
                          std::abs(j.speed_to_rpm - s.to_rpm) < 1e-9 * o.step_rpm + 1e-9);
    }
    if (!across) kept.push_back(j);
  }
  run.regimes.jumps = kept;
  run.cpu_seconds = ThreadCpuSeconds() - cpu_start;
  return run;
}

// One escape copy's outcome, as a job's result string: the stretch of its arrival (0: stayed),
// whether it failed, its CPU seconds.
struct CopyOutcome {
  int stretch = 0;
  bool failed = false;
  double cpu_seconds = 0.0;
  long long work = 0;  // work units
};
constexpr std::size_t kPackedCopy = sizeof(int) + sizeof(char) + sizeof(double) + sizeof(long long);
std::string Pack(const CopyOutcome& c) {
  std::string s(kPackedCopy, '\0');
  const char failed = c.failed ? 1 : 0;
  std::memcpy(&s[0], &c.stretch, sizeof(int));
  std::memcpy(&s[sizeof(int)], &failed, sizeof(char));
  std::memcpy(&s[sizeof(int) + sizeof(char)], &c.cpu_seconds, sizeof(double));
  std::memcpy(&s[sizeof(int) + sizeof(char) + sizeof(double)], &c.work, sizeof(long long));
  return s;
}
CopyOutcome Unpack(const std::string& s) {
  if (s.size() != kPackedCopy) throw std::logic_error("loop: a copy's result is malformed");
  CopyOutcome c;
  char failed = 0;
  std::memcpy(&c.stretch, &s[0], sizeof(int));
  std::memcpy(&failed, &s[sizeof(int)], sizeof(char));
  std::memcpy(&c.cpu_seconds, &s[sizeof(int) + sizeof(char)], sizeof(double));
  std::memcpy(&c.work, &s[sizeof(int) + sizeof(char) + sizeof(double)], sizeof(long long));
  c.failed = failed != 0;
  return c;
}

// A copy of `x0` (perturbed with `seed`) at `omega` for `stretches` stretches of two windows, until
// it arrives at the target (it stops there: the time after does not matter).
CopyOutcome RunCopy(const RubStructure& structure, const RubSweepOptions& sweep, double window, double perturbation,
                    const Vector& x0, double omega, int stretches, std::uint64_t seed, const ArrivalTarget& target) {
  const double cpu_start = ThreadCpuSeconds();
  WorkAccount copy_work;  // nested in the loop's where this thread runs the loop's jobs
  const WorkScope counting(&copy_work);
  SweepOptions s = sweep.sweep;
  s.parameters.assign(static_cast<std::size_t>(stretches), omega);
  s.window = window;
  s.settle_windows = 1;
  s.dwell = 2.0 * window;
  s.analysis_length = 2.0 * window;
  RubFixedFrame system(structure);
  RubSweepObservables observables(system);
  EnsembleOptions e;
  e.perturbation = perturbation;
  e.seed = seed;
  SweepStepper stepper(system, observables, s, PerturbedStart(x0, system.StateScale(), e, 0));
  CopyOutcome out;
  for (int j = 1; j <= stretches; ++j) {
    stepper.Step();
    if (stepper.Failed()) {
      out.failed = true;
      break;
    }
    const RubSweepRegimes r = ClassifySweep(structure, {stepper.points().back()}, sweep.regimes);
    if (Arrived(r, 0, target)) {
      out.stretch = j;
      break;
    }
  }
  out.cpu_seconds = ThreadCpuSeconds() - cpu_start;
  out.work = copy_work.Work();
  return out;
}

std::string ContactsOf(const RubStructure& structure, const std::vector<int>& contacts) {
  std::string s;
  for (int k : contacts) s += (s.empty() ? "" : ", ") + structure.contacts[static_cast<std::size_t>(k)].name;
  return s;
}

// A special point's name as a cause, the contact left to the corner's contact column:
// "test function: left knee" → "knee", "event: right contact loss" → "contact loss", "Hopf".
std::string CauseOf(const std::string& name, const RubStructure& structure) {
  std::string cause = name;
  for (const char* prefix : {"test function: ", "event: "}) {
    if (cause.rfind(prefix, 0) == 0) cause = cause.substr(std::strlen(prefix));
  }
  for (const RubContact& contact : structure.contacts) {
    if (cause.rfind(contact.name + " ", 0) == 0) cause = cause.substr(contact.name.size() + 1);
  }
  return cause;
}

// The jumps of one direction grouped over contacts: one corner where the contacts jump alike.
struct Jump {
  std::vector<int> contacts;
  std::vector<std::size_t> rows;  // into the run's jumps
};
std::vector<Jump> GroupJumps(const LoopRun& run, const RubStructure& structure) {
  std::vector<Jump> out;
  for (std::size_t i = 0; i < run.jumps.size(); ++i) {
    const PredictedJump& a = run.jumps[i];
    bool joined = false;
    for (Jump& g : out) {
      const PredictedJump& b = run.jumps[g.rows.front()];
      if (a.jump.kind == b.jump.kind && a.jump.speed_from_rpm == b.jump.speed_from_rpm &&
          a.jump.speed_to_rpm == b.jump.speed_to_rpm &&
          CauseOf(a.bifurcation, structure) == CauseOf(b.bifurcation, structure) &&
          (a.bifurcation.empty() || a.bifurcation_speed_rpm == b.bifurcation_speed_rpm)) {
        g.contacts.push_back(a.jump.contact);
        g.rows.push_back(i);
        joined = true;
        break;
      }
    }
    if (!joined) out.push_back(Jump{{a.jump.contact}, {i}});
  }
  return out;
}

// The special point named `name` of the ε/10 waves nearest `speed_rpm` (within max_rpm), NaN if none.
double CounterpartRpm(const std::vector<RotatingWaveBranch>& waves, const std::string& name, double speed_rpm,
                      double max_rpm) {
  double best = kNaN;
  for (const RotatingWaveBranch& b : waves) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.Name() != name) continue;
      const double rpm = RadPerSecondToRpm(p.lambda);
      if (std::abs(rpm - speed_rpm) <= max_rpm && (std::isnan(best) || std::abs(rpm - speed_rpm) < std::abs(best - speed_rpm))) {
        best = rpm;
      }
    }
  }
  return best;
}

// Whether every contact of `contacts` touched less than `barely` of the analysed time at both
// tracked points (and touched at all at one of them: no contact at both is no reading).
bool Flickers(const LoopRun& run, const std::vector<int>& contacts, std::size_t from, std::size_t to, double barely) {
  bool touched = false;
  for (int k : contacts) {
    for (std::size_t i : {from, to}) {
      const double share = ContactTimeShare(run.points[i], static_cast<std::size_t>(k));
      if (!(share < barely)) return false;
      touched = touched || share > 0.0;
    }
  }
  return touched;
}

// The departure state as the run was on it: the index of the first tracked speed since the run's
// previous jump at `contacts` (a barely touching other contact flickers: case C's left) up to the
// departure (index `from`).
std::size_t FirstOnState(const LoopRun& run, const std::vector<int>& contacts, std::size_t from, int sign,
                         double seen_from_rpm, double barely) {
  std::size_t first_on = 0;
  for (const RubSweepJump& j : run.regimes.jumps) {
    if (sign * (seen_from_rpm - j.speed_to_rpm) < -1e-9) continue;  // at or after this one
    if (std::find(contacts.begin(), contacts.end(), j.contact) == contacts.end()) continue;  // another contact's
    std::size_t j_from = 0, j_to = 0;
    for (std::size_t k = 0; k < run.points.size(); ++k) {
      const double rpm = RadPerSecondToRpm(run.points[k].parameter);
      if (std::abs(rpm - j.speed_from_rpm) < 1e-9) j_from = k;
      if (std::abs(rpm - j.speed_to_rpm) < 1e-9) j_to = k;
    }
    if (Flickers(run, {j.contact}, j_from, j_to, barely)) continue;  // a reading, not a state
    for (std::size_t k = 0; k <= from; ++k) {
      if (std::abs(RadPerSecondToRpm(run.points[k].parameter) - j.speed_to_rpm) < 1e-9) first_on = std::max(first_on, k);
    }
  }
  return first_on;
}

// "2.5 %" (or "2.5 %, 3.1 %" for several contacts): the share of the time in contact at point i.
std::string ContactShare(const LoopRun& run, const std::vector<int>& contacts, std::size_t i) {
  std::string s;
  for (int k : contacts) {
    s += fmt::format("{}{:.1f} %", s.empty() ? "" : ", ",
                     100.0 * ContactTimeShare(run.points[i], static_cast<std::size_t>(k)));
  }
  return s;
}

// A jump's importance for the budget: the direction's first whirl → whip and last whip → whirl
// first (the thesis's four corners), then the rest in speed order.
bool Principal(const std::vector<LoopCorner>& corners, std::size_t i) {
  const LoopCorner& c = corners[i];
  if (c.kind != "whirl_to_whip" && c.kind != "whip_to_whirl") return false;
  int first = -1, last = -1;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (corners[k].direction != c.direction) continue;
    if (corners[k].kind == "whirl_to_whip" && first < 0) first = static_cast<int>(k);
    if (corners[k].kind == "whip_to_whirl") last = static_cast<int>(k);
  }
  return static_cast<int>(i) == first || static_cast<int>(i) == last;
}

}  // namespace

EscapeCandidates EscapeCandidatesFor(const std::vector<double>& schedule, int sign, double seen_from,
                                     double first_on, double seen_to, double reach, double step) {
  EscapeCandidates result;
  for (double p : schedule) {
    if (sign * (p - seen_from) >= -reach - 1e-9 && sign * (p - first_on) >= -1e-9 &&
        sign * (p - seen_to) <= 2.0 * step + 1e-9) {
      result.speeds.push_back(p);
    }
  }
  double nearest = kInfinity;
  for (double p : result.speeds) {
    if (std::abs(p - seen_to) < nearest) {
      nearest = std::abs(p - seen_to);
      result.first = p;
    }
  }
  return result;
}

// A fold ends the state's existence; a period doubling, Neimark–Sacker or branch point or a
// multiplier +1 its stability; a grazing its character (a contact opens or closes).
bool EndsState(const SpecialPoint& p) {
  switch (p.type) {
    case SpecialPointType::kFold:
    case SpecialPointType::kPeriodDoubling:
    case SpecialPointType::kNeimarkSacker:
    case SpecialPointType::kBranchPoint:
    case SpecialPointType::kMultiplierPlusOne:
    case SpecialPointType::kGrazing:
      return true;
    default:
      return false;
  }
}

OrbitSkeletonEnd SkeletonEnd(const PeriodicOrbitBranch& family, const std::vector<OrbitPeriodDoubling>& doublings,
                             double from, int sign, double scale, const std::string& unit) {
  OrbitSkeletonEnd end;
  end.lambda = end.doubling_lambda = kNaN;
  auto at = [&](double lambda) { return fmt::format("{:.4f}{}", lambda * scale, unit.empty() ? "" : " " + unit); };
  const Branch& b = family.branch;
  int first = -1;
  for (std::size_t k = 0; k < b.special_points.size(); ++k) {
    const SpecialPoint& p = b.special_points[k];
    if (!EndsState(p) || !(sign * (p.lambda - from) > 0.0)) continue;
    if (first < 0 || sign * p.lambda < sign * b.special_points[static_cast<std::size_t>(first)].lambda) {
      first = static_cast<int>(k);
    }
  }
  if (first < 0) {
    double reach = from;
    for (const BranchPoint& q : b.points)
      if (sign * (q.lambda - reach) > 0.0) reach = q.lambda;
    end.route = fmt::format("no point that ends the state from {} to {}, as far as the family went ({})", at(from),
                            at(reach), b.BriefReport());
    return end;
  }
  const SpecialPoint& p = b.special_points[static_cast<std::size_t>(first)];
  end.found = true;
  end.lambda = p.lambda;
  end.name = p.Name();
  end.type = p.type;
  end.route = fmt::format("{} at {}", p.Name(), at(p.lambda));
  if (p.type != SpecialPointType::kPeriodDoubling) return end;
  end.doubling_lambda = p.lambda;
  const auto d = std::find_if(doublings.begin(), doublings.end(), [&](const OrbitPeriodDoubling& x) {
    return x.special_point == static_cast<std::size_t>(first);
  });
  if (d == doublings.end()) {
    end.route += " (its doubled orbits not followed)";
    return end;
  }
  if (!d->ok) {
    end.route += fmt::format(" (no doubled orbits: {})", d->message);
    return end;
  }
  // The doubled family's stable stretch whose speeds hold the doubling (a stretch from the family's
  // first orbit holds it too: that orbit lies a little past the doubling, by the start's amplitude).
  const std::vector<BranchPoint>& q = d->branch.branch.points;
  std::size_t lo = q.size(), hi = q.size();
  double lo_lambda = kNaN, hi_lambda = kNaN;
  for (std::size_t i = 0; i < q.size();) {
    if (q[i].num_unstable != 0) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < q.size() && q[j + 1].num_unstable == 0) ++j;
    double a = q[i].lambda, c = q[i].lambda;
    for (std::size_t k = i; k <= j; ++k) {
      a = std::min(a, q[k].lambda);
      c = std::max(c, q[k].lambda);
    }
    if (i == 0) {
      a = std::min(a, p.lambda);
      c = std::max(c, p.lambda);
    }
    if (a <= p.lambda && p.lambda <= c) {
      lo = i;
      hi = j;
      lo_lambda = a;
      hi_lambda = c;
      break;
    }
    i = j + 1;
  }
  if (lo == q.size()) {
    // Unstable there only as far as the family went: one cut short (the budget's callback, the
    // step limit, a failure) may yet turn back stable over the doubling's speed, as A(a)'s does
    // past its fold and Neimark–Sacker point (121.0 rpm, below the doubling at 128.35).
    const BranchStatus status = d->branch.branch.status;
    if (status == BranchStatus::kStoppedByCaller || status == BranchStatus::kMaxSteps ||
        IsFailure(status)) {
      end.route += fmt::format("; no stable doubled orbit at the doubling's speed as far as their "
                               "family went ({}): not decided",
                               d->branch.branch.BriefReport());
      return end;
    }
    end.route += fmt::format("; the doubled orbits are unstable there ({}): the run has no periodic state to move on to",
                             d->branch.branch.BriefReport());
    return end;
  }
  std::size_t e = lo;
  for (std::size_t i = lo; i <= hi; ++i)
    if (sign * q[i].lambda > sign * q[e].lambda) e = i;
  const std::vector<SpecialPoint>& dp = d->branch.branch.special_points;
  int last = -1;
  for (std::size_t k = 0; k < dp.size(); ++k) {
    const Index index = dp[k].index;
    if (!EndsState(dp[k]) || (index != static_cast<Index>(e) && index + 1 != static_cast<Index>(e))) continue;
    if (last < 0 || std::abs(dp[k].lambda - q[e].lambda) <
                        std::abs(dp[static_cast<std::size_t>(last)].lambda - q[e].lambda)) {
      last = static_cast<int>(k);
    }
  }
  // The stretch's other end, named by its special point where it has one (A(a)'s Neimark–Sacker point).
  std::size_t b_end = lo;
  for (std::size_t i = lo; i <= hi; ++i)
    if (sign * q[i].lambda < sign * q[b_end].lambda) b_end = i;
  std::string begins = at(sign > 0 ? lo_lambda : hi_lambda);
  for (const SpecialPoint& x : dp) {
    if (EndsState(x) && (x.index == static_cast<Index>(b_end) || x.index + 1 == static_cast<Index>(b_end))) {
      begins = fmt::format("the {} at {}", x.Name(), at(x.lambda));
    }
  }
  end.doubled = true;
  end.route += fmt::format("; the doubled orbits (period 2T) stable from {}", begins);
  if (last < 0) {
    end.found = false;
    end.lambda = kNaN;
    end.name.clear();
    end.route += fmt::format(" to {}, as far as their continuation went ({}): their end not reached",
                             at(sign > 0 ? hi_lambda : lo_lambda), d->branch.branch.BriefReport());
    return end;
  }
  end.lambda = dp[static_cast<std::size_t>(last)].lambda;
  end.name = dp[static_cast<std::size_t>(last)].Name();
  end.type = dp[static_cast<std::size_t>(last)].type;
  end.route += fmt::format(" to where they end: {} at {}", end.name, at(end.lambda));
  return end;
}


OrbitRide RideFamily(const PeriodicOrbitBranch& family, double orbit, int sign, double far,
                     std::vector<OrbitPeriodDoubling>& doublings, const DoublingFollower& follow, double scale,
                     const std::string& unit) {
  OrbitRide ride;
  ride.from = kNaN;
  const Branch& b = family.branch;
  for (const BranchPoint& q : b.points) {
    if (q.num_unstable == 0 && sign * (q.lambda - orbit) <= 1e-9 * std::abs(orbit) &&
        (std::isnan(ride.from) || sign * (q.lambda - ride.from) > 0.0)) {
      ride.from = q.lambda;
    }
  }
  if (std::isnan(ride.from)) {
    ride.end.lambda = ride.end.doubling_lambda = kNaN;
    ride.text = "no stable orbit of the family at or before the orbit found: the run was not on it";
    return ride;
  }
  ride.rides = true;
  ride.end = SkeletonEnd(family, doublings, ride.from, sign, scale, unit);
  if (ride.end.found && ride.end.type == SpecialPointType::kPeriodDoubling && !ride.end.doubled) {
    for (std::size_t k = 0; k < b.special_points.size(); ++k) {
      const SpecialPoint& p = b.special_points[k];
      const bool followed = std::any_of(doublings.begin(), doublings.end(),
                                        [k](const OrbitPeriodDoubling& d) { return d.special_point == k; });
      if (p.type != SpecialPointType::kPeriodDoubling || p.lambda != ride.end.lambda || followed) continue;
      // Why not, where not (B(b)'s at 148.07 rpm: a multiplier jumping from 0.97 to 2.7 between two
      // orbits where a contact grazes, located only to a bracket).
      std::string why;
      if (!p.converged) why = "located only to a bracket";
      else if (!BoundsStablePiece(b, p)) why = "the family is not stable on exactly one side of it";
      else if (!(sign * (p.lambda - far) <= 0.0)) why = "past the landing";
      else if (!follow) why = "no budget left, or doubled_steps = 0";
      if (why.empty()) {
        doublings.push_back(follow(k));
        ride.end = SkeletonEnd(family, doublings, ride.from, sign, scale, unit);
      } else if (!ride.end.route.empty() && ride.end.route.back() == ')') {
        ride.end.route.insert(ride.end.route.size() - 1, ": " + why);  // "(its doubled orbits not followed: …)"
      }
      break;
    }
  }
  ride.text = fmt::format("the run rides the family from {:.4f}{}: {}", ride.from * scale,
                          unit.empty() ? "" : " " + unit, ride.end.route);
  return ride;
}

const char* ToString(LoopStatus status) {
  switch (status) {
    case LoopStatus::kExplained: return "explained";
    case LoopStatus::kPartly: return "partly explained";
    case LoopStatus::kRunFailed: return "run failed";
  }
  return "?";
}

void Validate(const LoopOptions& o) {
  auto fail = [](const char* field, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("LoopOptions.{} = {}: {}", field, value, rule));
  };
  Validate(o.up);
  Validate(o.down);
  if (o.up.sweep.parameters.size() < 2 || o.down.sweep.parameters.size() < 2) {
    fail("up/down.sweep.parameters", "(fewer than 2 speeds)", "each direction needs a range: its first and last speed");
  }
  if (!(o.step_rpm > 0.0) || !std::isfinite(o.step_rpm)) fail("step_rpm", o.step_rpm, "must be positive");
  if (!(o.dwell > 0.0) || !std::isfinite(o.dwell)) fail("dwell", o.dwell, "must be positive");
  if (!(o.dwell >= (o.up.sweep.settle_windows + 1) * o.up.sweep.window)) {
    fail("dwell", o.dwell, "must hold the settle test's windows ((settle_windows + 1) × window)");
  }
  if (!(o.window > 0.0) || !std::isfinite(o.window)) fail("window", o.window, "must be positive");
  if (!(o.perturbation >= 0.0) || !std::isfinite(o.perturbation)) fail("perturbation", o.perturbation, "must be non-negative");
  if (!(o.escape_reach_rpm >= o.step_rpm) || !std::isfinite(o.escape_reach_rpm)) {
    fail("escape_reach_rpm", o.escape_reach_rpm, "must be at least step_rpm");
  }
  if (!(o.budget > 0.0) || !std::isfinite(o.budget)) fail("budget", o.budget, "must be positive (CPU seconds)");
  if (o.orbit_steps < 1) fail("orbit_steps", o.orbit_steps, "must be at least 1");
  if (o.route_tries < 0) fail("route_tries", o.route_tries, "must be non-negative (0: no route)");
  if (o.doubled_steps < 0) fail("doubled_steps", o.doubled_steps, "must be non-negative (0: not followed)");
  if (!(o.min_escape_budget >= 0.0)) fail("min_escape_budget", o.min_escape_budget, "must be non-negative");
  if (!(o.barely_touching > 0.0 && o.barely_touching <= 1.0)) fail("barely_touching", o.barely_touching, "must be in (0, 1]");
  if (o.orbits) Validate(o.orbit_start);
  for (const double span : {std::abs(o.up.sweep.parameters.back() - o.up.sweep.parameters.front()),
                            std::abs(o.down.sweep.parameters.back() - o.down.sweep.parameters.front())}) {
    if (RadPerSecondToRpm(span) / o.step_rpm > 10000.0) fail("step_rpm", o.step_rpm, "gives more than 10000 speeds");
  }
}

std::string LoopResult::BriefReport() const {
  int explained = 0;
  std::map<std::string, int> by_level;
  for (const LoopCorner& c : corners) {
    if (!c.level.empty()) {
      ++explained;
      ++by_level[c.level];
    }
  }
  std::string levels;
  for (const auto& [level, n] : by_level) levels += fmt::format("{}{} {}", levels.empty() ? "" : ", ", n, level);
  return fmt::format("loop {}: {} jumps, {} explained{}; {:.2f} G work units, {:.1f} s CPU{}", ToString(status),
                     corners.size(), explained, levels.empty() ? "" : " (" + levels + ")", work, cpu_seconds,
                     message.empty() ? "" : "; " + message);
}

LoopResult ComputeLoop(const RubStructure& structure, const LoopOptions& options, const JobRunner& jobs,
                       const LoopProgress& progress) {
  Validate(options);
  const double cpu_start = ProcessCpuSeconds();
  const SteadyClock::time_point wall_start = SteadyClock::now();
  LoopResult result;
  auto note = [&](std::string line) {
    if (progress.note) progress.note(line);
    result.decisions.push_back(std::move(line));
  };
  auto cpu = [&] { return ProcessCpuSeconds() - cpu_start; };
  // The copies run by other processes (MPI ranks) are in neither count of this one.
  double escape_cpu = 0.0;
  long long escape_work = 0;
  auto spent = [&] { return cpu() + escape_cpu; };
  // What the budget counts [G work units]: this loop's integrations, not another thread's.
  WorkAccount loop_work;
  const WorkScope counting(&loop_work);
  auto used = [&] { return 1e-9 * static_cast<double>(loop_work.Work() + escape_work); };

  // L1: the waves of the law the sweep integrates, over both runs' speeds; and at ε/10.
  RubStructure balanced = structure;
  balanced.imbalance = 0.0;
  RotatingWaveBranchOptions waves = options.waves;
  result.waves = ComputeRotatingWaveBranches(balanced, FrictionLawKind::kTanh, waves);
  RubStructure tenth = balanced;
  tenth.law.velocity_scale /= 10.0;
  const std::vector<RotatingWaveBranch> waves_tenth = ComputeRotatingWaveBranches(tenth, FrictionLawKind::kTanh, waves);
  note(fmt::format("L1: {} rotating waves (tanh law, ε = {:g} m/s) in {:.2f} s CPU; and at ε/10 for the corners' "
                   "regularization bias", result.waves.size(), structure.law.velocity_scale, cpu()));
  if (structure.imbalance != 0.0) {
    note(fmt::format("imbalance {:g} kg·m: the waves are the balanced rotor's; they explain the jumps, and the runs "
                     "are integrated at every speed (no move along a wave)", structure.imbalance));
  }

  // The runs, both directions at once (each on its own thread).
  std::vector<LoopRun> runs(2);
  ParallelFor(2, 2, [&](int d) {
    runs[static_cast<std::size_t>(d)] =
        Track(structure, result.waves, options, d == 0 ? SweepDirection::kUp : SweepDirection::kDown, progress);
  });
  result.up = std::move(runs[0]);
  result.down = std::move(runs[1]);
  for (LoopRun* run : {&result.up, &result.down}) {
    const char* dir = ToString(run->direction);
    run->jumps = PredictJumps(dir, balanced, run->points, run->regimes, result.waves, options.match);
    if (!run->points.empty()) {
      std::vector<RubRegime> last;
      for (const auto& regime : run->regimes.regime) last.push_back(regime.back());
      run->end = fmt::format("{} at {:g} rpm", RegimeList(structure, last),
                             RadPerSecondToRpm(run->points.back().parameter));
    }
    double skipped = 0.0;
    for (const LoopSkip& s : run->skips) skipped += std::abs(s.to_rpm - s.from_rpm);
    note(fmt::format("L3 tracker {}: {} of {} speeds integrated ({:g} rpm moved along stable waves by L1), {} jumps, "
                     "{:.1f} s CPU; it ends in {}{}", dir, run->points.size(), run->schedule_rpm.size(), skipped,
                     run->jumps.size(), run->cpu_seconds, run->end, run->message.empty() ? "" : "; " + run->message));
  }

  // The corners, with L1's explanation where it has one.
  for (const LoopRun* run : {&result.up, &result.down}) {
    for (const Jump& g : GroupJumps(*run, structure)) {
      const PredictedJump& j = run->jumps[g.rows.front()];
      LoopCorner c;
      c.direction = j.direction;
      c.kind = ToString(j.jump.kind);
      c.contact = ContactsOf(structure, g.contacts);
      c.seen_from_rpm = j.jump.speed_from_rpm;
      c.seen_to_rpm = j.jump.speed_to_rpm;
      c.precession_from_hz = j.jump.precession_from_hz;
      c.precession_to_hz = j.jump.precession_to_hz;
      c.crisis_lower_rpm = c.crisis_upper_rpm = kNaN;
      c.speed_rpm = c.lower_rpm = c.upper_rpm = kNaN;
      if (!j.bifurcation.empty()) {
        c.cause = CauseOf(j.bifurcation, structure);
        c.level = "L1";
        c.speed_rpm = j.bifurcation_speed_rpm;
        const double other = CounterpartRpm(waves_tenth, j.bifurcation, c.speed_rpm, options.match.max_distance_rpm);
        if (std::isnan(other)) {
          c.lower_rpm = c.upper_rpm = c.speed_rpm;
          c.interval = "the point itself (its counterpart at ε/10 not found)";
        } else {
          c.lower_rpm = std::min(c.speed_rpm, other);
          c.upper_rpm = std::max(c.speed_rpm, other);
          c.interval = "regularization: the point at ε and at ε/10";
        }
        c.evidence = fmt::format("branches/{}/special_points", j.branch);
        c.note = fmt::format("{} on {} ({} state, {}); the run jumped {:g} → {:g} rpm", j.bifurcation, j.branch,
                             j.matched_side, j.branch_stable == 1 ? "stable" : j.branch_stable == 0 ? "unstable" : "stability unknown",
                             c.seen_from_rpm, c.seen_to_rpm);
      } else {
        c.cause = "not explained";
        c.interval = "the run's step";
        c.lower_rpm = std::min(c.seen_from_rpm, c.seen_to_rpm);
        c.upper_rpm = std::max(c.seen_from_rpm, c.seen_to_rpm);
        c.speed_rpm = 0.5 * (c.seen_from_rpm + c.seen_to_rpm);
        c.evidence = fmt::format("runs/{}", c.direction);
        c.note = j.matched_side == "none" ? "L1: neither state is a rotating wave"
                                          : fmt::format("L1: {} state on {} ({}), no special point within {:g} rpm",
                                                        j.matched_side, j.branch,
                                                        j.branch_stable == 1 ? "stable" : "unstable",
                                                        options.match.max_distance_rpm);
      }
      result.corners.push_back(c);
    }
  }

  // L2's families: over a jump (lo … hi rpm) and from an orbit at orbit_rpm, in the run's direction.
  auto family_over = [&](double orbit_rpm, int sign, double lo, double hi) {
    PeriodicOrbitBranchOptions family = options.orbit_family;
    family.lambda_min = RpmToRadPerSecond(std::max(std::min(lo, orbit_rpm - options.step_rpm), 1e-3));
    family.lambda_max = RpmToRadPerSecond(std::max(hi, orbit_rpm + options.step_rpm));
    family.direction = sign;
    family.on_step = [&](const Branch&) { return used() < options.budget; };
    return family;
  };
  // The skeleton along the family L2 found (asked.orbits, converged): RideFamily, the doubled family
  // followed to past the landing and as far back as the escape design reaches (a subcritical
  // doubling's orbits run back first: A(a)'s to a fold 7.3 rpm below it).
  auto ride_family = [&](LoopOrbits& asked, int sign, double lo, double hi) {
    const RubTransientOrbits& family = asked.orbits;
    const auto follow = [&](std::size_t k) {
      const double at = family.family.orbits.branch.special_points[k].lambda;
      PeriodicOrbitBranchOptions doubled = family_over(asked.orbit_rpm, sign, lo, hi);
      const double back = RpmToRadPerSecond(options.escape_reach_rpm);
      doubled.lambda_min = std::max(RpmToRadPerSecond(1e-3), std::min(doubled.lambda_min, at - back));
      doubled.lambda_max = std::max(doubled.lambda_max, at + back);
      doubled.continuation.bounds.max_steps = options.doubled_steps;
      doubled.stop_at_grazing = true;
      const double t0 = spent();
      OrbitPeriodDoubling d = ContinueTransientDoubling(balanced, family, k, doubled);
      note(fmt::format("  L2: the doubled family from the period doubling at {:.4f} rpm: {} ({:.1f} s CPU)",
                       RadPerSecondToRpm(at), d.ok ? d.branch.branch.BriefReport() : d.message, spent() - t0));
      return d;
    };
    const bool may_follow = options.doubled_steps > 0 && used() < options.budget;
    const OrbitRide ride = RideFamily(asked.orbits.family.orbits, RpmToRadPerSecond(asked.orbit_rpm), sign,
                                      RpmToRadPerSecond(sign > 0 ? hi : lo), asked.orbits.family.doublings,
                                      may_follow ? DoublingFollower(follow) : DoublingFollower(), kRpmPerRadPerSecond,
                                      "rpm");
    asked.skeleton = ride.text;
    note("  L2 skeleton: " + asked.skeleton);
    return ride;
  };
  struct PendingRoute {
    std::size_t corner;
    std::size_t from;      // the departure's index in its run
    std::size_t first_on;  // the run's first index on the whip
  };
  std::vector<PendingRoute> routes;

  // L3 for the corners L1 leaves open: principal ones first.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < result.corners.size(); ++i)
    if (result.corners[i].level.empty() && Principal(result.corners, i)) order.push_back(i);
  for (std::size_t i = 0; i < result.corners.size(); ++i)
    if (result.corners[i].level.empty() && !Principal(result.corners, i)) order.push_back(i);
  std::map<std::tuple<std::string, double, double>, std::size_t> escalated;  // (direction, from, to) → corner
  for (std::size_t i : order) {
    LoopCorner& c = result.corners[i];
    const LoopRun& run = c.direction == "up" ? result.up : result.down;
    const int sign = DirectionSign(run.direction);
    const std::string what = fmt::format("{} {} {:g} → {:g} rpm ({})", c.direction, c.kind, c.seen_from_rpm, c.seen_to_rpm,
                                         c.contact);
    std::size_t from = 0, to = 0;
    for (std::size_t k = 0; k < run.points.size(); ++k) {
      const double rpm = RadPerSecondToRpm(run.points[k].parameter);
      if (std::abs(rpm - c.seen_from_rpm) < 1e-9) from = k;
      if (std::abs(rpm - c.seen_to_rpm) < 1e-9) to = k;
    }
    std::vector<int> contacts;
    for (std::size_t k = 0; k < structure.contacts.size(); ++k)
      if (c.contact.find(structure.contacts[k].name) != std::string::npos) contacts.push_back(static_cast<int>(k));
    // A contact that barely touches on both sides of the jump reads its precession off its free
    // orbit: what changes is a reading, not the rotor's state.
    if (Flickers(run, contacts, from, to, options.barely_touching)) {
      c.level = "L3";
      c.cause = "flicker of a barely touching contact";
      c.note = fmt::format("in contact {} of the time at {:g} rpm and {} at {:g} rpm (below {:g}): its precession is "
                           "read off its free orbit, not a state of the rotor; {}",
                           ContactShare(run, contacts, from), c.seen_from_rpm, ContactShare(run, contacts, to),
                           c.seen_to_rpm, options.barely_touching, c.note);
      c.evidence = fmt::format("runs/{}", c.direction);
      continue;
    }
    // Another contact's jump at the same two speeds was asked already: the same verdict.
    const auto key = std::make_tuple(c.direction, c.seen_from_rpm, c.seen_to_rpm);
    if (const auto it = escalated.find(key); it != escalated.end()) {
      const LoopCorner& other = result.corners[it->second];
      if (!other.level.empty()) {
        const std::string own = c.note;
        c.level = other.level;
        c.cause = other.cause;
        c.speed_rpm = other.speed_rpm;
        c.lower_rpm = other.lower_rpm;
        c.upper_rpm = other.upper_rpm;
        c.interval = other.interval;
        c.crisis_lower_rpm = other.crisis_lower_rpm;
        c.crisis_upper_rpm = other.crisis_upper_rpm;
        c.evidence = other.evidence;
        c.note = fmt::format("as the {} contact's jump at the same speeds; {}", other.contact, own);
      } else {
        c.note += fmt::format("; as the {} contact's jump at the same speeds: {}", other.contact, other.note);
      }
      continue;
    }
    escalated[key] = i;
    if (used() >= options.budget) {
      c.note += fmt::format("; not decided within the budget ({:.2f} G work units used before it)", used());
      note(fmt::format("budget: {} left undecided ({:.2f} of {:g} G work units used, {:.1f} s CPU)", what, used(),
                       options.budget, spent()));
      continue;
    }
    const std::size_t first_on = FirstOnState(run, contacts, from, sign, c.seen_from_rpm, options.barely_touching);
    // L2: is the departure a relative periodic orbit, and does its family end between the speeds?
    // Where it is none (a chaotic whip), the route: the latest state of the run on its way that is
    // one. Along the family, the period doubling the run meets is followed into the doubled family
    // (studies/loop.h, L2).
    const double frame_hz = run.regimes.precession_hz[0][from];
    if (options.orbits && balanced.imbalance == 0.0 && structure.imbalance == 0.0 && std::isfinite(frame_hz) &&
        frame_hz > 0.0) {
      const double before_l2 = spent();
      const double lo = std::min(c.seen_from_rpm, c.seen_to_rpm) - options.step_rpm;
      const double hi = std::max(c.seen_from_rpm, c.seen_to_rpm) + options.step_rpm;
      note(fmt::format("L2 for {}: {}; its departure at {:g} rpm as a relative periodic orbit (frame {:.2f} Hz)", what,
                       c.note, c.seen_from_rpm, frame_hz));
      LoopOrbits asked;
      asked.direction = c.direction;
      asked.seen_from_rpm = c.seen_from_rpm;
      asked.seen_to_rpm = c.seen_to_rpm;
      asked.orbit_rpm = c.seen_from_rpm;
      asked.orbits = ContinueTransientOrbits(balanced, RpmToRadPerSecond(c.seen_from_rpm), HzToRadPerSecond(frame_hz),
                                             run.states[from], options.orbit_start,
                                             family_over(c.seen_from_rpm, sign, lo, hi), options.orbit_steps);
      if (!asked.orbits.start.converged) note(fmt::format("  L2: no orbit: {}", asked.orbits.start.message));
      // The route to a whip's end that is no orbit explains, it never decides: asked after every
      // corner is decided, with what is left of the budget (below).
      if (!asked.orbits.start.converged && c.kind == "whip_to_whirl" && options.route_tries > 0) {
        routes.push_back(PendingRoute{i, from, first_on});
      }
      RubTransientOrbits& l2 = asked.orbits;
      const int index = static_cast<int>(result.orbits.size());
      c.orbits = index;
      const OrbitRide ride = l2.start.converged ? ride_family(asked, sign, lo, hi) : OrbitRide();
      const OrbitSkeletonEnd& skeleton = ride.end;
      result.orbits.push_back(asked);
      c.cpu_seconds += spent() - before_l2;
      const std::string pd_evidence = fmt::format("orbits/{}_pd1/special_points", index);
      if (!l2.start.converged) {
        c.note += fmt::format("; L2: no relative periodic orbit from the state at {:g} rpm ({})", c.seen_from_rpm,
                              l2.start.message);
      } else {
        const Branch& b = l2.family.orbits.branch;
        const bool stable = !b.points.empty() && b.points.front().num_unstable == 0;
        const std::string orbit = fmt::format("a{} relative periodic orbit (modulation {:.3g} Hz)",
                                              stable ? " stable" : "n unstable", 1.0 / l2.start.period);
        const double end_rpm = RadPerSecondToRpm(skeleton.lambda);
        if (skeleton.found && skeleton.doubled && end_rpm >= lo - 1e-9 && end_rpm <= hi + 1e-9) {
          // The run moved on to the doubled orbits at the doubling and left them where they end.
          c.level = "L2";
          c.cause = CauseOf(skeleton.name, structure) + " of the period-doubled state";
          c.speed_rpm = c.lower_rpm = c.upper_rpm = end_rpm;
          c.interval = "the point itself (L2: located on the doubled family; the regularization not varied)";
          c.evidence = pd_evidence;
          c.note = fmt::format("the departure at {:g} rpm is {}; {}; the run jumped {:g} → {:g} rpm", c.seen_from_rpm,
                               orbit, asked.skeleton, c.seen_from_rpm, c.seen_to_rpm);
          note(fmt::format("  L2: {} of the doubled family at {:.4f} rpm", skeleton.name, c.speed_rpm));
          continue;
        }
        int found = -1;
        for (std::size_t k = 0; k < b.special_points.size() && found < 0; ++k) {
          const SpecialPoint& p = b.special_points[k];
          const double rpm = RadPerSecondToRpm(p.lambda);
          if (EndsState(p) && rpm >= lo - 1e-9 && rpm <= hi + 1e-9) found = static_cast<int>(k);
        }
        const std::string ride = asked.skeleton.empty() ? "" : "; " + asked.skeleton;
        if (found >= 0) {
          const SpecialPoint& p = b.special_points[static_cast<std::size_t>(found)];
          c.level = "L2";
          c.cause = CauseOf(p.Name(), structure) + " of the modulated state";
          c.speed_rpm = c.lower_rpm = c.upper_rpm = RadPerSecondToRpm(p.lambda);
          c.interval = "the point itself (L2: located on the family; the regularization not varied)";
          c.evidence = fmt::format("orbits/{}/special_points", index);
          c.note = fmt::format("the departure at {:g} rpm is {}; its family ends or changes there ({}); the run jumped "
                               "{:g} → {:g} rpm{}", c.seen_from_rpm, orbit, p.Name(), c.seen_from_rpm, c.seen_to_rpm,
                               ride);
          note(fmt::format("  L2: {} at {:.4f} rpm", p.Name(), c.speed_rpm));
          continue;
        }
        c.note += fmt::format("; L2: the departure is {}, and its family ({}) has no special point between {:g} and "
                              "{:g} rpm{}", orbit, b.BriefReport(), lo, hi, ride);
        note(fmt::format("  L2: {}; no special point in the jump", orbit));
        if (stable) {
          // A stable orbit that goes on past the jump: the run did not leave it by chance.
          c.note += "; L3 not tried: the departure is a stable orbit";
          continue;
        }
      }
      if (used() >= options.budget) {
        c.note += fmt::format("; not decided within the budget ({:.2f} G work units used)", used());
        continue;
      }
    }
    // L3 measures how long a state lasts; a departure that settled at its speed was a steady state
    // there, and a steady state that is gone one step later ended at a bifurcation between the two
    // speeds, not by chance.
    if (run.points[from].status == SweepPointStatus::kSettled) {
      c.note += fmt::format("; L3 not tried: the departure settled at {:g} rpm (a steady state: the jump is a "
                            "bifurcation between {:g} and {:g} rpm that no level located)",
                            c.seen_from_rpm, c.seen_from_rpm, c.seen_to_rpm);
      note("L3 not tried for " + what + ": its departure settled");
      continue;
    }
    ArrivalTarget target;
    const RubRegime landing = run.regimes.regime[static_cast<std::size_t>(contacts.front())][to];
    if (c.kind == "frequency_jump") {
      if (!(c.precession_to_hz > c.precession_from_hz)) {
        c.note += "; L3: a jump to a lower precession has no arrival rule (only \"precession above\")";
        note("L3 not tried for " + what + ": a frequency jump downwards");
        continue;
      }
      target.precession_above_hz = 0.5 * (c.precession_from_hz + c.precession_to_hz);
    } else {
      target.regime = landing;
    }
    if (contacts.size() == structure.contacts.size()) {
      target.contacts = ArrivalContacts::kEvery;
    } else {
      target.contacts = ArrivalContacts::kOne;
      target.contact = contacts.front();
    }
    const double first_on_rpm = RadPerSecondToRpm(run.points[first_on].parameter);
    const std::vector<double>& schedule = run.schedule_rpm;
    const EscapeCandidates escape =
        EscapeCandidatesFor(schedule, sign, c.seen_from_rpm, first_on_rpm, c.seen_to_rpm,
                            options.escape_reach_rpm, options.step_rpm);
    const std::vector<double>& candidates = escape.speeds;
    if (candidates.size() < 2) {
      c.note += "; L3 not tried: the run was on the departure state for too few speeds";
      note("L3 not tried for " + what + ": too few speeds on the departure state");
      continue;
    }
    // The copies' starts: the tracker's state after the last speed on the state before each
    // candidate (the first such state for the first candidate; the departure's past it).
    std::map<double, std::size_t> start_of;
    for (double p : candidates) {
      std::size_t best = first_on;
      for (std::size_t k = first_on; k <= from; ++k) {
        if (sign * (p - RadPerSecondToRpm(run.points[k].parameter)) > 1e-9) best = k;
      }
      start_of[p] = best;
    }
    EscapeDesignOptions design = options.escapes;
    design.side = sign > 0 ? CrisisSide::kAbove : CrisisSide::kBelow;
    design.schedule = schedule;
    design.dwell = options.dwell;
    design.candidates = candidates;
    design.first = escape.first;
    design.budget = options.budget - used();
    design.cost_unit = "G";
    if (design.budget < options.min_escape_budget) {
      c.note += fmt::format("; not decided within the budget ({:.2f} G work units left, an escape design needs {:g})",
                            design.budget, options.min_escape_budget);
      note(fmt::format("budget: {} left undecided ({:.2f} G work units left)", what, design.budget));
      continue;
    }
    RubSweepOptions copy_sweep = run.direction == SweepDirection::kUp ? options.up : options.down;
    const int copies_stretches_max = StretchCount(design.max_duration, options.window);
    (void)copies_stretches_max;
    note(fmt::format("L3 for {}: {}; the escape design over {:g} … {:g} rpm ({} values), copies until {}", what,
                     c.note, candidates.front(), candidates.back(), candidates.size(), Describe(structure, target)));
    const double before = spent();
    const EscapeRunner runner = [&](const std::vector<EscapeRequest>& requests) {
      struct Job {
        std::size_t request;
        int copy;
      };
      std::vector<Job> list;
      for (std::size_t r = 0; r < requests.size(); ++r)
        for (int k = 0; k < requests[r].copies; ++k) list.push_back(Job{r, k});
      const double local_start = ProcessCpuSeconds();
      const long long local_work = loop_work.Work();
      const std::vector<std::string> out = jobs(static_cast<int>(list.size()), [&](int n) {
        const Job& job = list[static_cast<std::size_t>(n)];
        const EscapeRequest& q = requests[job.request];
        return Pack(RunCopy(structure, copy_sweep, options.window, options.perturbation,
                            run.states[start_of.at(q.parameter)], RpmToRadPerSecond(q.parameter),
                            StretchCount(q.duration, options.window), q.seed + static_cast<std::uint64_t>(job.copy), target));
      });
      EscapeBatch batch;
      batch.observations.resize(requests.size());
      for (std::size_t r = 0; r < requests.size(); ++r) {
        EscapeObservations& e = batch.observations[r];
        e.parameter = requests[r].parameter;
        e.stretch = 2.0 * options.window;
        e.duration = StretchCount(requests[r].duration, options.window) * e.stretch;
      }
      int failed = 0;
      double copies_cpu = 0.0;
      long long copies_work = 0;
      for (std::size_t n = 0; n < list.size(); ++n) {
        const CopyOutcome o = Unpack(out[n]);
        copies_cpu += o.cpu_seconds;
        copies_work += o.work;
        EscapeObservations& e = batch.observations[list[n].request];
        if (o.failed) ++failed;
        else if (o.stretch > 0) e.escape_stretch.push_back(o.stretch);
        else ++e.stayed;
      }
      // The copies run here are in this process's counts already; those of other ranks are not.
      batch.cost = 1e-9 * static_cast<double>(copies_work);
      escape_cpu += std::max(0.0, copies_cpu - (ProcessCpuSeconds() - local_start));
      escape_work += std::max(0LL, copies_work - (loop_work.Work() - local_work));
      if (failed > 0) note(fmt::format("  {} copies failed to integrate (counted neither as escaped nor as stayed)", failed));
      for (EscapeObservations& e : batch.observations) {
        if (e.escape_stretch.empty() && e.stayed == 0) ++e.stayed;  // never: every copy failed
      }
      return batch;
    };
    LoopEscapeDesign record;
    record.direction = c.direction;
    record.seen_from_rpm = c.seen_from_rpm;
    record.seen_to_rpm = c.seen_to_rpm;
    record.target = Describe(structure, target);
    record.design = RunEscapeDesign(design, runner, [&](const std::string& line) { note("  " + line); });
    const EscapeDesign& d = record.design;
    c.cpu_seconds = spent() - before;
    c.escape_design = static_cast<int>(result.escape_designs.size());
    c.evidence = fmt::format("escapes/{}", result.escape_designs.size());
    result.escape_designs.push_back(record);
    // A crisis leaks: memoryless, exponential lifetimes. A deterministic passage past a point no
    // level located also makes copies leave and a law fit: told apart by the escape times' spread.
    const bool law = d.fit.status == CrisisStatus::kLocated && !std::isnan(d.leave.median);
    const LifetimeShape shape = CheckExponential(d.observations);
    note("  L3: " + shape.message);
    if (law && !shape.exponential) {
      c.note += fmt::format("; L3: {}; {}", d.BriefReport(), shape.message);
    } else if (law) {
      c.level = "L3";
      const RubRegime departure = run.regimes.regime[static_cast<std::size_t>(contacts.front())][from];
      c.cause = departure == RubRegime::kWhip ? "crisis of a chaotic whip" : "crisis of a chaotic state";
      c.speed_rpm = d.leave.median;
      c.lower_rpm = std::min(d.leave.low, d.leave.high);
      c.upper_rpm = std::isnan(d.leave.high) ? kNaN : std::max(d.leave.low, d.leave.high);
      c.interval = fmt::format("run-{} with {:g} rpm steps and {:g} s per speed: 5–95 % of the speed it leaves at",
                               c.direction, options.step_rpm, options.dwell);
      c.crisis_lower_rpm = d.fit.lower_bounded ? d.fit.critical_lower : kNaN;
      c.crisis_upper_rpm = d.fit.upper_bounded ? d.fit.critical_upper : kNaN;
      c.note = fmt::format("escape rates κ = A·({})^γ, γ = {:.3g}: p_c = {:.2f} rpm ({}); the median's 95 % interval {}; "
                           "{} ensembles, {}",
                           sign > 0 ? "p − p_c" : "p_c − p", d.fit.exponent, d.fit.critical,
                           d.fit.lower_bounded && d.fit.upper_bounded
                               ? fmt::format("95 % {:.2f} … {:.2f}", d.fit.critical_lower, d.fit.critical_upper)
                           : d.fit.upper_bounded ? fmt::format("below {:.2f} at 95 %: one-sided", d.fit.critical_upper)
                           : d.fit.lower_bounded ? fmt::format("above {:.2f} at 95 %: one-sided", d.fit.critical_lower)
                                                 : "not bounded",
                           std::isnan(d.median_lower) ? "open: " + d.median_open
                                                      : fmt::format("{:g} … {:g} rpm", d.median_lower, d.median_upper),
                           d.observations.size(), ToString(d.status)) +
               "; " + shape.message + "; before it " + c.note;
    } else {
      c.note += fmt::format("; L3: {}", d.BriefReport());
    }
  }

  // The routes of whip ends that are no orbit: the latest state of the run on the whip that is one,
  // by bisection over its settled states with steady contacts (a route into chaos passes periodic
  // states first), the latest first; then its family and doubled family (studies/loop.h, L2).
  for (const PendingRoute& r : routes) {
    LoopCorner& c = result.corners[r.corner];
    LoopOrbits& asked = result.orbits[static_cast<std::size_t>(c.orbits)];
    const LoopRun& run = c.direction == "up" ? result.up : result.down;
    const int sign = DirectionSign(run.direction);
    const double lo = std::min(c.seen_from_rpm, c.seen_to_rpm) - options.step_rpm;
    const double hi = std::max(c.seen_from_rpm, c.seen_to_rpm) + options.step_rpm;
    const double before = spent();
    if (used() >= options.budget) {
      c.note += "; L2's route to the whip's end not asked: the budget was spent deciding the corners";
      continue;
    }
    note(fmt::format("L2 route for {} {} {:g} → {:g} rpm ({}): the latest periodic state on the whip", c.direction,
                     c.kind, c.seen_from_rpm, c.seen_to_rpm, c.contact));
    std::vector<std::size_t> states;
    for (std::size_t k = r.first_on; k < r.from; ++k) {
      const double hz = run.regimes.precession_hz[0][k];
      if (std::isfinite(hz) && hz > 0.0 && SteadyContacts(structure, run.points[k], 1.0 - options.barely_touching)) {
        states.push_back(k);
      }
    }
    int below = -1, above = static_cast<int>(states.size());  // an orbit at `below`, none from `above` on
    for (int tries = 0; tries < options.route_tries && above - below > 1 && used() < options.budget; ++tries) {
      const int mid = tries == 0 ? above - 1 : (below + above) / 2;
      const std::size_t k = states[static_cast<std::size_t>(mid)];
      const double t0 = spent();
      const ModulatedOrbit o = SolveModulatedOrbit(balanced, run.points[k].parameter,
                                                   HzToRadPerSecond(run.regimes.precession_hz[0][k]), run.states[k],
                                                   options.orbit_start);
      const std::string tried = fmt::format("{:g} rpm {} ({:.1f} s CPU)", RadPerSecondToRpm(run.points[k].parameter),
                                            o.converged ? fmt::format("an orbit of modulation {:.4g} Hz", 1.0 / o.period)
                                                        : "no orbit",
                                            spent() - t0);
      note("  L2 route: " + tried + (o.converged ? "" : ": " + o.message));
      asked.tries += (asked.tries.empty() ? "" : "; ") + tried;
      (o.converged ? below : above) = mid;
    }
    if (states.empty()) note("  L2 route: no settled state with steady contacts on the whip");
    if (below >= 0 && used() < options.budget) {
      // The family from the latest orbit (its start solved again from the run's state: one more
      // Newton, a few seconds).
      const std::size_t k = states[static_cast<std::size_t>(below)];
      const double orbit_rpm = RadPerSecondToRpm(run.points[k].parameter);
      RubTransientOrbits route = ContinueTransientOrbits(
          balanced, run.points[k].parameter, HzToRadPerSecond(run.regimes.precession_hz[0][k]), run.states[k],
          options.orbit_start, family_over(orbit_rpm, sign, lo, hi), options.orbit_steps);
      if (route.start.converged) {
        asked.route = true;
        asked.orbit_rpm = orbit_rpm;
        asked.orbits = std::move(route);
      }
    }
    if (asked.route) {
      const OrbitSkeletonEnd end = ride_family(asked, sign, lo, hi).end;
      const bool early = end.found && sign * (RadPerSecondToRpm(end.lambda) - c.seen_from_rpm) < 0.0;
      c.note += fmt::format("; L2's route (asked after every corner was decided): the state at {:g} rpm is a relative "
                            "periodic orbit (tries: {}), {}{}",
                            asked.orbit_rpm, asked.tries, asked.skeleton,
                            early ? fmt::format(", {:.2f} rpm before the jump: the state the run leaves is no periodic "
                                                "orbit",
                                                std::abs(RadPerSecondToRpm(end.lambda) - c.seen_from_rpm))
                                  : "");
    } else {
      c.note += fmt::format("; L2's route (asked after every corner was decided): no periodic state on the way to "
                            "the whip's end ({})",
                            asked.tries.empty() ? "no settled state with steady contacts on the whip" : asked.tries);
    }
    c.cpu_seconds += spent() - before;
  }

  // The status.
  result.status = LoopStatus::kExplained;
  for (const LoopCorner& c : result.corners)
    if (c.level.empty()) result.status = LoopStatus::kPartly;
  for (const LoopRun* run : {&result.up, &result.down}) {
    if (!run->message.empty()) {
      result.status = LoopStatus::kRunFailed;
      result.message = fmt::format("the {} run: {}", ToString(run->direction), run->message);
    }
  }
  result.work = used();
  result.cpu_seconds = spent();
  result.wall_seconds = SecondsSince(wall_start);
  return result;
}

}  // namespace rubcont
