// Uses one header of every library folder through the installed package: a scene (apps), its
// closed form (models, L0), its rotating waves (waves, L1) and the options of a sweep (sweeps).
// Prints the Mode 1 whirl → whip transition of the closed form and of the branches.
#include <cstdio>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "continuation/branch.h"
#include "models/analytic.h"
#include "models/units.h"
#include "shooting/shooting.h"
#include "solvers/newton.h"
#include "studies/jump_prediction.h"
#include "sweeps/rub_sweep.h"
#include "waves/rotating_wave_branches.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer SCENE.toml\n");
    return 2;
  }
  const rubcont::Scene scene = rubcont::LoadScene(argv[1]);
  const rubcont::AnalyticResult analytic =
      rubcont::ComputeAnalytic(scene.two_point, rubcont::AnalyticOptionsOf(scene));
  for (const rubcont::Transition& t : analytic.mode1.transitions) {
    if (t.type == rubcont::TransitionType::kMuCrossing && t.direction > 0) {
      std::printf("closed form: Mode 1 whirl -> whip at %.6f Hz\n", t.precession_hz);
      break;
    }
  }
  const std::vector<rubcont::RotatingWaveBranch> branches = rubcont::ComputeRotatingWaveBranches(
      rubcont::StructureOf(scene), rubcont::FrictionLawOf(scene), rubcont::BranchOptionsOf(scene));
  for (const rubcont::RotatingWaveBranch& b : branches) {
    for (std::size_t i = 0; i < b.branch.special_points.size(); ++i) {
      const rubcont::SpecialPoint& p = b.branch.special_points[i];
      if (p.type == rubcont::SpecialPointType::kEvent &&
          p.label.find("stick to slip") != std::string::npos) {
        std::printf("branches: %s %s at %.6f rpm, %.6f Hz\n", b.name.c_str(), p.label.c_str(),
                    rubcont::RadPerSecondToRpm(p.lambda), b.SpecialPrecessionHz(i));
        return 0;
      }
    }
  }
  std::fprintf(stderr, "no stick-to-slip event found\n");
  return 1;
}
