// Experiment (not part of the test suite): what ends case C(a)'s two-frequency whip between 49 and
// 59 rpm, by L2. The speed-up whip is a torus to 49.2 rpm and chaotic from 49.7 to 57.2 rpm
// (results/thesis_C_a/attractor_*: Lyapunov exponents); between, the attractor is a relative
// periodic orbit. Here that orbit is solved from a settled transient as a locked orbit of three
// modulation periods (SolveModulatedOrbit, laps = 3: the torus locked at 1:3) and continued in
// running speed (ContinuePeriodicOrbits, Floquet stability, folds and period doublings located),
// with the period-doubled family from each located doubling; every special point and the cost of
// each part printed. Then the same at a second speed, to show that both stable pieces lie on one
// family. Usage: locked_whip_bench [RPM [LAPS [FROM TO [CHECK_RPM [AMPLITUDE [CASE [MEMORY [PREDICTOR]]]]]]]],
// defaults 49.4 3 49 59 58 1e-5 a 0 tangent (AMPLITUDE: the doubled orbits' first step off the doubling,
// scaled, tried again 10 and 100 times closer where its start fails; CASE: a, b or c of case C;
// MEMORY: the engine's StepOptions::failure_memory; PREDICTOR: tangent or curved, the engine's
// StepOptions::curved_predictor).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/bench_main.h"
#include "models/units.h"
#include "shooting/modulated_orbit.h"
#include "shooting/modulated_torus.h"
#include "shooting/orbit_branches.h"
#include "shooting/rub_orbits.h"
#include "solvers/stopwatch.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

// Gauss–Legendre collocation of order 8, 400 intervals per modulation period, two segments per
// lap (the orbits stage's mesh for C(a)).
ShootingOptions LockedShooting(int laps) {
  ShootingOptions shooting;
  shooting.segments = 2 * laps;
  shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  shooting.integrator.collocation_stages = 4;
  shooting.integrator.collocation_steps = 200;
  return shooting;
}

double LargestMultiplier(const BranchPoint& p) {
  double largest = 0.0;
  for (Index i = 0; i < p.spectrum.values.size(); ++i) {
    largest = std::max(largest, std::abs(p.spectrum.values(i)));
  }
  return largest;
}

void PrintFamily(const char* name, const PeriodicOrbitBranch& family) {
  const Branch& b = family.branch;
  std::printf("%s: %s\n", name, b.BriefReport().c_str());
  const BranchStatistics& work = b.statistics;
  std::printf("  engine: %d steps, %d corrector failures, %d angle rejections, %d stray, %d jump "
              "rejections\n", work.steps, work.corrector_failures, work.angle_rejections,
              work.stray_rejections, work.jump_rejections);
  // Where the tangent turns (scaled unknowns: the segment starts' n states, T, φ, then λ): the
  // shares of Σ_k |τ_(k+1) − τ_k|² by state index, T, φ and λ, and the mean turning angle.
  const Index n = family.state_dimension, starts = n * family.segments;
  if (b.points.size() >= 2 && b.points[0].tangent.size() >= starts + 1) {
    Vector share = Vector::Zero(n + 3);
    double angles = 0.0;
    for (std::size_t k = 0; k + 1 < b.points.size(); ++k) {
      if (b.points[k + 1].tangent.size() != b.points[k].tangent.size()) continue;
      const Vector d = b.points[k + 1].tangent - b.points[k].tangent;
      for (Index i = 0; i < starts; ++i) share(i % n) += d(i) * d(i);
      for (Index i = starts; i + 1 < d.size(); ++i) {
        share(n + std::min<Index>(i - starts, 1)) += d(i) * d(i);
      }
      share(n + 2) += d(d.size() - 1) * d(d.size() - 1);
      angles += std::acos(std::clamp(b.points[k + 1].tangent.dot(b.points[k].tangent), -1.0, 1.0));
    }
    share /= share.sum();
    std::printf("  tangent turning: mean %.3f rad per step; shares:",
                angles / static_cast<double>(b.points.size() - 1));
    for (Index i = 0; i < n; ++i) std::printf(" x%ld %.3f", static_cast<long>(i), share(i));
    std::printf(" T %.3f phi %.3f lambda %.3f\n", share(n), share(n + 1), share(n + 2));
  }
  for (const SpecialPoint& p : b.special_points) {
    std::printf("  %-16s %.5f rpm  critical multiplier %+.4f%+.4fi  %s\n", ToString(p.type),
                RadPerSecondToRpm(p.lambda), p.critical_value.real(), p.critical_value.imag(),
                p.converged ? "located" : "not located");
  }
  // The stable pieces, from the points' Floquet multipliers.
  for (std::size_t i = 0; i < b.points.size();) {
    if (b.points[i].StableFlag() != 1) {
      ++i;
      continue;
    }
    std::size_t j = i;
    double largest = 0.0;
    while (j + 1 < b.points.size() && b.points[j + 1].StableFlag() == 1) ++j;
    for (std::size_t k = i; k <= j; ++k) largest = std::max(largest, LargestMultiplier(b.points[k]));
    std::printf("  stable from %.5f to %.5f rpm (%zu points, largest |μ| %.4f)\n",
                RadPerSecondToRpm(std::min(b.points[i].lambda, b.points[j].lambda)),
                RadPerSecondToRpm(std::max(b.points[i].lambda, b.points[j].lambda)), j - i + 1,
                largest);
    i = j + 1;
  }
}

int Main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress as it comes
  const double rpm = argc > 1 ? std::atof(argv[1]) : 49.4;
  const int laps = argc > 2 ? std::atoi(argv[2]) : 3;
  const double from_rpm = argc > 3 ? std::atof(argv[3]) : 49.0;
  const double to_rpm = argc > 4 ? std::atof(argv[4]) : 59.0;
  const double check_rpm = argc > 5 ? std::atof(argv[5]) : 58.0;
  const double doubling_amplitude = argc > 6 ? std::atof(argv[6]) : 1e-5;
  const std::string which = argc > 7 ? argv[7] : "a";
  const int failure_memory = argc > 8 ? std::atoi(argv[8]) : 0;
  const std::string predictor = argc > 9 ? argv[9] : "tangent";
  if (predictor != "tangent" && predictor != "curved") {
    std::fprintf(stderr, "locked_whip_bench: PREDICTOR = %s: must be tangent or curved\n", predictor.c_str());
    return 2;
  }
  const TwoPointParams params =
      which == "b" ? ThesisCaseCb() : which == "c" ? ThesisCaseCc() : ThesisCaseCa();
  if (which != "a" && which != "b" && which != "c") {
    std::fprintf(stderr, "locked_whip_bench: CASE = %s: must be a, b or c\n", which.c_str());
    return 2;
  }
  const std::string name = "C(" + which + ")";
  const RubStructure structure = TwoPointStructure(params);
  ModulatedOrbitOptions solve;
  solve.shooting = LockedShooting(laps);
  solve.search_duration = 1.0;
  solve.laps = laps;
  solve.newton.residual_tolerance = solve.newton.step_tolerance = 1e-8;
  solve.newton.max_iterations = 20;

  auto locked_orbit = [&](double at_rpm) {
    const double omega = RpmToRadPerSecond(at_rpm);
    const double start = ProcessCpuSeconds();
    const RubSettledSpeed transient = SettleAtSpeed(structure, LongSettleOptions(omega), 1.0);
    // 4 s more, as the tori's start (SettledTransientStart): at 58 rpm, next to the chaos, the
    // settled transient's slip still had its strongest line at 123.16 Hz, no line of the orbit
    // (3/T = 121.41 Hz), and Newton failed (measured).
    Vector state = transient.state;
    RubFixedFrame fixed(structure, omega);
    const ModulatedTorusOptions tori_start = SettledTransientStart(1);
    OdeIntegrator approach(fixed, tori_start.integrator);
    const IntegrationResult approached =
        approach.Integrate(0.0, transient.state, tori_start.approach, state);
    if (!approached.Succeeded()) {
      std::printf("  (the approach failed: %s; the settled state instead)\n",
                  approached.BriefReport().c_str());
      state = transient.state;
    }
    const double settled = ProcessCpuSeconds();
    const ModulatedOrbit orbit = SolveModulatedOrbit(
        structure, omega, HzToRadPerSecond(transient.precession_hz), state, solve);
    std::printf("%s at %.3f rpm: the transient %s, precession %.4f Hz (%.1f s CPU); the %d-lap "
                "orbit (%.1f s CPU): %s\n", name.c_str(), at_rpm,
                transient.settled ? "settled" : "did not settle", transient.precession_hz,
                settled - start, laps, CpuSecondsSince(settled), orbit.message.c_str());
    return orbit;
  };
  const ModulatedOrbit orbit = locked_orbit(rpm);
  if (!orbit.converged) return 1;

  RubRotatingFrame frame(structure, orbit.frame_rate, RpmToRadPerSecond(rpm));
  PeriodicOrbitBranchOptions options;
  options.lambda_min = RpmToRadPerSecond(from_rpm);
  options.lambda_max = RpmToRadPerSecond(to_rpm);
  options.shooting = solve.shooting;
  options.measures = RubOrbitMeasures(frame);
  options.continuation.corrector.residual_tolerance = 1e-8;
  options.continuation.corrector.max_iterations = 15;
  options.continuation.step.initial = 0.01;
  options.continuation.step.failure_memory = failure_memory;
  options.continuation.step.curved_predictor = predictor == "curved";
  options.continuation.bounds.max_steps = 1500;
  options.stop_round_closed_curve = true;  // the tongue's orbits: a closed curve
  double step_start = ProcessCpuSeconds();
  options.on_step = [&step_start](const Branch& b) {  // every 10th step, with its CPU time
    if (b.points.size() % 10 == 0) {
      const BranchPoint& p = b.points.back();
      std::printf("    step %zu: %.5f rpm, %s, largest |μ| %.4f (%.1f s CPU)\n", b.points.size(),
                  RadPerSecondToRpm(p.lambda), p.StableFlag() == 1 ? "stable" : "unstable",
                  LargestMultiplier(p), CpuSecondsSince(step_start));
      step_start = ProcessCpuSeconds();
    }
    return true;
  };
  double start = ProcessCpuSeconds();
  const PeriodicOrbitBranch family =
      ContinuePeriodicOrbits(frame, OrbitKind::kRelative, StartOf(orbit, RpmToRadPerSecond(rpm)),
                             options);
  std::printf("the %d-lap family over [%g, %g] rpm (%.1f s CPU)\n", laps, from_rpm, to_rpm,
              CpuSecondsSince(start));
  PrintFamily("  family", family);

  // The doubled families at the doublings that bound a stable piece.
  for (std::size_t k = 0; k < family.branch.special_points.size(); ++k) {
    const SpecialPoint& p = family.branch.special_points[k];
    if (p.type != SpecialPointType::kPeriodDoubling || !BoundsStablePiece(family.branch, p)) continue;
    PeriodicOrbitBranchOptions doubled = options;
    doubled.lambda_min = p.lambda - RpmToRadPerSecond(0.3);
    doubled.lambda_max = p.lambda + RpmToRadPerSecond(0.3);
    doubled.continuation.bounds.max_steps = 80;
    doubled.stop_round_closed_curve = false;
    start = ProcessCpuSeconds();
    const OrbitPeriodDoubling d =
        ContinueOrbitsFromPeriodDoubling(frame, family, k, doubled, doubling_amplitude);
    std::printf("the %d-lap family from the doubling at %.5f rpm (%.1f s CPU): %s\n", 2 * laps,
                RadPerSecondToRpm(p.lambda), CpuSecondsSince(start), d.message.c_str());
    if (d.ok) PrintFamily("  doubled", d.branch);
  }

  // The orbit at a second speed, from its own transient, against the family's orbits there.
  const ModulatedOrbit check = locked_orbit(check_rpm);
  if (!check.converged) return 1;
  const Branch& b = family.branch;
  const Index period_index = b.MeasureIndex("period");
  for (std::size_t i = 0; i + 1 < b.points.size(); ++i) {
    const double l0 = RadPerSecondToRpm(b.points[i].lambda);
    const double l1 = RadPerSecondToRpm(b.points[i + 1].lambda);
    if ((l0 - check_rpm) * (l1 - check_rpm) > 0.0) continue;
    const double w = (check_rpm - l0) / (l1 - l0);
    const double period = (1 - w) * b.points[i].measures(period_index) +
                          w * b.points[i + 1].measures(period_index);
    std::printf("  the family crosses %.3f rpm with period %.9g s (%s there); the transient's "
                "orbit: %.9g s\n", check_rpm, period,
                b.points[i].StableFlag() == 1 ? "stable" : "unstable", check.period);
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("locked_whip_bench", [&] { return rubcont::Main(argc, argv); });
}
