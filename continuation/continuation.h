// Pseudo-arclength continuation of F(u, λ) = 0 (Keller 1977; Allgower & Georg 1990; the stepping
// of AUTO, BifurcationKit's ContIterable and LOCA), with step control, special points and events.
//
// How it scales. Everything is done in x̂ = (u ./ Scale(), λ / LambdaScale()) with residuals
// F ./ ResidualScale() (continuation/scaled_system.h): arclength, tangents, step lengths and their
// bounds, turning angles, Newton tolerances, closure and location tolerances. Give a problem
// scales equal to its unknowns' typical magnitudes and the options' defaults apply to it whatever
// its units.
//
// One step, from the accepted point x̂_k with unit tangent τ̂_k:
//  1. predictor x̂ = x̂_k + Δs τ̂_k (StepOptions::curved_predictor: + Δs² c, the parabola through
//     x̂_{k−1});
//  2. corrector: Newton on [F̂(x̂); τ̂_kᵀ(x̂ − x̂_k) − Δs] = 0 (BorderedCorrector); on failure Δs is
//     halved and the step retried, and below StepOptions::min the branch ends (kStepTooSmall);
//  3. tangent τ̂_{k+1} from [DF̂; τ̂_kᵀ] z = e_{n+1} with the corrector's last LU, so that
//     τ̂_kᵀτ̂_{k+1} > 0 (consistent orientation); a step turning by more than max_angle is rejected
//     and halved (it may have jumped to another branch);
//  4. bounds: a step leaving [lambda_min, lambda_max] is cut where it meets the bound (located on
//     arclength), and the branch ends there; a point outside the state box or norm bound ends it
//     at the previous point;
//  5. events (piecewise-smooth problems), closure, stability at the new point, detection and
//     location of special points between x̂_k and x̂_{k+1} (below); the point is stored. A step in
//     which an event margin jumps or cannot be followed, or a special point cannot be located, may
//     have jumped to another branch whose end point the angle test let pass (a branch almost flat
//     in the state: the random scenes' full-slip whips): it is rejected and halved, up to four
//     times (BranchStatistics::jump_rejections), then taken as it is;
//  6. Δs ← Δs·clamp(min(2^((N_target − N)/2), α_target/α), ½, max_growth), within [min, max].
//
// Special points (continuation/branch.h SpecialPoint), detected between consecutive points of one
// smooth piece and located:
//  - fold: τ̂_λ changes sign; Newton on the minimally augmented system [F; g] (Govaerts 2000;
//    continuation/fold.h), falling back to Illinois regula falsi on τ̂_λ along arclength;
//  - simple branch point: sign of det [DF̂; τ̂ᵀ] changes; Illinois on that determinant (normalized
//    by its value at x̂_k) along arclength. ContinueFromBranchPoint switches onto the other branch;
//  - with DetectionOptions::stability: Hopf (complex pair through the imaginary axis, frequency
//    recorded), real eigenvalue through 0, Floquet multiplier through −1 (period doubling), +1, or
//    a complex pair through the unit circle (Neimark–Sacker, angle recorded); Illinois on the
//    critical value's Re or |·| − 1 with the corrector and Stability at each trial point, and
//    where that value jumps (a collision changed the kinds within the step) on SpectralProduct,
//    refined from the stability tolerance to the boundary; a pair crossing only where the unstable
//    counts need one (continuation/spectrum_crossing.h). Stability is computed once per stored
//    point and kept;
//  - Problem::TestFunctions (e.g. cusps on a fold curve): Illinois on the function.
// "Along arclength" means on the points X(σ) of the branch with τ̂_kᵀ(X − x̂_k) = σ, each obtained
// by the corrector; Illinois keeps a bracket, so the located σ is within location.step_tolerance.
//
// Events. When an event margin (Problem::EventFunctions, ≥ 0 on the valid piece) turns negative,
// its zero is located on arclength (the earliest, if several), stored as the last point of the old
// piece and recorded as a kEvent special point labelled with its name; then SwitchAt(k, u, λ)
// changes the formulation (u may be rewritten, Dimension() may change). The engine re-reads the
// scales, corrects the point in the new formulation if needed, computes the new tangent (SVD null
// vector of DF̂, oriented like the old tangent: by their dot product when the dimensions agree,
// else by the sign of the λ-component), and probes one small step either way: it continues where
// the new margins that vanish at the switch grow; if that is against the old tangent, it turns
// round (the new piece's tangent pointed back into the region the branch came from) and says so in
// the note. When λ turns back at the switch, the point is a non-smooth fold
// (SpecialPoint::nonsmooth_fold). If neither way is valid the branch ends (kNoValidDirection); if
// SwitchAt returns false it ends (kSwitchRefused).
// The switch point is stored again as the first point of the new piece, with the new piece's
// label and stability. Nothing is compared across a switch (the spectrum jumps there).
//
// Closed branches: when the branch crosses the hyperplane through its start point normal to the
// start tangent, near the start and going the same way, the crossing is located on arclength; if
// it is the start point within closure_tolerance the branch ends there (kClosed).
//
// Stepping API (docs/conventions.md): Continuation::Start, then Step() until it returns kStop or kFailed;
// Continue() is the thin driver with a per-step callback. After every stored point the problem's
// PointAccepted hook runs. Use:
//     ContinuationOptions options;
//     options.bounds.lambda_max = 27.0;
//     options.detect.stability = true;
//     Branch branch = Continue(problem, u0, lambda0, options,
//                              [](const Branch& b) { return true; /* progress */ });
//     // branch.BriefReport(), branch.Lambda(), branch.Measure("precession_hz"), ...
//     for (const SpecialPoint& p : branch.special_points) {
//       if (p.type == SpecialPointType::kFold) ContinueFoldCurve(problem, p, curve_options);
//       if (p.type == SpecialPointType::kBranchPoint) ContinueFromBranchPoint(problem, p, +1);
//     }
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "continuation/branch.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace rubcont {

enum class StepResult {
  kContinue,  // a point was added; call Step() again
  kStop,      // the branch ended normally (bound, closed, max steps, caller, switch refused, ...)
  kFailed,    // the branch ended on a numerical failure (start failed, step below its minimum)
};

class Continuation {
 public:
  // Throws std::invalid_argument when the options are invalid. The problem must outlive this.
  Continuation(Problem& problem, const ContinuationOptions& options);
  ~Continuation();
  Continuation(const Continuation&) = delete;
  Continuation& operator=(const Continuation&) = delete;

  // Corrects (u0, λ0) by Newton at fixed λ0 (falling back to a border along the SVD null vector if
  // that fails, as where F_u is singular; the point may then move off λ0, which
  // Branch::start_note and BriefReport say), takes the tangent with sign(τ_λ) =
  // options.direction, and stores the first point. Throws std::invalid_argument for a wrong size
  // of u0, a λ0 outside the bounds, or a state box of the wrong size. Returns kFailed (status
  // kStartFailed) when the point cannot be corrected or violates an event margin.
  StepResult Start(const Vector& u0, double lambda0);

  // As Start, but corrects on the hyperplane through (u0, λ0) normal to the direction (du, dλ)
  // (scaled), and orients the tangent along it: for starting at a fold or along a known direction.
  StepResult StartWithTangent(const Vector& u0, double lambda0, const Vector& du, double dlambda);

  // Starts at a located simple branch point on the other branch through it (ABE direction from
  // ComputeBranchSwitch, continuation/branch_switching.h); `side` = ±1 picks one half of it (see
  // there). The branch point itself is the first point; nothing is detected in the first step.
  // Returns kFailed when the branch point is not simple (the ABE has no real root pair).
  StepResult StartFromBranchPoint(const SpecialPoint& branch_point, int side);

  // One continuation step (possibly with retries at smaller steps). After the branch has ended it
  // returns kStop or kFailed again without doing anything.
  StepResult Step();

  // Ends the branch with the given reason and status: kStoppedByCaller (the caller's decision), or
  // what the caller found by its own test (e.g. kClosed: round a closed curve that the engine's
  // comparison of the unknowns does not see). Throws std::invalid_argument for kRunning.
  void Stop(const std::string& reason, BranchStatus status = BranchStatus::kStoppedByCaller);

  const Branch& branch() const;
  // Moves the branch out (the stepper is done after this).
  Branch TakeBranch();
  // The arclength step the next Step() will try first (scaled).
  double step_size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Called after every step with the branch so far; return false to stop the branch.
using StepCallback = std::function<bool(const Branch& branch)>;

// A caller's own end of a branch, with the status and message it ends with.
struct BranchEnd {
  BranchStatus status = BranchStatus::kStoppedByCaller;
  std::string message;
};
// Called after every step (after the StepCallback): the end to end the branch with, or none.
using EndTest = std::function<std::optional<BranchEnd>(const Branch& branch)>;

// The thin driver: Start, then Step until the branch ends, calling `callback` and then
// `end_test` after each step.
Branch Continue(Problem& problem, const Vector& u0, double lambda0,
                const ContinuationOptions& options = {}, const StepCallback& callback = {},
                const EndTest& end_test = {});

// Runs a Continuation already started (any of its Start variants) to its end.
Branch RunToEnd(Continuation& continuation, const StepCallback& callback = {},
                const EndTest& end_test = {});

}  // namespace rubcont
