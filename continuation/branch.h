// Results of a continuation run: a copyable value type (Ceres Solver::Summary, BifurcationKit
// ContResult) with a table of points, a list of special points, the options used, and how and why
// the branch ended. apps/ writes it under /branches/<name>/ (docs/result_files.md): the column
// accessors below flatten it without knowing the engine.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "continuation/options.h"
#include "continuation/problem.h"
#include "solvers/constants.h"
#include "solvers/types.h"

namespace rubcont {

// One accepted point of the branch, in the problem's own units.
struct BranchPoint {
  double lambda = 0.0;
  Vector u;                    // Dimension() of the piece it lies on
  Vector measures;             // Problem::Measures, in the order of Branch::measure_names
  Vector tangent;              // unit tangent in scaled variables (û, λ̂), n + 1 entries
  double step = 0.0;           // scaled arclength from the previous point (0 for the first)
  double arclength = 0.0;      // scaled arclength from the start of the branch
  int newton_iterations = 0;   // corrector iterations of the attempt that produced the point
  double residual_norm = 0.0;  // ‖F ./ ResidualScale‖∞ at the point
  int num_unstable = -1;       // Spectrum::UnstableCount; −1 when stability was not computed
  Spectrum spectrum;           // valid = false when stability was not computed
  std::string piece;           // Problem::PieceLabel() of the smooth piece it lies on

  // 1 stable, 0 unstable, −1 stability not computed (the result files' `stable` columns).
  int StableFlag() const { return num_unstable < 0 ? -1 : num_unstable == 0 ? 1 : 0; }
};

// A detected (and usually located) special point. For points located on arclength, `index` is the
// branch point after which it lies: it is between points[index] and points[index + 1] (an event or
// a bound ends at points[index + 1] itself).
struct SpecialPoint {
  SpecialPointType type = SpecialPointType::kFold;
  std::string label;    // event or test-function name; empty otherwise
  double lambda = 0.0;
  Vector u;
  Vector measures;      // Problem::Measures at the point (for events: on the piece that ends)
  Vector tangent;       // unit branch tangent in scaled variables (û, λ̂) at the point
  Index index = 0;
  std::string piece;    // piece label where it was found (for events: the piece that ends there)
  bool converged = false;        // located to the requested precision (false: a guess)
  int iterations = 0;            // Newton iterations or trial points spent locating it
  double residual_norm = 0.0;    // ‖defining system‖∞ at the point: [F̂; g] for folds (g the
                                 // minimally augmented test function), F̂ otherwise
  double test_value = 0.0;       // the test function at the point (λ̂-component of the tangent,
                                 // normalized det, Re of the critical eigenvalue, |μ| − 1, event
                                 // margin, …); ideally 0
  double last_correction = 0.0;  // size of the last Newton correction ‖Δx̂‖∞ (folds) or of the
                                 // last change of the trial arclength (Illinois location)
  // Hopf: the critical eigenvalue ≈ iω; period doubling / Neimark–Sacker: the critical multiplier.
  std::complex<double> critical_value{0.0, 0.0};
  // Hopf: ω = Im of the critical eigenvalue (rad per time unit of the problem); Neimark–Sacker:
  // the angle arg μ ∈ (0, π) of the critical multiplier (rad); NaN otherwise.
  double frequency = kNaN;
  // Events: λ turns back at the switch (the λ-components of the tangents on the old and the new
  // piece have opposite signs): a non-smooth fold, where a sweep in λ would jump.
  bool nonsmooth_fold = false;
  // Hopf: the first Lyapunov coefficient (continuation/lyapunov.h), where the problem computes it
  // (rotating waves: RotatingWaveProblem::FirstLyapunov); < 0 supercritical, > 0 subcritical.
  // NaN where it is not computed or not trusted (the note says why).
  double lyapunov = kNaN;
  std::string note;     // a human sentence when there is more to say

  // "fold", "Hopf", "event: right stick to slip+", …: the type, and the label when it adds to it.
  std::string Name() const;
};

enum class BranchStatus {
  kRunning,            // not ended yet (a stepper mid-way)
  kReachedLambdaBound,
  kReachedStateBound,
  kMaxSteps,
  kClosed,             // returned to its start point: a closed curve (isola) followed round
  kStoppedByCaller,    // the per-step callback (or Continuation::Stop) ended it
  kSwitchRefused,      // Problem::SwitchAt returned false at an event
  kNoValidDirection,   // after a switch, the new piece is invalid in both directions
  kStepTooSmall,       // the corrector failed with the step at its minimum
  kStartFailed,        // the start point could not be corrected, or violates an event margin
  // Ended at a located grazing, as the caller asked (PeriodicOrbitBranchOptions::stop_at_grazing):
  // past it the orbits cross a switching surface, where a fixed mesh creeps in shrinking steps.
  kGrazing,
};

const char* ToString(BranchStatus status);
// kStepTooSmall and kStartFailed: the branch ended because of a numerical failure.
bool IsFailure(BranchStatus status);

struct BranchStatistics {
  int steps = 0;                  // accepted steps
  int corrector_failures = 0;     // failed correctors (each halves the step and retries)
  int angle_rejections = 0;       // converged steps rejected because the tangent turned too far
  long residual_evaluations = 0;  // calls of Problem::Residual
  long jacobian_evaluations = 0;  // calls of Problem::Jacobian
  long stability_evaluations = 0; // calls of Problem::Stability
  int switches = 0;               // events at which the problem switched pieces
  int jump_rejections = 0;        // converged steps rejected because an event margin jumps within
                                  // them: the corrector's end point lay on another branch
  int stray_rejections = 0;       // converged steps rejected because the problem named their
                                  // point no continuation of the branch (Problem::StrayPoint)
};

// The counts of two runs together (JoinAtStart; a torus family continued after a refinement in K).
BranchStatistics& operator+=(BranchStatistics& into, const BranchStatistics& other);

struct Branch {
  std::vector<BranchPoint> points;
  std::vector<SpecialPoint> special_points;
  std::vector<std::string> measure_names;  // Problem::MeasureNames at the start
  ContinuationOptions options;             // the options used
  BranchStatus status = BranchStatus::kRunning;
  std::string message;                     // why it ended, one sentence with numbers
  // Where the start could not be corrected at its λ and was corrected along DF's null vector
  // instead (Continuation::Start at a fold): from which λ to which, and why; else empty.
  std::string start_note;
  BranchStatistics statistics;

  // One line, e.g. "branch: 143 points, λ ∈ [20, 260], 2 folds, 1 Hopf, ended: reached λ max".
  std::string BriefReport() const;

  Index Size() const { return static_cast<Index>(points.size()); }
  int Count(SpecialPointType type) const;
  // The first special point of that type that converged (located), or nullptr.
  const SpecialPoint* FirstLocated(SpecialPointType type) const;

  // Columns, one entry per point.
  Vector Lambda() const;
  // The named measure (throws std::invalid_argument naming the measure if it is unknown).
  Vector Measure(const std::string& name) const;
  // Position of the named measure in BranchPoint::measures and SpecialPoint::measures (throws
  // like Measure).
  Index MeasureIndex(const std::string& name) const;
  // Component i of u; NaN at points whose piece has fewer unknowns.
  Vector StateComponent(Index i) const;
  Vector Arclength() const;
  Vector Step() const;
  Vector ResidualNorm() const;
  Eigen::VectorXi NewtonIterations() const;
  Eigen::VectorXi NumUnstable() const;
  std::vector<std::string> PieceLabels() const;
};

// One branch through a start point from two runs started there in opposite directions (AUTO's
// two-way continuation): `backward`'s points reversed (tangents negated, arclength negative),
// then `forward`'s points after its first (the shared start). Special points are re-indexed;
// statistics are summed; the status is `forward`'s if it failed, else `backward`'s if that failed,
// else `forward`'s, and the message says how each half ended. Throws std::invalid_argument when
// either run is empty or their first points differ in λ.
Branch JoinAtStart(const Branch& backward, const Branch& forward);

}  // namespace rubcont
