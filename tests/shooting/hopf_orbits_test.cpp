// Periodic orbits born at a Hopf point: the Stuart–Landau equilibrium z = 0 loses stability at
// λ = 0 (eigenvalues λ ± iω), located by the engine on the equilibrium branch; the switch onto
// the orbits born there follows them to λ = 1 with the closed form r = √λ, T = 2π/|ω − γλ| and
// nontrivial multiplier e^{−2λT} on every point.
#include <cmath>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "models/textbook.h"
#include "shooting/hopf_orbits.h"

namespace rubcont {
namespace {

TEST_CASE("Stuart–Landau: Hopf point of the equilibrium located, the orbits born there continued "
          "to lambda = 1 as in closed form",
          "[hopf][shooting]") {
  StuartLandauParams params;
  params.omega = 1.0;
  params.gamma = 0.5;
  params.lambda = -0.5;
  StuartLandauOscillator system(params);

  EquilibriumProblem equilibria(system);
  ContinuationOptions options;
  options.bounds.lambda_min = -0.5;
  options.bounds.lambda_max = 0.5;
  options.detect.stability = true;
  const Branch equilibrium_branch = Continue(equilibria, Vector::Zero(2), -0.5, options);
  INFO(equilibrium_branch.BriefReport());
  REQUIRE(equilibrium_branch.Count(SpecialPointType::kHopf) == 1);
  const SpecialPoint* hopf = nullptr;
  for (const SpecialPoint& p : equilibrium_branch.special_points) {
    if (p.type == SpecialPointType::kHopf) hopf = &p;
  }
  CHECK(hopf->converged);
  CHECK(hopf->lambda == Approx(0.0).margin(1e-8));
  CHECK(hopf->frequency == Approx(params.omega).epsilon(1e-8));

  for (int segments : {1, 4}) {
    CAPTURE(segments);
    HopfOrbitOptions hopf_options;
    hopf_options.amplitude = 1e-2;
    hopf_options.orbits.lambda_min = -0.5;
    hopf_options.orbits.lambda_max = 1.0;
    hopf_options.orbits.shooting.segments = segments;
    hopf_options.orbits.shooting.integrator.method = IntegrationMethod::kExplicitRungeKutta;
    hopf_options.orbits.shooting.integrator.explicit_order = 8;
    hopf_options.orbits.shooting.sensitivities_in_residual = true;
    hopf_options.orbits.continuation.step.target_iterations = 5;
    hopf_options.orbits.continuation.step.max = 0.5;
    const PeriodicOrbitBranch orbits = ContinueOrbitsFromHopf(system, *hopf, hopf_options);
    const Branch& branch = orbits.branch;
    INFO(branch.BriefReport() << " — " << branch.message);
    REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
    REQUIRE(branch.Size() > 5);
    // Supercritical: the orbits lie at λ > 0, the first one at λ = a² (r = a = 1e-2).
    CHECK(branch.points.front().lambda == Approx(1e-4).epsilon(1e-6));
    CHECK(branch.points.back().lambda == Approx(1.0).margin(1e-9));
    const Vector period = branch.Measure("period");
    for (Index i = 0; i < branch.Size(); ++i) {
      const BranchPoint& p = branch.points[static_cast<std::size_t>(i)];
      CAPTURE(p.lambda);
      // On the circle r = √λ every point has |x| = r; the phase condition picks one of them.
      CHECK(p.u.head(2).norm() == Approx(std::sqrt(p.lambda)).margin(1e-9));
      const double T = 2 * M_PI / std::abs(params.omega - params.gamma * p.lambda);
      CHECK(period(i) == Approx(T).epsilon(1e-9));
      REQUIRE(p.spectrum.valid);
      REQUIRE(p.spectrum.values.size() == 1);
      CHECK(p.spectrum.values(0).real() == Approx(std::exp(-2 * p.lambda * T)).margin(1e-8));
      CHECK(p.num_unstable == 0);
    }
  }
}

}  // namespace
}  // namespace rubcont
