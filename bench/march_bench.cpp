// Time marching at hand-written speed (issue 49, item 5): the CPU per simulated second of the
// library's sweep stepper (SweepStepper with the scene's "explicit" integrator, Boost.Odeint's
// Dormand–Prince 5(4) at the scene's tolerance) against a plain-C Dormand–Prince of the same model
// (bench/plain_rub_dopri5.c: no library layers, the same error norm and tolerance), per regime.
//
// Per regime the state is reached once by the scene's own sweep (ApproachSweep), then one sweep
// speed (dwell = settle windows + 1, sampled at the scene's rate) is integrated from it, the
// measured runs alternating, each the median of --repeats:
//   sweep       SweepStepper::Step: the integrator, the observation of every sample, the window
//               spectra and the settle test, the summary (what `rubcont sweep` pays per speed);
//   integrator  OdeIntegrator::Sample over the same windows (one call per window, as the stepper
//               makes them): the integrator alone;
//   plain f     the same integrator on the plain C's right-hand side (PlainField): the integrator's
//               cost apart from the model's;
//   no landing  the integrator alone with land_on_switches off (the cost of landing on the
//               switches; other steps where contacts switch, so other results there);
//   plain       the plain-C reference sampling the same times, step-size control as Odeint's
//               (so the steps are those of the library) and as Hairer's DOPRI5 (PI control).
// CPU seconds of the process (solvers/stopwatch.h), per simulated second; ratios to the plain
// reference with Odeint's control. The plain model is checked against RubFixedFrame::Rhs first, and
// both right-hand sides are timed alone at the approach state (ns per call).
//
// --schedule adds the whole speed-up sweep of the issue (44 → 184 rpm, 4 rpm, the scene's dwell),
// rubcont's SweepRun against the plain reference marching the same schedule, once each, alternating;
// with the speeds where each leaves the whip (the dominant backward precession of the last
// analysis_length of each speed, by solvers/spectrum.h, above 150 Hz: rolling whirl).
//
// --methods adds, per regime, one window by other methods (BDF, DIRK, Gauss collocation, Dormand–
// Prince at other tolerances) against a tight reference: CompareMethods.
//
// Usage: march_bench [SCENE] [--repeats K] [--regime NAME] [--schedule] [--schedule-only] [--methods]
// Default: scenes/thesis_A_a.toml, 5 repeats.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/units.h"
#include "plain_rub_dopri5.h"
#include "solvers/constants.h"
#include "solvers/ode.h"
#include "solvers/spectrum.h"
#include "solvers/stopwatch.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"

namespace {

using rubcont::Vector;

PlainRubData PlainDataOf(const rubcont::TwoPointParams& p) {
  PlainRubData d{};
  d.rotor_mass = p.rotor_mass;
  d.rotor_inertia = p.rotor_inertia;
  d.contact_span = p.contact_span;
  d.rotor_mass_center = p.rotor_mass_center;
  d.stator_mass = p.stator_mass;
  d.stator_inertia = p.stator_inertia;
  d.stator_span = p.stator_span;
  d.stator_mass_center = p.stator_mass_center;
  for (int k = 0; k < 2; ++k) {
    d.support_stiffness[k] = p.support_stiffness[k];
    d.support_damping[k] = p.support_damping[k];
    d.clearance[k] = p.clearance[k];
    d.radius[k] = p.radius[k];
  }
  d.friction = p.friction;
  d.contact_stiffness = p.contact_stiffness;
  d.contact_stiffness2 = p.contact_stiffness2;
  d.contact_damping = p.contact_damping;
  d.velocity_scale = p.friction_law.velocity_scale;
  d.center_damping = p.center_damping;
  return d;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The sample times of one sweep speed: windows × round(window·rate) samples after t = 0.
Vector SpeedTimes(const rubcont::SweepOptions& o, int windows) {
  const long per_window = std::lround(o.window * o.sample_rate);
  Vector times(windows * per_window);
  for (long k = 0; k < times.size(); ++k) times(k) = static_cast<double>(k + 1) / o.sample_rate;
  return times;
}

struct PlainRun {
  double cpu = 0.0;
  PlainStatistics statistics{};
  Vector end;
  bool ok = true;
};

PlainRun RunPlain(const PlainRubData& data, double omega, PlainControl control, double tolerance,
                  const Vector& x0, const Vector& times) {
  PlainRub model;
  PlainRubInit(&data, omega, &model);
  std::vector<double> samples(16 * static_cast<std::size_t>(times.size()));
  PlainRun run;
  run.end = x0;
  double step = 0.0;
  const double c0 = rubcont::ProcessCpuSeconds();
  run.ok = PlainDopri5(&model, control, tolerance, 0.0, run.end.data(), times.data(), times.size(),
                       samples.data(), &step, &run.statistics) == 0;
  run.cpu = rubcont::CpuSecondsSince(c0);
  return run;
}

struct Regime {
  const char* name;
  double from_rpm, to_rpm;  // the approach sweep starts at from_rpm; to_rpm is measured
};

double ScaledDistance(const Vector& a, const Vector& b, const Vector& scale) {
  return (a - b).cwiseQuotient(scale).cwiseAbs().maxCoeff();
}

// RubFixedFrame with the plain C's right-hand side: the library's integrator on the plain model
// (the integrator's overhead apart from the model's; the switching functions stay the library's).
class PlainField final : public rubcont::RubFixedFrame {
 public:
  PlainField(const rubcont::RubStructure& structure, double omega, const PlainRubData& data)
      : RubFixedFrame(structure, omega) {
    PlainRubInit(&data, omega, &model_);
  }
  void Rhs(double /*t*/, rubcont::ConstVectorRef x, rubcont::VectorRef f) override {
    PlainRubRhs(&model_, x.data(), f.data());
  }

 private:
  PlainRub model_;
};

// OdeIntegrator::Sample over the windows of `times` (one call per window, as the sweep stepper
// makes them) from x0; the end state into `end`; returns the CPU seconds.
double IntegrateWindows(rubcont::OdeSystem& system, const rubcont::IntegratorOptions& options,
                        const Vector& x0, const Vector& times, int windows, Vector& end) {
  rubcont::OdeIntegrator integrator(system, options);
  const long per_window = times.size() / windows;
  Vector window_times(per_window);
  rubcont::Matrix states;
  end = x0;
  const double c0 = rubcont::ProcessCpuSeconds();
  for (int w = 0; w < windows; ++w) {
    window_times = times.segment(w * per_window, per_window);
    integrator.Sample(w == 0 ? 0.0 : times(w * per_window - 1), end, window_times, states);
    end = states.col(per_window - 1);
  }
  return rubcont::CpuSecondsSince(c0);
}

int ClosedContacts(rubcont::RubFixedFrame& system, const Vector& x) {
  int closed = 0;
  for (const rubcont::ContactEvaluation& c : system.Contacts(x)) closed += c.touching ? 1 : 0;
  return closed;
}

// One window (the first of the regime's speed) integrated by other methods against a reference
// (the plain C at 1e-12; its f agrees with the library's to 1e-16): CPU per simulated second and the
// largest scaled distance to the reference over the window's samples. Whether a method whose step is
// not bound by the contact modes' stability (BDF, DIRK, Gauss collocation) beats the explicit one at
// the same accuracy. One run each (not a median).
void CompareMethods(const rubcont::RubStructure& structure, const PlainRubData& data, double omega,
                    const Vector& x0, const rubcont::SweepOptions& o) {
  using rubcont::IntegrationMethod;
  const Vector times = SpeedTimes(o, 1);
  const double simulated = times(times.size() - 1);
  PlainRub model;
  PlainRubInit(&data, omega, &model);
  std::vector<double> reference(16 * static_cast<std::size_t>(times.size()));
  Vector x = x0;
  double step = 0.0;
  PlainStatistics reference_statistics{};
  PlainDopri5(&model, kPlainOdeintControl, 1e-12, 0.0, x.data(), times.data(), times.size(),
              reference.data(), &step, &reference_statistics);
  rubcont::RubFixedFrame system(structure, omega);
  const Vector scale = system.StateScale();
  struct Method {
    std::string name;
    rubcont::IntegratorOptions options;
  };
  std::vector<Method> methods;
  const auto add = [&](std::string name, IntegrationMethod method, double tolerance, int order,
                       long collocation_steps) {
    rubcont::IntegratorOptions options = o.integrator;
    options.method = method;
    options.relative_tolerance = options.absolute_tolerance = tolerance;
    options.max_order = method == IntegrationMethod::kBdf ? order : 0;
    if (method == IntegrationMethod::kDiagonallyImplicitRungeKutta) options.implicit_order = order;
    if (collocation_steps > 0) options.collocation_steps = collocation_steps;
    options.max_steps = 10000000;
    methods.push_back({std::move(name), options});
  };
  for (double tolerance : {1e-7, 1e-8, 1e-9}) {
    add(fmt::format("Dormand-Prince {:g}", tolerance), IntegrationMethod::kDormandPrince, tolerance, 0, 0);
  }
  for (double tolerance : {1e-5, 1e-6, 1e-7, 1e-8}) {
    add(fmt::format("BDF <= 2 {:g}", tolerance), IntegrationMethod::kBdf, tolerance, 2, 0);
  }
  for (double tolerance : {1e-6, 1e-7, 1e-8}) {
    add(fmt::format("BDF <= 5 {:g}", tolerance), IntegrationMethod::kBdf, tolerance, 5, 0);
  }
  for (double tolerance : {1e-6, 1e-7, 1e-8}) {
    add(fmt::format("DIRK 4 {:g}", tolerance), IntegrationMethod::kDiagonallyImplicitRungeKutta, tolerance, 4, 0);
  }
  for (long steps : {2000L, 8000L, 32000L}) {
    add(fmt::format("Gauss s = 4, {} steps", steps), IntegrationMethod::kGaussCollocation, 1e-8, 0, steps);
  }
  std::printf("  other methods, one window (%g s) from the same state; error: max over the samples of "
              "the scaled distance to the plain C at 1e-12\n", simulated);
  std::printf("  %-30s %10s %10s %10s %10s %10s\n", "", "CPU s/s", "steps/s", "f/s", "Jac/s", "error");
  for (const Method& method : methods) {
    rubcont::OdeIntegrator integrator(system, method.options);
    rubcont::Matrix states;
    const double c0 = rubcont::ProcessCpuSeconds();
    const rubcont::IntegrationResult result = integrator.Sample(0.0, x0, times, states);
    const double cpu = rubcont::CpuSecondsSince(c0);
    double error = 0.0;
    for (long k = 0; k < times.size(); ++k) {
      const Eigen::Map<const Vector> r(reference.data() + 16 * k, 16);
      error = std::max(error, ScaledDistance(states.col(k), r, scale));
    }
    const rubcont::IntegrationStatistics& s = result.statistics;
    std::printf("  %-30s %10.3f %10.0f %10.0f %10.0f %10.1e%s\n", method.name.c_str(), cpu / simulated,
                s.steps / simulated, s.rhs_evaluations / simulated, s.jacobian_evaluations / simulated,
                error, result.status == rubcont::IntegrationStatus::kSuccess ? "" : "  (failed)");
    std::fflush(stdout);
  }
}

void MeasureRegime(const rubcont::Scene& scene, const Regime& regime, int repeats, bool methods) {
  const rubcont::RubStructure structure = rubcont::SweepStructureOf(scene);
  rubcont::Scene approach_scene = scene;
  approach_scene.analysis.sweep.up_range_rpm = {regime.from_rpm, regime.to_rpm};
  const rubcont::RubSweepOptions approach_options =
      rubcont::RubSweepOptionsOf(approach_scene, rubcont::SweepDirection::kUp);
  const double omega = rubcont::RpmToRadPerSecond(regime.to_rpm);
  const rubcont::SweepApproach approach = rubcont::ApproachSweep(structure, approach_options, omega);
  if (approach.status != rubcont::ApproachStatus::kReached) {
    std::printf("%s: %s\n", regime.name, approach.BriefReport().c_str());
    return;
  }
  const Vector& x0 = approach.state;
  rubcont::RubSweepOptions speed = approach_options;
  speed.sweep.parameters = {omega};
  const rubcont::SweepOptions& o = speed.sweep;
  const PlainRubData data = PlainDataOf(scene.two_point);
  const double tolerance = o.integrator.relative_tolerance;

  // The plain model against the library's at the approach state.
  rubcont::RubFixedFrame system(structure, omega);
  const Vector scale = system.StateScale();
  Vector f(16), g(16);
  system.Rhs(0.0, x0, f);
  PlainRub plain_model;
  PlainRubInit(&data, omega, &plain_model);
  PlainRubRhs(&plain_model, x0.data(), g.data());
  double scale_difference = 0.0;
  for (int i = 0; i < 16; ++i) scale_difference = std::max(scale_difference, std::abs(plain_model.scale[i] / scale(i) - 1.0));

  // The right-hand sides alone at the approach state, per call (the integrators' other cost is the
  // rest of the CPU per step; both are calls into other translation units, never optimized away).
  constexpr long kCalls = 2000000;
  double c0 = rubcont::ProcessCpuSeconds();
  for (long i = 0; i < kCalls; ++i) {
    system.Rhs(0.0, x0, f);
  }
  const double rubcont_call = rubcont::CpuSecondsSince(c0) / kCalls;
  c0 = rubcont::ProcessCpuSeconds();
  for (long i = 0; i < kCalls; ++i) {
    PlainRubRhs(&plain_model, x0.data(), g.data());
  }
  const double plain_call = rubcont::CpuSecondsSince(c0) / kCalls;
  system.Rhs(0.0, x0, f);
  PlainRubRhs(&plain_model, x0.data(), g.data());

  std::vector<double> sweep_cpu, integrator_cpu, plain_field_cpu, unlanded_cpu, plain_cpu, hairer_cpu;
  rubcont::IntegrationStatistics sweep_statistics;
  PlainRun plain, hairer;
  Vector sweep_end, integrator_end, plain_field_end, unlanded_end;
  int windows = 0;
  double simulated = 0.0;
  for (int r = 0; r < repeats; ++r) {
    {
      rubcont::SweepRun run(structure, speed, {}, x0);
      const double c0 = rubcont::ProcessCpuSeconds();
      run.stepper().Step();
      sweep_cpu.push_back(rubcont::CpuSecondsSince(c0));
      const rubcont::SweepPoint& p = run.stepper().points().back();
      sweep_statistics = p.statistics;
      windows = p.windows;
      simulated = p.simulated_time;
      sweep_end = run.stepper().state();
    }
    const Vector times = SpeedTimes(o, windows);
    {
      rubcont::RubFixedFrame marching(structure, omega);
      integrator_cpu.push_back(IntegrateWindows(marching, o.integrator, x0, times, windows, integrator_end));
      PlainField plain_field(structure, omega, data);
      plain_field_cpu.push_back(IntegrateWindows(plain_field, o.integrator, x0, times, windows, plain_field_end));
      rubcont::IntegratorOptions unlanded = o.integrator;
      unlanded.land_on_switches = false;
      unlanded_cpu.push_back(IntegrateWindows(marching, unlanded, x0, times, windows, unlanded_end));
    }
    plain = RunPlain(data, omega, kPlainOdeintControl, tolerance, x0, times);
    plain_cpu.push_back(plain.cpu);
    hairer = RunPlain(data, omega, kPlainHairerControl, tolerance, x0, times);
    hairer_cpu.push_back(hairer.cpu);
  }
  const double sweep = Median(sweep_cpu) / simulated, integrator = Median(integrator_cpu) / simulated,
               plain_field = Median(plain_field_cpu) / simulated,
               unlanded = Median(unlanded_cpu) / simulated,
               plain_s = Median(plain_cpu) / simulated, hairer_s = Median(hairer_cpu) / simulated;
  std::printf("\n%s at %g rpm (approach %s; %d windows, %g s simulated; model check: |Δf| / |f| = "
              "%.1e, scales %.1e)\n",
              regime.name, regime.to_rpm, approach.BriefReport().c_str(), windows, simulated,
              (f - g).cwiseQuotient(scale).norm() / f.cwiseQuotient(scale).norm(), scale_difference);
  std::printf("  one f: RubFixedFrame::Rhs %.1f ns, plain C %.1f ns (%d contact(s) closed)\n",
              1e9 * rubcont_call, 1e9 * plain_call, ClosedContacts(system, x0));
  std::printf("  %-30s %10s %8s %10s %10s %9s %12s\n", "", "CPU s/s", "ratio", "steps/s", "f/s",
              "rejected", "end vs plain");
  std::printf("  %-30s %10.3f %8.2f %10.0f %10.0f %9.3f %12.1e\n", "rubcont sweep speed", sweep,
              sweep / plain_s, sweep_statistics.steps / simulated,
              sweep_statistics.rhs_evaluations / simulated,
              double(sweep_statistics.error_test_failures) / std::max(1L, sweep_statistics.steps),
              ScaledDistance(sweep_end, plain.end, scale));
  std::printf("  %-30s %10.3f %8.2f %10s %10s %9s %12.1e\n", "rubcont integrator alone", integrator,
              integrator / plain_s, "", "", "", ScaledDistance(integrator_end, plain.end, scale));
  std::printf("  %-30s %10.3f %8.2f %10s %10s %9s %12.1e\n", "rubcont integrator, plain f",
              plain_field, plain_field / plain_s, "", "", "", ScaledDistance(plain_field_end, plain.end, scale));
  std::printf("  %-30s %10.3f %8.2f %10s %10s %9s %12.1e\n", "rubcont integrator, no landing",
              unlanded, unlanded / plain_s, "", "", "", ScaledDistance(unlanded_end, plain.end, scale));
  std::printf("  %-30s %10.3f %8.2f %10.0f %10.0f %9.3f %12s\n", "plain C, Odeint's control",
              plain_s, 1.0, plain.statistics.steps / simulated,
              plain.statistics.rhs_evaluations / simulated,
              double(plain.statistics.rejected) / std::max(1L, plain.statistics.steps), "");
  std::printf("  %-30s %10.3f %8.2f %10.0f %10.0f %9.3f %12.1e\n", "plain C, Hairer's PI control",
              hairer_s, hairer_s / plain_s, hairer.statistics.steps / simulated,
              hairer.statistics.rhs_evaluations / simulated,
              double(hairer.statistics.rejected) / std::max(1L, hairer.statistics.steps),
              ScaledDistance(hairer.end, plain.end, scale));
  std::fflush(stdout);
  if (methods) CompareMethods(structure, data, omega, x0, o);
}

// The precession [Hz] of the last analysis_length of a speed, from samples of one contact's
// relative motion (16 × count, column-major).
double Precession(const std::vector<double>& samples, long count, const rubcont::SweepOptions& o) {
  const long n = std::lround(o.analysis_length * o.sample_rate);
  rubcont::ComplexVector z(n);
  for (long k = 0; k < n; ++k) {
    const double* x = samples.data() + 16 * (count - n + k);
    z(k) = std::complex<double>(x[0] - x[4], x[1] - x[5]);
  }
  const rubcont::SpectralPeak peak = rubcont::DominantPeak(rubcont::TwoSidedSpectrum(z, o.sample_rate),
                                                           rubcont::PeakSide::kNegative, o.min_frequency);
  return peak.found ? -peak.frequency : rubcont::kNaN;
}

void MeasureSchedule(const rubcont::Scene& scene) {
  rubcont::Scene s = scene;
  s.analysis.sweep.up_range_rpm = {44.0, 184.0};
  const rubcont::RubSweepOptions options = rubcont::RubSweepOptionsOf(s, rubcont::SweepDirection::kUp);
  const rubcont::RubStructure structure = rubcont::SweepStructureOf(s);
  const PlainRubData data = PlainDataOf(s.two_point);
  const rubcont::SweepOptions& o = options.sweep;
  const int windows = o.settle_windows + 1;
  std::printf("\nschedule 44 → 184 rpm, %zu speeds × %g s (rubcont: up to the dwell, %g s)\n",
              o.parameters.size(), windows * o.window, o.dwell);

  // rubcont.
  const std::string stays = "– (on the whip to 184 rpm)";
  std::string rubcont_leaves = stays;
  // Per speed, for the ratio over the speeds both runs spend in the same regimes (before either
  // leaves the whip: past it they integrate different motions).
  std::vector<double> rubcont_cpu_at, rubcont_simulated_at, plain_cpu_at, plain_simulated_at;
  std::size_t rubcont_left = o.parameters.size(), plain_left = o.parameters.size();
  {
    rubcont::SweepRun run(structure, options);
    while (!run.stepper().Done() && !run.stepper().Failed()) {
      const double c0 = rubcont::ProcessCpuSeconds();
      run.stepper().Step();
      rubcont_cpu_at.push_back(rubcont::CpuSecondsSince(c0));
    }
    const auto& points = run.stepper().points();
    for (std::size_t i = 0; i < points.size(); ++i) {
      rubcont_simulated_at.push_back(points[i].simulated_time);
      const double bp = -points[i].channels[0].peak.frequency;
      if (i > 0 && rubcont_leaves == stays && bp > 150.0 && rubcont::RadPerSecondToRpm(o.parameters[i]) > 100) {
        rubcont_leaves = fmt::format("{:g} → {:g} rpm", rubcont::RadPerSecondToRpm(o.parameters[i - 1]),
                                     rubcont::RadPerSecondToRpm(o.parameters[i]));
        rubcont_left = i;
      }
    }
  }
  // The plain reference: the same speeds, the same start (rest plus the impulse), windows × window
  // each, sampled at the same rate.
  std::string plain_leaves = stays;
  {
    Vector x = rubcont::RubImpulseIncrement(structure, options.impulse);
    const Vector times = SpeedTimes(o, windows);
    std::vector<double> samples(16 * static_cast<std::size_t>(times.size()));
    double previous_rpm = 0.0;
    for (double omega : o.parameters) {
      PlainRub model;
      PlainRubInit(&data, omega, &model);
      PlainStatistics statistics{};
      double step = 0.0;
      const double c0 = rubcont::ProcessCpuSeconds();
      PlainDopri5(&model, kPlainOdeintControl, o.integrator.relative_tolerance, 0.0, x.data(),
                  times.data(), times.size(), samples.data(), &step, &statistics);
      plain_cpu_at.push_back(rubcont::CpuSecondsSince(c0));
      plain_simulated_at.push_back(times(times.size() - 1));
      const double rpm = rubcont::RadPerSecondToRpm(omega);
      if (plain_leaves == stays && rpm > 100 && Precession(samples, times.size(), o) > 150.0) {
        plain_leaves = fmt::format("{:g} → {:g} rpm", previous_rpm, rpm);
        plain_left = plain_cpu_at.size() - 1;
      }
      previous_rpm = rpm;
    }
  }
  // The first `count` speeds' sum (all of them for SIZE_MAX).
  auto sum = [](const std::vector<double>& at, std::size_t count) {
    return std::accumulate(at.begin(), at.begin() + static_cast<std::ptrdiff_t>(std::min(count, at.size())), 0.0);
  };
  const std::size_t all = SIZE_MAX;
  const double rubcont_cpu = sum(rubcont_cpu_at, all), rubcont_simulated = sum(rubcont_simulated_at, all);
  const double plain_cpu = sum(plain_cpu_at, all), plain_simulated = sum(plain_simulated_at, all);
  std::printf("  rubcont sweep   %7.2f s CPU for %5.2f s simulated (%.3f s/s), leaves the whip at %s\n",
              rubcont_cpu, rubcont_simulated, rubcont_cpu / rubcont_simulated, rubcont_leaves.c_str());
  std::printf("  plain C         %7.2f s CPU for %5.2f s simulated (%.3f s/s), leaves the whip at %s\n",
              plain_cpu, plain_simulated, plain_cpu / plain_simulated, plain_leaves.c_str());
  std::printf("  ratio rubcont / plain, per simulated second: %.2f\n",
              (rubcont_cpu / rubcont_simulated) / (plain_cpu / plain_simulated));
  const std::size_t common = std::min({rubcont_left, plain_left, rubcont_cpu_at.size(),
                                       rubcont_simulated_at.size(), plain_cpu_at.size()});
  if (common > 0) {
    const double rc = sum(rubcont_cpu_at, common), rs = sum(rubcont_simulated_at, common);
    const double pc = sum(plain_cpu_at, common), ps = sum(plain_simulated_at, common);
    std::printf("  the speeds before either leaves the whip, 44 → %g rpm: rubcont %.2f s CPU for %.2f s, "
                "plain C %.2f s for %.2f s: ratio %.2f\n",
                rubcont::RadPerSecondToRpm(o.parameters[common - 1]), rc, rs, pc, ps, (rc / rs) / (pc / ps));
  }
}

// The machine's load average over the last minute (/proc/loadavg; NaN where there is none): the
// CPU times are measured beside other work.
double LoadAverage() {
  double load = rubcont::kNaN;
  if (std::FILE* file = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(file, "%lf", &load) != 1) load = rubcont::kNaN;
    std::fclose(file);
  }
  return load;
}

}  // namespace

static int Run(int argc, char** argv) {
  std::string scene_file = "scenes/thesis_A_a.toml";
  std::string only;
  int repeats = 5;
  bool schedule = false, regimes = true, methods = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeats" && i + 1 < argc) repeats = std::atoi(argv[++i]);
    else if (a == "--regime" && i + 1 < argc) only = argv[++i];
    else if (a == "--schedule") schedule = true;
    else if (a == "--methods") methods = true;
    else if (a == "--schedule-only") schedule = true, regimes = false;
    else scene_file = a;
  }
  const rubcont::Scene scene = rubcont::LoadScene(scene_file);
  const rubcont::SweepOptions o = rubcont::SweepOptionsOf(scene, rubcont::SweepDirection::kUp);
  std::printf("march_bench: scene %s, integrator %s at rtol = atol = %g, %g s windows at %g Hz, "
              "CPU medians of %d\n", scene.name.c_str(), rubcont::ToString(o.integrator.method),
              o.integrator.relative_tolerance, o.window, o.sample_rate, repeats);
  std::printf("load average (1 min, 2 cores) at the start: %.2f\n", LoadAverage());
  if (regimes) {
    const std::vector<Regime> list = {
        {"whirl", 20, 40}, {"whip, full contact", 56, 80}, {"whip, impacting", 56, 160}};
    for (const Regime& r : list) {
      if (only.empty() || only == r.name) MeasureRegime(scene, r, repeats, methods);
    }
  }
  if (schedule) MeasureSchedule(scene);
  std::printf("\nload average (1 min) at the end: %.2f\n", LoadAverage());
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("march_bench", [&] { return Run(argc, argv); });
}
