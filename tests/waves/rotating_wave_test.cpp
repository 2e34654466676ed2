#include "waves/rotating_wave.h"

#include <cmath>
#include <complex>
#include <iomanip>

#include <catch2/catch.hpp>

#include "models/units.h"
#include "solvers/finite_difference.h"

namespace rubcont {
namespace {

// Case A(a) of the thesis (disk at centre, RCI 100/100), centre damper included.
TwoPointParams CaseAa() { return ThesisCaseAa(); }

// Compares the analytic Jacobian and ∂F/∂ω with central differences. `tolerance` applies to
// entries relative to max(|J_ij|, floor × max_j |J_ij|).
void CheckProblemJacobians(RotatingWaveProblem& problem, const Vector& u, double omega,
                           double tolerance, double floor) {
  Matrix J;
  problem.Jacobian(u, omega, J);
  const Vector typical = problem.Scale();
  auto residual = [&](const Vector& x, Vector& F) { problem.Residual(x, omega, F); };
  const JacobianCheck check = CheckJacobian(residual, u, J, tolerance, &typical, floor);
  INFO(problem.PieceLabel() << ": error " << check.max_error << " worst (" << check.worst_row << ", " << check.worst_col
                            << ") analytic " << std::setprecision(12) << check.analytic_value << " fd "
                            << check.difference_value);
  CHECK(check.ok);
  Vector dF, F_plus, F_minus;
  problem.DfDlambda(u, omega, dF);
  const double h = 1e-6 * omega;
  problem.Residual(u, omega + h, F_plus);
  problem.Residual(u, omega - h, F_minus);
  const Vector fd = (F_plus - F_minus) / (2 * h);
  CHECK((dF - fd).cwiseQuotient(problem.ResidualScale()).lpNorm<Eigen::Infinity>() <= 1e-7);
}

// The formulas do not depend on the contact stiffness, but difference quotients do: with the
// thesis's k1 = 1.75e11 N/m a contact row holds entries ~1e11 beside entries ~1e5, and central
// differences resolve an entry only to ~1e-11 of its row's largest. So the Jacobians are checked
// tightly (1e-7) with a softer contact (k1 = 1e8 N/m), and at the thesis's stiffness against
// max(|J_ij|, 1e-5 × row max) to 1e-5.
TEST_CASE("rotating-wave Jacobians match finite differences in every contact mode",
          "[rotating_wave]") {
  const bool thesis_stiffness = GENERATE(false, true);
  const double tolerance = thesis_stiffness ? 1e-5 : 1e-7;
  const double floor = thesis_stiffness ? 1e-5 : 1e-8;
  TwoPointParams params = CaseAa();
  if (!thesis_stiffness) {
    params.contact_stiffness = 1e8;
    params.contact_damping = 1e2;
  }
  params.rotor_mass_center = 0.22;  // asymmetric rotor: contacts differ
  params.rotor_inertia = 0.04;
  params.friction_law.velocity_scale = 0.02;
  const RubStructure s = TwoPointStructure(params);
  const RigidContactOrbit orbit = SolveRigidContactOrbit(s, kTwoPi * 70.0, {1.0, std::polar(1.0, 0.2)});
  // Push the contacts slightly into the stator so that they touch.
  auto touching = [&](RotatingWaveProblem& problem) {
    Vector u = problem.FromRigidContactOrbit(orbit);
    // Penetration (relative to |d|) well above the difference step (6e-6 of the largest |p|).
    const double scale = thesis_stiffness ? 1e-4 : 1e-2;
    u.head(2) += 2.0 * scale * (u.head(2) - u.segment<2>(4));
    u.segment<2>(2) += scale * (u.segment<2>(2) - u.segment<2>(6));
    return u;
  };
  const double omega = kTwoPi * 0.8;
  SECTION("regularized friction") {
    RotatingWaveProblem problem(s, FrictionLawKind::kTanh);
    CheckProblemJacobians(problem, touching(problem), omega, tolerance, floor);
  }
  SECTION("exact friction, all mode pairs") {
    RotatingWaveProblem problem(s, FrictionLawKind::kExact);
    for (ContactMode left : {ContactMode::kStick, ContactMode::kSlipPositive,
                             ContactMode::kSlipNegative, ContactMode::kFree}) {
      for (ContactMode right : {ContactMode::kStick, ContactMode::kSlipPositive}) {
        problem.SetModes({left, right});
        CheckProblemJacobians(problem, touching(problem), omega, tolerance, floor);
      }
    }
  }
}

TEST_CASE("whirl from the analytic Mode 1 start: rolling at both contacts, μ_req as in closed form",
          "[rotating_wave]") {
  const TwoPointParams params = CaseAa();
  const RubStructure s = TwoPointStructure(params);
  RotatingWaveProblem problem(s, FrictionLawKind::kExact);
  const double precession = HzToRadPerSecond(60.0);
  const double rci = params.Rci(0);
  const double omega = precession / rci;  // rolling speed for rigid contacts
  Vector u = problem.FromRigidContactOrbit(SolveRigidContactOrbit(s, precession, {1.0, 1.0}));
  const auto start = problem.SolveConsistent(u, omega);
  INFO(start.newton.BriefReport() << ", " << problem.PieceLabel());
  REQUIRE(start.newton.Converged());
  REQUIRE(start.consistent);
  CHECK(problem.modes()[0] == ContactMode::kStick);
  CHECK(problem.modes()[1] == ContactMode::kStick);
  const auto contacts = problem.EvaluateContacts(u, omega);
  const double W = problem.Precession(u);
  for (const ContactEvaluation& e : contacts) {
    CHECK(e.touching);
    // Rolling: Ω = ωR/|d| exactly, |d| = C + δ.
    CHECK(W == Approx(omega * params.radius[0] / (params.clearance[0] + e.penetration))
                   .epsilon(1e-12));
    // Penetration is tiny against the clearance.
    CHECK(e.penetration > 0.0);
    CHECK(e.penetration < 1e-4 * params.clearance[0]);
  }
  // The friction needed equals the closed form's μ_req at the computed Ω (with the centre damper):
  // compliance scales both contact displacements alike, so F/N is unchanged for a symmetric rotor.
  const RigidContactOrbit closed = SolveRigidContactOrbit(s, W, {1.0, 1.0});
  const double mu_closed = closed.force[0].imag() / closed.force[0].real();
  const Vector measures = problem.Measures(u, omega);
  const auto names = problem.MeasureNames();
  const auto at = [&](const std::string& name) {
    return measures(std::find(names.begin(), names.end(), name) - names.begin());
  };
  // The phase between the contacts is fixed only through compliance (see the phase-drift test
  // below): the scaled Jacobian's smallest singular value is ~1e-3, so round-off in the residual
  // (~1e-12) leaves θ uncertain to ~1e-9 rad and each contact's F/N to ~1e-7 relative.
  CHECK(at("mu_ratio_left") == Approx(mu_closed).epsilon(1e-6));
  CHECK(at("mu_ratio_right") == Approx(mu_closed).epsilon(1e-6));
  CHECK(at("normal_phase_deg") == Approx(0.0).epsilon(0).margin(1e-7));
  INFO("whirl at " << RadPerSecondToRpm(omega) << " rpm, Ω = " << RadPerSecondToHz(W)
                   << " Hz, μ_req = " << mu_closed);
}

TEST_CASE("whip: slipping at both contacts precesses where μ_req = μ", "[rotating_wave]") {
  const TwoPointParams params = CaseAa();
  const RubStructure s = TwoPointStructure(params);
  RotatingWaveProblem problem(s, FrictionLawKind::kExact);
  problem.SetModes({ContactMode::kSlipPositive, ContactMode::kSlipPositive});
  // Start from the analytic Mode 1 orbit at 86 Hz, where rolling would need μ_req > 0.5.
  const double omega = RpmToRadPerSecond(70.0);  // 70 rpm: slip velocity ωR − ΩC > 0
  Vector u = problem.FromRigidContactOrbit(SolveRigidContactOrbit(s, kTwoPi * 86.0, {1.0, 1.0}));
  const auto start = problem.SolveConsistent(u, omega);
  INFO(start.newton.BriefReport());
  REQUIRE(start.consistent);
  CHECK(start.mode_changes == 0);
  // Whip precesses where the closed form (with the centre damper) has μ_req = μ: 84.478 Hz.
  const double W = problem.Precession(u);
  const RigidContactOrbit closed = SolveRigidContactOrbit(s, W, {1.0, 1.0});
  CHECK(closed.force[0].imag() / closed.force[0].real() == Approx(params.friction).epsilon(1e-8));
  CHECK(RadPerSecondToHz(W) == Approx(84.478).epsilon(2e-5));
  for (const ContactEvaluation& e : problem.EvaluateContacts(u, omega)) {
    CHECK(e.slip_velocity > 0.0);
    CHECK(e.friction_force == Approx(params.friction * e.normal_force).epsilon(1e-12));
  }
}

TEST_CASE("an inconsistent start is repaired by switching contact modes", "[rotating_wave]") {
  // With μ = 0.4, rolling at 84 Hz (μ_req ≈ 0.47) is impossible: the start in stick must switch
  // both contacts to slip and land where μ_req = 0.4.
  TwoPointParams params = CaseAa();
  params.friction = 0.4;
  const RubStructure s = TwoPointStructure(params);
  RotatingWaveProblem problem(s, FrictionLawKind::kExact);
  const double precession = kTwoPi * 84.0;
  const double omega = precession / params.Rci(0);
  Vector u = problem.FromRigidContactOrbit(SolveRigidContactOrbit(s, precession, {1.0, 1.0}));
  const auto start = problem.SolveConsistent(u, omega);
  INFO(start.newton.BriefReport() << ", " << problem.PieceLabel());
  REQUIRE(start.consistent);
  CHECK(start.mode_changes == 2);
  CHECK(problem.modes()[0] == ContactMode::kSlipPositive);
  CHECK(problem.modes()[1] == ContactMode::kSlipPositive);
  const RigidContactOrbit closed = SolveRigidContactOrbit(s, problem.Precession(u), {1.0, 1.0});
  CHECK(closed.force[0].imag() / closed.force[0].real() == Approx(0.4).epsilon(1e-8));
}

TEST_CASE("rotating-wave stability: exact stick is the ε → 0 limit of tanh, with the symmetry deflated",
          "[rotating_wave]") {
  TwoPointParams params = CaseAa();
  const RubStructure s = TwoPointStructure(params);
  const double precession = HzToRadPerSecond(60.0);
  const double omega = precession / params.Rci(0);
  RotatingWaveProblem exact(s, FrictionLawKind::kExact);
  Vector u = exact.FromRigidContactOrbit(SolveRigidContactOrbit(s, precession, {1.0, 1.0}));
  REQUIRE(exact.SolveConsistent(u, omega).consistent);
  const Spectrum exact_spectrum = exact.Stability(u, omega);
  REQUIRE(exact_spectrum.valid);
  CHECK(exact_spectrum.values.size() == 16 - 2 - 1);  // two rolling constraints, one symmetry

  // Regularized friction, ε = 1e-6 m/s: the same whirl with V ≈ ε atanh(F/μN) at both contacts.
  params.friction_law.velocity_scale = 1e-6;
  RubStructure s_tanh = TwoPointStructure(params);
  RotatingWaveProblem tanh_problem(s_tanh, FrictionLawKind::kTanh);
  Vector v = tanh_problem.FromRigidContactOrbit(SolveRigidContactOrbit(s_tanh, precession, {1.0, 1.0}));
  REQUIRE(tanh_problem.SolveConsistent(v, omega).newton.Converged());
  REQUIRE(tanh_problem.Precession(v) == Approx(exact.Precession(u)).epsilon(1e-5));
  const Spectrum tanh_spectrum = tanh_problem.Stability(v, omega);
  REQUIRE(tanh_spectrum.valid);
  REQUIRE(tanh_spectrum.values.size() == 15);
  // Each constrained eigenvalue has a regularized counterpart within O(ε); the regularized
  // problem has two more, strongly damped tangential modes (Re ≈ −μN/(ε m) < −1e7 s⁻¹).
  for (Index i = 0; i < exact_spectrum.values.size(); ++i) {
    double nearest = kInfinity;
    for (Index j = 0; j < tanh_spectrum.values.size(); ++j) {
      nearest = std::min(nearest, std::abs(tanh_spectrum.values(j) - exact_spectrum.values(i)));
    }
    INFO("exact eigenvalue " << exact_spectrum.values(i));
    CHECK(nearest <= 1e-2 + 1e-6 * std::abs(exact_spectrum.values(i)));
  }
  CHECK(tanh_spectrum.values.real().minCoeff() < -1e7);
}

TEST_CASE("rolling at two contacts: the phase drift between them is set by contact compliance",
          "[rotating_wave]") {
  // With rigid contacts rolling at both planes leaves the phase θ = arg n_R − arg n_L between
  // the contact normals free; compliance makes contact k roll on the radius C + N_k/k1, so it
  // precesses at Ω_k = ωR/(C + N_k/k1), and θ drifts at dθ/dt = −(Ω_R − Ω_L) ≈ Ω(N_R − N_L)/(k1 C):
  // the spectrum holds the real eigenvalue Ω ∂(N_R − N_L)/∂θ / (k1 C). Check it against the
  // closed form's ∂N/∂θ. (For A(a) at 60 Hz it is +4.3e-5 s⁻¹: unstable with an e-folding time
  // of hours — marginal for any practical purpose.)
  const TwoPointParams params = CaseAa();
  const RubStructure s = TwoPointStructure(params);
  const double precession = HzToRadPerSecond(60.0);
  const double omega = precession / params.Rci(0);
  RotatingWaveProblem exact(s, FrictionLawKind::kExact);
  Vector u = exact.FromRigidContactOrbit(SolveRigidContactOrbit(s, precession, {1.0, 1.0}));
  REQUIRE(exact.SolveConsistent(u, omega).consistent);
  const double W = exact.Precession(u);
  const double h = 1e-4;
  const RigidContactOrbit plus = SolveRigidContactOrbit(s, W, {1.0, std::polar(1.0, h)});
  const RigidContactOrbit minus = SolveRigidContactOrbit(s, W, {1.0, std::polar(1.0, -h)});
  const double dDeltaN = ((plus.force[1].real() - plus.force[0].real()) -
                          (minus.force[1].real() - minus.force[0].real())) / (2 * h);
  const double predicted = W * dDeltaN / (params.contact_stiffness * params.clearance[0]);
  const Spectrum spectrum = exact.Stability(u, omega);
  double nearest = kInfinity;
  for (Index i = 0; i < spectrum.values.size(); ++i) {
    nearest = std::min(nearest, std::abs(spectrum.values(i) - predicted));
  }
  INFO("predicted drift eigenvalue " << predicted);
  CHECK(std::abs(predicted) < 1e-3);
  CHECK(nearest <= 1e-3 * std::abs(predicted));
}

}  // namespace
}  // namespace rubcont
