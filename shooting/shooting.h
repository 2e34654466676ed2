// Periodic orbits by single and multiple shooting, as continuation problems F(u, λ) = 0
// (continuation/problem.h). λ is the OdeSystem's parameter. Three kinds of orbit:
//
//   kAutonomous  ẋ = f(x):            x(T) = x(0), T unknown, one phase condition.
//   kForced      ẋ = f(t, x), f T-periodic in t with T = system.ForcingPeriod() at λ (the
//                parameter may change it, e.g. a forcing frequency): x(T) = x(0), no phase condition.
//   kRelative    relative periodic orbit of a system with a rotation symmetry R_φ
//                (OdeSystem::Rotate): x(T) = R_φ x(0) with T and φ unknown, two phase conditions.
//                In the frame that rotates by φ per period the orbit is periodic; in the original
//                frame it is quasi-periodic (frequencies 2π/T and φ/T) unless φ/2π is rational.
//
// Sign convention of the rotation: φ is the angle for which x(T) = R_φ x(0), R_φ being the model's
// own Rotate(φ, ·) (OdeSystem's convention). If the model's Rotate multiplies complex coordinates by
// e^{jφ}, docs/theory.md §7's p(T) = e^{−jφ_d} p(0) has φ_d = −φ.
//
// Unknowns (N segments, n states; mesh 0 = τ_0 < τ_1 < … < τ_N = 1, segment i covers
// [T τ_i, T τ_{i+1}]):
//   u = [x_0, x_1, …, x_{N−1}, T (kAutonomous, kRelative), φ (kRelative), τ_b (event boundaries)],
// size N n + 0/1/2 + m. An event boundary b on surface k adds the row e = h_k(x_b) and moves
// with its unknown τ_b: ∂r_{b−1}/∂τ_b = T d_{b−1}, ∂r_b/∂τ_b = −T d_b, ∂e/∂x_b = ∇h_k (central
// differences), with d_i = ∂y_i/∂t_{i+1} the integrator's (Gauss: its discrete map's exact
// derivative; OdeIntegrator::Integrate's dxdt1), which then also gives
// ∂r_i/∂T = d_i (τ_{i+1} − τ_i).
// Residual, with y_i = x(T τ_{i+1}; T τ_i, x_i) the end of segment i:
//   r_i = y_i − x_{i+1}   (i < N−1),       r_{N−1} = y_{N−1} − R_φ x_0   (R = I unless kRelative),
//   p_t = n̂_fᵀ S⁻¹ (x_0 − x_ref),           p_φ = n̂_gᵀ S⁻¹ (x_0 − x_ref)   (kRelative),
// S = diag(StateScale()), n̂_f = S⁻¹ f(x_ref) / ‖S⁻¹ f(x_ref)‖, n̂_g likewise with the rotation
// generator g(x_ref). These are Poincaré-type phase conditions (a hyperplane through a reference
// point, orthogonal in the scaled metric to the flow, resp. to the group orbit; Seydel §7.3, Lust
// 2001). The integral phase condition of collocation (AUTO) would need the sensitivities along the
// whole orbit; the hyperplane needs them at one point only, and stays transversal as long as the
// reference is updated from time to time along a branch (SetPhaseReference).
//
// The Jacobian is assembled from forward sensitivities (block-bidiagonal with a corner block, plus
// the bordering columns ∂/∂T, ∂/∂φ and the phase rows; Keller 1968, Ascher–Mattheij–Russell):
//   ∂r_i/∂x_i = M_i,  ∂r_i/∂x_{i+1} = −I,  ∂r_{N−1}/∂x_0 = −R_φ,  ∂r_{N−1}/∂φ = −g(R_φ x_0),
//   ∂r_i/∂T = f(y_i)(τ_{i+1} − τ_i) (autonomous: y_i depends on T through the duration only).
// ∂F/∂λ: r_i gets ∂y_i/∂p (parameter sensitivity) plus, for kForced, the motion of the segment
// ends with T(λ): T′(λ)[τ_{i+1} f(t_{i+1}, y_i) − τ_i M_i f(t_i, x_i)].
//
// Integrations are cached at the last (u, λ): Residual, Jacobian, DfDlambda, Stability at the same
// point integrate once (Residual alone integrates without sensitivities, which is cheaper; the
// residual value at a point is kept from its first evaluation so that F(u) is one function).
// Floquet multipliers: periodic Schur method on the segment STMs (solvers/floquet.h), trivial
// multipliers deflated with f(x_i) (and g(x_i)); for kRelative the return map is x ↦ R_{−φ} x(T),
// so the last factor is R_{−φ} M_{N−1}.
//
// Integration failures (tier 3): Residual and Jacobian fill their output with NaN, which
// NewtonSolve reports as kNonFinite and the continuation engine treats as a failed step;
// LastFailure() says why. Stability returns valid = false.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "continuation/problem.h"
#include "solvers/floquet.h"
#include "solvers/ode.h"

namespace rubcont {

enum class OrbitKind { kAutonomous, kForced, kRelative };
const char* ToString(OrbitKind kind);

enum class LambdaDerivative {
  kSensitivity,       // ∂y_i/∂p from one more forward sensitivity, computed with the Jacobian
  kFiniteDifference,  // central differences of the residual in λ (two more integrations)
};

struct ShootingOptions {
  // Number of shooting segments N ≥ 1 (1: single shooting).
  int segments = 1;
  // Segment boundaries as fractions of the period, N + 1 values 0 = τ_0 < … < τ_N = 1. Empty:
  // uniform. Put boundaries before fast phases (relaxation jumps) to keep each segment benign.
  // With event_boundaries, the starting values of the boundaries that move.
  std::vector<double> mesh;
  // Boundaries that sit on switching surfaces (piecewise-smooth orbits: a contact's touchdown and
  // lift-off): boundary b (1 ≤ b < segments, distinct) gets its fraction τ_b as an unknown and the
  // equation h_k(x_b) = 0 (k = surface, OdeSystem::SwitchingFunctions, which must not depend on
  // t or λ). Each segment then stays on one side of every surface that its ends switch, so that a
  // fixed Gauss mesh integrates only smooth pieces and keeps its order (tests/shooting/
  // grazing_test.cpp measures it). The other boundaries keep their places between the nearest
  // event boundaries (or ends) on either side, as fractions of the way on `mesh`, so that a
  // switch never overtakes them. Autonomous and relative kinds only (a segment's end then depends
  // on its duration alone). The number of switches per period is fixed: where it changes (at
  // grazing) the family is restarted with another list (ContinueAcrossSwitches,
  // shooting/switching_orbits.h, does that).
  struct EventBoundary {
    int boundary = 1;
    int surface = 0;
  };
  std::vector<EventBoundary> event_boundaries;
  // Integrator for every segment. Tight defaults: the Newton tolerances of the caller cannot be
  // met below the integration error (rtol 1e-10 gives residuals of order 1e-9).
  IntegratorOptions integrator = [] {
    IntegratorOptions options;
    options.relative_tolerance = 1e-10;
    options.absolute_tolerance = 1e-10;
    return options;
  }();
  FloquetMethod floquet_method = FloquetMethod::kPeriodicSchur;
  LambdaDerivative lambda_derivative = LambdaDerivative::kSensitivity;
  // Integrate with sensitivities already in Residual (useful when almost every residual is
  // followed by a Jacobian at the same point, as in continuation correctors).
  bool sensitivities_in_residual = false;
  // When integrator.sensitivity_error_control is off (a cheap Jacobian for Newton: on stiff
  // systems 18–150× cheaper and as good for convergence, see bench/shooting_bench.cpp), integrate
  // the STM once more with it on for Stability, Floquet and SegmentMonodromies, so that the
  // multipliers keep their accuracy. No effect when error control is on.
  bool accurate_stability = true;
  // Typical period (time units) for Scale(); 0: |T| of the first phase reference.
  double period_scale = 0.0;
  // Typical |λ| for LambdaScale(); 0: max(|λ|, 1) with λ the system's parameter at construction.
  double lambda_scale = 0.0;
  // Stop and restart the integrator where the system's switching functions vanish
  // (OdeSystem::SwitchingFunctions: contacts opening and closing; EventOptions::restart), so that
  // CVODES never steps across a kink of the vector field: across one, its error control makes the
  // segment ends a rough function of the unknowns and Newton stalls (measured on the soft impact
  // oscillator, tests/shooting/grazing_test.cpp). No effect with Gauss collocation (a fixed mesh
  // has no events: event_boundaries put its segment ends on the switches instead) or for a system
  // without switching functions.
  bool restart_at_switches = true;
  // Gauss collocation: at every `adapt_mesh_every`-th accepted continuation point
  // (PointAccepted), each segment's collocation steps (their number kept) move to equidistribute
  // the error monitor of that orbit over the period (CollocationMonitor plus
  // adapt_mesh_floor × its mean; EquidistributedMesh), as AUTO-07p adapts its mesh every IAD
  // steps. The segment boundaries stay. 0: the uniform mesh throughout. Other methods: must be 0.
  int adapt_mesh_every = 0;
  // The floor added to the monitor, as a fraction of its mean over the period (> 0): where the
  // orbit is smooth the steps grow to at most (1 + floor)/floor times the mean step. Measured on
  // A(a)'s whip family at 400 intervals (bench/whip_family_bench.cpp, one run each): 0.1 (steps up to 11×)
  // locates the period doubling best with the curved predictor but with the tangent one the family
  // stalls short of its grazing among spurious crossings of multipliers (the contact's stiff mode,
  // unresolved on the long steps); 1 (2×) leaves 0.014 rpm of error; 0.3 (4.3×) neither.
  double adapt_mesh_floor = 0.3;
  // Samples per segment for measures and Orbit() (≥ 2); the test functions read at least 4 per
  // collocation step with Gauss collocation (ShootingProblem::TestOrbit).
  int samples_per_segment = 64;
  // Move the phase conditions' reference to every accepted continuation point (PointAccepted),
  // so that the hyperplane stays transversal to an orbit that changes along the branch (the
  // accepted point stays a solution; the next one lies on the new hyperplane). No effect for
  // kForced.
  bool refresh_phase_reference = false;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const ShootingOptions& options);

// Gauss collocation's mesh is counted in intervals per period, IntegratorOptions::collocation_steps
// in steps per integrated span; these two functions are the one place where the one becomes the
// other. A period's `intervals_per_period` shared evenly by `segments` segments give each
// ⌈intervals_per_period / segments⌉ steps (the period then has at least that many intervals); the
// integrator of `pieces` spans run end to end (a whole period of `pieces` segments, a section of
// `pieces` modulation periods) is `span`'s with `pieces` times its steps. Other methods ignore
// collocation_steps.
long CollocationStepsPerSegment(long intervals_per_period, int segments);
IntegratorOptions JoinedIntegrator(IntegratorOptions span, long pieces);

// An orbit sampled in time: times from 0 to T (the last sample is the end of the last segment).
struct OrbitSamples {
  Vector times;      // m
  Matrix states;     // n × m
  double period = 0.0;
  double rotation = 0.0;  // φ (kRelative), else 0
  double parameter = 0.0;
  // Gauss collocation on an adapted mesh (ShootingOptions::adapt_mesh_every): the length of every
  // step as a fraction of the period, in time order; empty on a uniform mesh and for the other
  // methods.
  Vector collocation_steps;
  bool valid = false;     // false when an integration failed
};

// A named scalar of an orbit, evaluated from its samples (measures are stored with every branch
// point by the continuation engine).
struct OrbitMeasure {
  std::string name;
  std::function<double(const OrbitSamples&)> evaluate;
};
// Maximum / minimum of state i over the orbit (refined by a parabola through the extreme sample
// and its neighbours), half the peak-to-peak range, and the time average (trapezoidal rule).
OrbitMeasure StateMaximum(Index state, std::string name);
OrbitMeasure StateMinimum(Index state, std::string name);
OrbitMeasure StateAmplitude(Index state, std::string name);
OrbitMeasure StateMean(Index state, std::string name);
// The time average of √(x₀² + x₁²), the distance from the origin in the plane of the first two
// states (trapezoidal rule): the radius of a circular orbit about the origin.
OrbitMeasure MeanRadius(std::string name = "mean_radius");

// ‖(x(T) − R_φ x(0)) ./ StateScale‖∞ with x(T) integrated from the orbit's first sample by an
// independent integrator (`options`, state only; R = I unless the orbit is relative): the orbit's
// defect as a solution of the ODE rather than of the shooting integrator's discrete map — the
// check of a fixed-mesh method (Gauss collocation). NaN when the integration fails. `system` is a
// copy owned by the measure (its parameter is set to the orbit's).
OrbitMeasure PeriodicityDefect(std::shared_ptr<OdeSystem> system, const IntegratorOptions& options,
                               std::string name = "defect");

// max_t ‖S⁻¹(κx(t) − x(t))‖∞ / max_t ‖S⁻¹x(t)‖∞ over the samples, κ the system's mirror symmetry
// (OdeSystem::Mirror): 0 for an orbit in the symmetric subspace (to the solution's precision,
// measured ~1e-11 on A(a)'s modulated whip), of order 1 for one that breaks the symmetry. An
// orbit symmetric only up to a time shift (κx(t) = x(t + T/2)) counts as asymmetric. Throws
// std::invalid_argument when the system has no mirror symmetry.
OrbitMeasure MirrorAsymmetry(std::shared_ptr<const OdeSystem> system,
                             std::string name = "asymmetry");
// The same quantity over the columns of `states` (samples of an orbit, or its segment starts):
// max_j ‖S⁻¹(κx_j − x_j)‖∞ / max_j ‖S⁻¹x_j‖∞, 0 for all-zero states.
double MirrorAsymmetryOf(const OdeSystem& system, const Eigen::Ref<const Matrix>& states);

// The modes a fixed Gauss mesh does not resolve, frozen at the orbit's first sample: for each
// eigenvalue λ_k of ∂f/∂x there, the modulus one period gives it on the mesh, Π_j |R(λ_k h_j)| over
// the orbit's steps (R the stability function, GaussLogGrowth; OrbitSamples::collocation_steps, or
// N = steps_per_period uniform steps h = T/N where the samples do not carry them), against the exact
// e^{Re λ_k T}. Returns the largest discrete modulus among the modes misplaced by more than 1e-3
// (relative to e^{Re λ_k T} where it exceeds 1: a growing frozen mode the mesh resolves is not
// misplaced; 0 when there are none). Gauss keeps the sign of Re λ and underestimates the damping of a
// lightly damped stiff mode it does not resolve (the thesis's contact at |λ|h = 11: 0.68 for
// 0.33), so a value well below 1 means those modes cannot decide the orbit's stability; near 1
// the mesh must be refined. `system` is a copy owned by the measure.
OrbitMeasure UnresolvedMultiplier(std::shared_ptr<OdeSystem> system, int stages,
                                  long steps_per_period, std::string name = "unresolved_multiplier");

// A scalar of an orbit whose sign changes along a family are special points of `type` labelled
// with the measure's name: the engine locates them along arclength as it locates folds
// (Problem::TestFunctions, continuation/continuation.h). It must vary continuously along the
// family; nothing switches at its zeros.
struct OrbitTestFunction {
  OrbitMeasure measure;
  SpecialPointType type = SpecialPointType::kTestFunction;
};

// Grazing of a switching surface h(x) = 0 of a piecewise-smooth system, h > 0 on the side where
// the other law applies (a contact's penetration δ = |d| − C: the contact force acts for δ > 0).
//   kLiftOff    min_t h(x(t)): turns negative where an orbit that stays on the positive side (a
//               contact that never opens) first leaves it — the contact opens once per period;
//   kTouchdown  max_t h(x(t)): turns positive where an orbit that stays on the negative side first
//               touches it — impacts begin.
// At either zero the orbit is tangent to the surface (SpecialPointType::kGrazing); past it the
// orbit crosses the surface twice per period. Where the vector field is continuous across the
// surface with a jump in its derivative (a linear contact spring, N = k1 δ + …), the family goes on
// through the point (the flow stays C¹ at transversal crossings, Filippov/di Bernardo), but its
// orbits past it are smooth only piecewise, which a fixed collocation mesh resolves at a lower
// order unless its segments end on the switches (ShootingOptions::event_boundaries;
// tests/shooting/grazing_test.cpp measures both). The extremum is taken over the orbit's
// samples and refined by a parabola through the extreme sample and its neighbours, so it is as
// accurate as the samples make it (ShootingProblem::TestSamplesPerSegment; the test measures
// that too). h must be a function of the state alone and, for relative orbits, invariant under
// the system's rotation (a contact's penetration is): the samples then wrap round the period.
enum class GrazingSide { kLiftOff, kTouchdown };
OrbitTestFunction Grazing(std::function<double(ConstVectorRef)> surface, GrazingSide side,
                          std::string name);

// Shooting options for an orbit that crosses switching surfaces (past grazing): the segment
// boundaries of `options` (uniform when its mesh is empty) with one more at every zero of a
// switching function along the orbit u (solved with `options`, which must have no event
// boundaries), each an event boundary on its surface (ShootingOptions::event_boundaries). The
// zeros are found on the orbit sampled `samples` times per period and refined linearly (starting
// values: Newton corrects them); a boundary of the old mesh within `min_gap` (a fraction of the
// period) of a zero is dropped, and zeros within `coincide` of each other (necessarily of
// different surfaces: a symmetric orbit's contacts that switch together) share one boundary on
// the first surface. ok = false with a message when the orbit cannot be sampled or a zero lies
// within min_gap of t = 0 (the phase condition's boundary: start the orbit elsewhere). No zeros:
// the options unchanged.
struct EventMesh {
  bool ok = false;
  std::string message;
  ShootingOptions options;
  int zeros = 0;  // zeros found, before sharing
};
EventMesh WithEventBoundaries(OdeSystem& system, OrbitKind kind, const ShootingOptions& options,
                              const Vector& u, double lambda, int samples = 8192,
                              double min_gap = 1e-3, double coincide = 1e-6);
// An orbit u (solved with `options`) sampled `samples` times per period (samples_per_segment =
// samples / segments, at least 2); on failure orbit.valid is false and *failure says why.
OrbitSamples SampleOrbit(OdeSystem& system, OrbitKind kind, const ShootingOptions& options,
                         const Vector& u, double lambda, int samples, std::string* failure);
// A sign change of a switching function between two samples of an orbit: where (linearly between
// them, a fraction of the period), on which surface, and the index of the sample after it.
struct SurfaceCrossing {
  double tau = 0.0;
  int surface = 0;
  Index sample = 0;
};
// Every sign change of the system's switching functions along the samples, by surface, then time.
std::vector<SurfaceCrossing> SurfaceCrossings(const OdeSystem& system, const OrbitSamples& orbit);
// WithEventBoundaries from samples of an orbit over one period (any shooting's), for the orbit
// started at `start` (a fraction of the period: the zeros' times are taken from there, modulo the
// period).
EventMesh EventMeshOf(const OdeSystem& system, const ShootingOptions& options,
                      const OrbitSamples& orbit, double start = 0.0, double min_gap = 1e-3,
                      double coincide = 1e-6);

// Work done, summed over calls (for benchmarks).
struct ShootingStatistics {
  long residual_integrations = 0;     // segment integrations without sensitivities
  long sensitivity_integrations = 0;  // segment integrations with the STM
  long steps = 0;                     // integrator steps, all integrations
  long nonlinear_iterations = 0;      // the implicit integrators' Newton iterations, all steps
  long linear_solver_setups = 0;      // their factorisations
  long cache_hits = 0;                // evaluations served from the cache
  ShootingStatistics& operator+=(const ShootingStatistics& more) {
    residual_integrations += more.residual_integrations;
    sensitivity_integrations += more.sensitivity_integrations;
    steps += more.steps;
    nonlinear_iterations += more.nonlinear_iterations;
    linear_solver_setups += more.linear_solver_setups;
    cache_hits += more.cache_hits;
    return *this;
  }
};

class ShootingProblem : public Problem {
 public:
  // The system must outlive the problem. Throws std::invalid_argument when the kind does not fit
  // the system (kForced without ForcingPeriod() > 0, kRelative without rotation symmetry).
  ShootingProblem(OdeSystem& system, OrbitKind kind, const ShootingOptions& options = {});

  // --- Problem ---
  Index Dimension() const override;
  void Residual(const Vector& u, double lambda, Vector& F) override;
  void Jacobian(const Vector& u, double lambda, Matrix& J) override;
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override;
  Vector Scale() const override;
  double LambdaScale() const override { return lambda_scale_; }
  // The period's scale in Scale(): options().period_scale, or |T| of the first phase reference
  // (0 before it is set).
  double PeriodScale() const { return period_scale_; }
  Vector ResidualScale() const override;
  bool HasStability() const override { return true; }
  // Nontrivial Floquet multipliers (1 removed for kAutonomous, 2 for kRelative).
  Spectrum Stability(const Vector& u, double lambda) override;
  // "period", then "rotation" (kRelative), then the measures of SetMeasures (default: max and min
  // of every state, "max_<StateName(i)>", "min_<StateName(i)>").
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& u, double lambda) override;
  // The test functions of SetTestFunctions (none by default), by their measures' names.
  std::vector<std::string> TestFunctionNames() const override;
  Vector TestFunctions(const Vector& u, double lambda) override;
  SpecialPointType TestFunctionType(int k) const override;
  // SetPhaseReference(u, λ) when options().refresh_phase_reference.
  void PointAccepted(const Vector& u, double lambda) override;
  // With event boundaries: one margin per phase between two consecutive ones b < b' (a contact
  // phase or an open phase, "switches_<b>_<b'>"), its length τ_b' − τ_b as a fraction of the
  // period. It vanishes where the orbit becomes tangent to the surface (grazing: the phase
  // shrinks to nothing and the switching pattern changes); the phase's segments may take negative
  // lengths while the engine brackets that point (integrated backwards: the equations stay smooth
  // through it), which the engine locates as an event and where the family ends (SwitchAt is the
  // default's refusal: the other side is another pattern, started anew by
  // ContinueAcrossSwitches). The phase that wraps round t = 0 has no margin.
  std::vector<std::string> EventNames() const override;
  Vector EventFunctions(const Vector& u, double lambda) override;

  // --- Building and reading unknowns ---
  OrbitKind kind() const { return kind_; }
  Index StateDimension() const { return n_; }
  Index SegmentCount() const { return segments_; }
  const ShootingOptions& options() const { return options_; }
  // u from segment starts (n × N), T and φ (ignored where not unknowns); event boundaries at
  // their starting fractions (ShootingOptions::mesh).
  Vector Pack(const Matrix& starts, double period, double rotation = 0.0) const;
  Eigen::VectorBlock<const Vector> SegmentStart(const Vector& u, Index segment) const;
  // T: the unknown (kAutonomous, kRelative) or ForcingPeriod() at λ (kForced).
  double Period(const Vector& u, double lambda);
  // The N + 1 segment boundaries of u as fractions of the period (the event boundaries' unknowns
  // in their places).
  std::vector<double> Mesh(const Vector& u) const;
  double Rotation(const Vector& u) const;  // φ (kRelative), else 0

  // An initial guess from one point x0 near the orbit: integrates from x0 over one period guess
  // (kForced: the forcing period at λ) and places the segment starts on that trajectory; sets the
  // phase reference to x0 (not for kForced). On an integration failure the result has NaN
  // entries and LastFailure() says why.
  Vector InitialGuess(ConstVectorRef x0, double period, double lambda, double rotation = 0.0);

  // The phase conditions' hyperplanes pass through x_0 of u, normal to f and g there. Call it on
  // accepted continuation points to keep the hyperplane transversal to a changing orbit.
  void SetPhaseReference(const Vector& u, double lambda);

  // Replaces the default state min/max measures (period and rotation always come first).
  void SetMeasures(std::vector<OrbitMeasure> measures);
  // Test functions located along a family (e.g. Grazing).
  void SetTestFunctions(std::vector<OrbitTestFunction> tests);

  // The orbit sampled with samples_per_segment points per segment (kept for the last (u, λ):
  // the measures at one point sample it once).
  const OrbitSamples& Orbit(const Vector& u, double lambda);
  // The samples the test functions read: with Gauss collocation at least
  // kTestSamplesPerCollocationStep per collocation step (the orbit sampled again where that is more
  // than samples_per_segment; kept for the last (u, λ)), otherwise Orbit's. A grazing is the
  // extremum of a contact's penetration, and on A(a)'s whip the stiff contact's ripple (11.7 µs)
  // is shorter than 64 samples per segment's spacing (21 µs at 400 intervals): its grazing came out
  // at 132.632 rpm at the stage's settings, 132.499 with 256 samples and 132.497 with 1024 per
  // segment, and the step past the extremum's true zero met the jumps of a contact opening at the
  // collocation points (bench/whip_family_bench --samples).
  static constexpr Index kTestSamplesPerCollocationStep = 4;
  const OrbitSamples& TestOrbit(const Vector& u, double lambda);
  Index TestSamplesPerSegment() const;

  // Full Floquet information at (u, λ): nontrivial and trivial multipliers, invariance defect.
  FloquetResult Floquet(const Vector& u, double lambda);

  // Segment state-transition matrices M_i at (u, λ), the ones Stability uses (integrated under
  // sensitivity error control when accurate_stability applies); empty on failure.
  const std::vector<Matrix>& SegmentMonodromies(const Vector& u, double lambda);

  // Each segment's collocation mesh (fractions of the segment, SetCollocationMesh), adapted by
  // adapt_mesh_every; empty while uniform.
  const std::vector<std::vector<double>>& CollocationMeshes() const { return collocation_meshes_; }
  // Every collocation step over the period as a fraction of it, in time order (the segments'
  // uniform steps while not adapted). Gauss collocation only.
  Vector CollocationStepFractions() const;

  // The last integration failure (status kSuccess if none since construction).
  const IntegrationResult& LastFailure() const { return last_failure_; }
  const ShootingStatistics& statistics() const { return statistics_; }
  void ResetStatistics() { statistics_ = {}; }

 private:
  enum class Need { kState, kStm, kStmAndParameter };
  struct SegmentData {
    std::vector<Vector> ends;   // y_i
    std::vector<Matrix> stm;    // M_i
    std::vector<Vector> dxdp;   // ∂y_i/∂p
    std::vector<Vector> dxdt1;  // ∂y_i/∂t_{i+1}, with the STM when there are event boundaries
    std::vector<Matrix> derivatives;  // Gauss's u^(s) on each step, when adapt_mesh_every > 0
    bool has_stm = false;
    bool has_dxdp = false;
  };

  void CheckUnknowns(const Vector& u, const char* where) const;
  bool SameKey(const Vector& u, double lambda) const;
  // Integrates every segment at (u, λ) into data; false on failure (last_failure_ set).
  bool IntegrateSegments(const Vector& u, double lambda, Need need, SegmentData& data,
                         OdeIntegrator& integrator);
  // The segment STMs for stability at (u, λ) (see accurate_stability); null on failure.
  const std::vector<Matrix>* StabilityMonodromies(const Vector& u, double lambda);
  // Makes the cache hold (u, λ) with at least `need`; false on failure.
  bool Ensure(const Vector& u, double lambda, Need need);
  void AssembleResidual(const Vector& u, const SegmentData& data, Vector& F);
  double SegmentTime(double period, Index boundary) const { return period * mesh_[boundary]; }
  // Index of the first event unknown (and row) in u.
  Index EventOffset() const;
  // ∂τ_boundary/∂(event unknown `event`): 1 at its own boundary, the anchoring weights at the
  // boundaries placed between it and the next event boundary or end.
  double MeshWeight(Index boundary, int event) const;
  // Whether the segment lies between two event boundaries (in a phase: it may shrink past 0).
  bool InPhase(Index segment) const;
  // Consecutive event boundaries (b, b'), the phases between switches, in boundary order.
  std::vector<std::pair<Index, Index>> Phases() const;
  // Copies u's event boundaries into mesh_; false (last_failure_ set) unless they lie strictly
  // inside their neighbours.
  bool UseMesh(const Vector& u);
  // The collocation mesh over the period as times, N + 1 from SegmentTime(period, 0) to
  // SegmentTime(period, segments), segment after segment (uniform while not adapted).
  Vector CollocationTimes(double period) const;
  // Sets segment i's collocation mesh into `integrator` (when adapted).
  void UseCollocationMesh(OdeIntegrator& integrator, Index segment);
  // Re-equidistributes the collocation meshes on the orbit (u, λ) (adapt_mesh_every); leaves
  // them as they are when its integration fails.
  void AdaptCollocationMeshes(const Vector& u, double lambda);
  // ∇h_k at x by central differences in the scaled states.
  Vector SwitchingGradient(int surface, ConstVectorRef x);
  double ForcingPeriodAt(double lambda);
  double ForcingPeriodDerivative(double lambda);
  void RotationMatrix(double phi, Matrix& R) const;

  OdeSystem& system_;
  OrbitKind kind_;
  ShootingOptions options_;
  OdeIntegrator integrator_;
  std::unique_ptr<OdeIntegrator> stability_integrator_;  // see accurate_stability
  Index n_;
  Index segments_;
  std::vector<double> mesh_;       // N + 1 fractions (the event boundaries of the last u used)
  std::vector<double> base_mesh_;  // options' mesh or uniform: the event boundaries' start
  std::vector<std::vector<double>> collocation_meshes_;  // per segment; empty: uniform
  long accepted_points_ = 0;                              // PointAccepted calls
  // Per boundary: the event it is (index into event_boundaries) or −1; for the others the nearest
  // event boundary or end on each side and the fraction of the way between them (base mesh).
  std::vector<int> event_at_;
  std::vector<Index> anchor_left_, anchor_right_;
  std::vector<double> anchor_alpha_;
  Vector event_scale_;        // per event row: |∇h_k| in scaled states at the first reference
  Vector h_work_;
  Vector state_scale_;
  double period_scale_ = 0.0;
  double lambda_scale_ = 1.0;
  std::vector<OrbitMeasure> measures_;
  std::vector<OrbitTestFunction> tests_;
  // An orbit's samples, kept for the last (u, λ) they were made at.
  struct SampleCache {
    bool valid = false;
    Vector u;
    double lambda = 0.0;
    OrbitSamples orbit;
  };
  SampleCache samples_;       // Orbit's
  Vector samples_measures_;   // Measures of samples_ (empty: not yet asked since they were made)
  SampleCache test_samples_;  // TestOrbit's, where they are not Orbit's
  // The orbit u at λ sampled s times per segment, from `cache` when it holds (u, λ); made and kept
  // there otherwise (orbit.valid = false where it cannot be sampled).
  const OrbitSamples& Sampled(SampleCache& cache, const Vector& u, double lambda, Index s);

  // Phase reference.
  bool has_reference_ = false;
  Vector reference_;       // x_ref
  Vector time_normal_;     // S⁻¹ n̂_f  (so that p_t = time_normalᵀ (x_0 − x_ref))
  Vector rotation_normal_; // S⁻¹ n̂_g

  // Cache of the last evaluation point.
  bool cache_valid_ = false;
  Vector cache_u_;
  double cache_lambda_ = 0.0;
  bool residual_ready_ = false;
  Vector cache_F_;
  SegmentData cache_;
  SegmentData scratch_;  // for finite differences in λ, which must not evict the cache
  // STMs integrated with sensitivity error control for stability (accurate_stability).
  SegmentData stability_;
  bool stability_valid_ = false;
  Vector stability_u_;
  double stability_lambda_ = 0.0;

  // Workspaces.
  Vector f_work_, g_work_, x_work_;
  Matrix rotation_work_;
  IntegrationResult last_failure_;
  ShootingStatistics statistics_;
};

}  // namespace rubcont
