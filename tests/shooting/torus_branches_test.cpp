// Tori from a Neimark–Sacker point, with a known answer: a limit cycle z₀ (ż₀ = (1 − |z₀|²)z₀ +
// iω₀z₀, the unit circle, period T = 2π/ω₀) beside an oscillator ż₁ = (λ − |z₁|²)z₁ + i(ω₁ +
// s|z₁|²)z₁. The orbits with z₁ = 0 exist for every λ; their multipliers e^{(λ ± iω₁)T} cross the
// unit circle at λ = 0 (a Neimark–Sacker point, angle 2πω₁/ω₀), and for λ > 0 the torus |z₁| = √λ
// is born, on which the return map Φ_T turns z₁ by 2π(ω₁ + sλ)/ω₀: ρ(λ) = (ω₁ + sλ)/ω₀. Its
// Lyapunov exponents per period: 0 (along the circle), 0 (along the flow), −2λT (across, in z₁),
// −2T (z₀'s radius).
#include "shooting/torus_branches.h"
#include "solvers/constants.h"

#include <cmath>
#include <complex>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

constexpr double kOmega0 = 1.0, kOmega1 = 0.37, kShear = 0.1;

class CycleBesideOscillator : public OdeSystem {
 public:
  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const double r0 = x(0) * x(0) + x(1) * x(1), r1 = x(2) * x(2) + x(3) * x(3);
    const double turn = kOmega1 + kShear * r1;
    f << (1 - r0) * x(0) - kOmega0 * x(1), (1 - r0) * x(1) + kOmega0 * x(0),
        (lambda_ - r1) * x(2) - turn * x(3), (lambda_ - r1) * x(3) + turn * x(2);
  }
  double Parameter() const override { return lambda_; }
  void SetParameter(double lambda) override { lambda_ = lambda; }
  void DfDparameter(double, ConstVectorRef x, VectorRef df) override { df << 0, 0, x(2), x(3); }

 private:
  double lambda_ = -0.1;
};

IntegratorOptions TightTorus() {
  IntegratorOptions o;
  o.method = IntegrationMethod::kExplicitRungeKutta;
  o.explicit_order = 8;
  o.relative_tolerance = o.absolute_tolerance = 1e-11;
  return o;
}

PeriodicOrbitBranch Family(CycleBesideOscillator& system) {
  PeriodicOrbitBranchOptions options;
  options.lambda_min = -0.1;
  options.lambda_max = 0.25;
  options.shooting.segments = 2;
  options.shooting.integrator = TightTorus();
  options.continuation.step.max = 0.1;
  OrbitStart start;
  start.x0 = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  start.period = kTwoPi / kOmega0;
  start.lambda = -0.1;
  start.valid = true;
  return ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, start, options);
}

TorusBranchOptions TorusOptions() {
  TorusBranchOptions options;
  options.lambda_min = -0.1;
  options.lambda_max = 0.25;
  options.harmonics = 3;  // ρ runs over 0.37–0.395: it crosses 3/8, a rational the circle's K = 3
                          // cannot see (this system's phases do not interact: at ρ = p/q, q ≤ K,
                          // its circle equations are singular)
  options.integrator = TightTorus();
  options.continuation.step.max = 0.05;
  options.continuation.corrector.residual_tolerance = 1e-9;
  options.lyapunov_iterates = 40;
  return options;
}

// The coefficients (K = 3) of the circle θ ↦ (z₀, z₁) = (e^{iα}, r e^{i(θ + β)}) on the torus
// |z₀| = 1, |z₁| = r: in the closed form r = √λ.
Matrix CircleCoefficients(double r, double alpha = 0.0, double beta = 0.0) {
  Matrix c = Matrix::Zero(4, 7);
  c(0, 0) = std::cos(alpha);
  c(1, 0) = std::sin(alpha);
  c(2, 1) = c(3, 2) = r * std::cos(beta);
  c(3, 1) = r * std::sin(beta);
  c(2, 2) = -c(3, 1);
  return c;
}

std::size_t FirstOf(const Branch& branch, SpecialPointType type) {
  for (std::size_t k = 0; k < branch.special_points.size(); ++k) {
    if (branch.special_points[k].type == type) return k;
  }
  FAIL("no special point of that type: " << branch.BriefReport());
  return 0;
}

TEST_CASE("tori from a Neimark-Sacker point: radius sqrt(lambda), rotation number and exponents in "
          "closed form",
          "[torus]") {
  auto system = std::make_shared<CycleBesideOscillator>();
  const PeriodicOrbitBranch family = Family(*system);
  INFO(family.branch.BriefReport());
  REQUIRE(family.branch.Count(SpecialPointType::kNeimarkSacker) == 1);
  const std::size_t k = FirstOf(family.branch, SpecialPointType::kNeimarkSacker);
  CHECK(family.branch.special_points[k].lambda == Approx(0.0).epsilon(0).margin(1e-7));

  TorusBranchOptions options = TorusOptions();
  std::vector<std::pair<std::size_t, std::size_t>> said;  // on_exponents' (torus, family size)
  options.on_exponents = [&said](std::size_t i, std::size_t n) { said.emplace_back(i, n); };
  const TorusBranch tori = ContinueToriFromNeimarkSacker(system, family, k, options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  // Each torus's exponents announced once, in order, with the family's size.
  REQUIRE(said.size() == tori.branch.points.size());
  for (std::size_t i = 0; i < said.size(); ++i) {
    CHECK(said[i] == std::make_pair(i, tori.branch.points.size()));
  }
  CHECK(tori.birth_rotation_number == Approx(kOmega1 / kOmega0).epsilon(1e-6));
  CHECK(tori.birth_modulus == Approx(1.0).epsilon(0).margin(1e-6));
  CHECK(tori.end == TorusEnd::kBound);
  REQUIRE(tori.branch.points.size() >= 5);
  CHECK(tori.branch.points.back().lambda == Approx(0.25));
  InvariantCircleProblem problem(system, 3, OrbitKind::kAutonomous, TightTorus());
  const double period = kTwoPi / kOmega0;
  for (std::size_t i = 0; i < tori.branch.points.size(); ++i) {
    const BranchPoint& p = tori.branch.points[i];
    INFO("point " << i << " at lambda = " << p.lambda);
    // Supercritical: every torus lies at λ > 0 (the first at ~ε², ε = 1e-3).
    CHECK(p.lambda > 0.0);
    CHECK(problem.RotationNumber(p.u) ==
          Approx((kOmega1 + kShear * p.lambda) / kOmega0).epsilon(0).margin(1e-8));
    CHECK(problem.Period(p.u, p.lambda) == Approx(period).epsilon(1e-8));
    for (const double theta : {0.0, 1.0, 2.5, 4.0}) {
      const Vector x = problem.PointAt(p.u, theta);
      CHECK(std::hypot(x(0), x(1)) == Approx(1.0).epsilon(0).margin(1e-8));
      CHECK(std::hypot(x(2), x(3)) == Approx(std::sqrt(p.lambda)).epsilon(0).margin(1e-8));
    }
    REQUIRE(tori.stability.size() == tori.branch.points.size());
    const auto& s = tori.stability[i];
    REQUIRE(s.valid);
    CHECK(s.trivial.size() == 2);
    // Away from the birth, where −2λT is not yet distinguishable from the trivial exponents.
    if (p.lambda > 0.05) {
      CHECK(s.stable);
      CHECK(s.LargestNontrivial() == Approx(-2 * p.lambda * period).epsilon(1e-3));
      CHECK(s.exponents(3) == Approx(-2 * period).epsilon(1e-3));
    }
  }
}

TEST_CASE("tori from a Neimark-Sacker point: wrong points, kinds and options are refused by name",
          "[torus]") {
  auto system = std::make_shared<CycleBesideOscillator>();
  const PeriodicOrbitBranch family = Family(*system);
  REQUIRE(family.branch.special_points.size() >= 1);
  const std::size_t ns = FirstOf(family.branch, SpecialPointType::kNeimarkSacker);
  CHECK_THROWS_WITH(ContinueToriFromNeimarkSacker(system, family, 99, TorusOptions()),
                    Catch::Contains("is not a Neimark–Sacker point"));
  PeriodicOrbitBranch forced = family;
  forced.kind = OrbitKind::kForced;
  CHECK_THROWS_WITH(ContinueToriFromNeimarkSacker(system, forced, ns, TorusOptions()),
                    Catch::Contains("forced"));
  TorusBranchOptions bad = TorusOptions();
  bad.max_fourier_tail = 1.5;
  CHECK_THROWS_WITH(ContinueToriFromNeimarkSacker(system, family, ns, bad),
                    Catch::Contains("max_fourier_tail = 1.5: must be in (0, 1)"));
  bad = TorusOptions();
  bad.harmonics = 0;
  CHECK_THROWS_WITH(ContinueToriFromNeimarkSacker(system, family, ns, bad),
                    Catch::Contains("harmonics = 0"));
}

TEST_CASE("tori from a given circle: a guess 2 % off at lambda = 0.2 corrected and continued down "
          "to 0.02, every torus in closed form",
          "[torus]") {
  auto system = std::make_shared<CycleBesideOscillator>();
  TorusBranchOptions options = TorusOptions();
  options.lambda_min = 0.02;
  options.lambda_max = 0.25;
  options.lyapunov_iterates = 0;
  options.continuation.direction = -1;
  InvariantCircleProblem problem(system, 3, OrbitKind::kAutonomous, TightTorus());
  // The circle θ ↦ (cos θ₀, sin θ₀, r cos θ, r sin θ) off by 2 % in r, T and ρ.
  const double lambda0 = 0.2, r = 1.02 * std::sqrt(lambda0), period = kTwoPi / kOmega0;
  const Vector u0 = problem.Pack(CircleCoefficients(r),
                                 1.02 * (kOmega1 + kShear * lambda0) / kOmega0, 1.02 * period);
  const TorusBranch tori = ContinueTori(system, OrbitKind::kAutonomous, u0, lambda0, options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  CHECK(tori.end == TorusEnd::kBound);
  REQUIRE(tori.branch.points.size() >= 4);
  CHECK(tori.branch.points.front().lambda == Approx(lambda0));
  CHECK(tori.branch.points.back().lambda == Approx(0.02));
  for (const BranchPoint& p : tori.branch.points) {
    INFO("lambda = " << p.lambda);
    CHECK(p.lambda <= lambda0 + 1e-12);
    CHECK(problem.RotationNumber(p.u) ==
          Approx((kOmega1 + kShear * p.lambda) / kOmega0).epsilon(0).margin(1e-8));
    CHECK(problem.Period(p.u, p.lambda) == Approx(period).epsilon(1e-8));
    for (const double theta : {0.0, 2.0, 5.0}) {
      const Vector x = problem.PointAt(p.u, theta);
      CHECK(std::hypot(x(0), x(1)) == Approx(1.0).epsilon(0).margin(1e-8));
      CHECK(std::hypot(x(2), x(3)) == Approx(std::sqrt(p.lambda)).epsilon(0).margin(1e-8));
    }
  }
  CHECK_THROWS_WITH(ContinueTori(system, OrbitKind::kAutonomous, u0.head(10), lambda0, options),
                    Catch::Contains("the circle has 10 unknowns; 3 harmonics of 4 states need 30"));
}

TEST_CASE("tori grazing a surface: the family ends on the torus that touches it, at the "
          "closed-form lambda",
          "[torus][grazing]") {
  // h = x₀ + x₂ − c over the torus (z₀ and z₁ turn independently) has the maximum 1 + √λ − c and
  // its negative the minimum −1 − √λ + c: touchdown of c = 1.4 at λ = 0.16, lift-off of
  // −h = −(x₀ + x₂) + 1.45 at λ = 0.2025, past the first.
  auto system = std::make_shared<CycleBesideOscillator>();
  TorusBranchOptions options = TorusOptions();
  options.lyapunov_iterates = 0;
  options.grazing = {
      {[](ConstVectorRef x) { return x(0) + x(2) - 1.4; }, GrazingSide::kTouchdown, "touchdown"},
      {[](ConstVectorRef x) { return 1.45 - x(0) - x(2); }, GrazingSide::kLiftOff, "lift_off"}};
  InvariantCircleProblem problem(system, 3, OrbitKind::kAutonomous, TightTorus());
  // The torus at λ = 0.05, z₀ = e^{0.2i}, z₁ = √λ e^{i(θ + 0.3)} on its circle: the extremum lies
  // between the grid's samples.
  const double lambda0 = 0.05, period = kTwoPi / kOmega0, r = std::sqrt(lambda0);
  const Vector u0 =
      problem.Pack(CircleCoefficients(r, 0.2, 0.3), (kOmega1 + kShear * lambda0) / kOmega0, period);

  // The test functions on the closed-form torus, from 28 starts round the circle at 64 instants
  // each: the stencil's quadratic measured 1.3e-5 off (the grid's raw extreme sample 1.4e-3).
  problem.SetGrazingTests(options.grazing);
  CHECK(problem.GrazingSamples() == 64);
  REQUIRE(problem.TestFunctionNames() == std::vector<std::string>{"touchdown", "lift_off"});
  CHECK(problem.TestFunctionType(1) == SpecialPointType::kGrazing);
  const Vector tests = problem.TestFunctions(u0, lambda0);
  CHECK(tests(0) == Approx(1.0 + std::sqrt(lambda0) - 1.4).epsilon(0).margin(2e-5));
  CHECK(tests(1) == Approx(1.45 - 1.0 - std::sqrt(lambda0)).epsilon(0).margin(2e-5));
  // A grid twice as dense each way (56 starts, 128 instants): measured 4.1e-9 off.
  problem.SetGrazingGrid(8, 8);
  CHECK(problem.GrazingSamples() == 128);
  CHECK(problem.TestFunctions(u0, lambda0)(0) ==
        Approx(1.0 + std::sqrt(lambda0) - 1.4).epsilon(0).margin(1e-7));
  CHECK_THROWS_WITH(problem.SetGrazingGrid(0, 4), Catch::Contains("each must be at least 1"));

  const TorusBranch tori = ContinueTori(system, OrbitKind::kAutonomous, u0, lambda0, options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  CHECK(tori.end == TorusEnd::kGrazing);
  CHECK(tori.branch.status == BranchStatus::kGrazing);
  REQUIRE(!tori.branch.special_points.empty());
  const SpecialPoint& end = tori.branch.special_points.back();
  CHECK(end.type == SpecialPointType::kGrazing);
  CHECK(end.label == "touchdown");
  // Measured 3.9e-6 off (3.0e-4 from the raw extreme samples).
  CHECK(end.lambda == Approx(0.16).epsilon(0).margin(1e-5));
  CHECK(tori.branch.points.back().lambda == Approx(end.lambda).epsilon(1e-12));
  CHECK(tori.branch.Count(SpecialPointType::kGrazing) == 1);  // the lift-off lies past the end
  CHECK_THAT(tori.end_note, Catch::Contains("the torus grazes: touchdown at λ = 0.16"));
  // Without the surfaces the family goes on to the range's end.
  options.grazing.clear();
  CHECK(ContinueTori(system, OrbitKind::kAutonomous, u0, lambda0, options).end == TorusEnd::kBound);
}

TEST_CASE("tori continued down to their Neimark-Sacker point: the circle shrinks onto its centre "
          "and the centre's orbits locate the point and its angle",
          "[torus]") {
  auto system = std::make_shared<CycleBesideOscillator>();
  TorusBranchOptions options = TorusOptions();
  options.lambda_min = -0.1;
  options.lyapunov_iterates = 0;
  options.continuation.direction = -1;
  InvariantCircleProblem problem(system, 3, OrbitKind::kAutonomous, TightTorus());
  // The torus at λ = 0.2: θ ↦ (1, 0, r cos θ, r sin θ), r = √λ, whose radius is r.
  const double lambda0 = 0.2, period = kTwoPi / kOmega0;
  const Vector u0 = problem.Pack(CircleCoefficients(std::sqrt(lambda0)),
                                 (kOmega1 + kShear * lambda0) / kOmega0, period);
  CHECK(problem.Radius(u0) == Approx(std::sqrt(lambda0)).epsilon(1e-12));
  const TorusBranch tori = ContinueTori(system, OrbitKind::kAutonomous, u0, lambda0, options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  REQUIRE(tori.end == TorusEnd::kShrinks);
  const Branch& b = tori.branch;
  const Index radius = b.MeasureIndex("radius");
  for (const BranchPoint& p : b.points) {
    INFO("lambda = " << p.lambda);
    CHECK(p.lambda > 0.0);
    CHECK(p.measures(radius) == Approx(std::sqrt(p.lambda)).epsilon(0).margin(1e-8));
  }
  // The event where the radius is min_radius: λ = r² = 2.5e-7.
  const SpecialPoint& end = b.special_points.back();
  CHECK(end.label == kShrinksOntoCentre);
  CHECK(end.lambda == Approx(options.min_radius * options.min_radius).epsilon(1e-3));
  CHECK_THAT(tori.end_note, Catch::Contains("the circle shrinks onto its centre"));

  // The orbit z₁ = 0 through the last circle's centre, its Neimark–Sacker point at λ = 0 with the
  // angle 2πω₁/ω₀ of its multipliers.
  PeriodicOrbitBranchOptions orbits;
  orbits.lambda_min = options.lambda_min;
  orbits.lambda_max = options.lambda_max;
  orbits.continuation = options.continuation;
  orbits.shooting.segments = 2;
  orbits.shooting.integrator = TightTorus();
  orbits.stop_at_neimark_sacker = true;
  const CentreOrbits centre = ContinueCentreOrbits(system, tori, orbits);
  INFO(centre.message << " / " << centre.orbits.branch.BriefReport());
  REQUIRE(centre.ok);
  REQUIRE(centre.located);
  CHECK(centre.lambda == Approx(0.0).epsilon(0).margin(1e-7));
  CHECK(centre.rotation_number == Approx(kOmega1 / kOmega0).epsilon(1e-6));
  CHECK(centre.orbits.branch.status == BranchStatus::kStoppedByCaller);

  // Without the stop the orbits go on over the range, downwards as the tori went: unstable above
  // the point (the oscillator grows at rate λ), stable below it, to the range's end.
  orbits.stop_at_neimark_sacker = false;
  const CentreOrbits onward = ContinueCentreOrbits(system, tori, orbits);
  INFO(onward.message << " / " << onward.orbits.branch.BriefReport());
  REQUIRE(onward.located);
  CHECK(onward.lambda == Approx(centre.lambda).epsilon(0).margin(1e-9));
  const Branch& family = onward.orbits.branch;
  CHECK(family.status == BranchStatus::kReachedLambdaBound);
  CHECK(family.points.back().lambda == Approx(options.lambda_min));
  for (const BranchPoint& p : family.points) {
    INFO("lambda = " << p.lambda);
    CHECK(p.lambda <= end.lambda + 1e-12);
    if (std::abs(p.lambda) > 1e-6) CHECK(p.StableFlag() == (p.lambda < 0.0 ? 1 : 0));
  }

  TorusBranch bound = tori;
  bound.end = TorusEnd::kBound;
  CHECK_THROWS_WITH(ContinueCentreOrbits(system, bound, orbits),
                    Catch::Contains("did not end with its circle shrinking onto its centre"));
  TorusBranchOptions bad = options;
  bad.min_radius = 1e-3;
  CHECK_THROWS_WITH(ContinueTori(system, OrbitKind::kAutonomous, u0, lambda0, bad),
                    Catch::Contains("min_radius = 0.001: must be in [0, amplitude / √2"));
}

// A torus whose circle's harmonics decay as c^k, in closed form: the limit cycle
// ż = (1 − |z|²)z + iωz (the unit circle) seen through x = z / (1 − cz) (|c| < 1), so that
// ẋ = (1 + cx)² ż at z = x / (1 + cx), with a clock of period 2π (kForced). The stroboscopic map
// turns z by 2πω, and the invariant circle is x(θ) = e^{iθ} / (1 − c e^{iθ}) = Σ_{k ≥ 0} c^k
// e^{i(k + 1)θ}, ρ = ω: harmonic m has the size √2 c^{m − 1}, so the Fourier tail of K harmonics
// is c^{K − 1}, and a family in c outgrows every K.
class DistortedCycle : public OdeSystem {
 public:
  static constexpr double kOmega = 0.3819660112501051;  // 2 − the golden ratio
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const std::complex<double> w(x(0), x(1)), stretch = 1.0 + c_ * w, z = w / stretch;
    const std::complex<double> dz = (1.0 - std::norm(z)) * z + std::complex<double>(0.0, kOmega) * z;
    const std::complex<double> dx = stretch * stretch * dz;
    f << dx.real(), dx.imag();
  }
  double Parameter() const override { return c_; }
  void SetParameter(double c) override { c_ = c; }
  double ForcingPeriod() const override { return kTwoPi; }
  // The point's distance from the torus: |z| − 1.
  double OffTorus(const Vector& x) const {
    const std::complex<double> w(x(0), x(1));
    return std::abs(w / (1.0 + c_ * w)) - 1.0;
  }

 private:
  double c_ = 0.01;
};

TEST_CASE("tori refined in K along the family: where the tail reaches 1e-4 the circle is solved "
          "again with 2K harmonics, at the closed-form speeds, and every circle lies on the torus",
          "[torus]") {
  auto system = std::make_shared<DistortedCycle>();
  TorusBranchOptions options;
  options.lambda_min = 0.005;
  options.lambda_max = 0.6;
  options.harmonics = 4;
  options.max_harmonics = 16;
  options.converged_tail = 1e-4;
  options.max_fourier_tail = 1e-2;
  options.integrator = TightTorus();
  options.min_radius = 0.0;
  options.continuation.step.max = 0.05;
  options.continuation.corrector.residual_tolerance = 1e-9;
  const double c0 = 0.01;
  InvariantCircleProblem coarse(system, 4, OrbitKind::kForced, TightTorus());
  Matrix coefficients = Matrix::Zero(2, 9);
  for (int m = 1; m <= 4; ++m) {
    coefficients(0, 2 * m - 1) = coefficients(1, 2 * m) = std::pow(c0, m - 1);
  }
  const Vector u0 = coarse.Pack(coefficients, DistortedCycle::kOmega);
  const TorusBranch tori = ContinueTori(system, OrbitKind::kForced, u0, c0, options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  CHECK(tori.end == TorusEnd::kBound);
  CHECK(tori.harmonics == 16);
  const Branch& b = tori.branch;
  CHECK(b.points.back().lambda == Approx(0.6));
  // K doubled where c^{K − 1} = 1e-4: c = 0.0464 (4 → 8) and 0.2683 (8 → 16); at K = 16 the bound
  // is max_fourier_tail's, which c^15 reaches past the range (c = 0.736).
  REQUIRE(tori.refinements.size() == 2);
  for (std::size_t r = 0; r < 2; ++r) {
    const TorusBranch::Refinement& refined = tori.refinements[r];
    INFO("refinement " << r << " at c = " << refined.lambda);
    CHECK(refined.from == 4 << r);
    CHECK(refined.to == 8 << r);
    CHECK(refined.images == 3);
    CHECK(refined.lambda == Approx(std::pow(1e-4, 1.0 / (refined.from - 1))).epsilon(0.02));
    CHECK(refined.fourier_tail_from == Approx(1e-4).epsilon(1e-3));
    CHECK(refined.fourier_tail_to < 1e-8);
  }
  // Per point its K, rising 4, 8, 16 (at each refinement's c both circles); below K = 16 every
  // tail within the bound. Every circle, written at K = 16 (the coarser padded), lies on the torus
  // to within its truncation: |z| − 1 at most twice the point's tail (measured 0.03–1.4 times it;
  // the K = 4 circle at c = 0.6 would be off by 0.3), ρ = ω (measured 3.3e-8 off at c = 0.6).
  REQUIRE(tori.point_harmonics.size() == b.points.size());
  InvariantCircleProblem finest(system, 16, OrbitKind::kForced, TightTorus());
  const Index tail = b.MeasureIndex("fourier_tail");
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    const BranchPoint& p = b.points[i];
    const int k = tori.point_harmonics[i];
    INFO("c = " << p.lambda << ", K = " << k);
    if (i > 0) CHECK(k >= tori.point_harmonics[i - 1]);
    CHECK(k == (p.lambda < tori.refinements[0].lambda   ? 4
                : p.lambda > tori.refinements[1].lambda ? 16
                : p.lambda > tori.refinements[0].lambda && p.lambda < tori.refinements[1].lambda
                    ? 8
                    : k));
    if (k < 16) CHECK(p.measures(tail) <= 1e-4 * (1.0 + 1e-6));
    REQUIRE(p.u.size() == finest.Dimension());
    system->SetParameter(p.lambda);
    const Vector solved = tori.SolvedCircle(i);
    InvariantCircleProblem own(system, k, OrbitKind::kForced, TightTorus());
    REQUIRE(solved.size() == own.Dimension());
    for (int j = 0; j < 50; ++j) {
      const double theta = kTwoPi * j / 50.0;
      const Vector x = finest.PointAt(p.u, theta);
      CHECK(std::abs(system->OffTorus(x)) <= 2.0 * p.measures(tail));
      CHECK((own.PointAt(solved, theta) - x).norm() < 1e-14);
    }
    CHECK(finest.RotationNumber(p.u) == Approx(DistortedCycle::kOmega).epsilon(0).margin(1e-7));
  }
  // Not converged in K: the K = 16 tori past c^15 = 1e-4 (c = 0.5412) to the range's end, none
  // before; within 3 % of that c the tail is c^15 only to within the refinements' 2 % in c.
  const double edge = std::pow(1e-4, 1.0 / 15.0);
  std::size_t past = 0, near = 0;
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    if (tori.point_harmonics[i] < 16) continue;
    const double c = b.points[i].lambda;
    if (c > 1.03 * edge) ++past;
    else if (c > 0.97 * edge) ++near;
  }
  CHECK(past >= 2);
  CHECK(tori.unconverged_in_k >= past);
  CHECK(tori.unconverged_in_k <= past + near);
  CHECK_THAT(tori.convergence_note,
             Catch::Contains(std::to_string(tori.unconverged_in_k) + " of the " +
                             std::to_string(b.points.size()) + " tori, at K = 16 (the finest)"));
  // At K = 4 throughout the family breaks down where its tail, about c³, reaches 1e-2.
  options.max_harmonics = 0;
  const TorusBranch fixed = ContinueTori(system, OrbitKind::kForced, u0, c0, options);
  CHECK(fixed.end == TorusEnd::kBreakdown);
  CHECK(fixed.refinements.empty());
  CHECK(fixed.unconverged_in_k == 0);
  CHECK(fixed.convergence_note.empty());
  CHECK(fixed.branch.points.back().measures(tail) == Approx(1e-2).epsilon(1e-3));
  CHECK(fixed.branch.points.back().lambda == Approx(std::cbrt(1e-2)).epsilon(0.05));  // 0.2096
  options.refinement_images = {3, 0};
  CHECK_THROWS_WITH(ContinueTori(system, OrbitKind::kForced, u0, c0, options),
                    Catch::Contains("refinement_images = {3, 0}: must be one or more counts"));
  options.refinement_images = {3};
  options.converged_tail = 0.1;
  CHECK_THROWS_WITH(ContinueTori(system, OrbitKind::kForced, u0, c0, options),
                    Catch::Contains("converged_tail = 0.1: must be in (0, max_fourier_tail = 0.01]"));
}

// The limit cycle of DistortedCycle seen through x = z + c z¹⁰ instead (invertible near |z| = 1
// for c < 0.1; z from x by the fixed point z ← x − c z¹⁰), turned per period by ρ = ω near 2/5:
// its circle x(θ) = e^{iθ} + c e^{10iθ} has harmonics 1 and 10 only, so with K = 10 the tail is c
// and harmonic 10 stands out of harmonic 9 (zero) — a multiple of 5.
class TenfoldCycle : public OdeSystem {
 public:
  static constexpr double kOmega = 0.4003;
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const std::complex<double> w(x(0), x(1));
    std::complex<double> z = w;
    for (int i = 0; i < 60; ++i) z = w - c_ * std::pow(z, 10);
    const std::complex<double> dz = (1.0 - std::norm(z)) * z + std::complex<double>(0.0, kOmega) * z;
    const std::complex<double> dx = (1.0 + 10.0 * c_ * std::pow(z, 9)) * dz;
    f << dx.real(), dx.imag();
  }
  double Parameter() const override { return c_; }
  void SetParameter(double c) override { c_ = c; }
  double ForcingPeriod() const override { return kTwoPi; }

 private:
  double c_ = 1e-3;
};

TEST_CASE("tori ending at a resonance: the harmonic that stands out, a multiple of q, reads as "
          "p:q in lowest terms",
          "[torus]") {
  auto system = std::make_shared<TenfoldCycle>();
  TorusBranchOptions options;
  options.lambda_min = 1e-4;
  options.lambda_max = 0.05;
  options.harmonics = 10;
  options.max_fourier_tail = 0.01;
  options.integrator = TightTorus();
  options.min_radius = 0.0;
  options.continuation.step.initial = 0.002;
  options.continuation.step.max = 0.005;
  options.continuation.corrector.residual_tolerance = 1e-9;
  const double c0 = 1e-3;
  InvariantCircleProblem problem(system, 10, OrbitKind::kForced, TightTorus());
  Matrix coefficients = Matrix::Zero(2, 21);
  coefficients(0, 1) = coefficients(1, 2) = 1.0;
  coefficients(0, 19) = coefficients(1, 20) = c0;
  const TorusBranch tori =
      ContinueTori(system, OrbitKind::kForced, problem.Pack(coefficients, TenfoldCycle::kOmega), c0,
                   options);
  INFO(tori.message << " / " << tori.branch.BriefReport() << " / " << tori.end_note);
  REQUIRE(tori.ok);
  REQUIRE(tori.end == TorusEnd::kLocking);
  CHECK(tori.branch.points.back().lambda == Approx(0.01).epsilon(1e-3));  // tail c = 0.01
  CHECK(tori.locking_p == 2);
  CHECK(tori.locking_q == 5);
  CHECK_THAT(tori.end_note, Catch::Contains("phase locking near the 2:5 resonance"));
  CHECK_THAT(tori.end_note, Catch::Contains("harmonic 10 stands out"));
  CHECK_THAT(tori.end_note, Catch::Contains("ρ − 2/5 = +3.00e-04"));
}

}  // namespace
}  // namespace rubcont
