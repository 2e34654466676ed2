// The hysteresis loop of a rub rotor, explained: every jump a run-up and a run-down make, why each
// happens, how sure, and which level decided it (`rubcont loop`; docs/loop.md).
//
// The run. A run-up visits the speeds p_0 < p_1 < … of its schedule (step_rpm apart) and stays
// `dwell` seconds at each; a run-down the same from the top. Which state the rotor is on at each
// speed, and where it jumps, is what a time-marching sweep shows (level L3). This study follows
// the run the same way (the tracker: the sweep's own stepper, integrators and regime rules) but
// integrates only where no cheaper level already knows the answer:
//
//  L1  The rotating waves (circular whirl and whip) of the tanh law the sweep integrates, with
//      their stability and special points (waves/rotating_wave_branches.h). Wherever the tracked
//      state lies on a stable wave (the jump table's matching rule, studies/jump_prediction.h;
//      and settled, each contact touching all the time or never, as a circular wave does),
//      the run is known to stay on it until that wave's stable stretch ends (StableLimitFrom): the
//      tracker is moved there, onto the wave's own state (skip), and integrates again from the
//      last schedule speed before the limit. Every jump the tracker then sees whose departure or
//      landing state lies on a wave with a special point near it is that point's (knee, Hopf,
//      fold, branch point, contact loss …): cause, speed and level L1.
//  L2  A jump no special point of the waves explains is escalated, first to L2: is the state the
//      run leaves a relative periodic orbit (a modulated whirl or whip, shot from the tracker's
//      own state: shooting/rub_orbits.h ContinueTransientOrbits), and does its family, continued
//      from the departure towards the landing, end or lose stability in between — a fold, a
//      period doubling, a Neimark–Sacker point, a branch point, a contact lifting off or touching
//      down? Then that point is the cause, at level L2.
//      The skeleton. A run on a stable orbit family rides it to the first point that ends its state
//      (RideFamily, SkeletonEnd). At a period doubling that bounds a stable piece the run does not
//      jump if the doubled orbits are stable there: it moves on to them (supercritical: the doubled
//      family is stable from the doubling on; subcritical, as A(a)'s whip at 128.35 rpm: the
//      doubled orbits born there are unstable, turn at a fold and gain stability at a
//      Neimark–Sacker point, and their stable stretch holds the doubling's speed), and rides them to
//      where that stretch ends — their own grazing (a contact lifting off), fold, further doubling
//      or Neimark–Sacker point. So L2 follows the doubled family from the doubling the run meets
//      (ContinueTransientDoubling, at most doubled_steps steps, ending at its first grazing: past
//      it a fixed mesh only creeps) and reports that end as the cause when it lies in the jump
//      ("grazing of the period-doubled state"); a doubling whose doubled orbits are unstable
//      there is itself the cause, as before. A further doubling on the doubled family is named as
//      the end, not followed (a cascade is for [analysis.orbits], not the loop's budget).
//      The route. A whip's end whose departure is no orbit (a chaotic whip: A(a) at 180 rpm) was
//      not left at an orbit's end, but the way into it is the skeleton too: L2 looks for the
//      latest state of the run on the whip that is a relative periodic orbit (bisection over its
//      settled states with steady contacts, at most route_tries starts: a route into chaos
//      passes periodic states first), rides that orbit's family and its doubled family as above,
//      and names where the stable periodic whip ends ("…, 42.4 rpm before the jump: the state the
//      run leaves is no periodic orbit"). The jump stays L3's. The route explains and never
//      decides, so it is asked after every corner is decided, with what is left of the budget: the
//      default scene's loop at 120 s, route first, had no budget left for its whip end's L3.
//  L3  When L2 has no orbit (the state is no periodic motion) or its family passes the jump
//      unchanged, L3. When the run leaves its state
//      by chance — a chaotic whip past a crisis, whose lifetime falls with speed — the speed at
//      which a run of this schedule leaves it is a random variable: its median and 5–95 % range
//      are measured by the sequential escape design (sweeps/escape_design.h) with copies of the
//      tracker's own states, and the crisis's p_c with its profile interval stands beside them.
//      The copies run over the job runner (threads, or the ranks of an MPI run); the design's
//      choices depend only on their outcomes.
//  A jump nothing explains within the budget says so, with what was tried — never a guess.
//  L4: a scene with [flexible] runs all of this on its flexible structure (the caller's level).
//
// The budget is CPU seconds for the whole loop: the waves and the tracker first (they are needed
// for everything), then the escalations in order of importance — the first whirl → whip and the
// last whip → whirl jump of each direction, then the rest in speed order.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "shooting/rub_orbits.h"
#include "solvers/parallel.h"
#include "studies/jump_prediction.h"
#include "sweeps/escape_design.h"
#include "sweeps/rub_runs.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

struct LoopOptions {
  // The sweeps of the scene in both directions: their ranges [rad/s] (sweep.parameters' first and
  // last speed; the loop lays its own schedule over them), integrators, windows, regime rules and
  // impulse. Their dwell and step are replaced by `dwell` and `step_rpm`.
  RubSweepOptions up;
  RubSweepOptions down;
  double step_rpm = 2.0;  // [rpm] > 0: the run's speed step (the thesis: 2 rpm)
  double dwell = 1.5;     // [s] > 0: time at each speed (the thesis: 1.5 s)
  // The rotating waves (tanh law at the structure's ε) over the sweeps' range.
  RotatingWaveBranchOptions waves;
  JumpMatchOptions match;  // a tracked state on a wave, a special point near a jump
  // The escape design of a jump L1 does not explain (schedule, dwell, candidates and first are
  // the loop's): copies per ensemble, durations, the width asked of the median's interval.
  EscapeDesignOptions escapes;
  double window = 0.05;       // [s] > 0: a copy's state is read every two windows
  double perturbation = 1e-6;  // of each copy, in units of each state's scale (≥ 0)
  // How far below (run-up) or above (run-down) the tracker's last speed on the state the escape
  // design may place its ensembles [rpm] ≥ step_rpm.
  double escape_reach_rpm = 16.0;
  // A contact in touch for less than this share of the analysed time at both speeds of a jump
  // reads its precession off its free orbit (C(a)'s left contact at 180–216 rpm, 4 rpm / 0.75 s: 2–10 %, its
  // "precession" wandering 301 → 416 Hz from speed to speed): such a jump is a flicker of readings,
  // not of the rotor's state, and is not escalated. In (0, 1].
  double barely_touching = 0.1;
  // L2: the departure's orbit (its shooting and mesh: the scene's [analysis.orbits]) and its family
  // (range and direction are set per jump: from the departure to a step past the landing), with
  // at most orbit_steps continuation steps (≥ 1). orbits = false: no L2.
  bool orbits = true;
  ModulatedOrbitOptions orbit_start;
  PeriodicOrbitBranchOptions orbit_family;
  int orbit_steps = 30;
  // L2's route to a departure that is no orbit (a chaotic whip): the latest of the run's states on
  // the departure's regime that is one, by bisection over its settled states with steady contacts
  // (SolveModulatedOrbit from each), with at most route_tries starts (≥ 0; 0: no route). A(a)'s
  // run-up: 48 such states from 52 to 146 rpm; 6 starts found the latest orbit (128 rpm) in 35 s.
  int route_tries = 6;
  // The doubled family from the period doubling the run meets on the L2 family (one that bounds a
  // stable piece), with at most doubled_steps continuation steps (≥ 0; 0: not followed) and ending
  // at its first grazing. A(a)'s doubled whip from its doubling (128.36 rpm) down to its fold
  // (121.0) and up to its grazing (137.6) took 120 steps on the loop's 400 intervals (237.5 s of
  // CPU), 112 on 1600 with the curved predictor (results/thesis_A_a_whip_doubling).
  int doubled_steps = 200;
  // The work the whole loop may do [G work units] > 0: its integrations' cost (counted in a
  // WorkAccount of its own, solvers/ode.h), the same on every machine and under any load, so that a
  // loop explains the same corners wherever it runs (a budget in CPU seconds explained fewer on a
  // slower machine, or beside another job). The committed loops took 75–94 s of CPU per G here
  // (2026-11-30, two at a time; A(a) 9.67 G in 763 s).
  double budget = 4.0;
  // An escape design is not started with less of the budget left [G work units] ≥ 0: its first
  // batch (3 ensembles of 8 copies × 2 s) costs 0.3–0.6 G in an impacting whip (A(a), B(b)).
  double min_escape_budget = 0.4;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const LoopOptions& options);

// A stretch of a run decided by L1: the tracker stood on a stable wave and moved along it.
struct LoopSkip {
  double from_rpm = 0.0;
  double to_rpm = 0.0;
  std::string branch;  // the wave
  std::string limit;   // what ends its stable stretch (SpecialPoint::Name()), or why none
};

// The share of the analysed time contact `k` touched at `point` (its channel's active_fraction), or
// NaN where the point has no channel for it (a failed speed).
double ContactTimeShare(const SweepPoint& point, std::size_t k);

// One direction of the run as the tracker followed it.
struct LoopRun {
  SweepDirection direction = SweepDirection::kUp;
  std::vector<double> schedule_rpm;  // every speed of the run's schedule
  std::vector<SweepPoint> points;    // the speeds integrated, in order
  std::vector<Vector> states;        // the state after each of them
  RubSweepRegimes regimes;           // of `points`
  std::vector<LoopSkip> skips;
  std::vector<PredictedJump> jumps;  // seen by the tracker, with the L1 attribution
  std::string message;               // why the run ended early ("" when it reached the end)
  // Where the run ends: "left whirl, right whirl at 256 rpm" (RegimeList at its last speed).
  std::string end;
  double cpu_seconds = 0.0;
};

// A jump of the loop: a row of /loop/corners.
struct LoopCorner {
  std::string direction;  // "up", "down"
  std::string kind;       // RubJumpKind: "whirl_to_whip", "whip_to_whirl", "contact_lost", …
  std::string contact;    // "left", "right", or "left, right" where they jump alike
  double speed_rpm = 0.0;  // where the run jumps (the bifurcation's speed, or the median)
  double lower_rpm = 0.0;  // with `interval` saying what [lower, upper] is
  double upper_rpm = 0.0;
  std::string interval;
  std::string cause;  // "knee", "Hopf", "fold", …, "crisis of a chaotic whip", "not explained"
  std::string level;  // "L1", "L2", "L3"; "" when not explained
  std::string evidence;  // the result file's dataset that shows it (set by the writer's layout)
  double cpu_seconds = 0.0;         // spent on deciding it (beyond the waves and the tracker)
  double crisis_lower_rpm = 0.0;    // the crisis's p_c interval (NaN unless L3; an end the data
  double crisis_upper_rpm = 0.0;    // do not bound is NaN, said in `note`)
  std::string note;                 // what was tried, and the numbers behind the cause
  // The jump as the tracker saw it.
  double seen_from_rpm = 0.0;
  double seen_to_rpm = 0.0;
  double precession_from_hz = 0.0;
  double precession_to_hz = 0.0;
  int orbits = -1;         // index into LoopResult::orbits (−1: L2 not asked)
  int escape_design = -1;  // index into LoopResult::escape_designs (−1: none)
};

enum class LoopStatus {
  kExplained,     // every corner has a cause
  kPartly,        // some corners are not explained (within the budget or at all)
  kRunFailed,     // a tracker's integration failed: the loop is incomplete
};
const char* ToString(LoopStatus status);

// The L2 question asked of one jump's departure state.
struct LoopOrbits {
  std::string direction;
  double seen_from_rpm = 0.0;
  double seen_to_rpm = 0.0;
  // Where the orbit was shot from: the departure, or the state the route found (its speed [rpm]).
  double orbit_rpm = 0.0;
  bool route = false;  // the departure is no orbit: orbit_rpm is the route's
  std::string tries;   // the route's starts and their outcomes, in order ("" without a route)
  // The start (converged or why not), its family (orbits.family.orbits: period 1) and, beside it,
  // the doubled family from the period doubling the run meets on it (orbits.family.doublings: none
  // or one, ContinueTransientDoubling).
  RubTransientOrbits orbits;
  // The stable state's end the run meets along them (SkeletonEnd), in words with its numbers.
  std::string skeleton;
};

// Where the stable state a run rides on an orbit family ends, going `sign` (+1: up in λ) from
// λ = `from` (a stable orbit of `family`): at the first special point past `from` that ends a state
// (a fold, period doubling, Neimark–Sacker or branch point, a multiplier +1, a grazing). At a
// period doubling the run moves on to the doubled orbits where they are stable there: the doubled
// family followed from that point (an element of `doublings` whose special_point is it) has a
// stable stretch whose speeds hold the doubling — supercritical, the stretch that starts at it;
// subcritical, the stretch past the doubled orbits' fold and Neimark–Sacker point, as A(a)'s —
// and the state ends where that stretch ends in the run's direction (the special point there). A
// doubling whose doubled orbits are unstable there (or not followed) is itself the end: the run
// jumps.
struct OrbitSkeletonEnd {
  bool found = false;   // false: the families as computed end before any such point
  double lambda = 0.0;  // of the end (NaN when not found)
  std::string name;     // SpecialPoint::Name() of the end
  SpecialPointType type = SpecialPointType::kFold;  // and its type
  bool doubled = false;  // the end lies on the doubled family
  double doubling_lambda = 0.0;  // the period doubling passed on the way (NaN if none)
  std::string route;     // the way in words, λ in `unit` (e.g. "period doubling at 128.32, ...")
};
// `scale` converts λ to the unit the route is written in (rpm per rad/s for the loop), `unit` names it.
OrbitSkeletonEnd SkeletonEnd(const PeriodicOrbitBranch& family, const std::vector<OrbitPeriodDoubling>& doublings,
                             double from, int sign, double scale = 1.0, const std::string& unit = "");
// The stable state a run rides on `family` from its orbit at λ = `orbit` — or, where that orbit is
// unstable, from the family's last stable orbit before it (the run left the family there) — to its
// end (SkeletonEnd). Where that end is a period doubling that bounds a stable piece of the family,
// lies before `far` in the run's direction and has no doubled family in `doublings` yet, `follow`
// (when set) continues the doubled family from it (the family's special point index), appended to
// `doublings`, and the end is sought along it.
using DoublingFollower = std::function<OrbitPeriodDoubling(std::size_t special_point)>;
struct OrbitRide {
  bool rides = false;   // the family has a stable orbit at or before `orbit`
  double from = 0.0;    // where the ride starts (NaN when it does not)
  OrbitSkeletonEnd end;
  std::string text;     // "the run rides the family from 125.6 rpm: period doubling at …"
};
OrbitRide RideFamily(const PeriodicOrbitBranch& family, double orbit, int sign, double far,
                     std::vector<OrbitPeriodDoubling>& doublings, const DoublingFollower& follow,
                     double scale = 1.0, const std::string& unit = "");
// Whether a special point ends the state a run is on (the kinds SkeletonEnd stops at).
bool EndsState(const SpecialPoint& p);

// The speeds an escape design tries for a corner of a run on `schedule` [rpm], `sign` its direction
// (+1 up): the schedule's from `reach` before the departure `seen_from` (not before `first_on`, where
// the run was first seen on the departure state) to two steps (`step`) past the landing `seen_to`;
// and `first`, the one nearest the landing. Decision: the nearest, not the landing itself — the
// run's points carry their speeds through rad/s, and RadPerSecondToRpm(RpmToRadPerSecond(126)) is
// 126.00000000000001, no candidate (C(c)'s loop ended there with exit 2 on 2026-11-30).
struct EscapeCandidates {
  std::vector<double> speeds;
  double first = 0.0;
};
EscapeCandidates EscapeCandidatesFor(const std::vector<double>& schedule, int sign, double seen_from,
                                     double first_on, double seen_to, double reach, double step);

struct LoopEscapeDesign {
  std::string direction;
  double seen_from_rpm = 0.0;
  double seen_to_rpm = 0.0;
  std::string target;  // what a copy arrives at, in words (Describe)
  EscapeDesign design;
};

struct LoopResult {
  LoopStatus status = LoopStatus::kExplained;
  std::string message;
  std::vector<RotatingWaveBranch> waves;
  LoopRun up, down;
  std::vector<LoopCorner> corners;  // the table: run-up first, each direction in speed order
  std::vector<LoopOrbits> orbits;  // every L2 question, in order
  std::vector<LoopEscapeDesign> escape_designs;
  // Every escalation and why, in order ("L3 for up whip_to_whirl 180 → 184 rpm: no special point
  // of the waves within 10 rpm of it"), and what the budget stopped.
  std::vector<std::string> decisions;
  double work = 0.0;  // [G work units]: what the budget counts
  double cpu_seconds = 0.0;
  double wall_seconds = 0.0;
  std::string BriefReport() const;
};

struct LoopProgress {
  std::function<void(const std::string& line)> note;  // decisions and stages, as they are made
  // After each tracked speed: the direction and the speed [rpm].
  std::function<void(SweepDirection direction, double speed_rpm)> speed;
};

// The loop of `structure` (its fixed frame, with imbalance if any; the waves are those of its
// balanced rotor, and an imbalanced rotor's runs are integrated at every speed: no skip). `jobs` runs the escape copies (ThreadJobs, or the ranks of an MPI run). Throws
// std::invalid_argument for invalid options.
LoopResult ComputeLoop(const RubStructure& structure, const LoopOptions& options, const JobRunner& jobs,
                       const LoopProgress& progress = {});

}  // namespace rubcont
