// Experiment (not part of the test suite): case C(a)'s two-frequency whip from a settled transient
// (shooting/rub_tori.h, ContinueTransientTori) — the sweep's time-marching model settled at one
// speed from rest and a 1 N·s impulse, the torus it lies on solved by BDF, and the family through
// it continued both ways in running speed — with every torus printed and the cost of each part.
// Usage: transient_tori_bench [RPM [STEPS [HARMONICS [COLLOCATION_STEPS [CASE [COORDINATES
//                              [START_COLLOCATION [MAX_HARMONICS [HALVINGS [IMAGES]]]]]]]]]]
// COLLOCATION_STEPS > 0: the continuation by Gauss collocation of that many steps per modulation
// period; 0: by the start's BDF (sensitivities outside the error test). CASE: a, b or c (case
// C(a), C(b), C(c)); COORDINATES: state or chart (the circle's, shooting/invariant_circle.h).
// START_COLLOCATION: the start's Gauss intervals per modulation period (the scene's
// [analysis.orbits] collocation_intervals with a chart); MAX_HARMONICS: the start refined in K up
// to it; HALVINGS: the start's Newton steps halved up to that many times where they fail;
// IMAGES: the finer circles' starts, the coarser mapped that many times, tried in turn ("3,10").
// Defaults 49, 12, 16, 400, a, state, the options' own.
// STEPS = 0: the start only, its harmonics' sizes and its circle's residual under other maps
// (BDF at tighter tolerances, Gauss on finer meshes): how accurate the start's own map is.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>

#include "bench/bench_main.h"
#include "models/units.h"
#include "shooting/rub_tori.h"
#include "solvers/stopwatch.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

int Main(int argc, char** argv) {
  const double rpm = argc > 1 ? std::atof(argv[1]) : 49.0;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 12;
  const int harmonics = argc > 3 ? std::atoi(argv[3]) : 16;
  const long collocation_steps = argc > 4 ? std::atol(argv[4]) : 400;
  const char case_letter = argc > 5 ? argv[5][0] : 'a';
  const CircleCoordinates coordinates =
      argc > 6 && std::string(argv[6]) == "chart" ? CircleCoordinates::kChart : CircleCoordinates::kState;
  const RubStructure structure = TwoPointStructure(
      case_letter == 'b' ? ThesisCaseCb() : case_letter == 'c' ? ThesisCaseCc() : ThesisCaseCa());
  const double omega = RpmToRadPerSecond(rpm);

  // The transient: 8 s at the speed from rest plus the impulse, settled by 0.5 s windows.
  const double settle_start = ProcessCpuSeconds();
  const RubSettledSpeed transient = SettleAtSpeed(structure, LongSettleOptions(omega), 1.0);
  const double precession_hz = transient.precession_hz;
  const double precession = HzToRadPerSecond(precession_hz);  // [rad/s]
  std::printf("C(%c) at %.3f rpm: the transient %s, precession %.4f Hz (%.1f s CPU)\n", case_letter, rpm,
              transient.settled ? "settled" : "did not settle", precession_hz,
              CpuSecondsSince(settle_start));

  ModulatedTorusOptions start = SettledTransientStart(harmonics);
  start.coordinates = coordinates;
  if (argc > 7) start.collocation_intervals = std::atoi(argv[7]);
  if (argc > 8) start.max_harmonics = std::atoi(argv[8]);
  if (argc > 9) start.newton.max_step_halvings = std::atoi(argv[9]);
  if (argc > 10) {  // e.g. "3,10"
    start.refinement_images.clear();
    std::istringstream counts(argv[10]);
    for (std::string count; std::getline(counts, count, ',');) {
      start.refinement_images.push_back(std::atoi(count.c_str()));
    }
  }
  if (steps == 0) {
    const ModulatedTorus torus =
        SolveModulatedTorus(structure, omega, precession, transient.state,
                            start);
    std::printf("start (%.1f s wall): %s\n", torus.seconds, torus.message.c_str());
    if (!torus.converged) return 1;
    const auto frame =
        std::make_shared<RubRotatingFrame>(structure, precession, omega);
    auto residual = [&](const IntegratorOptions& integrator, const std::string& name) {
      InvariantCircleProblem problem(frame, torus.harmonics, OrbitKind::kRelative, integrator,
                                     coordinates);
      problem.SetPhaseReference(torus.u);
      Vector F;
      problem.Residual(torus.u, omega, F);
      std::printf("  its residual under %-34s %.4e (scaled, max)\n", (name + ":").c_str(),
                  F.cwiseQuotient(problem.ResidualScale()).lpNorm<Eigen::Infinity>());
    };
    {
      const InvariantCircleProblem problem(frame, torus.harmonics, OrbitKind::kRelative, {},
                                           coordinates);
      std::printf("  its harmonics' sizes (scaled), k = 1 … %d:", torus.harmonics);
      for (int k = 1; k <= torus.harmonics; ++k)
        std::printf(" %.2e", problem.HarmonicSize(torus.u, k));
      std::printf("\n");
    }
    IntegratorOptions bdf = start.integrator;
    residual(bdf, "BDF <= 2 at 1e-7 (the start's map)");
    bdf.relative_tolerance = bdf.absolute_tolerance = 1e-9;
    residual(bdf, "BDF <= 2 at 1e-9");
    bdf.max_order = 0;
    bdf.relative_tolerance = bdf.absolute_tolerance = 1e-11;
    bdf.max_steps = 20000000;
    residual(bdf, "BDF <= 5 at 1e-11");
    for (const long intervals : {200L, 400L, 800L, 1600L}) {
      IntegratorOptions gauss = start.integrator;
      gauss.method = IntegrationMethod::kGaussCollocation;
      gauss.collocation_stages = 4;
      gauss.collocation_steps = intervals;
      residual(JoinedIntegrator(gauss, torus.laps),
               "Gauss, " + std::to_string(intervals) + " intervals per period");
    }
    return 0;
  }
  RubTorusOptions options;
  options.tori.lambda_min = RpmToRadPerSecond(rpm - 0.5);
  options.tori.lambda_max = RpmToRadPerSecond(rpm + 0.5);
  options.tori.max_fourier_tail = 0.2;
  if (collocation_steps > 0) {
    options.tori.integrator.method = IntegrationMethod::kGaussCollocation;
    options.tori.integrator.collocation_steps = collocation_steps;
    options.tori.continuation.corrector.residual_tolerance = 1e-8;
  } else {
    options.tori.integrator = start.integrator;
    options.tori.continuation.corrector.residual_tolerance = 1e-5;
    options.tori.continuation.corrector.step_tolerance = 1e-4;
  }
  options.tori.continuation.corrector.max_iterations = 15;
  options.tori.continuation.bounds.max_steps = steps;
  options.tori.continuation.step.initial = 0.005;
  const double tori_start = ProcessCpuSeconds();
  double step_start = tori_start;
  const auto frame =
      std::make_shared<RubRotatingFrame>(structure, precession, omega);
  // The families' K: the start's, refined up to MAX_HARMONICS.
  std::unique_ptr<InvariantCircleProblem> family_circle;
  const RubTransientTori tori = ContinueTransientTori(
      structure, omega, precession, transient.state, start, options,
      [&](std::size_t family, const Branch& branch) {
        const BranchPoint& p = branch.points.back();
        const Index points = (p.u.size() - 3) / frame->Dimension();  // 2K + 1 (then ρ, T, φ)
        if (!family_circle || family_circle->Dimension() != p.u.size()) {
          family_circle = std::make_unique<InvariantCircleProblem>(
              frame, static_cast<int>(points - 1) / 2, OrbitKind::kRelative, IntegratorOptions{},
              coordinates);
        }
        InvariantCircleProblem& circle = *family_circle;
        const double rho = circle.RotationNumber(p.u);
        const double period = circle.Period(p.u, p.lambda);
        // The harmonics of the resonances met: 5:13, 3:8 and 2:5.
        std::printf("  %s %.5f rpm: ρ = %.6f, f1 = %.4f Hz, f2 = %.4f Hz, tail %.3g, |c5| %.2e, "
                    "|c8| %.2e, |c13| %.2e (%.1f s CPU)\n",
                    family == 0 ? "down" : "up  ", RadPerSecondToRpm(p.lambda), rho, 1.0 / period,
                    rho / period, p.measures(1), circle.HarmonicSize(p.u, 5),
                    circle.HarmonicSize(p.u, 8),
                    circle.HarmonicSize(p.u, std::min(13, circle.harmonics())),
                    CpuSecondsSince(step_start));
        std::fflush(stdout);
        step_start = ProcessCpuSeconds();
        return true;
      });
  std::printf("start (%.1f s wall: the search and Newton): %s\n", tori.start.seconds,
              tori.start.message.c_str());
  for (std::size_t k = 0; k < tori.tori.size(); ++k) {
    const TorusBranch& family = tori.tori[k];
    std::printf("%s: %zu tori, %s; %s\n", k == 0 ? "down" : "up", family.branch.points.size(),
                ToString(family.end), family.ok ? family.end_note.c_str() : family.message.c_str());
  }
  std::printf("CPU: transient %.1f s, start and families %.1f s\n", tori_start - settle_start,
              CpuSecondsSince(tori_start));
  return tori.start.converged ? 0 : 1;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("transient_tori_bench", [&] { return rubcont::Main(argc, argv); });
}
