// Experiment (not part of the test suite): case A(a)'s period-1 modulated whip past its grazing,
// three ways. On Gauss collocation's fixed mesh (the orbits stage's default, 400 intervals per
// period) the family grazes at 132.539 rpm (both contacts lift off once per modulation) and then
// creeps in halving steps to 132.864 rpm, where the corrector fails (docs/studies/attractors.md,
// "What the whip is, speed by speed"): a fold of the impacting orbits, or the mesh's limit (a fixed
// mesh is of lower order past a kink)? (1) CVODES BDF with the segments stopped and restarted where
// a contact opens or closes (ShootingOptions::restart_at_switches); (2) Gauss on its fixed mesh;
// (3) Gauss across the switching patterns (ContinueAcrossSwitches): to the first orbit past
// grazing on the fixed mesh, then with the contacts' switches as segment boundaries
// (ShootingOptions::event_boundaries), every segment smooth, restarted where the pattern
// changes. The
// orbit is solved on a settled transient at START_RPM (from rest and an impulse the rotor whips at
// 60 rpm; at 110 rpm it whirls: measured), continued with Gauss to SWITCH_RPM, and from that orbit
// the chosen ways continue to TO_RPM with the grazing test functions; each step printed with its
// cost.
// Usage: past_grazing_bench [START_RPM [SWITCH_RPM [TO_RPM [BDF_TOLERANCE [METHODS
// [EVENT_STEPS [PIECES]]]]]]], defaults 60 125 133.5 1e-7 bdf,gauss,events 100 8 (BDF's corrector
// diverged from the Gauss orbit at 132.45 rpm, 7 N from grazing; from 125 rpm it starts;
// EVENT_STEPS: Gauss steps per segment in the third way, PIECES its patterns at most:
// results/bench/past_grazing.txt).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/units.h"
#include "shooting/modulated_orbit.h"
#include "shooting/orbit_branches.h"
#include "shooting/rub_orbits.h"
#include "shooting/switching_orbits.h"
#include "solvers/stopwatch.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

// The orbits stage's shooting (apps/stage_options.h, RubShootingOptionsOf): 4 segments,
// Gauss–Legendre of order 8 on 400 intervals per period (100 each), or CVODES BDF with the
// sensitivities under error control at `tolerance`.
ShootingOptions Shooting(IntegrationMethod method, double tolerance) {
  Scene scene;  // [analysis.orbits]' defaults
  scene.analysis.orbits.integrator =
      method == IntegrationMethod::kBdf ? OrbitIntegrator::kBdf : OrbitIntegrator::kGauss;
  scene.analysis.orbits.tolerance = tolerance;
  return RubShootingOptionsOf(scene);
}

double Largest(const BranchPoint& p) {
  return p.spectrum.values.size() > 0 ? p.spectrum.values.cwiseAbs().maxCoeff() : kNaN;
}

void PrintFamily(const char* name, const PeriodicOrbitBranch& family) {
  const Branch& b = family.branch;
  std::printf("%s: %s\n", name, b.BriefReport().c_str());
  for (const SpecialPoint& p : b.special_points) {
    std::printf("  %-16s %-16s %.5f rpm  %s\n", ToString(p.type), p.label.c_str(),
                RadPerSecondToRpm(p.lambda), p.converged ? "located" : "not located");
  }
}

// Gauss across the switching patterns (ContinueAcrossSwitches): on the fixed mesh to the first
// orbit past grazing, then with the contacts' switches as segment boundaries (every segment
// smooth), restarted wherever a phase between two switches vanishes.
void AcrossSwitches(RubRotatingFrame& frame, const OrbitStart& from,
                    const PeriodicOrbitBranchOptions& options, double to_rpm, long steps,
                    int max_pieces) {
  SwitchingOrbitOptions across;
  across.family = options;
  across.family.lambda_min = from.lambda;
  across.family.lambda_max = RpmToRadPerSecond(to_rpm);
  across.family.shooting.integrator.collocation_steps = steps;
  across.family.continuation = OrbitContinuationOptions(120);
  across.max_pieces = max_pieces;
  double step_start = ProcessCpuSeconds();
  across.family.on_step = [&](const Branch& b) {
    const BranchPoint& p = b.points.back();
    std::printf("    %3zu: %.5f rpm, largest |mu| %9.4g, %d Newton iterations (%.1f s CPU)\n",
                b.points.size(), RadPerSecondToRpm(p.lambda), Largest(p), p.newton_iterations,
                CpuSecondsSince(step_start));
    step_start = ProcessCpuSeconds();
    return true;
  };
  const double start = ProcessCpuSeconds();
  std::printf("Gauss across the switching patterns (%ld steps per segment) from %.5f to %.2f "
              "rpm:\n", steps, RadPerSecondToRpm(from.lambda), to_rpm);
  const SwitchingOrbitFamily family =
      ContinueAcrossSwitches(frame, OrbitKind::kRelative, from, across);
  std::printf("  (%.1f s CPU, %ld integrator steps) %s\n", CpuSecondsSince(start),
              static_cast<long>(family.work.steps), family.message.c_str());
  for (std::size_t k = 0; k < family.pieces.size(); ++k) {
    const SwitchingOrbitPiece& piece = family.pieces[k];
    const std::vector<double> mesh = piece.family.shooting.mesh;
    std::printf("  piece %zu, %d switches as boundaries (mesh", k, piece.switches);
    for (const double tau : mesh) std::printf(" %.5f", tau);
    std::printf(" at its start): %s\n", piece.end.c_str());
    PrintFamily("   ", piece.family);
  }
}

int Main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress as it comes
  const double start_rpm = argc > 1 ? std::atof(argv[1]) : 60.0;
  const double switch_rpm = argc > 2 ? std::atof(argv[2]) : 125.0;
  const double to_rpm = argc > 3 ? std::atof(argv[3]) : 133.5;
  const double bdf_tolerance = argc > 4 ? std::atof(argv[4]) : 1e-7;
  const std::string methods = argc > 5 ? argv[5] : "bdf,gauss,events";
  const long event_steps = argc > 6 ? std::atol(argv[6]) : 100;
  const int max_pieces = argc > 7 ? std::atoi(argv[7]) : 8;
  const RubStructure structure = TwoPointStructure(ThesisCaseAa());
  const double omega = RpmToRadPerSecond(start_rpm);

  double start = ProcessCpuSeconds();
  const RubSettledSpeed transient = SettleAtSpeed(structure, LongSettleOptions(omega, 3.0), 1.0);
  ModulatedOrbitOptions solve;
  solve.shooting = Shooting(IntegrationMethod::kGaussCollocation, 1e-7);
  solve.search_duration = 1.0;
  solve.newton.residual_tolerance = 1e-10;
  solve.newton.step_tolerance = 1e-8;
  solve.newton.max_iterations = 20;
  const ModulatedOrbit orbit = SolveModulatedOrbit(
      structure, omega, HzToRadPerSecond(transient.precession_hz), transient.state, solve);
  std::printf(
      "A(a) at %.2f rpm: the transient %s, precession %.4f Hz; its orbit (%.1f s CPU): %s\n",
      start_rpm, transient.settled ? "settled" : "did not settle", transient.precession_hz,
      CpuSecondsSince(start), orbit.message.c_str());
  if (!orbit.converged) return 1;

  RubRotatingFrame frame(structure, orbit.frame_rate, omega);
  PeriodicOrbitBranchOptions options;
  options.lambda_min = omega;
  options.lambda_max = RpmToRadPerSecond(switch_rpm);
  options.shooting = solve.shooting;
  options.measures = RubOrbitMeasures(frame);
  options.test_functions = RubGrazingTests(structure);
  options.continuation = OrbitContinuationOptions(400);
  start = ProcessCpuSeconds();
  const PeriodicOrbitBranch approach =
      ContinuePeriodicOrbits(frame, OrbitKind::kRelative, StartOf(orbit, omega), options);
  std::printf("Gauss from %.2f to %.2f rpm (%.1f s CPU)\n", start_rpm, switch_rpm,
              CpuSecondsSince(start));
  PrintFamily("  approach", approach);
  if (approach.branch.points.empty()) return 1;

  // The last orbit as the start of both continuations.
  const BranchPoint& last = approach.branch.points.back();
  const OrbitStart from = OrbitStartAt(frame, OrbitKind::kRelative, approach.shooting, last);
  const Index forces[2] = {approach.branch.MeasureIndex("min_normal_force_left"),
                           approach.branch.MeasureIndex("min_normal_force_right")};

  for (const IntegrationMethod method :
       {IntegrationMethod::kBdf, IntegrationMethod::kGaussCollocation}) {
    const bool bdf = method == IntegrationMethod::kBdf;
    if (methods.find(bdf ? "bdf" : "gauss") == std::string::npos) continue;
    PeriodicOrbitBranchOptions past = options;
    past.lambda_min = last.lambda;
    past.lambda_max = RpmToRadPerSecond(to_rpm);
    past.shooting = Shooting(method, bdf ? bdf_tolerance : 1e-7);
    past.continuation = OrbitContinuationOptions(120);
    double step_start = ProcessCpuSeconds();
    past.on_step = [&](const Branch& b) {
      const BranchPoint& p = b.points.back();
      std::printf("    %3zu: %.5f rpm, min N left %9.3f right %9.3f N, largest |mu| %9.4g, %d "
                  "Newton iterations (%.1f s CPU)\n", b.points.size(), RadPerSecondToRpm(p.lambda),
                  p.measures(forces[0]), p.measures(forces[1]), Largest(p), p.newton_iterations,
                  CpuSecondsSince(step_start));
      step_start = ProcessCpuSeconds();
      return true;
    };
    start = ProcessCpuSeconds();
    std::printf(
        "%s from %.5f to %.2f rpm:\n",
        bdf ? "CVODES BDF, restarted at contact switches," : "Gauss collocation (400/period)",
        RadPerSecondToRpm(last.lambda), to_rpm);
    const PeriodicOrbitBranch family =
        ContinuePeriodicOrbits(frame, OrbitKind::kRelative, from, past);
    std::printf("  (%.1f s CPU, %ld integrator steps)\n", CpuSecondsSince(start),
                static_cast<long>(family.work.steps));
    PrintFamily(bdf ? "  BDF" : "  Gauss", family);
  }
  if (methods.find("events") != std::string::npos) {
    AcrossSwitches(frame, from, options, to_rpm, event_steps, max_pieces);
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("past_grazing_bench", [&] { return rubcont::Main(argc, argv); });
}
