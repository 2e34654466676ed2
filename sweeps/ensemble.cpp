#include "sweeps/ensemble.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <random>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/parallel.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

// A uniform draw in (0, 1) from 53 random bits (never 0, so that log() is finite).
double Uniform(std::mt19937_64& generator) {
  return (static_cast<double>(generator() >> 11) + 0.5) * 0x1.0p-53;
}

}  // namespace

void Validate(const EnsembleOptions& o) {
  auto fail = [](const char* field, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("EnsembleOptions.{} = {}: {}", field, value, rule));
  };
  if (o.copies < 1) fail("copies", o.copies, "must be at least 1");
  if (!(o.perturbation >= 0.0) || !std::isfinite(o.perturbation)) {
    fail("perturbation", o.perturbation, "must be finite and non-negative");
  }
  if (o.threads < 0) fail("threads", o.threads, "must be non-negative (0: one per core)");
}

Vector PerturbedStart(const Vector& x0, const Vector& scale, const EnsembleOptions& options,
                      int index) {
  std::mt19937_64 generator(options.seed + static_cast<std::uint64_t>(index));
  Vector x = x0;
  for (Index i = 0; i < x.size(); i += 2) {
    // Box–Muller: two independent standard normal draws per pair of uniforms.
    const double radius = std::sqrt(-2.0 * std::log(Uniform(generator)));
    const double angle = kTwoPi * Uniform(generator);
    x(i) += options.perturbation * scale(i) * radius * std::cos(angle);
    if (i + 1 < x.size()) x(i + 1) += options.perturbation * scale(i + 1) * radius * std::sin(angle);
  }
  return x;
}

std::vector<EnsembleCopy> RunEnsemble(const SystemFactory& make_system,
                                      const ObservablesFactory& make_observables,
                                      const SweepOptions& sweep, const Vector& x0,
                                      const EnsembleOptions& options,
                                      const EnsembleProgress& progress) {
  Validate(options);
  Validate(sweep);
  const Vector scale = make_system()->StateScale();
  if (scale.size() != x0.size()) {
    throw std::invalid_argument(fmt::format("RunEnsemble: x0 has {} entries, the system {}",
                                            x0.size(), scale.size()));
  }
  std::vector<EnsembleCopy> copies(static_cast<std::size_t>(options.copies));
  std::mutex mutex;  // guards `done` and the progress callback
  int done = 0;
  ParallelFor(options.copies, ThreadsFor(options.threads), [&](int i) {
    EnsembleCopy& copy = copies[static_cast<std::size_t>(i)];
    const double cpu_start = ThreadCpuSeconds();
    copy.start = PerturbedStart(x0, scale, options, i);
    std::unique_ptr<OdeSystem> system = make_system();
    std::unique_ptr<SweepObservables> observables = make_observables(*system);
    SweepStepper stepper(*system, *observables, sweep, copy.start);
    while (stepper.Step() == SweepStepOutcome::kContinue) {
    }
    copy.failed = stepper.Failed();
    copy.points = stepper.points();
    copy.cpu_seconds = ThreadCpuSeconds() - cpu_start;
    std::lock_guard<std::mutex> lock(mutex);
    ++done;
    if (progress) progress(done, options.copies);
  });
  return copies;
}

}  // namespace rubcont
