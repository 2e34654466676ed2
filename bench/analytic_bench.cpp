// Time of the analytic (L0) curve: 4000 precession frequencies for one scene (thesis case A(a),
// with its centre damper), including the location of every transition by Brent's method.
// Goal (issue 2): under 20 ms. Reports the median and the minimum of repeated runs.
//
//   build/bench/analytic_bench [repetitions]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bench/bench_main.h"
#include "models/analytic.h"

namespace {

template <class Function>
std::vector<double> TimeMs(int repetitions, Function&& function) {
  std::vector<double> ms;
  for (int i = 0; i < repetitions; ++i) {
    const auto start = std::chrono::steady_clock::now();
    function();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms;
}

void Report(const char* what, const std::vector<double>& ms, int points) {
  std::printf("%-52s median %7.3f ms   min %7.3f ms   (%5.0f ns per frequency)\n", what,
              ms[ms.size() / 2], ms.front(), 1e6 * ms[ms.size() / 2] / points);
}

}  // namespace

static int Run(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 101;
  // thesis A(a): disk at centre, RCI 100/100, c_d = 52 N·s/m
  const rubcont::TwoPointParams p = rubcont::ThesisCaseAa();
  rubcont::AnalyticOptions options;  // 4000 points over 1–200 Hz
  std::size_t sink = 0;
  std::printf("analytic curve, thesis A(a), %d frequencies over %g–%g Hz, %d repetitions\n",
              options.precession_points, options.min_precession_hz, options.max_precession_hz,
              repetitions);
  Report("Mode 1 curve + transitions (ComputeAnalyticCurve)",
         TimeMs(repetitions, [&] {
           sink += rubcont::ComputeAnalyticCurve(p, rubcont::CircularMode::kMode1, options).transitions.size();
         }),
         options.precession_points);
  Report("both modes + natural frequencies (ComputeAnalytic)",
         TimeMs(repetitions, [&] { sink += rubcont::ComputeAnalytic(p, options).mode2.transitions.size(); }),
         2 * options.precession_points);
  Report("one point with amplitudes (SolveCircularOrbit) x 4000",
         TimeMs(repetitions, [&] {
           for (int i = 0; i < options.precession_points; ++i)
             sink += rubcont::SolveCircularOrbit(p, rubcont::CircularMode::kMode1, 6.0 + 0.3 * i)
                         .rotor_amplitude.size();
         }),
         options.precession_points);
  return sink == 0 ? 1 : 0;  // keeps the work from being optimized away
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("analytic_bench", [&] { return Run(argc, argv); });
}
