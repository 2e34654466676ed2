// Time-marching parameter sweeps (level L3): the brute-force experiment of Kumar (2010) §3.5.
//
// A sweep visits a schedule of parameter values p_1, p_2, … in order. At each value it integrates
// the system, continuing from the state the previous value ended in, in windows of fixed length,
// until the response has settled or the dwell limit is reached; it then summarizes the last part
// of the run: the two-sided spectrum of each observed complex signal, its dominant peak (refined
// below the bin width; solvers/spectrum.h), and statistics of real measures over the samples where the channel is
// active. Nothing here knows a model: sweeps/rub_sweep.h supplies the rub observables (relative
// motion and slip velocity at each contact) and reads regimes and jumps off the result.
//
// Settled (the criterion, per parameter value): the run is cut into consecutive windows of
// `window` time units, each sampled at `sample_rate`. Two successive windows agree when, for every
// channel, (a) the relative L2 distance between their two-sided amplitude spectra is at most
// `spectrum_tolerance` and (b) their dominant frequencies differ by at most `frequency_tolerance`.
// The value is settled once `settle_windows` successive pairs agree (so at least
// settle_windows + 1 windows are integrated); otherwise the run stops, unsettled, when another
// window would pass `dwell`. A steady modulated response (sidebands that do not change) settles;
// a drifting, beating or chaotic one does not, and says so.
//
// Forcing phase: each parameter value restarts the time at 0. For a forced system whose forcing
// rotates (e^{j2πt/T_f}, T_f = ForcingPeriod()) and whose unforced part commutes with
// OdeSystem::Rotate (an isotropic rotor with imbalance), `rotate_forcing_phase` keeps the forcing
// phase continuous: after a run of length T the state is rotated by −2πT/T_f, which is the same
// as continuing the forcing from where it was. The summaries are invariant under that rotation.
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "solvers/ode.h"
#include "solvers/ode_system.h"
#include "solvers/spectrum.h"

namespace rubcont {

// ---------------------------------------------------------------------------------------------
// What a sweep observes.

// One observation of all channels at a state.
struct SweepObservation {
  ComplexVector signal;       // channels: the complex signal whose spectrum is analysed
  std::vector<char> active;   // channels: 1 where the measures count (e.g. the contact touches)
  Matrix measures;            // channels × measures: real quantities summarized over active samples
};

class SweepObservables {
 public:
  virtual ~SweepObservables() = default;
  virtual int Channels() const = 0;
  virtual int Measures() const = 0;
  virtual std::string ChannelName(int channel) const = 0;
  virtual std::string MeasureName(int measure) const = 0;
  // Fills `out` (already sized Channels() / Channels() × Measures()) for state x at time t. The
  // system's parameter is the current sweep value.
  virtual void Observe(double t, ConstVectorRef x, SweepObservation& out) = 0;
};

// ---------------------------------------------------------------------------------------------
// Options and results.

struct SweepOptions {
  // The schedule: parameter values in the order visited (≥ 1 entry, each finite).
  std::vector<double> parameters;
  // Longest simulated time per value (time units) > 0; runs are whole windows, so the limit is
  // floor(dwell / window) windows. Kumar (2010): 1.5 s per speed.
  double dwell = 1.5;
  double window = 0.25;        // settle window length (time units) > 0, ≤ dwell / 2
  int settle_windows = 2;      // successive agreeing window pairs needed to settle, ≥ 1
  double spectrum_tolerance = 0.05;   // relative spectral distance between windows, in (0, 1)
  double frequency_tolerance = 0.25;  // dominant-frequency change between windows (cycles/time) > 0
  // Length of the stretch the summary analyses: the last `analysis_length` of the run (time
  // units) > 0, at most (settle_windows + 1)·window (the shortest run) — so every value is
  // analysed over the same length and the spectra share one frequency grid.
  double analysis_length = 0.5;
  double sample_rate = 4096.0;  // samples per time unit > 0; window·rate and analysis·rate ≥ 16
  double band = 600.0;          // spectra are kept for |f| ≤ band (cycles/time), 0 < band ≤ fs/2
  PeakSide peak_side = PeakSide::kNegative;
  double min_frequency = 0.0;   // ignore peaks at |f| below this (cycles/time) ≥ 0
  bool rotate_forcing_phase = false;  // see the header comment
  // The integrator for every run (each window is one OdeIntegrator::Sample call).
  IntegratorOptions integrator;
  // An integrator for intermittent activity (e.g. a contact that impacts): when set, a window is
  // integrated with it if, in the window before it, some channel was active for a share of the
  // samples in (0, intermittent_fraction]; otherwise with `integrator`. A speed's first window
  // looks at the previous speed's analysed stretch (ChannelSummary::active_fraction), so a resumed
  // sweep chooses as an uninterrupted one. On the rub's stiff contact Dormand–Prince 5(4) costs an
  // eighth of BDF's CPU time in the impacting whip and 1.1–4.8 times it in continuous contact
  // (bench/sweep_integrators_bench.cpp, docs/studies/sweep_integrators.md); and where contacts
  // chatter around an unstable rotating wave, BDF's damping of the contact modes can hide the
  // chatter (tests/sweeps/rub_sweep_test.cpp, cases B(b) and B(c)).
  std::optional<IntegratorOptions> intermittent_integrator;
  double intermittent_fraction = 0.9;  // in (0, 1)
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const SweepOptions& options);

struct MeasureSummary {
  double mean = 0.0;  // over the active samples of the analysed stretch; NaN when there are none
  double min = 0.0;
  double max = 0.0;
};

struct ChannelSummary {
  SpectralPeak peak;             // the dominant peak of the analysed stretch (on peak_side)
  double active_fraction = 0.0;  // share of the analysed samples where the channel is active
  double mean_modulus = 0.0;     // mean |signal| over the analysed samples
  std::vector<MeasureSummary> measures;
  Vector spectrum;               // amplitudes for |f| ≤ band (SweepStepper::BandFrequencies())
};

enum class SweepPointStatus {
  kSettled,             // settle_windows successive window pairs agreed
  kNotSettled,          // the dwell limit came first: the summary is of a response still changing
  kIntegrationFailure,  // the integrator failed (see message); no summary
};
const char* ToString(SweepPointStatus status);

struct SweepPoint {
  double parameter = 0.0;
  SweepPointStatus status = SweepPointStatus::kSettled;
  int windows = 0;               // windows integrated
  double simulated_time = 0.0;   // windows · window (or up to the failure)
  double spectrum_change = 0.0;  // the last window-to-window spectral distance (max over channels)
  double frequency_change = 0.0; // the last window-to-window |Δf| (max over channels)
  double wall_seconds = 0.0;     // wall-clock time of this value
  IntegrationStatistics statistics;  // summed over the windows
  int intermittent_windows = 0;  // windows integrated by SweepOptions::intermittent_integrator
  std::string message;           // the integrator's report on failure
  std::vector<ChannelSummary> channels;
};

// ---------------------------------------------------------------------------------------------
// The stepper: one parameter value per Step(), so that a driver can report progress and write a
// checkpoint after each one, and a test can step once.

enum class SweepStepOutcome {
  kContinue,  // a value was finished and more remain
  kDone,      // the last value was finished (or none remained)
  kFailed,    // the integrator failed at this value; the sweep cannot go on
};

class SweepStepper {
 public:
  // A new sweep from x0 (Dimension() entries). The system and the observables must outlive the
  // stepper. Options are validated here.
  SweepStepper(OdeSystem& system, SweepObservables& observables, SweepOptions options,
               const Vector& x0);

  // Resumes a sweep: `finished` are the points already done (the first finished.size() values of
  // the schedule, in order; their parameters equal to 1e-12 relative, then set to the schedule's
  // values), `x` the state after the last of them (already rotated when rotate_forcing_phase is
  // set). Throws std::invalid_argument when the points do not match the schedule or the spectra do
  // not match the band.
  SweepStepper(OdeSystem& system, SweepObservables& observables, SweepOptions options,
               std::vector<SweepPoint> finished, const Vector& x);

  // Integrates the next value of the schedule and appends its point. After a failure the point is
  // kept (status kIntegrationFailure, next_index() unchanged) and every later call returns kFailed.
  SweepStepOutcome Step();
  bool Done() const { return next_ >= options_.parameters.size(); }
  bool Failed() const { return failed_; }

  const SweepOptions& options() const { return options_; }
  const std::vector<SweepPoint>& points() const { return points_; }
  const Vector& state() const { return x_; }      // the state to continue from
  std::size_t next_index() const { return next_; }
  // The frequencies of ChannelSummary::spectrum (|f| ≤ band on the analysis grid, ascending).
  const Vector& BandFrequencies() const { return band_frequencies_; }

 private:
  void Setup();
  bool Intermittent(double active_fraction) const;
  void SetIntermittent(const SweepPoint& point);  // from a finished speed's summary
  ChannelSummary Summarize(int channel, Index first_sample, Index count) const;

  OdeSystem& system_;
  SweepObservables& observables_;
  SweepOptions options_;
  OdeIntegrator integrator_;
  std::optional<OdeIntegrator> intermittent_integrator_;
  std::vector<SweepPoint> points_;
  std::size_t next_ = 0;
  bool failed_ = false;
  Vector x_;
  Index window_samples_ = 0;
  Index analysis_samples_ = 0;
  // Whether the last window (or the last finished speed) had intermittent activity.
  bool intermittent_ = false;
  int max_windows_ = 0;
  Vector band_frequencies_;
  Index band_first_ = 0;  // first analysis-grid bin inside the band
  // Per-run sample storage (channels × samples), sized once for the longest run.
  ComplexMatrix signals_;
  Eigen::Matrix<char, Eigen::Dynamic, Eigen::Dynamic> active_;
  std::vector<Matrix> measures_;  // per measure: channels × samples
  SweepObservation observation_;
  Matrix window_states_;
  Vector window_times_;
};

}  // namespace rubcont
