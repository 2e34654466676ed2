// Time integration of an OdeSystem with SUNDIALS: CVODES (BDF or Adams, dense LU, forward
// sensitivities) and ARKODE (explicit or diagonally implicit Runge–Kutta); Gauss collocation on a
// fixed mesh (ode_gauss.cpp), the fully implicit method SUNDIALS does not have; and Boost.Odeint's
// Dormand–Prince (ode_odeint.cpp), the cheapest explicit step for plain time marching.
//
// What the shooting code needs from an integrator, and what this one gives:
//   x(t1)                      the end state, from x(t0) = x0;
//   Φ = ∂x(t1)/∂x0  (n × n)    the state-transition matrix, from forward sensitivities
//                              (CVODES: ṡ_j = J(t, x) s_j, s_j(t0) = e_j, Hindmarsh et al. 2005);
//   q = ∂x(t1)/∂p   (n)        the parameter sensitivity (q̇ = J q + ∂f/∂p, q(t0) = 0);
//   x(t_k) at requested times  dense output (orbit samples for measures and FFTs);
//   events                     zeros of user functions g(t, x) (Poincaré sections, contact events).
// ARKODE has no sensitivity module: for it the variational equations are appended to the state
// (n + n² [+ n] unknowns) and integrated with full error control — an independent check of CVODES.
//
// Failures of the integration (too much work, repeated error-test or convergence failures, a
// failing right-hand side, a trajectory that leaves `state_bound`) are expected numerical outcomes:
// they are returned as an IntegrationStatus with SUNDIALS' flag name and message, never thrown and
// never printed (the SUNDIALS error handler is replaced, so nothing reaches stderr). Wrong sizes and
// invalid options are caller mistakes and throw std::invalid_argument.
//
// One OdeIntegrator keeps its SUNDIALS memory between calls (CVodeReInit / CVodeSensReInit,
// ERKStepReInit), so that the thousands of integrations of a continuation run allocate nothing
// after the first. It is not thread-safe; use one per thread.
#pragma once

#include <atomic>
#include <complex>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solvers/ode_system.h"

namespace rubcont {

enum class IntegrationMethod {
  kBdf,    // CVODES, variable-order BDF (orders 1–5), Newton + dense LU: stiff systems (the rub contact)
  kAdams,  // CVODES, Adams–Moulton (orders 1–12), Newton + dense LU: smooth, non-stiff systems
  kExplicitRungeKutta,             // ARKODE ERKStep, embedded pair of order `explicit_order`
  kDiagonallyImplicitRungeKutta,   // ARKODE ARKStep, DIRK of order `implicit_order`, dense LU
  // Boost.Odeint's Dormand–Prince 5(4) with dense output (ode_odeint.cpp): the state only (no
  // sensitivities, no events), with a per-step cost a fraction of ARKODE's on small systems — for
  // long explicit time marching (sweeps, ensembles).
  kDormandPrince,
  // Gauss–Legendre collocation (implicit Runge–Kutta of order 2·collocation_stages) on a fixed
  // uniform mesh of collocation_steps steps per call, Newton + dense LU, the STM as the exact
  // derivative of the discrete map (ode_gauss.cpp). No error estimate, no events: for shooting on
  // stiff, nearly undamped modes, with the mesh's accuracy measured where it is used.
  kGaussCollocation,
};
const char* ToString(IntegrationMethod method);

enum class SensitivityMethod {
  kStaggered,     // CV_STAGGERED: sensitivities corrected after the state has converged (cheapest
                  // with a direct solver: they reuse the state's Newton matrix)
  kSimultaneous,  // CV_SIMULTANEOUS: state and sensitivities in one nonlinear system
};

struct IntegratorOptions {
  IntegrationMethod method = IntegrationMethod::kBdf;
  // Local error control: |e_i| ≤ relative_tolerance·|x_i| + absolute_tolerance·scale_i, with
  // scale = OdeSystem::StateScale(): the absolute tolerance is in units of each state's typical
  // magnitude (metres and metres per second are judged alike). Both in (0, 1).
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-8;
  // Steps allowed between two output times before giving up with kTooMuchWork (≥ 1).
  long max_steps = 100000;
  double max_step = 0.0;      // largest |h| (time units); 0: unlimited
  double initial_step = 0.0;  // first |h| (time units); 0: estimated by the integrator
  // Largest order used: BDF 1–5, Adams 1–12; 0: the method's maximum. BDF ≤ 2 is A- and L-stable;
  // orders 3–5 are unstable for eigenvalues near the imaginary axis (lightly damped stiff modes).
  int max_order = 0;
  // CVODES BDF stability-limit detection (CVodeSetStabLimDet): lowers the order when it sees the
  // instability of orders ≥ 3 on lightly damped oscillatory modes.
  bool stability_limit_detection = false;
  // ERK order: 2, 3, 4, 5 (Dormand–Prince 7-4-5), 6 (Verner 8-5-6) or 8 (Fehlberg 13-7-8).
  int explicit_order = 5;
  // DIRK order: 2, 3, 4 (SDIRK 5-3-4) or 5 (ARK5(4)8L[2]SA's implicit table).
  int implicit_order = 4;
  // kDormandPrince: end a step where a switching function of the system (OdeSystem::
  // SwitchingFunctions: a contact closing or opening) is predicted to vanish, rather than let the
  // step straddle the kink of f there, which the error control passes only with tiny steps and
  // rejections (A(a)'s impacting whip: 22 % fewer f evaluations, half the rejected steps).
  bool land_on_switches = true;

  // Gauss collocation: stages s in [1, 6] (order 2s) and uniform steps per Integrate / Sample call
  // (≥ 1). The tolerances only set its Newton's stopping test (1e-3·absolute_tolerance, scaled).
  int collocation_stages = 4;
  long collocation_steps = 200;

  // Forward sensitivities (CVODES only; ARKODE integrates the augmented system).
  SensitivityMethod sensitivity_method = SensitivityMethod::kStaggered;
  // Include the sensitivities in the local error test (CVodeSetSensErrCon). Without it the STM is
  // only as accurate as the step sequence chosen for the state makes it — and a fast mode that the
  // state does not excite but a column of Φ does is then left to the method's stability: measured
  // on a 16-state stiff chain (bench/shooting_bench.cpp), 18–150× cheaper and as good for Newton,
  // but BDF orders 3–5 let a lightly damped fast mode of Φ grow without bound at rtol 1e-10
  // (use max_order = 2 with it off), and a nearly undamped fast mode is damped numerically.
  bool sensitivity_error_control = true;
  // Typical magnitude of the parameter, for the absolute tolerance on q = ∂x/∂p
  // (atol_q,i = absolute_tolerance·scale_i / parameter_scale). 0: max(|p|, 1) at each call.
  double parameter_scale = 0.0;

  // A trajectory with ‖x ./ scale‖∞ > state_bound stops with kStateBound: a finite-time blow-up or a
  // wild Newton iterate ends at once instead of exhausting max_steps. Must be > 1.
  double state_bound = 1e12;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const IntegratorOptions& options);

// A mesh for piecewise polynomial collocation of degree s that equidistributes the monitor of de
// Boor and AUTO-07p (Doedel et al.; Ascher, Mattheij & Russell §9.3): the local error of a step is
// ∝ (h ω)^(s+1) with ω = ‖u^(s+1)‖^(1/(s+1)), and u^(s+1) is estimated from the jumps of the
// piecewise constant u^(s) (CollocationDerivatives, scaled) between neighbouring steps.
//   `times`        the old mesh, N + 1 increasing times (a whole period across segments);
//   `derivatives`  n × N: u^(s) on each old step, each row in the units of its state's scale;
//   `stages`       s ≥ 1.
// Returns the density ω on each old step (N entries, ≥ 0, per time unit), with the one-sided jump
// at either end. A step whose neighbours agree (u^(s+1) ≈ 0) gets ω ≈ 0; callers add a floor.
Vector CollocationMonitor(const Vector& times, const Matrix& derivatives, int stages);
// N + 1 fractions 0 = θ_0 < … < θ_N = 1 of [a, b] (within the span of `times`) that give each new
// step the same integral of the piecewise constant `density` on the old mesh `times` (the
// density must be positive on [a, b]). Throws std::invalid_argument on N < 1, a ≥ b, sizes that do
// not match or a non-positive density.
std::vector<double> EquidistributedMesh(const Vector& times, const Vector& density, double a,
                                        double b, long steps);

// The stability function R(z) = 1 + z bᵀ(I − zA)⁻¹𝟙 of s-stage Gauss collocation (s in [1, 6]):
// one step of ẋ = λx multiplies x by R(λh). |R(iy)| = 1, |R(z)| < 1 for Re z < 0, R(−∞) = (−1)^s.
std::complex<double> GaussStabilityFunction(int stages, std::complex<double> z);
// Σ_k ln |R(λ h_k)|: the logarithm of the modulus the steps h_k together give the mode ẋ = λx
// (on a uniform mesh N ln |R(λh)|). Throws std::invalid_argument for stages outside [1, 6].
double GaussLogGrowth(int stages, std::complex<double> lambda, const Vector& steps);

enum class IntegrationStatus {
  kSuccess,
  kTooMuchWork,          // max_steps taken before reaching the next output time
  kTooMuchAccuracy,      // the tolerances are below what the arithmetic can deliver
  kErrorTestFailures,    // repeated local error-test failures, or the step became too small
  kConvergenceFailures,  // repeated failures of the implicit method's Newton iteration
  kLinearSolverFailure,  // the dense LU failed (setup or solve)
  kRhsFailure,           // the right-hand side (or the sensitivity right-hand side) failed
  kNonFinite,            // the right-hand side kept returning NaN or Inf
  kStateBound,           // ‖x ./ scale‖∞ exceeded state_bound
  kOther,                // any other SUNDIALS failure: see flag_name and message
};
const char* ToString(IntegrationStatus status);

// Counters of one integration call (they restart at every call).
struct IntegrationStatistics {
  long steps = 0;
  long rhs_evaluations = 0;            // f evaluations by the integrator (not the sensitivity ones)
  long jacobian_evaluations = 0;       // analytic or difference-quotient Jacobians for the Newton matrix
  long linear_solver_setups = 0;
  long reduced_setups = 0;  // of those, Gauss's on a second-order system's Schur complement (half size)
  long error_test_failures = 0;
  long nonlinear_iterations = 0;
  long nonlinear_convergence_failures = 0;
  long sensitivity_rhs_evaluations = 0;  // calls of the sensitivity right-hand side (CVODES)
  long restarts = 0;  // re-initializations at events (EventOptions::restart, CVODES)
  long long work = 0;  // steps × WorkPerStep × states: the call's cost in work units, the same on every machine
};

// Adds the counters of b to a.
void Accumulate(IntegrationStatistics& a, const IntegrationStatistics& b);

// The cost of one step of `method` on one state equation, in work units (a work unit: one explicit
// Runge–Kutta step of one state): 1 for the explicit methods, 4 for BDF, Adams and DIRK (a Newton
// iteration with a dense LU now and then), 100 for Gauss collocation (its stages' LU and the STM's
// solves); a step of an n-state system costs n times that. Measured on A(a)'s loop (16 states,
// 2026-11-30, this 2-core machine): a Dormand–Prince step of the runs 1.3 µs of CPU, a BDF step of
// L2's route and doubled family 5 µs, a Gauss step of the doubled family about 130 µs (the family's
// CPU its BDF steps leave, over its Gauss steps), in one probe run alone; in an earlier pair run
// side by side the flexible A(a)'s f evaluation took 2.4 times the rigid one's. A coarse model, not
// a clock: its point is that the same computation costs the same units on every machine and under
// any load, where CPU seconds do not.
long long WorkPerStep(IntegrationMethod method);

// The work (IntegrationStatistics::work) of one computation's integrations: those of the thread
// that made its WorkScope current and of the threads ParallelFor starts from there
// (solvers/parallel.h carries the account to its workers), and of no other. Decision: the loop's
// budget read a count of the whole process, so two loops on two threads of one process (e.g. from
// Python) would each have counted the other's work. An account made while another is current is
// nested in it (its work is the outer account's too) and must not outlive it.
class WorkAccount {
 public:
  WorkAccount();  // nested in the calling thread's current account, if any
  WorkAccount(const WorkAccount&) = delete;
  WorkAccount& operator=(const WorkAccount&) = delete;
  long long Work() const { return work_.load(std::memory_order_relaxed); }
  // Adds to this account and to the ones it is nested in.
  void Add(long long work);

 private:
  std::atomic<long long> work_{0};
  WorkAccount* const outer_;
};

// Makes `account` the calling thread's current one until the scope ends (then the previous one).
class WorkScope {
 public:
  explicit WorkScope(WorkAccount* account);
  ~WorkScope();
  WorkScope(const WorkScope&) = delete;
  WorkScope& operator=(const WorkScope&) = delete;

 private:
  WorkAccount* const previous_;
};

// The calling thread's current account (nullptr: none).
WorkAccount* CurrentWorkAccount();

// One zero of an event function.
struct IntegrationEvent {
  int index = 0;    // which component of g
  int direction = 0;  // +1: g rising through zero, −1: falling
  double t = 0.0;
  Vector x;         // state at t
};

struct IntegrationResult {
  IntegrationStatus status = IntegrationStatus::kSuccess;
  double t_reached = 0.0;           // the final time on success; the event time after a terminal event
  bool stopped_at_event = false;    // a terminal event ended the integration before t1
  int flag = 0;                     // SUNDIALS return flag of the failing call (0 on success)
  std::string flag_name;            // e.g. "CV_TOO_MUCH_WORK" (empty on success)
  std::string message;              // SUNDIALS' error message, or ours (state bound, NaN)
  int warnings = 0;                 // warnings SUNDIALS raised (e.g. "t + h = t")
  IntegrationStatistics statistics;
  std::vector<IntegrationEvent> events;  // in time order
  bool Succeeded() const { return status == IntegrationStatus::kSuccess; }
  std::string BriefReport() const;
};

// Event functions g(t, x) ∈ R^count whose zeros are located by the integrator's root finder
// (CVodeRootInit / ERKStepRootInit).
struct EventOptions {
  std::function<void(double t, ConstVectorRef x, VectorRef g)> function;
  int count = 0;
  // Per component: +1 report only rising zeros, −1 only falling, 0 both. Empty: all 0.
  std::vector<int> directions;
  // Stop at the first event (t_reached = event time, outputs = state there); otherwise record
  // every event and go on to t1.
  bool terminal = false;
  // Non-terminal events only: restart the method at every event, as at a new initial point (a
  // multistep method's history then never spans a switching surface of a piecewise-smooth field;
  // CVODES is re-initialized, its sensitivities too; an ARKODE one-step method already starts its
  // next step at the event). The state and sensitivities are continuous through the event — right
  // for a vector field that is continuous there (a kink, no saltation); a jump in f would need a
  // saltation matrix, which this does not apply.
  bool restart = false;
};

class OdeIntegrator {
 public:
  // The system must outlive the integrator. The options are validated here.
  explicit OdeIntegrator(OdeSystem& system, const IntegratorOptions& options = {});
  ~OdeIntegrator();
  OdeIntegrator(OdeIntegrator&&) noexcept;
  OdeIntegrator& operator=(OdeIntegrator&&) noexcept;
  OdeIntegrator(const OdeIntegrator&) = delete;
  OdeIntegrator& operator=(const OdeIntegrator&) = delete;

  const IntegratorOptions& options() const;
  OdeSystem& system();

  // Events apply to every later integration until cleared.
  void SetEvents(const EventOptions& events);
  void ClearEvents();

  // x(t1) from x(t0) = x0 (t1 < t0 integrates backwards). x0 and x1 have Dimension() entries and
  // may alias. With stm (resized to n × n): Φ(t1, t0) = ∂x(t1)/∂x0, column j = ∂x(t1)/∂x0_j.
  // With dxdp as well (resized to n): ∂x(t1)/∂p at the system's current parameter. With dxdt1
  // (resized to n; needs stm): ∂x(t1)/∂t1 — for Gauss collocation the exact derivative of its
  // map on the N uniform steps of [t0, t1] (h = (t1 − t0)/N moves with t1), not f(t1, x1): the
  // two differ where the mesh does not resolve a stiff mode (C(a)'s torus at 49 rpm: by 77 % of
  // the column's size, measured); for the error-controlled methods f(t1, x1), the derivative of
  // the flow they approximate.
  IntegrationResult Integrate(double t0, ConstVectorRef x0, double t1, VectorRef x1,
                              Matrix* stm = nullptr, Vector* dxdp = nullptr,
                              Vector* dxdt1 = nullptr);

  // The tangent map along the trajectory: x(t1) from x0, and images = Φ(t1, t0)·directions for the
  // n × k directions (1 ≤ k ≤ n; images resized to n × k, may alias directions): the variational
  // equations for k columns only (CVODES: k forward sensitivities seeded with the directions;
  // ARKODE: k columns appended; Gauss: its discrete map's exact derivative) — what Lyapunov
  // exponents need, at a fraction of the full Φ's cost. Each column's absolute tolerance is the
  // state's times ‖direction ./ scale‖₂. With `samples`, the state is also sampled at `times`
  // (monotone, within [t0, t1]; samples resized to n × m) by the integrator's dense output.
  IntegrationResult IntegrateTangents(double t0, ConstVectorRef x0, double t1, VectorRef x1,
                                      const Matrix& directions, Matrix& images,
                                      const Vector& times = Vector(), Matrix* samples = nullptr);

  // Dense output: states (resized to n × m) column k = x(times(k)), from x(t0) = x0. times has
  // m ≥ 1 entries, monotone in the direction of integration, none before t0 (in that direction).
  IntegrationResult Sample(double t0, ConstVectorRef x0, const Vector& times, Matrix& states);

  // Gauss collocation only (std::invalid_argument otherwise). The mesh of every later call until
  // changed: N + 1 fractions 0 = θ_0 < θ_1 < … < θ_N = 1 of the integrated span [t0, t1], step k
  // covering [t0 + θ_k (t1 − t0), t0 + θ_{k+1} (t1 − t0)]; empty: options().collocation_steps
  // uniform steps. Throws std::invalid_argument naming the rule a mesh breaks.
  void SetCollocationMesh(std::vector<double> fractions);
  // Gauss collocation only: d^s u/dt^s of the collocation polynomial u (degree s = stages, so
  // constant on a step) on each step of the last call, n × N in state units per time unit^s —
  // what a mesh is equidistributed from (EquidistributedMesh).
  const Matrix& CollocationDerivatives() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rubcont
