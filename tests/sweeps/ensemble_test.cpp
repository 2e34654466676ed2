#include "sweeps/ensemble.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "models/units.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

// Stuart–Landau from near its unstable origin: the channel is active once r > r_th. The radius
// grows as r(t)² = λ / (1 + (λ/r0² − 1) e^{−2λt}), so it reaches r_th at
// t = ln[(λ/r0² − 1) / (λ/r_th² − 1)] / (2λ).
class RadiusObservables : public SweepObservables {
 public:
  explicit RadiusObservables(double threshold) : threshold_(threshold) {}
  int Channels() const override { return 1; }
  int Measures() const override { return 1; }
  std::string ChannelName(int) const override { return "z"; }
  std::string MeasureName(int) const override { return "radius"; }
  void Observe(double, ConstVectorRef x, SweepObservation& out) override {
    out.signal(0) = std::complex<double>(x(0), x(1));
    out.active[0] = x.norm() > threshold_ ? 1 : 0;
    out.measures(0, 0) = x.norm();
  }

 private:
  double threshold_;
};

constexpr double kLambda = 10.0;
const double kThreshold = 0.5 * std::sqrt(kLambda);

SystemFactory StuartLandau() {
  return [] {
    StuartLandauParams p;
    p.lambda = kLambda;
    p.omega = HzToRadPerSecond(20.0);
    return std::make_unique<StuartLandauOscillator>(p);
  };
}

ObservablesFactory Radius() {
  return [](OdeSystem&) { return std::make_unique<RadiusObservables>(kThreshold); };
}

// Points of 0.1 s (two 0.05 s windows), 2 s in all.
SweepOptions Stretches() {
  SweepOptions o;
  o.parameters.assign(20, kLambda);
  o.window = 0.05;
  o.settle_windows = 1;
  o.dwell = 0.1;
  o.analysis_length = 0.1;
  o.sample_rate = 1024.0;
  o.band = 100.0;
  o.peak_side = PeakSide::kPositive;
  o.integrator.relative_tolerance = o.integrator.absolute_tolerance = 1e-10;
  return o;
}

TEST_CASE("Ensemble copies start from seeded normal perturbations of the state's scale",
          "[ensemble]") {
  EnsembleOptions o;
  o.perturbation = 1e-3;
  o.seed = 7;
  const Vector x0 = Vector::LinSpaced(20000, 0.0, 1.0);
  const Vector scale = Vector::Constant(20000, 2.0);
  const Vector a = PerturbedStart(x0, scale, o, 3);
  CHECK(a == PerturbedStart(x0, scale, o, 3));  // reproducible
  CHECK((a - PerturbedStart(x0, scale, o, 4)).norm() > 0.0);  // copies differ
  const Vector xi = (a - x0) / (o.perturbation * 2.0);
  const double mean = xi.mean();
  const double deviation = std::sqrt((xi.array() - mean).square().mean());
  CHECK(std::abs(mean) < 0.03);       // 4.2 standard errors of the mean (1/√20000)
  CHECK(deviation == Approx(1.0).epsilon(0).margin(0.02));
  o.perturbation = 0.0;
  CHECK(PerturbedStart(x0, scale, o, 5) == x0);
}

TEST_CASE("An ensemble leaves an unstable state when the closed form says, the same on any "
          "number of threads", "[ensemble]") {
  EnsembleOptions o;
  o.copies = 6;
  o.perturbation = 1e-6;
  o.threads = 2;
  int reports = 0;
  const std::vector<EnsembleCopy> copies =
      RunEnsemble(StuartLandau(), Radius(), Stretches(), Vector::Zero(2), o,
                  [&](int done, int total) {
                    ++reports;
                    CHECK(done == reports);
                    CHECK(total == 6);
                  });
  CHECK(reports == 6);
  REQUIRE(copies.size() == 6);
  for (const EnsembleCopy& copy : copies) {
    REQUIRE_FALSE(copy.failed);
    REQUIRE(copy.points.size() == 20);
    CHECK(copy.cpu_seconds > 0.0);
    const double r0 = copy.start.norm();  // Box–Muller: one radius per (x, y) pair
    const double t_reach =
        std::log((kLambda / (r0 * r0) - 1.0) / (kLambda / (kThreshold * kThreshold) - 1.0)) /
        (2.0 * kLambda);
    // The first stretch in which the channel is active ends after t_reach, the one before it
    // ends before.
    double end = 0.0;
    std::size_t first = copy.points.size();
    for (std::size_t i = 0; i < copy.points.size(); ++i) {
      end += copy.points[i].simulated_time;
      if (copy.points[i].channels[0].active_fraction > 0.0) {
        first = i;
        break;
      }
    }
    CAPTURE(r0, t_reach, end);
    REQUIRE(first < copy.points.size());
    CHECK(end >= t_reach);
    CHECK(end - copy.points[first].simulated_time <= t_reach);
    // Active share of that stretch: (end − t_reach)/0.1 s, to a sample.
    CHECK(copy.points[first].channels[0].active_fraction ==
          Approx((end - t_reach) / 0.1).epsilon(0).margin(2.0 / 102.4));
  }
  // Different perturbations, different times; the same copies on one thread, bit for bit.
  CHECK(copies[0].start != copies[1].start);
  o.threads = 1;
  const std::vector<EnsembleCopy> serial =
      RunEnsemble(StuartLandau(), Radius(), Stretches(), Vector::Zero(2), o);
  for (std::size_t c = 0; c < copies.size(); ++c) {
    CHECK(serial[c].start == copies[c].start);
    for (std::size_t i = 0; i < copies[c].points.size(); ++i) {
      CHECK(serial[c].points[i].channels[0].spectrum == copies[c].points[i].channels[0].spectrum);
    }
  }
}

TEST_CASE("Ensemble options and sizes are checked before any copy runs", "[ensemble]") {
  auto message = [](auto change, Vector x0 = Vector::Zero(2)) {
    EnsembleOptions o;
    SweepOptions s = Stretches();
    change(o, s);
    try {
      RunEnsemble(StuartLandau(), Radius(), s, x0, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(message([](EnsembleOptions& o, SweepOptions&) { o.copies = 0; }),
             Contains("EnsembleOptions.copies = 0: must be at least 1"));
  CHECK_THAT(message([](EnsembleOptions& o, SweepOptions&) { o.perturbation = -1.0; }),
             Contains("EnsembleOptions.perturbation = -1"));
  CHECK_THAT(message([](EnsembleOptions& o, SweepOptions&) { o.threads = -2; }),
             Contains("EnsembleOptions.threads = -2"));
  CHECK_THAT(message([](EnsembleOptions&, SweepOptions& s) { s.window = 1.0; }),
             Contains("SweepOptions.dwell"));
  CHECK_THAT(message([](EnsembleOptions&, SweepOptions&) {}, Vector::Zero(3)),
             Contains("x0 has 3 entries"));
}

}  // namespace
}  // namespace rubcont
