#include "sweeps/escape_design.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <catch2/catch.hpp>

#include "solvers/constants.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// The tent map x ↦ a·min(x, 1 − x) past its boundary crisis at a = 2. For a > 2 the points whose
// image passes 1 leave [0, 1] for good; of points spread uniformly over [0, 1] a share 2/a stays,
// spread uniformly again (each of the two preimages of [0, 1] has length 1/a and is stretched
// onto it), so the number of steps to escape is geometric and, with a step of τ seconds, the
// lifetime is exponential at rate κ = ln(a/2)/τ exactly. The slope is set from the parameter so
// that the closed form is a crisis law: a(p) = 2·exp(A τ (p − p_c)^γ) above p_c, 2 below, i.e.
// κ(p) = A (p − p_c)^γ.
struct TentCrisis {
  double critical = 171.6;  // p_c
  double exponent = 2.0;    // γ
  double amplitude = 0.01;  // A [1/s per unit^γ]
  double step = 1e-3;       // τ [s]
  double stretch = 0.1;     // [s]: 100 steps

  double Rate(double p) const { return p > critical ? amplitude * std::pow(p - critical, exponent) : 0.0; }

  // Copies from uniform starts (copy c of a request: seed + c), iterated until they leave or the
  // duration ends. The cost is the simulated time (steps × τ), so designs are reproducible.
  EscapeBatch Run(const std::vector<EscapeRequest>& requests) const {
    EscapeBatch batch;
    for (const EscapeRequest& r : requests) {
      EscapeObservations o;
      o.parameter = r.parameter;
      o.stretch = stretch;
      const long steps_per_stretch = std::lround(stretch / step);
      const long stretches = std::lround(std::ceil(r.duration / stretch - 1e-9));
      o.duration = stretches * stretch;
      const double a = 2.0 * std::exp(Rate(r.parameter) * step);
      for (int c = 0; c < r.copies; ++c) {
        std::mt19937_64 generator(r.seed + static_cast<std::uint64_t>(c));
        double x = std::uniform_real_distribution<double>(0.0, 1.0)(generator);
        long n = 0;
        const long limit = stretches * steps_per_stretch;
        while (n < limit && x >= 0.0 && x <= 1.0) {
          x = a * std::min(x, 1.0 - x);
          ++n;
        }
        batch.cost += n * step;
        if (x < 0.0 || x > 1.0) {
          o.escape_stretch.push_back(static_cast<int>((n + steps_per_stretch - 1) / steps_per_stretch));
        } else {
          ++o.stayed;
        }
      }
      batch.observations.push_back(o);
    }
    return batch;
  }

  // The exact leave distribution of a run through `schedule` with `dwell` per value: the median.
  double TrueMedian(const std::vector<double>& schedule, double dwell) const {
    double stay = 1.0;
    for (double p : schedule) {
      stay *= std::exp(-Rate(p) * dwell);
      if (stay <= 0.5) return p;
    }
    return kNaN;
  }
};

// A run-up in 1-unit steps, 1.5 s per value, from 160 to 200; ensembles allowed at 165 … 195.
EscapeDesignOptions RunUp(const TentCrisis& tent, double first) {
  EscapeDesignOptions o;
  for (double p = 160.0; p <= 200.0; p += 1.0) o.schedule.push_back(p);
  o.dwell = 1.5;
  for (double p = 165.0; p <= 195.0; p += 1.0) o.candidates.push_back(p);
  o.first = first;
  o.copies = 8;
  o.min_duration = 1.0;
  o.max_duration = 40.0;
  o.target_width = 2.0;
  o.budget = 3000.0;
  (void)tent;
  return o;
}

TEST_CASE("tent map past its crisis: lifetimes are exponential at the closed-form rate") {
  const TentCrisis tent;
  EscapeRequest r;
  r.parameter = 181.6;  // κ = 0.01·10² = 1 /s
  r.copies = 2000;
  r.duration = 5.0;
  r.seed = 11;
  const EscapeRate rate = EstimateEscapeRate(tent.Run({r}).observations.front());
  CHECK(rate.lower < 1.0);
  CHECK(rate.upper > 1.0);
  CHECK(std::abs(rate.rate - 1.0) < 0.07);  // 2000 copies: 3 standard errors ≈ 0.067
}

TEST_CASE("escape design: the median of a run-up's leave value, within the requested width") {
  const TentCrisis tent;
  const double truth = tent.TrueMedian(RunUp(tent, 179.0).schedule, 1.5);
  REQUIRE(truth == 177.0);  // 1 − e^{−1.5·Σκ} is 0.40 at 176 and 0.64 at 177
  int covered = 0, critical_covered = 0, converged = 0;
  const int designs = 12;
  double cost = 0.0;
  for (int k = 0; k < designs; ++k) {
    EscapeDesignOptions o = RunUp(tent, 179.0);
    o.seed = 100 + 7919 * static_cast<std::uint64_t>(k);
    const EscapeDesign d = RunEscapeDesign(o, [&](const std::vector<EscapeRequest>& q) { return tent.Run(q); });
    INFO(d.BriefReport());
    if (d.status == EscapeDesignStatus::kConverged) {
      ++converged;
      CHECK(d.median_upper - d.median_lower <= o.target_width + 1e-9);
    }
    if (d.median_lower <= truth && truth <= d.median_upper) ++covered;
    // The law's p_c interval, where bounded, holds the true critical value.
    CHECK(d.fit.status == CrisisStatus::kLocated);
    if ((!d.fit.lower_bounded || d.fit.critical_lower <= tent.critical) &&
        (!d.fit.upper_bounded || d.fit.critical_upper >= tent.critical)) {
      ++critical_covered;
    }
    cost += d.cost;
  }
  CHECK(converged == designs);
  // The median's interval covered the truth in 198 of 200 designs of this kind, p_c's in 183 of
  // 200 (sweeps/escape_design.h): at most 2 and 3 misses of 12 (each P < 0.02 at those rates).
  CHECK(covered >= designs - 2);
  CHECK(critical_covered >= designs - 3);
  // Far less than a fixed grid that resolves the same: 31 values × 16 copies × 5 s = 2480 s.
  CHECK(cost / designs < 1200.0);
}

TEST_CASE("escape design: stops when the budget is spent, and says so") {
  const TentCrisis tent;
  EscapeDesignOptions o = RunUp(tent, 179.0);
  o.budget = 60.0;
  o.target_width = 0.5;  // below the grid's step: only the budget can stop it
  const EscapeDesign d = RunEscapeDesign(o, [&](const std::vector<EscapeRequest>& q) { return tent.Run(q); });
  CHECK(d.status == EscapeDesignStatus::kBudget);
  CHECK(d.cost >= o.budget);
  // No batch starts once the budget is spent: the last one began below it.
  double before_last = 0.0;
  const EscapeDesign shorter = [&] {
    EscapeDesignOptions p = o;
    p.max_rounds = d.rounds - 1;
    return RunEscapeDesign(p, [&](const std::vector<EscapeRequest>& q) { return tent.Run(q); });
  }();
  before_last = shorter.cost;
  CHECK(before_last < o.budget);
  CHECK_THAT(d.BriefReport(), Contains("budget spent"));
}

TEST_CASE("escape design: a state that never leaves is reported, not located") {
  TentCrisis tent;
  tent.critical = 400.0;  // beyond every candidate: no escapes at all
  EscapeDesignOptions o = RunUp(tent, 179.0);
  o.max_duration = 8.0;
  const EscapeDesign d = RunEscapeDesign(o, [&](const std::vector<EscapeRequest>& q) { return tent.Run(q); });
  CHECK(d.status == EscapeDesignStatus::kNoEscape);
  CHECK(std::isnan(d.leave.median));
  CHECK_THAT(d.message, Contains("no copy left"));
}

TEST_CASE("escape design: the mirror image, a state that ends going down") {
  // κ(p) = A (p_c − p)^γ below p_c = 60.4 (the mirror p ↦ 232 − p of the run-up's law): a
  // run-down from 80 leaves it at 55 (the mirror of 177).
  const TentCrisis up;
  auto run = [&](const std::vector<EscapeRequest>& q) {
    std::vector<EscapeRequest> mirrored = q;
    for (EscapeRequest& r : mirrored) r.parameter = 232.0 - r.parameter;
    EscapeBatch b = up.Run(mirrored);
    for (std::size_t i = 0; i < q.size(); ++i) b.observations[i].parameter = q[i].parameter;
    return b;
  };
  EscapeDesignOptions o;
  o.side = CrisisSide::kBelow;
  for (double p = 80.0; p >= 30.0; p -= 1.0) o.schedule.push_back(p);
  for (double p = 66.0; p >= 36.0; p -= 1.0) o.candidates.push_back(p);
  o.first = 53.0;
  o.min_duration = 1.0;
  o.target_width = 2.0;
  o.budget = 3000.0;
  const EscapeDesign d = RunEscapeDesign(o, run);
  INFO(d.BriefReport());
  CHECK(d.status == EscapeDesignStatus::kConverged);
  CHECK(d.median_lower <= 55.0 + 1e-9);
  CHECK(d.median_upper >= 55.0 - 1e-9);
  CHECK(d.fit.critical < 63.0);
  CHECK(d.fit.critical > 57.0);
}

TEST_CASE("escape times: the tent map's are exponential, a passage's are not") {
  const TentCrisis tent;
  EscapeRequest r;
  r.parameter = 178.0;  // κ ≈ 0.41 /s
  r.copies = 40;
  r.duration = 6.0;
  r.seed = 5;
  const LifetimeShape leak = CheckExponential(tent.Run({r}).observations);
  CHECK(leak.resolved);
  CHECK(leak.exponential);
  CHECK(leak.largest_ratio > 0.7);
  // Every copy leaves 1.2–1.5 s after the start: a deterministic drift past a bifurcation.
  EscapeObservations passage;
  passage.parameter = 40.0;
  passage.stretch = 0.1;
  passage.duration = 6.0;
  for (int i = 0; i < 12; ++i) passage.escape_stretch.push_back(12 + i % 4);
  const LifetimeShape drift = CheckExponential({passage});
  CHECK(drift.resolved);
  CHECK_FALSE(drift.exponential);
  CHECK_THAT(drift.message, Contains("passage"));
  // All in the first stretch: nothing to say about the shape.
  EscapeObservations immediate = passage;
  immediate.escape_stretch.assign(12, 1);
  CHECK_FALSE(CheckExponential({immediate}).resolved);
}

TEST_CASE("escape design: options are checked, naming the field") {
  EscapeDesignOptions o;
  o.schedule = {1.0, 2.0};
  o.candidates = {1.0, 2.0};
  o.first = 3.0;
  CHECK_THROWS_WITH(Validate(o), Contains("first = 3") && Contains("one of the candidates"));
  o.first = 2.0;
  o.dwell = 0.0;
  CHECK_THROWS_WITH(Validate(o), Contains("dwell = 0"));
  o.dwell = 1.0;
  o.candidates = {1.0, 1.0};
  o.first = 1.0;
  CHECK_THROWS_WITH(Validate(o), Contains("distinct"));
}

}  // namespace
}  // namespace rubcont
