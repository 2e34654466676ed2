#include "sweeps/escape_design.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "solvers/constants.h"

namespace rubcont {
namespace {

// Seeds of request r of batch k: seed + 1000·(16k + r) + copy (copies ≤ 1000, requests ≤ 16).
constexpr std::uint64_t kSeedsPerRequest = 1000;
constexpr int kRequestsPerBatch = 16;
constexpr double kAlwaysLeaves = 3.0;  // κ·dwell beyond which a value's rate no longer matters

// The position of p along the state's side: grows towards where the state ends.
double Along(CrisisSide side, double p) { return side == CrisisSide::kAbove ? p : -p; }

// What the design knows at one candidate value.
struct Site {
  double parameter = 0.0;
  std::vector<int> groups;  // indices into the observations
  int escapes = 0;
  double exposure = 0.0;    // Σ (j − 1)Δ + stayed·T over its groups [s]
  double longest = 0.0;     // the longest duration measured [s]
  bool finite = false;      // some copy was seen to stay for a while (exposure > 0)
};

// The profile-likelihood interval of the leave distribution's median (header comment). The law's
// parameters θ = (p_c, γ, a = ln A') with κ = A'·u^γ, u = (p − p_c)/span on the state's mirrored
// side: the region R = {θ : ℓ(θ) ≥ ℓ_max − 1.92} is scanned on a grid of (p_c, γ) — for each, ℓ is
// concave in a, so its maximum and the a-interval inside R follow by bisection — and since the
// cumulative hazard H_i = dwell·Σ_{j≤i} κ(p_j) is A'·S_i(p_c, γ), linear in A', its extremes over R
// are at the ends of those a-intervals. The median is the first i with H_i ≥ ln 2, so the plausible
// medians run from the first i with max_R H_i ≥ ln 2 to the first i with min_R H_i ≥ ln 2.
struct MedianRange {
  int lower = -1;  // schedule indices; n (the schedule's size): beyond it; −1: no region
  int upper = -1;
};

MedianRange MedianRangeOf(const std::vector<EscapeObservations>& observations, const CrisisFit& fit,
                          const EscapeDesignOptions& o, const CrisisOptions& crisis) {
  // The scaling FitCrisis uses: the mirrored parameters' span, p_c up to the first escape.
  double low = kInfinity, high = -kInfinity, first = kInfinity;
  for (const EscapeObservations& e : observations) {
    const double p = Along(o.side, e.parameter);
    low = std::min(low, p);
    high = std::max(high, p);
    if (!e.escape_stretch.empty()) first = std::min(first, p);
  }
  const double span = high - low;
  const double c_hi = first - 1e-6 * span, c_lo = first - crisis.search_range * span;
  const double threshold = fit.log_likelihood - 1.920729410347062;
  const int groups = static_cast<int>(observations.size());
  std::vector<double> u(static_cast<std::size_t>(groups)), w(u.size());
  auto log_likelihood = [&](double a) {
    double sum = 0.0;
    for (int g = 0; g < groups; ++g) {
      const std::size_t k = static_cast<std::size_t>(g);
      sum += EscapeLogLikelihood(observations[k], w[k] > 0.0 ? std::exp(a) * w[k] : 0.0);
    }
    return sum;
  };
  auto slope = [&](double a) {  // dℓ/da, decreasing (ℓ is concave in a)
    double sum = 0.0;
    for (int g = 0; g < groups; ++g) {
      const std::size_t k = static_cast<std::size_t>(g);
      if (!(w[k] > 0.0)) continue;
      const EscapeObservations& e = observations[k];
      const double rate = std::exp(a) * w[k];
      const double x = rate * e.stretch;
      sum += -rate * Exposure(e) + (x > 0.0 ? e.escape_stretch.size() * x / std::expm1(x) : 0.0);
    }
    return sum;
  };
  auto bisect = [](auto f, double a, double b) {  // f(a) > 0 ≥ f(b)
    for (int i = 0; i < 60; ++i) {
      const double m = 0.5 * (a + b);
      (f(m) > 0.0 ? a : b) = m;
    }
    return 0.5 * (a + b);
  };
  const std::size_t n = o.schedule.size();
  std::vector<double> h_max(n, 0.0), h_min(n, kInfinity);
  bool any = false;
  constexpr int kCriticalPoints = 81, kExponentPoints = 61;
  constexpr double kLow = -60.0, kHigh = 60.0;  // a's search range
  for (int ic = 0; ic < kCriticalPoints; ++ic) {
    const double c = c_lo + (c_hi - c_lo) * ic / (kCriticalPoints - 1.0);
    for (int ig = 0; ig < kExponentPoints; ++ig) {
      const double gamma = crisis.min_exponent *
                           std::pow(crisis.max_exponent / crisis.min_exponent, ig / (kExponentPoints - 1.0));
      for (int g = 0; g < groups; ++g) {
        const double v = (Along(o.side, observations[static_cast<std::size_t>(g)].parameter) - c) / span;
        u[static_cast<std::size_t>(g)] = v;
        w[static_cast<std::size_t>(g)] = v > 0.0 ? std::pow(v, gamma) : 0.0;
      }
      if (!(slope(kLow) > 0.0) || slope(kHigh) > 0.0) continue;
      const double top = bisect(slope, kLow, kHigh);
      if (!(log_likelihood(top) >= threshold)) continue;
      const double a_lo = log_likelihood(kLow) >= threshold
                              ? kLow
                              : bisect([&](double a) { return -(log_likelihood(a) - threshold); }, kLow, top);
      const double a_hi = log_likelihood(kHigh) >= threshold
                              ? kHigh
                              : bisect([&](double a) { return log_likelihood(a) - threshold; }, top, kHigh);
      any = true;
      double sum = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double v = (Along(o.side, o.schedule[i]) - c) / span;
        if (v > 0.0) sum += o.dwell * std::pow(v, gamma);
        h_max[i] = std::max(h_max[i], std::exp(a_hi) * sum);
        h_min[i] = std::min(h_min[i], std::exp(a_lo) * sum);
      }
    }
  }
  MedianRange range;
  if (!any) return range;
  range.lower = range.upper = static_cast<int>(n);
  const double half = std::log(2.0);
  for (std::size_t i = n; i-- > 0;) {
    if (h_max[i] >= half) range.lower = static_cast<int>(i);
    if (h_min[i] >= half) range.upper = static_cast<int>(i);
  }
  return range;
}

}  // namespace

void Validate(const EscapeDesignOptions& o) {
  auto fail = [](const char* field, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("EscapeDesignOptions.{} = {}: {}", field, value, rule));
  };
  if (o.schedule.empty()) fail("schedule", "[]", "must hold at least one value");
  for (double p : o.schedule) {
    if (!std::isfinite(p)) fail("schedule", p, "must be finite");
  }
  if (!(o.dwell > 0.0) || !std::isfinite(o.dwell)) fail("dwell", o.dwell, "must be positive");
  if (o.candidates.size() < 2) fail("candidates", o.candidates.size(), "must hold at least two values");
  std::vector<double> sorted = o.candidates;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (!std::isfinite(sorted[i])) fail("candidates", sorted[i], "must be finite");
    if (i > 0 && sorted[i] == sorted[i - 1]) fail("candidates", sorted[i], "must be distinct");
  }
  if (std::find(o.candidates.begin(), o.candidates.end(), o.first) == o.candidates.end()) {
    fail("first", o.first, "must be one of the candidates");
  }
  if (o.copies < 1 || o.copies > static_cast<int>(kSeedsPerRequest)) fail("copies", o.copies, "must be in 1 … 1000");
  if (!(o.min_duration > 0.0) || !std::isfinite(o.min_duration)) fail("min_duration", o.min_duration, "must be positive");
  if (!(o.max_duration >= o.min_duration) || !std::isfinite(o.max_duration)) {
    fail("max_duration", o.max_duration, "must be finite and at least min_duration");
  }
  if (!(o.target_width > 0.0) || !std::isfinite(o.target_width)) fail("target_width", o.target_width, "must be positive");
  if (!(o.budget > 0.0) || !std::isfinite(o.budget)) fail("budget", o.budget, "must be positive");
  if (o.max_rounds < 1) fail("max_rounds", o.max_rounds, "must be at least 1");
  if (o.min_escapes < 0) fail("min_escapes", o.min_escapes, "must be non-negative");
  if (!(o.floor_hazard > 0.0) || !std::isfinite(o.floor_hazard)) fail("floor_hazard", o.floor_hazard, "must be positive");
}

const char* ToString(EscapeDesignStatus status) {
  switch (status) {
    case EscapeDesignStatus::kConverged: return "converged";
    case EscapeDesignStatus::kBudget: return "budget spent";
    case EscapeDesignStatus::kRounds: return "rounds spent";
    case EscapeDesignStatus::kNoEscape: return "no escape";
    case EscapeDesignStatus::kNoLaw: return "no law";
  }
  return "?";
}

LeaveDistribution PredictLeave(const CrisisFit& fit, CrisisSide side, const std::vector<double>& schedule,
                               double dwell) {
  LeaveDistribution d;
  d.low = d.median = d.high = kNaN;
  if (fit.status != CrisisStatus::kLocated) {
    d.probability.assign(schedule.size(), kNaN);
    d.stay = kNaN;
    return d;
  }
  d.probability = SweepLeaveProbabilities(fit, side, schedule, dwell);
  double sum = 0.0;
  for (std::size_t i = 0; i < schedule.size(); ++i) {
    sum += d.probability[i];
    if (std::isnan(d.low) && sum >= 0.05) d.low = schedule[i];
    if (std::isnan(d.median) && sum >= 0.5) d.median = schedule[i];
    if (std::isnan(d.high) && sum >= 0.95) d.high = schedule[i];
  }
  d.stay = std::max(0.0, 1.0 - sum);
  return d;
}

LeaveMedianInterval MedianInterval(const std::vector<EscapeObservations>& observations, const CrisisFit& fit,
                                   CrisisSide side, const std::vector<double>& schedule, double dwell) {
  LeaveMedianInterval interval;
  interval.lower = interval.upper = kNaN;
  if (fit.status != CrisisStatus::kLocated) {
    interval.open = "no law";
    return interval;
  }
  EscapeDesignOptions o;
  o.side = side;
  o.schedule = schedule;
  o.dwell = dwell;
  CrisisOptions crisis;
  crisis.side = side;
  const MedianRange range = MedianRangeOf(observations, fit, o, crisis);
  const int n = static_cast<int>(schedule.size());
  if (range.lower < 0) {
    interval.open = "no law within the likelihood region";
    return interval;
  }
  const double a = range.lower < n ? schedule[static_cast<std::size_t>(range.lower)] : kNaN;
  const double b = range.upper < n ? schedule[static_cast<std::size_t>(range.upper)] : kNaN;
  if (std::isnan(b)) {
    interval.open = std::isnan(a) ? "the run may keep the state to the end of the schedule"
                                  : fmt::format("from {:g} to beyond the schedule", a);
    return interval;
  }
  interval.lower = std::min(a, b);
  interval.upper = std::max(a, b);
  return interval;
}

LifetimeShape CheckExponential(const std::vector<EscapeObservations>& observations) {
  constexpr int kMinEscapes = 5;
  constexpr double kPassage = 0.5;
  LifetimeShape shape;
  shape.largest_ratio = kNaN;
  double best_at = kNaN;
  for (const EscapeObservations& o : observations) {
    const std::size_t d = o.escape_stretch.size();
    if (static_cast<int>(d) < kMinEscapes) continue;
    const EscapeRate rate = EstimateEscapeRate(o);
    if (rate.status != EscapeRateStatus::kEstimated) continue;  // all in the first stretch
    double sum = 0.0, sum2 = 0.0;
    for (int j : o.escape_stretch) {
      const double t = (j - 0.5) * o.stretch;
      sum += t;
      sum2 += t * t;
    }
    const double mean = sum / d;
    const double observed = std::sqrt(std::max(0.0, sum2 / d - mean * mean) * d / (d - 1.0)) / mean;
    // The exponential at κ conditioned on X ≤ T, plus the binning's Δ²/12.
    const double k = rate.rate, T = o.duration, q = -std::expm1(-k * T), e = std::exp(-k * T);
    const double m1 = (1.0 / k - e * (T + 1.0 / k)) / q;
    const double m2 = (2.0 / (k * k) - e * (T * T + 2.0 * T / k + 2.0 / (k * k))) / q;
    const double expected = std::sqrt(std::max(0.0, m2 - m1 * m1) + o.stretch * o.stretch / 12.0) / m1;
    const double ratio = observed / expected;
    shape.resolved = true;
    if (std::isnan(shape.largest_ratio) || ratio > shape.largest_ratio) {
      shape.largest_ratio = ratio;
      best_at = o.parameter;
    }
  }
  if (!shape.resolved) {
    shape.message = fmt::format("no ensemble with {} escapes spread over more than its first stretch: the lifetimes' "
                                "shape is not resolved", kMinEscapes);
    return shape;
  }
  shape.exponential = shape.largest_ratio >= kPassage;
  shape.message = fmt::format("escape times {} (the widest spread {:.2f} of an exponential's, at {:g})",
                              shape.exponential ? "spread as an exponential's" : "bunched at every value: a passage, not a leak",
                              shape.largest_ratio, best_at);
  return shape;
}

std::string EscapeDesign::BriefReport() const {
  std::string median = std::isnan(leave.median) ? std::string("no median")
                                                : fmt::format("median {:g}", leave.median);
  if (!std::isnan(median_lower) && !std::isnan(median_upper)) {
    median += fmt::format(" (95 % {:g} … {:g})", median_lower, median_upper);
  } else if (!median_open.empty()) {
    median += " (" + median_open + ")";
  }
  return fmt::format("{}: {} ensembles in {} batches, cost {:.1f} {}; {}{}", ToString(status),
                     observations.size(), rounds, cost, cost_unit, median, message.empty() ? "" : "; " + message);
}

EscapeDesign RunEscapeDesign(const EscapeDesignOptions& o, const EscapeRunner& run,
                             const std::function<void(const std::string&)>& progress) {
  Validate(o);
  EscapeDesign design;
  design.median_lower = design.median_upper = kNaN;
  design.cost_unit = o.cost_unit;
  auto note = [&](std::string line) {
    if (progress) progress(line);
    design.log.push_back(std::move(line));
  };

  // The candidates along the state's side: sites[0] deepest in the state, the last beyond `first`.
  std::vector<Site> sites;
  for (double p : o.candidates) {
    Site site;
    site.parameter = p;
    sites.push_back(site);
  }
  std::sort(sites.begin(), sites.end(),
            [&](const Site& a, const Site& b) { return Along(o.side, a.parameter) < Along(o.side, b.parameter); });
  int first = 0;
  while (sites[static_cast<std::size_t>(first)].parameter != o.first) ++first;

  CrisisOptions crisis;
  crisis.side = o.side;

  // Measures `requests` (one batch) and books them.
  auto measure = [&](std::vector<std::pair<int, double>> requests, const std::string& why) {
    std::vector<EscapeRequest> batch;
    for (std::size_t r = 0; r < requests.size() && static_cast<int>(r) < kRequestsPerBatch; ++r) {
      EscapeRequest q;
      q.parameter = sites[static_cast<std::size_t>(requests[r].first)].parameter;
      q.copies = o.copies;
      q.duration = std::clamp(requests[r].second, o.min_duration, o.max_duration);
      q.seed = o.seed + kSeedsPerRequest * static_cast<std::uint64_t>(design.rounds * kRequestsPerBatch + static_cast<int>(r));
      batch.push_back(q);
    }
    const EscapeBatch outcome = run(batch);
    if (outcome.observations.size() != batch.size()) {
      throw std::logic_error(fmt::format("escape design: the runner returned {} observations for {} requests",
                                         outcome.observations.size(), batch.size()));
    }
    design.cost += outcome.cost;
    ++design.rounds;
    std::string line = fmt::format("batch {} ({}):", design.rounds, why);
    for (std::size_t r = 0; r < batch.size(); ++r) {
      const EscapeObservations& e = outcome.observations[r];
      Site& s = sites[static_cast<std::size_t>(requests[r].first)];
      s.groups.push_back(static_cast<int>(design.observations.size()));
      s.escapes += static_cast<int>(e.escape_stretch.size());
      s.exposure += Exposure(e);
      s.finite = s.finite || Exposure(e) > 0.0;
      s.longest = std::max(s.longest, e.duration);
      design.observations.push_back(e);
      line += fmt::format(" {} copies × {:.3g} s at {:g}: {} left;", batch[r].copies, e.duration, e.parameter,
                          e.escape_stretch.size());
    }
    line += fmt::format(" cost {:.1f} {} of {:.1f} {}", design.cost, o.cost_unit, o.budget, o.cost_unit);
    note(line);
  };
  auto spent = [&] { return design.cost >= o.budget; };
  // The site's rate from all its ensembles (EstimateEscapeRate pooled).
  auto rate_of = [&](const Site& s) {
    std::vector<EscapeObservations> groups;
    for (int g : s.groups) groups.push_back(design.observations[static_cast<std::size_t>(g)]);
    return EstimateEscapeRate(groups);
  };
  // What the data lack before an interval may be trusted (the law's interval is asymptotic and
  // assumes the law; a few copies near p_c give intervals that exclude the truth): "" when nothing.
  auto evidence = [&]() -> std::string {
    int escapes = 0;
    for (const Site& s : sites) escapes += s.escapes;
    if (escapes < o.min_escapes) return fmt::format("{} escapes of the {} needed", escapes, o.min_escapes);
    for (const Site& s : sites) {
      if (s.groups.empty()) continue;
      if (!std::isnan(design.median_lower) &&
          Along(o.side, s.parameter) >= Along(o.side, o.side == CrisisSide::kAbove ? design.median_lower
                                                                                    : design.median_upper)) {
        break;
      }
      if (rate_of(s).upper * o.dwell <= o.floor_hazard) return "";
    }
    // The first candidate leaks too fast for any exposure to bound it: no floor can be measured
    // (the run was not seen on the state before it); the interval then rests on the law, said so.
    const Site& deepest = sites.front();  // the first candidate: nothing lies further towards the state
    if (!deepest.groups.empty() && rate_of(deepest).rate * o.dwell > 0.5 * o.floor_hazard) {
      design.message = fmt::format("no floor: the first value the state was seen at ({:g}) already leaks at {:.3g} "
                                   "per dwell; the median's interval towards the state rests on the law",
                                   deepest.parameter, rate_of(deepest).rate * o.dwell);
      return "";
    }
    return fmt::format("no value before the median's interval with a hazard bounded by {:g} per dwell", o.floor_hazard);
  };
  auto measured = [&](int i) { return !sites[static_cast<std::size_t>(i)].groups.empty(); };

  // Bracketing: `first` and its two neighbours towards the state.
  {
    std::vector<std::pair<int, double>> start;
    for (int i = first; i >= 0 && i > first - 3; --i) start.push_back({i, o.min_duration});
    measure(start, "the value the run was seen to leave at, and the two before it");
  }

  while (true) {
    design.fit = FitCrisis(design.observations, crisis);
    if (design.fit.status == CrisisStatus::kLocated) {
      design.leave = PredictLeave(design.fit, o.side, o.schedule, o.dwell);
      // The median's profile-likelihood interval.
      const LeaveMedianInterval interval =
          MedianInterval(design.observations, design.fit, o.side, o.schedule, o.dwell);
      design.median_lower = interval.lower;
      design.median_upper = interval.upper;
      design.median_open = interval.open;
      const double width = std::abs(design.median_upper - design.median_lower);
      note(fmt::format("  law: p_c = {:.4g}, γ = {:.3g}; leave median {:g}, 5–95 % {:g} … {:g}; median's 95 % {:g} … {:g}{}",
                       design.fit.critical, design.fit.exponent, design.leave.median, design.leave.low,
                       design.leave.high, design.median_lower, design.median_upper,
                       design.median_open.empty() ? "" : " (" + design.median_open + ")"));
      if (std::isfinite(width) && width <= o.target_width + 1e-9 * std::abs(o.target_width) && evidence().empty()) {
        design.status = EscapeDesignStatus::kConverged;
        break;
      }
    } else {
      note(fmt::format("  law: {} ({})", ToString(design.fit.status), design.fit.message));
    }
    if (spent()) {
      design.status = EscapeDesignStatus::kBudget;
      break;
    }
    if (design.rounds >= o.max_rounds) {
      design.status = EscapeDesignStatus::kRounds;
      break;
    }

    // The next ensemble.
    const int count = static_cast<int>(sites.size());
    int deepest = -1;  // the measured site deepest in the state
    for (int i = 0; i < count && deepest < 0; ++i)
      if (measured(i)) deepest = i;
    bool any_escape = false;
    for (const Site& s : sites) any_escape = any_escape || s.escapes > 0;
    if (!any_escape) {
      // Nothing left anywhere: longer copies at `first`; at the longest, the value furthest from
      // the state; if none leaves there either, the state does not end within the candidates.
      const Site& at_first = sites[static_cast<std::size_t>(first)];
      const Site& furthest = sites.back();
      if (at_first.longest < o.max_duration) {
        measure({{first, 2.0 * at_first.longest}}, "no copy has left yet: longer copies");
        continue;
      }
      if (furthest.longest < o.max_duration) {
        measure({{count - 1, o.max_duration}}, "no copy has left yet: the value furthest from the state");
        continue;
      }
      design.status = EscapeDesignStatus::kNoEscape;
      design.message = fmt::format("no copy left the state within {:g} s at {:g} or {:g}", o.max_duration,
                                   at_first.parameter, furthest.parameter);
      break;
    }
    if (design.fit.status == CrisisStatus::kFailed) {
      design.status = EscapeDesignStatus::kNoLaw;
      design.message = design.fit.message;
      break;
    }
    if (design.fit.status != CrisisStatus::kLocated) {
      // Too few values with escapes, or rates without a critical point: go towards the state.
      if (deepest > 0 && (sites[static_cast<std::size_t>(deepest)].escapes > 0 ||
                          design.fit.status == CrisisStatus::kNotBracketed)) {
        measure({{deepest - 1, o.min_duration}}, "no law yet: the next value towards the state");
        continue;
      }
      // The values towards the state have no escapes: longer copies at the nearest one without
      // (where every copy left in its first stretch, longer copies would tell nothing more).
      int target = -1;
      for (int i = first; i >= 0 && target < 0; --i) {
        const Site& s = sites[static_cast<std::size_t>(i)];
        if (measured(i) && s.escapes == 0 && s.longest < o.max_duration) target = i;
      }
      if (target < 0) {
        design.status = EscapeDesignStatus::kNoLaw;
        bool sharp = true;
        for (const Site& s : sites) sharp = sharp && (s.escapes == 0 || !s.finite);
        design.message = sharp ? fmt::format("a sharp change, no lifetime: where copies left, every one left in its first "
                                             "stretch; where none did, none within {:g} s", o.max_duration)
                               : fmt::format("{} ({})", ToString(design.fit.status), design.fit.message);
        break;
      }
      const Site& s = sites[static_cast<std::size_t>(target)];
      measure({{target, 2.0 * s.longest}}, "no law yet: longer copies where none left");
      continue;
    }
    // A law: bracket from the state's side first (a measured value deepest in the state that
    // still leaks leaves p_c open below), then where the median's uncertainty comes from.
    if (deepest > 0 && sites[static_cast<std::size_t>(deepest)].escapes > 0) {
      const double rate = CrisisRate(design.fit, o.side, sites[static_cast<std::size_t>(deepest - 1)].parameter);
      measure({{deepest - 1, rate > 0.0 ? 2.0 / rate : 2.0 * sites[static_cast<std::size_t>(deepest)].longest}},
              "the value deepest in the state still leaks: the next one towards it");
      continue;
    }
    // The floor: a value before the median's interval whose hazard per dwell is bounded small
    // (so that the interval does not rest on the law's extrapolation towards the state).
    if (evidence().rfind("no value before", 0) == 0 && deepest >= 0) {
      const Site& s = sites[static_cast<std::size_t>(deepest)];
      if (deepest > 0 && rate_of(s).rate * o.dwell > 0.5 * o.floor_hazard) {
        measure({{deepest - 1, 2.0 * s.longest}},
                "a floor: the value deepest in the state leaks too fast to bound; the next one towards it");
      } else {
        measure({{deepest, s.longest >= o.max_duration ? o.max_duration : 2.0 * s.longest}},
                "a floor: longer copies at the value deepest in the state");
      }
      continue;
    }
    // Score: (κD)² / escapes per unit cost over the values the run can still be on at the 95 %
    // point (sensitivity of the cumulative hazard), an unmeasured value with hazard first.
    int high = count - 1;
    for (int i = 0; i < count; ++i) {
      if (!std::isnan(design.leave.high) && Along(o.side, sites[static_cast<std::size_t>(i)].parameter) >
                                                Along(o.side, design.leave.high)) {
        high = i;
        break;
      }
    }
    int best = -1;
    double best_score = 0.0, best_duration = 0.0;
    for (int i = 0; i <= high; ++i) {
      const Site& s = sites[static_cast<std::size_t>(i)];
      const double rate = CrisisRate(design.fit, o.side, s.parameter);
      const double hazard = std::min(rate * o.dwell, kAlwaysLeaves);
      if (!(hazard > 0.0)) continue;
      const double duration = std::clamp(2.0 / rate, o.min_duration, o.max_duration);
      const double expected = o.copies * -std::expm1(-rate * duration);
      const double cost = o.copies * -std::expm1(-rate * duration) / rate;
      const double gain = s.escapes == 0 ? 1e300 : hazard * hazard * (1.0 / s.escapes - 1.0 / (s.escapes + expected));
      const double score = gain / cost;
      if (score > best_score) {
        best = i;
        best_score = score;
        best_duration = duration;
      }
    }
    if (best < 0) {
      design.status = EscapeDesignStatus::kNoLaw;
      design.message = "the fitted law gives no value with a hazard to measure";
      break;
    }
    measure({{best, best_duration}}, "where the median's uncertainty comes from");
  }

  // The last fit (with its profile interval of p_c) and its prediction.
  design.leave = PredictLeave(design.fit, o.side, o.schedule, o.dwell);
  if (design.fit.status != CrisisStatus::kLocated && design.message.empty()) {
    design.message = fmt::format("{} ({})", ToString(design.fit.status), design.fit.message);
  }
  return design;
}

}  // namespace rubcont
