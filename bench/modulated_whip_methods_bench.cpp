// The modulated whip of case A(a) at the thesis's contact stiffness (k1 = 1.75e11 N/m), shot as
// relative periodic orbits (shooting/rub_orbits.h) with each integrator, in one run: CVODES BDF
// with sensitivities (the reference at rtol 1e-9, and the old default 1e-7) against Gauss
// collocation on fixed meshes (solvers/ode_gauss.cpp). Part 1 continues each from the Hopf point
// to 56 rpm (the engine places the last orbit on the bound) and compares the orbit there with the
// reference: modulation 1/T, carrier, the four largest Floquet multipliers; CPU time per
// continuation step (median). Part 2 times the whole family 51.7 → 63 rpm for the Gauss variants.
// Usage: modulated_whip_methods_bench [VARIANT ...]   VARIANT: bdf:RTOL or gauss:STAGES:STEPS
//        (default: the table of docs/studies/orbits.md; the first variant is the reference).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

struct Variant {
  std::string name;
  IntegratorOptions integrator;
};

Variant Parse(const std::string& text) {
  Variant v{text, {}};
  if (text.rfind("bdf:", 0) == 0) {
    v.integrator.relative_tolerance = v.integrator.absolute_tolerance = std::atof(text.c_str() + 4);
  } else if (text.rfind("gauss:", 0) == 0) {
    v.integrator.method = IntegrationMethod::kGaussCollocation;
    v.integrator.collocation_stages = std::atoi(text.c_str() + 6);
    v.integrator.collocation_steps = std::atol(text.c_str() + text.find(':', 6) + 1);
    v.integrator.relative_tolerance = v.integrator.absolute_tolerance = 1e-9;
  } else {
    std::fprintf(stderr, "variant %s: expected bdf:RTOL or gauss:STAGES:STEPS\n", text.c_str());
    std::exit(2);
  }
  v.integrator.max_steps = 2000000;
  return v;
}

struct Run {
  PeriodicOrbitBranch orbits;
  double cpu = 0.0;
  std::vector<double> step_cpu;
};

Run Continue(const RubStructure& structure, const std::vector<RotatingWaveBranch>& branches,
             const RubHopfStart& start, const Variant& variant, double rpm_max) {
  HopfOrbitOptions options;
  options.amplitude = 1e-3;
  options.orbits.lambda_min = RpmToRadPerSecond(20);
  options.orbits.lambda_max = RpmToRadPerSecond(rpm_max);
  options.orbits.shooting.segments = 4;
  options.orbits.shooting.integrator = variant.integrator;
  options.orbits.shooting.sensitivities_in_residual = true;
  options.orbits.continuation.bounds.max_steps = 200;
  options.orbits.continuation.step.target_iterations = 5;
  Run run;
  double last = ProcessCpuSeconds();
  options.on_step = [&run, &last](const Branch&) {
    const double now = ProcessCpuSeconds();
    run.step_cpu.push_back(now - last);
    last = now;
    return true;
  };
  const double cpu0 = ProcessCpuSeconds();
  run.orbits = ContinueModulatedOrbits(structure, branches, start, options).orbits;
  run.cpu = CpuSecondsSince(cpu0);
  return run;
}

double Median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// The four largest multipliers by modulus.
std::vector<std::complex<double>> Largest(const BranchPoint& p) {
  std::vector<std::complex<double>> mu(p.spectrum.values.data(),
                                       p.spectrum.values.data() + p.spectrum.values.size());
  std::sort(mu.begin(), mu.end(),
            [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  mu.resize(std::min<std::size_t>(mu.size(), 4));
  return mu;
}

int Main(int argc, char** argv) {
  std::vector<Variant> variants;
  for (int i = 1; i < argc; ++i) variants.push_back(Parse(argv[i]));
  if (variants.empty()) {
    for (const char* v : {"bdf:1e-9", "bdf:1e-7", "gauss:4:25", "gauss:4:50", "gauss:4:100",
                          "gauss:3:50", "gauss:4:200"}) {
      variants.push_back(Parse(v));
    }
  }
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  const RubStructure structure = TwoPointStructure(params);
  RotatingWaveBranchOptions wave_options;
  wave_options.search.speed_min = RpmToRadPerSecond(20);
  wave_options.search.speed_max = RpmToRadPerSecond(120);
  wave_options.search.precession_max = HzToRadPerSecond(200);
  const auto branches =
      ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, wave_options, {});
  const RubHopfStart start = StableBoundaryHopfPoints(branches, structure.Coordinates()).at(0);
  std::printf("Hopf point %.4f rpm, carrier %.4f Hz; 4 segments; CPU seconds of the process\n\n",
              RadPerSecondToRpm(start.speed), RadPerSecondToHz(start.precession));

  std::printf("Part 1: from the Hopf point to 56 rpm\n");
  std::printf("%-12s %6s %9s %12s %10s %15s %15s %10s %s\n", "variant", "orbits", "CPU s",
              "median s/step", "steps", "modulation Hz", "carrier Hz", "rel. dT", "|mu| (4 largest)");
  std::vector<double> reference_measures;
  std::vector<std::complex<double>> reference_mu;
  for (const Variant& v : variants) {
    const Run run = Continue(structure, branches, start, v, 56.0);
    const Branch& b = run.orbits.branch;
    const BranchPoint& last = b.points.back();
    const double modulation = b.Measure("modulation_hz")(b.Size() - 1);
    const double carrier = b.Measure("precession_hz")(b.Size() - 1);
    const std::vector<std::complex<double>> mu = Largest(last);
    std::printf("%-12s %6zu %9.2f %12.3f %10ld %15.9f %15.10f", v.name.c_str(), b.points.size(),
                run.cpu, Median(run.step_cpu), run.orbits.work.steps, modulation, carrier);
    std::printf("  at %.9f rpm, %s\n", RadPerSecondToRpm(last.lambda), b.message.c_str());
    if (reference_measures.empty()) {
      reference_measures = {modulation, carrier};
      reference_mu = mu;
    }
    // The largest multiplier, and each of the reference's four matched to the nearest of all.
    const double largest_error = std::abs(mu[0] - reference_mu[0]);
    double match_error = 0.0;
    for (const auto& r : reference_mu) {
      double nearest = kInfinity;
      for (Index k = 0; k < last.spectrum.values.size(); ++k) {
        nearest = std::min(nearest, std::abs(last.spectrum.values(k) - r));
      }
      match_error = std::max(match_error, nearest);
    }
    std::printf("%-12s   vs reference: modulation %.2e, carrier %.2e relative; largest multiplier"
                " %.2e, the reference's four matched %.2e; |mu| =", "",
                std::abs(modulation / reference_measures[0] - 1),
                std::abs(carrier / reference_measures[1] - 1), largest_error, match_error);
    for (const auto& m : mu) std::printf(" %.6f", std::abs(m));
    std::printf("\n");
    std::fflush(stdout);
  }

  std::printf("\nPart 2: the whole family to 63 rpm (Gauss variants)\n");
  for (const Variant& v : variants) {
    if (v.integrator.method != IntegrationMethod::kGaussCollocation) continue;
    const Run run = Continue(structure, branches, start, v, 63.0);
    const Branch& b = run.orbits.branch;
    std::printf("%-12s %4zu orbits to %.3f rpm in %.2f s CPU (median %.3f s/step); special points:",
                v.name.c_str(), b.points.size(), RadPerSecondToRpm(b.points.back().lambda), run.cpu,
                Median(run.step_cpu));
    for (const SpecialPoint& p : b.special_points) {
      std::printf(" %s %.4f rpm%s", ToString(p.type), RadPerSecondToRpm(p.lambda),
                  p.converged ? "" : " (not converged)");
    }
    std::printf("; %s\n", b.message.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("modulated_whip_methods_bench",
                               [&] { return rubcont::Main(argc, argv); });
}
