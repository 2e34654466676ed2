// Central differences of an integrator's flow map x0 ↦ x(T), for checking its state-transition
// matrix: steps h·max(|x0_i|, 1) (solvers/finite_difference.h).
#pragma once

#include <catch2/catch.hpp>

#include "solvers/finite_difference.h"
#include "solvers/ode.h"

namespace rubcont::testing {

inline Matrix FlowJacobianByDifferences(OdeIntegrator& integrator, const Vector& x0, double T,
                                        double h) {
  FiniteDifferenceOptions steps;
  steps.relative_step = h;
  const Vector typical = Vector::Ones(x0.size());
  Matrix fd;
  FiniteDifferenceJacobian(
      [&](const Vector& start, Vector& end) {
        end.resize(x0.size());
        REQUIRE(integrator.Integrate(0.0, start, T, end).Succeeded());
      },
      x0, x0.size(), fd, steps, &typical);
  return fd;
}

}  // namespace rubcont::testing
