/* A plain-C reference for time marching the two-point rub rotor (bench/march_bench.cpp): the
 * model of docs/theory.md §2 in the fixed frame (rigid rotor and stator, four planar coordinates:
 * rotor left, rotor right, stator left, stator right; Hunt–Crossley contact, tanh friction, centre
 * damper, no imbalance) and Dormand–Prince 5(4) with dense output, written without rubcont's
 * layers (no Eigen, no OdeSystem, no integrator classes, no allocation): what a hand-written
 * integrator of this model costs, for the library's sweep stepper to be measured against.
 *
 * Error norm: that of IntegratorOptions (solvers/ode.h) and Boost.Odeint's default error checker,
 * the maximum over the 16 states of |e_i| / (atol·scale_i + rtol·|x_i|), x_i at the step's start,
 * scale the library's StateScale (positions: the largest clearance; velocities: that times the
 * fastest undamped frequency of the stator on its supports).
 *
 * State layout (16): positions (x, y) of rotor L, rotor R, stator L, stator R, then velocities. */
#ifndef RUBCONT_BENCH_PLAIN_RUB_DOPRI5_H
#define RUBCONT_BENCH_PLAIN_RUB_DOPRI5_H

#ifdef __cplusplus
extern "C" {
#endif

/* The raw data of a two-point scene (SI units), as docs/theory.md §3 lists them. */
typedef struct {
  double rotor_mass, rotor_inertia, contact_span, rotor_mass_center;
  double stator_mass, stator_inertia, stator_span, stator_mass_center;
  double support_stiffness[2], support_damping[2];
  double clearance[2], radius[2];
  double friction, contact_stiffness, contact_stiffness2, contact_damping, velocity_scale;
  double center_damping;
} PlainRubData;

/* The model, built once by PlainRubInit. */
typedef struct {
  double mass_inverse[4][4];
  double damping[4][4];
  double stiffness[4][4];
  double clearance[2], radius[2];
  double k1, k2, c_nl, mu, epsilon;
  double omega; /* spin [rad/s] */
  double scale[16];
} PlainRub;

/* How the step size follows the error estimate err (accepted when err ≤ 1). */
typedef enum {
  /* Boost.Odeint's controlled_runge_kutta with its default step adjuster: on rejection
   * h·max(0.9 err^(−1/3), 0.2); on acceptance with err < 0.5, h·0.9·max(err, 5^−5)^(−1/5);
   * otherwise h. The library's sweep stepper uses this rule. */
  kPlainOdeintControl = 0,
  /* Hairer's DOPRI5 (Hairer, Nørsett & Wanner, Solving ODEs I, §II.4 and the code's defaults):
   * h·min(10, max(0.2, 0.9·err^(−0.2 + 0.04·0.75)·err_old^0.04)) after an accepted step (the PI
   * controller that damps the step-size oscillation where stability limits the step), and
   * h·max(0.2, 0.9 err^(−0.17)) after a rejected one, no increase right after a rejection. */
  kPlainHairerControl = 1
} PlainControl;

typedef struct {
  long steps, rejected, rhs_evaluations;
} PlainStatistics;

void PlainRubInit(const PlainRubData* data, double omega, PlainRub* model);

/* f = ẋ at x (16 entries each). */
void PlainRubRhs(const PlainRub* model, const double* x, double* f);

/* Integrates x (16 entries, updated in place) from t0 to times[count − 1] at rtol = atol = tol,
 * writing x at each of the count increasing output times into samples (16 × count, sample after
 * sample) by the method's dense output. *step is the step to try first (0: estimated) and holds the
 * next step on return. Returns 0 on success, 1 when the step size underflowed. */
int PlainDopri5(const PlainRub* model, PlainControl control, double tol, double t0, double* x,
                const double* times, long count, double* samples, double* step,
                PlainStatistics* statistics);

#ifdef __cplusplus
}
#endif

#endif
