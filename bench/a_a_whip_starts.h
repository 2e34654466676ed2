// Case A(a) with the tanh law (ε = 1e-3 m/s), its rotating waves at 20–100 rpm (precessions to
// 200 Hz) and the Hopf points where a stable one loses stability: where the benchmarks of A(a)'s
// modulated whip start (whip_family_bench, doubled_whip_bench).
#pragma once

#include <vector>

#include "models/rub_model.h"
#include "models/units.h"
#include "shooting/rub_orbits.h"
#include "solvers/constants.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

struct AaWhipStarts {
  RubStructure structure;
  std::vector<RotatingWaveBranch> branches;
  std::vector<RubHopfStart> starts;  // StableBoundaryHopfPoints: the first is the Mode 1 whirl's
};

inline AaWhipStarts ComputeAaWhipStarts() {
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  AaWhipStarts a{TwoPointStructure(params), {}, {}};
  RotatingWaveBranchOptions wave_options;
  wave_options.search.speed_min = RpmToRadPerSecond(20);
  wave_options.search.speed_max = RpmToRadPerSecond(100);
  wave_options.search.precession_max = kTwoPi * 200;
  a.branches = ComputeRotatingWaveBranches(a.structure, FrictionLawKind::kTanh, wave_options, {});
  a.starts = StableBoundaryHopfPoints(a.branches, a.structure.Coordinates());
  return a;
}

}  // namespace rubcont
