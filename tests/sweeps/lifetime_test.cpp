#include "solvers/constants.h"
#include "sweeps/lifetime.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// N copies whose escape times are exponential with rate κ, seen in stretches Δ up to T.
EscapeObservations Sample(double parameter, double rate, int copies, double stretch, double duration,
                          std::uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  EscapeObservations o;
  o.parameter = parameter;
  o.stretch = stretch;
  o.duration = duration;
  for (int i = 0; i < copies; ++i) {
    const double t = rate > 0.0 ? -std::log1p(-uniform(generator)) / rate : kInfinity;
    if (t > duration) {
      ++o.stayed;
    } else {
      o.escape_stretch.push_back(std::max(1, static_cast<int>(std::ceil(t / stretch))));
    }
  }
  return o;
}

TEST_CASE("escape rate: the interval-censored maximum and its limits") {
  const EscapeObservations o = Sample(0.0, 1.3, 4000, 0.1, 3.0, 7);
  const EscapeRate r = EstimateEscapeRate(o);
  CHECK(r.status == EscapeRateStatus::kEstimated);
  CHECK(r.copies == 4000);
  // The closed form is the likelihood's maximum, and the limits lie 1.92 below it.
  const double top = EscapeLogLikelihood(o, r.rate);
  CHECK(EscapeLogLikelihood(o, r.rate * (1 + 1e-4)) < top);
  CHECK(EscapeLogLikelihood(o, r.rate * (1 - 1e-4)) < top);
  const double drop = 1.920729410347062;  // χ²₁(0.95)/2
  CHECK(EscapeLogLikelihood(o, r.lower) == Approx(top - drop).epsilon(0).margin(1e-8));
  CHECK(EscapeLogLikelihood(o, r.upper) == Approx(top - drop).epsilon(0).margin(1e-8));
  // 4000 copies: the estimate within 3 standard errors (κ/√d ≈ 0.021).
  CHECK(std::abs(r.rate - 1.3) < 0.065);
  CHECK(r.lower < 1.3);
  CHECK(r.upper > 1.3);
  // Binning into coarse stretches does not bias it: the naive d/Σt would (times rounded up).
  const EscapeObservations coarse = Sample(0.0, 1.3, 4000, 0.5, 3.0, 7);
  CHECK(std::abs(EstimateEscapeRate(coarse).rate - 1.3) < 0.07);
}

TEST_CASE("escape rate: the 95 % interval covers the true rate in about 95 % of experiments") {
  int covered = 0;
  const int experiments = 400;
  for (int e = 0; e < experiments; ++e) {
    const EscapeRate r = EstimateEscapeRate(Sample(0.0, 0.7, 16, 0.1, 5.0, 1000 + e));
    covered += (r.lower <= 0.7 && 0.7 <= r.upper) ? 1 : 0;
  }
  // Binomial(400, 0.95): 380 ± 4.4; a wrong drop (1 instead of 1.92, or 3.84) moves it by > 20.
  CHECK(covered >= 366);
  CHECK(covered <= 394);
}

TEST_CASE("escape rate: no escape bounds it above, all in the first stretch below") {
  EscapeObservations none;
  none.stretch = 0.1;
  none.duration = 5.0;
  none.stayed = 8;
  const EscapeRate a = EstimateEscapeRate(none);
  CHECK(a.status == EscapeRateStatus::kNoEscape);
  CHECK(a.rate == 0.0);
  CHECK(a.upper == Approx(1.9207294 / 40.0));

  EscapeObservations immediate;
  immediate.stretch = 0.1;
  immediate.duration = 5.0;
  immediate.escape_stretch.assign(8, 1);
  const EscapeRate b = EstimateEscapeRate(immediate);
  CHECK(b.status == EscapeRateStatus::kAllImmediate);
  CHECK(std::isinf(b.rate));
  CHECK(EscapeLogLikelihood(immediate, b.lower) ==
        Approx(-1.920729410347062).epsilon(0).margin(1e-9));

  EscapeObservations bad = immediate;
  bad.escape_stretch.push_back(51);
  CHECK_THROWS_WITH(EstimateEscapeRate(bad), Contains("escape_stretch = 51") && Contains("duration/stretch"));
  bad = none;
  bad.stayed = 0;
  CHECK_THROWS_WITH(EstimateEscapeRate(bad), Contains("nothing observed"));
}

// κ = A (p − p_c)^γ above p_c = 178 (A = 0.4, γ = 1.5), 200 copies per speed.
std::vector<EscapeObservations> CrisisData(CrisisSide side, std::uint64_t seed) {
  std::vector<EscapeObservations> data;
  for (double p = 174.0; p <= 186.0; p += 1.0) {
    const double u = side == CrisisSide::kAbove ? p - 178.0 : 178.0 - p;
    const double rate = u > 0 ? 0.4 * std::pow(u, 1.5) : 0.0;
    data.push_back(Sample(p, rate, 200, 0.1, 5.0, seed++));
  }
  return data;
}

TEST_CASE("crisis fit: the critical speed and exponent of a power law, on either side") {
  for (CrisisSide side : {CrisisSide::kAbove, CrisisSide::kBelow}) {
    CAPTURE(side == CrisisSide::kAbove);
    CrisisOptions options;
    options.side = side;
    const CrisisFit fit = FitCrisis(CrisisData(side, 11), options);
    REQUIRE(fit.status == CrisisStatus::kLocated);
    CHECK(std::abs(fit.critical - 178.0) < 0.3);
    CHECK(fit.critical_lower < 178.0);
    CHECK(fit.critical_upper > 178.0);
    CHECK(fit.lower_bounded);
    CHECK(fit.upper_bounded);
    CHECK(fit.critical_upper - fit.critical_lower < 1.5);
    CHECK(std::abs(fit.exponent - 1.5) < 0.3);
    CHECK(CrisisRate(fit, side, 184.0 * (side == CrisisSide::kAbove) + 172.0 * (side == CrisisSide::kBelow)) ==
          Approx(0.4 * std::pow(6.0, 1.5)).epsilon(0.25));
    CHECK(CrisisRate(fit, side, 178.0 + (side == CrisisSide::kAbove ? -0.5 : 0.5)) == 0.0);
  }
}

TEST_CASE("crisis fit: a rate that does not fall with speed is not bracketed, one speed is too few") {
  std::vector<EscapeObservations> flat;
  for (int k = 0; k < 6; ++k) flat.push_back(Sample(170.0 + k, 1.0, 200, 0.1, 5.0, 50 + k));
  const CrisisFit fit = FitCrisis(flat);
  CHECK(fit.status == CrisisStatus::kNotBracketed);
  CHECK_THAT(fit.message, Contains("without a critical point"));

  std::vector<EscapeObservations> one = {Sample(170.0, 0.0, 10, 0.1, 5.0, 1), Sample(171.0, 1.0, 10, 0.1, 5.0, 2)};
  const CrisisFit few = FitCrisis(one);
  CHECK(few.status == CrisisStatus::kTooFewSpeeds);
  CHECK_THAT(few.message, Contains("1 parameter values with escapes"));
}

TEST_CASE("crisis fit: the probability that a sweep leaves at each speed") {
  CrisisFit fit;
  fit.status = CrisisStatus::kLocated;
  fit.critical = 178.0;
  fit.exponent = 1.0;
  fit.amplitude = 0.2;
  const std::vector<double> leave = SweepLeaveProbabilities(fit, CrisisSide::kAbove, {177.0, 179.0, 180.0}, 5.0);
  REQUIRE(leave.size() == 3);
  CHECK(leave[0] == 0.0);
  CHECK(leave[1] == Approx(1.0 - std::exp(-1.0)));
  CHECK(leave[2] == Approx(std::exp(-1.0) * (1.0 - std::exp(-2.0))));
}

}  // namespace
}  // namespace rubcont
