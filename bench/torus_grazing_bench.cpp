// Experiment (not part of the test suite): how far a torus family's located grazing moves with the
// test's grid and with the map that carries it (InvariantCircleProblem::SetGrazingTests). For the
// last two tori of a family in a result file (the grazing torus and the one before it), the rub's
// grazing tests (RubTorusGrazing) are evaluated
//   default  the family's map (the scene's Gauss mesh over one period), 4N starts × 4 samples per
//            collocation step — the values the engine located the zero of;
//   dense    the same map, 8N starts × 8 samples per step;
//   fine     Gauss on twice the mesh, 8N × 4 samples per (finer) step;
//   bdf      CVODES BDF (order ≤ 5) at 1e-10 as the map, 8N starts × 3200 … instants per period
//            (the default grid's instant count).
// Each test's value at the grazing torus, over its change between the two tori, is its speed's
// shift [rpm] to first order: the located zero's sensitivity to the grid and to the map.
// Usage: torus_grazing_bench SCENE RESULT_H5 GROUP     (from the repository root), e.g.
//   build-dev/bench/torus_grazing_bench scenes/thesis_C_c_tori.toml
//     results/thesis_C_c_tori/thesis_C_c_tori.h5 tori/transient_up   (one line)
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/units.h"
#include "shooting/invariant_circle.h"
#include "shooting/rub_tori.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

int Main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: torus_grazing_bench SCENE RESULT_H5 GROUP\n");
    return 2;
  }
  const Scene scene = LoadScene(argv[1]);
  const ResultReader file(argv[2]);
  const std::string group = argv[3];
  const RubStructure structure = StructureOf(scene);
  const RubTorusOptions options = TransientTorusOptionsOf(scene);
  const int harmonics = static_cast<int>(file.ReadDoubleAttribute(group, "harmonics"));
  const CircleCoordinates coordinates =
      file.ReadStringAttribute(group, "circle_coordinates") == "chart" ? CircleCoordinates::kChart
                                                                       : CircleCoordinates::kState;
  const double frame_rate =
      HzToRadPerSecond(file.ReadDoubleAttribute(group, "frame_precession_hz"));
  const Matrix unknowns = file.ReadMatrix(group + "/unknowns");
  const std::vector<double> speeds = file.ReadDoubles(group + "/speed_rpm");
  const Index last = unknowns.rows() - 1;
  if (last < 1) {
    std::fprintf(stderr, "%s: fewer than two tori\n", group.c_str());
    return 1;
  }
  const std::vector<TorusGrazing> tests = RubTorusGrazing(structure);
  std::printf("# %s, %s: tori at %.6f and %.6f rpm (K = %d, %s); the rub's grazing tests [nm]\n",
              argv[2], group.c_str(), speeds[static_cast<std::size_t>(last - 1)],
              speeds[static_cast<std::size_t>(last)], harmonics, ToString(coordinates));

  struct Variant {
    const char* name;
    IntegratorOptions integrator;
    int starts, samples;
  };
  IntegratorOptions fine = options.tori.integrator;
  fine.collocation_steps *= 2;
  IntegratorOptions bdf;
  bdf.relative_tolerance = bdf.absolute_tolerance = 1e-10;
  bdf.max_steps = 20000000;
  const std::vector<Variant> variants{
      {"default", options.tori.integrator, 4, 4},
      {"dense", options.tori.integrator, 8, 8},
      {"fine", fine, 8, 4},
      // BDF's grid: 16 · samples instants per period; 200 gives the default grid's 3200 on 800.
      {"bdf", bdf, 8, static_cast<int>(options.tori.integrator.collocation_steps * 4 / 16)}};
  for (const Variant& v : variants) {
    const double cpu0 = ProcessCpuSeconds();
    auto frame =
        std::make_shared<RubRotatingFrame>(structure, frame_rate, RpmToRadPerSecond(speeds.back()));
    InvariantCircleProblem problem(frame, harmonics, OrbitKind::kRelative, v.integrator,
                                   coordinates);
    problem.SetGrazingTests(tests);
    problem.SetGrazingGrid(v.starts, v.samples);
    Vector at[2];
    for (int k = 0; k < 2; ++k) {
      const Index row = last - 1 + k;
      at[k] = problem.TestFunctions(unknowns.row(row).transpose(),
                                    RpmToRadPerSecond(speeds[static_cast<std::size_t>(row)]));
    }
    std::printf("%-8s %3d starts per point, %5ld instants per period (%.1f s CPU)\n", v.name,
                v.starts, static_cast<long>(problem.GrazingSamples()), CpuSecondsSince(cpu0));
    const double dspeed = speeds.back() - speeds[static_cast<std::size_t>(last - 1)];
    for (std::size_t t = 0; t < tests.size(); ++t) {
      const auto i = static_cast<Index>(t);
      const double slope = (at[1](i) - at[0](i)) / dspeed;
      std::printf("  %-18s %12.4f %12.4f   zero at %+.5f rpm from the last torus\n",
                  tests[t].name.c_str(), 1e9 * at[0](i), 1e9 * at[1](i), -at[1](i) / slope);
    }
  }
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("torus_grazing_bench", [&] { return rubcont::Main(argc, argv); });
}
