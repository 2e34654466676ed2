#include "models/beam.h"
#include "solvers/constants.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

ShaftElement Steel(double length, double outer, double inner = 0.0) {
  ShaftElement e;
  e.length = length;
  e.outer_diameter = outer;
  e.inner_diameter = inner;
  e.youngs_modulus = 2.11e11;
  e.shear_modulus = 8.12e10;
  e.density = 7810.0;
  return e;
}

// A uniform shaft of total length L cut into `count` equal elements.
Shaft Uniform(const ShaftElement& whole, int count) {
  Shaft shaft;
  ShaftElement piece = whole;
  piece.length = whole.length / count;
  shaft.elements.assign(static_cast<std::size_t>(count), piece);
  return shaft;
}

// The positive whirl frequencies ν [rad/s] (Im s > 0), ascending.
std::vector<double> BeamFrequencies(const StructuralMatrices& m, double spin,
                                    const std::vector<Index>& held) {
  std::vector<double> nu;
  for (const std::complex<double>& s : WhirlEigenvalues(m, spin, held)) {
    if (s.imag() > 0.0) nu.push_back(s.imag());
  }
  return nu;
}

// Simply supported uniform Timoshenko beam, mode n (w = W sin kz, ψ = Ψ cos kz, k = nπ/L):
// (ρAν² − κGAk²)(ρIν² − EIk² − κGA) − (κGAk)² = 0, the lower root in ν².
double PinnedTimoshenko(const ShaftElement& e, int n) {
  const double k = n * kPi / e.length;
  const double A = e.Area(), I = e.AreaMoment(), s = e.ShearCoefficient() * e.shear_modulus * A;
  const double a = e.density * A * e.density * I;
  const double b = -(e.density * A * (e.youngs_modulus * I * k * k + s) +
                     s * k * k * e.density * I);
  const double c = s * k * k * (e.youngs_modulus * I * k * k + s) - s * s * k * k;
  const double disc = std::sqrt(b * b - 4 * a * c);
  return std::sqrt((-b - disc) / (2 * a));
}

TEST_CASE("Timoshenko element: rigid motions cost no strain and carry the rigid inertia",
          "[beam]") {
  for (double length : {0.02, 0.1, 0.5}) {  // Φ from 10 down to 0.03
    const ShaftElement e = Steel(length, 0.05, 0.02);
    const BeamElementMatrices m = TimoshenkoElement(e);
    const double L = e.length;
    Eigen::Vector4d translation(1, 0, 1, 0), rotation(0, 1, L, 1);  // rotation about node 1
    CHECK((m.stiffness * translation).norm() <= 1e-9 * m.stiffness.norm());
    CHECK((m.stiffness * rotation).norm() <= 1e-9 * m.stiffness.norm() * L);
    CHECK((m.stiffness - m.stiffness.transpose()).norm() == 0.0);
    CHECK((m.mass - m.mass.transpose()).norm() == 0.0);
    const double mass = e.density * e.Area() * L;
    CHECK(translation.dot(m.mass * translation) == Approx(mass).epsilon(1e-12));
    // About its end: ρAL³/3 + ρIL (the rotary inertia of the sections).
    CHECK(rotation.dot(m.mass * rotation) ==
          Approx(mass * L * L / 3 + e.density * e.AreaMoment() * L).epsilon(1e-12));
    // A rigid tilt spins the sections' polar inertia: 2ρIL.
    CHECK(rotation.dot(m.gyroscopic * rotation) ==
          Approx(2 * e.density * e.AreaMoment() * L).epsilon(1e-12));
  }
}

TEST_CASE("Timoshenko element: Cowper's shear coefficient and the shear parameter", "[beam]") {
  ShaftElement solid = Steel(0.1, 0.05);
  const double nu = solid.Poisson();
  CHECK(solid.ShearCoefficient() == Approx(6 * (1 + nu) / (7 + 6 * nu)).epsilon(1e-14));
  // A thin tube tends to 2(1+ν)/(4+3ν).
  ShaftElement tube = Steel(0.1, 0.05, 0.05 * (1 - 1e-6));
  CHECK(tube.ShearCoefficient() == Approx(2 * (1 + nu) / (4 + 3 * nu)).epsilon(1e-6));
  CHECK(solid.ShearParameter() ==
        Approx(12 * solid.youngs_modulus * solid.AreaMoment() /
               (solid.ShearCoefficient() * solid.shear_modulus * solid.Area() * 0.01))
            .epsilon(1e-14));
}

// Relative errors of the first three frequencies of a pinned–pinned shaft cut into `count` elements.
std::vector<double> PinnedErrors(const ShaftElement& whole, int count) {
  const StructuralMatrices m = Assemble({{Uniform(whole, count)}, {}});
  const std::vector<double> nu = BeamFrequencies(m, 0.0, {0, 2 * count});
  std::vector<double> errors;
  for (int n = 1; n <= 3; ++n) {
    errors.push_back(nu[static_cast<std::size_t>(n - 1)] / PinnedTimoshenko(whole, n) - 1);
  }
  return errors;
}

TEST_CASE("pinned–pinned shafts: Timoshenko's frequencies, h⁴ while Φ ≪ 1, h² once Φ ≫ 1",
          "[beam]") {
  // Slender (L/D = 100): element Φ = 0.005 to 0.02, bending-dominated, cubic interpolation.
  const ShaftElement slender = Steel(0.4, 0.004, 0.0016);
  const std::vector<double> coarse = PinnedErrors(slender, 4), fine = PinnedErrors(slender, 8);
  for (int n = 0; n < 3; ++n) {
    const double ratio = coarse[static_cast<std::size_t>(n)] / fine[static_cast<std::size_t>(n)];
    INFO("slender, mode " << n + 1 << ": error 4 → 8 elements falls " << ratio << "×");
    CHECK(fine[static_cast<std::size_t>(n)] > 0.0);  // from above: a Rayleigh–Ritz bound
    CHECK(ratio > 12.0);                             // order > 3.5
  }
  CHECK(PinnedErrors(slender, 16)[2] < 2e-4);
  // Thick (L/D = 4, shear and rotary inertia lower the first mode by 9 % against
  // Euler–Bernoulli): element Φ = 54 to 215, shear-dominated, where the interdependent
  // interpolation tends to linear in u and the order to 2.
  const ShaftElement thick = Steel(0.4, 0.1, 0.04);
  const std::vector<double> e16 = PinnedErrors(thick, 16), e32 = PinnedErrors(thick, 32);
  for (int n = 0; n < 3; ++n) {
    const double ratio = e16[static_cast<std::size_t>(n)] / e32[static_cast<std::size_t>(n)];
    INFO("thick, mode " << n + 1 << ": error 16 → 32 elements falls " << ratio << "×");
    CHECK(e32[static_cast<std::size_t>(n)] > 0.0);
    CHECK(e32[static_cast<std::size_t>(n)] < 2e-3);
    CHECK(ratio == Approx(4.0).epsilon(0).margin(0.1));
  }
  const double eb = kPi * kPi / (thick.length * thick.length) *
                    std::sqrt(thick.youngs_modulus * thick.AreaMoment() /
                              (thick.density * thick.Area()));
  CHECK(PinnedTimoshenko(thick, 1) / eb == Approx(0.909).epsilon(0).margin(0.001));
}

TEST_CASE("free–free slender shaft: two rigid modes, then Euler–Bernoulli's β_n L", "[beam]") {
  // L/D = 4000 puts shear and rotary inertia near 1e-6 of the third frequency (at L/D = 1000
  // they take 1.4e-5 off it: (β₃r)²(1 + E/κG) ≈ 3e-5).
  const ShaftElement whole = Steel(10.0, 0.0025);
  const StructuralMatrices m = Assemble({{Uniform(whole, 64)}, {}});
  const std::vector<double> nu = BeamFrequencies(m, 0.0, {});
  const double scale = std::sqrt(whole.youngs_modulus * whole.AreaMoment() /
                                 (whole.density * whole.Area())) /
                       (whole.length * whole.length);
  REQUIRE(nu.size() >= 5);
  // The two rigid modes (eigenvalues at 0 up to round-off, so not counted among the positive ones
  // reliably): the first elastic modes come after them.
  std::vector<double> elastic;
  for (double v : nu) {
    if (v > 0.5 * 4.73 * 4.73 * scale) elastic.push_back(v);
  }
  REQUIRE(elastic.size() >= 3);
  const double beta_l[] = {4.730040744862704, 7.853204624095838, 10.995607838001671};
  for (int n = 0; n < 3; ++n) {
    CHECK(elastic[static_cast<std::size_t>(n)] / (beta_l[n] * beta_l[n] * scale) ==
          Approx(1.0).epsilon(1e-5));
  }
}

TEST_CASE("disk on a clamped shaft: gyroscopic splitting as the closed-form quartic", "[beam]") {
  // One massless Timoshenko element clamped at node 0, a disk at node 1. Tip flexibility with
  // shear: δ = F(L³/3EI + L/κGA) + M L²/2EI, θ = F L²/2EI + M L/EI; its inverse is the stiffness
  // [k11 k12; k12 k22], and whirl u ∝ e^{jνt} at spin ω needs
  // (k11 − mν²)(k22 − I_d ν² + I_p ω ν) − k12² = 0.
  ShaftElement e = Steel(0.3, 0.02);
  e.density = 0.0;
  const Disk disk{1, 8.0, 0.03, 0.055};
  const StructuralMatrices m = Assemble({{Shaft{"rotor", {e}, {disk}}}, {}});
  const double EI = e.youngs_modulus * e.AreaMoment(), L = e.length;
  Eigen::Matrix2d flexibility;
  flexibility << L * L * L / (3 * EI) + L / (e.ShearCoefficient() * e.shear_modulus * e.Area()),
      L * L / (2 * EI), L * L / (2 * EI), L / EI;
  const Eigen::Matrix2d k = flexibility.inverse();
  for (double spin : {0.0, 500.0, 3000.0}) {
    // m I_d ν⁴ − m I_p ω ν³ − (k11 I_d + m k22) ν² + k11 I_p ω ν + (k11 k22 − k12²) = 0.
    const double c4 = disk.mass * disk.diametral_inertia;
    Eigen::Vector4d c(-disk.mass * disk.polar_inertia * spin,
                      -(k(0, 0) * disk.diametral_inertia + disk.mass * k(1, 1)),
                      k(0, 0) * disk.polar_inertia * spin, k.determinant());
    Eigen::Matrix4d companion = Eigen::Matrix4d::Zero();
    companion.row(0) = -c.transpose() / c4;
    companion.bottomLeftCorner(3, 3).setIdentity();
    Eigen::Vector4cd roots = companion.eigenvalues();
    std::vector<double> exact;
    for (int i = 0; i < 4; ++i) exact.push_back(roots(i).real());
    std::sort(exact.begin(), exact.end());
    const ComplexVector s = WhirlEigenvalues(m, spin, {0, 1});
    REQUIRE(s.size() == 4);
    for (int i = 0; i < 4; ++i) {
      CHECK(std::abs(s(i).real()) <= 1e-9 * std::abs(s(i)));
      CHECK(s(i).imag() == Approx(exact[static_cast<std::size_t>(i)]).epsilon(1e-9));
    }
    if (spin > 0.0) {
      // Forward whirl stiffens, backward softens (the sign of −jωG).
      const ComplexVector rest = WhirlEigenvalues(m, 0.0, {0, 1});
      CHECK(s(3).imag() > rest(3).imag());
      CHECK(-s(0).imag() < rest(3).imag());
    }
  }
}

TEST_CASE("assembly: springs to ground and between shafts, disks on their nodes", "[beam]") {
  BeamModel model;
  model.shafts = {Uniform(Steel(0.3, 0.05), 3), Uniform(Steel(0.2, 0.1, 0.08), 2)};
  model.shafts[0].disks = {{2, 4.0, 0.01, 0.02}};
  model.springs = {{1, 0, -1, 0, 4.7e6, 325.0}, {0, 3, 1, 2, 1e7, 10.0}};
  const StructuralMatrices m = Assemble(model);
  REQUIRE(m.Coordinates() == 2 * 4 + 2 * 3);
  CHECK(model.Coordinate(1, 2, 0) == 12);
  const StructuralMatrices bare = Assemble({model.shafts, {}});
  Matrix dk = m.stiffness - bare.stiffness, dc = m.damping - bare.damping;
  CHECK(dk(8, 8) == 4.7e6);
  CHECK(dc(8, 8) == 325.0);
  CHECK(dk(6, 6) == 1e7);
  CHECK(dk(12, 12) == 1e7);
  CHECK(dk(6, 12) == -1e7);
  CHECK(dk(12, 6) == -1e7);
  dk(8, 8) = dk(6, 6) = dk(12, 12) = dk(6, 12) = dk(12, 6) = 0.0;
  CHECK(dk.norm() == 0.0);
  Shaft no_disk = model.shafts[0];
  no_disk.disks.clear();
  const StructuralMatrices without = Assemble({{no_disk, model.shafts[1]}, {}});
  CHECK(m.mass(4, 4) - without.mass(4, 4) == Approx(4.0));
  CHECK(m.mass(5, 5) - without.mass(5, 5) == Approx(0.01));
  CHECK(m.gyroscopic(5, 5) - without.gyroscopic(5, 5) == Approx(0.02));
  CHECK(model.shafts[0].NodePositions().back() == Approx(0.3));
}

TEST_CASE("beam model validation names the entry, its value and the rule", "[beam]") {
  auto message = [](const BeamModel& model) {
    try {
      model.Validate();
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const BeamModel good{{Uniform(Steel(0.3, 0.05), 3)}, {{0, 0, -1, 0, 1e6, 0.0}}};
  CHECK(message(good) == "accepted");
  BeamModel bad = good;
  bad.shafts[0].elements[1].inner_diameter = 0.06;
  CHECK_THAT(message(bad), Catch::StartsWith("shafts[0].elements[1].inner_diameter = 0.06: must "
                                             "be below outer_diameter"));
  bad = good;
  bad.shafts[0].elements[2].shear_modulus = 1e10;
  CHECK_THAT(message(bad), Catch::StartsWith("shafts[0].elements[2].shear_modulus = 1e+10: must "
                                             "give a Poisson ratio"));
  bad = good;
  bad.shafts[0].elements[0].length = -0.1;
  CHECK(message(bad) == "shafts[0].elements[0].length = -0.1: must be positive (m)");
  bad = good;
  bad.shafts[0].disks = {{4, 1.0, 0.0, 0.0}};
  CHECK(message(bad) == "shafts[0].disks[0].node = 4: must name a node of shafts[0] (0 to 3)");
  bad = good;
  bad.springs[0].other_shaft = 1;
  CHECK_THAT(message(bad), Catch::StartsWith("springs[0].other_shaft = 1: must name a shaft"));
  bad = good;
  bad.springs[0].stiffness = kNaN;
  CHECK(message(bad) == "springs[0].stiffness = nan: must be finite");
  CHECK(message(BeamModel{}) == "shafts: at least one shaft is needed");
  ShaftElement massless = Steel(0.3, 0.05);
  massless.density = 0.0;
  CHECK_THROWS_WITH(WhirlEigenvalues(Assemble({{Shaft{"s", {massless}, {}}}, {}}), 0.0, {}),
                    Catch::StartsWith("mass: not positive definite"));
}

}  // namespace
}  // namespace rubcont
