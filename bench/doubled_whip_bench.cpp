// The period-doubled whip of case A(a) (issue 53, part 2): its family from the main whip's period
// doubling at 128.35 rpm with the orbits stage's settings (4 segments per lap, Gauss collocation
// s = 4, target angle 0.3, 5 target iterations, the curved predictor, ending at a grazing), its CPU
// (all families, and the doubled one alone) and special points;
// then, at each --check speed, the stable-flagged doubled orbit measured independently of the
// collocation:
//   1. the Floquet multipliers of the same orbit (the collocation's segment starts) from CVODES BDF
//      with sensitivities under error control (--bdf-tolerance), before and after --newton
//      corrections of the orbit with that integrator;
//   2. the frozen Jacobian ∂f/∂x along the orbit: the largest Re λ at the first sample (what
//      UnresolvedMultiplier reads), its least, mean and largest over the samples;
//   3. time marching from the orbit (BDF and Dormand–Prince at --march-tolerance) for --periods
//      doubled periods, unperturbed and perturbed by --perturbation (scaled) along the real part
//      of the frozen Jacobian's most unstable eigenvector at the first sample: the distance of
//      each return from the orbit's first point across the orbit (phase and rotation drift
//      projected out).
//
// Usage: doubled_whip_bench [--to RPM] [--intervals N] [--check RPM]... [--bdf-tolerance T]
//                           [--newton K] [--periods K] [--march-tolerance T] [--perturbation E]
// Default: to 130.5 rpm, 1600 intervals, checks at 125 and 130 rpm, BDF 1e-10, 2 corrections,
// 200 periods, marching at 1e-10, perturbation 1e-6.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "bench/bench_main.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

#include "a_a_whip_starts.h"

namespace rubcont {
namespace {

struct Settings {
  double to_rpm = 130.5;
  int intervals = 1600;
  std::vector<double> checks;
  double bdf_tolerance = 1e-10;
  int newton = 2;
  int periods = 200;
  double march_tolerance = 1e-10;
  double perturbation = 1e-6;
};

void PrintMultipliers(const char* what, const FloquetResult& floquet, double cpu) {
  std::printf("    %s (%.1f s CPU):", what, cpu);
  for (Index k = 0; k < std::min<Index>(4, floquet.multipliers.size()); ++k) {
    const std::complex<double> m = floquet.multipliers(k);
    std::printf("  %.6f%+.6fi (|%.6f|)", m.real(), m.imag(), std::abs(m));
  }
  std::printf("\n      trivial:");
  for (Index k = 0; k < floquet.trivial.size(); ++k) std::printf(" %.6f", std::abs(floquet.trivial(k)));
  std::printf(", invariance defect %.1e, unresolved %d\n", floquet.invariance_defect,
              floquet.Unresolved());
}

// The eigenvalue of ∂f/∂x at x with the largest real part, and its eigenvector's real part.
std::complex<double> LargestGrowth(OdeSystem& system, ConstVectorRef x, Vector* direction) {
  const Index n = system.Dimension();
  Matrix J(n, n);
  system.JacobianX(0.0, x, J);
  Eigen::EigenSolver<Matrix> eig(J);
  Index best = 0;
  for (Index k = 1; k < n; ++k) {
    if (eig.eigenvalues()(k).real() > eig.eigenvalues()(best).real()) best = k;
  }
  if (direction) *direction = eig.eigenvectors().col(best).real();
  return eig.eigenvalues()(best);
}

// The relative orbit through x0 (period T, rotation φ) marched from `start` for `periods` periods:
// after each, the distance of R_{−kφ} x(kT) from x0 across the orbit (scaled, ∞-norm, relative to
// ‖S⁻¹x0‖∞): the component along f(x0) and g(x0) (a phase or rotation drift, neutral) removed.
void March(RubRotatingFrame& frame, IntegrationMethod method, double tolerance, const Vector& x0,
           double period, double rotation, const Vector& start, int periods, const char* what) {
  IntegratorOptions options;
  options.method = method;
  options.relative_tolerance = options.absolute_tolerance = tolerance;
  options.max_steps = 50000000;
  OdeIntegrator integrator(frame, options);
  const Index n = frame.Dimension();
  const Vector scale = frame.StateScale();
  Matrix neutral(n, 2);
  Vector column(n);
  frame.Rhs(0.0, x0, column);
  neutral.col(0) = column.cwiseQuotient(scale);
  frame.RotationGenerator(x0, column);
  neutral.col(1) = column.cwiseQuotient(scale);
  const Matrix q = Eigen::HouseholderQR<Matrix>(neutral).householderQ() * Matrix::Identity(n, 2);
  const double size = x0.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
  const auto across = [&](const Vector& x, int laps) {
    Vector y = x;
    frame.Rotate(-laps * rotation, y);
    Vector d = (y - x0).cwiseQuotient(scale);
    d -= q * (q.transpose() * d);
    return d.lpNorm<Eigen::Infinity>() / size;
  };
  const double cpu0 = ProcessCpuSeconds();
  Vector x = start;
  double worst = 0.0;
  long steps = 0;
  std::printf("    march %s at %g, %d periods: start %.2e;", what, tolerance, periods, across(x, 0));
  for (int lap = 0; lap < periods; ++lap) {
    const IntegrationResult r = integrator.Integrate(lap * period, x, (lap + 1) * period, x);
    steps += r.statistics.steps;
    if (!r.Succeeded()) {
      std::printf(" failed in period %d: %s\n", lap + 1, r.BriefReport().c_str());
      return;
    }
    const double off = across(x, lap + 1);
    worst = std::max(worst, off);
    if ((lap + 1) % (periods / 5 > 0 ? periods / 5 : 1) == 0 || lap == 0) {
      std::printf(" [%d] %.2e", lap + 1, off);
    }
  }
  std::printf("\n      largest %.2e; %ld steps, %.1f s CPU\n", worst, steps, CpuSecondsSince(cpu0));
}

void Check(const RubStructure& structure, double frame_rate, const PeriodicOrbitBranch& doubled,
           double rpm, const Settings& s) {
  const Branch& branch = doubled.branch;
  const BranchPoint* best = nullptr;
  for (const BranchPoint& p : branch.points) {
    if (p.num_unstable != 0) continue;
    if (!best || std::abs(p.lambda - RpmToRadPerSecond(rpm)) < std::abs(best->lambda - RpmToRadPerSecond(rpm))) {
      best = &p;
    }
  }
  if (!best) {
    std::printf("  %.2f rpm: no stable-flagged doubled orbit\n", rpm);
    return;
  }
  const double lambda = best->lambda;
  std::printf("  doubled orbit at %.4f rpm (the stable-flagged one nearest %.2f rpm), unresolved_multiplier %.3e\n",
              RadPerSecondToRpm(lambda), rpm, best->measures(branch.MeasureIndex("unresolved_multiplier")));
  std::printf("    collocation multipliers:");
  for (Index k = 0; k < std::min<Index>(4, best->spectrum.values.size()); ++k) {
    std::printf("  %.6f%+.6fi (|%.6f|)", best->spectrum.values(k).real(), best->spectrum.values(k).imag(),
                std::abs(best->spectrum.values(k)));
  }
  std::printf("\n");

  RubRotatingFrame frame(structure, frame_rate, lambda);
  ShootingOptions options = doubled.shooting;
  options.integrator = IntegratorOptions{};
  options.integrator.method = IntegrationMethod::kBdf;
  options.integrator.relative_tolerance = options.integrator.absolute_tolerance = s.bdf_tolerance;
  options.integrator.max_steps = 50000000;
  options.sensitivities_in_residual = false;
  ShootingProblem bdf(frame, OrbitKind::kRelative, options);
  Vector u = best->u;
  bdf.SetPhaseReference(u, lambda);
  Vector F;
  double cpu0 = ProcessCpuSeconds();
  bdf.Residual(u, lambda, F);
  const Vector residual_scale = bdf.ResidualScale();
  std::printf("    BDF residual of the collocation orbit (scaled, ∞): %.2e\n",
              F.cwiseQuotient(residual_scale).lpNorm<Eigen::Infinity>());
  FloquetResult floquet = bdf.Floquet(u, lambda);
  PrintMultipliers("BDF multipliers of the collocation orbit", floquet, CpuSecondsSince(cpu0));
  for (int k = 0; k < s.newton; ++k) {
    cpu0 = ProcessCpuSeconds();
    Matrix J;
    bdf.Jacobian(u, lambda, J);
    bdf.Residual(u, lambda, F);
    const Vector du = J.partialPivLu().solve(-F);
    u += du;
    bdf.Residual(u, lambda, F);
    std::printf("    BDF Newton %d: correction %.2e (scaled ∞), residual %.2e (%.1f s CPU)\n", k + 1,
                du.cwiseQuotient(bdf.Scale()).lpNorm<Eigen::Infinity>(),
                F.cwiseQuotient(residual_scale).lpNorm<Eigen::Infinity>(), CpuSecondsSince(cpu0));
  }
  if (s.newton > 0) {
    cpu0 = ProcessCpuSeconds();
    floquet = bdf.Floquet(u, lambda);
    PrintMultipliers("BDF multipliers of the BDF orbit", floquet, CpuSecondsSince(cpu0));
  }

  // The frozen Jacobian along the orbit.
  const OrbitSamples& orbit = bdf.Orbit(u, lambda);
  frame.SetParameter(lambda);
  Vector direction;
  const std::complex<double> first = LargestGrowth(frame, orbit.states.col(0), &direction);
  double least = kInfinity, largest = -kInfinity, sum = 0.0;
  int positive = 0;
  for (Index j = 0; j < orbit.states.cols(); ++j) {
    const double g = LargestGrowth(frame, orbit.states.col(j), nullptr).real();
    least = std::min(least, g);
    largest = std::max(largest, g);
    sum += g;
    positive += g > 0.0 ? 1 : 0;
  }
  const double period = orbit.period;
  std::printf("    frozen ∂f/∂x, the eigenvalue of largest Re [1/s]: first sample %.1f%+.1fi "
              "(e^{Re λ T} = %.3e); Re over %ld samples least %.1f, mean %.1f, largest %.1f, positive at %d\n",
              first.real(), first.imag(), std::exp(first.real() * period),
              static_cast<long>(orbit.states.cols()), least,
              sum / static_cast<double>(orbit.states.cols()), largest, positive);

  // Time marching from the orbit's first sample, and from it kicked along that eigenvector.
  const Vector x0 = orbit.states.col(0);
  const Vector scale = frame.StateScale();
  Vector kick = direction.cwiseQuotient(scale);
  kick = s.perturbation * kick / kick.lpNorm<Eigen::Infinity>();
  const Vector x0_kicked = x0 + kick.cwiseProduct(scale);
  std::printf("    T = %.6e s, φ = %.6f rad\n", period, orbit.rotation);
  March(frame, IntegrationMethod::kBdf, s.march_tolerance, x0, period, orbit.rotation, x0, s.periods,
        "BDF");
  March(frame, IntegrationMethod::kBdf, s.march_tolerance, x0, period, orbit.rotation, x0_kicked,
        s.periods, "BDF, kicked");
  March(frame, IntegrationMethod::kDormandPrince, s.march_tolerance, x0, period, orbit.rotation,
        x0_kicked, s.periods, "Dormand-Prince, kicked");
}

int Main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  Settings s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--to") s.to_rpm = next();
    else if (a == "--intervals") s.intervals = static_cast<int>(next());
    else if (a == "--check") s.checks.push_back(next());
    else if (a == "--bdf-tolerance") s.bdf_tolerance = next();
    else if (a == "--newton") s.newton = static_cast<int>(next());
    else if (a == "--periods") s.periods = static_cast<int>(next());
    else if (a == "--march-tolerance") s.march_tolerance = next();
    else if (a == "--perturbation") s.perturbation = next();
    else {
      std::fprintf(stderr, "doubled_whip_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (s.checks.empty()) s.checks = {125.0, 130.0};
  const AaWhipStarts a = ComputeAaWhipStarts();
  const RubStructure& structure = a.structure;
  const auto& branches = a.branches;
  const auto& starts = a.starts;
  if (starts.empty()) return 1;

  HopfOrbitOptions options;
  options.amplitude = 1e-3;
  options.orbits.lambda_min = RpmToRadPerSecond(20);
  options.orbits.lambda_max = RpmToRadPerSecond(s.to_rpm);
  ShootingOptions& shooting = options.orbits.shooting;
  shooting.segments = 4;
  shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  shooting.integrator.relative_tolerance = shooting.integrator.absolute_tolerance = 1e-7;
  shooting.integrator.max_steps = 2000000;
  shooting.integrator.collocation_steps = CollocationStepsPerSegment(s.intervals, 4);
  shooting.sensitivities_in_residual = true;
  ContinuationOptions& c = options.orbits.continuation;
  c.step.max = 1.0;
  c.step.target_angle = 0.3;
  c.step.target_iterations = 5;
  c.step.curved_predictor = true;
  c.bounds.max_steps = 400;
  options.orbits.stop_at_grazing = true;
  // The families come one after the other (the main one, the side branches, the doubled one
  // last): a step with fewer points than the one before starts the next, and the doubled family's
  // cost runs from the last step of the family before it to the end.
  std::size_t last_points = 0;
  double cpu_last_step = 0.0, cpu_doubled_start = 0.0;
  options.on_step = [&](const Branch& b) {
    if (b.points.size() < last_points) cpu_doubled_start = cpu_last_step;
    last_points = b.points.size();
    cpu_last_step = ProcessCpuSeconds();
    return true;
  };
  const double cpu0 = ProcessCpuSeconds();
  const RubModulatedOrbits result = ContinueModulatedOrbits(structure, branches, starts.front(), options, true);
  const double cpu = CpuSecondsSince(cpu0);
  std::printf("doubled_whip_bench: Hopf %.6f rpm → %g rpm, %d intervals per lap: %.1f s CPU in all, "
              "the doubled family %.1f s\n",
              RadPerSecondToRpm(starts.front().speed), s.to_rpm, s.intervals, cpu,
              CpuSecondsSince(cpu_doubled_start));
  std::printf("  main family: %s\n", result.orbits.branch.BriefReport().c_str());
  if (result.doublings.empty() || !result.doublings.front().ok) {
    std::printf("  no doubled family\n");
    return 1;
  }
  const PeriodicOrbitBranch& doubled = result.doublings.front().branch;
  std::printf("  doubled family: %s\n", doubled.branch.BriefReport().c_str());
  for (const SpecialPoint& p : doubled.branch.special_points) {
    std::printf("    %-22s %.4f rpm%s\n", ToString(p.type), RadPerSecondToRpm(p.lambda),
                p.converged ? "" : " (not located)");
  }
  for (double rpm : s.checks) Check(structure, starts.front().precession, doubled, rpm, s);
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("doubled_whip_bench", [&] { return rubcont::Main(argc, argv); });
}
