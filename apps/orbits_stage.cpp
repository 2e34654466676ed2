#include "apps/orbits_stage.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/branch_output.h"
#include "apps/orbit_output.h"
#include "apps/stage_options.h"
#include "models/textbook.h"
#include "models/units.h"
#include "shooting/orbit_branches.h"
#include "shooting/rub_orbits.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

struct StageSetup {
  std::unique_ptr<OdeSystem> system;
  OrbitKind kind = OrbitKind::kForced;
  OrbitStart start;
  PeriodicOrbitBranchOptions options;
  std::string parameter_name;
  // Compares the branch with a closed form, when the model has one: writes and prints the errors.
  std::function<void(const Scene&, const Branch&, ResultWriter&, std::ostream&)> check;
};

// The scene's orbit options, integrated as [<model>.orbits] integrator says ("model":
// `model_default`), and the model's own integrator for the transient that finds the first orbit
// (Gauss collocation's fixed mesh is one period's).
PeriodicOrbitBranchOptions TextbookOptions(const Scene& scene, IntegrationMethod model_default,
                                           IntegratorOptions& transient) {
  transient = TextbookOrbitOptionsOf(scene, model_default).shooting.integrator;
  return TextbookOrbitOptionsOf(scene, TextbookOrbitMethodOf(scene, model_default));
}

StageSetup DuffingSetup(const Scene& scene) {
  StageSetup setup;
  DuffingParams p = scene.duffing;
  p.frequency = scene.orbits.start;
  Validate(p);
  setup.system = std::make_unique<DuffingOscillator>(p);
  setup.kind = OrbitKind::kForced;
  setup.parameter_name = "frequency";
  // Duffing is not stiff: an explicit 8th-order Runge–Kutta pair is the cheapest accurate
  // integrator (bench/duffing_branch_bench.cpp).
  IntegratorOptions transient;
  setup.options = TextbookOptions(scene, IntegrationMethod::kExplicitRungeKutta, transient);
  setup.options.measures = {StateMaximum(0, "max_x"), StateMinimum(0, "min_x"),
                            StateAmplitude(0, "amplitude_x"), StateMaximum(1, "max_v"),
                            StateMinimum(1, "min_v")};
  const ForcedStart start = DuffingStart(p);
  setup.start =
      SettleForced(*setup.system, start.x0, start.periods, transient);
  return setup;
}

// The branch against Stuart–Landau's closed form (StuartLandauOscillator at each λ: r = √λ,
// T = 2π/|ω − γλ|, multiplier e^{−2λT}): the errors written beside the branch and their largest
// printed.
void CompareWithStuartLandauClosedForm(const Scene& scene, const Branch& branch,
                                       ResultWriter& writer, std::ostream& out) {
  const Vector lambda = branch.Lambda(), radius = branch.Measure("mean_radius"),
               period = branch.Measure("period");
  Vector radius_error(lambda.size()), period_error(lambda.size()),
      multiplier_error(lambda.size());
  for (Index i = 0; i < lambda.size(); ++i) {
    StuartLandauParams p = scene.stuart_landau;
    p.lambda = lambda(i);
    const StuartLandauOscillator closed(p);
    radius_error(i) = radius(i) - closed.OrbitRadius();
    period_error(i) = period(i) - closed.Period();
    const ComplexVector& mu = branch.points[static_cast<std::size_t>(i)].spectrum.values;
    multiplier_error(i) = mu.size() > 0 ? std::abs(mu(0) - closed.NontrivialMultiplier()) : kNaN;
  }
  writer.WriteDoubles("/branches/periodic_orbits/closed_form_radius_error", radius_error);
  writer.WriteDoubles("/branches/periodic_orbits/closed_form_period_error", period_error);
  writer.WriteDoubles("/branches/periodic_orbits/closed_form_multiplier_error", multiplier_error);
  fmt::print(out, "  against the closed form r = √λ, T = 2π/|ω − γλ|, μ = e^(−2λT): "
                  "max |Δr| = {:.1e}, max |ΔT| = {:.1e}, max |Δμ| = {:.1e}\n",
             radius_error.cwiseAbs().maxCoeff(), period_error.cwiseAbs().maxCoeff(),
             multiplier_error.cwiseAbs().maxCoeff());
}

StageSetup StuartLandauSetup(const Scene& scene) {
  StageSetup setup;
  StuartLandauParams p = scene.stuart_landau;
  p.lambda = scene.orbits.start;
  Validate(p);
  setup.system = std::make_unique<StuartLandauOscillator>(p);
  setup.kind = OrbitKind::kAutonomous;
  setup.parameter_name = "lambda";
  IntegratorOptions transient;
  setup.options = TextbookOptions(scene, IntegrationMethod::kExplicitRungeKutta, transient);
  setup.options.measures = {MeanRadius(), StateMaximum(0, "max_x"), StateMinimum(0, "min_x")};
  const CycleStart start = StuartLandauStart(p);
  setup.start = SettleOnCycle(*setup.system, start.x0, start.duration, 1,
                              transient);
  setup.check = CompareWithStuartLandauClosedForm;
  return setup;
}

StageSetup VanDerPolSetup(const Scene& scene) {
  StageSetup setup;
  VanDerPolParams p;
  p.mu = scene.orbits.start;
  Validate(p);
  setup.system = std::make_unique<VanDerPolOscillator>(p);
  setup.kind = OrbitKind::kAutonomous;
  setup.parameter_name = "mu";
  // Stiff for large μ: BDF.
  IntegratorOptions transient;
  setup.options = TextbookOptions(scene, IntegrationMethod::kBdf, transient);
  setup.options.measures = {StateMaximum(0, "max_x"), StateMinimum(0, "min_x"),
                            StateMaximum(1, "max_v"), StateMinimum(1, "min_v")};
  const CycleStart start = VanDerPolStart(p);
  setup.start = SettleOnCycle(*setup.system, start.x0, start.duration, 1,
                              transient);
  return setup;
}

StageSetup ForcedVanDerPolSetup(const Scene& scene) {
  StageSetup setup;
  ForcedVanDerPolParams p = scene.forced_van_der_pol;
  p.frequency = scene.orbits.start;
  Validate(p);
  setup.system = std::make_unique<ForcedVanDerPolOscillator>(p);
  setup.kind = OrbitKind::kForced;
  setup.parameter_name = "frequency";
  IntegratorOptions transient;
  setup.options = TextbookOptions(scene, IntegrationMethod::kBdf, transient);
  setup.options.measures = {StateMaximum(0, "max_x"), StateMinimum(0, "min_x"),
                            StateAmplitude(0, "amplitude_x"), StateMaximum(1, "max_v")};
  const ForcedStart start = ForcedVanDerPolStart(p);
  setup.start =
      SettleForced(*setup.system, start.x0, start.periods, transient);
  return setup;
}

// Above these the summary and the result say so: an orbit that is not a solution of the ODE to
// 1e-5 (scaled) under an independent integrator (measured by Dormand–Prince at 1e-12: 4e-12 –
// 3.3e-6 on A(a)'s family at the stage's 400 intervals, ≤ 3.3e-9 at 1600; 1.9e-5 near its period
// doubling on 400 adapted ones), or modes the mesh does not resolve whose multipliers
// come within 1 % of the unit circle (RubOrbitMeasures, UnresolvedMultiplier).
constexpr double kDefectLimit = 1e-5;
constexpr double kUnresolvedMultiplierLimit = 0.99;

}  // namespace

void ReportOrbitChecks(const Branch& branch, const std::string& group, const OrbitTrust& trust,
                       ResultWriter& writer, std::ostream& out) {
  if (branch.points.empty()) return;
  const std::vector<std::string> untrusted =
      UntrustedOrbits(branch, trust.structure, trust.max_penetration);
  writer.WriteStrings(group + "/untrusted", untrusted);
  const auto& names = branch.measure_names;
  std::string line = "    check: no defect check (defect_check = \"off\")";
  std::vector<std::string> notes;
  if (std::find(names.begin(), names.end(), "defect") != names.end()) {
    // A check whose integration failed measured nothing (NaN): counted, not compared.
    const Vector all = branch.Measure("defect");
    double defect = -kInfinity;
    Index failed = 0;
    for (Index i = 0; i < all.size(); ++i) {
      if (std::isnan(all(i))) ++failed;
      else defect = std::max(defect, all(i));
    }
    line = failed == all.size()
               ? "    check: no defect measured (Dormand–Prince at 1e-12)"
               : fmt::format("    check: largest defect {:.1e} (Dormand–Prince at 1e-12)", defect);
    if (failed > 0 && failed < all.size()) line += fmt::format(" of {} orbits", all.size() - failed);
    if (defect > kDefectLimit) {
      notes.push_back(fmt::format("an orbit's defect {:.1e} exceeds {:g}: refine the mesh or the "
                                  "tolerance", defect, kDefectLimit));
    }
    if (failed > 0) {
      notes.push_back(fmt::format("the defect check could not integrate {} of {} orbits (NaN in "
                                  "their defect): refine the mesh or the tolerance",
                                  failed, all.size()));
    }
  }
  if (std::find(names.begin(), names.end(), "unresolved_multiplier") != names.end()) {
    const double largest = branch.Measure("unresolved_multiplier").maxCoeff();
    line += fmt::format(", modes the mesh does not resolve: |multiplier| ≤ {:.3f}", largest);
    if (!(largest < kUnresolvedMultiplierLimit)) {
      notes.push_back(fmt::format(
          "a mode the mesh does not resolve has a multiplier of modulus {:.3f}: it may decide the "
          "stability; raise collocation_intervals", largest));
    }
  }
  std::size_t first = untrusted.size(), count = 0;
  for (std::size_t i = 0; i < untrusted.size(); ++i) {
    if (untrusted[i].empty()) continue;
    if (count++ == 0) first = i;
  }
  if (count > 0) {
    notes.push_back(fmt::format("{} of {} orbits untrusted, the first at {:.4f} rpm: {}", count,
                                untrusted.size(), RadPerSecondToRpm(branch.points[first].lambda),
                                untrusted[first]));
  }
  fmt::print(out, "{}\n", line);
  for (const std::string& note : notes) fmt::print(out, "    note: {}\n", note);
  if (!notes.empty()) writer.SetAttribute(group, "check_note", fmt::format("{}", fmt::join(notes, "; ")));
}

void PrintSpecialPoints(const Branch& branch, std::ostream& out) {
  for (const SpecialPoint& p : branch.special_points) {
    fmt::print(out, "    {:<28} {:9.4f} rpm  precession (carrier) {:.4f} Hz  modulation {:.2f} Hz{}\n",
               p.Name(), RadPerSecondToRpm(p.lambda),
               p.measures(branch.MeasureIndex("precession_hz")),
               p.measures(branch.MeasureIndex("modulation_hz")),
               p.converged ? "" : "  (not located" + (p.note.empty() ? "" : ": " + p.note) + ")");
  }
}

namespace {

// A branch followed from special point `point` of family `parent`: /orbits/<branch_name> with
// attrs parent, branch_point_speed_rpm, branch_point_precession_hz, branch_point_note, its summary
// lines and checks.
void WriteFollowedBranch(const PeriodicOrbitBranch& followed, const std::string& branch_name,
                         const std::string& parent, const Branch& family,
                         const SpecialPoint& point, const std::string& note,
                         const OrbitTrust& trust, ResultWriter& writer, std::ostream& out,
                         std::vector<std::string>& failures) {
  WritePeriodicOrbitBranch(writer, branch_name, followed, {"speed_rpm", kRpmPerRadPerSecond},
                           "/orbits");
  const std::string group = "/orbits/" + branch_name;
  writer.SetAttribute(group, "parent", parent);
  writer.SetAttribute(group, "branch_point_speed_rpm", RadPerSecondToRpm(point.lambda));
  writer.SetAttribute(group, "branch_point_precession_hz",
                      point.measures(family.MeasureIndex("precession_hz")));
  writer.SetAttribute(group, "branch_point_note", note);
  const Branch& b = followed.branch;
  fmt::print(out, "  {}: {}\n", branch_name, b.BriefReport());
  PrintSpecialPoints(b, out);
  ReportOrbitChecks(b, group, trust, writer, out);
  if (IsFailure(b.status)) {
    failures.push_back(fmt::format("[orbits] {}: {}", branch_name, b.message));
  }
}

// The branches followed from the located branch points of family `name`: /orbits/<name>_bp<k>
// (k = 1, 2, … in the family's order; a second side "_bp<k>b"), with what the point breaks.
void WriteBranchSwitches(const RubModulatedOrbits& orbits, const std::string& name,
                         const OrbitTrust& trust, ResultWriter& writer, std::ostream& out,
                         std::vector<std::string>& failures) {
  const Branch& family = orbits.orbits.branch;
  int count = 0;
  for (std::size_t k = 0; k < family.special_points.size(); ++k) {
    const SpecialPoint& point = family.special_points[k];
    if (point.type != SpecialPointType::kBranchPoint) continue;
    const double rpm = RadPerSecondToRpm(point.lambda);
    const auto followed = std::find_if(orbits.switches.begin(), orbits.switches.end(),
                                       [k](const OrbitBranchSwitch& s) { return s.special_point == k; });
    if (followed == orbits.switches.end()) {
      const auto reached = std::find_if(
          orbits.switches.begin(), orbits.switches.end(),
          [&](const OrbitBranchSwitch& s) { return s.RejoinedNear(point.lambda); });
      if (reached != orbits.switches.end()) {
        fmt::print(out, "    branch point {:.4f} rpm: the far end of the branch from {:.4f} rpm, "
                        "which rejoins the family here\n",
                   rpm, RadPerSecondToRpm(family.special_points[reached->special_point].lambda));
      }
      continue;
    }
    const OrbitBranchSwitch& change = *followed;
    ++count;
    std::string what;
    if (!change.ok) {
      what = "no other branch: " + change.message;
    } else if (change.breaks_mirror_symmetry) {
      what = fmt::format("breaks the left–right symmetry (the family's orbits are symmetric, the new "
                         "direction {:.3f} odd): the other side is its mirror image",
                         change.direction_odd_part);
    } else if (change.mirror_symmetric_orbit) {
      what = fmt::format("keeps the left–right symmetry (new direction {:.3f} odd)",
                         change.direction_odd_part);
    } else {
      what = "no symmetry decides it";
    }
    fmt::print(out, "    branch point {:.4f} rpm: {}\n", rpm, what);
    for (std::size_t side = 0; side < change.branches.size(); ++side) {
      const std::string branch_name = fmt::format("{}_bp{}{}", name, count, side == 0 ? "" : "b");
      WriteFollowedBranch(change.branches[side], branch_name, name, family, point, what, trust,
                          writer, out, failures);
      writer.SetAttribute("/orbits/" + branch_name, "branch_angle", change.change.angle);
    }
  }
}

// The doubled families followed from the family's period doublings: /orbits/<name>_pd<k>
// (k = 1, 2, … in the family's order).
void WritePeriodDoublings(const RubModulatedOrbits& orbits, const std::string& name,
                          const OrbitTrust& trust, ResultWriter& writer, std::ostream& out,
                          std::vector<std::string>& failures) {
  const Branch& family = orbits.orbits.branch;
  int count = 0;
  for (const OrbitPeriodDoubling& doubling : orbits.doublings) {
    const SpecialPoint& point = family.special_points[doubling.special_point];
    const double rpm = RadPerSecondToRpm(point.lambda);
    if (!doubling.ok) {
      fmt::print(out, "    period doubling {:.4f} rpm: no doubled orbits: {}\n", rpm,
                 doubling.message);
      failures.push_back(fmt::format("[orbits] {}: period doubling at {:.4f} rpm: {}", name, rpm,
                                     doubling.message));
      continue;
    }
    const std::string what = fmt::format(
        "period doubling (multiplier {:.6f}): the doubled orbits, period 2T", doubling.multiplier);
    fmt::print(out, "    period doubling {:.4f} rpm: followed (multiplier {:.6f})\n", rpm,
               doubling.multiplier);
    const std::string branch_name = fmt::format("{}_pd{}", name, ++count);
    WriteFollowedBranch(doubling.branch, branch_name, name, family, point, what, trust, writer,
                        out, failures);
    writer.SetAttribute("/orbits/" + branch_name, "period_doubling_multiplier",
                        doubling.multiplier);
  }
}

// The family through the orbit a transient settles on ([analysis.orbits.transient]): the
// transient, its orbit, the family as /orbits/transient and its side branches.
void RunTransientOrbits(const Scene& scene, const RubOrbitsPlan& plan, const OrbitTrust& trust,
                        StageContext& context) {
  const RubOrbitsSettings::Transient& t = scene.analysis.orbits.transient;
  std::ostream& out = context.out;
  const SteadyClock::time_point t0 = SteadyClock::now();
  const std::string name = "transient";
  const std::optional<SceneTransientOrbits> solved = SolveSceneTransientOrbits(
      scene, plan, "[orbits]", name, scene.analysis.orbits.follow_branch_points, t0, context);
  if (!solved) return;
  const RubSettledSpeed& transient = solved->transient;
  const RubTransientOrbits& result = solved->orbits;
  const ModulatedOrbit& orbit = result.start;
  const PeriodicOrbitBranch& family = result.family.orbits;
  WritePeriodicOrbitBranch(context.writer, name, family, {"speed_rpm", kRpmPerRadPerSecond},
                           "/orbits");
  const std::string group = "/orbits/" + name;
  ResultWriter& w = context.writer;
  WriteTransientAttributes(w, group, t.speed_rpm, t.seconds, transient);
  w.SetAttribute(group, "laps", static_cast<double>(t.laps));
  w.SetAttribute(group, "start_period", orbit.period);
  w.SetAttribute(group, "start_rotation", orbit.rotation);
  w.SetAttribute(group, "start_carrier_hz", orbit.carrier_hz);
  w.SetAttribute(group, "start_dominant_hz", orbit.dominant_hz);
  w.SetAttribute(group, "start_message", orbit.message);
  std::vector<double> folds;
  for (const double f : DistinctFolds(family.branch)) folds.push_back(RadPerSecondToRpm(f));
  w.SetAttribute(group, "fold_speeds_rpm", folds);
  const Branch& branch = family.branch;
  fmt::print(out, "  {}: {} ({:.1f} s; {} integrator steps)\n", name, branch.BriefReport(),
             SecondsSince(t0), family.work.steps);
  PrintSpecialPoints(branch, out);
  ReportOrbitChecks(branch, group, trust, w, out);
  if (IsFailure(branch.status)) {
    context.failures.push_back(fmt::format("[orbits] {}: {}", name, branch.message));
  }
  WriteBranchSwitches(result.family, name, trust, w, out, context.failures);
  WritePeriodDoublings(result.family, name, trust, w, out, context.failures);
}

// A textbook model: its periodic orbits continued in its parameter from the first one.
void RunTextbookOrbits(const Scene& scene, StageSetup setup, ResultWriter& writer,
                       const std::function<void(const std::string&)>& progress, std::ostream& out,
                       std::vector<std::string>& failures) {
  const SteadyClock::time_point begin = SteadyClock::now();
  if (!setup.start.valid) {
    failures.push_back(fmt::format("[orbits] no periodic orbit found at {} = {}: {}",
                                   setup.parameter_name, scene.orbits.start, setup.start.message));
    return;
  }
  const PeriodicOrbitBranch orbits =
      ContinuePeriodicOrbits(*setup.system, setup.kind, setup.start, setup.options);
  const double seconds = SecondsSince(begin);
  progress(fmt::format("[orbits] {} points in {:.2f} s", orbits.branch.Size(), seconds));
  WritePeriodicOrbitBranch(writer, "periodic_orbits", orbits, {setup.parameter_name, 1.0});

  const Branch& branch = orbits.branch;
  fmt::print(out, "[orbits] L2 periodic orbits of {} ({} shooting, {} segment{}), {} in [{}, {}] "
                  "from {}: {:.3f} s\n",
             ToString(scene.model), setup.kind == OrbitKind::kForced ? "forced" : "autonomous",
             orbits.segments, orbits.segments == 1 ? "" : "s", setup.parameter_name,
             setup.options.lambda_min, setup.options.lambda_max, scene.orbits.start, seconds);
  fmt::print(out, "  periodic_orbits: {}\n", branch.BriefReport());
  fmt::print(out, "    work: {} segment integrations ({} with sensitivities), {} integrator steps\n",
             orbits.work.residual_integrations + orbits.work.sensitivity_integrations,
             orbits.work.sensitivity_integrations, orbits.work.steps);
  for (const SpecialPoint& p : branch.special_points) {
    fmt::print(out, "    {:<28} {} = {:.10g}{}\n", p.Name(), setup.parameter_name, p.lambda,
               p.converged ? "" : "  (not located" + (p.note.empty() ? "" : ": " + p.note) + ")");
  }
  if (setup.check && branch.Size() > 0) setup.check(scene, branch, writer, out);
  if (IsFailure(branch.status)) {
    failures.push_back(fmt::format("[orbits] periodic_orbits: {}", branch.message));
  }
}

}  // namespace

RubOrbitsPlan PlanRubOrbits(const Scene& scene) {
  RubOrbitsPlan plan;
  plan.structure = StructureOf(scene);
  if (plan.structure.imbalance != 0.0) {
    plan.note = fmt::format(
        "the imbalance ({} kg·m) is left out: the co-rotating frame needs a balanced rotor",
        plan.structure.imbalance);
  }
  plan.structure.imbalance = 0.0;  // not stationary in the co-rotating frame (as for the branches)
  plan.waves = ComputeRotatingWaveBranches(plan.structure, FrictionLawKind::kTanh,
                                           BranchOptionsOf(scene));
  plan.starts = StableBoundaryHopfPoints(plan.waves, plan.structure.Coordinates());
  plan.followed =
      std::min(plan.starts.size(), static_cast<std::size_t>(scene.analysis.orbits.hopf_points));
  plan.options = RubOrbitOptionsOf(scene);
  return plan;
}

void PrintHopfStarts(const RubOrbitsPlan& plan, std::ostream& out) {
  for (const RubHopfStart& s : plan.starts) {
    const auto wave = std::find_if(plan.waves.begin(), plan.waves.end(),
                                   [&](const RotatingWaveBranch& b) { return b.name == s.branch; });
    fmt::print(out, "  Hopf on {} at {:.4f} rpm, {:.4f} Hz, modulation {:.3f} Hz, stable {}{}\n",
               s.branch, RadPerSecondToRpm(s.speed), RadPerSecondToHz(s.precession),
               RadPerSecondToHz(s.modulation), s.stable_below ? "below" : "above",
               LyapunovText(wave->branch.special_points[s.special_point]));
  }
}

std::string RubOrbitsNumerics(const Scene& scene) {
  const RubOrbitsSettings& settings = scene.analysis.orbits;
  const ShootingOptions options = RubShootingOptionsOf(scene);
  const std::string segments =
      fmt::format("{} segment{}", settings.segments, settings.segments == 1 ? "" : "s");
  if (settings.integrator == OrbitIntegrator::kGauss) {
    return fmt::format("{}, Gauss collocation of order {} on {} intervals per period", segments,
                       2 * options.integrator.collocation_stages,
                       JoinedIntegrator(options.integrator, settings.segments).collocation_steps);
  }
  return fmt::format("{}, CVODES BDF at tolerance {:g} with sensitivities", segments,
                     settings.tolerance);
}

std::optional<SceneTransientOrbits> SolveSceneTransientOrbits(
    const Scene& scene, const RubOrbitsPlan& plan, const std::string& prefix,
    const std::string& name, bool side_branches, SteadyClock::time_point t0,
    StageContext& context) {
  const RubOrbitsSettings::Transient& t = scene.analysis.orbits.transient;
  context.progress(
      fmt::format("{} {} at {:g} rpm: {:g} s from rest", prefix, name, t.speed_rpm, t.seconds));
  SceneTransientOrbits solved;
  solved.transient = SceneTransient(scene, plan.structure, t.speed_rpm, t.seconds);
  const RubSettledSpeed& transient = solved.transient;
  if (!ReportTransient(prefix, "orbit", scene, plan.structure, t.speed_rpm, t.seconds, transient,
                       SecondsSince(t0), context)) {
    return std::nullopt;
  }
  PeriodicOrbitBranchOptions options = plan.options.orbits;  // the side branches' max_steps
  options.on_step = [&](const Branch& b) {
    context.progress(fmt::format("{} {}: {} orbits, {:.4f} rpm, {:.0f} s", prefix, name, b.Size(),
                                 RadPerSecondToRpm(b.points.back().lambda), SecondsSince(t0)));
    return true;
  };
  context.progress(fmt::format("{} {} at {:g} rpm: its orbit ({} lap{})", prefix, name,
                               t.speed_rpm, t.laps, t.laps == 1 ? "" : "s"));
  solved.orbits = ContinueTransientOrbits(
      plan.structure, RpmToRadPerSecond(t.speed_rpm), HzToRadPerSecond(transient.precession_hz),
      transient.state, TransientOrbitStartOf(scene), options, t.max_steps, side_branches);
  const ModulatedOrbit& orbit = solved.orbits.start;
  fmt::print(context.out, "  its orbit ({} modulation period{}): {}\n", t.laps,
             t.laps == 1 ? "" : "s", orbit.message);
  if (!orbit.converged) {
    context.failures.push_back(fmt::format("{} the orbit of the transient at {:g} rpm: {}", prefix,
                                           t.speed_rpm, orbit.message));
    return std::nullopt;
  }
  return solved;
}

RubSettledSpeed SceneTransient(const Scene& scene, const RubStructure& structure, double speed_rpm,
                               double seconds) {
  return SettleAtSpeed(structure, TransientSweepOptionsOf(scene, speed_rpm, seconds),
                       scene.analysis.sweep.impulse);
}

bool ReportTransient(const std::string& prefix, const std::string& what, const Scene& scene,
                     const RubStructure& structure, double speed_rpm, double seconds,
                     const RubSettledSpeed& transient, double elapsed_seconds,
                     StageContext& context) {
  const IntegrationMethod method = SweepOptionsOf(scene, SweepDirection::kUp).integrator.method;
  fmt::print(context.out,
             "{} transient at {:g} rpm, {:g} s from rest and a {:g} N·s impulse ({}): "
             "{}, backward precession {:.4f} Hz at the {} contact ({:.1f} s)\n",
             prefix, speed_rpm, seconds, scene.analysis.sweep.impulse, ToString(method),
             transient.settled ? "settled" : "not settled", transient.precession_hz,
             structure.contacts[0].name, elapsed_seconds);
  if (transient.precession_hz > 0.0) return true;
  const std::string why = fmt::format(
      "the transient at {:g} rpm shows no backward precession at the {} contact ({}): no frame to "
      "solve its {} in", speed_rpm, structure.contacts[0].name, transient.point.message, what);
  fmt::print(context.out, "  transient: {}\n", why);
  context.failures.push_back(prefix + " " + why);
  return false;
}

void WriteTransientAttributes(ResultWriter& writer, const std::string& group, double speed_rpm,
                              double seconds, const RubSettledSpeed& transient) {
  writer.SetAttribute(group, "transient_speed_rpm", speed_rpm);
  writer.SetAttribute(group, "transient_seconds", seconds);
  writer.SetAttribute(group, "transient_settled", transient.settled ? 1.0 : 0.0);
  writer.SetAttribute(group, "frame_precession_hz", transient.precession_hz);
}

// Model two_point: the tanh-law rotating waves (the law shooting integrates), then the modulated
// orbits born at the first scene.analysis.orbits.hopf_points Hopf points that bound a stable piece
// of them, and the orbits on a settled transient ([analysis.orbits.transient]).
void RunRubOrbits(const Scene& scene, StageContext& context) {
  ResultWriter& writer = context.writer;
  std::ostream& out = context.out;
  std::vector<std::string>& failures = context.failures;
  const SteadyClock::time_point begin = SteadyClock::now();
  RubOrbitsPlan plan = PlanRubOrbits(scene);
  const RubStructure& structure = plan.structure;
  const std::vector<RotatingWaveBranch>& waves = plan.waves;
  const std::vector<RubHopfStart>& starts = plan.starts;
  const std::size_t followed = plan.followed;
  WriteRotatingWaveBranches(writer, waves, FrictionLawKind::kTanh, scene.analysis.speed_range_rpm,
                            "/orbits/rotating_waves");
  writer.SetAttribute("/orbits", "friction_law", "tanh");
  writer.SetAttribute("/orbits", "velocity_scale", structure.law.velocity_scale);
  const std::string numerics = RubOrbitsNumerics(scene);
  writer.SetAttribute("/orbits", "numerics", numerics);
  fmt::print(out, "[orbits] L2 modulated orbits (relative periodic orbits in the co-rotating frame, "
                  "{}) from {} of the {} Hopf points bounding a stable rotating wave (tanh "
                  "friction, ε = {:g} m/s; {} rotating waves in {:.3f} s)\n",
             numerics, followed, starts.size(), structure.law.velocity_scale, waves.size(),
             SecondsSince(begin));
  if (!plan.note.empty()) {
    writer.SetAttribute("/orbits", "note", plan.note);
    fmt::print(out, "[orbits] note: {}\n", plan.note);
  }
  PrintHopfStarts(plan, out);
  const RubOrbitsSettings& settings = scene.analysis.orbits;
  const OrbitTrust trust{structure, scene.analysis.sweep.max_penetration};
  HopfOrbitOptions& options = plan.options;
  for (std::size_t k = 0; k < followed; ++k) {
    const RubHopfStart& start = starts[k];
    const std::string name = fmt::format("{}_hopf{}", start.branch, start.special_point);
    const SteadyClock::time_point t0 = SteadyClock::now();
    options.on_step = [&](const Branch& b) {
      const double rpm = b.points.empty() ? 0.0 : RadPerSecondToRpm(b.points.back().lambda);
      context.progress(fmt::format("[orbits] {} ({}/{}): {} orbits, {:.2f} rpm, {:.0f} s", name,
                                   k + 1, followed, b.Size(), rpm, SecondsSince(t0)));
      return true;
    };
    const RubModulatedOrbits orbits =
        ContinueModulatedOrbits(structure, waves, start, options, settings.follow_branch_points);
    WritePeriodicOrbitBranch(writer, name, orbits.orbits, {"speed_rpm", kRpmPerRadPerSecond},
                             "/orbits");
    const std::string group = "/orbits/" + name;
    writer.SetAttribute(group, "hopf_branch", start.branch);
    writer.SetAttribute(group, "hopf_speed_rpm", RadPerSecondToRpm(start.speed));
    writer.SetAttribute(group, "hopf_precession_hz", RadPerSecondToHz(start.precession));
    writer.SetAttribute(group, "hopf_modulation_hz", RadPerSecondToHz(start.modulation));
    const Branch& branch = orbits.orbits.branch;
    fmt::print(out, "  {}: {} ({:.1f} s; {} integrator steps)\n", name, branch.BriefReport(),
               SecondsSince(t0), orbits.orbits.work.steps);
    PrintSpecialPoints(branch, out);
    ReportOrbitChecks(branch, group, trust, writer, out);
    if (IsFailure(branch.status)) {
      failures.push_back(fmt::format("[orbits] {}: {}", name, branch.message));
    }
    WriteBranchSwitches(orbits, name, trust, writer, out, failures);
    WritePeriodDoublings(orbits, name, trust, writer, out, failures);
  }
  if (settings.transient.enabled) RunTransientOrbits(scene, plan, trust, context);
}

void RunDuffingOrbits(const Scene& scene, StageContext& context) {
  RunTextbookOrbits(scene, DuffingSetup(scene), context.writer, context.progress, context.out,
                    context.failures);
}

void RunStuartLandauOrbits(const Scene& scene, StageContext& context) {
  RunTextbookOrbits(scene, StuartLandauSetup(scene), context.writer, context.progress, context.out,
                    context.failures);
}

void RunVanDerPolOrbits(const Scene& scene, StageContext& context) {
  RunTextbookOrbits(scene, VanDerPolSetup(scene), context.writer, context.progress, context.out,
                    context.failures);
}

void RunForcedVanDerPolOrbits(const Scene& scene, StageContext& context) {
  RunTextbookOrbits(scene, ForcedVanDerPolSetup(scene), context.writer, context.progress,
                    context.out, context.failures);
}

}  // namespace rubcont
