#include "models/jeffcott.h"
#include "models/units.h"

#include <cmath>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

TEST_CASE("Jeffcott closed form equals the general circular-orbit solve", "[jeffcott]") {
  const JeffcottParams params;
  const RubStructure s = JeffcottStructure(params);
  for (double hz : {20.0, 55.0, 65.0, 90.0, 140.0}) {
    const std::complex<double> closed = JeffcottContactForce(params, kTwoPi * hz);
    const RigidContactOrbit orbit = SolveRigidContactOrbit(s, kTwoPi * hz, {1.0});
    CHECK(std::abs(orbit.force[0] - closed) <= 1e-10 * std::abs(closed));
  }
}

TEST_CASE("Jeffcott: contact only between the rotor and the combined natural frequencies",
          "[jeffcott]") {
  // Black (1968): with light damping, N > 0 only for ω_r < Ω < ω_c (rotor alone, then pinned).
  const JeffcottParams params;
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(params);
  REQUIRE(f.rotor_hz < f.combined_hz);
  REQUIRE(f.combined_hz < f.stator_hz);
  CHECK(JeffcottContactForce(params, kTwoPi * 0.9 * f.rotor_hz).real() < 0.0);
  CHECK(JeffcottContactForce(params, kTwoPi * 0.5 * (f.rotor_hz + f.combined_hz)).real() > 0.0);
  CHECK(JeffcottContactForce(params, kTwoPi * 0.5 * (f.combined_hz + f.stator_hz)).real() < 0.0);
  // Undamped: F = 0 (no friction needed to sustain rolling without dissipation).
  JeffcottParams undamped = params;
  undamped.c_r = 0.0;
  undamped.c_s = 0.0;
  CHECK(JeffcottContactForce(undamped, HzToRadPerSecond(60.0)).imag() == 0.0);
  // Damped: rolling backward whirl needs a positive friction force.
  CHECK(JeffcottContactForce(params, HzToRadPerSecond(60.0)).imag() > 0.0);
}

TEST_CASE("Jeffcott curve: transitions are roots of the closed form", "[jeffcott]") {
  const JeffcottParams params;
  const AnalyticCurve curve = ComputeJeffcottCurve(params, {1.0, 150.0, 3000});
  REQUIRE(curve.Succeeded());
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(params);
  CHECK(curve.normal_force[1].size() == 0);
  int mu_crossings = 0, contact_changes = 0;
  for (const Transition& t : curve.transitions) {
    const std::complex<double> P = JeffcottContactForce(params, kTwoPi * t.precession_hz);
    if (t.type == TransitionType::kMuCrossing) {
      if (t.precession_hz > f.rotor_hz && t.precession_hz < f.combined_hz) ++mu_crossings;
      CHECK(P.imag() / P.real() == Approx(params.friction).epsilon(1e-10));
    }
    if (t.type == TransitionType::kContactLoss || t.type == TransitionType::kContactRegain) {
      ++contact_changes;
      CHECK(std::abs(P.real()) <= 1e-9 * std::abs(P));
    }
  }
  // Black's U: contact from the rotor to the combined frequency with μ_req dipping below μ
  // inside (and contact again above the stator frequency).
  CHECK(contact_changes >= 2);
  CHECK(mu_crossings == 2);
}

}  // namespace
}  // namespace rubcont
