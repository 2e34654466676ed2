#include "sweeps/sweep.h"

#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using Complex = std::complex<double>;

// ---------------------------------------------------------------------------------------------
// The stepper.

// Stuart–Landau: the limit cycle z = √λ e^{j(ω − γλ)t}; channel 0 is z, its measure r² − λ.
class StuartLandauObservables : public SweepObservables {
 public:
  explicit StuartLandauObservables(StuartLandauOscillator& system) : system_(system) {}
  int Channels() const override { return 1; }
  int Measures() const override { return 1; }
  std::string ChannelName(int) const override { return "z"; }
  std::string MeasureName(int) const override { return "radius_residual"; }
  void Observe(double, ConstVectorRef x, SweepObservation& out) override {
    out.signal(0) = Complex(x(0), x(1));
    out.active[0] = x(0) > 0.0 ? 1 : 0;  // half of the orbit
    out.measures(0, 0) = x(0) * x(0) + x(1) * x(1) - system_.params().lambda;
  }

 private:
  StuartLandauOscillator& system_;
};

SweepOptions StuartLandauOptions() {
  SweepOptions o;
  o.parameters = {2.0, 4.0, 6.0};  // λ
  o.dwell = 8.0;
  o.window = 1.0;
  o.settle_windows = 2;
  o.analysis_length = 2.0;
  o.sample_rate = 256.0;
  o.band = 40.0;
  o.frequency_tolerance = 1e-3;
  o.spectrum_tolerance = 1e-3;
  o.peak_side = PeakSide::kPositive;
  o.integrator.relative_tolerance = 1e-10;
  o.integrator.absolute_tolerance = 1e-10;
  return o;
}

StuartLandauParams Shear() {
  StuartLandauParams p;
  p.omega = HzToRadPerSecond(20.0);
  p.gamma = HzToRadPerSecond(1.0);  // frequency 20 − λ Hz
  return p;
}

TEST_CASE("A Stuart-Landau sweep finds the closed-form orbit at every parameter value", "[sweep]") {
  StuartLandauOscillator system(Shear());
  StuartLandauObservables observables(system);
  SweepStepper stepper(system, observables, StuartLandauOptions(), Vector::Constant(2, 0.1));
  CHECK(stepper.Step() == SweepStepOutcome::kContinue);
  CHECK(stepper.points().size() == 1);
  while (stepper.Step() == SweepStepOutcome::kContinue) {
  }
  REQUIRE(stepper.Done());
  REQUIRE(stepper.points().size() == 3);
  for (const SweepPoint& p : stepper.points()) {
    CAPTURE(p.parameter);
    CHECK(p.status == SweepPointStatus::kSettled);
    CHECK(p.windows >= 3);
    CHECK(p.windows < 8);
    CHECK(p.simulated_time == Approx(p.windows * 1.0));
    CHECK(p.statistics.steps > 0);
    const ChannelSummary& c = p.channels.at(0);
    CHECK(c.peak.frequency == Approx(20.0 - p.parameter).epsilon(0).margin(1e-4));
    CHECK(c.peak.amplitude == Approx(std::sqrt(p.parameter)).epsilon(1e-4));
    CHECK(c.mean_modulus == Approx(std::sqrt(p.parameter)).epsilon(1e-6));
    CHECK(c.active_fraction == Approx(0.5).epsilon(0).margin(0.01));
    // Settled to spectrum_tolerance = 1e-3: r² = λ to that order (the transient decays as e^{−2λt}).
    CHECK(std::abs(c.measures.at(0).mean) < 1e-3 * p.parameter);
    CHECK(std::abs(c.measures.at(0).min) < 1e-3 * p.parameter);
    CHECK(std::abs(c.measures.at(0).max) < 1e-3 * p.parameter);
    REQUIRE(c.spectrum.size() == stepper.BandFrequencies().size());
  }
  // The band: |f| ≤ 40 Hz on the 0.5 Hz grid of the 2 s analysis.
  CHECK(stepper.BandFrequencies().size() == 161);
  CHECK(stepper.BandFrequencies()(0) == Approx(-40.0));
  CHECK(stepper.Step() == SweepStepOutcome::kDone);
}

// ż = j2π(f0 + c t) z: the frequency drifts by c per time unit, so no two windows agree.
class Chirp : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    const double w = HzToRadPerSecond(f0_ + rate * t);
    f(0) = -w * x(1);
    f(1) = w * x(0);
  }
  double Parameter() const override { return f0_; }
  void SetParameter(double p) override { f0_ = p; }
  double rate = 0.0;

 private:
  double f0_ = 10.0;
};

class PlaneObservables : public SweepObservables {
 public:
  int Channels() const override { return 1; }
  int Measures() const override { return 0; }
  std::string ChannelName(int) const override { return "z"; }
  std::string MeasureName(int) const override { return ""; }
  void Observe(double, ConstVectorRef x, SweepObservation& out) override {
    out.signal(0) = Complex(x(0), x(1));
    out.active[0] = 1;
  }
};

TEST_CASE("A drifting response runs to the dwell and is flagged not settled", "[sweep]") {
  Chirp system;
  PlaneObservables observables;
  SweepOptions o = StuartLandauOptions();
  o.parameters = {10.0, 12.0};
  o.peak_side = PeakSide::kPositive;
  o.dwell = 6.5;  // whole windows: 6
  o.frequency_tolerance = 0.1;
  o.spectrum_tolerance = 0.2;
  SECTION("drifting") {
    system.rate = 0.5;  // 0.5 Hz per window
    SweepStepper stepper(system, observables, o, (Vector(2) << 1.0, 0.0).finished());
    stepper.Step();
    const SweepPoint& p = stepper.points().at(0);
    CHECK(p.status == SweepPointStatus::kNotSettled);
    CHECK(p.windows == 6);
    CHECK(p.simulated_time == Approx(6.0));
    CHECK(p.frequency_change == Approx(0.5).epsilon(0).margin(0.02));
    // The analysed stretch is the last 2 s: mean frequency 10 + 0.5·5.
    CHECK(p.channels.at(0).peak.frequency == Approx(12.5).epsilon(0).margin(0.05));
  }
  SECTION("steady") {
    SweepStepper stepper(system, observables, o, (Vector(2) << 1.0, 0.0).finished());
    stepper.Step();
    CHECK(stepper.points().at(0).status == SweepPointStatus::kSettled);
    CHECK(stepper.points().at(0).windows == 3);
    CHECK(stepper.points().at(0).channels.at(0).peak.frequency ==
          Approx(10.0).epsilon(0).margin(1e-4));
  }
}

// z̈ + 2ζω₀ż + ω₀²z = F e^{jΩt}, Ω the parameter: steady state z = A e^{jΩt},
// A = F/(ω₀² − Ω² + 2jζω₀Ω). The plane rotation commutes with the unforced part.
class ForcedOscillator : public OdeSystem {
 public:
  Index Dimension() const override { return 4; }  // (x, y, ẋ, ẏ)
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    f(0) = x(2);
    f(1) = x(3);
    f(2) = -2.0 * kZeta * kW0 * x(2) - kW0 * kW0 * x(0) + kForce * std::cos(omega_ * t);
    f(3) = -2.0 * kZeta * kW0 * x(3) - kW0 * kW0 * x(1) + kForce * std::sin(omega_ * t);
  }
  double Parameter() const override { return omega_; }
  void SetParameter(double p) override { omega_ = p; }
  double ForcingPeriod() const override { return kTwoPi / omega_; }
  void Rotate(double phi, VectorRef x) const override {
    const double c = std::cos(phi), s = std::sin(phi);
    for (Index i = 0; i < 4; i += 2) {
      const double a = x(i), b = x(i + 1);
      x(i) = c * a - s * b;
      x(i + 1) = s * a + c * b;
    }
  }
  Complex Amplitude() const {
    return kForce / Complex(kW0 * kW0 - omega_ * omega_, 2.0 * kZeta * kW0 * omega_);
  }
  static constexpr double kW0 = HzToRadPerSecond(5.0), kZeta = 0.2, kForce = 3.0;

 private:
  double omega_ = 1.0;
};

TEST_CASE("Rotating the state keeps the forcing phase continuous across parameter values", "[sweep]") {
  ForcedOscillator system;
  PlaneObservables observables;
  SweepOptions o = StuartLandauOptions();
  o.parameters = {HzToRadPerSecond(3.3), HzToRadPerSecond(3.3)};
  o.peak_side = PeakSide::kPositive;
  o.dwell = 3.0;  // 3 windows of 1 s (256 samples each)
  o.window = 1.0;
  o.analysis_length = 2.0;
  o.settle_windows = 2;
  // The state at the start of the next value is the steady state at its t = 0 (phase 0) when
  // rotated, and the steady state at t = 3 s otherwise.
  const double w = o.parameters[0];
  system.SetParameter(w);
  const Complex A = system.Amplitude();
  const Vector x0 = (Vector(4) << A.real(), A.imag(), (Complex(0, w) * A).real(),
                     (Complex(0, w) * A).imag()).finished();
  for (bool rotate : {true, false}) {
    CAPTURE(rotate);
    o.rotate_forcing_phase = rotate;
    SweepStepper stepper(system, observables, o, x0);
    const Complex phase = rotate ? 1.0 : std::exp(Complex(0.0, w * 3.0));
    for (int value = 0; value < 2; ++value) {
      stepper.Step();
      REQUIRE(stepper.points().at(value).simulated_time == 3.0);
      const Complex z(stepper.state()(0), stepper.state()(1));
      const Complex v(stepper.state()(2), stepper.state()(3));
      CHECK(std::abs(z - A * phase) < 1e-6 * std::abs(A));
      CHECK(std::abs(v - Complex(0, w) * A * phase) < 1e-6 * w * std::abs(A));
    }
    // With the rotation the second value continues the steady response; without it the forcing
    // jumps in phase at t = 0 and the transient (decay rate ζω₀ = 6.3/s) is still seen 1 s later.
    CHECK(stepper.points()[1].channels[0].peak.frequency == Approx(3.3).epsilon(0).margin(1e-5));
    const double amplitude_error = std::abs(stepper.points()[1].channels[0].peak.amplitude / std::abs(A) - 1.0);
    if (rotate) CHECK(amplitude_error < 1e-7);
    else CHECK(amplitude_error > 1e-7);
  }
}

TEST_CASE("A resumed sweep continues exactly where the interrupted one stopped", "[sweep]") {
  StuartLandauOscillator full_system(Shear()), part_system(Shear()), resumed_system(Shear());
  StuartLandauObservables full_observables(full_system), part_observables(part_system),
      resumed_observables(resumed_system);
  const Vector x0 = Vector::Constant(2, 0.1);
  SweepStepper full(full_system, full_observables, StuartLandauOptions(), x0);
  while (full.Step() == SweepStepOutcome::kContinue) {
  }
  SweepStepper part(part_system, part_observables, StuartLandauOptions(), x0);
  part.Step();
  SweepStepper resumed(resumed_system, resumed_observables, StuartLandauOptions(), part.points(),
                       part.state());
  CHECK(resumed.next_index() == 1);
  while (resumed.Step() == SweepStepOutcome::kContinue) {
  }
  REQUIRE(resumed.points().size() == full.points().size());
  for (std::size_t i = 0; i < full.points().size(); ++i) {
    CHECK(resumed.points()[i].channels[0].peak.frequency == full.points()[i].channels[0].peak.frequency);
    CHECK(resumed.points()[i].channels[0].spectrum == full.points()[i].channels[0].spectrum);
    CHECK(resumed.points()[i].statistics.steps == full.points()[i].statistics.steps);
  }
  CHECK(resumed.state() == full.state());
  // Points that do not belong to the schedule are refused.
  std::vector<SweepPoint> wrong = part.points();
  wrong[0].parameter = 3.0;
  CHECK_THROWS_WITH(SweepStepper(resumed_system, resumed_observables, StuartLandauOptions(), wrong, x0),
                    Contains("finished point 0 has parameter 3"));
  // A parameter that went through a file in another unit (rpm) and back is a few ulps off: it is
  // accepted and takes the schedule's exact value, so the resumed sweep continues bit for bit.
  std::vector<SweepPoint> rounded = part.points();
  const double scheduled = rounded[0].parameter;
  rounded[0].parameter = std::nextafter(std::nextafter(scheduled, 1e300), 1e300);
  SweepStepper from_file(resumed_system, resumed_observables, StuartLandauOptions(), rounded,
                         part.state());
  CHECK(from_file.points()[0].parameter == scheduled);
}

TEST_CASE("A window after intermittent activity is integrated by the intermittent integrator",
          "[sweep]") {
  // Channel 0 is active on half of the Stuart–Landau orbit (x > 0): intermittent at 0.5.
  SweepOptions o = StuartLandauOptions();
  o.intermittent_integrator = o.integrator;
  o.intermittent_integrator->method = IntegrationMethod::kExplicitRungeKutta;
  const Vector x0 = Vector::Constant(2, 0.1);
  StuartLandauOscillator system(Shear());
  StuartLandauObservables observables(system);
  SweepStepper stepper(system, observables, o, x0);
  while (stepper.Step() == SweepStepOutcome::kContinue) {
  }
  REQUIRE(stepper.points().size() == 3);
  // The first window of the sweep follows no activity; every later one follows a window in which
  // the channel was active half of the time.
  CHECK(stepper.points()[0].intermittent_windows == stepper.points()[0].windows - 1);
  for (std::size_t i = 1; i < 3; ++i) CHECK(stepper.points()[i].intermittent_windows == stepper.points()[i].windows);
  for (const SweepPoint& p : stepper.points()) {
    CHECK(p.status == SweepPointStatus::kSettled);
    CHECK(p.channels[0].peak.frequency == Approx(20.0 - p.parameter).epsilon(0).margin(1e-4));
  }
  // Explicit windows build no Newton matrix: the last speed, all explicit, has none.
  CHECK(stepper.points()[2].statistics.jacobian_evaluations == 0);

  // A resumed sweep chooses as the uninterrupted one (from the stored active fractions).
  StuartLandauOscillator part_system(Shear()), resumed_system(Shear());
  StuartLandauObservables part_observables(part_system), resumed_observables(resumed_system);
  SweepStepper part(part_system, part_observables, o, x0);
  part.Step();
  SweepStepper resumed(resumed_system, resumed_observables, o, part.points(), part.state());
  while (resumed.Step() == SweepStepOutcome::kContinue) {
  }
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(resumed.points()[i].intermittent_windows == stepper.points()[i].intermittent_windows);
    CHECK(resumed.points()[i].channels[0].spectrum == stepper.points()[i].channels[0].spectrum);
  }

  // Activity above intermittent_fraction is continuous: the main integrator throughout.
  o.intermittent_fraction = 0.4;
  StuartLandauOscillator continuous_system(Shear());
  StuartLandauObservables continuous_observables(continuous_system);
  SweepStepper continuous(continuous_system, continuous_observables, o, x0);
  while (continuous.Step() == SweepStepOutcome::kContinue) {
  }
  for (const SweepPoint& p : continuous.points()) CHECK(p.intermittent_windows == 0);
}

// Blows up in finite time for p > 0: ẋ = p x².
class BlowUp : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f(0) = p_ * x(0) * x(0);
    f(1) = 0.0;
  }
  double Parameter() const override { return p_; }
  void SetParameter(double p) override { p_ = p; }

 private:
  double p_ = 0.0;
};

TEST_CASE("An integrator failure stops the sweep with the reason, and stays stopped", "[sweep]") {
  BlowUp system;
  PlaneObservables observables;
  SweepOptions o = StuartLandauOptions();
  o.parameters = {0.0, 1.0, 2.0};
  SweepStepper stepper(system, observables, o, (Vector(2) << 1.0, 0.0).finished());
  CHECK(stepper.Step() == SweepStepOutcome::kContinue);
  CHECK(stepper.Step() == SweepStepOutcome::kFailed);  // x = 1/(1 − t) blows up at t = 1
  REQUIRE(stepper.points().size() == 2);
  const SweepPoint& failed = stepper.points()[1];
  CHECK(failed.status == SweepPointStatus::kIntegrationFailure);
  CHECK(failed.channels.empty());
  CHECK_THAT(failed.message, Contains("state bound"));
  CHECK(failed.simulated_time < 1.0);
  CHECK(stepper.Failed());
  CHECK(stepper.next_index() == 1);
  CHECK(stepper.Step() == SweepStepOutcome::kFailed);
  CHECK(stepper.points().size() == 2);
}

TEST_CASE("Sweep options are validated with field, value and rule", "[sweep]") {
  StuartLandauOscillator system(Shear());
  StuartLandauObservables observables(system);
  auto message = [&](auto change) {
    SweepOptions o = StuartLandauOptions();
    change(o);
    try {
      SweepStepper stepper(system, observables, o, Vector::Zero(2));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(message([](SweepOptions& o) { o.parameters.clear(); }), Contains("SweepOptions.parameters"));
  CHECK_THAT(message([](SweepOptions& o) { o.parameters[1] = kNaN; }),
             Contains("parameters[1] = nan: must be finite"));
  CHECK_THAT(message([](SweepOptions& o) { o.dwell = 2.5; }),
             Contains("SweepOptions.dwell = 2.5: must be at least (settle_windows + 1)·window = 3"));
  CHECK_THAT(message([](SweepOptions& o) { o.analysis_length = 3.5; }),
             Contains("SweepOptions.analysis_length = 3.5: must not exceed"));
  CHECK_THAT(message([](SweepOptions& o) { o.band = 200.0; }),
             Contains("SweepOptions.band = 200: must not exceed the Nyquist frequency"));
  CHECK_THAT(message([](SweepOptions& o) { o.spectrum_tolerance = 1.0; }),
             Contains("spectrum_tolerance = 1: must lie in (0, 1)"));
  CHECK_THAT(message([](SweepOptions& o) { o.settle_windows = 0; }), Contains("settle_windows = 0"));
  CHECK_THAT(message([](SweepOptions& o) { o.window = 0.01; o.dwell = 8.0; }),
             Contains("window = 0.01: must hold at least 16 samples"));
  CHECK_THAT(message([](SweepOptions& o) { o.integrator.relative_tolerance = 2.0; }),
             Contains("IntegratorOptions.relative_tolerance"));
  CHECK_THAT(message([](SweepOptions& o) { o.intermittent_fraction = 1.0; }),
             Contains("SweepOptions.intermittent_fraction = 1: must lie in (0, 1)"));
  CHECK_THAT(message([](SweepOptions& o) {
               o.intermittent_integrator = o.integrator;
               o.intermittent_integrator->explicit_order = 7;
             }),
             Contains("IntegratorOptions.explicit_order = 7"));
  CHECK_THAT(message([](SweepOptions&) {}), Contains("no error"));
  CHECK_THROWS_WITH(SweepStepper(system, observables, StuartLandauOptions(), Vector::Zero(3)),
                    Contains("x0 has 3 entries"));
}

}  // namespace
}  // namespace rubcont
