// Design and identification (issue 8) on case A(a): Ipopt against the engine's located folds,
// hysteresis-map timings, and the identification of hidden parameters from synthetic targets.
// Prints measured numbers; not part of the test suite.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "continuation/fold_optimization.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "solvers/stopwatch.h"
#include "studies/hysteresis_map.h"
#include "studies/identification.h"

namespace {

using namespace rubcont;

RotatingWaveBranchOptions Range(double rpm_min, double rpm_max) {
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(rpm_min);
  options.search.speed_max = RpmToRadPerSecond(rpm_max);
  options.search.precession_max = HzToRadPerSecond(200.0);
  return options;
}


void FoldsByIpopt() {
  std::printf("== Ipopt vs the engine's located folds (tanh friction, ε = 1e-3 m/s, case A(a)) ==\n");
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  const RubStructure structure = TwoPointStructure(params);
  RotatingWaveBranchOptions options = Range(20, 260);
  options.continuation.detect.test_functions = false;
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options);
  RotatingWaveProblem problem(structure, FrictionLawKind::kTanh);
  for (const RotatingWaveBranch& b : branches) {
    for (const SpecialPoint& fold : b.branch.special_points) {
      if (fold.type != SpecialPointType::kFold || !fold.converged) continue;
      const BranchPoint& before = b.branch.points[fold.index];
      problem.SetPhaseReference(before.u);
      FoldOptimizationOptions nlp;
      nlp.sense = before.lambda < fold.lambda ? +1 : -1;
      const SteadyClock::time_point start = SteadyClock::now();
      const FoldOptimizationResult r = LocateFoldByOptimization(problem, before.u, before.lambda, nlp);
      std::printf("  %s (%s): engine %.12f rpm, Ipopt %.12f rpm (%s, %d it, %.1f ms), rel. diff %.2e\n",
                  b.name.c_str(), PatternName(b.normals).c_str(), RadPerSecondToRpm(fold.lambda),
                  RadPerSecondToRpm(r.lambda), ToString(r.status), r.iterations,
                  1e3 * SecondsSince(start), std::abs(r.lambda - fold.lambda) / fold.lambda);
    }
  }
}

void Maps() {
  std::printf("== hysteresis maps of case A(a), exact law, 20-260 rpm, 31 values x 481 speeds ==\n");
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kExact;
  for (DesignParameter p : {DesignParameter::kFriction, DesignParameter::kStatorDamping,
                            DesignParameter::kRciRatio}) {
    HysteresisMapOptions options;
    options.parameter = p;
    const double base = GetDesignParameter(params, p);
    options.eta_min = p == DesignParameter::kRciRatio ? 0.75 * base : 0.5 * base;
    options.eta_max = p == DesignParameter::kRciRatio ? 1.35 * base : 1.5 * base;
    options.branches = Range(20, 260);
    const HysteresisMap map = ComputeHysteresisMap(params, options);
    std::printf("  %s\n", map.BriefReport().c_str());
  }
}

void Identification() {
  std::printf("== identification from synthetic targets (hidden parameters) ==\n");
  TwoPointParams truth = ThesisCaseAa();
  truth.friction_law.kind = FrictionLawKind::kExact;
  truth.friction = 0.42;
  truth.support_damping = {410.0, 410.0};
  truth.center_damping = 52.0;
  const RotatingWaveBranchOptions range = Range(20, 120);
  std::vector<IdentificationTarget> targets = {
      {"mode1", "stick to slip+", TargetQuantity::kSpeedRpm, 0.0, 0.01},
      {"mode1", "stick to slip+", TargetQuantity::kPrecessionHz, 0.0, 0.01},
      {"mode1", "slip to stick", TargetQuantity::kSpeedRpm, 0.0, 0.01},
      {"mode2", "stick to slip+", TargetQuantity::kSpeedRpm, 0.0, 0.01},
  };
  // Made by the model itself at the hidden parameters: seed each target near the nominal value,
  // then predict.
  const double nominal[] = {50.7, 84.5, 65.9, 79.9};
  for (std::size_t i = 0; i < targets.size(); ++i) targets[i].value = nominal[i];
  const std::vector<double> made = PredictTargets(truth, targets, range);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    targets[i].value = made[i];
    std::printf("  target %-36s %.6f\n", targets[i].Name().c_str(), made[i]);
  }
  TwoPointParams start = ThesisCaseAa();  // the fit sees the nominal thesis values only
  start.friction_law.kind = FrictionLawKind::kExact;
  for (const auto& fit : std::vector<std::vector<FitParameter>>{
           {{DesignParameter::kFriction, 0.2, 0.8}, {DesignParameter::kStatorDamping, 100.0, 800.0}},
           {{DesignParameter::kFriction, 0.2, 0.8}, {DesignParameter::kCenterDamping, 0.0, 200.0}}}) {
    IdentificationOptions options;
    options.branches = range;
    const IdentificationResult r = Identify(start, targets, fit, options);
    std::printf("  fit %s + %s: %s: %s\n", ToString(fit[0].parameter), ToString(fit[1].parameter),
                ToString(r.status), r.message.c_str());
    for (std::size_t k = 0; k < fit.size(); ++k) {
      std::printf("    %-16s = %.8g (global %.6g), σ = %.3g, J rise for ±1 %%: %.3g\n",
                  ToString(fit[k].parameter), r.parameters[k], r.global_parameters[k],
                  r.standard_deviation[k], r.objective_rise[k]);
    }
    if (r.correlation.size() == 2) std::printf("    correlation %.4f\n", r.correlation[0][1]);
    for (std::size_t i = 0; i < targets.size(); ++i) {
      std::printf("    %-36s predicted %.6f, residual %.3g\n", targets[i].Name().c_str(),
                  r.predicted[i], r.residuals[i]);
    }
  }
}

}  // namespace

static int Run(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "all";
  if (what == "all" || what == "folds") FoldsByIpopt();
  if (what == "all" || what == "maps") Maps();
  if (what == "all" || what == "fit") Identification();
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("design_bench", [&] { return Run(argc, argv); });
}
