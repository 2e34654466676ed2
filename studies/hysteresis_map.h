// Hysteresis maps of the two-point rub model: where in the plane (running speed ω, design
// parameter η) the rotor has one stable circular rub state, two coexisting ones (a speed-up and a
// speed-down run end on different states: hysteresis), or none; and the curves along which the
// jumps of a speed sweep move.
//
// Two independent computations, cross-checked against each other:
//  1. a grid in η: at each value the whole L1 branch set (ComputeRotatingWaveBranches: every
//     whirl and whip family, stability, events, folds, Hopf points). Each stable segment of a
//     branch (consecutive points of one piece, both stable) covers a speed interval; the number of
//     segments covering ω is the number of coexisting stable circular states there. The trivial
//     no-rub state (rotor centred) is not counted: it is a state of its own, reached without an
//     impulse, and the thesis sweeps start contact with one.
//  2. two-parameter continuation, from the branch set at the scene's own η, of every located event
//     (stick ↔ slip switch, contact loss or regain: EventCurveProblem, continuation/event_curve.h),
//     every located fold (minimally augmented, ContinueFoldCurve with cusp detection) and every
//     Hopf point (ContinueHopfCurve, continuation/hopf.h: where a circular state loses or gains
//     stability through a complex pair, with its Bogdanov–Takens, zero-Hopf and double-Hopf points,
//     and ending where the Hopf point reaches a switch) in (ω, η). These curves are the region
//     boundaries at the precision of the location (~1e-10), where the grid resolves them only to
//     its spacing; the grid's special points must lie on them.
//
// Level L1 (rotating waves, exact friction law by default): the map inherits the branch set's
// assumptions (isotropic supports, no imbalance, circular orbits only). With the regularized
// (tanh) law the branch sets are computed without the knee test functions, which would otherwise
// be recorded at the turning points in place of the folds; the folds are then continued.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "continuation/branch.h"
#include "continuation/fold_optimization.h"
#include "waves/rotating_wave_branches.h"
#include "waves/rotating_wave_parameters.h"

namespace rubcont {

struct HysteresisMapOptions {
  DesignParameter parameter = DesignParameter::kFriction;
  double eta_min = 0.0;        // η range, parameter units, inside the physical range, < eta_max
  double eta_max = 0.0;
  int eta_points = 31;         // grid values of η (≥ 2)
  int speed_points = 481;      // grid speeds for the stable-state count (≥ 2)
  RotatingWaveBranchOptions branches;  // speed range (search.speed_min/max, rad/s) and the rest
  bool continue_curves = true;         // part 2 above
  int curve_max_steps = 1500;          // continuation steps per half curve (≥ 1)
  double curve_max_step = 0.2;         // largest arclength step on a curve (scaled, > 0)
  int threads = 1;                     // grid values computed side by side (≥ 1)
};

// Throws std::invalid_argument naming the field, value and rule.
void Validate(const HysteresisMapOptions& options);

// A special point of the branch set at one grid value of η.
struct MapPoint {
  double eta = 0.0;
  double speed = 0.0;          // ω [rad/s]
  double precession_hz = 0.0;
  SpecialPointType type = SpecialPointType::kEvent;
  std::string label;           // event name, or "" for folds / Hopf
  bool nonsmooth_fold = false; // events where ω turns back (the sweep jumps there)
  int branch = 0;              // index into the branch set at that η
  int stable_before = -1;      // stability (1 / 0, −1 unknown) of the branch point before it
  int stable_after = -1;       // ... and after it (on the new piece for events)
};

// A turning point of an event curve in η: where two jump curves of the (ω, η) plane meet and the
// jump they mark disappears (e.g. a family's speed-up and speed-down jumps coincide: the gap or
// overlap between its whirl and its whip closes). Located twice: by the engine (fold of the curve)
// and by Ipopt as the extremum of η on the event manifold {F = 0, m_k = 0}
// (LocateFoldByOptimization on the EventCurveProblem), the engineering question "the smallest /
// largest η for which the jump still exists" posed as an NLP.
struct CurveExtremum {
  double engine_eta = 0.0;
  double engine_speed = 0.0;   // ω [rad/s]
  int sense = +1;              // +1: η is largest there, −1: smallest
  FoldOptimizationResult ipopt;
  double ipopt_speed = 0.0;    // ω of the Ipopt solution [rad/s]
};

// One continued curve in (ω, η).
struct MapCurve {
  std::string name;            // "curve1", ...
  std::string kind;            // "event", "fold" or "hopf"
  std::string label;           // the event's name, "fold" or "Hopf"
  std::string piece;           // piece label of the branch where it starts
  int branch = 0;              // branch index (at the base η) it starts from
  std::string pattern;         // that branch's closed-form pattern (PatternName)
  double start_eta = 0.0;
  double start_speed = 0.0;
  bool start_nonsmooth_fold = false;
  // Folds: +1 where ω is locally largest on the branch at the fold, −1 smallest (the sense to give
  // LocateFoldByOptimization along the curve, unchanged up to a cusp); 0 for events.
  int fold_sense = 0;
  Branch curve;                // λ = η; states (u, ω); measure "lambda" = ω (Hopf curves: then
                               // "hopf_frequency" [rad/s]; points stable where the rest of the
                               // spectrum is)
  std::vector<std::string> partner_margins;  // EventCurveProblem::PartnerMargins (events)
  std::vector<CurveExtremum> extrema;        // event curves: their located turning points in η
};

enum class MapRegion { kNone = 0, kOne = 1, kCoexisting = 2 };
const char* ToString(MapRegion region);

struct HysteresisMap {
  DesignParameter parameter = DesignParameter::kFriction;
  double base_value = 0.0;     // η of the given parameters
  Vector eta;                  // grid (m)
  Vector speed;                // grid speeds [rad/s] (k)
  Eigen::MatrixXi stable_count;  // m × k: stable circular states at (η_i, ω_j); −1 where the
                                 // branch set at η_i failed
  // The same count restricted to the branches of one closed-form pattern (PatternName: "mode1",
  // "mode2", "left_only", "right_only", "single"), in the order first met. A sweep that starts on
  // a Mode 1 whirl stays in its family until that family has no stable state left.
  std::vector<std::string> patterns;
  std::vector<Eigen::MatrixXi> pattern_counts;
  std::vector<MapPoint> points;
  std::vector<MapCurve> curves;
  std::vector<std::string> failures;  // grid values or curves that failed, one sentence each
  std::string note;            // why part 2 was skipped (the scene's value outside the range), or
                               // which Hopf points start no curve and why, or "".
  double grid_seconds = 0.0;
  double curve_seconds = 0.0;
  int grid_branches = 0;       // branches computed over the whole grid

  // Region (none / one / coexisting) at (i, j); stable_count must be ≥ 0 there.
  MapRegion Region(Index i, Index j) const;
  // One line: parameter, grid, curves, timings.
  std::string BriefReport() const;
};

// Progress: (stage "grid" or "curves", done, total).
using MapProgress = std::function<void(const std::string& stage, int done, int total)>;

// Throws std::invalid_argument for invalid options or parameters (including a base value outside
// the physical range). Numerical failures are listed in HysteresisMap::failures and in each
// curve's Branch::status. = AssembleHysteresisMap(ComputeMapGrid(every grid value)).
HysteresisMap ComputeHysteresisMap(const TwoPointParams& params, const HysteresisMapOptions& options,
                                   const MapProgress& progress = {});

// One grid value's share of the map (part 1): what its branch set adds. The grid values are
// independent, so processes can compute different rows (`rubcont map` under mpirun) and one
// assembles them.
struct MapGridRow {
  Index index = 0;                // i: η = eta(i)
  bool failed = false;            // the branch set failed: its counts become −1
  std::vector<int> stable_count;  // k
  std::vector<std::pair<std::string, std::vector<int>>> pattern_counts;  // in the order met
  std::vector<MapPoint> points;
  std::vector<std::string> failures;
  int branches = 0;
};

// The rows of the grid values `indices` (each in 0 … eta_points − 1), over options.threads
// threads. Progress: ("grid", done, indices.size()), from one thread at a time.
std::vector<MapGridRow> ComputeMapGrid(const TwoPointParams& params,
                                       const HysteresisMapOptions& options,
                                       const std::vector<Index>& indices,
                                       const MapProgress& progress = {});

// The map from all its grid rows (any order; each exactly once) and the time they took, with the
// curves (part 2) computed here.
HysteresisMap AssembleHysteresisMap(const TwoPointParams& params,
                                    const HysteresisMapOptions& options,
                                    std::vector<MapGridRow> rows, double grid_seconds,
                                    const MapProgress& progress = {});

// The stable speed intervals [ω_a, ω_b] of a branch: maximal runs of consecutive stable points of
// one piece (an interval per run).
std::vector<std::pair<double, double>> StableIntervals(const Branch& branch);

}  // namespace rubcont
