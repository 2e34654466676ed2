// The forced van der Pol oscillator (models/textbook.h): the locked (1:1 entrained) orbit continued
// in the forcing frequency, against brute-force transients on both sides of each located end.
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "shooting/orbit_branches.h"

namespace rubcont {
namespace {

// The spread of the stroboscopic points x(kT) over the last `last` of `periods` forcing periods of
// a transient from (2, 0): ~0 when the response locks to the forcing, of the cycle's size when it
// drifts on a torus.
double StroboscopicSpread(const ForcedVanDerPolParams& params, int periods, int last) {
  ForcedVanDerPolOscillator system(params);
  IntegratorOptions options;
  options.method = IntegrationMethod::kExplicitRungeKutta;
  options.relative_tolerance = options.absolute_tolerance = 1e-10;
  OdeIntegrator integrator(system, options);
  const double T = system.ForcingPeriod();
  Vector x = (Vector(2) << 2.0, 0.0).finished(), next(2);
  std::vector<Vector> points;
  for (int k = 0; k < periods; ++k) {
    REQUIRE(integrator.Integrate(k * T, x, (k + 1) * T, next).Succeeded());
    x = next;
    if (k >= periods - last) points.push_back(x);
  }
  double spread = 0.0;
  for (const Vector& p : points) spread = std::max(spread, (p - points.back()).norm());
  return spread;
}

TEST_CASE("Forced van der Pol: the locked orbit ends at two folds that bound 1:1 entrainment",
          "[shooting][textbook]") {
  const ForcedVanDerPolParams params{0.2, 0.1, 1.0};
  ForcedVanDerPolOscillator system(params);
  PeriodicOrbitBranchOptions options;
  options.lambda_min = 0.9;
  options.lambda_max = 1.1;
  options.shooting.integrator.relative_tolerance = 1e-10;
  options.shooting.integrator.absolute_tolerance = 1e-10;
  options.continuation.bounds.max_steps = 400;
  const OrbitStart start =
      SettleForced(system, (Vector(2) << 2.0, 0.0).finished(), 400, options.shooting.integrator);
  REQUIRE(start.valid);
  const PeriodicOrbitBranch orbits =
      ContinuePeriodicOrbits(system, OrbitKind::kForced, start, options);
  std::vector<double> folds;
  for (const SpecialPoint& p : orbits.branch.special_points) {
    if (p.type != SpecialPointType::kFold || !p.converged) continue;
    if (std::none_of(folds.begin(), folds.end(),
                     [&](double w) { return std::abs(w - p.lambda) < 1e-6; })) {
      folds.push_back(p.lambda);
    }
  }
  std::sort(folds.begin(), folds.end());
  REQUIRE(folds.size() == 2);
  const double low = folds[0], high = folds[1];
  CAPTURE(low, high);
  CHECK(low < 1.0);
  CHECK(high > 1.0);
  // First-order averaging: the locking interval has width F/a₀ = 0.1/2 (a₀ = 2, the free cycle).
  CHECK(high - low == Approx(0.05).epsilon(0.1));
  // Inside the interval the transient locks; just outside, its stroboscopic points drift.
  const double margin = 0.005;
  for (const auto& [w, locked] : {std::pair{low + margin, true}, std::pair{high - margin, true},
                                  std::pair{low - margin, false}, std::pair{high + margin, false}}) {
    ForcedVanDerPolParams at = params;
    at.frequency = w;
    const double spread = StroboscopicSpread(at, 1500, 300);
    CAPTURE(w, spread);
    if (locked) {
      CHECK(spread < 1e-4);
    } else {
      CHECK(spread > 0.1);
    }
  }
}

}  // namespace
}  // namespace rubcont
