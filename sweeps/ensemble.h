// Ensembles of transients (level L3): N perturbed copies of one state, each marched through the
// same schedule, in parallel over the cores. What a single sweep cannot say where the motion is
// chaotic or a state is only slightly unstable — how long a state lasts — becomes a distribution.
//
// Copy i starts from x0 + perturbation · scale ∘ ξ_i, where scale = OdeSystem::StateScale() and
// ξ_i is a standard normal vector drawn from a generator seeded with seed + i (std::mt19937_64 and
// the Box–Muller transform written here, so that the draws are the same with every standard
// library); copy 0 is perturbed too. Each copy is a SweepStepper over `sweep` (its schedule, its
// windows, its integrators) with its own system and observables from the factories, so copies
// share nothing and the result does not depend on the number of threads.
//
// The lifetime of a state is read off the copies' points by the model's side (e.g. the rub's
// regimes, sweeps/rub_sweep.h): here only the points are produced.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sweeps/sweep.h"

namespace rubcont {

struct EnsembleOptions {
  int copies = 16;              // ≥ 1
  double perturbation = 1e-6;   // ≥ 0, in units of each state's scale
  std::uint64_t seed = 1;
  int threads = 0;              // ≥ 0; 0: std::thread::hardware_concurrency()
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const EnsembleOptions& options);

struct EnsembleCopy {
  Vector start;                   // the perturbed initial state
  std::vector<SweepPoint> points; // as SweepStepper::points(); a failed copy ends with the failure
  bool failed = false;
  double cpu_seconds = 0.0;       // CPU time of the thread that ran it, for this copy
};

using SystemFactory = std::function<std::unique_ptr<OdeSystem>()>;
using ObservablesFactory = std::function<std::unique_ptr<SweepObservables>(OdeSystem&)>;
// Called (from the worker threads, serialized) after each finished copy: copies done, total.
using EnsembleProgress = std::function<void(int done, int total)>;

// Runs the copies. `sweep` is validated (as SweepStepper does) before any thread starts.
std::vector<EnsembleCopy> RunEnsemble(const SystemFactory& make_system,
                                      const ObservablesFactory& make_observables,
                                      const SweepOptions& sweep, const Vector& x0,
                                      const EnsembleOptions& options,
                                      const EnsembleProgress& progress = {});

// The perturbed start of copy `index` (what RunEnsemble uses).
Vector PerturbedStart(const Vector& x0, const Vector& scale, const EnsembleOptions& options,
                      int index);

}  // namespace rubcont
