// Experiment (not part of the test suite): is case C's whip at a speed locked, and on how many
// modulation periods? The sweep's settled transient (as transient_tori_bench's), 4 s more of
// approach and the modulation search (shooting/modulated_orbit.h, SearchModulation) under the
// integrator given, then PERIODS modulation periods of the co-rotating flow: the section of one
// period, x_k = x(kT). For each q ≤ 64 the distance between points q apart, the later turned about
// the axis by the first contact gap's turn between them (the symmetry group's drift taken out),
// max over the states scaled by StateScale, median over k: a relative periodic orbit of q periods
// (locked at p:q) comes back to its integration's error at q and its multiples; a torus or chaos
// comes back nowhere. The medians of the record's two halves say whether a return holds along it;
// the points' mean turn per period round their centroid is p/q (or 1 − p/q: the plane's
// orientation is the SVD's). A whip integrated too coarsely can wander instead: C(a) at 74 rpm
// under BDF ≤ 2 at 1e-7 (docs/studies/attractors.md).
// Usage: section_return_bench [RPM [PERIODS [CASE [INTEGRATOR [TOLERANCE [SETTLE]]]]]]
// CASE: a, b or c (case C(a), C(b), C(c)); INTEGRATOR: dopri (Dormand–Prince), bdf (CVODES BDF
// ≤ 5) or bdf2 (≤ 2, the torus start's, shooting/modulated_torus.h); TOLERANCE: rtol = atol
// (scaled states); SETTLE: long (LongSettleOptions' BDF ≤ 2 at 1e-6, then the 4 s of approach) or
// rest (the orbits stage's transient with a scene's defaults and explicit_tolerance = 1e-9: 8 s at
// most from rest and a 1 N·s impulse under Dormand–Prince at 1e-9, settled by 0.25 s windows,
// then the approach). At C(a) 74 rpm the two reach different whips (docs/studies/attractors.md).
// Defaults 74, 1000, a, dopri, 1e-9, long.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "models/units.h"
#include "shooting/modulated_orbit.h"
#include "solvers/stopwatch.h"
#include "sweeps/attractor.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

constexpr int kMaxLaps = 64;
constexpr Index kSamplesPerPeriod = 16;

double Median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The orbits stage's transient (apps/stage_options.cpp, TransientSweepOptionsOf) with
// [analysis.sweep]'s defaults and explicit_tolerance = 1e-9.
SweepOptions FromRestOptions(double omega) {
  SweepOptions options;
  options.parameters = {omega};
  options.dwell = 8.0;
  options.window = 0.25;
  options.settle_windows = 2;
  options.spectrum_tolerance = 0.05;
  options.frequency_tolerance = 0.25;
  options.analysis_length = 0.5;
  options.sample_rate = 4096.0;
  options.band = 600.0;
  options.peak_side = PeakSide::kNegative;
  options.integrator.method = IntegrationMethod::kDormandPrince;
  options.integrator.relative_tolerance = options.integrator.absolute_tolerance = 1e-9;
  options.integrator.max_steps = 100000000;
  return options;
}

int Main(int argc, char** argv) {
  const double rpm = argc > 1 ? std::atof(argv[1]) : 74.0;
  const int periods = argc > 2 ? std::atoi(argv[2]) : 1000;
  const char case_letter = argc > 3 ? argv[3][0] : 'a';
  const std::string method = argc > 4 ? argv[4] : "dopri";
  const double tolerance = argc > 5 ? std::atof(argv[5]) : 1e-9;
  const std::string settle = argc > 6 ? argv[6] : "long";
  if (settle != "long" && settle != "rest") {
    std::fprintf(stderr, "section_return_bench: SETTLE = %s: must be long or rest\n",
                 settle.c_str());
    return 2;
  }
  if (periods < 2 * kMaxLaps) {
    std::fprintf(stderr, "section_return_bench: PERIODS = %d: must be at least %d\n", periods,
                 2 * kMaxLaps);
    return 2;
  }
  IntegratorOptions integrator;
  if (method == "dopri") {
    integrator.method = IntegrationMethod::kDormandPrince;
  } else if (method == "bdf" || method == "bdf2") {
    integrator.method = IntegrationMethod::kBdf;
    integrator.max_order = method == "bdf2" ? 2 : 0;
  } else {
    std::fprintf(stderr, "section_return_bench: INTEGRATOR = %s: must be dopri, bdf or bdf2\n",
                 method.c_str());
    return 2;
  }
  integrator.relative_tolerance = integrator.absolute_tolerance = tolerance;
  integrator.max_steps = 100000000;
  const RubStructure structure = TwoPointStructure(
      case_letter == 'b' ? ThesisCaseCb() : case_letter == 'c' ? ThesisCaseCc() : ThesisCaseCa());
  const double omega = RpmToRadPerSecond(rpm);
  const double cpu_start = ProcessCpuSeconds();

  const RubSettledSpeed transient = SettleAtSpeed(
      structure, settle == "rest" ? FromRestOptions(omega) : LongSettleOptions(omega), 1.0);
  Vector approached = transient.state;
  {
    RubFixedFrame fixed(structure, omega);
    OdeIntegrator approach(fixed, integrator);
    const IntegrationResult result = approach.Integrate(0.0, transient.state, 4.0, approached);
    if (!result.Succeeded()) {
      throw std::runtime_error("the approach failed: " + result.BriefReport());
    }
  }
  RubRotatingFrame frame(structure, HzToRadPerSecond(transient.precession_hz), omega);
  const ModulationSearch search = SearchModulation(frame, approached, integrator, 4.0, 20000.0);
  if (!search.found) throw std::runtime_error(search.message);
  const double period = search.period;

  const Index count = static_cast<Index>(periods) * kSamplesPerPeriod + 1;
  Matrix samples;
  OdeIntegrator flow(frame, integrator);
  const IntegrationResult sampled = flow.Sample(
      0.0, search.state,
      Vector::LinSpaced(count, 0.0, static_cast<double>(count - 1) * period / kSamplesPerPeriod),
      samples);
  if (!sampled.Succeeded()) throw std::runtime_error("the record failed: " + sampled.BriefReport());
  const Vector scale = frame.StateScale();
  std::vector<Vector> points;
  for (int k = 0; k <= periods; ++k) points.push_back(samples.col(k * kSamplesPerPeriod));
  // The distance from x_k to x_{k+q}, the latter turned back by its gap's turn since x_k.
  auto distance = [&](int k, int q) {
    Vector later = points[static_cast<std::size_t>(k + q)];
    frame.Rotate(-std::arg(FirstContactGap(structure, later) /
                           FirstContactGap(structure, points[static_cast<std::size_t>(k)])),
                 later);
    later -= points[static_cast<std::size_t>(k)];
    return later.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
  };
  struct Return {
    double median, first_half, second_half;
    int laps;
  };
  std::vector<Return> returns;
  const int half = periods / 2;
  for (int q = 1; q <= kMaxLaps; ++q) {
    std::vector<double> first, second;
    for (int k = 0; k + q <= periods; ++k) (k < half ? first : second).push_back(distance(k, q));
    std::vector<double> all = first;
    all.insert(all.end(), second.begin(), second.end());
    returns.push_back({Median(all), Median(first), Median(second), q});
  }
  std::sort(returns.begin(), returns.end(),
            [](const Return& a, const Return& b) { return a.median < b.median; });
  std::printf("C(%c) at %.3f rpm, settled %s, %s at %.0e: T = %.9f s (1/T = %.4f Hz), %d periods "
              "(%.1f s); %.1f s CPU\n",
              case_letter, rpm, settle == "rest" ? "from rest" : "long", method.c_str(), tolerance,
              period, 1.0 / period, periods, periods * period, CpuSecondsSince(cpu_start));
  // The points' turn round their centroid in their principal plane, per period: features that
  // the axis's turn leaves alone (the first complex coordinate's modulus, the others relative to
  // its direction), each by its spread; the mean turn, in (0, 1), is p/q on a p:q locked orbit.
  const Index pairs = samples.rows() / 2;
  Matrix features(periods + 1, 2 * pairs - 1);
  for (int k = 0; k <= periods; ++k) {
    const Vector& x = points[static_cast<std::size_t>(k)];
    const std::complex<double> axis = std::polar(1.0, -std::atan2(x(1), x(0)));
    features(k, 0) = std::hypot(x(0), x(1));
    for (Index i = 1; i < pairs; ++i) {
      const std::complex<double> w = std::complex<double>(x(2 * i), x(2 * i + 1)) * axis;
      features(k, 2 * i - 1) = w.real();
      features(k, 2 * i) = w.imag();
    }
  }
  features.rowwise() -= features.colwise().mean();
  for (Index j = 0; j < features.cols(); ++j) {
    const double spread = features.col(j).norm();
    if (spread > 0.0) features.col(j) /= spread;
  }
  const Eigen::JacobiSVD<Matrix> svd(features, Eigen::ComputeThinV);
  const Matrix plane = features * svd.matrixV().leftCols(2);
  double turn = 0.0;
  for (int k = 0; k < periods; ++k) {
    const double step =
        std::atan2(plane(k + 1, 1), plane(k + 1, 0)) - std::atan2(plane(k, 1), plane(k, 0));
    turn += step / kTwoPi - std::floor(step / kTwoPi);
  }
  std::printf("  the points' mean turn per period round their centroid: %.6f\n", turn / periods);
  // The section's dimension and pieces (sweeps/attractor.h): a torus's section is curves
  // (dimension 1); on an orbit of q periods the nearest neighbour lies q periods away at the
  // return's distance (C(a)'s 5-lap orbit at 66 rpm: dimension 1.00, 5 pieces). The record's
  // halves each: where they read less than the whole, the points moved between them (C(a)'s
  // torus at 49 rpm, near 3:8: 1.26 and 1.24 against 1.78).
  const SectionDimension section = MeasureSectionDimension(features.transpose());
  const Index middle = features.rows() / 2;
  const double first_half = MeasureSectionDimension(features.topRows(middle).transpose()).dimension;
  const double second_half =
      MeasureSectionDimension(features.bottomRows(features.rows() - middle).transpose()).dimension;
  std::printf("  the section's dimension %.2f (halves %.2f, %.2f; r4 %.2e, r16 %.2e), %d pieces; "
              "the nearest neighbour %.2e away, %.0f periods later (medians)\n",
              section.dimension, first_half, second_half, section.fourth, section.sixteenth,
              section.pieces, section.nearest, section.apart);
  std::printf("  nearest returns (median scaled distance; first half, second half):");
  for (std::size_t i = 0; i < 5; ++i) {
    std::printf(" q = %d: %.2e (%.2e, %.2e)%s", returns[i].laps, returns[i].median,
                returns[i].first_half, returns[i].second_half, i + 1 < 5 ? ";" : "\n");
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("section_return_bench", [&] { return rubcont::Main(argc, argv); });
}
