#include "models/component_modes.h"

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "models/beam.h"

namespace rubcont {
namespace {

// A free–free stepped steel rotor (a heavy disk two thirds along) inside a hollow stator on two
// springs: the shape of the thesis's models, 10 + 6 elements.
BeamModel RotorAndStator() {
  auto element = [](double length, double outer, double inner) {
    ShaftElement e;
    e.length = length;
    e.outer_diameter = outer;
    e.inner_diameter = inner;
    e.youngs_modulus = 2.0e11;
    e.shear_modulus = 7.7e10;
    e.density = 7800.0;
    return e;
  };
  Shaft rotor{"rotor", {}, {}};
  for (int i = 0; i < 10; ++i) rotor.elements.push_back(element(0.03, i < 5 ? 0.03 : 0.035, 0.0));
  rotor.disks = {{7, 6.0, 0.02, 0.035}};
  Shaft stator{"stator", std::vector<ShaftElement>(6, element(0.045, 0.16, 0.12)), {}};
  BeamModel model{{rotor, stator}, {}};
  model.springs = {{1, 0, -1, 0, 4.7e6, 325.0}, {1, 6, -1, 0, 4.7e6, 325.0}};
  return model;
}

std::vector<double> HeldFrequencies(const StructuralMatrices& m, const std::vector<Index>& held) {
  std::vector<double> nu;
  for (const std::complex<double>& s : WhirlEigenvalues(m, 0.0, held)) {
    if (s.imag() > 1e-6) nu.push_back(s.imag());
  }
  return nu;
}

// The rotor pinned to the stator at two planes: the rotor's nodes 0 and 10 tied to the stator's
// 0 and 6 by stiff springs, as contact holds them.
struct Pinned {
  BeamModel model = RotorAndStator();
  std::vector<Index> contacts;
  Pinned() {
    model.springs.push_back({0, 0, 1, 0, 1e11, 0.0});
    model.springs.push_back({0, 10, 1, 6, 1e11, 0.0});
    contacts = {model.Coordinate(0, 0, 0), model.Coordinate(0, 10, 0), model.Coordinate(1, 0, 0),
                model.Coordinate(1, 6, 0)};
  }
};

TEST_CASE("Craig–Bampton with every fixed-interface mode is exact", "[component_modes]") {
  const Pinned pinned;
  const StructuralMatrices full = Assemble(pinned.model);
  const Index interior = full.Coordinates() - 4;
  const ModalReduction reduction = CraigBampton(full, pinned.contacts, interior);
  CHECK(reduction.ReducedCoordinates() == full.Coordinates());
  const std::vector<double> exact = HeldFrequencies(full, {});
  const std::vector<double> reduced = HeldFrequencies(reduction.Reduce(full), {});
  REQUIRE(reduced.size() == exact.size());
  for (std::size_t i = 0; i < exact.size(); ++i) {
    CHECK(reduced[i] == Approx(exact[i]).epsilon(1e-8));
  }
}

TEST_CASE("Craig–Bampton: boundary kept physical, blocks decoupled in K, bounds from above",
          "[component_modes]") {
  const Pinned pinned;
  const StructuralMatrices full = Assemble(pinned.model);
  const std::vector<double> exact = HeldFrequencies(full, {});
  double previous_error = 1.0;
  for (Index modes : {2, 6, 12}) {
    const ModalReduction reduction = CraigBampton(full, pinned.contacts, modes);
    const StructuralMatrices reduced = reduction.Reduce(full);
    REQUIRE(reduced.Coordinates() == 4 + modes);
    // u = B q reproduces q's first four entries at the boundary coordinates.
    for (Index c = 0; c < 4; ++c) {
      CHECK(reduction.basis(pinned.contacts[static_cast<std::size_t>(c)], c) == 1.0);
      CHECK(reduction.basis.row(pinned.contacts[static_cast<std::size_t>(c)]).sum() == 1.0);
    }
    // Constraint and fixed-interface modes are K-orthogonal, the modes mass-normalized with
    // K = diag(ω²) on them.
    const double scale = reduced.stiffness.norm();
    CHECK(reduced.stiffness.topRightCorner(4, modes).norm() <= 1e-9 * scale);
    for (Index j = 0; j < modes; ++j) {
      const double w = reduction.interface_frequencies(j);
      CHECK(reduced.mass(4 + j, 4 + j) == Approx(1.0).epsilon(1e-10));
      CHECK(reduced.stiffness(4 + j, 4 + j) == Approx(w * w).epsilon(1e-9));
      if (j > 0) CHECK(w >= reduction.interface_frequencies(j - 1));
    }
    // The boundary block is the exact static condensation (Schur complement).
    const ModalReduction guyan = CraigBampton(full, pinned.contacts, 0);
    CHECK((reduced.stiffness.topLeftCorner(4, 4) - guyan.Reduce(full).stiffness).norm() <=
          1e-9 * scale);
    // Rayleigh–Ritz: every reduced frequency bounds the exact one of its rank from above, and the
    // lowest four converge as modes are added.
    const std::vector<double> nu = HeldFrequencies(reduced, {});
    double error = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      CHECK(nu[i] >= exact[i] * (1 - 1e-10));
      error = std::max(error, nu[i] / exact[i] - 1);
    }
    INFO(modes << " modes: lowest four to " << error);
    CHECK(error < previous_error);
    previous_error = error;
  }
  CHECK(previous_error < 1e-4);
}

TEST_CASE("Craig–Bampton refuses bad boundaries and mode counts by name", "[component_modes]") {
  const Pinned pinned;
  const StructuralMatrices full = Assemble(pinned.model);
  const Index n = full.Coordinates();
  CHECK_THROWS_WITH(CraigBampton(full, {0, n}, 0),
                    "boundary coordinate " + std::to_string(n) +
                        ": must be a coordinate of the structure (0 to " + std::to_string(n - 1) +
                        ")");
  CHECK_THROWS_WITH(CraigBampton(full, {3, 3}, 0), "boundary coordinate 3: given twice");
  CHECK_THROWS_WITH(CraigBampton(full, pinned.contacts, -1), "modes = -1: must be non-negative");
  CHECK_THROWS_WITH(CraigBampton(full, pinned.contacts, n),
                    Catch::StartsWith("modes = " + std::to_string(n) + ": the interior has only"));
  // The free–free rotor held at one plane only can still turn about it.
  const StructuralMatrices rotor = Assemble({{pinned.model.shafts[0]}, {}});
  CHECK_THROWS_WITH(CraigBampton(rotor, {0}, 2),
                    Catch::Contains("do not hold the structure against rigid motion"));
}

}  // namespace
}  // namespace rubcont
