// Invariant tori continued in the system's parameter from a Neimark–Sacker point of a periodic-orbit
// family (level L2): the torus born where a complex pair of Floquet multipliers μ = e^{±2πiρ₀}
// crosses the unit circle, as the invariant circle of the return map (shooting/invariant_circle.h)
// that grows out of the orbit's point.
//
// The start. At the point the return map P = R_{−φ} Φ_T (autonomous orbits: φ = 0) of the orbit
// through x₀ = its first segment start has the pair e^{±2πiρ₀} with eigenvector v; P carries the
// small ellipse x₀ + ε(Re v cos θ − Im v sin θ) into itself turned by 2πρ₀, to first order in ε.
// That ellipse (amplitude ε in scaled state units, ‖v ./ StateScale‖ = 1) with ρ = ρ₀, T and φ of
// the orbit is the first circle; the corrector fixes its projection on the ellipse's direction and
// solves for λ, on whichever side of the point the tori lie (supercritical or subcritical), as
// ContinueOrbitsFromPeriodDoubling does for the doubled orbits. Strong resonances (ρ₀ = 0, 1/4,
// 1/3, 1/2) are refused: there the circle equations of the harmonics k ≤ 4 are singular at the point.
//
// How a family ends, as statuses (TorusEnd):
//   kBreakdown  the circle loses smoothness: its Fourier tail (the last harmonic against the largest)
//               reaches max_fourier_tail (InvariantCircleProblem's event) — past it the collocation
//               equations still have solutions, which are no invariant circles;
//   kLocking    the same event where one harmonic h of the circle stands out of its decaying
//               spectrum (at least twice harmonic h − 1) and |ρ − p/q| ≤ 1/(2q²), p/q = round(hρ)/h
//               in lowest terms, q ≥ 2 (a multiple of q can stand out: C(a) refined to K = 32
//               ends with harmonic 30 standing out, 12/30 = 2/5): the circle folds towards q
//               points as the torus meets the p:q resonance, where the motion on it locks to a
//               periodic orbit of q laps — read as phase locking (C(a) at K = 8: harmonic 5
//               grows to 2.5 times harmonic 4 as ρ falls to 0.404);
//   kGrazing    the torus grazes a switching surface (TorusBranchOptions::grazing, located: the
//               family's last torus), or a contact lifts off at the last torus of a failed family
//               (the rub model's reading, shooting/rub_tori.h ReadLiftOff);
//   kShrinks    the circle's radius falls to min_radius (InvariantCircleProblem's event): the torus
//               shrinks onto the periodic orbit at its centre, as at a Neimark–Sacker point of
//               that orbit; ContinueCentreOrbits finds the orbit and locates the point;
//   kBound      the range's end; kFailed the engine's other ends (step too small, ...) with its message;
//   kSteps      the step limit.
// Decision: locking is read from the circle's harmonics and ρ at the tail event, not proved by
// finding the locked orbit (a q-lap shooting problem of its own); the report gives the harmonic,
// p/q and |ρ − p/q|, so the reader can judge.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "continuation/continuation.h"
#include "shooting/invariant_circle.h"
#include "shooting/orbit_branches.h"
#include "solvers/constants.h"

namespace rubcont {

struct TorusBranchOptions {
  double lambda_min = 0.0;  // parameter range (system units), containing the point
  double lambda_max = 1.0;
  int harmonics = 8;        // K ≥ 1 (N = 2K + 1 points on the circle)
  // The return map's integrator. With Gauss collocation, collocation_steps is the mesh over one
  // period T (the family's steps per segment times its segments).
  IntegratorOptions integrator;
  // The engine; bounds are overwritten by the range, detect.stability is switched off (the torus's
  // stability is the Lyapunov spectrum below, not a spectrum of the Jacobian).
  ContinuationOptions continuation;
  double amplitude = 1e-3;           // ε of the first circle (scaled state units)
  double max_fourier_tail = 1e-4;    // the breakdown event, (0, 1)
  // The event "the circle shrinks onto its centre" (InvariantCircleProblem::Radius, scaled state
  // units): in [0, amplitude / √2), 0 switching it off. Below the first circle a Neimark–Sacker
  // start draws (radius amplitude / √2), so that a family born at one such point can end at
  // another. Decision: an absolute size, as the start's amplitude is — a torus family whose whole
  // modulation is smaller than this is not told from its orbit.
  double min_radius = 5e-4;
  // Lyapunov exponents of every stored torus from this many iterates of the map
  // (InvariantCircleProblem::LyapunovStability); 0: no stability.
  int lyapunov_iterates = 0;
  // Called before each torus's exponents with its index and the family's size: they come after
  // the family, a long stretch otherwise silent.
  std::function<void(std::size_t, std::size_t)> on_exponents;
  // The circle's coordinates (InvariantCircleProblem): the state, or the system's chart.
  CircleCoordinates coordinates = CircleCoordinates::kState;
  // Switching surfaces whose grazing ends the family (InvariantCircleProblem::SetGrazingTests):
  // the step that meets the first located one is cut there (BoundsOptions::end_at_grazing), the
  // family ends kGrazing on the grazing torus. Past it the map's trajectories cross the surface,
  // which a fixed Gauss mesh does not follow.
  std::vector<TorusGrazing> grazing;
  // Convergence in K along the family (0: K = harmonics throughout). While 2K ≤ max_harmonics the
  // tail event is set at `converged_tail` instead of max_fourier_tail: where the circle's tail
  // reaches it (or the corrected start's tail exceeds it), the circle is solved again with 2K
  // harmonics (RefineCircle: its images under the map, `refinement_images` tried in turn; Newton
  // at the corrector's tolerances, up to 30 iterations, failing steps halved up to 8 times) and
  // the family goes on at 2K from the refined circle along the same tangent. At K = max_harmonics
  // the event is max_fourier_tail's again, so breakdown and locking are read at the finest K; K is
  // not lowered where the tail falls again. Decision: doubling at a located event, as the start
  // does (ModulatedTorusOptions::max_harmonics), rather than re-meshing at every step as AUTO does
  // for orbits — each K's circle is a solution of its own equations, and the family's circles
  // are all written in the finest K's layout (the coarser padded with zero harmonics: the same
  // curves), with the K each was solved at (TorusBranch::point_harmonics).
  int max_harmonics = 0;  // 0 … 1000 (below 2 · harmonics: K fixed)
  double converged_tail = 1e-4;  // (0, max_fourier_tail]
  std::vector<int> refinement_images = {3, 10};  // each in 1 … 100
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const TorusBranchOptions& options);

// kGrazing: a located grazing of TorusBranchOptions::grazing, or a contact lifting off at the
// family's last torus (read by the rub model's tori, shooting/rub_tori.h, from an end that would
// otherwise be kFailed).
enum class TorusEnd { kBound, kSteps, kBreakdown, kLocking, kGrazing, kShrinks, kFailed };
const char* ToString(TorusEnd end);


struct TorusBranch {
  std::size_t special_point = 0;  // index into the family's branch.special_points
  bool ok = false;                // false: no start (message says why), no branch
  std::string message;
  OrbitKind kind = OrbitKind::kAutonomous;
  Index state_dimension = 0;
  int harmonics = 0;
  CircleCoordinates coordinates = CircleCoordinates::kState;  // of the circles in `branch`
  double birth_lambda = kNaN;
  double birth_rotation_number = kNaN;  // ρ₀ = arg μ / 2π
  double birth_modulus = kNaN;          // |μ| at the point
  Branch branch;  // unknowns: InvariantCircleProblem::Pack layout
  // Per point of the branch (empty without lyapunov_iterates).
  std::vector<InvariantCircleProblem::TorusStability> stability;
  TorusEnd end = TorusEnd::kFailed;
  std::string end_note;  // one sentence: where and why the family ended, with ρ and p/q
  int locking_p = 0;     // kLocking: the resonance p:q
  int locking_q = 0;
  // Per point of `branch`: the K its circle was solved with (TorusBranchOptions::max_harmonics;
  // `harmonics` is the finest, the layout of every point's u).
  std::vector<int> point_harmonics;
  // Where K doubled along the family: the circle at λ solved again with `to` harmonics. Both
  // circles are points of the branch, at the same λ.
  struct Refinement {
    double lambda = kNaN;
    int from = 0;
    int to = 0;
    int images = 0;  // the start's images under the map (RefineCircle)
    double rotation_number_from = kNaN;
    double rotation_number_to = kNaN;
    double fourier_tail_from = kNaN;
    double fourier_tail_to = kNaN;
  };
  std::vector<Refinement> refinements;
  // With max_harmonics: how many tori are not converged in K — those at the finest K whose Fourier
  // tail exceeds converged_tail (a coarser circle is refined where its tail reaches that bound; at
  // the finest K the family goes on to max_fourier_tail) — and one sentence saying which ("" with
  // max_harmonics 0).
  std::size_t unconverged_in_k = 0;
  std::string convergence_note;

  // The K point i was solved with (point_harmonics[i]; `harmonics` where that is empty), and its
  // circle in that K's layout (CircleWithHarmonics: the padded harmonics cut off).
  int SolvedHarmonics(std::size_t i) const;
  Vector SolvedCircle(std::size_t i) const;
};

// The tori born at the Neimark–Sacker point `special_point` of `family` (autonomous or relative
// orbits; `system` the family's), continued over the range; on_step is called after every step.
// Throws std::invalid_argument when the point is not a Neimark–Sacker point, the family is forced,
// or the options are invalid; numerical failures are ok = false or the branch's status.
TorusBranch ContinueToriFromNeimarkSacker(std::shared_ptr<OdeSystem> system,
                                          const PeriodicOrbitBranch& family,
                                          std::size_t special_point,
                                          const TorusBranchOptions& options,
                                          const StepCallback& on_step = {});

// The tori through the circle u0 (InvariantCircleProblem::Pack layout for `kind` and the options'
// harmonics; a solution or a close guess) at λ0, continued over the range in the direction of
// options.continuation.direction: the start from a circle found otherwise — from a settled
// transient (shooting/modulated_torus.h), or a torus family's point to restart from. The family
// ends as ContinueToriFromNeimarkSacker's (special_point and the birth fields are unset). Throws
// std::invalid_argument for invalid options or a u0 of the wrong size; a start that does not
// converge is ok = false with the engine's message.
TorusBranch ContinueTori(std::shared_ptr<OdeSystem> system, OrbitKind kind, const Vector& u0,
                         double lambda0, const TorusBranchOptions& options,
                         const StepCallback& on_step = {});

// The locked motion a torus family ended at (end kLocking, p:q): relative (or autonomous) periodic
// orbits of q laps of the family's period, x(qT') = R_{qφ'} x(0), found and continued in the
// parameter with the family's shooting (q times its segments). Inside the resonance tongue two
// such orbits exist, a saddle and a node of the q-th power of the map, joined at two folds: the
// tongue's edges, where the motion on the torus locks and unlocks (the family is typically a closed
// curve through both folds).
//
// The start: where ρ, extrapolated linearly from the family's last two tori, reaches p/q (past the
// last torus), then up to three times as far again on the same side if Newton fails there; at each
// speed from the last circle's points θ_j = 2πj/N (the first N' = min(N, 5)), the orbit through
// u(θ_j) run q laps (period qT, rotation qφ of the last torus). The continuation ends with status
// kClosed (EndRoundClosedCurve) once two folds are located and the branch is back across its
// start: the closed curve followed round once.
struct LockedOrbits {
  bool ok = false;        // false: not found (message says where it was tried)
  std::string message;
  int p = 0;
  int q = 0;
  PeriodicOrbitBranch orbits;
  // The located folds' parameters, ascending, each once: the locking interval when there are two.
  std::vector<double> folds;
  // The family's tori inside that interval. A circle's rotation number is p/q wherever it
  // carries the q-lap orbits (Arnold's tongue, whose edges are the folds), so a torus there with
  // ρ ≠ p/q is no invariant circle: a root of the truncated equations past the tongue's edge.
  std::size_t tori_inside = 0;
};

// Throws std::invalid_argument when `tori` did not end in kLocking or has no points.
LockedOrbits ContinueLockedOrbits(std::shared_ptr<OdeSystem> system,
                                  const PeriodicOrbitBranch& family, const TorusBranch& tori,
                                  const TorusBranchOptions& options,
                                  const StepCallback& on_step = {});

// The orbit a torus family shrank onto (end kShrinks): the periodic orbit (of the family's kind,
// period T and rotation φ of its last torus) through the last circle's centre, continued with
// `options` (ContinuePeriodicOrbits: its shooting, range, engine, measures, test functions and
// ends) in the direction the family moved in at its end. Its first located Neimark–Sacker point,
// next to the start: the point's speed and the angle of its multiplier, arg μ / 2π, against the
// last torus's λ and ρ (or 1 − ρ: the circle's orientation is the fit's) say whether the family
// ends there. With options.stop_at_neimark_sacker the orbits end at that point; without, they go
// on over the range to their own end: the orbit a supercritical point hands the motion to, and
// what becomes of it.
struct CentreOrbits {
  bool ok = false;  // false: the orbit did not converge (message says where)
  std::string message;
  PeriodicOrbitBranch orbits;
  bool located = false;           // a Neimark–Sacker point was located on them
  double lambda = kNaN;           // the first one's parameter
  double rotation_number = kNaN;  // arg μ / 2π of its critical multiplier, in (0, 1/2]
};

// Throws std::invalid_argument when `tori` did not end in kShrinks or has no points, and as
// ContinuePeriodicOrbits (invalid options; the end's λ outside their range).
CentreOrbits ContinueCentreOrbits(std::shared_ptr<OdeSystem> system, const TorusBranch& tori,
                                  PeriodicOrbitBranchOptions options);

}  // namespace rubcont
