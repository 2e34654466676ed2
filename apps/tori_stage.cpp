#include "apps/tori_stage.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/branch_output.h"
#include "apps/orbit_output.h"
#include "apps/orbits_stage.h"
#include "apps/stage_options.h"
#include "models/units.h"
#include "shooting/rub_tori.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "studies/hysteresis_map.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {

namespace {

void WriteTorusFamily(ResultWriter& writer, const std::string& group, const std::string& parent,
                      const TorusBranch& tori, const std::vector<RubTorusLines>& lines,
                      const RubStructure& structure) {
  writer.CreateGroup(group);
  const Branch& b = tori.branch;
  writer.SetAttribute(group, "parent", parent);
  if (std::isfinite(tori.birth_lambda)) {  // born at a Neimark–Sacker point
    writer.SetAttribute(group, "birth_speed_rpm", RadPerSecondToRpm(tori.birth_lambda));
    writer.SetAttribute(group, "birth_rotation_number", tori.birth_rotation_number);
    writer.SetAttribute(group, "birth_modulus", tori.birth_modulus);
  }
  writer.SetAttribute(group, "harmonics", static_cast<double>(tori.harmonics));
  writer.SetAttribute(group, "circle_coordinates", ToString(tori.coordinates));
  writer.SetAttribute(group, "end", ToString(tori.end));
  writer.SetAttribute(group, "end_note", tori.end_note);
  writer.SetAttribute(group, "convergence_note", tori.convergence_note);
  writer.SetAttribute(group, "status", ToString(b.status));
  writer.SetAttribute(group, "message", b.message);
  writer.SetAttribute(group, "summary", b.BriefReport());
  // The engine's columns and special points (the family's folds and its end event), each torus's
  // stability from its Lyapunov spectrum (stable 1, unstable 0, undecided or not computed −1;
  // unstable_count: the nontrivial exponents above the tolerance).
  Branch columns = b;
  for (std::size_t i = 0; i < columns.points.size(); ++i) {
    columns.points[i].num_unstable =
        i < tori.stability.size() ? tori.stability[i].UnstableCount() : -1;
  }
  const ParameterColumn speed{"speed_rpm", kRpmPerRadPerSecond};
  WriteBranchPointColumns(writer, group, columns, speed);
  WriteSpecialPointColumns(writer, group + "/special_points", columns, speed);
  auto column = [&](const std::string& name, const std::function<double(const RubTorusLines&)>& f) {
    std::vector<double> values;
    for (const RubTorusLines& l : lines) {
      values.push_back(l.valid ? f(l) : kNaN);
    }
    writer.WriteDoubles(group + "/" + name, values);
  };
  column("carrier_hz", [](const RubTorusLines& l) { return l.carrier_hz; });
  column("first_hz", [](const RubTorusLines& l) { return l.first_hz; });
  column("second_hz", [](const RubTorusLines& l) { return l.second_hz; });
  for (std::size_t c = 0; c < structure.contacts.size(); ++c) {
    const std::string& name = structure.contacts[c].name;
    column("line_hz_" + name, [c](const RubTorusLines& l) { return l.contacts[c].line_hz; });
    column("line_l_" + name, [c](const RubTorusLines& l) { return l.contacts[c].line_l; });
    column("line_k_" + name, [c](const RubTorusLines& l) { return l.contacts[c].line_k; });
    column("line_ratio_" + name, [c](const RubTorusLines& l) { return l.contacts[c].line_ratio; });
    column("min_normal_force_" + name,
           [c](const RubTorusLines& l) { return l.contacts[c].min_normal_force; });
    column("max_normal_force_" + name,
           [c](const RubTorusLines& l) { return l.contacts[c].max_normal_force; });
  }
  std::vector<double> largest, tolerance;
  Matrix exponents =
      Matrix::Constant(static_cast<Index>(b.points.size()), tori.state_dimension, kNaN);
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    const bool known = i < tori.stability.size() && tori.stability[i].valid;
    largest.push_back(known ? tori.stability[i].LargestNontrivial() : kNaN);
    tolerance.push_back(known ? tori.stability[i].tolerance : kNaN);
    if (known) exponents.row(static_cast<Index>(i)) = tori.stability[i].exponents.transpose();
  }
  writer.WriteDoubles(group + "/largest_exponent", largest);
  writer.WriteDoubles(group + "/exponent_tolerance", tolerance);
  writer.WriteMatrix(group + "/exponents", exponents);
  // The circles themselves, so that a torus can be reopened (InvariantCircleProblem::Pack layout).
  Matrix unknowns(static_cast<Index>(b.points.size()), b.points.empty() ? 0 : b.points[0].u.size());
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    unknowns.row(static_cast<Index>(i)) = b.points[i].u.transpose();
  }
  writer.WriteMatrix(group + "/unknowns", unknowns);
  std::vector<double> harmonics;
  for (std::size_t i = 0; i < b.points.size(); ++i) harmonics.push_back(tori.SolvedHarmonics(i));
  writer.WriteDoubles(group + "/harmonics", harmonics);
  std::vector<double> refinement[8];
  for (const TorusBranch::Refinement& r : tori.refinements) {
    refinement[0].push_back(RadPerSecondToRpm(r.lambda));
    refinement[1].push_back(r.from);
    refinement[2].push_back(r.to);
    refinement[3].push_back(r.images);
    refinement[4].push_back(r.rotation_number_from);
    refinement[5].push_back(r.rotation_number_to);
    refinement[6].push_back(r.fourier_tail_from);
    refinement[7].push_back(r.fourier_tail_to);
  }
  const char* names[8] = {"speeds_rpm",       "from_harmonics",     "to_harmonics",
                          "images",           "rotation_numbers_from", "rotation_numbers_to",
                          "fourier_tails_from", "fourier_tails_to"};
  for (int k = 0; k < 8; ++k) {
    writer.SetAttribute(group, std::string("refinement_") + names[k], refinement[k]);
  }
}

// One line per torus: speed, ρ, the two frequencies, each contact's strongest line, stability.
void PrintTori(const TorusBranch& tori, const std::vector<RubTorusLines>& lines,
               const RubStructure& structure, std::ostream& out) {
  const Branch& b = tori.branch;
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    const RubTorusLines& l = lines[i];
    std::string contacts;
    for (std::size_t c = 0; c < structure.contacts.size() && l.valid; ++c) {
      const RubTorusLines::Contact& k = l.contacts[c];
      contacts += fmt::format("  {} {:.2f} Hz ({:+d},{:+d}) ×{:.2g}", structure.contacts[c].name,
                              k.line_hz, k.line_l, k.line_k, k.line_ratio);
    }
    std::string stability = "";
    if (i < tori.stability.size() && tori.stability[i].valid) {
      stability = fmt::format("  {} (largest exponent {:+.3g} ± {:.1g} per period)",
                              tori.stability[i].Verdict(),
                              tori.stability[i].LargestNontrivial(), tori.stability[i].tolerance);
    }
    fmt::print(out, "      {:9.4f} rpm  ρ {:.6f}  f1 {:.3f} Hz  f2 {:.3f} Hz  carrier {:.4f} Hz{}{}{}\n",
               RadPerSecondToRpm(b.points[i].lambda), b.points[i].measures(0), l.first_hz,
               l.second_hz, l.carrier_hz,
               tori.convergence_note.empty()
                   ? std::string()
                   : fmt::format("  K {} tail {:.2g}", tori.SolvedHarmonics(i),
                                 b.points[i].measures(b.MeasureIndex("fourier_tail"))),
               contacts, stability);
  }
  for (const TorusBranch::Refinement& r : tori.refinements) {
    fmt::print(out, "      K {} → {} at {:.4f} rpm: ρ {:.8f} → {:.8f}, Fourier tail {:.2g} → {:.2g} "
                    "(from {} images)\n",
               r.from, r.to, RadPerSecondToRpm(r.lambda), r.rotation_number_from,
               r.rotation_number_to, r.fourier_tail_from, r.fourier_tail_to, r.images);
  }
  if (!tori.convergence_note.empty()) fmt::print(out, "      {}\n", tori.convergence_note);
}

// A torus family's step as progress: its size, speed, ρ and radius; the orbits continued from
// its end (locked, at its centre) by their size and speed.
std::string StepProgress(const Branch& b) {
  const BranchPoint& last = b.points.back();
  const bool tori = std::find(b.measure_names.begin(), b.measure_names.end(), "radius") !=
                    b.measure_names.end();
  if (!tori) return fmt::format("{} orbits, {:.4f} rpm", b.Size(), RadPerSecondToRpm(last.lambda));
  return fmt::format("{} tori, {:.4f} rpm, ρ = {:.6f}, radius {:.2g}", b.Size(),
                     RadPerSecondToRpm(last.lambda), last.measures(b.MeasureIndex("rotation_number")),
                     last.measures(b.MeasureIndex("radius")));
}

// The locked orbits a torus family ended at: /tori/<torus family>_locked, and a summary line.
void WriteLockedOrbits(ResultWriter& writer, const std::string& torus_group,
                       const LockedOrbits& locked, std::ostream& out,
                       std::vector<std::string>& failures) {
  if (locked.q == 0) return;  // the family did not end in locking
  if (!locked.ok) {
    fmt::print(out, "    locked {}:{} orbits: {}\n", locked.p, locked.q, locked.message);
    failures.push_back(fmt::format("[tori] {}: the locked orbits: {}", torus_group, locked.message));
    return;
  }
  const std::string name = torus_group.substr(torus_group.rfind('/') + 1) + "_locked";
  WritePeriodicOrbitBranch(writer, name, locked.orbits, {"speed_rpm", kRpmPerRadPerSecond}, "/tori");
  const std::string group = "/tori/" + name;
  writer.SetAttribute(group, "resonance_p", static_cast<double>(locked.p));
  writer.SetAttribute(group, "resonance_q", static_cast<double>(locked.q));
  std::vector<double> folds;
  for (const double f : locked.folds) folds.push_back(RadPerSecondToRpm(f));
  writer.SetAttribute(group, "fold_speeds_rpm", folds);
  writer.SetAttribute(group, "tori_inside", static_cast<double>(locked.tori_inside));
  writer.SetAttribute(group, "note", locked.message);
  const Branch& b = locked.orbits.branch;
  fmt::print(out, "    locked {}:{} orbits ({} laps, {} segments; {}): {}\n", locked.p, locked.q,
             locked.q, locked.orbits.segments, locked.message, b.BriefReport());
  if (folds.size() == 2) {
    fmt::print(out, "      the torus is locked from {:.5f} to {:.5f} rpm (the folds: a stable and a "
                    "saddle {}-lap orbit between them)\n",
               folds[0], folds[1], locked.q);
    if (locked.tori_inside > 0) {
      fmt::print(out, "      {} of the family's tori lie inside it with ρ ≠ {}/{}: no invariant "
                      "circles (roots of the truncated equations past the tongue's edge)\n",
                 locked.tori_inside, locked.p, locked.q);
    }
  } else {
    fmt::print(out, "      folds at {} rpm\n", fmt::join(folds, ", "));
  }
  if (IsFailure(b.status)) failures.push_back(fmt::format("[tori] {}: {}", name, b.message));
}

// The orbits a torus family shrank onto: /tori/<torus family>_centre, its summary lines (the
// located point; the special points and stable speeds of the family beyond it) and checks.
void WriteCentreOrbits(ResultWriter& writer, const std::string& torus_group, const TorusBranch& tori,
                       const CentreOrbits& centre, const OrbitTrust& trust, std::ostream& out,
                       std::vector<std::string>& failures) {
  if (tori.end != TorusEnd::kShrinks) return;
  if (!centre.ok) {
    fmt::print(out, "    the orbits at its centre: {}\n", centre.message);
    failures.push_back(fmt::format("[tori] {}: the orbits at its centre: {}", torus_group,
                                   centre.message));
    return;
  }
  const std::string name = torus_group.substr(torus_group.rfind('/') + 1) + "_centre";
  WritePeriodicOrbitBranch(writer, name, centre.orbits, {"speed_rpm", kRpmPerRadPerSecond}, "/tori");
  const std::string group = "/tori/" + name;
  writer.SetAttribute(group, "neimark_sacker_speed_rpm",
                      centre.located ? RadPerSecondToRpm(centre.lambda) : kNaN);
  writer.SetAttribute(group, "neimark_sacker_rotation_number", centre.rotation_number);
  writer.SetAttribute(group, "note", centre.message);
  const Branch& b = centre.orbits.branch;
  fmt::print(out, "    the orbits at its centre ({} segments): {}\n", centre.orbits.segments,
             b.BriefReport());
  if (centre.located) {
    fmt::print(out, "      Neimark–Sacker point at {:.5f} rpm, arg μ / 2π = {:.6f}: the tori end "
                    "there\n",
               RadPerSecondToRpm(centre.lambda), centre.rotation_number);
  } else {
    fmt::print(out, "      {}\n", centre.message);
  }
  PrintSpecialPoints(b, out);
  std::vector<std::string> stable;
  for (const auto& [from, to] : StableIntervals(b)) {
    stable.push_back(fmt::format("{:.4f}–{:.4f}", RadPerSecondToRpm(std::min(from, to)),
                                 RadPerSecondToRpm(std::max(from, to))));
  }
  if (stable.empty()) {
    fmt::print(out, "    stable at no computed speed\n");
  } else {
    fmt::print(out, "    stable at {} rpm\n", fmt::join(stable, ", "));
  }
  ReportOrbitChecks(b, group, trust, writer, out);
  if (IsFailure(b.status)) failures.push_back(fmt::format("[tori] {}: {}", name, b.message));
}

// `options` saying the work after each family (its tori's lines and exponents) as progress, the
// family of index j named name_of(j) as the step progress names it; t0 when the work began.
RubTorusOptions WithWorkProgress(RubTorusOptions options, StageContext& context,
                                 std::function<std::string(std::size_t)> name_of,
                                 SteadyClock::time_point t0) {
  options.on_work = [&context, name_of = std::move(name_of), t0](std::size_t j, const char* what,
                                                                 std::size_t i, std::size_t n) {
    context.progress(fmt::format("[tori] {}: {} of torus {}/{}, {:.0f} s", name_of(j), what,
                                 i + 1, n, SecondsSince(t0)));
  };
  return options;
}

// The tori's continuation steps as progress, "[tori] <name_of(j)>: <the step>, <s> s" for the
// family of index j; t0 when the work began.
std::function<bool(std::size_t, const Branch&)> TorusStepProgress(
    StageContext& context, std::function<std::string(std::size_t)> name_of,
    SteadyClock::time_point t0) {
  return [&context, name_of = std::move(name_of), t0](std::size_t j, const Branch& b) {
    context.progress(fmt::format("[tori] {}: {}, {:.0f} s", name_of(j), StepProgress(b),
                                 SecondsSince(t0)));
    return true;
  };
}

// The name of the j-th torus family from the Neimark–Sacker points of the orbit family `family`:
// "<family>_ns<j + 1>" (/tori/<that>).
std::string NeimarkSackerToriName(const std::string& family, std::size_t j) {
  return fmt::format("{}_ns{}", family, j + 1);
}

// The tori through the torus a transient settles on ([analysis.tori.transient]): the transient,
// its torus, both families written as /tori/transient_down and /tori/transient_up.
void RunTransientTori(const Scene& scene, const RubOrbitsPlan& plan, StageContext& context) {
  const RubToriSettings::Transient& t = scene.analysis.tori.transient;
  std::ostream& out = context.out;
  const OrbitTrust trust{plan.structure, scene.analysis.sweep.max_penetration};
  const SteadyClock::time_point t0 = SteadyClock::now();
  const double omega = RpmToRadPerSecond(t.speed_rpm);
  context.progress(fmt::format("[tori] transient at {:g} rpm: {:g} s from rest", t.speed_rpm, t.seconds));
  const RubSettledSpeed transient = SceneTransient(scene, plan.structure, t.speed_rpm, t.seconds);
  if (!ReportTransient("[tori]", "torus", scene, plan.structure, t.speed_rpm, t.seconds, transient,
                       SecondsSince(t0), context)) {
    return;
  }
  const ModulatedTorusOptions start = TransientTorusStartOf(scene);
  const auto family_name = [](std::size_t j) -> std::string {
    return j == 0 ? "transient_down" : "transient_up";
  };
  context.progress(fmt::format("[tori] transient at {:g} rpm: its torus ({} harmonics)", t.speed_rpm,
                               t.harmonics));
  const RubTransientTori result = ContinueTransientTori(
      plan.structure, omega, HzToRadPerSecond(transient.precession_hz), transient.state, start,
      WithWorkProgress(TransientTorusOptionsOf(scene), context, family_name, t0),
      TorusStepProgress(context, family_name, t0));
  const ModulatedTorus& torus = result.start;
  fmt::print(out, "  its torus ({} harmonics, {} modulation period{} per section, circles in the {}; "
                  "{:.1f} s): {}\n",
             torus.converged ? torus.harmonics : t.harmonics, torus.laps, torus.laps == 1 ? "" : "s",
             ToString(start.coordinates), torus.seconds, torus.message);
  if (!torus.converged) {
    context.failures.push_back(fmt::format("[tori] the torus of the transient at {:g} rpm: {}",
                                           t.speed_rpm, torus.message));
    return;
  }
  for (std::size_t j = 0; j < result.tori.size(); ++j) {
    const TorusBranch& tori = result.tori[j];
    const std::string name = j == 0 ? "transient_down" : "transient_up";
    if (!tori.ok) {
      fmt::print(out, "  {}: no start: {}\n", name, tori.message);
      context.failures.push_back(fmt::format("[tori] {}: {}", name, tori.message));
      continue;
    }
    const std::string group = "/tori/" + name;
    WriteTorusFamily(context.writer, group, "transient", tori, result.lines[j], plan.structure);
    ResultWriter& w = context.writer;
    const std::string first_map =
        start.collocation_intervals > 0
            ? fmt::format("Gauss collocation on {} intervals per period", start.collocation_intervals)
            : fmt::format("CVODES BDF ≤ 2 at {:g} (sensitivities outside the error test)",
                          start.integrator.relative_tolerance);
    w.SetAttribute(group, "numerics",
                   fmt::format("invariant circles of {} harmonics ({} points) in the {}; the first "
                               "solved with each point over one period by {}, then by the orbits' {}",
                               torus.harmonics, 2 * torus.harmonics + 1, ToString(start.coordinates),
                               first_map, RubOrbitsNumerics(scene)));
    WriteTransientAttributes(w, group, t.speed_rpm, t.seconds, transient);
    w.SetAttribute(group, "start_laps", static_cast<double>(torus.laps));
    w.SetAttribute(group, "start_rotation_number", torus.rotation_number);
    if (std::isfinite(torus.first_map_rotation_number)) {
      w.SetAttribute(group, "start_first_map_rotation_number", torus.first_map_rotation_number);
    }
    w.SetAttribute(group, "start_first_hz", torus.first_hz);
    w.SetAttribute(group, "start_second_hz", torus.second_hz);
    w.SetAttribute(group, "start_carrier_hz", torus.carrier_hz);
    w.SetAttribute(group, "start_fourier_tail", torus.fourier_tail);
    w.SetAttribute(group, "start_invariance_error", torus.invariance_error);
    std::vector<double> in_k[5];  // K, ρ, tail, invariance error, images: each K solved
    for (const ModulatedTorus::AtHarmonics& k : torus.by_harmonics) {
      in_k[0].push_back(k.harmonics);
      in_k[1].push_back(k.rotation_number);
      in_k[2].push_back(k.fourier_tail);
      in_k[3].push_back(k.invariance_error);
      in_k[4].push_back(k.images);
    }
    w.SetAttribute(group, "start_in_k_harmonics", in_k[0]);
    w.SetAttribute(group, "start_in_k_rotation_numbers", in_k[1]);
    w.SetAttribute(group, "start_in_k_fourier_tails", in_k[2]);
    w.SetAttribute(group, "start_in_k_invariance_errors", in_k[3]);
    w.SetAttribute(group, "start_in_k_images", in_k[4]);
    w.SetAttribute(group, "start_message", torus.message);
    fmt::print(out, "  {}: {} ({:.1f} s)\n    {}\n", name, tori.branch.BriefReport(),
               SecondsSince(t0), tori.end_note);
    PrintTori(tori, result.lines[j], plan.structure, out);
    WriteCentreOrbits(w, group, tori, result.centres[j], trust, out, context.failures);
    if (tori.end == TorusEnd::kFailed) {
      context.failures.push_back(fmt::format("[tori] {}: {}", name, tori.end_note));
    }
  }
}

// The family `name` of result.orbits (as /tori/orbits/<name>) and the tori from its
// Neimark–Sacker points (as /tori/<name>_ns<j>), printed; t0 when the family's work began.
void WriteNeimarkSackerTori(const std::string& name, const RubModulatedTori& result,
                            const RubStructure& structure, const OrbitTrust& trust,
                            SteadyClock::time_point t0, StageContext& context) {
  ResultWriter& writer = context.writer;
  std::ostream& out = context.out;
  const PeriodicOrbitBranch& family = result.orbits.orbits;
  WritePeriodicOrbitBranch(writer, name, family, {"speed_rpm", kRpmPerRadPerSecond},
                           "/tori/orbits");
  fmt::print(out, "  {}: {}\n", name, family.branch.BriefReport());
  if (IsFailure(family.branch.status)) {
    context.failures.push_back(fmt::format("[tori] {}: {}", name, family.branch.message));
  }
  if (result.tori.empty()) {
    fmt::print(out, "    no Neimark–Sacker point bounds a stable piece of it: no tori\n");
  }
  for (std::size_t j = 0; j < result.tori.size(); ++j) {
    const TorusBranch& tori = result.tori[j];
    const std::string torus_name = NeimarkSackerToriName(name, j);
    if (!tori.ok) {
      fmt::print(out, "  {}: no start: {}\n", torus_name, tori.message);
      context.failures.push_back(fmt::format("[tori] {}: {}", torus_name, tori.message));
      continue;
    }
    WriteTorusFamily(writer, "/tori/" + torus_name, name, tori, result.lines[j], structure);
    fmt::print(out, "  {}: born at {:.4f} rpm (ρ₀ = {:.6f}, |μ| = {:.6f}): {} ({:.1f} s)\n    {}\n",
               torus_name, RadPerSecondToRpm(tori.birth_lambda), tori.birth_rotation_number,
               tori.birth_modulus, tori.branch.BriefReport(), SecondsSince(t0), tori.end_note);
    PrintTori(tori, result.lines[j], structure, out);
    WriteLockedOrbits(writer, "/tori/" + torus_name, result.locked[j], out, context.failures);
    WriteCentreOrbits(writer, "/tori/" + torus_name, tori, result.centres[j], trust, out,
                      context.failures);
    if (tori.end == TorusEnd::kFailed) {
      context.failures.push_back(fmt::format("[tori] {}: {}", torus_name, tori.end_note));
    }
  }
}

// The family through the orbit a transient settles on ([analysis.orbits.transient]) as
// /tori/orbits/orbit_transient and the tori from its Neimark–Sacker points as
// /tori/orbit_transient_ns<j>: the whips no Hopf point's family reaches (C(b)'s at 53–56 rpm).
void RunTransientOrbitTori(const Scene& scene, const RubOrbitsPlan& plan, StageContext& context) {
  const RubOrbitsSettings::Transient& t = scene.analysis.orbits.transient;
  const OrbitTrust trust{plan.structure, scene.analysis.sweep.max_penetration};
  const SteadyClock::time_point t0 = SteadyClock::now();
  const std::string name = "orbit_transient";
  const std::optional<SceneTransientOrbits> solved =
      SolveSceneTransientOrbits(scene, plan, "[tori]", name, false, t0, context);
  if (!solved) return;
  const auto torus_name = [&name](std::size_t j) { return NeimarkSackerToriName(name, j); };
  const RubModulatedTori result = ContinueTransientOrbitTori(
      plan.structure, solved->orbits,
      WithWorkProgress(TorusOptionsOf(scene), context, torus_name, t0),
      TorusStepProgress(context, torus_name, t0));
  WriteNeimarkSackerTori(name, result, plan.structure, trust, t0, context);
  const std::string group = "/tori/orbits/" + name;
  WriteTransientAttributes(context.writer, group, t.speed_rpm, t.seconds, solved->transient);
  context.writer.SetAttribute(group, "laps", static_cast<double>(t.laps));
}

}  // namespace

void RunRubTori(const Scene& scene, StageContext& context) {
  const SteadyClock::time_point begin = SteadyClock::now();
  RubOrbitsPlan plan = PlanRubOrbits(scene);
  const RubTorusOptions options = TorusOptionsOf(scene);
  ResultWriter& writer = context.writer;
  std::ostream& out = context.out;
  const RubToriSettings& settings = scene.analysis.tori;
  const OrbitTrust trust{plan.structure, scene.analysis.sweep.max_penetration};
  // K of the Neimark–Sacker families, or of the transient's when those are skipped.
  const int harmonics = settings.from_neimark_sacker ? settings.harmonics : settings.transient.harmonics;
  const std::string numerics =
      fmt::format("invariant circles of {} harmonics ({} points), each point over one period by "
                  "the orbits' {}",
                  harmonics, 2 * harmonics + 1, RubOrbitsNumerics(scene));
  writer.CreateGroup("/tori");
  writer.SetAttribute("/tori", "level", "L2");
  writer.SetAttribute("/tori", "parameter_name", "speed_rpm");
  writer.SetAttribute("/tori", "friction_law", "tanh");
  writer.SetAttribute("/tori", "numerics", numerics);
  const std::string transient =
      settings.transient.enabled
          ? fmt::format("through the torus a transient settles on at {:g} rpm", settings.transient.speed_rpm)
          : "";
  const RubOrbitsSettings::Transient& orbit_transient = scene.analysis.orbits.transient;
  std::string neimark_sacker;
  if (settings.from_neimark_sacker) {
    neimark_sacker = fmt::format("from the Neimark–Sacker points of the modulated orbits born at "
                                 "{} of the {} Hopf points bounding a stable rotating wave",
                                 plan.followed, plan.starts.size());
  }
  if (settings.from_neimark_sacker && orbit_transient.enabled) {
    neimark_sacker += fmt::format(" and of the family through the orbit a transient settles on at "
                                  "{:g} rpm", orbit_transient.speed_rpm);
  }
  fmt::print(out, "[tori] L2 relative 2-tori ({}) {}{}{} ({:.3f} s)\n", numerics, neimark_sacker,
             neimark_sacker.empty() || transient.empty() ? "" : "; ", transient, SecondsSince(begin));
  if (!plan.note.empty()) {
    writer.SetAttribute("/tori", "note", plan.note);
    fmt::print(out, "[tori] note: {}\n", plan.note);
  }
  if (settings.from_neimark_sacker) PrintHopfStarts(plan, out);
  const std::size_t followed = settings.from_neimark_sacker ? plan.followed : 0;
  for (std::size_t k = 0; k < followed; ++k) {
    const RubHopfStart& start = plan.starts[k];
    const std::string name = fmt::format("{}_hopf{}", start.branch, start.special_point);
    const SteadyClock::time_point t0 = SteadyClock::now();
    plan.options.on_step = [&](const Branch& b) {
      context.progress(fmt::format("[tori] {} ({}/{}): {} orbits, {:.2f} rpm, {:.0f} s", name,
                                   k + 1, plan.followed, b.Size(),
                                   RadPerSecondToRpm(b.points.back().lambda), SecondsSince(t0)));
      return true;
    };
    const auto torus_name = [&name](std::size_t j) { return NeimarkSackerToriName(name, j); };
    const RubModulatedTori result = ContinueModulatedTori(
        plan.structure, plan.waves, start, plan.options,
        WithWorkProgress(options, context, torus_name, t0),
        TorusStepProgress(context, torus_name, t0));
    const std::string family_group = "/tori/orbits/" + name;
    WriteNeimarkSackerTori(name, result, plan.structure, trust, t0, context);
    writer.SetAttribute(family_group, "hopf_branch", start.branch);
    writer.SetAttribute(family_group, "hopf_speed_rpm", RadPerSecondToRpm(start.speed));
    writer.SetAttribute(family_group, "hopf_precession_hz", RadPerSecondToHz(start.precession));
    writer.SetAttribute(family_group, "hopf_modulation_hz", RadPerSecondToHz(start.modulation));
  }
  if (settings.from_neimark_sacker && orbit_transient.enabled) {
    RunTransientOrbitTori(scene, plan, context);
  }
  if (settings.transient.enabled) RunTransientTori(scene, plan, context);
}

}  // namespace rubcont
