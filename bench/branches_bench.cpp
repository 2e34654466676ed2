// Rotating-wave branch sets (issue 4): the cost of `rubcont branches` per thesis case, and the
// ε → 0 convergence of the regularized (tanh) whirl → whip transition towards the exact one.
//
// Part 1 times ComputeRotatingWaveBranches (family search + two-way continuation of every family,
// with stability, events and special points) on each scene, median of `repetitions` runs.
// Part 2, on case A(a): the exact law's Mode 1 stick → slip event (ω_t, Ω_t) is the reference; for
// each ε the same branch set is computed with tanh(V/ε), and the regularized transition is the
// located test-function point "left knee" on the Mode 1 branch (dΩ/dω half the rolling slope R/C:
// the midpoint of the rounded corner between whirl and whip; RotatingWaveProblem explains why not
// V = ε). Its relative errors in speed and precession, and the branch set's time, are printed and,
// with an output file, written as CSV.
//
//   build/bench/branches_bench [scenes-dir] [repetitions] [out.csv]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {


struct Timed {
  std::vector<RotatingWaveBranch> branches;
  double median_s = 0.0;
};

Timed Time(const RubStructure& structure, FrictionLawKind law,
           const RotatingWaveBranchOptions& options, int repetitions) {
  Timed out;
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r) {
    const SteadyClock::time_point start = SteadyClock::now();
    out.branches = ComputeRotatingWaveBranches(structure, law, options);
    times.push_back(SecondsSince(start));
  }
  std::sort(times.begin(), times.end());
  out.median_s = times[times.size() / 2];
  return out;
}

// The first special point on a Mode 1 branch labelled `label`, within 10 % of `near_hz`.
const SpecialPoint* Find(const std::vector<RotatingWaveBranch>& branches, const std::string& label,
                         double near_hz) {
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    for (const SpecialPoint& p : b.branch.special_points) {
      if (p.label == label && std::abs(p.measures(0) - near_hz) < 0.1 * near_hz) return &p;
    }
  }
  return nullptr;
}

int Main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : "scenes";
  const int repetitions = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const std::string csv = argc > 3 ? argv[3] : "";

  std::printf("Rotating-wave branch sets, exact friction, median of %d runs\n", repetitions);
  std::printf("%-12s %9s %9s %8s %10s\n", "scene", "branches", "points", "special", "time [ms]");
  double total_s = 0.0;
  for (const char* name : {"thesis_A_a", "thesis_A_b", "thesis_B_a", "thesis_B_b", "thesis_B_c",
                           "thesis_C_a", "thesis_C_b", "thesis_C_c"}) {
    const Scene scene = LoadScene(dir / (std::string(name) + ".toml"));
    const Timed t = Time(TwoPointStructure(scene.two_point), FrictionLawKind::kExact,
                         BranchOptionsOf(scene), repetitions);
    long points = 0, special = 0;
    for (const RotatingWaveBranch& b : t.branches) {
      points += b.branch.Size();
      special += static_cast<long>(b.branch.special_points.size());
    }
    total_s += t.median_s;
    std::printf("%-12s %9zu %9ld %8ld %10.1f\n", name, t.branches.size(), points, special,
                1e3 * t.median_s);
  }
  std::printf("all eight cases: %.1f ms\n\n", 1e3 * total_s);

  // Part 2: ε → 0 on case A(a).
  const Scene scene = LoadScene(dir / "thesis_A_a.toml");
  TwoPointParams params = scene.two_point;
  const RotatingWaveBranchOptions options = BranchOptionsOf(scene);
  const Timed exact = Time(TwoPointStructure(params), FrictionLawKind::kExact, options, repetitions);
  const SpecialPoint* event = Find(exact.branches, "left stick to slip+", 84.5);
  if (event == nullptr) {
    std::fprintf(stderr, "branches_bench: no exact Mode 1 stick → slip event near 84.5 Hz\n");
    return 1;
  }
  const double w_exact = event->lambda, hz_exact = event->measures(0);
  std::printf("case A(a), Mode 1 whirl → whip. Exact: %.9f rpm, %.9f Hz (%.1f ms per branch set)\n",
              RadPerSecondToRpm(w_exact), hz_exact, 1e3 * exact.median_s);
  std::printf("%10s %14s %14s %12s %12s %10s\n", "eps [m/s]", "speed [rpm]", "precession [Hz]",
              "speed err", "freq err", "time [ms]");
  std::ofstream out;
  if (!csv.empty()) {
    std::filesystem::create_directories(std::filesystem::path(csv).parent_path());
    out.open(csv);
    out << "# case A(a) Mode 1 whirl -> whip: tanh(V/eps) transition (knee: dW/dw = R/(2C), left contact) "
           "against the exact stick -> slip event\n"
        << "# exact: speed_rpm " << RadPerSecondToRpm(w_exact) << ", precession_hz " << hz_exact
        << ", time_ms " << 1e3 * exact.median_s << "\n"
        << "eps_m_per_s,speed_rpm,precession_hz,speed_rel_error,precession_rel_error,time_ms\n";
  }
  for (double eps : {1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5}) {
    params.friction_law.velocity_scale = eps;
    const Timed tanh = Time(TwoPointStructure(params), FrictionLawKind::kTanh, options, repetitions);
    const SpecialPoint* p = Find(tanh.branches, "left knee", 84.5);
    if (p == nullptr) {
      std::printf("%10.0e   (no V = ε point on the Mode 1 branch)\n", eps);
      continue;
    }
    const double e_w = (p->lambda - w_exact) / w_exact;
    const double e_hz = (p->measures(0) - hz_exact) / hz_exact;
    std::printf("%10.0e %14.6f %14.6f %12.3e %12.3e %10.1f\n", eps, RadPerSecondToRpm(p->lambda),
                p->measures(0), e_w, e_hz, 1e3 * tanh.median_s);
    if (out) {
      out << eps << ',' << RadPerSecondToRpm(p->lambda) << ',' << p->measures(0) << ',' << e_w
          << ',' << e_hz << ',' << 1e3 * tanh.median_s << '\n';
    }
  }
  if (!csv.empty()) std::printf("wrote %s\n", csv.c_str());
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("branches_bench", [&] { return rubcont::Main(argc, argv); });
}
