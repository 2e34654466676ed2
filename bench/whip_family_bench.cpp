// The A(a) modulated whip family from its Hopf point (issue 49, items 1–2): CPU, orbits, Newton
// iterations and where each step was limited, and the landmarks (branch points, period doubling,
// stability, grazing), with the orbits stage's settings (apps/orbits_stage.cpp: 4 segments, Gauss
// collocation s = 4 on 400 intervals per modulation period, the engine's steps up to 1 with target
// angle 0.3 and 5 target iterations) and the step-control levers on the command line, to measure
// them one by one against the same run.
//
// Usage: whip_family_bench [--to RPM] [--intervals N] [--angle A] [--max-angle A] [--iterations K]
//                          [--growth G] [--max-step S] [--steps N] [--tolerance T] [--residual R]
//                          [--step-tolerance D] [--failure-memory N]
//                          [--curved-predictor] [--stop-at-grazing] [--adapt-mesh K]
//                          [--mesh-floor F] [--samples N] [--verbose] [--digest] [--no-defect-check]
// --max-angle: the engine's rejection angle (default its 0.35 rad, raised to --angle if below).
// --stop-at-grazing: PeriodicOrbitBranchOptions::stop_at_grazing (the family ends at its first
// located grazing with status kGrazing); the cost from the last orbit before each grazing to the
// end of the run is printed.
// --tolerance: the shooting's (Gauss: its Newton stops at 1e-3·T, scaled); --residual: the
// continuation corrector's residual tolerance (default the engine's); --step-tolerance: its bound on
// the last Newton correction (default the engine's); --failure-memory: StepOptions::failure_memory
// (default 0, off); --curved-predictor: StepOptions::curved_predictor (the parabola through the
// previous point as the corrector's first iterate); --adapt-mesh K: ShootingOptions::
// adapt_mesh_every (the collocation steps equidistributed on every K-th orbit; default 0, uniform),
// --mesh-floor: its adapt_mesh_floor. --samples N: ShootingOptions::samples_per_segment (the
// samples the measures and the grazing tests read; default 64). --digest: a hash of every bit of
// the orbits and special points (unknowns, speed, measures, tangents, multipliers), to tell two
// builds' runs apart or not.
// The CPU of the orbits' measures is printed per measure; --no-defect-check drops the "defect"
// measure (RubOrbitMeasures' Dormand–Prince at 1e-12 over every orbit: an independent check
// AUTO-07p has no counterpart of), to set the continuation alone beside AUTO's.
// Default: to 63 rpm (the first figure), the stage's settings.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "bench/bench_main.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

#include "a_a_whip_starts.h"

namespace rubcont {
namespace {

// FNV-1a over the bytes of every number the family's points and special points hold.
class Fnv1a {
 public:
  void Add(double x) {
    unsigned char bytes[sizeof x];
    std::memcpy(bytes, &x, sizeof x);
    for (unsigned char b : bytes) hash_ = (hash_ ^ b) * 1099511628211ULL;
  }
  void Add(const Vector& v) {
    for (Index i = 0; i < v.size(); ++i) Add(v(i));
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ULL;
};

std::uint64_t Digest(const Branch& branch) {
  Fnv1a hash;
  for (const BranchPoint& p : branch.points) {
    hash.Add(p.lambda);
    hash.Add(p.u);
    hash.Add(p.measures);
    hash.Add(p.tangent);
    for (Index i = 0; i < p.spectrum.values.size(); ++i) {
      hash.Add(p.spectrum.values(i).real());
      hash.Add(p.spectrum.values(i).imag());
    }
  }
  for (const SpecialPoint& s : branch.special_points) {
    hash.Add(s.lambda);
    hash.Add(s.u);
    hash.Add(s.measures);
  }
  return hash.value();
}

int Main(int argc, char** argv) {
  double to_rpm = 63.0, angle = 0.3, max_angle = 0.0, growth = 2.0, max_step = 1.0,
         tolerance = 1e-7, residual = 0.0, step_tolerance = 0.0;
  int intervals = 400, iterations = 5, steps = 400, failure_memory = 0, adapt_mesh = 0;
  double mesh_floor = ShootingOptions{}.adapt_mesh_floor;
  int samples = 0;
  bool verbose = false, stop_at_grazing = false, curved_predictor = false, digest = false,
       defect_check = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--to") to_rpm = next();
    else if (a == "--intervals") intervals = static_cast<int>(next());
    else if (a == "--angle") angle = next();
    else if (a == "--max-angle") max_angle = next();
    else if (a == "--iterations") iterations = static_cast<int>(next());
    else if (a == "--growth") growth = next();
    else if (a == "--max-step") max_step = next();
    else if (a == "--steps") steps = static_cast<int>(next());
    else if (a == "--tolerance") tolerance = next();
    else if (a == "--residual") residual = next();
    else if (a == "--step-tolerance") step_tolerance = next();
    else if (a == "--failure-memory") failure_memory = static_cast<int>(next());
    else if (a == "--stop-at-grazing") stop_at_grazing = true;
    else if (a == "--curved-predictor") curved_predictor = true;
    else if (a == "--adapt-mesh") adapt_mesh = static_cast<int>(next());
    else if (a == "--mesh-floor") mesh_floor = next();
    else if (a == "--samples") samples = static_cast<int>(next());
    else if (a == "--verbose") verbose = true;
    else if (a == "--digest") digest = true;
    else if (a == "--no-defect-check") defect_check = false;
  }
  const double cpu_waves = ProcessCpuSeconds();
  const AaWhipStarts a = ComputeAaWhipStarts();
  const RubStructure& structure = a.structure;
  const auto& branches = a.branches;
  const auto& starts = a.starts;
  if (starts.empty()) return 1;
  const double waves_cpu = CpuSecondsSince(cpu_waves);

  HopfOrbitOptions options;
  options.amplitude = 1e-3;
  options.orbits.lambda_min = RpmToRadPerSecond(20);
  options.orbits.lambda_max = RpmToRadPerSecond(to_rpm);
  ShootingOptions& shooting = options.orbits.shooting;
  shooting.segments = 4;
  shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  shooting.integrator.relative_tolerance = shooting.integrator.absolute_tolerance = tolerance;
  shooting.integrator.collocation_steps = (intervals + 3) / 4;
  shooting.sensitivities_in_residual = true;
  shooting.adapt_mesh_every = adapt_mesh;
  shooting.adapt_mesh_floor = mesh_floor;
  if (samples > 0) shooting.samples_per_segment = samples;
  ContinuationOptions& c = options.orbits.continuation;
  c.step.max = max_step;
  c.step.target_angle = angle;
  c.step.max_angle = max_angle > 0.0 ? max_angle : std::max(c.step.max_angle, angle);
  c.step.target_iterations = iterations;
  c.step.max_growth = growth;
  c.step.failure_memory = failure_memory;
  c.step.curved_predictor = curved_predictor;
  c.bounds.max_steps = steps;
  if (residual > 0.0) c.corrector.residual_tolerance = residual;
  if (step_tolerance > 0.0) c.corrector.step_tolerance = step_tolerance;
  options.orbits.stop_at_grazing = stop_at_grazing;
  // The family's own measures (ContinueModulatedOrbits' default), each timed.
  const RubHopfStart& start = starts.front();
  const std::vector<OrbitMeasure> measures = RubFamilyMeasures(
      RubRotatingFrame(structure, start.precession, start.speed), shooting, 1, defect_check);
  std::vector<double> measure_cpu(measures.size(), 0.0);
  for (std::size_t i = 0; i < measures.size(); ++i) {
    options.orbits.measures.push_back(
        {measures[i].name, [evaluate = measures[i].evaluate, &cpu = measure_cpu[i]](
                               const OrbitSamples& orbit) {
           const double cpu0 = ProcessCpuSeconds();
           const double value = evaluate(orbit);
           cpu += CpuSecondsSince(cpu0);
           return value;
         }});
  }
  std::vector<double> cpu_at;  // CPU seconds at each accepted orbit
  options.on_step = [&](const Branch& b) {
    cpu_at.resize(b.points.size(), ProcessCpuSeconds());
    return true;
  };
  const double cpu0 = ProcessCpuSeconds();
  const RubModulatedOrbits result = ContinueModulatedOrbits(structure, branches, start, options);
  const double cpu = CpuSecondsSince(cpu0);
  const Branch& branch = result.orbits.branch;
  long newton = 0;
  for (const BranchPoint& p : branch.points) newton += p.newton_iterations;
  std::printf("whip_family_bench: Hopf %.8f rpm → %g rpm, %d intervals, angle %g, iterations %d, "
              "max angle %g, growth %g, max step %g, tolerance %g, residual %g, correction %g, "
              "failure memory %d%s, mesh %s (floor %g)\n",
              RadPerSecondToRpm(start.speed), to_rpm, intervals, angle, iterations,
              c.step.max_angle, growth, max_step, tolerance, c.corrector.residual_tolerance,
              c.corrector.step_tolerance, failure_memory, curved_predictor ? ", curved predictor" : "",
              adapt_mesh > 0 ? fmt::format("adapted every {} orbits", adapt_mesh).c_str() : "uniform",
              mesh_floor);
  std::printf("  %zu orbits, %ld Newton iterations, %ld integrator steps, %.2f s CPU (waves %.2f s): %s\n",
              branch.points.size(), newton, result.orbits.work.steps, cpu, waves_cpu,
              branch.BriefReport().c_str());
  const BranchStatistics& st = branch.statistics;
  const ShootingStatistics& work = result.orbits.work;
  std::printf("  integrator: %ld collocation Newton iterations (%.2f per step), %ld factorisations\n",
              work.nonlinear_iterations,
              static_cast<double>(work.nonlinear_iterations) / static_cast<double>(std::max(1L, work.steps)),
              work.linear_solver_setups);
  std::printf("  %d corrector failures, %d angle rejections, %ld residuals, %ld Jacobians\n",
              st.corrector_failures, st.angle_rejections, st.residual_evaluations,
              st.jacobian_evaluations);
  double all_measures = 0.0;
  std::string per_measure;
  for (std::size_t i = 0; i < measures.size(); ++i) {
    all_measures += measure_cpu[i];
    if (measure_cpu[i] >= 0.005) {
      per_measure += fmt::format(", {} {:.2f} s", measures[i].name, measure_cpu[i]);
    }
  }
  std::printf("  the orbits' measures: %.2f s CPU%s%s\n", all_measures, per_measure.c_str(),
              defect_check ? "" : " (no defect check)");
  for (const SpecialPoint& s : branch.special_points) {
    std::printf("  %-22s %.6f rpm%s %s (%d trial points)\n", ToString(s.type),
                RadPerSecondToRpm(s.lambda), s.converged ? "" : " (guess)", s.label.c_str(),
                s.iterations);
    // The cost past a grazing: from the last orbit before it to the end of the run.
    if (s.type == SpecialPointType::kGrazing && s.index < static_cast<Index>(cpu_at.size())) {
      std::printf("    %.2f s CPU and %zu orbits from the last orbit before it to the end (%s)\n",
                  cpu0 + cpu - cpu_at[static_cast<std::size_t>(s.index)],
                  branch.points.size() - 1 - static_cast<std::size_t>(s.index), branch.message.c_str());
    }
  }
  if (digest) std::printf("  digest %016llx\n", static_cast<unsigned long long>(Digest(branch)));
  if (verbose) {
    // The tangent's turn from the previous point [rad]: which of the step's limits binds; the CPU
    // from the previous orbit (its step, failed attempts, locations and measures).
    for (std::size_t i = 0; i < branch.points.size(); ++i) {
      const BranchPoint& p = branch.points[i];
      const double turn = i == 0 ? 0.0
          : std::acos(std::min(1.0, std::abs(p.tangent.dot(branch.points[i - 1].tangent))));
      const std::string since = i > 0 && i < cpu_at.size()
                                    ? fmt::format("{:.2f} s", cpu_at[i] - cpu_at[i - 1])
                                    : "–";
      std::printf("    %9.4f rpm  ds %.4f  newton %d  turn %.3f  unstable %d  CPU %s\n",
                  RadPerSecondToRpm(p.lambda), p.step, p.newton_iterations, turn, p.num_unstable,
                  since.c_str());
    }
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("whip_family_bench", [&] { return rubcont::Main(argc, argv); });
}
