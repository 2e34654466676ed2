#include "models/rub_model.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/flexible.h"
#include "models/units.h"
#include "solvers/finite_difference.h"
#include "solvers/ode.h"

namespace rubcont {
namespace {

// A state of the two-point model with both contacts penetrating slightly and moving.
Vector TouchingState(const RubStructure& s) {
  Vector x = Vector::Zero(s.States());
  const double C = s.contacts[0].geometry.clearance;
  // rotor L, R; stator L, R (x, y pairs), then velocities
  x.head(8) << 1.0002 * C * std::cos(0.3), 1.0002 * C * std::sin(0.3),
      1.0001 * C * std::cos(2.0) + 1e-6, 1.0001 * C * std::sin(2.0) - 2e-6,
      1e-6, -2e-6, 3e-6, 1e-6;
  x.tail(8) << 0.02, -0.13, 0.11, 0.05, -0.01, 0.02, 0.03, -0.04;
  return x;
}

TEST_CASE("contact law derivatives match finite differences in every friction mode",
          "[contact]") {
  ContactLaw law;
  law.velocity_scale = 0.05;
  const ContactGeometry geometry;
  const double omega = 7.0;
  Vector x(4);  // d, ḋ
  x << 3.8105e-4 * std::cos(0.7), 3.8105e-4 * std::sin(0.7), 0.03, -0.21;
  for (FrictionMode mode : {FrictionMode::kRegularized, FrictionMode::kSlipPositive,
                            FrictionMode::kSlipNegative, FrictionMode::kStick}) {
    auto force = [&](const Vector& y, Vector& f) {
      ContactEvaluation e;
      EvaluateContact(law, geometry, omega, y.head<2>(), y.tail<2>(), mode, 123.0, false, e);
      f.resize(4);
      f << e.force, e.normal_force, e.slip_velocity;
    };
    ContactEvaluation e;
    EvaluateContact(law, geometry, omega, x.head<2>(), x.tail<2>(), mode, 123.0, true, e);
    REQUIRE(e.touching);
    Matrix J(4, 4);
    J << e.df_dd, e.df_dddot, e.dN_dd, e.dN_dddot, e.dV_dd, e.dV_dddot;
    const Vector typical = (Vector(4) << 3.8e-4, 3.8e-4, 0.1, 0.1).finished();
    const JacobianCheck check = CheckJacobian(force, x, J, 1e-6, &typical);
    INFO("mode " << static_cast<int>(mode) << " worst (" << check.worst_row << ", "
                 << check.worst_col << ") analytic " << check.analytic_value << " fd "
                 << check.difference_value);
    CHECK(check.ok);
  }
}

TEST_CASE("contact law: no force in the gap, friction drives backward precession", "[contact]") {
  const ContactLaw law;
  const ContactGeometry geometry;
  ContactEvaluation e;
  EvaluateContact(law, geometry, 10.0, Vector2(3.0e-4, 0.0), Vector2(0.0, -0.1),
                  FrictionMode::kRegularized, 0.0, true, e);
  CHECK_FALSE(e.touching);
  CHECK(e.force.norm() == 0.0);
  // An inactive contact exerts nothing even when it penetrates; an exact (held) mode continues
  // the normal law into the gap with N < 0, smoothly, for piecewise formulations.
  EvaluateContact(law, geometry, 10.0, Vector2(3.82e-4, 0.0), Vector2(0.0, 0.0),
                  FrictionMode::kInactive, 0.0, true, e);
  CHECK_FALSE(e.touching);
  CHECK(e.force.norm() == 0.0);
  EvaluateContact(law, geometry, 10.0, Vector2(3.80e-4, 0.0), Vector2(0.0, 0.0),
                  FrictionMode::kStick, 0.0, true, e);
  CHECK(e.touching);
  CHECK(e.normal_force == Approx(-law.stiffness * 1e-6).epsilon(1e-6));
  // Penetrating at n = (1, 0), sliding with V > 0: normal pushes the rotor back (−x), friction
  // −F t = −F (0, 1) points along −y, the direction of backward (clockwise) precession at n.
  EvaluateContact(law, geometry, 10.0, Vector2(3.82e-4, 0.0), Vector2(0.0, 0.0),
                  FrictionMode::kSlipPositive, 0.0, false, e);
  REQUIRE(e.touching);
  CHECK(e.normal_force == Approx(law.stiffness * 1e-6).epsilon(1e-9));
  CHECK(e.slip_velocity == Approx(10.0 * geometry.radius));
  CHECK(e.force.x() < 0.0);
  CHECK(e.force.y() == Approx(-law.friction * e.normal_force));
}

TEST_CASE("two-point structure: fixed-frame Jacobian and parameter derivative", "[rub_model]") {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.velocity_scale = 0.05;
  params.imbalance = 3.43e-5;
  RubFixedFrame model(TwoPointStructure(params), RpmToRadPerSecond(60.0));
  const Vector x = TouchingState(model.structure());
  const Vector typical = model.StateScale();
  const double t = 0.0123;
  Matrix J(16, 16);
  model.JacobianX(t, x, J);
  auto rhs = [&](const Vector& y, Vector& f) {
    f.resize(16);
    model.Rhs(t, y, f);
  };
  const JacobianCheck check = CheckJacobian(rhs, x, J, 1e-6, &typical);
  INFO("worst (" << check.worst_row << ", " << check.worst_col << ") analytic "
                 << check.analytic_value << " fd " << check.difference_value);
  CHECK(check.ok);

  Vector df(16);
  model.DfDparameter(t, x, df);
  const double omega = model.Parameter();
  const double h = 1e-5 * omega;
  Vector f_plus(16), f_minus(16);
  model.SetParameter(omega + h);
  model.Rhs(t, x, f_plus);
  model.SetParameter(omega - h);
  model.Rhs(t, x, f_minus);
  model.SetParameter(omega);
  const Vector fd = (f_plus - f_minus) / (2 * h);
  CHECK((df - fd).norm() <= 1e-6 * fd.norm());
}

TEST_CASE("rotating frame: Jacobian, equivariance and agreement with the fixed frame",
          "[rub_model]") {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.velocity_scale = 0.05;
  const double frame_rate = kTwoPi * 80.0;
  RubRotatingFrame rotating(TwoPointStructure(params), frame_rate, kTwoPi * 0.9);
  const Vector x = TouchingState(rotating.structure());
  const Vector typical = rotating.StateScale();
  Matrix J(16, 16);
  rotating.JacobianX(0.0, x, J);
  auto rhs = [&](const Vector& y, Vector& f) {
    f.resize(16);
    rotating.Rhs(0.0, y, f);
  };
  const JacobianCheck check = CheckJacobian(rhs, x, J, 1e-6, &typical);
  INFO("worst (" << check.worst_row << ", " << check.worst_col << ") analytic "
                 << check.analytic_value << " fd " << check.difference_value);
  CHECK(check.ok);

  // Equivariance: f(R_φ x) = R_φ f(x).
  Vector f(16), f_rotated(16);
  rotating.Rhs(0.0, x, f);
  Vector y = x;
  rotating.Rotate(1.1, y);
  rotating.Rhs(0.0, y, f_rotated);
  rotating.Rotate(1.1, f);
  CHECK((f_rotated - f).norm() <= 1e-12 * f.norm());

  // d/dt of u(t) = e^{−jΩt} p(t) computed from the rotating-frame field equals the fixed-frame
  // field at u: compare at t = 0.37 s by central differences of ToFixedFrame along a short step.
  const double t = 0.37, h = 1e-7;
  const Vector fixed_derivative =
      (rotating.ToFixedFrame(t + h, y + h * f_rotated) -
       rotating.ToFixedFrame(t - h, y - h * f_rotated)) / (2 * h);
  RubFixedFrame fixed(rotating.structure(), rotating.Parameter());
  Vector f_fixed(16);
  fixed.Rhs(t, rotating.ToFixedFrame(t, y), f_fixed);
  CHECK((fixed_derivative - f_fixed).norm() <= 1e-5 * f_fixed.norm());

  // ToRotatingFrame inverts ToFixedFrame at any time.
  for (double time : {0.0, t}) {
    CHECK((rotating.ToRotatingFrame(time, rotating.ToFixedFrame(time, y)) - y).norm() <= 1e-14 * y.norm());
  }
}

TEST_CASE("contact chart: the gap and angle of each contact, inverted exactly, with its Jacobian",
          "[rub_model]") {
  const RubRotatingFrame frame(TwoPointStructure(ThesisCaseCc()), kTwoPi * 80.0, kTwoPi * 1.05);
  REQUIRE(frame.HasStateChart());
  const Vector x = TouchingState(frame.structure());
  Vector y(16), back(16);
  frame.ToChart(x, y);
  // Contact k's stator position becomes (|d| − C, arg d), d = u_rotor − u_stator, its velocity
  // (n·ḋ, t·ḋ) = Re and Im of ḋ e^{−j arg d}; the rotor's coordinates stay.
  for (const RubContact& c : frame.structure().contacts) {
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    const std::complex<double> d(x(r) - x(s), x(r + 1) - x(s + 1));
    const std::complex<double> rate(x(8 + r) - x(8 + s), x(8 + r + 1) - x(8 + s + 1));
    CHECK(y(s) == Approx(std::abs(d) - c.geometry.clearance).margin(1e-18));
    CHECK(y(s + 1) == Approx(std::arg(d)));
    CHECK(y(8 + s) == Approx((rate * std::conj(d) / std::abs(d)).real()));
    CHECK(y(8 + s + 1) == Approx((rate * std::conj(d) / std::abs(d)).imag()));
    CHECK(y(r) == x(r));
    CHECK(y(8 + r + 1) == x(8 + r + 1));
  }
  CHECK(frame.ChartAngles() == std::vector<Index>{5, 7});
  // Round trip to rounding, and the angle taken modulo 2π.
  Matrix D(16, 16);
  frame.FromChart(y, back, &D);
  CHECK((back - x).cwiseQuotient(frame.StateScale()).lpNorm<Eigen::Infinity>() <= 1e-12);
  Vector turned = y;
  turned(5) += kTwoPi;
  frame.FromChart(turned, back);
  CHECK((back - x).cwiseQuotient(frame.StateScale()).lpNorm<Eigen::Infinity>() <= 1e-12);
  // ∂Ψ/∂y against central differences.
  const Vector scale = frame.ChartScale();
  for (Index j = 0; j < 16; ++j) {
    const double h = 1e-6 * scale(j);
    Vector plus = y, minus = y, x_plus(16), x_minus(16);
    plus(j) += h;
    minus(j) -= h;
    frame.FromChart(plus, x_plus);
    frame.FromChart(minus, x_minus);
    const Vector column = (x_plus - x_minus) / (2 * h);
    INFO("column " << j);
    // Per scaled unit of y_j, in scaled units of x.
    CHECK(((column - D.col(j)) * scale(j)).cwiseQuotient(frame.StateScale()).norm() <= 1e-8);
  }
  // A structure whose contacts share a stator coordinate has no chart.
  RubStructure shared = TwoPointStructure(ThesisCaseAa());
  shared.contacts[1].stator = shared.contacts[0].stator;
  CHECK(!RubFixedFrame(shared).HasStateChart());
}

TEST_CASE("gyroscopic moments (a flexible rotor): Jacobians, ∂f/∂ω, whirl out of contact",
          "[rub_model]") {
  ShaftElement rotor, stator;
  rotor.outer_diameter = 0.03;
  stator.outer_diameter = 0.16;
  stator.inner_diameter = 0.13;
  for (ShaftElement* e : {&rotor, &stator}) {
    e->youngs_modulus = 2.11e11;
    e->shear_modulus = 8.12e10;
    e->density = 7810.0;
  }
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.velocity_scale = 0.05;
  const RubStructure s = BuildFlexibleRub(FlexibleTwoPoint(params, rotor, stator, 6, 3)).structure;
  REQUIRE(s.gyroscopic.norm() > 0.0);
  const Index n = s.States();
  const double omega = RpmToRadPerSecond(3000.0);
  Vector x = Vector::Zero(n);
  x.head(8) = TouchingState(s).head(8);
  for (Index i = 8; i < n / 2; ++i) x(i) = 1e-6 * std::sin(1.0 + i);
  for (Index i = n / 2; i < n; ++i) x(i) = 0.05 * std::cos(2.0 + i);

  RubFixedFrame fixed(s, omega);
  RubRotatingFrame rotating(s, kTwoPi * 80.0, omega);
  for (OdeSystem* model : {static_cast<OdeSystem*>(&fixed), static_cast<OdeSystem*>(&rotating)}) {
    Matrix J(n, n);
    model->JacobianX(0.0, x, J);
    auto rhs = [&](const Vector& y, Vector& f) {
      f.resize(n);
      model->Rhs(0.0, y, f);
    };
    const Vector typical = model->StateScale();
    // The modal rows combine the contacts' 1.75e11 N/m with modal stiffnesses to 5e14: central
    // differences leave round-off of ~1e-8 of a row's largest entry, so entries below 1e-7 of it
    // are compared absolutely (the gyroscopic terms are checked exactly out of contact below).
    const JacobianCheck check = CheckJacobian(rhs, x, J, 1e-6, &typical, 1e-7);
    INFO("worst (" << check.worst_row << ", " << check.worst_col << ") analytic "
                   << check.analytic_value << " fd " << check.difference_value);
    CHECK(check.ok);
    Vector df(n), f_plus(n), f_minus(n);
    model->DfDparameter(0.0, x, df);
    const double h = 1e-5 * omega;
    model->SetParameter(omega + h);
    model->Rhs(0.0, x, f_plus);
    model->SetParameter(omega - h);
    model->Rhs(0.0, x, f_minus);
    model->SetParameter(omega);
    const Vector fd = (f_plus - f_minus) / (2 * h);
    CHECK((df - fd).norm() <= 1e-6 * fd.norm());
  }
  // Out of contact the fixed-frame field is linear: its eigenvalues are the structure's whirl
  // eigenvalues at the spin, forward (+jν) and backward (−jν) split by G.
  Matrix J(n, n);
  fixed.JacobianX(0.0, Vector::Zero(n), J);
  Vector free_state = x;
  free_state.head(n / 2) *= 0.1;  // out of contact: the field is J x
  Vector f(n);
  fixed.Rhs(0.0, free_state, f);
  CHECK((f - J * free_state).norm() <= 1e-12 * f.norm());
  const Eigen::VectorXcd lambda = J.eigenvalues();
  for (bool backward : {false, true}) {
    for (const StructureMode& mode : StructureModes(s, false, omega, backward)) {
      const std::complex<double> target(-mode.damping_ratio * kTwoPi * mode.frequency_hz /
                                            std::sqrt(1 - mode.damping_ratio * mode.damping_ratio),
                                        (backward ? -1.0 : 1.0) * kTwoPi * mode.frequency_hz);
      double nearest = kInfinity;
      for (Index i = 0; i < lambda.size(); ++i) {
        nearest = std::min(nearest, std::abs(lambda(i) - target));
      }
      INFO((backward ? "backward " : "forward ") << mode.frequency_hz << " Hz");
      CHECK(nearest <= 1e-6 * (std::abs(target) + 1.0));  // + 1 rad/s: the rigid modes at 0
    }
  }
  // Backward and forward differ: the spin does enter the field.
  CHECK(StructureModes(s, false, omega, true)[2].frequency_hz <
        StructureModes(s, false, omega)[2].frequency_hz);
}

TEST_CASE("contact exchange: a mirror symmetry of A(a) (f commutes with it), none with unequal "
          "clearances or an off-centre mass",
          "[rub_model]") {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.velocity_scale = 0.05;
  const RubStructure structure = TwoPointStructure(params);
  const std::vector<Index> exchange = ContactExchange(structure);
  CHECK(exchange == std::vector<Index>{1, 0, 3, 2});  // rotor L ↔ R, stator L ↔ R
  RubRotatingFrame rotating(structure, kTwoPi * 80.0, kTwoPi * 0.9);
  RubFixedFrame fixed(structure, kTwoPi * 0.9);
  REQUIRE(rotating.HasMirrorSymmetry());
  REQUIRE(fixed.HasMirrorSymmetry());
  // A state that is not symmetric: the right contact deeper than the left, different velocities.
  Vector x = TouchingState(structure);
  x(2) *= 1.001;
  x(13) += 0.01;
  for (OdeSystem* system : {static_cast<OdeSystem*>(&rotating), static_cast<OdeSystem*>(&fixed)}) {
    Vector f(16), f_mirrored(16), y = x;
    system->Mirror(y);
    CHECK((y - x).norm() > 1e-3 * x.norm());
    system->Rhs(0.0, x, f);
    system->Rhs(0.0, y, f_mirrored);
    system->Mirror(f);
    CHECK((f_mirrored - f).norm() <= 1e-12 * f.norm());
    system->Mirror(y);
    CHECK(y == x);  // an involution
  }

  TwoPointParams unequal = params;
  unequal.clearance[1] *= 2.0;  // case A(b)-like RCIs
  CHECK(ContactExchange(TwoPointStructure(unequal)).empty());
  CHECK_FALSE(RubFixedFrame(TwoPointStructure(unequal)).HasMirrorSymmetry());
  TwoPointParams off_centre = params;
  off_centre.rotor_mass_center = 0.2;
  CHECK(ContactExchange(TwoPointStructure(off_centre)).empty());
}

TEST_CASE("rigid-contact orbit of the general structure equals the analytic Mode 1/2 closed form",
          "[rub_model]") {
  // Two independent derivations: the thesis-form W(Ω) receptance of models/analytic.h and the
  // bordered solve of the assembled structure (with the centre damper inside C).
  TwoPointParams params = ThesisCaseAa();
  params.rotor_mass_center = 0.22;  // asymmetric rotor, unequal clearances
  params.rotor_inertia = 0.04;
  params.clearance = {3.81e-4, 3.048e-4};
  const RubStructure s = TwoPointStructure(params);
  for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
    // 450 and 540 Hz (the family search's grid reaches RCI × 260 rpm = 541 Hz): there the bordered
    // matrix's Schur pivots (~1/|D|) fell below full-pivoting LU's default rank threshold and the
    // solve returned forces of 0 until 2026-11-27.
    for (double hz : {30.0, 84.0, 120.0, 170.0, 450.0, 540.0}) {
      const CircularOrbit closed = SolveCircularOrbit(params, mode, kTwoPi * hz);
      const RigidContactOrbit orbit =
          SolveRigidContactOrbit(s, kTwoPi * hz, {1.0, double(ContactSign(mode))});
      for (int k = 0; k < 2; ++k) {
        CHECK(std::abs(orbit.force[k] - closed.contact_force(k)) <=
              1e-9 * std::abs(closed.contact_force(k)));
        CHECK(std::abs(orbit.amplitude[k] - closed.rotor_amplitude(k)) <=
              1e-9 * std::abs(closed.rotor_amplitude(k)));
        CHECK(std::abs(orbit.amplitude[2 + k] - closed.stator_amplitude(k)) <=
              1e-9 * std::abs(closed.stator_amplitude(k)));
      }
    }
  }
}


// The model without its switching increment bounds (everything else delegated): landing on the
// switches then predicts at every step.
class WithoutIncrementBounds final : public OdeSystem {
 public:
  explicit WithoutIncrementBounds(RubFixedFrame& model) : model_(model) {}
  Index Dimension() const override { return model_.Dimension(); }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override { model_.Rhs(t, x, f); }
  double Parameter() const override { return model_.Parameter(); }
  void SetParameter(double p) override { model_.SetParameter(p); }
  Vector StateScale() const override { return model_.StateScale(); }
  int SwitchingCount() const override { return model_.SwitchingCount(); }
  void SwitchingFunctions(double t, ConstVectorRef x, VectorRef h) const override {
    model_.SwitchingFunctions(t, x, h);
  }

 private:
  RubFixedFrame& model_;
};

TEST_CASE("switching increment bounds: they hold along x + s f, and landing that skips predictions "
          "with them takes the same steps bit for bit", "[rub_model]") {
  RubFixedFrame model(TwoPointStructure(ThesisCaseAa()), RpmToRadPerSecond(160.0));
  const double C = model.structure().contacts[0].geometry.clearance;
  // Radial motion of the left contact (d and ḋ along x: h moves by exactly s |ḋ|), oblique motion
  // at the right one, and the touching state.
  Vector radial = Vector::Zero(16);
  radial(0) = 1.0001 * C;
  radial(8) = 0.3;
  radial(2) = 0.5 * C;
  radial(3) = 0.7 * C;
  radial(10) = -0.2;
  radial(11) = 0.15;
  for (const Vector& x : {radial, TouchingState(model.structure())}) {
    Vector f(16), h(2), h_ahead(2), bound(2);
    model.Rhs(0.0, x, f);
    model.SwitchingFunctions(0.0, x, h);
    for (double s : {1e-9, 1e-6, 1e-4}) {
      CAPTURE(s);
      REQUIRE(model.SwitchingIncrementBounds(0.0, x, f, s, bound));
      const Vector ahead = x + s * f;
      model.SwitchingFunctions(s, ahead, h_ahead);
      for (int k = 0; k < 2; ++k) {
        const Index r = 2 * k, q = 4 + 2 * k;
        const double rate = std::hypot(f(r) - f(q), f(r + 1) - f(q + 1));
        CHECK(std::abs(h_ahead(k) - h(k)) <= bound(k));
        // Not looser than the L1 norm of ḋ allows (√2 |ḋ|) and the rounding terms.
        CHECK(bound(k) <= 1.5 * s * rate + 1e-12 * s * rate + 1e-18);
      }
    }
  }
  // Radial motion: the bound is tight (h moves by s |ḋ| to 1e-3). Tangential motion (a contact
  // whirling closed): h moves by s² |ḋ|² / 2|d|, and so does the bound, far below s |ḋ|.
  {
    Vector f(16), h(2), h_ahead(2), bound(2);
    model.Rhs(0.0, radial, f);
    model.SwitchingFunctions(0.0, radial, h);
    const double s = 1e-6;
    model.SwitchingIncrementBounds(0.0, radial, f, s, bound);
    model.SwitchingFunctions(s, radial + s * f, h_ahead);
    CHECK(std::abs(h_ahead(0) - h(0)) >= 0.999 * bound(0));
    Vector tangential = radial;
    tangential(8) = 0.0;
    tangential(9) = 0.3;
    model.Rhs(0.0, tangential, f);
    model.SwitchingFunctions(0.0, tangential, h);
    model.SwitchingIncrementBounds(0.0, tangential, f, s, bound);
    model.SwitchingFunctions(s, tangential + s * f, h_ahead);
    CHECK(std::abs(h_ahead(0) - h(0)) <= bound(0));
    CHECK(bound(0) <= 2.0 * s * s * 0.09 / (2.0 * tangential(0)));
    CHECK(bound(0) <= 1e-3 * s * 0.3);
  }

  // From the touching state the contacts open and close: landing must take the same steps with
  // the bounds (predictions skipped far from a switch) as without (every step predicts).
  IntegratorOptions options;
  options.method = IntegrationMethod::kDormandPrince;
  options.max_steps = 1000000;
  WithoutIncrementBounds plain(model);
  const Vector x0 = TouchingState(model.structure());
  Vector times(400);
  for (Index k = 0; k < times.size(); ++k) times(k) = 0.02 * static_cast<double>(k + 1) / 400.0;
  Matrix with_bounds, without_bounds;
  const IntegrationResult a = OdeIntegrator(model, options).Sample(0.0, x0, times, with_bounds);
  const IntegrationResult b = OdeIntegrator(plain, options).Sample(0.0, x0, times, without_bounds);
  REQUIRE(a.status == IntegrationStatus::kSuccess);
  REQUIRE(b.status == IntegrationStatus::kSuccess);
  int switches = 0;
  Vector h(2), h_before(2);
  model.SwitchingFunctions(0.0, x0, h_before);
  for (Index k = 0; k < times.size(); ++k) {
    model.SwitchingFunctions(times(k), with_bounds.col(k), h);
    for (int c = 0; c < 2; ++c) switches += (h(c) > 0.0) != (h_before(c) > 0.0) ? 1 : 0;
    h_before = h;
  }
  CAPTURE(switches, a.statistics.steps, a.statistics.error_test_failures);
  CHECK(switches >= 4);
  CHECK(a.statistics.steps == b.statistics.steps);
  CHECK(a.statistics.rhs_evaluations == b.statistics.rhs_evaluations);
  CHECK(a.statistics.error_test_failures == b.statistics.error_test_failures);
  CHECK((with_bounds.array() == without_bounds.array()).all());
}
}  // namespace
}  // namespace rubcont
