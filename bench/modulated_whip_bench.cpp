// Experiment (not part of the test suite): the modulated orbits born at the Hopf points of the
// tanh-law rotating-wave branches of thesis case A(a), shot as relative periodic orbits in the
// co-rotating frame (shooting/rub_orbits.h) and continued in running speed — what the scene stage
// "orbits" does, with the numerics on the command line, to measure their cost.
// Usage: modulated_whip_bench [AMPLITUDE [SEGMENTS [TOLERANCE [STEPS [MAX_ORDER [ERROR_CONTROL
//                             [CONTACT_STIFFNESS [COLLOCATION_STEPS [COLLOCATION_STAGES]]]]]]]]]
// COLLOCATION_STEPS > 0 shoots with Gauss collocation of that many steps per segment instead of
// CVODES BDF (CONTACT_STIFFNESS 0: the thesis's).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bench/bench_main.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

int Main(int argc, char** argv) {
  const double amplitude = argc > 1 ? std::atof(argv[1]) : 1e-3;
  const int segments = argc > 2 ? std::atoi(argv[2]) : 4;
  const double tolerance = argc > 3 ? std::atof(argv[3]) : 1e-7;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 10;
  const int max_order = argc > 5 ? std::atoi(argv[5]) : 0;
  const bool error_control = argc > 6 ? std::atoi(argv[6]) != 0 : true;
  TwoPointParams params = ThesisCaseAa();  // case A(a)
  params.friction_law.kind = FrictionLawKind::kTanh;
  if (argc > 7 && std::atof(argv[7]) > 0) params.contact_stiffness = std::atof(argv[7]);
  const long collocation_steps = argc > 8 ? std::atol(argv[8]) : 0;
  const int collocation_stages = argc > 9 ? std::atoi(argv[9]) : 4;
  const RubStructure structure = TwoPointStructure(params);
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(20);
  options.search.speed_max = RpmToRadPerSecond(260);
  options.search.precession_max = HzToRadPerSecond(200);
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options, {});
  const auto starts = StableBoundaryHopfPoints(branches, structure.Coordinates());
  for (const RubHopfStart& s : starts) {
    std::printf("%s: Hopf at %.4f rpm, precession %.4f Hz, modulation %.3f rad/s, stable %s\n",
                s.branch.c_str(), RadPerSecondToRpm(s.speed), RadPerSecondToHz(s.precession), s.modulation,
                s.stable_below ? "below" : "above");
  }
  if (starts.empty()) return 1;
  HopfOrbitOptions hopf_options;
  hopf_options.amplitude = amplitude;
  hopf_options.orbits.lambda_min = RpmToRadPerSecond(20);
  hopf_options.orbits.lambda_max = RpmToRadPerSecond(260);
  hopf_options.orbits.shooting.segments = segments;
  hopf_options.orbits.shooting.integrator.relative_tolerance = tolerance;
  hopf_options.orbits.shooting.integrator.absolute_tolerance = tolerance;
  hopf_options.orbits.shooting.integrator.max_steps = 2000000;
  hopf_options.orbits.shooting.integrator.max_order = max_order;
  hopf_options.orbits.shooting.integrator.sensitivity_error_control = error_control;
  hopf_options.orbits.shooting.sensitivities_in_residual = true;
  if (collocation_steps > 0) {
    IntegratorOptions& integrator = hopf_options.orbits.shooting.integrator;
    integrator.method = IntegrationMethod::kGaussCollocation;
    integrator.collocation_steps = collocation_steps;
    integrator.collocation_stages = collocation_stages;
  }
  hopf_options.orbits.continuation.bounds.max_steps = steps;
  hopf_options.orbits.continuation.step.target_iterations = 5;
  const SteadyClock::time_point t0 = SteadyClock::now();
  const double cpu0 = ProcessCpuSeconds();
  const RubModulatedOrbits result =
      ContinueModulatedOrbits(structure, branches, starts.front(), hopf_options);
  const double s = SecondsSince(t0);
  const double cpu = CpuSecondsSince(cpu0);
  const Branch& branch = result.orbits.branch;
  std::printf("%s — %s (%.1f s wall, %.1f s CPU, %ld integrator steps)\n",
              branch.BriefReport().c_str(), branch.message.c_str(), s, cpu, result.orbits.work.steps);
  const Vector period = branch.Measure("period"), carrier = branch.Measure("precession_hz");
  const Vector n_min = branch.Measure("min_normal_force_left");
  const Vector n_max = branch.Measure("max_normal_force_left");
  const Vector defect = branch.Measure("defect");
  for (Index i = 0; i < branch.Size(); ++i) {
    const BranchPoint& q = branch.points[static_cast<std::size_t>(i)];
    std::printf("  %9.4f rpm  T = %.6e s  carrier %.4f Hz  N_left %.1f–%.1f N  unstable %d  "
                "max|mu| %.4f  defect %.1e\n",
                RadPerSecondToRpm(q.lambda), period(i), carrier(i), n_min(i), n_max(i), q.num_unstable,
                q.spectrum.values.size() ? q.spectrum.values.cwiseAbs().maxCoeff() : kNaN, defect(i));
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("modulated_whip_bench", [&] { return rubcont::Main(argc, argv); });
}
