#include "models/analytic.h"
#include "models/units.h"

#include <cmath>
#include <complex>
#include <set>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

using Complex = std::complex<double>;

// Thesis data, disk at centre (Eq. 31, Table 1 case A): the TwoPointParams defaults.
TwoPointParams DiskAtCenter(double center_damping = 0.0) {
  TwoPointParams p = ThesisCaseAa();
  p.center_damping = center_damping;
  return p;
}

TwoPointParams DiskAtThreeQuarters() {
  TwoPointParams p = DiskAtCenter();
  p.rotor_mass_center = 0.22;
  p.rotor_inertia = 0.04;
  return p;
}

TwoPointParams TrulyOverhung() {  // a = 0.35 / 0.29 > 1, unequal clearances, damper on
  TwoPointParams p = DiskAtCenter(52.0);
  p.rotor_mass_center = 0.35;
  p.rotor_inertia = 0.07;
  p.clearance = {3.81e-4, 3.048e-4};
  return p;
}

std::vector<Transition> OfType(const AnalyticCurve& curve, TransitionType type, int contact) {
  std::vector<Transition> out;
  for (const Transition& t : curve.transitions)
    if (t.type == type && t.contact == contact) out.push_back(t);
  return out;
}

// The matrices written out again from docs/theory.md §2, independently of the library's helpers.
Eigen::Matrix2d MassMatrix(double m, double I, double span, double c) {
  Eigen::Matrix2d M;
  M << m * (1 - c) * (1 - c) + I / (span * span), m * c * (1 - c) - I / (span * span),
       m * c * (1 - c) - I / (span * span), m * c * c + I / (span * span);
  return M;
}

TEST_CASE("Natural frequencies match the thesis (§2.3) within 0.5 %", "[analytic]") {
  const NaturalFrequencies nf = ComputeNaturalFrequencies(DiskAtCenter());
  CHECK_THAT(nf.stator_bounce.frequency_hz, Catch::Matchers::WithinRel(105.3, 0.005));
  CHECK_THAT(nf.stator_pitch.frequency_hz, Catch::Matchers::WithinRel(144.9, 0.005));
  CHECK_THAT(nf.pinned_bounce.frequency_hz, Catch::Matchers::WithinRel(87.03, 0.005));
}

TEST_CASE("Natural frequencies of a symmetric system equal their closed forms", "[analytic]") {
  // Symmetric stator (b = ½) and rotor (a = ½), k_L = k_R = k: bounce ω² = 2k / m (v = (1, 1)),
  // pitch ω² = k / (2 Σ I/l²) (v = (1, −1)).
  const TwoPointParams p = DiskAtCenter();
  const double k = p.support_stiffness[0];
  const NaturalFrequencies nf = ComputeNaturalFrequencies(p);
  auto hz = [](double omega_squared) { return RadPerSecondToHz(std::sqrt(omega_squared)); };
  CHECK_THAT(nf.stator_bounce.frequency_hz, Catch::Matchers::WithinRel(hz(2 * k / p.stator_mass), 1e-12));
  CHECK_THAT(nf.stator_pitch.frequency_hz,
             Catch::Matchers::WithinRel(hz(k * p.stator_span * p.stator_span / (2 * p.stator_inertia)), 1e-12));
  CHECK_THAT(nf.pinned_bounce.frequency_hz,
             Catch::Matchers::WithinRel(hz(2 * k / (p.stator_mass + p.rotor_mass)), 1e-12));
  const double pitch_inertia = p.stator_inertia / (p.stator_span * p.stator_span) +
                               p.rotor_inertia / (p.contact_span * p.contact_span);
  CHECK_THAT(nf.pinned_pitch.frequency_hz, Catch::Matchers::WithinRel(hz(k / (2 * pitch_inertia)), 1e-12));
  CHECK(nf.stator_bounce.shape(0) == Approx(1.0));
  CHECK(nf.stator_bounce.shape(1) == Approx(1.0));
  CHECK(nf.stator_pitch.shape(0) * nf.stator_pitch.shape(1) == Approx(-1.0));
}

TEST_CASE("Bounce and pitch are told apart by mode shape, not by ordering", "[analytic]") {
  // A rotor so heavy in pitch that the pinned pitch mode drops below the pinned bounce mode.
  TwoPointParams p = DiskAtCenter();
  p.rotor_inertia = 2.0;
  const NaturalFrequencies nf = ComputeNaturalFrequencies(p);
  CHECK(nf.pinned_pitch.frequency_hz < nf.pinned_bounce.frequency_hz);
  CHECK(nf.pinned_bounce.shape(0) * nf.pinned_bounce.shape(1) > 0.0);
  CHECK(nf.pinned_pitch.shape(0) * nf.pinned_pitch.shape(1) < 0.0);
  // Each frequency is a root of det(K − ω² (M_r + M_s)).
  const Eigen::Matrix2d M = MassMatrix(p.rotor_mass, p.rotor_inertia, p.contact_span, p.a()) +
                            MassMatrix(p.stator_mass, p.stator_inertia, p.stator_span, p.b());
  const Eigen::Matrix2d K = Eigen::Vector2d(p.support_stiffness[0], p.support_stiffness[1]).asDiagonal();
  for (double hz : {nf.pinned_bounce.frequency_hz, nf.pinned_pitch.frequency_hz}) {
    const double w2 = std::pow(kTwoPi * hz, 2);
    CHECK(std::abs((K - w2 * M).determinant()) < 1e-9 * K.determinant());
  }
}

TEST_CASE("Mode 1, disk at centre, thesis form: μ_req = 0.5 at 84.5 and 109.4 Hz, contact lost "
          "between about 87.3 and 105 Hz (thesis §2.3.1)", "[analytic]") {
  const AnalyticCurve curve = ComputeAnalyticCurve(DiskAtCenter(), CircularMode::kMode1);
  REQUIRE(curve.Succeeded());
  for (int k = 0; k < 2; ++k) {
    const auto mu = OfType(curve, TransitionType::kMuCrossing, k);
    REQUIRE(mu.size() == 2);
    CHECK(mu[0].precession_hz == Approx(84.5).epsilon(0).margin(0.1));
    CHECK(mu[0].direction == 1);  // whirl → whip as Ω rises
    CHECK(mu[1].precession_hz == Approx(109.4).epsilon(0).margin(0.1));
    CHECK(mu[1].direction == -1);  // whip → whirl
    const auto loss = OfType(curve, TransitionType::kContactLoss, k);
    const auto regain = OfType(curve, TransitionType::kContactRegain, k);
    REQUIRE(loss.size() == 1);
    REQUIRE(regain.size() == 1);
    CHECK(loss[0].precession_hz == Approx(87.3).epsilon(0).margin(0.1));
    CHECK(regain[0].precession_hz == Approx(105.0).epsilon(0).margin(0.2));
    CHECK_FALSE(loss[0].through_pole);
    // On the grid: N ≤ 0 exactly inside the band, N > 0 outside.
    for (Index i = 0; i < curve.precession_hz.size(); ++i) {
      const double hz = curve.precession_hz(i);
      const bool inside = hz > loss[0].precession_hz && hz < regain[0].precession_hz;
      CHECK((curve.normal_force[k](i) <= 0.0) == inside);
    }
  }
}

TEST_CASE("Transitions are located to machine precision", "[analytic]") {
  std::set<TransitionType> seen;
  for (const TwoPointParams& p : {DiskAtCenter(52.0), DiskAtThreeQuarters(), TrulyOverhung()}) {
    for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
      const AnalyticCurve curve = ComputeAnalyticCurve(p, mode);
      REQUIRE_FALSE(curve.transitions.empty());
      for (const Transition& t : curve.transitions) seen.insert(t.type);
      for (const Transition& t : curve.transitions) {
        // The crossing quantity changes sign within ±1e-13 relative of the located frequency.
        auto quantity = [&](double hz) {
          const ComplexVector2 P = SolveCircularOrbit(p, mode, kTwoPi * hz).contact_force;
          const double N = P(t.contact).real(), F = P(t.contact).imag();
          switch (t.type) {
            case TransitionType::kMuCrossing: return F - p.friction * N;
            case TransitionType::kNegativeMuCrossing: return F + p.friction * N;
            case TransitionType::kZeroMuCrossing: return F;
            default: return N;
          }
        };
        const double below = quantity(t.precession_hz * (1 - 1e-13));
        const double above = quantity(t.precession_hz * (1 + 1e-13));
        INFO(ToString(mode) << " " << ToString(t.type) << " contact " << t.contact << " at "
                            << t.precession_hz << " Hz");
        CHECK(below * above < 0.0);
        CHECK((above > 0.0 ? 1 : -1) == t.direction);
        if (t.type != TransitionType::kContactLoss && t.type != TransitionType::kContactRegain)
          CHECK(t.normal_force > 0.0);  // μ crossings count only in contact
      }
    }
  }
  CHECK(seen.size() == 5);  // every kind of transition was exercised
}

TEST_CASE("The centre damper: only friction changes, by s_k Ω c_d (wᵀd0) / 2", "[analytic]") {
  for (const TwoPointParams& base : {DiskAtCenter(), TrulyOverhung()}) {
    TwoPointParams with = base, without = base;
    with.center_damping = 52.0;
    without.center_damping = 0.0;
    for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
      const int s = ContactSign(mode);
      const double midpoint = 0.5 * (base.clearance[0] + s * base.clearance[1]);  // wᵀ d0
      for (double hz : {2.0, 60.0, 95.0, 150.0}) {
        const double omega = kTwoPi * hz;
        const ComplexVector2 P1 = SolveCircularOrbit(with, mode, omega).contact_force;
        const ComplexVector2 P0 = SolveCircularOrbit(without, mode, omega).contact_force;
        for (int k = 0; k < 2; ++k) {
          const double sign_k = k == 0 ? 1.0 : s;
          CHECK(P1(k).real() == Approx(P0(k).real()).epsilon(1e-12));
          CHECK(P1(k).imag() - P0(k).imag() ==
                Approx(sign_k * omega * 52.0 * midpoint / 2).epsilon(1e-9).margin(1e-9 * std::abs(P0(k))));
        }
      }
    }
  }
}

TEST_CASE("Mode 1, disk at centre, with the 52 N·s/m centre damper", "[analytic]") {
  const AnalyticCurve with = ComputeAnalyticCurve(DiskAtCenter(52.0), CircularMode::kMode1);
  const AnalyticCurve without = ComputeAnalyticCurve(DiskAtCenter(0.0), CircularMode::kMode1);
  const auto mu = OfType(with, TransitionType::kMuCrossing, 0);
  REQUIRE(mu.size() == 3);
  // A low-frequency crossing appears: at very slow whirl the damper force needs friction to
  // sustain it (μ_req ~ c_d / (m Ω) → ∞ as Ω → 0), so μ_req falls through μ there.
  CHECK(mu[0].precession_hz < 5.0);
  CHECK(mu[0].direction == -1);
  CHECK(with.mu_required[0](0) > 0.5);
  CHECK(without.mu_required[0](0) < 0.5);
  // The damper needs more friction: the whip band widens on both sides.
  const auto mu0 = OfType(without, TransitionType::kMuCrossing, 0);
  CHECK(mu[1].precession_hz < mu0[0].precession_hz);
  CHECK(mu[2].precession_hz > mu0[1].precession_hz);
  // Contact loss does not move (N is unchanged).
  CHECK(OfType(with, TransitionType::kContactLoss, 0)[0].precession_hz ==
        OfType(without, TransitionType::kContactLoss, 0)[0].precession_hz);
}

TEST_CASE("A symmetric rotor has equal forces at both contacts, and its Mode 1 excites no pitch",
          "[analytic]") {
  const TwoPointParams p = DiskAtCenter(52.0);
  for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
    const AnalyticCurve curve = ComputeAnalyticCurve(p, mode);
    for (Index i = 0; i < curve.precession_hz.size(); ++i) {
      CHECK(curve.normal_force[0](i) == Approx(curve.normal_force[1](i)).epsilon(1e-9).margin(1e-9));
      CHECK(curve.friction_force[0](i) == Approx(curve.friction_force[1](i)).epsilon(1e-9).margin(1e-9));
    }
  }
  for (double hz : {10.0, 84.0, 120.0}) {
    const CircularOrbit orbit = SolveCircularOrbit(p, CircularMode::kMode1, kTwoPi * hz);
    CHECK(std::abs(orbit.rotor_amplitude(0) - orbit.rotor_amplitude(1)) <= 1e-12 * std::abs(orbit.rotor_amplitude(0)));
    CHECK(std::abs(orbit.stator_amplitude(0) - orbit.stator_amplitude(1)) <= 1e-12 * std::abs(orbit.stator_amplitude(0)));
    // Mode 2 of the symmetric rotor is pure pitch: the ends move in antiphase.
    const CircularOrbit pitch = SolveCircularOrbit(p, CircularMode::kMode2, kTwoPi * hz);
    CHECK(std::abs(pitch.rotor_amplitude(0) + pitch.rotor_amplitude(1)) <= 1e-12 * std::abs(pitch.rotor_amplitude(0)));
  }
}

TEST_CASE("The centre damper term vanishes in Mode 2 of a symmetric rotor", "[analytic]") {
  const AnalyticCurve with = ComputeAnalyticCurve(DiskAtCenter(52.0), CircularMode::kMode2);
  const AnalyticCurve without = ComputeAnalyticCurve(DiskAtCenter(0.0), CircularMode::kMode2);
  for (int k = 0; k < 2; ++k) {
    CHECK(with.friction_force[k] == without.friction_force[k]);
    CHECK(with.normal_force[k] == without.normal_force[k]);
  }
  const CircularOrbit orbit = SolveCircularOrbit(DiskAtCenter(52.0), CircularMode::kMode2, kTwoPi * 50);
  CHECK(std::abs(orbit.damper_force(0)) == 0.0);
}

TEST_CASE("N > 0 below the first pinned frequency", "[analytic]") {
  for (const TwoPointParams& p : {DiskAtCenter(), DiskAtCenter(52.0), DiskAtThreeQuarters()}) {
    const NaturalFrequencies nf = ComputeNaturalFrequencies(p);
    const double first = std::min(nf.pinned_bounce.frequency_hz, nf.pinned_pitch.frequency_hz);
    const AnalyticCurve curve = ComputeAnalyticCurve(p, CircularMode::kMode1);
    for (Index i = 0; i < curve.precession_hz.size() && curve.precession_hz(i) < 0.99 * first; ++i) {
      CHECK(curve.normal_force[0](i) > 0.0);
      CHECK(curve.normal_force[1](i) > 0.0);
    }
  }
  // Mode 2 of the symmetric rotor (pure pitch): below the pinned pitch frequency.
  const TwoPointParams p = DiskAtCenter();
  const double pitch = ComputeNaturalFrequencies(p).pinned_pitch.frequency_hz;
  const AnalyticCurve curve = ComputeAnalyticCurve(p, CircularMode::kMode2);
  for (Index i = 0; i < curve.precession_hz.size() && curve.precession_hz(i) < 0.99 * pitch; ++i)
    CHECK(curve.normal_force[0](i) > 0.0);
}

TEST_CASE("r0 and s0 satisfy the rotor and stator equations of motion and r0 − s0 = S C",
          "[analytic]") {
  for (const TwoPointParams& p : {DiskAtCenter(52.0), DiskAtThreeQuarters(), TrulyOverhung()}) {
    const Eigen::Matrix2cd M_r =
        MassMatrix(p.rotor_mass, p.rotor_inertia, p.contact_span, p.rotor_mass_center / p.contact_span).cast<Complex>();
    const Eigen::Matrix2cd M_s =
        MassMatrix(p.stator_mass, p.stator_inertia, p.stator_span, p.stator_mass_center / p.stator_span).cast<Complex>();
    Eigen::Matrix2cd K = Eigen::Matrix2cd::Zero(), C = Eigen::Matrix2cd::Zero();
    K.diagonal() << p.support_stiffness[0], p.support_stiffness[1];
    C.diagonal() << p.support_damping[0], p.support_damping[1];
    for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
      const double s = ContactSign(mode);
      for (double hz : {3.0, 50.0, 86.0, 100.0, 130.0, 190.0}) {
        const double W = kTwoPi * hz;
        const Complex j(0, 1);
        const CircularOrbit o = SolveCircularOrbit(p, mode, W);
        // Contact force on the rotor, f_k = −P_k n_k with n = (1, s): −S P.
        const Eigen::Vector2cd f(-o.contact_force(0), -s * o.contact_force(1));
        // Damper on the rotor: −c_d w wᵀ (u̇_r − u̇_s), u̇ = −jΩ u.
        const Complex mid_velocity = 0.5 * (-j * W) * ((o.rotor_amplitude(0) - o.stator_amplitude(0)) +
                                                       (o.rotor_amplitude(1) - o.stator_amplitude(1)));
        const Eigen::Vector2cd f_d = Eigen::Vector2cd::Constant(-p.center_damping * 0.5 * mid_velocity);
        const Eigen::Vector2cd rotor = -W * W * M_r * o.rotor_amplitude - f - f_d;
        const Eigen::Vector2cd stator = (K - W * W * M_s - j * W * C) * o.stator_amplitude + f + f_d;
        const double scale = o.contact_force.norm();
        INFO(ToString(mode) << " at " << hz << " Hz, a = " << p.a());
        CHECK(rotor.norm() <= 1e-10 * scale);
        CHECK(stator.norm() <= 1e-10 * scale);
        CHECK(std::abs(o.rotor_amplitude(0) - o.stator_amplitude(0) - p.clearance[0]) <= 1e-12 * p.clearance[0]);
        CHECK(std::abs(o.rotor_amplitude(1) - o.stator_amplitude(1) - s * p.clearance[1]) <= 1e-12 * p.clearance[1]);
        CHECK(std::abs(o.damper_force(0) - f_d(0)) <= 1e-9 * (std::abs(f_d(0)) + 1e-12));
      }
    }
  }
}

TEST_CASE("Undamped supports: contact is lost through the pinned pole and regained at the "
          "stator frequency, with no friction", "[analytic]") {
  TwoPointParams p = DiskAtCenter();
  p.support_damping = {0.0, 0.0};
  const NaturalFrequencies nf = ComputeNaturalFrequencies(p);
  const AnalyticCurve curve = ComputeAnalyticCurve(p, CircularMode::kMode1);
  const auto loss = OfType(curve, TransitionType::kContactLoss, 0);
  const auto regain = OfType(curve, TransitionType::kContactRegain, 0);
  REQUIRE(loss.size() == 1);
  REQUIRE(regain.size() == 1);
  CHECK(loss[0].through_pole);
  CHECK(loss[0].precession_hz == Approx(nf.pinned_bounce.frequency_hz).epsilon(1e-9));
  CHECK_FALSE(regain[0].through_pole);
  CHECK(regain[0].precession_hz == Approx(nf.stator_bounce.frequency_hz).epsilon(1e-9));
  CHECK(OfType(curve, TransitionType::kMuCrossing, 0).empty());
  CHECK(curve.friction_force[0].cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("An overhung disk (a > 1) and unequal clearances give finite, distinct contacts",
          "[analytic]") {
  const TwoPointParams p = TrulyOverhung();
  REQUIRE(p.a() > 1.0);
  const AnalyticResult result = ComputeAnalytic(p);
  REQUIRE(result.Succeeded());
  CHECK(result.mode1.normal_force[0].allFinite());
  CHECK((result.mode1.normal_force[0] - result.mode1.normal_force[1]).cwiseAbs().maxCoeff() > 1.0);
}

TEST_CASE("Caller mistakes throw std::invalid_argument naming the value and the rule", "[analytic]") {
  TwoPointParams p = DiskAtCenter();
  CHECK_THROWS_WITH(SolveCircularOrbit(p, CircularMode::kMode1, 0.0),
                    Catch::Matchers::Contains("precession = 0"));
  p.rotor_mass = -1.0;
  CHECK_THROWS_WITH(ComputeAnalyticCurve(p, CircularMode::kMode1),
                    Catch::Matchers::Contains("rotor_mass = -1: must be positive"));
  AnalyticOptions options;
  options.max_precession_hz = 0.5;
  CHECK_THROWS_AS(ComputeAnalyticCurve(DiskAtCenter(), CircularMode::kMode1, options),
                  std::invalid_argument);
}

}  // namespace
}  // namespace rubcont
