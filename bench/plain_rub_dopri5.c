/* The plain-C reference of bench/plain_rub_dopri5.h. */
#include "plain_rub_dopri5.h"

#include <math.h>
#include <string.h>

enum { kStates = 16, kCoordinates = 4 };

/* m [[(1−a)², a(1−a)], [a(1−a), a²]] + (I/l²) [[1, −1], [−1, 1]] (docs/theory.md §2). */
static void RigidBody(double m, double inertia, double span, double center, double out[2][2]) {
  const double a = center / span, j = inertia / (span * span);
  out[0][0] = m * (1.0 - a) * (1.0 - a) + j;
  out[0][1] = out[1][0] = m * a * (1.0 - a) - j;
  out[1][1] = m * a * a + j;
}

static void Invert2(const double m[2][2], double out[2][2]) {
  const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  out[0][0] = m[1][1] / det;
  out[1][1] = m[0][0] / det;
  out[0][1] = -m[0][1] / det;
  out[1][0] = -m[1][0] / det;
}

void PlainRubInit(const PlainRubData* d, double omega, PlainRub* model) {
  memset(model, 0, sizeof *model);
  double rotor[2][2], stator[2][2], rotor_inverse[2][2], stator_inverse[2][2];
  RigidBody(d->rotor_mass, d->rotor_inertia, d->contact_span, d->rotor_mass_center, rotor);
  RigidBody(d->stator_mass, d->stator_inertia, d->stator_span, d->stator_mass_center, stator);
  Invert2(rotor, rotor_inverse);
  Invert2(stator, stator_inverse);
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      model->mass_inverse[i][j] = rotor_inverse[i][j];
      model->mass_inverse[2 + i][2 + j] = stator_inverse[i][j];
    }
    model->stiffness[2 + i][2 + i] = d->support_stiffness[i];
    model->damping[2 + i][2 + i] = d->support_damping[i];
    model->clearance[i] = d->clearance[i];
    model->radius[i] = d->radius[i];
  }
  /* The centre damper between the mid-points: c_d w wᵀ, w = (½, ½, −½, −½). */
  const double w[kCoordinates] = {0.5, 0.5, -0.5, -0.5};
  for (int i = 0; i < kCoordinates; ++i) {
    for (int j = 0; j < kCoordinates; ++j) model->damping[i][j] += d->center_damping * w[i] * w[j];
  }
  model->k1 = d->contact_stiffness;
  model->k2 = d->contact_stiffness2;
  model->c_nl = d->contact_damping;
  model->mu = d->friction;
  model->epsilon = d->velocity_scale;
  model->omega = omega;
  /* Scales: the largest clearance, and that times the stator's fastest frequency on its supports
   * (the largest eigenvalue of M_s⁻¹ K_s: the rotor is free). */
  const double clearance = d->clearance[0] > d->clearance[1] ? d->clearance[0] : d->clearance[1];
  double a[2][2];
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) a[i][j] = stator_inverse[i][j] * d->support_stiffness[j];
  }
  const double half_trace = 0.5 * (a[0][0] + a[1][1]);
  const double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  const double fastest = sqrt(half_trace + sqrt(half_trace * half_trace - det));
  for (int i = 0; i < 8; ++i) {
    model->scale[i] = clearance;
    model->scale[8 + i] = clearance * fastest;
  }
}

void PlainRubRhs(const PlainRub* m, const double* x, double* f) {
  const double* q = x;      /* q[2c], q[2c + 1]: coordinate c's x and y */
  const double* v = x + 8;
  double load[8] = {0};
  for (int k = 0; k < 2; ++k) {
    const int r = 2 * k, s = 2 * (2 + k);
    const double dx = q[r] - q[s], dy = q[r + 1] - q[s + 1];
    const double rho = sqrt(dx * dx + dy * dy);
    const double delta = rho - m->clearance[k];
    if (!(delta > 0.0)) continue;
    const double nx = dx / rho, ny = dy / rho;
    const double vx = v[r] - v[s], vy = v[r + 1] - v[s + 1];
    const double delta_dot = nx * vx + ny * vy;
    const double normal = m->k1 * delta + m->k2 * delta * delta + m->c_nl * delta_dot * delta;
    if (!(normal > 0.0)) continue;
    const double slip = m->omega * m->radius[k] - ny * vx + nx * vy; /* ωR + tᵀḋ, t = (−n_y, n_x) */
    const double friction = m->mu * normal * tanh(slip / m->epsilon);
    const double fx = -normal * nx + friction * ny, fy = -normal * ny - friction * nx;
    load[r] += fx;
    load[r + 1] += fy;
    load[s] -= fx;
    load[s + 1] -= fy;
  }
  /* r = load − C v − K q, then a = M⁻¹ r, component by component. */
  double rest[8];
  for (int i = 0; i < kCoordinates; ++i) {
    double rx = load[2 * i], ry = load[2 * i + 1];
    for (int j = 0; j < kCoordinates; ++j) {
      rx -= m->damping[i][j] * v[2 * j] + m->stiffness[i][j] * q[2 * j];
      ry -= m->damping[i][j] * v[2 * j + 1] + m->stiffness[i][j] * q[2 * j + 1];
    }
    rest[2 * i] = rx;
    rest[2 * i + 1] = ry;
  }
  for (int i = 0; i < kCoordinates; ++i) {
    double ax = 0.0, ay = 0.0;
    for (int j = 0; j < kCoordinates; ++j) {
      ax += m->mass_inverse[i][j] * rest[2 * j];
      ay += m->mass_inverse[i][j] * rest[2 * j + 1];
    }
    f[8 + 2 * i] = ax;
    f[8 + 2 * i + 1] = ay;
  }
  for (int i = 0; i < 8; ++i) f[i] = v[i];
}

/* The Dormand–Prince 5(4) tableau. */
/* (The nodes c_i are not needed: without imbalance the field is autonomous.) */
static const double a21 = 1.0 / 5;
static const double a31 = 3.0 / 40, a32 = 9.0 / 40;
static const double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
static const double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                    a54 = -212.0 / 729;
static const double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                    a65 = -5103.0 / 18656;
static const double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784,
                    b6 = 11.0 / 84;
/* b − b̂ (the error estimate's weights; b̂ the fourth-order solution's). */
static const double e1 = 35.0 / 384 - 5179.0 / 57600, e3 = 500.0 / 1113 - 7571.0 / 16695,
                    e4 = 125.0 / 192 - 393.0 / 640, e5 = -2187.0 / 6784 + 92097.0 / 339200,
                    e6 = 11.0 / 84 - 187.0 / 2100, e7 = -1.0 / 40;

/* x(t_old + θh) by the method's continuous extension (Hairer's, as Boost.Odeint's calc_state). */
static void DenseOutput(double theta, double h, const double* x, const double* k1,
                        const double* k3, const double* k4, const double* k5, const double* k6,
                        const double* k7, double* out) {
  const double X1 = 5.0 * (2558722523.0 - 31403016.0 * theta) / 11282082432.0;
  const double X3 = 100.0 * (882725551.0 - 15701508.0 * theta) / 32700410799.0;
  const double X4 = 25.0 * (443332067.0 - 31403016.0 * theta) / 1880347072.0;
  const double X5 = 32805.0 * (23143187.0 - 3489224.0 * theta) / 199316789632.0;
  const double X6 = 55.0 * (29972135.0 - 7076736.0 * theta) / 822651844.0;
  const double X7 = 10.0 * (7414447.0 - 829305.0 * theta) / 29380423.0;
  const double tm1 = theta - 1.0, sq = theta * theta;
  const double A = sq * (3.0 - 2.0 * theta), B = sq * tm1, C = sq * tm1 * tm1, D = theta * tm1 * tm1;
  const double w1 = h * (A * b1 - C * X1 + D), w3 = h * (A * b3 + C * X3),
               w4 = h * (A * b4 - C * X4), w5 = h * (A * b5 + C * X5), w6 = h * (A * b6 - C * X6),
               w7 = h * (B + C * X7);
  for (int i = 0; i < kStates; ++i) {
    out[i] = x[i] + w1 * k1[i] + w3 * k3[i] + w4 * k4[i] + w5 * k5[i] + w6 * k6[i] + w7 * k7[i];
  }
}

int PlainDopri5(const PlainRub* m, PlainControl control, double tol, double t0, double* x,
                const double* times, long count, double* samples, double* step,
                PlainStatistics* statistics) {
  double k1[kStates], k2[kStates], k3[kStates], k4[kStates], k5[kStates], k6[kStates],
      k7[kStates], y[kStates], x_new[kStates], atol[kStates];
  for (int i = 0; i < kStates; ++i) atol[i] = tol * m->scale[i];
  double t = t0;
  const double t_final = times[count - 1];
  PlainRubRhs(m, x, k1);
  ++statistics->rhs_evaluations;
  double h = *step;
  if (!(h > 0.0)) { /* 1 % of ‖x‖/‖ẋ‖ in the scaled maximum norm (Hairer, Nørsett & Wanner) */
    double size = 0.0, rate = 0.0;
    for (int i = 0; i < kStates; ++i) {
      size = fmax(size, fabs(x[i]) / m->scale[i]);
      rate = fmax(rate, fabs(k1[i]) / m->scale[i]);
    }
    h = size > 1e-5 && rate > 1e-5 ? 0.01 * size / rate : 1e-6 * (t_final - t0);
  }
  double error_old = 1e-4;
  int rejected_last = 0;
  long filled = 0;
  while (t < t_final) {
    const int last = t + h >= t_final;
    const double h_try = last ? t_final - t : h;
    for (int i = 0; i < kStates; ++i) y[i] = x[i] + h_try * a21 * k1[i];
    PlainRubRhs(m, y, k2);
    for (int i = 0; i < kStates; ++i) y[i] = x[i] + h_try * (a31 * k1[i] + a32 * k2[i]);
    PlainRubRhs(m, y, k3);
    for (int i = 0; i < kStates; ++i) y[i] = x[i] + h_try * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
    PlainRubRhs(m, y, k4);
    for (int i = 0; i < kStates; ++i) {
      y[i] = x[i] + h_try * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
    }
    PlainRubRhs(m, y, k5);
    for (int i = 0; i < kStates; ++i) {
      y[i] = x[i] + h_try * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
    }
    PlainRubRhs(m, y, k6);
    for (int i = 0; i < kStates; ++i) {
      x_new[i] = x[i] + h_try * (b1 * k1[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
    }
    PlainRubRhs(m, x_new, k7);
    statistics->rhs_evaluations += 6;
    double error = 0.0;
    for (int i = 0; i < kStates; ++i) {
      const double e = h_try * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] +
                                e7 * k7[i]);
      error = fmax(error, fabs(e) / (atol[i] + tol * fabs(x[i])));
    }
    if (!(error <= 1.0)) { /* rejected (a NaN estimate too) */
      ++statistics->rejected;
      if (control == kPlainOdeintControl) {
        h = h_try * fmax(0.9 * pow(error, -1.0 / 3.0), 0.2);
      } else {
        h = h_try / fmin(5.0, pow(error, 0.17) / 0.9);
        rejected_last = 1;
      }
      if (!(h > 1e-14 * fabs(t)) || isnan(error)) return 1;
      continue;
    }
    ++statistics->steps;
    const double t_new = last ? t_final : t + h_try;
    while (filled < count && times[filled] <= t_new) {
      DenseOutput((times[filled] - t) / h_try, h_try, x, k1, k3, k4, k5, k6, k7,
                  samples + kStates * filled);
      ++filled;
    }
    memcpy(x, x_new, sizeof x_new);
    memcpy(k1, k7, sizeof k7);
    t = t_new;
    /* The next step. A clipped last step keeps the step it clipped. */
    double next;
    if (control == kPlainOdeintControl) {
      next = error < 0.5 ? h_try * 0.9 * pow(fmax(error, pow(5.0, -5.0)), -0.2) : h_try;
    } else {
      const double fac11 = pow(error, 0.17);
      double fac = fac11 / pow(error_old, 0.04);
      fac = fmax(0.1, fmin(5.0, fac / 0.9));
      next = h_try / fac;
      if (rejected_last) next = fmin(next, h_try);
      error_old = fmax(error, 1e-4);
      rejected_last = 0;
    }
    h = last && h > h_try ? fmax(next, h) : next;
  }
  *step = h;
  return 0;
}
