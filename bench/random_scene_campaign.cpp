// Random-scene campaign (issue 17): valid two-point scenes drawn at random over the ranges below,
// each run through levels L0 (analytic) and L1 (rotating-wave branches) as `rubcont run` does, and
// every outcome counted:
//   complete       every branch ended by a property of the problem, every special point located
//   ended          a branch ended by a numerical failure (step too small, start failed) or the
//                  closed form met a non-finite value: a status with a reason
//   not_located    a special point left as a guess within its bracket (converged = false)
//   nan            a non-finite number in a computed point (λ, state, measures) or transition
//   crashed        an exception escaped, or the process died (each scene runs in a forked child)
// A scene counts once, in the first of crashed, nan, not_located, ended, complete that applies;
// the counts are printed per friction law, with the not-located special points by kind and the
// CPU time per scene (the child's), and with --csv one row per scene.
//
// The ranges (also in docs/robustness.md), log-uniform where marked (log):
//   rotor mass 2–50 kg (log); contact span l 0.1–1 m (log); mass centre a = l_g/l in −0.3…1.5
//   (overhung beyond either contact); inertia m_r (κ l)² with κ 0.1–0.8;
//   stator mass 2–100 kg (log); span l·(0.7–1.3); b 0.2–0.8; inertia m_s (κ_s l_s)², κ_s 0.1–0.8;
//   support stiffness 1e5–1e8 N/m per station (log); damping ratio 0–0.1 of each station's
//   √(k m_s/2); clearance 1e-4–1e-3 m per contact (log); RCI 30–300 per contact (log);
//   μ 0.05–1.5; contact stiffness k1 1e8–1e12 N/m (log), k2 = 0, c_nl = k1·(0–1e-5) s;
//   friction law exact or tanh (half each) with ε 1e-4–1e-2 m/s (log);
//   centre damper 0 (half) or 0–100 N·s/m.
// The precession range is 1 Hz to 2.5× the highest natural frequency (at least 200 Hz), the speed
// range 0.25× to 3× the speed at which the rolling line R/C·ω meets the pinned bounce/pitch
// frequencies (so the whirl → whip transitions fall inside).
//
//   build/bench/random_scene_campaign [--scenes N] [--first I] [--seed S] [--csv FILE] [--require-clean]
//   build/bench/random_scene_campaign --seed S --print I > scene.toml
// Scenes I … I + N − 1 of seed S (default 0 … 499 of seed 1).
// --require-clean: exit 1 unless 0 crashed and 0 nan (the ctest slice uses it). --print writes
// scene I of seed S as a scene file, to reproduce one outcome with `rubcont run`.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/analytic.h"
#include "models/units.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

struct Draw {
  std::mt19937_64 rng;
  double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  double Log(double lo, double hi) { return std::exp(Uniform(std::log(lo), std::log(hi))); }
  bool Coin() { return Uniform(0.0, 1.0) < 0.5; }
};

struct RandomScene {
  std::string toml;
  std::string law;  // the rotating waves' friction law: "exact" or "tanh"
};

// Draw `index` of seed `seed` (one generator per scene: a scene's draw does not depend on how many
// scenes come before it).
RandomScene DrawScene(std::uint64_t seed, int index) {
  Draw d{std::mt19937_64(seed * 1000003u + static_cast<std::uint64_t>(index))};
  TwoPointParams p;
  p.rotor_mass = d.Log(2.0, 50.0);
  p.contact_span = d.Log(0.1, 1.0);
  p.rotor_mass_center = d.Uniform(-0.3, 1.5) * p.contact_span;
  p.rotor_inertia = p.rotor_mass * std::pow(d.Uniform(0.1, 0.8) * p.contact_span, 2);
  p.stator_mass = d.Log(2.0, 100.0);
  p.stator_span = p.contact_span * d.Uniform(0.7, 1.3);
  p.stator_mass_center = d.Uniform(0.2, 0.8) * p.stator_span;
  p.stator_inertia = p.stator_mass * std::pow(d.Uniform(0.1, 0.8) * p.stator_span, 2);
  for (int k = 0; k < 2; ++k) {
    p.support_stiffness[k] = d.Log(1e5, 1e8);
    p.support_damping[k] = d.Uniform(0.0, 0.1) * std::sqrt(p.support_stiffness[k] * p.stator_mass / 2);
    p.clearance[k] = d.Log(1e-4, 1e-3);
    p.radius[k] = d.Log(30.0, 300.0) * p.clearance[k];
  }
  p.friction = d.Uniform(0.05, 1.5);
  p.contact_stiffness = d.Log(1e8, 1e12);
  p.contact_damping = p.contact_stiffness * d.Uniform(0.0, 1e-5);
  const bool tanh = d.Coin();
  const double eps = d.Log(1e-4, 1e-2);
  p.center_damping = d.Coin() ? 0.0 : d.Uniform(0.0, 100.0);

  const NaturalFrequencies f = ComputeNaturalFrequencies(p);
  const double f_lo = std::min(f.pinned_bounce.frequency_hz, f.pinned_pitch.frequency_hz);
  const double f_hi = std::max({f.pinned_bounce.frequency_hz, f.pinned_pitch.frequency_hz,
                                f.stator_bounce.frequency_hz, f.stator_pitch.frequency_hz});
  const double rci_lo = std::min(p.Rci(0), p.Rci(1)), rci_hi = std::max(p.Rci(0), p.Rci(1));
  const double speed_lo = 0.25 * HzToRpm(f_lo) / rci_hi, speed_hi = 3.0 * HzToRpm(f_hi) / rci_lo;

  RandomScene scene;
  scene.law = tanh ? "tanh" : "exact";
  scene.toml = fmt::format(
      "description = \"random scene {} of seed {}\"\n"
      "[rotor]\nmass = {:.17g}\ninertia = {:.17g}\ncontact_span = {:.17g}\nmass_center = {:.17g}\n"
      "[stator]\nmass = {:.17g}\ninertia = {:.17g}\nspan = {:.17g}\nmass_center = {:.17g}\n"
      "stiffness = [{:.17g}, {:.17g}]\ndamping = [{:.17g}, {:.17g}]\n"
      "[contact]\nclearance = [{:.17g}, {:.17g}]\nradius = [{:.17g}, {:.17g}]\nfriction = {:.17g}\n"
      "stiffness = {:.17g}\nstiffness2 = 0.0\ndamping = {:.17g}\n"
      "[contact.friction_law]\nkind = \"{}\"\nvelocity_scale = {:.17g}\n"
      "[center_damper]\ndamping = {:.17g}\n"
      "[analysis]\nstages = [\"analytic\", \"branches\"]\nprecession_range_hz = [1.0, {:.17g}]\n"
      "speed_range_rpm = [{:.17g}, {:.17g}]\n",
      index, seed, p.rotor_mass, p.rotor_inertia, p.contact_span, p.rotor_mass_center,
      p.stator_mass, p.stator_inertia, p.stator_span, p.stator_mass_center,
      p.support_stiffness[0], p.support_stiffness[1], p.support_damping[0], p.support_damping[1],
      p.clearance[0], p.clearance[1], p.radius[0], p.radius[1], p.friction, p.contact_stiffness,
      p.contact_damping, scene.law, eps, p.center_damping, std::max(200.0, 2.5 * f_hi), speed_lo,
      speed_hi);
  return scene;
}

// A point's measures are finite except μ_req = F/N ("mu_ratio_<contact>"), which is NaN by
// definition where the contact is open (N ≤ 0).
bool MeasuresFinite(const Branch& branch, const Vector& measures) {
  for (Index i = 0; i < measures.size(); ++i) {
    if (std::isfinite(measures(i))) continue;
    const std::string& name = branch.measure_names[static_cast<std::size_t>(i)];
    if (name.rfind("mu_ratio_", 0) != 0 || !std::isnan(measures(i))) return false;
  }
  return true;
}

// What a scene came to. The child sends it to the parent as one line of tab-separated fields.
struct SceneOutcome {
  std::string outcome;  // complete, ended, not_located, nan or crashed
  std::string branches = "0", special = "0";
  std::string tally;    // the special points left not located by kind: "kind|count;…"
  std::string detail;   // why, for every outcome but complete

  static SceneOutcome Crashed(const std::string& why) { return {"crashed", "0", "0", "", why}; }
  std::string ToLine() const {
    std::string line = fmt::format("{}\t{}\t{}\t{}\t{}", outcome, branches, special, tally, detail);
    std::replace(line.begin(), line.end(), '\n', ' ');
    return line;
  }
  static SceneOutcome FromLine(const std::string& line) {
    std::vector<std::string> f;
    for (std::size_t from = 0, tab; from <= line.size(); from = tab + 1) {
      tab = std::min(line.find('\t', from), line.size());
      f.push_back(line.substr(from, tab - from));
    }
    f.resize(5);
    return {f[0], f[1], f[2], f[3], f[4]};
  }
};

// One scene through L0 and L1.
SceneOutcome RunScene(const std::string& toml, const std::string& name) {
  const Scene scene = ParseScene(toml, name, name);
  std::string nan, not_located, ended;
  const AnalyticResult analytic = ComputeAnalytic(scene.two_point, AnalyticOptionsOf(scene));
  for (const AnalyticCurve* c : {&analytic.mode1, &analytic.mode2}) {
    if (!c->Succeeded()) {
      ended = fmt::format("analytic {}: {}", ToString(c->mode), c->message);
      continue;
    }
    for (int k = 0; k < 2; ++k) {
      if (!c->normal_force[k].allFinite() || !c->friction_force[k].allFinite())
        nan = fmt::format("analytic {}: a non-finite force", ToString(c->mode));
    }
    for (const Transition& t : c->transitions) {
      if (!std::isfinite(t.precession_hz) || !std::isfinite(t.normal_force))
        nan = fmt::format("analytic {}: a non-finite {}", ToString(c->mode), ToString(t.type));
    }
  }
  const std::vector<RotatingWaveBranch> branches =
      ComputeRotatingWaveBranches(StructureOf(scene), FrictionLawOf(scene), BranchOptionsOf(scene));
  long special = 0;
  std::map<std::string, int> unlocated;  // not-located special points by kind
  for (const RotatingWaveBranch& b : branches) {
    for (const BranchPoint& q : b.branch.points) {
      if (!std::isfinite(q.lambda) || !q.u.allFinite() || !MeasuresFinite(b.branch, q.measures))
        nan = fmt::format("{} ({}): a non-finite point at λ = {}", b.name, b.family, q.lambda);
    }
    for (const SpecialPoint& s : b.branch.special_points) {
      ++special;
      if (s.converged) continue;
      ++unlocated[fmt::format("{} ({} law, {})", s.Name(),
                              scene.two_point.friction_law.kind == FrictionLawKind::kTanh ? "tanh" : "exact",
                              s.note.rfind("not a zero", 0) == 0 ? "not a zero" : "not to tolerance")];
      if (not_located.empty())
        not_located = fmt::format("{} ({}): {} at {:.6g} rpm not located ({})", b.name, b.family,
                                  s.Name(), RadPerSecondToRpm(s.lambda), s.note);
    }
    if (IsFailure(b.branch.status) && ended.empty())
      ended = fmt::format("{} ({}): {}", b.name, b.family, b.branch.message);
  }
  SceneOutcome out;
  out.outcome = !nan.empty()           ? "nan"
                : !not_located.empty() ? "not_located"
                : !ended.empty()       ? "ended"
                                       : "complete";
  out.branches = std::to_string(branches.size());
  out.special = std::to_string(special);
  std::string kinds;
  for (const auto& [kind, count] : unlocated) {
    kinds += fmt::format("{}{} × {}", kinds.empty() ? "" : ", ", count, kind);
    out.tally += fmt::format("{}|{};", kind, count);
  }
  out.detail = !nan.empty()           ? nan
               : !not_located.empty() ? fmt::format("{}; first: {}", kinds, not_located)
                                      : ended;
  return out;
}

// Runs RunScene in a forked child, so a crash counts as "crashed" and the campaign goes on;
// `cpu_seconds` is the child's CPU time (user + system).
SceneOutcome RunIsolated(const std::string& toml, const std::string& name, double& cpu_seconds) {
  cpu_seconds = 0.0;
  int fd[2];
  if (pipe(fd) != 0) return SceneOutcome::Crashed("pipe failed");
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    std::string line;
    try {
      line = RunScene(toml, name).ToLine();
    } catch (const std::exception& e) {
      line = SceneOutcome::Crashed(std::string("exception: ") + e.what()).ToLine();
    }
    const ssize_t written = write(fd[1], line.data(), line.size());
    _exit(written == static_cast<ssize_t>(line.size()) ? 0 : 3);
  }
  close(fd[1]);
  std::string line;
  char buffer[4096];
  for (ssize_t n; (n = read(fd[0], buffer, sizeof buffer)) > 0;) line.append(buffer, n);
  close(fd[0]);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  cpu_seconds = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
                1e-6 * usage.ru_stime.tv_usec;
  if (WIFSIGNALED(status)) {
    return SceneOutcome::Crashed(
        fmt::format("signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status))));
  }
  if (line.empty()) return SceneOutcome::Crashed("no result from the child");
  return SceneOutcome::FromLine(line);
}

int Main(int argc, char** argv) {
  int scenes = 500;
  int first = 0;
  std::uint64_t seed = 1;
  std::string csv;
  bool require_clean = false;
  int print = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scenes" && i + 1 < argc) scenes = std::atoi(argv[++i]);
    else if (a == "--first" && i + 1 < argc) first = std::atoi(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--require-clean") require_clean = true;
    else if (a == "--print" && i + 1 < argc) print = std::atoi(argv[++i]);
    else {
      std::fprintf(stderr, "usage: random_scene_campaign [--scenes N] [--first I] [--seed S] [--csv FILE] "
                           "[--require-clean] [--print I]\n");
      return 2;
    }
  }
  if (print >= 0) {
    std::fputs(DrawScene(seed, print).toml.c_str(), stdout);
    return 0;
  }
  std::ofstream out;
  if (!csv.empty()) {
    if (std::filesystem::path(csv).has_parent_path())
      std::filesystem::create_directories(std::filesystem::path(csv).parent_path());
    out.open(csv);
    out << "# random_scene_campaign --scenes " << scenes << " --first " << first << " --seed " << seed
        << "\n"
        << "index\tlaw\toutcome\tbranches\tspecial_points\tcpu_seconds\tdetail\n";
  }
  // Outcomes per friction law of the rotating waves, and in all.
  std::map<std::string, std::map<std::string, int>> counts;
  std::vector<double> seconds, cpu_seconds;
  std::map<std::string, int> not_located;  // special points left not located, by kind
  std::map<std::string, std::vector<std::string>> examples;
  for (int i = first; i < first + scenes; ++i) {
    const std::string name = fmt::format("random_{}_{}", seed, i);
    const SteadyClock::time_point start = SteadyClock::now();
    const RandomScene scene = DrawScene(seed, i);
    double cpu = 0.0;
    const SceneOutcome r = RunIsolated(scene.toml, name, cpu);
    seconds.push_back(SecondsSince(start));
    cpu_seconds.push_back(cpu);
    ++counts[scene.law][r.outcome];
    ++counts["all"][r.outcome];
    for (std::size_t from = 0, end; (end = r.tally.find(';', from)) != std::string::npos; from = end + 1) {
      const std::string entry = r.tally.substr(from, end - from);
      const std::size_t bar = entry.rfind('|');
      not_located[entry.substr(0, bar)] += std::atoi(entry.c_str() + bar + 1);
    }
    if (r.outcome != "complete" && examples[r.outcome].size() < 5)
      examples[r.outcome].push_back(fmt::format("scene {}: {}", i, r.detail));
    if (out) {
      out << i << '\t' << scene.law << '\t' << r.outcome << '\t' << r.branches << '\t' << r.special
          << '\t' << cpu << '\t' << r.detail << '\n';
    }
    if ((i + 1 - first) % 50 == 0) std::fprintf(stderr, "%d of %d scenes\n", i + 1 - first, scenes);
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(cpu_seconds.begin(), cpu_seconds.end());
  std::printf("Random-scene campaign: %d two-point scenes (%d … %d of seed %llu), analytic + branches\n",
              scenes, first, first + scenes - 1, static_cast<unsigned long long>(seed));
  std::printf("  %-12s %6s %6s %6s\n", "outcome", "exact", "tanh", "all");
  for (const char* k : {"complete", "ended", "not_located", "nan", "crashed"})
    std::printf("  %-12s %6d %6d %6d\n", k, counts["exact"][k], counts["tanh"][k], counts["all"][k]);
  if (!seconds.empty()) {
    std::printf("  CPU seconds per scene: median %.3f, 90 %% %.3f, max %.3f (all %d: %.1f s)\n",
                cpu_seconds[cpu_seconds.size() / 2], cpu_seconds[cpu_seconds.size() * 9 / 10],
                cpu_seconds.back(), scenes, std::accumulate(cpu_seconds.begin(), cpu_seconds.end(), 0.0));
    std::printf("  wall seconds per scene, with the fork: median %.3f, 90 %% %.3f, max %.3f\n",
                seconds[seconds.size() / 2], seconds[seconds.size() * 9 / 10], seconds.back());
  }
  if (!not_located.empty()) std::printf("special points not located, by kind:\n");
  for (const auto& [kind, count] : not_located) std::printf("  %5d  %s\n", count, kind.c_str());
  for (const auto& [outcome, lines] : examples) {
    std::printf("first %s:\n", outcome.c_str());
    for (const std::string& l : lines) std::printf("  %s\n", l.c_str());
  }
  if (!csv.empty()) std::printf("wrote %s\n", csv.c_str());
  return require_clean && (counts["all"]["crashed"] > 0 || counts["all"]["nan"] > 0) ? 1 : 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("random_scene_campaign", [&] { return rubcont::Main(argc, argv); });
}
