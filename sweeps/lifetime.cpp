#include "sweeps/lifetime.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>
#include <nlopt.hpp>

#include "solvers/constants.h"

namespace rubcont {
namespace {

constexpr double kDrop = 1.920729410347062;  // χ²₁(0.95)/2: the likelihood-ratio 95 % limit

// The root of f(x) = 0 between a (f < 0) and b (f ≥ 0) by bisection.
template <class F>
double Bisect(F f, double a, double b, int iterations = 80) {
  for (int i = 0; i < iterations; ++i) {
    const double m = 0.5 * (a + b);
    (f(m) < 0.0 ? a : b) = m;
  }
  return 0.5 * (a + b);
}

// The observations seen from the side where the state ends: p → −p for kBelow, so that the rate
// always grows with the (mirrored) parameter.
double Mirror(CrisisSide side, double p) { return side == CrisisSide::kAbove ? p : -p; }

struct Model {
  const std::vector<EscapeObservations>* observations;
  CrisisSide side;
  double span;
  int evaluations = 0;

  // ℓ(p_c, γ, a), κ_s = e^a · ((p_s − p_c)/span)^γ on the side where it ends.
  double LogLikelihood(double critical, double exponent, double log_amplitude) {
    ++evaluations;
    double sum = 0.0;
    for (const EscapeObservations& o : *observations) {
      const double u = (Mirror(side, o.parameter) - critical) / span;
      const double rate = u > 0.0 ? std::exp(log_amplitude + exponent * std::log(u)) : 0.0;
      sum += EscapeLogLikelihood(o, rate);
    }
    return sum;
  }
};

struct Maximum {
  std::vector<double> x;
  double value = -kInfinity;
  int code = 0;
};

Maximum Maximize(nlopt::opt& opt, std::vector<double> x) {
  Maximum m;
  double f = 0.0;
  try {
    m.code = static_cast<int>(opt.optimize(x, f));
  } catch (const nlopt::roundoff_limited&) {
    f = opt.last_optimum_value();
    m.code = static_cast<int>(nlopt::ROUNDOFF_LIMITED);
  } catch (const std::exception&) {
    m.code = static_cast<int>(nlopt::FAILURE);
    return m;
  }
  m.x = x;
  m.value = f;  // the objective's maximum (set_max_objective)
  return m;
}

}  // namespace

// E = Σ (j − 1)·Δ + stayed·duration: the time during which every copy is known to have stayed.
double Exposure(const EscapeObservations& o) {
  double e = o.stayed * o.duration;
  for (int j : o.escape_stretch) e += (j - 1) * o.stretch;
  return e;
}

void Validate(const EscapeObservations& o) {
  auto fail = [](const char* field, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("EscapeObservations.{} = {}: {}", field, value, rule));
  };
  if (!std::isfinite(o.parameter)) fail("parameter", o.parameter, "must be finite");
  if (!(o.stretch > 0.0) || !std::isfinite(o.stretch)) fail("stretch", o.stretch, "must be positive");
  if (!(o.duration >= o.stretch * (1.0 - 1e-9)) || !std::isfinite(o.duration)) {
    fail("duration", o.duration, "must be at least one stretch");
  }
  if (o.stayed < 0) fail("stayed", o.stayed, "must be non-negative");
  const double last = std::round(o.duration / o.stretch);
  for (int j : o.escape_stretch) {
    if (j < 1 || j > last) fail("escape_stretch", j, "must be within 1 … duration/stretch");
  }
  if (o.escape_stretch.empty() && o.stayed == 0) fail("stayed", o.stayed, "no copies: nothing observed");
}

double EscapeLogLikelihood(const EscapeObservations& o, double rate) {
  const double d = static_cast<double>(o.escape_stretch.size());
  const double exposure = Exposure(o);
  if (rate == kInfinity) return exposure > 0.0 ? -kInfinity : 0.0;
  // log P(escape in ((j−1)Δ, jΔ]) = −κ(j−1)Δ + log(1 − e^{−κΔ}); log P(stay to T) = −κT.
  const double interval = d > 0.0 ? d * std::log(-std::expm1(-rate * o.stretch)) : 0.0;
  return -rate * exposure + interval;
}

const char* ToString(EscapeRateStatus status) {
  switch (status) {
    case EscapeRateStatus::kEstimated: return "estimated";
    case EscapeRateStatus::kNoEscape: return "no escape";
    case EscapeRateStatus::kAllImmediate: return "all in the first stretch";
  }
  return "?";
}

EscapeRate EstimateEscapeRate(const EscapeObservations& o) {
  return EstimateEscapeRate(std::vector<EscapeObservations>{o});
}

EscapeRate EstimateEscapeRate(const std::vector<EscapeObservations>& groups) {
  if (groups.empty()) throw std::invalid_argument("EstimateEscapeRate: no observations");
  for (const EscapeObservations& g : groups) {
    Validate(g);
    if (g.parameter != groups.front().parameter || g.stretch != groups.front().stretch) {
      throw std::invalid_argument(fmt::format(
          "EstimateEscapeRate: observations at parameter {} with stretch {} pooled with parameter {} "
          "and stretch {}: pooled groups must share both", g.parameter, g.stretch,
          groups.front().parameter, groups.front().stretch));
    }
  }
  EscapeRate r;
  double exposure = 0.0;
  for (const EscapeObservations& g : groups) {
    r.escapes += static_cast<int>(g.escape_stretch.size());
    r.copies += static_cast<int>(g.escape_stretch.size()) + g.stayed;
    exposure += Exposure(g);
  }
  const double d = r.escapes, delta = groups.front().stretch;
  auto log_likelihood = [&](double rate) {
    double sum = 0.0;
    for (const EscapeObservations& g : groups) sum += EscapeLogLikelihood(g, rate);
    return sum;
  };
  if (r.escapes == 0) {
    r.status = EscapeRateStatus::kNoEscape;
    r.rate = 0.0;
    r.lower = 0.0;
    r.upper = kDrop / exposure;  // ℓ(κ) = −κE
    return r;
  }
  if (exposure == 0.0) {
    r.status = EscapeRateStatus::kAllImmediate;
    r.rate = kInfinity;
    r.upper = kInfinity;
    // ℓ(κ) = d·log(1 − e^{−κΔ}) = −1.92
    r.lower = -std::log(-std::expm1(-kDrop / d)) / delta;
    return r;
  }
  r.rate = std::log1p(d * delta / exposure) / delta;
  // Below the maximum the log-likelihood rises, above it falls: each limit is one sign change,
  // bracketed in log κ between the maximum and a point 1.92 below it.
  const double top = log_likelihood(r.rate);
  auto below = [&](double rate) { return log_likelihood(rate) - (top - kDrop); };
  const double log_rate = std::log(r.rate);
  double lo = log_rate - 1.0, hi = log_rate + 1.0;
  while (below(std::exp(lo)) >= 0.0) lo -= 1.0;
  while (below(std::exp(hi)) >= 0.0) hi += 1.0;
  r.lower = std::exp(Bisect([&](double x) { return below(std::exp(x)); }, lo, log_rate));
  r.upper = std::exp(Bisect([&](double x) { return -below(std::exp(x)); }, log_rate, hi));
  return r;
}

const char* ToString(CrisisStatus status) {
  switch (status) {
    case CrisisStatus::kLocated: return "located";
    case CrisisStatus::kTooFewSpeeds: return "too few speeds";
    case CrisisStatus::kNotBracketed: return "not bracketed";
    case CrisisStatus::kFailed: return "failed";
  }
  return "?";
}

CrisisFit FitCrisis(const std::vector<EscapeObservations>& observations, const CrisisOptions& options) {
  for (const EscapeObservations& o : observations) Validate(o);
  if (!(options.search_range > 0.0) || !(options.min_exponent > 0.0) ||
      !(options.max_exponent > options.min_exponent)) {
    throw std::invalid_argument(fmt::format(
        "CrisisOptions: search_range = {}, exponents {} … {}: the range must be positive and "
        "0 < min_exponent < max_exponent", options.search_range, options.min_exponent, options.max_exponent));
  }
  CrisisFit fit;
  const CrisisSide side = options.side;
  double first = kInfinity, low = kInfinity, high = -kInfinity;
  int escaping = 0, finite = 0;
  for (const EscapeObservations& o : observations) {
    const double p = Mirror(side, o.parameter);
    low = std::min(low, p);
    high = std::max(high, p);
    if (o.escape_stretch.empty()) continue;
    ++escaping;
    first = std::min(first, p);
    if (Exposure(o) > 0.0) ++finite;
  }
  if (escaping < 2 || finite < 1 || !(high > low)) {
    fit.status = CrisisStatus::kTooFewSpeeds;
    fit.message = fmt::format("{} parameter values with escapes ({} with a finite rate) of {}: at least 2 "
                              "(1 finite) are needed", escaping, finite, observations.size());
    return fit;
  }
  Model model{&observations, side, high - low};
  const double span = model.span;
  const double c_hi = first - 1e-6 * span;
  const double c_lo = first - options.search_range * span;

  // The maximum over (p_c, γ, a) from starts spread over the range of p_c.
  nlopt::opt full(nlopt::LN_BOBYQA, 3);
  full.set_lower_bounds({c_lo, options.min_exponent, -40.0});
  full.set_upper_bounds({c_hi, options.max_exponent, 40.0});
  full.set_max_objective([](const std::vector<double>& x, std::vector<double>&, void* data) {
    const double v = static_cast<Model*>(data)->LogLikelihood(x[0], x[1], x[2]);
    return std::isfinite(v) ? v : -1e300;
  }, &model);
  full.set_xtol_rel(1e-10);
  full.set_maxeval(4000);
  full.set_initial_step({0.05 * span, 0.25, 0.5});
  Maximum best;
  for (int k = 0; k < 12; ++k) {
    const double c = c_hi - (c_hi - c_lo) * (k + 0.5) / 12.0;
    Maximum m = Maximize(full, {c, 1.0, 0.0});
    if (m.x.empty()) continue;
    if (m.value > best.value) best = m;
  }
  fit.evaluations = model.evaluations;
  if (best.x.empty() || !std::isfinite(best.value)) {
    fit.status = CrisisStatus::kFailed;
    fit.message = "the optimizer found no finite likelihood";
    return fit;
  }
  fit.log_likelihood = best.value;
  fit.exponent = best.x[1];

  // The profile of p_c: ℓ_p(c) = max over (γ, a).
  std::vector<double> at = {best.x[1], best.x[2]};
  auto profile = [&](double c) {
    nlopt::opt inner(nlopt::LN_BOBYQA, 2);
    inner.set_lower_bounds({options.min_exponent, -40.0});
    inner.set_upper_bounds({options.max_exponent, 40.0});
    struct Data { Model* model; double c; } data{&model, c};
    inner.set_max_objective([](const std::vector<double>& x, std::vector<double>&, void* p) {
      Data* d = static_cast<Data*>(p);
      const double v = d->model->LogLikelihood(d->c, x[0], x[1]);
      return std::isfinite(v) ? v : -1e300;
    }, &data);
    inner.set_xtol_rel(1e-10);
    inner.set_maxeval(2000);
    inner.set_initial_step({0.25, 0.5});
    Maximum m = Maximize(inner, at);
    return m.x.empty() ? -kInfinity : m.value;
  };
  const double target = best.value - kDrop;
  auto excess = [&](double c) { return profile(c) - target; };
  fit.lower_bounded = excess(c_lo) < 0.0;
  fit.upper_bounded = excess(c_hi) < 0.0;
  const double lower = fit.lower_bounded ? Bisect(excess, c_lo, best.x[0], 50) : c_lo;
  const double upper =
      fit.upper_bounded ? Bisect([&](double c) { return -excess(c); }, best.x[0], c_hi, 50) : c_hi;
  fit.evaluations = model.evaluations;

  // Back to the caller's parameter: p = ±(mirrored p); A per parameter unit.
  fit.amplitude = std::exp(best.x[2]) / std::pow(span, fit.exponent);
  if (side == CrisisSide::kAbove) {
    fit.critical = best.x[0];
    fit.critical_lower = lower;
    fit.critical_upper = upper;
  } else {
    fit.critical = -best.x[0];
    fit.critical_lower = -upper;
    fit.critical_upper = -lower;
    std::swap(fit.lower_bounded, fit.upper_bounded);
  }
  if (best.x[0] - c_lo < 1e-3 * span) {
    fit.status = CrisisStatus::kNotBracketed;
    fit.message = fmt::format("the best critical value lies at the end of the search range ({:g} spans "
                              "beyond the first escape): the rates rise without a critical point",
                              options.search_range);
    return fit;
  }
  fit.status = CrisisStatus::kLocated;
  if (fit.exponent > options.max_exponent * (1.0 - 1e-6)) {
    fit.message = fmt::format("the exponent reached its bound {:g}", options.max_exponent);
  }
  return fit;
}

double CrisisRate(const CrisisFit& fit, CrisisSide side, double parameter) {
  const double u = Mirror(side, parameter) - Mirror(side, fit.critical);
  return u > 0.0 ? fit.amplitude * std::pow(u, fit.exponent) : 0.0;
}

std::vector<double> SweepLeaveProbabilities(const CrisisFit& fit, CrisisSide side,
                                            const std::vector<double>& parameters, double dwell) {
  std::vector<double> leave;
  double stay = 1.0;
  for (double p : parameters) {
    const double q = stay * -std::expm1(-CrisisRate(fit, side, p) * dwell);
    leave.push_back(q);
    stay -= q;
  }
  return leave;
}

}  // namespace rubcont
