#include "sweeps/sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/stopwatch.h"

namespace rubcont {

const char* ToString(SweepPointStatus status) {
  switch (status) {
    case SweepPointStatus::kSettled: return "settled";
    case SweepPointStatus::kNotSettled: return "not settled";
    case SweepPointStatus::kIntegrationFailure: return "integration failure";
  }
  return "unknown";
}

void Validate(const SweepOptions& o) {
  auto fail = [](const char* field, const auto& value, const std::string& rule) {
    throw std::invalid_argument(fmt::format("SweepOptions.{} = {}: {}", field, value, rule));
  };
  if (o.parameters.empty()) fail("parameters", "[]", "the schedule needs at least one value");
  for (std::size_t i = 0; i < o.parameters.size(); ++i) {
    if (!std::isfinite(o.parameters[i])) {
      throw std::invalid_argument(fmt::format(
          "SweepOptions.parameters[{}] = {}: must be finite", i, o.parameters[i]));
    }
  }
  auto positive = [&](const char* field, double value) {
    if (!(value > 0.0) || !std::isfinite(value)) fail(field, value, "must be positive and finite");
  };
  positive("dwell", o.dwell);
  positive("window", o.window);
  positive("frequency_tolerance", o.frequency_tolerance);
  positive("analysis_length", o.analysis_length);
  positive("sample_rate", o.sample_rate);
  positive("band", o.band);
  if (o.settle_windows < 1) fail("settle_windows", o.settle_windows, "must be at least 1");
  if (!(o.spectrum_tolerance > 0.0 && o.spectrum_tolerance < 1.0)) {
    fail("spectrum_tolerance", o.spectrum_tolerance, "must lie in (0, 1)");
  }
  if (!(o.min_frequency >= 0.0) || !std::isfinite(o.min_frequency)) {
    fail("min_frequency", o.min_frequency, "must be finite and non-negative");
  }
  if (std::llround(o.window * o.sample_rate) < 16) {
    fail("window", o.window, fmt::format("must hold at least 16 samples at sample_rate = {}",
                                         o.sample_rate));
  }
  if (std::llround(o.analysis_length * o.sample_rate) < 16) {
    fail("analysis_length", o.analysis_length,
         fmt::format("must hold at least 16 samples at sample_rate = {}", o.sample_rate));
  }
  const double shortest = (o.settle_windows + 1) * o.window;
  if (o.dwell < shortest * (1.0 - 1e-12)) {
    fail("dwell", o.dwell,
         fmt::format("must be at least (settle_windows + 1)·window = {} (the shortest settled run)",
                     shortest));
  }
  if (o.analysis_length > shortest * (1.0 + 1e-12)) {
    fail("analysis_length", o.analysis_length,
         fmt::format("must not exceed (settle_windows + 1)·window = {} (the shortest run)",
                     shortest));
  }
  if (o.band > 0.5 * o.sample_rate) {
    fail("band", o.band, fmt::format("must not exceed the Nyquist frequency sample_rate/2 = {}",
                                     0.5 * o.sample_rate));
  }
  Validate(o.integrator);
  if (o.intermittent_integrator) Validate(*o.intermittent_integrator);
  if (!(o.intermittent_fraction > 0.0 && o.intermittent_fraction < 1.0)) {
    fail("intermittent_fraction", o.intermittent_fraction, "must lie in (0, 1)");
  }
}

bool SweepStepper::Intermittent(double active_fraction) const {
  return active_fraction > 0.0 && active_fraction <= options_.intermittent_fraction;
}

void SweepStepper::SetIntermittent(const SweepPoint& point) {
  intermittent_ = false;
  for (const ChannelSummary& c : point.channels)
    intermittent_ = intermittent_ || Intermittent(c.active_fraction);
}

SweepStepper::SweepStepper(OdeSystem& system, SweepObservables& observables, SweepOptions options,
                           const Vector& x0)
    : system_(system),
      observables_(observables),
      options_((Validate(options), std::move(options))),
      integrator_(system, options_.integrator),
      x_(x0) {
  if (options_.intermittent_integrator) {
    intermittent_integrator_.emplace(system, *options_.intermittent_integrator);
  }
  if (x0.size() != system.Dimension()) {
    throw std::invalid_argument(fmt::format("SweepStepper: x0 has {} entries, the system {}",
                                            x0.size(), system.Dimension()));
  }
  Setup();
}

SweepStepper::SweepStepper(OdeSystem& system, SweepObservables& observables, SweepOptions options,
                           std::vector<SweepPoint> finished, const Vector& x)
    : SweepStepper(system, observables, std::move(options), x) {
  if (finished.size() > options_.parameters.size()) {
    throw std::invalid_argument(fmt::format(
        "SweepStepper: {} finished points for a schedule of {} values", finished.size(),
        options_.parameters.size()));
  }
  for (std::size_t i = 0; i < finished.size(); ++i) {
    SweepPoint& p = finished[i];
    // Finished points come back from a file in other units (rpm): equal to 1e-12, they take the
    // schedule's own value.
    const double scheduled = options_.parameters[i];
    if (!(std::abs(p.parameter - scheduled) <= 1e-12 * std::max(std::abs(scheduled), 1.0))) {
      throw std::invalid_argument(fmt::format(
          "SweepStepper: finished point {} has parameter {}, the schedule {}", i, p.parameter,
          scheduled));
    }
    p.parameter = scheduled;
    if (p.status == SweepPointStatus::kIntegrationFailure) {
      throw std::invalid_argument(fmt::format(
          "SweepStepper: finished point {} (parameter {}) is an integration failure: a sweep "
          "cannot resume after it", i, p.parameter));
    }
    if (static_cast<int>(p.channels.size()) != observables_.Channels()) {
      throw std::invalid_argument(fmt::format(
          "SweepStepper: finished point {} has {} channels, the observables {}", i,
          p.channels.size(), observables_.Channels()));
    }
    for (const ChannelSummary& c : p.channels) {
      if (c.spectrum.size() != band_frequencies_.size()) {
        throw std::invalid_argument(fmt::format(
            "SweepStepper: finished point {} has spectra of {} bins, the band {}", i,
            c.spectrum.size(), band_frequencies_.size()));
      }
    }
  }
  points_ = std::move(finished);
  next_ = points_.size();
  if (!points_.empty()) SetIntermittent(points_.back());
}

void SweepStepper::Setup() {
  const SweepOptions& o = options_;
  window_samples_ = static_cast<Index>(std::llround(o.window * o.sample_rate));
  analysis_samples_ = static_cast<Index>(std::llround(o.analysis_length * o.sample_rate));
  const double window = static_cast<double>(window_samples_) / o.sample_rate;
  max_windows_ = std::max(o.settle_windows + 1,
                          static_cast<int>(std::floor(o.dwell / window * (1.0 + 1e-12))));
  const int channels = observables_.Channels();
  const int measures = observables_.Measures();
  if (channels < 1) {
    throw std::invalid_argument(fmt::format("SweepStepper: observables have {} channels", channels));
  }
  const Index capacity = static_cast<Index>(max_windows_) * window_samples_;
  signals_.resize(channels, capacity);
  active_.resize(channels, capacity);
  measures_.assign(static_cast<std::size_t>(measures), Matrix(channels, capacity));
  observation_.signal.resize(channels);
  observation_.active.assign(static_cast<std::size_t>(channels), 0);
  observation_.measures.resize(channels, measures);
  window_times_.resize(window_samples_);

  // The analysis frequency grid and the band kept.
  const Index n = analysis_samples_;
  const Index negatives = n / 2;
  std::vector<double> band;
  band_first_ = -1;
  for (Index j = 0; j < n; ++j) {
    const double f = static_cast<double>(j - negatives) * o.sample_rate / static_cast<double>(n);
    if (std::abs(f) <= o.band * (1.0 + 1e-12)) {
      if (band_first_ < 0) band_first_ = j;
      band.push_back(f);
    }
  }
  band_frequencies_ = Eigen::Map<Vector>(band.data(), static_cast<Index>(band.size()));
}

ChannelSummary SweepStepper::Summarize(int channel, Index first, Index count) const {
  ChannelSummary summary;
  const ComplexVector samples = signals_.row(channel).segment(first, count).transpose();
  const AmplitudeSpectrum spectrum = TwoSidedSpectrum(samples, options_.sample_rate);
  summary.peak = DominantPeak(spectrum, options_.peak_side, options_.min_frequency);
  summary.spectrum = spectrum.magnitude.segment(band_first_, band_frequencies_.size());
  summary.mean_modulus = samples.cwiseAbs().mean();
  const int measures = observables_.Measures();
  summary.measures.resize(static_cast<std::size_t>(measures));
  Index active = 0;
  for (Index i = first; i < first + count; ++i) active += active_(channel, i) ? 1 : 0;
  summary.active_fraction = static_cast<double>(active) / static_cast<double>(count);
  for (int m = 0; m < measures; ++m) {
    MeasureSummary& s = summary.measures[static_cast<std::size_t>(m)];
    if (active == 0) {
      s.mean = s.min = s.max = kNaN;
      continue;
    }
    double sum = 0.0, lo = kInfinity, hi = -lo;
    for (Index i = first; i < first + count; ++i) {
      if (!active_(channel, i)) continue;
      const double v = measures_[static_cast<std::size_t>(m)](channel, i);
      sum += v;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    s.mean = sum / static_cast<double>(active);
    s.min = lo;
    s.max = hi;
  }
  return summary;
}

SweepStepOutcome SweepStepper::Step() {
  if (failed_) return SweepStepOutcome::kFailed;
  if (Done()) return SweepStepOutcome::kDone;
  const SteadyClock::time_point wall_start = SteadyClock::now();
  const SweepOptions& o = options_;
  const int channels = observables_.Channels();
  const int measures = observables_.Measures();
  SweepPoint point;
  point.parameter = o.parameters[next_];
  system_.SetParameter(point.parameter);

  const double dt = 1.0 / o.sample_rate;
  const double window = static_cast<double>(window_samples_) * dt;
  std::vector<AmplitudeSpectrum> previous(static_cast<std::size_t>(channels));
  std::vector<SpectralPeak> previous_peak(static_cast<std::size_t>(channels));
  int agreeing = 0;
  bool settled = false;
  bool failed = false;
  for (int w = 0; w < max_windows_; ++w) {
    const double t0 = w * window;
    for (Index k = 0; k < window_samples_; ++k) window_times_(k) = t0 + static_cast<double>(k + 1) * dt;
    const bool intermittent = intermittent_integrator_ && intermittent_;
    OdeIntegrator& integrator = intermittent ? *intermittent_integrator_ : integrator_;
    const IntegrationResult result = integrator.Sample(t0, x_, window_times_, window_states_);
    point.intermittent_windows += intermittent ? 1 : 0;
    Accumulate(point.statistics, result.statistics);
    if (!result.Succeeded()) {
      point.status = SweepPointStatus::kIntegrationFailure;
      point.message = result.BriefReport();
      point.simulated_time = result.t_reached;
      failed = true;
      break;
    }
    x_ = window_states_.col(window_samples_ - 1);
    point.windows = w + 1;
    point.simulated_time = (w + 1) * window;
    // Observe every sample of the window.
    const Index offset = static_cast<Index>(w) * window_samples_;
    for (Index k = 0; k < window_samples_; ++k) {
      observables_.Observe(window_times_(k), window_states_.col(k), observation_);
      for (int c = 0; c < channels; ++c) {
        signals_(c, offset + k) = observation_.signal(c);
        active_(c, offset + k) = observation_.active[static_cast<std::size_t>(c)];
        for (int m = 0; m < measures; ++m)
          measures_[static_cast<std::size_t>(m)](c, offset + k) = observation_.measures(c, m);
      }
    }
    intermittent_ = false;
    for (int c = 0; c < channels; ++c) {
      const double active = static_cast<double>(active_.row(c).segment(offset, window_samples_).count());
      intermittent_ = intermittent_ || Intermittent(active / static_cast<double>(window_samples_));
    }
    // Compare this window with the previous one.
    double distance = 0.0, shift = 0.0;
    bool agree = w > 0;
    for (int c = 0; c < channels; ++c) {
      const ComplexVector samples = signals_.row(c).segment(offset, window_samples_).transpose();
      AmplitudeSpectrum spectrum = TwoSidedSpectrum(samples, o.sample_rate);
      const SpectralPeak peak = DominantPeak(spectrum, o.peak_side, o.min_frequency);
      if (w > 0) {
        const double d = SpectralDistance(spectrum, previous[static_cast<std::size_t>(c)]);
        const SpectralPeak& p = previous_peak[static_cast<std::size_t>(c)];
        const double df = peak.found && p.found ? std::abs(peak.frequency - p.frequency)
                          : peak.found == p.found ? 0.0 : kInfinity;
        distance = std::max(distance, d);
        shift = std::max(shift, df);
        if (!(d <= o.spectrum_tolerance && df <= o.frequency_tolerance)) agree = false;
      }
      previous[static_cast<std::size_t>(c)] = std::move(spectrum);
      previous_peak[static_cast<std::size_t>(c)] = peak;
    }
    if (w > 0) {
      point.spectrum_change = distance;
      point.frequency_change = shift;
    }
    agreeing = agree ? agreeing + 1 : 0;
    if (agreeing >= o.settle_windows) {
      settled = true;
      break;
    }
  }

  if (!failed) {
    point.status = settled ? SweepPointStatus::kSettled : SweepPointStatus::kNotSettled;
    const Index total = static_cast<Index>(point.windows) * window_samples_;
    const Index first = total - analysis_samples_;
    for (int c = 0; c < channels; ++c) point.channels.push_back(Summarize(c, first, analysis_samples_));
    SetIntermittent(point);
    if (o.rotate_forcing_phase && system_.ForcingPeriod() > 0.0) {
      // Continue the forcing from where it is: rotate the state back by the phase it advanced.
      const double phase = kTwoPi * point.simulated_time / system_.ForcingPeriod();
      system_.Rotate(-std::remainder(phase, kTwoPi), x_);
    }
  }
  point.wall_seconds = SecondsSince(wall_start);
  points_.push_back(std::move(point));
  if (failed) {
    failed_ = true;
    return SweepStepOutcome::kFailed;
  }
  ++next_;
  return Done() ? SweepStepOutcome::kDone : SweepStepOutcome::kContinue;
}

}  // namespace rubcont
