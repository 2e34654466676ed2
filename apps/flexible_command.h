// `rubcont flexible SCENE`: level L4 on a two-point scene (studies/flexible_thesis.h). The shaft
// sections are the scene's [flexible] ones, or, when it has none, those identified against the
// thesis's Tables 2–3 (NLopt; that geometry does not depend on the scene); the scene's rotor and
// stator are built from them
// (models/flexible.h: Timoshenko elements, Craig–Bampton with the contacts physical, `modes`
// fixed-interface modes, gyroscopic moments unless --no-gyroscopic), and the L1 branch sets of the
// rigid and the flexible model are compared point by point.
//
// HDF5 layout (written atomically; default results/<scene>/flexible.h5): root attributes as every
// result (scene_toml, level "L4", …); /flexible attributes modes, elements, gyroscopic,
// rotor_outer_diameter, rotor_inner_diameter, stator_outer_diameter, stator_inner_diameter [m],
// fit_objective, fit_evaluations, fit_message, rigid_seconds, flexible_seconds, coordinates;
// datasets table_case (A, B, C, stator), table_hz [4 × 3] and table_damping_ratio [4 × 3] (the
// fitted models' bounce, pitch, first bending), thesis_hz, thesis_damping_ratio (Tables 2–3);
// points: pattern, label, rigid_rpm, rigid_hz, flexible_rpm, flexible_hz (NaN: no match).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct FlexibleRequest {
  std::string scene_file;
  // Default: the scene's [flexible] values, or 4 modes with gyroscopic moments when it has none.
  std::optional<int> modes;        // fixed-interface modes kept (1 … 40)
  std::optional<bool> gyroscopic;
  std::optional<std::string> out_file;
  bool quiet = false;
};

int FlexibleCommand(const FlexibleRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
