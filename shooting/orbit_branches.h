// Periodic orbits continued in the system's parameter: the "orbits" stage of the textbook scenes
// (and of any OdeSystem with a periodic orbit to follow).
//
//   1. a start: a point on (or near) the orbit and its period, from a transient that has settled
//      onto an attracting orbit (SettleOnCycle for autonomous systems, SettleForced for forced
//      ones), or from anything else close enough for Newton;
//   2. ContinuePeriodicOrbits: a ShootingProblem (single or multiple shooting) started there and
//      continued with the engine both ways to the ends of [lambda_min, lambda_max] (one way when
//      the start is at an end), the two runs joined (JoinAtStart; a closed curve followed round
//      by the first run is not followed again the other way), Floquet stability at every
//      point, folds, period doubling and Neimark–Sacker points located (continuation.h).
//
// Use:
//     VanDerPolOscillator vdp({0.5});
//     const OrbitStart start = SettleOnCycle(vdp, Vector2(2, 0), 200.0, 1, {});
//     PeriodicOrbitBranchOptions options;
//     options.lambda_min = 0.5;  options.lambda_max = 10;  options.shooting.segments = 4;
//     const PeriodicOrbitBranch b = ContinuePeriodicOrbits(vdp, OrbitKind::kAutonomous, start,
//                                                          options);
//     // b.branch.Measure("period"), b.branch.points[i].spectrum, b.branch.special_points
#pragma once

#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/branch_switching.h"
#include "continuation/continuation.h"
#include "continuation/options.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"

namespace rubcont {

// A point near a periodic orbit.
struct OrbitStart {
  Vector x0;            // state at t = 0 (kForced: at the forcing phase 0)
  double period = 0.0;  // period guess (kForced: ignored, the forcing period applies)
  double lambda = 0.0;  // the system's parameter there
  bool valid = false;
  std::string message;  // why not, when !valid
  double rotation = 0.0;  // φ guess, x(T) = R_φ x(0) (kRelative; ignored otherwise)
};

// Integrates the autonomous system from x0 over `duration` at its current parameter, recording the
// falling zeros of state `section_state` (a Poincaré section); the start is the state at the last
// crossing and the period the time between the last two. Invalid when fewer than two crossings are
// found, the integration fails, or the last two periods differ by more than 1e-6 relative (the
// transient has not settled).
OrbitStart SettleOnCycle(OdeSystem& system, const Vector& x0, double duration, Index section_state,
                         const IntegratorOptions& integrator);

// Integrates the forced system from x0 over `periods` forcing periods at its current parameter (so
// that the forcing phase is 0 again): the start of an attracting forced orbit.
OrbitStart SettleForced(OdeSystem& system, const Vector& x0, int periods,
                        const IntegratorOptions& integrator);

struct PeriodicOrbitBranchOptions {
  double lambda_min = 0.0;  // parameter range (system units), lambda_min ≤ start ≤ lambda_max
  double lambda_max = 1.0;
  // The shooting problem; refresh_phase_reference is set for autonomous and relative orbits.
  ShootingOptions shooting;
  // The engine; bounds.lambda_min / lambda_max are overwritten by the range above,
  // detect.stability is switched on, and direction is set per run.
  ContinuationOptions continuation;
  // Replaces the default measures (max and min of every state) when not empty.
  std::vector<OrbitMeasure> measures;
  // Located along the branch where they change sign (e.g. Grazing); none by default.
  std::vector<OrbitTestFunction> test_functions;
  // End a run once it is round a closed curve (RoundClosedCurve; status kClosed, the message names
  // the folds), and then do not run the other way: a resonance tongue's locked orbits. The
  // engine's own closure test compares the unknowns, and with the phase reference moved along the
  // family (refresh_phase_reference) an orbit met again has other segment starts: measured on
  // C(a)'s 1:3 orbits, followed round and round.
  bool stop_round_closed_curve = false;
  // End a run at its first located grazing (a kGrazing test's zero that converged: an orbit
  // tangent to a switching surface; status BranchStatus::kGrazing, the message names it; the step
  // is cut there: ContinuationOptions' bounds.end_at_grazing), instead of continuing past it.
  // Past A(a)'s grazing the fixed collocation mesh creeps 87 orbits in halving steps over 0.33 rpm
  // (640 s) to a corrector failure (issue 49; bench/whip_family_bench.cpp);
  // ContinueAcrossSwitches (shooting/switching_orbits.h) continues there.
  bool stop_at_grazing = false;
  // End a run at its first located Neimark–Sacker point (status kStoppedByCaller, the message
  // names it): where the point is all a caller wants of the family (ContinueCentreOrbits proving
  // where a torus family ends), not the family beyond it.
  bool stop_at_neimark_sacker = false;
  // The rub families' independent check (shooting/rub_orbits.h: RubOrbitMeasures' "defect", each
  // orbit integrated again by Dormand–Prince 5(4) at 1e-12; 3 % of the CPU of A(a)'s whip family
  // to its grazing, docs/performance.md): false leaves it out of the measures those functions set.
  bool defect_check = true;
  // Called after every step of either run (progress of long runs); returning false ends that run.
  StepCallback on_step;
  // 0: both ways from the start (one way from an end of the range); ±1: only that way in λ.
  int direction = 0;
};

// The orbit of a branch point computed with `shooting` as a start: its first segment's start,
// period and rotation, at the point's λ.
OrbitStart OrbitStartAt(OdeSystem& system, OrbitKind kind, const ShootingOptions& shooting,
                        const BranchPoint& point);

// The parameters of a branch's located folds, ascending, each once (a closed curve followed
// round again meets its folds again, to within the location's tolerance).
std::vector<double> DistinctFolds(const Branch& branch);

// Whether a branch started at `start_lambda` has gone round a closed curve: two distinct folds
// located and its last step back across start_lambda.
bool RoundClosedCurve(const Branch& branch, double start_lambda);

// The engine's end test for that (stop_round_closed_curve, and the locked orbits of
// ContinueLockedOrbits): status kClosed once RoundClosedCurve(branch, start_lambda), the message
// naming the folds.
EndTest EndRoundClosedCurve(double start_lambda);
// The end at the first converged Neimark–Sacker point (PeriodicOrbitBranchOptions::
// stop_at_neimark_sacker): status kStoppedByCaller.
EndTest EndAtNeimarkSacker();
// The ends `options` ask for (stop_round_closed_curve, stop_at_neimark_sacker) as one end test of
// a run started at start_lambda; empty when they ask for none. (stop_at_grazing is the engine's:
// OrbitContinuationOptions.)
EndTest OrbitEndTest(const PeriodicOrbitBranchOptions& options, double start_lambda);
// The engine's options for a family of `options`: its continuation options with its λ range,
// stability on, and bounds.end_at_grazing = stop_at_grazing.
ContinuationOptions OrbitContinuationOptions(const PeriodicOrbitBranchOptions& options);

// Throws std::invalid_argument naming the field (an empty or non-finite range).
void Validate(const PeriodicOrbitBranchOptions& options);

struct PeriodicOrbitBranch {
  OrbitKind kind = OrbitKind::kForced;
  Branch branch;             // both runs joined at the start (or the one run)
  Index state_dimension = 0;
  int segments = 1;
  double start_lambda = 0.0;
  ShootingStatistics work;   // integrations of both runs
  // The shooting options the branch was computed with, its scales filled in (period_scale,
  // lambda_scale): a branch switch continues in the same scaled variables.
  ShootingOptions shooting;
};

// Throws std::invalid_argument for an invalid start (start.valid false: its message), a start
// outside the range, or invalid options. Numerical failures end the branch with a status
// (Branch::status, message).
PeriodicOrbitBranch ContinuePeriodicOrbits(OdeSystem& system, OrbitKind kind,
                                           const OrbitStart& start,
                                           const PeriodicOrbitBranchOptions& options);

// The other branch through a located branch point of a periodic-orbit family: the direction from
// the algebraic branching equation (continuation/branch_switching.h), followed with the family's
// shooting (PeriodicOrbitBranch::shooting, the phase reference at the last orbit before the point)
// over [options.lambda_min, options.lambda_max] with options.continuation and options.measures,
// to its first located grazing with stop_at_grazing (OrbitContinuationOptions).
//
// With a mirror symmetry κ (OdeSystem::HasMirrorSymmetry) the point is classified. Where the
// family's orbits on both sides of the point are symmetric (asymmetry ≤ kSymmetricOrbit) the
// branch point lies in the symmetric subspace: the located point is projected onto it ((u + κu)/2;
// located on the determinant it has drifted along the odd kernel direction, 8e-5 on A(a)), and
// when the new direction is odd (its κ-odd part ≥ 0.9 of it) the point is a symmetry-breaking
// pitchfork: the two sides of the new branch are each other's mirror images and only side +1 is
// followed, up to where its orbits are symmetric again (asymmetry of the segment starts back to
// kSymmetricOrbit after exceeding 1e-3: the branch has met the symmetric family at another
// pitchfork; status kStoppedByCaller, the message says where). Otherwise both sides are followed.
struct OrbitBranchSwitch {
  static constexpr double kSymmetricOrbit = 1e-8;
  std::size_t special_point = 0;   // index into the family's branch.special_points
  bool ok = false;                 // false: no direction (message says why), no branches
  std::string message;
  BranchSwitch change;             // ABE coefficients, angle, direction (side +1)
  bool mirror_symmetric_orbit = false;   // the family is κ-symmetric at the point
  bool breaks_mirror_symmetry = false;   // ... and the new direction is κ-odd
  double direction_odd_part = kNaN;  // in [0, 1]
  // Where side +1 rejoined the symmetric orbits: λ of its last two points (NaN if it did not).
  double rejoined_between[2] = {kNaN, kNaN};
  // Whether side +1 rejoined the symmetric orbits near λ: within the interval of its last two
  // points widened by its length each way (the far pitchfork is a tip in λ, λ* − λ ∝ (odd part)²:
  // both points may lie on one side of it).
  bool RejoinedNear(double lambda) const;
  std::vector<PeriodicOrbitBranch> branches;  // side +1, then side −1 unless mirror images
};

// Throws std::invalid_argument when special_point is not a branch point of the family or the
// options are invalid.
// on_step is called after every continuation step of each side (returning false stops it).
OrbitBranchSwitch ContinueOrbitsFromBranchPoint(OdeSystem& system,
                                                const PeriodicOrbitBranch& family,
                                                std::size_t special_point,
                                                const PeriodicOrbitBranchOptions& options,
                                                const StepCallback& on_step = {});

// The record of a family `problem` computed: its kind, dimensions and work, `shooting` with the
// scales the problem chose (a branch switch continues in the same scaled variables), and `branch`,
// started at `start_lambda`.
PeriodicOrbitBranch FamilyOf(const ShootingProblem& problem, const ShootingOptions& shooting,
                             double start_lambda, Branch branch);

// The linearized return map x ↦ R_{−φ} x(T) of a family's orbit at one of its points (`u`, λ of
// a special point): the product of the segment STMs turned back by the orbit's rotation
// (autonomous orbits: φ = 0), with the segment starts, T and φ. What the branch switches at period
// doublings and Neimark–Sacker points start from.
struct OrbitReturnMap {
  bool ok = false;
  std::string message;       // why not (an integration failed)
  std::vector<Matrix> stms;  // per segment
  Matrix starts;             // n × segments
  std::vector<double> mesh;  // the segment boundaries (event boundaries where the point has them)
  double period = 0.0;
  double rotation = 0.0;
  Matrix map;                // n × n
};
OrbitReturnMap ReturnMapAt(OdeSystem& system, const PeriodicOrbitBranch& family,
                           const SpecialPoint& point);

// The period-doubled orbits born at a located period doubling of a family (autonomous or
// relative orbits: x(T) = R_φ x(0)). At the point the return map x ↦ R_{−φ} x(T) has the
// multiplier −1 with a real eigenvector v; the doubled orbits start there as the orbit run twice
// (2N segments, the second lap's starts R_φ x_i, period 2T, rotation 2φ) moved by `amplitude`
// (scaled state units: ‖v ./ StateScale‖ = 1) along [v_i; −R_φ v_i] (v propagated to the segment
// starts by the segment STMs, and multiplied by −1 over one lap), and are continued with the
// engine as a new family (the corrector fixes that projection and solves for λ, whichever side
// of the point the doubled orbits lie on: supercritical or subcritical). Both signs of the
// amplitude give the same orbits shifted by T: one side is followed. The doubled problem keeps
// the family's integrator, steps per segment and measures, so a Gauss mesh resolves each lap as
// before (twice the intervals per doubled period). A start whose correction fails (C(a)'s stiff
// contact at 1e-3: a non-finite residual) is tried again at amplitude/10 and amplitude/100
// (kDoublingStartAttempts in all); the message names the failed starts and `amplitude` the one
// the family started from. The family ends where options ask (stop_at_grazing).
inline constexpr int kDoublingStartAttempts = 3;
struct OrbitPeriodDoubling {
  std::size_t special_point = 0;  // index into the family's branch.special_points
  bool ok = false;                // false: no start (message says why), no branch
  std::string message;            // why not; or the starts that failed before the one used
  double amplitude = kNaN;  // the start's, scaled units
  double multiplier = kNaN;  // the real one nearest −1
  PeriodicOrbitBranch branch;     // the doubled family: period 2T, 2N segments
};

// Throws std::invalid_argument when special_point is not a period doubling of the family, the
// family's orbits are forced (a subharmonic of the forcing needs a period the forcing does not
// set: not supported) or the options are invalid.
OrbitPeriodDoubling ContinueOrbitsFromPeriodDoubling(OdeSystem& system,
                                                     const PeriodicOrbitBranch& family,
                                                     std::size_t special_point,
                                                     const PeriodicOrbitBranchOptions& options,
                                                     double amplitude = 1e-3,
                                                     const StepCallback& on_step = {});

// Whether the branch is stable on exactly one side of its special point p (the branch points
// p.index and p.index + 1 around it, both with a computed stability): where a stable state hands
// over to another.
bool BoundsStablePiece(const Branch& branch, const SpecialPoint& p);

}  // namespace rubcont
