#include "sweeps/attractor.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>

#include <Eigen/QR>
#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "sweeps/sweep.h"

namespace rubcont {
namespace {

// Intervals of length τ that cover `time` (a last partial interval counts as a whole one).
long IntervalsIn(double time, double tau) {
  return static_cast<long>(std::ceil(time / tau - 1e-9));
}

// k directions with orthonormal scaled columns: a fixed pseudo-random draw (not the first unit
// vectors, which may lie in an invariant subspace such as one contact's coordinates).
Matrix InitialDirections(const Vector& scale, int k) {
  std::mt19937_64 generator(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix draw(scale.size(), k);
  for (Index j = 0; j < draw.cols(); ++j) {
    for (Index i = 0; i < draw.rows(); ++i) draw(i, j) = uniform(generator);
  }
  const Eigen::HouseholderQR<Matrix> qr(draw);
  return scale.asDiagonal() * (qr.householderQ() * Matrix::Identity(scale.size(), k));
}

// The section's samples: the last two of each channel carried across intervals, extrema located
// by the parabola through three successive samples.
class SectionSampler {
 public:
  SectionSampler(const SampledSection& section, Index n)
      : section_(section), values_(section.count, 3), states_(n, 3), times_(3) {}

  // Adds the sample (t, x); records an extremum of any channel at the previous sample.
  void Add(double t, const Vector& x, std::vector<SectionExtremum>& out) {
    values_.col(0) = values_.col(1);
    values_.col(1) = values_.col(2);
    states_.col(0) = states_.col(1);
    states_.col(1) = states_.col(2);
    times_(0) = times_(1);
    times_(1) = times_(2);
    section_.function(x, values_.col(2));
    states_.col(2) = x;
    times_(2) = t;
    if (++seen_ < 3) return;
    for (int c = 0; c < section_.count; ++c) {
      const double s0 = values_(c, 0), s1 = values_(c, 1), s2 = values_(c, 2);
      const int kind = s0 < s1 && s1 >= s2 ? 1 : s0 > s1 && s1 <= s2 ? -1 : 0;
      if (kind == 0) continue;
      const double curvature = s0 - 2.0 * s1 + s2;
      const double theta = curvature != 0.0 ? (s0 - s2) / (2.0 * curvature) : 0.0;  // in [−½, ½]
      const Vector weights = (Vector(3) << 0.5 * theta * (theta - 1.0), 1.0 - theta * theta,
                              0.5 * theta * (theta + 1.0)).finished();
      out.push_back({c, kind, times_(1) + theta * (times_(2) - times_(1)),
                     s1 - 0.5 * theta * theta * curvature, states_ * weights});
    }
  }

 private:
  const SampledSection& section_;
  Matrix values_;  // count × 3: the last three samples
  Matrix states_;  // n × 3
  Vector times_;
  long seen_ = 0;
};

}  // namespace

const char* ToString(ExponentSign sign) {
  switch (sign) {
    case ExponentSign::kNegative: return "negative";
    case ExponentSign::kZero: return "zero";
    case ExponentSign::kPositive: return "positive";
  }
  return "?";
}

const char* ToString(AttractorStatus status) {
  switch (status) {
    case AttractorStatus::kMeasured: return "measured";
    case AttractorStatus::kIntegrationFailure: return "integration failure";
  }
  return "?";
}

void Validate(const AttractorOptions& o) {
  auto fail = [](const char* field, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("AttractorOptions.{} = {}: {}", field, value, rule));
  };
  if (!(o.discard >= 0.0) || !std::isfinite(o.discard)) fail("discard", o.discard, "must be finite and ≥ 0");
  if (!(o.duration > 0.0) || !std::isfinite(o.duration)) fail("duration", o.duration, "must be positive");
  if (o.blocks < 2) fail("blocks", o.blocks, "must be at least 2");
  if (!(o.interval > 0.0) || !(o.interval <= o.duration / o.blocks)) {
    fail("interval", o.interval, "must be positive and at most duration / blocks");
  }
  if (o.exponents < 1) fail("exponents", o.exponents, "must be at least 1");
  if (!(o.zero_tolerance >= 0.0) || !std::isfinite(o.zero_tolerance)) {
    fail("zero_tolerance", o.zero_tolerance, "must be finite and ≥ 0");
  }
  Validate(o.integrator);
}

std::vector<std::size_t> ExcursionMaxima(const std::vector<double>& extrema, double floor) {
  std::vector<std::size_t> out;
  if (extrema.empty()) return out;
  const auto [low, high] = std::minmax_element(extrema.begin(), extrema.end());
  const double level = std::max(floor, 0.5 * (*low + *high));
  const double close = level - 0.25 * (*high - *low);
  bool open = extrema.front() > close, cut = open;
  std::size_t best = 0;
  for (std::size_t i = 0; i < extrema.size(); ++i) {
    if (open && extrema[i] > extrema[best]) best = i;
    if (!open && extrema[i] > level) {
      open = true;
      best = i;
    } else if (open && extrema[i] < close) {
      if (!cut) out.push_back(best);
      open = cut = false;
    }
  }
  return out;
}

int SectionPeriod(const std::vector<double>& values, double tolerance, int max_period) {
  const std::size_t first = values.size() / 2;
  if (max_period < 1 || values.size() - first < 2 * static_cast<std::size_t>(max_period)) return 0;
  for (int p = 1; p <= max_period; ++p) {
    bool periodic = true;
    for (std::size_t j = first; j + static_cast<std::size_t>(p) < values.size() && periodic; ++j) {
      periodic = std::abs(values[j + static_cast<std::size_t>(p)] - values[j]) <= tolerance;
    }
    if (periodic) return p;
  }
  return 0;
}

SectionDimension MeasureSectionDimension(const Matrix& points) {
  const Index m = points.cols();
  if (m < 17) {
    throw std::invalid_argument(
        fmt::format("MeasureSectionDimension: {} points: need at least 17", m));
  }
  auto distance = [&](Index i, Index j) { return (points.col(i) - points.col(j)).norm(); };
  auto median = [](std::vector<double> values) {
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
  };
  std::vector<double> nearest, apart, fourth, sixteenth;
  std::vector<std::pair<double, Index>> others(static_cast<std::size_t>(m - 1));
  for (Index i = 0; i < m; ++i) {
    for (Index j = 0, o = 0; j < m; ++j) {
      if (j != i) others[static_cast<std::size_t>(o++)] = {distance(i, j), j};
    }
    std::partial_sort(others.begin(), others.begin() + 16, others.end());
    nearest.push_back(others[0].first);
    apart.push_back(static_cast<double>(std::abs(others[0].second - i)));
    fourth.push_back(others[3].first);
    sixteenth.push_back(others[15].first);
  }
  SectionDimension result;
  result.nearest = median(nearest);
  result.apart = median(apart);
  result.fourth = median(fourth);
  result.sixteenth = median(sixteenth);
  result.dimension = std::log(4.0) / std::log(result.sixteenth / result.fourth);
  std::vector<int> piece(static_cast<std::size_t>(m), -1);
  for (Index seed = 0; seed < m; ++seed) {
    if (piece[static_cast<std::size_t>(seed)] >= 0) continue;
    std::vector<Index> stack = {seed};
    piece[static_cast<std::size_t>(seed)] = result.pieces;
    while (!stack.empty()) {
      const Index i = stack.back();
      stack.pop_back();
      for (Index j = 0; j < m; ++j) {
        if (piece[static_cast<std::size_t>(j)] < 0 && distance(i, j) < 3.0 * result.fourth) {
          piece[static_cast<std::size_t>(j)] = result.pieces;
          stack.push_back(j);
        }
      }
    }
    ++result.pieces;
  }
  return result;
}

AttractorResult MeasureAttractor(OdeSystem& system, const Vector& x0, const AttractorOptions& options,
                                 const SampledSection* section, const AttractorProgress& progress) {
  Validate(options);
  const Index n = system.Dimension();
  const int k = options.exponents;
  if (k > n) {
    throw std::invalid_argument(fmt::format(
        "AttractorOptions.exponents = {}: must be at most the dimension {}", k, n));
  }
  if (x0.size() != n) {
    throw std::invalid_argument(fmt::format("MeasureAttractor: x0 has {} entries, the system {}",
                                            x0.size(), n));
  }
  if (section != nullptr) {
    if (section->count < 1 || !section->function) {
      throw std::invalid_argument(fmt::format(
          "SampledSection.count = {}: must be at least 1, with a function", section->count));
    }
    if (!(section->interval > 0.0) || !(section->interval <= options.interval)) {
      throw std::invalid_argument(fmt::format(
          "SampledSection.interval = {}: must be positive and at most AttractorOptions.interval = {}",
          section->interval, options.interval));
    }
  }
  const double cpu_start = ThreadCpuSeconds();
  const double tau = options.interval;
  const long discarded = IntervalsIn(options.discard, tau);
  const long counted = IntervalsIn(options.duration, tau);
  const long total = discarded + counted;
  const Vector scale = system.StateScale();

  OdeIntegrator integrator(system, options.integrator);
  std::optional<SectionSampler> sampler;
  if (section != nullptr) sampler.emplace(*section, n);
  const double start = static_cast<double>(discarded) * tau;  // of the counted record
  long next_sample = 0;  // samples at start + j·h, j = 0, 1, ...
  Vector sample_times;
  Matrix samples;
  AttractorResult result;
  result.running.resize(k, counted);
  result.times.resize(counted);
  Matrix directions = InitialDirections(scale, k), images;
  Vector x = x0;
  Vector sums = Vector::Zero(k);
  Matrix block_sums = Matrix::Zero(k, options.blocks);
  Vector block_times = Vector::Zero(options.blocks);
  long done = 0;
  for (long i = 0; i < total; ++i) {
    const double t = static_cast<double>(i) * tau;
    // The section's samples in (t, t + τ] (and at the start of the counted record).
    sample_times.resize(0);
    if (sampler && i >= discarded) {
      const double h = section->interval;
      const long last = static_cast<long>(std::floor((t + tau - start) / h * (1.0 + 1e-12)));
      sample_times.resize(std::max(last - next_sample + 1, 0L));
      for (Index j = 0; j < sample_times.size(); ++j) {
        sample_times(j) = std::min(start + static_cast<double>(next_sample + j) * h, t + tau);
      }
      next_sample = last + 1;
    }
    const IntegrationResult step =
        integrator.IntegrateTangents(t, x, t + tau, x, directions, images, sample_times, &samples);
    Accumulate(result.statistics, step.statistics);
    if (!step.Succeeded()) {
      result.status = AttractorStatus::kIntegrationFailure;
      result.message = fmt::format("at t = {:.6g}: {}", step.t_reached, step.BriefReport());
      break;
    }
    const Eigen::HouseholderQR<Matrix> qr(scale.cwiseInverse().asDiagonal() * images);
    directions = scale.asDiagonal() * (qr.householderQ() * Matrix::Identity(n, k));
    if (i < discarded) {
      if (progress) progress(t + tau, static_cast<double>(total) * tau);
      continue;
    }
    const long c = i - discarded;
    const double t_counted = static_cast<double>(c + 1) * tau;
    const int block = static_cast<int>(c * options.blocks / counted);
    for (int j = 0; j < k; ++j) {
      const double growth = std::log(std::abs(qr.matrixQR()(j, j)));
      sums(j) += growth;
      block_sums(j, block) += growth;
    }
    block_times(block) += tau;
    result.running.col(c) = sums / t_counted;
    result.times(c) = t_counted;
    if (sampler) {
      for (Index j = 0; j < sample_times.size(); ++j) {
        sampler->Add(sample_times(j) - start, samples.col(j), result.extrema);
      }
    }
    done = c + 1;
    if (progress) progress(t + tau, static_cast<double>(total) * tau);
  }
  result.running.conservativeResize(k, done);
  result.times.conservativeResize(done);
  result.counted_time = static_cast<double>(done) * tau;
  result.state = x;
  result.exponents = Vector::Constant(k, kNaN);
  result.standard_errors = Vector::Constant(k, kNaN);
  if (done > 0) result.exponents = sums / result.counted_time;
  // Block estimates over the blocks that were completed (all of them after a full record): block
  // b holds the intervals c with ⌊c·blocks/counted⌋ = b, and is complete once its last one is done.
  int full_blocks = 0;
  for (int b = 0; b < options.blocks; ++b) {
    const long last = ((b + 1) * counted - 1) / options.blocks;
    full_blocks += last < done ? 1 : 0;
  }
  if (full_blocks >= 2) {
    for (int j = 0; j < k; ++j) {
      double mean = 0.0, square = 0.0;
      for (int b = 0; b < full_blocks; ++b) {
        const double estimate = block_sums(j, b) / block_times(b);
        mean += estimate;
        square += estimate * estimate;
      }
      mean /= full_blocks;
      const double variance = std::max(square / full_blocks - mean * mean, 0.0) *
                              full_blocks / (full_blocks - 1.0);
      result.standard_errors(j) = std::sqrt(variance / full_blocks);
    }
  }
  for (int j = 0; j < k; ++j) {
    const double lambda = result.exponents(j);
    const double error = std::isfinite(result.standard_errors(j)) ? result.standard_errors(j) : 0.0;
    const double band = std::max(3.0 * error, options.zero_tolerance);
    const ExponentSign sign = lambda > band    ? ExponentSign::kPositive
                              : lambda < -band ? ExponentSign::kNegative
                                               : ExponentSign::kZero;
    result.signs.push_back(sign);
    result.positive += sign == ExponentSign::kPositive ? 1 : 0;
    result.zero += sign == ExponentSign::kZero ? 1 : 0;
    result.negative += sign == ExponentSign::kNegative ? 1 : 0;
  }
  result.cpu_seconds = ThreadCpuSeconds() - cpu_start;
  return result;
}

}  // namespace rubcont
