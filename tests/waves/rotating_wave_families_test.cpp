#include "waves/rotating_wave_families.h"

#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/jeffcott.h"
#include "models/units.h"

namespace rubcont {
namespace {

double PrecessionHz(const RotatingWaveProblem& problem, const RotatingWaveStart& start) {
  return RadPerSecondToHz(problem.Precession(start.u));
}

FamilySearchOptions ThesisFamilySearch() {
  FamilySearchOptions options;
  options.speed_min = RpmToRadPerSecond(20.0);
  options.speed_max = RpmToRadPerSecond(260.0);
  options.precession_max = kTwoPi * 200.0;
  return options;
}

TEST_CASE("families of case A(a): Mode 1 and Mode 2 whirl, whip at every μ_req = μ crossing",
          "[families]") {
  const TwoPointParams params = ThesisCaseAa();
  RotatingWaveProblem problem(TwoPointStructure(params), FrictionLawKind::kExact);
  const auto starts = FindRotatingWaveStarts(problem, ThesisFamilySearch());
  auto count = [&](ContactMode mode, double normal_sign) {
    return std::count_if(starts.begin(), starts.end(), [&](const RotatingWaveStart& s) {
      return s.modes[0] == mode && s.modes[1] == mode && s.normals[1] == normal_sign;
    });
  };
  CHECK(count(ContactMode::kStick, +1.0) >= 1);  // Mode 1 whirl
  CHECK(count(ContactMode::kStick, -1.0) >= 1);  // Mode 2 whirl
  // Every μ crossing of the closed form (with N > 0 at both contacts) has a whip start at the
  // same precession (compliance changes it by ~δ/C).
  const AnalyticResult analytic = ComputeAnalytic(params, {1.0, 200.0, 4000});
  for (const AnalyticCurve* curve : {&analytic.mode1, &analytic.mode2}) {
    for (const Transition& t : curve->transitions) {
      if (t.type != TransitionType::kMuCrossing || t.contact != 0) continue;
      const double sign = curve->mode == CircularMode::kMode1 ? 1.0 : -1.0;
      const bool found = std::any_of(starts.begin(), starts.end(), [&](const RotatingWaveStart& s) {
        return s.modes[0] == ContactMode::kSlipPositive && s.normals[1] == sign &&
               std::abs(PrecessionHz(problem, s) - t.precession_hz) < 1e-4 * t.precession_hz;
      });
      INFO(ToString(curve->mode) << " μ crossing at " << t.precession_hz << " Hz");
      CHECK(found);
    }
  }
  // Rolling starts roll: Ω = ωR/(C + δ).
  for (const RotatingWaveStart& s : starts) {
    if (s.modes[0] != ContactMode::kStick) continue;
    problem.SetModes(s.modes);
    const auto contacts = problem.EvaluateContacts(s.u, s.speed);
    CHECK(std::abs(contacts[0].slip_velocity) < 1e-9);
  }
}

TEST_CASE("families of the Jeffcott rotor: whirl below the μ crossing, whip at it", "[families]") {
  const JeffcottParams params;
  RotatingWaveProblem problem(JeffcottStructure(params), FrictionLawKind::kExact);
  FamilySearchOptions options;
  options.speed_min = RpmToRadPerSecond(5.0);
  options.speed_max = RpmToRadPerSecond(100.0);
  options.precession_max = kTwoPi * 100.0;
  const auto starts = FindRotatingWaveStarts(problem, options);
  // Black's U-shaped curve: between the rotor and the combined frequency μ_req dips below μ; the
  // whirl → whip crossing is where it rises through μ again (bisection on the closed form).
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(params);
  auto excess = [&](double W) {
    const auto P = JeffcottContactForce(params, W);
    return P.imag() / P.real() - params.friction;
  };
  double lo = 0.0, hi = 0.0;
  const double a = kTwoPi * f.rotor_hz * 1.001, b = kTwoPi * f.combined_hz * 0.999;
  for (int i = 0; i < 1000; ++i) {
    const double W0 = a + (b - a) * i / 1000.0, W1 = a + (b - a) * (i + 1) / 1000.0;
    if (excess(W0) < 0.0 && excess(W1) > 0.0) {
      lo = W0;
      hi = W1;
    }
  }
  REQUIRE(hi > 0.0);
  for (int i = 0; i < 200; ++i) (excess(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
  const double crossing_hz = RadPerSecondToHz(0.5 * (lo + hi));
  const bool whip = std::any_of(starts.begin(), starts.end(), [&](const RotatingWaveStart& s) {
    return s.modes[0] == ContactMode::kSlipPositive &&
           std::abs(PrecessionHz(problem, s) - crossing_hz) < 1e-6 * crossing_hz;
  });
  const bool whirl = std::any_of(starts.begin(), starts.end(), [&](const RotatingWaveStart& s) {
    return s.modes[0] == ContactMode::kStick;
  });
  INFO("closed-form crossing " << crossing_hz << " Hz");
  CHECK(whip);
  CHECK(whirl);
}

TEST_CASE("family search rejects an inverted speed range", "[families]") {
  RotatingWaveProblem problem(TwoPointStructure(ThesisCaseAa()), FrictionLawKind::kExact);
  FamilySearchOptions options = ThesisFamilySearch();
  std::swap(options.speed_min, options.speed_max);
  CHECK_THROWS_WITH(FindRotatingWaveStarts(problem, options), Catch::Contains("speed range"));
}

}  // namespace
}  // namespace rubcont
