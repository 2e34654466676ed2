// Where forced-orbit shooting fails on the rub model: the imbalance response of thesis case A(a)
// (3.43 g·cm) in the fixed frame, away from contact. The rotor is free–free (docs/theory.md §2: no
// rotor supports; only the contacts and the centre damper hold it), so its position is neutral:
// every rotor offset carries the same forced response, the forced orbit is not isolated, and the
// shooting Jacobian M − I is singular. The multipliers say so: several equal 1.
#include <cmath>

#include <catch2/catch.hpp>

#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/shooting.h"
#include "solvers/newton.h"

namespace rubcont {
namespace {

TEST_CASE("case A(a) imbalance response without contact: the free-free rotor makes the forced "
          "orbit non-isolated, and forced shooting meets a singular Jacobian",
          "[shooting][rub]") {
  TwoPointParams params = ThesisCaseAa();  // case A(a): disk at centre, RCI 100/100, centre damper 52 N·s/m
  params.imbalance = 3.43e-5;
  const double omega = RpmToRadPerSecond(200.0);
  RubFixedFrame system(TwoPointStructure(params), omega);
  REQUIRE(system.ForcingPeriod() == Approx(kTwoPi / omega));

  // Start at rest in the centre: the imbalance response m_u e/m_r ≈ 3.4 µm stays far inside the
  // clearance (381 µm), so no contact force ever acts.
  ShootingOptions options;
  options.integrator.relative_tolerance = options.integrator.absolute_tolerance = 1e-9;
  ShootingProblem problem(system, OrbitKind::kForced, options);
  Vector u = problem.InitialGuess(Vector::Zero(system.Dimension()), 0.0, omega);
  REQUIRE(u.allFinite());

  // The monodromy has multipliers at 1 (to integration accuracy): the rotor's rigid translations
  // and tilts in x and y, which no stiffness restores.
  const Spectrum spectrum = problem.Stability(u, omega);
  REQUIRE(spectrum.valid);
  int at_one = 0;
  for (Index i = 0; i < spectrum.values.size(); ++i) {
    if (std::abs(spectrum.values(i) - 1.0) < 1e-6) ++at_one;
  }
  CHECK(at_one >= 4);

  // Newton on the forced-orbit equations: the Jacobian M − I is singular to working precision.
  Matrix J;
  problem.Jacobian(u, omega, J);
  const Vector s = problem.Scale();
  const Matrix scaled = problem.ResidualScale().cwiseInverse().asDiagonal() * J * s.asDiagonal();
  Eigen::JacobiSVD<Matrix> svd(scaled);
  const double condition = svd.singularValues()(0) / svd.singularValues().tail(1)(0);
  INFO("condition of the scaled shooting Jacobian: " << condition);
  CHECK(condition > 1e8);
}

}  // namespace
}  // namespace rubcont
