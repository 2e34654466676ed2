// Experiment (not part of the test suite): the modulated orbits born at a Hopf point of a
// rotating-wave branch of thesis case A(a) with tanh friction, shot as relative periodic orbits
// in the co-rotating frame (design.md §2) and continued in running speed.
// Usage: modulated_whip_bench [AMPLITUDE [SEGMENTS [TOLERANCE [STEPS]]]]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "continuation/continuation.h"
#include "models/rub_model.h"
#include "shooting/hopf_orbits.h"
#include "shooting/rotating_wave_branches.h"

namespace rubcont {
namespace {

int Main(int argc, char** argv) {
  const double amplitude = argc > 1 ? std::atof(argv[1]) : 1e-3;
  const int segments = argc > 2 ? std::atoi(argv[2]) : 4;
  const double tolerance = argc > 3 ? std::atof(argv[3]) : 1e-7;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 10;
  constexpr double kRpm = 2.0 * M_PI / 60.0;
  TwoPointParams params;  // case A(a)
  params.friction_law.kind = FrictionLawKind::kTanh;
  const RubStructure structure = TwoPointStructure(params);
  RotatingWaveBranchOptions options;
  options.search.speed_min = 20 * kRpm;
  options.search.speed_max = 260 * kRpm;
  options.search.precession_max = 2 * M_PI * 200;
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options, {});
  const Index nc = structure.Coordinates();
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf) continue;
      const double precession = p.u(2 * nc);
      std::printf("%s (%s): Hopf at %.4f rpm, precession %.4f Hz, modulation %.3f rad/s\n",
                  b.name.c_str(), b.family.c_str(), p.lambda / kRpm, precession / (2 * M_PI),
                  p.frequency);
    }
  }
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.type != SpecialPointType::kHopf) continue;
      const double precession = p.u(2 * nc);
      RubRotatingFrame frame(structure, precession, p.lambda);
      SpecialPoint hopf = p;
      hopf.u = Vector::Zero(4 * nc);
      hopf.u.head(2 * nc) = p.u.head(2 * nc);
      Vector f(4 * nc);
      frame.Rhs(0.0, hopf.u, f);
      std::printf("\n%s: Hopf at %.4f rpm; |f| at the rotating wave (scaled) = %.2e\n",
                  b.name.c_str(), p.lambda / kRpm,
                  f.cwiseQuotient(frame.StateScale()).lpNorm<Eigen::Infinity>());
      HopfOrbitOptions hopf_options;
      hopf_options.kind = OrbitKind::kRelative;
      hopf_options.amplitude = amplitude;
      hopf_options.orbits.lambda_min = 20 * kRpm;
      hopf_options.orbits.lambda_max = 260 * kRpm;
      hopf_options.orbits.shooting.segments = segments;
      hopf_options.orbits.shooting.integrator.relative_tolerance = tolerance;
      hopf_options.orbits.shooting.integrator.absolute_tolerance = tolerance;
      hopf_options.orbits.shooting.integrator.max_steps = 2000000;
      hopf_options.orbits.shooting.sensitivities_in_residual = true;
      hopf_options.orbits.continuation.bounds.max_steps = steps;
      hopf_options.orbits.continuation.step.target_iterations = 5;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        const PeriodicOrbitBranch orbits = ContinueOrbitsFromHopf(frame, hopf, hopf_options);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("%s — %s (%.1f s, %ld integrator steps)\n",
                    orbits.branch.BriefReport().c_str(), orbits.branch.message.c_str(), s,
                    orbits.work.steps);
        const Vector period = orbits.branch.Measure("period");
        const Vector rotation = orbits.branch.Measure("rotation");
        for (Index i = 0; i < orbits.branch.Size(); ++i) {
          const BranchPoint& q = orbits.branch.points[static_cast<std::size_t>(i)];
          std::printf("  %9.4f rpm  T = %.6e s  phi = %+.6f  unstable %d  max|mu| %.4f\n",
                      q.lambda / kRpm, period(i), rotation(i), q.num_unstable,
                      q.spectrum.values.size() ? q.spectrum.values.cwiseAbs().maxCoeff() : NAN);
        }
      } catch (const std::exception& e) {
        std::printf("failed: %s\n", e.what());
      }
      return 0;  // the first Hopf point only
    }
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) { return rubcont::Main(argc, argv); }
