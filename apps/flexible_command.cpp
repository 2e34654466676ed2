#include "apps/flexible_command.h"

#include <array>
#include <filesystem>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/guarded.h"
#include "apps/plan_check.h"
#include "apps/hdf5_file.h"
#include "apps/level.h"
#include "apps/models.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "studies/flexible_thesis.h"

namespace rubcont {
namespace {

}  // namespace

int FlexibleCommand(const FlexibleRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(request.scene_file);
    WarnUnitMistakes(scene, err);
    if (!scene.flexible.RotorUniform() || !scene.flexible.StatorUniform()) {
      // Tables 2–3 compare the three cases on one pair of uniform sections; listed shafts and
      // matrices are one machine's (their rigid-versus-flexible L1 points: `rubcont branches`
      // with and without [flexible]).
      throw std::invalid_argument(fmt::format(
          "[flexible] in scene {} {}: rubcont flexible fits and evaluates uniform "
          "sections (flexible.rotor_outer_diameter, …) on the thesis's Tables 2–3; run rubcont "
          "branches on the scene for its L4 branch set", scene.name,
          scene.flexible.matrices.enabled ? "gives its structure's matrices ([flexible.matrices])"
                                          : "lists its shafts"));
    }
    Scene rigid_scene = scene;
    rigid_scene.flexible.enabled = false;
    const TwoPointParams& params = TwoPointParamsOf(rigid_scene, "rubcont flexible");
    const int modes = request.modes.value_or(scene.flexible.enabled ? scene.flexible.modes : 4);
    const bool gyroscopic =
        request.gyroscopic.value_or(scene.flexible.enabled ? scene.flexible.gyroscopic : true);
    if (modes < 1 || modes > 40) {
      throw std::invalid_argument(
          fmt::format("--modes = {}: must be 1 … 40 (fixed-interface modes kept)", modes));
    }
    const SteadyClock::time_point start = SteadyClock::now();
    ThesisGeometryFit fit;
    if (scene.flexible.enabled) {
      const FlexibleRubModel from_scene = FlexibleModelOf(scene);
      ThesisGeometry geometry;
      geometry.rotor = from_scene.beams.shafts[0].elements.front();
      geometry.stator = from_scene.beams.shafts[1].elements.front();
      geometry.elements = scene.flexible.elements;
      fit = EvaluateThesisGeometry(geometry, ThesisCases());
      fit.message += " (the scene's [flexible])";
    } else {
      if (!request.quiet) fmt::print(err, "rubcont: [flexible] fitting the shafts to the thesis's Tables 2–3\n");
      fit = FitThesisGeometry(ThesisCases());
    }
    FlexibleRubModel model = fit.geometry.Model(params, modes);
    model.modal_damping = scene.flexible.enabled ? scene.flexible.modal_damping : 0.0;
    model.gyroscopic = gyroscopic;
    const RubStructure flexible = BuildFlexibleRub(model).structure;
    if (!request.quiet) {
      fmt::print(err, "rubcont: [flexible] {}; L1 branch sets, rigid and flexible ({} coordinates)\n",
                 fit.message, flexible.Coordinates());
    }
    const FlexibilityEffect effect = CompareRigidFlexible(
        StructureOf(rigid_scene), flexible, FrictionLawOf(scene), BranchOptionsOf(scene));

    const std::filesystem::path file = request.out_file
                                           ? std::filesystem::path(*request.out_file)
                                           : std::filesystem::path("results") / scene.name / "flexible.h5";
    PrepareToWrite(file);
    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(Level::kL4));
    const std::string g = "/flexible";
    writer.CreateGroup(g);
    writer.SetAttribute(g, "modes", static_cast<double>(modes));
    writer.SetAttribute(g, "elements", static_cast<double>(fit.geometry.elements));
    writer.SetAttribute(g, "gyroscopic", gyroscopic ? "yes" : "no");
    writer.SetAttribute(g, "rotor_outer_diameter", fit.geometry.rotor.outer_diameter);
    writer.SetAttribute(g, "rotor_inner_diameter", fit.geometry.rotor.inner_diameter);
    writer.SetAttribute(g, "stator_outer_diameter", fit.geometry.stator.outer_diameter);
    writer.SetAttribute(g, "stator_inner_diameter", fit.geometry.stator.inner_diameter);
    writer.SetAttribute(g, "fit_objective", fit.objective);
    writer.SetAttribute(g, "fit_evaluations", static_cast<double>(fit.evaluations));
    writer.SetAttribute(g, "fit_message", fit.message);
    writer.SetAttribute(g, "rigid_seconds", effect.rigid_seconds);
    writer.SetAttribute(g, "flexible_seconds", effect.flexible_seconds);
    writer.SetAttribute(g, "coordinates", static_cast<double>(effect.flexible_coordinates));
    const ThesisTableTargets thesis = ThesisTables();
    const std::array<const ThreeModes*, 4> ours = {&fit.pinned[0], &fit.pinned[1], &fit.pinned[2],
                                                   &fit.stator};
    const std::array<const ThreeModes*, 4> theirs = {&thesis.pinned[0], &thesis.pinned[1],
                                                     &thesis.pinned[2], &thesis.stator};
    Matrix hz(4, 3), zeta(4, 3), thesis_hz(4, 3), thesis_zeta(4, 3);
    for (Index r = 0; r < 4; ++r) {
      for (Index c = 0; c < 3; ++c) {
        hz(r, c) = ours[r]->hz[c];
        zeta(r, c) = ours[r]->damping_ratio[c];
        thesis_hz(r, c) = theirs[r]->hz[c];
        thesis_zeta(r, c) = theirs[r]->damping_ratio[c];
      }
    }
    const std::vector<std::string> rows = {"A pinned", "B pinned", "C pinned", "stator"};
    writer.WriteStrings(g + "/table_case", rows);
    writer.WriteMatrix(g + "/table_hz", hz);
    writer.WriteMatrix(g + "/table_damping_ratio", zeta);
    writer.WriteMatrix(g + "/thesis_hz", thesis_hz);
    writer.WriteMatrix(g + "/thesis_damping_ratio", thesis_zeta);
    std::vector<std::string> pattern, label;
    std::vector<double> rigid_rpm, rigid_hz, flexible_rpm, flexible_hz;
    for (const MovedPoint& p : effect.points) {
      pattern.push_back(p.branch_pattern);
      label.push_back(p.label);
      rigid_rpm.push_back(p.rigid_rpm);
      rigid_hz.push_back(p.rigid_hz);
      flexible_rpm.push_back(p.found ? p.flexible_rpm : kNaN);
      flexible_hz.push_back(p.found ? p.flexible_hz : kNaN);
    }
    writer.WriteStrings(g + "/pattern", pattern);
    writer.WriteStrings(g + "/label", label);
    writer.WriteDoubles(g + "/rigid_rpm", rigid_rpm);
    writer.WriteDoubles(g + "/rigid_hz", rigid_hz);
    writer.WriteDoubles(g + "/flexible_rpm", flexible_rpm);
    writer.WriteDoubles(g + "/flexible_hz", flexible_hz);
    writer.Commit();

    fmt::print(out, "scene {} from {}\n[flexible] L4: {}\n", scene.name, scene.source, fit.message);
    fmt::print(out, "  {:<9} {:>22} {:>22} {:>24}   (ours / thesis, Hz; damping ratio)\n", "",
               "bounce", "pitch", "first bending");
    for (Index r = 0; r < 4; ++r) {
      fmt::print(out, "  {:<9}", rows[static_cast<std::size_t>(r)]);
      for (Index c = 0; c < 3; ++c) {
        fmt::print(out, " {:>7.1f}/{:<7.1f} {:.3f}/{:.3f}", hz(r, c), thesis_hz(r, c), zeta(r, c),
                   thesis_zeta(r, c));
      }
      fmt::print(out, "\n");
    }
    fmt::print(out,
               "  L1 branch sets: rigid {} coordinates in {:.2f} s, flexible {} ({} modes, gyroscopic "
               "{}) in {:.2f} s; each special point, rigid → flexible:\n",
               effect.rigid_coordinates, effect.rigid_seconds, effect.flexible_coordinates,
               modes, gyroscopic ? "on" : "off", effect.flexible_seconds);
    for (const MovedPoint& p : effect.points) {
      if (p.found) {
        fmt::print(out, "    {:<10} {:<26} {:8.3f} rpm {:8.3f} Hz → {:8.3f} rpm {:8.3f} Hz ({:+.3f} rpm, {:+.3f} Hz)\n",
                   p.branch_pattern, p.label, p.rigid_rpm, p.rigid_hz, p.flexible_rpm, p.flexible_hz,
                   p.flexible_rpm - p.rigid_rpm, p.flexible_hz - p.rigid_hz);
      } else {
        fmt::print(out, "    {:<10} {:<26} {:8.3f} rpm {:8.3f} Hz → none (of its kind within 10 % of its "
                        "speed, a Hopf point's within a factor 1.5 of its frequency)\n",
                   p.branch_pattern, p.label, p.rigid_rpm, p.rigid_hz);
      }
    }
    fmt::print(out, "  {:.1f} s wall\nwrote {}\n", SecondsSince(start), file.string());
    return kExitSuccess;
  });
}

}  // namespace rubcont
