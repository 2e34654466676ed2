// The "orbits" stage of `rubcont run` for the textbook models (Duffing, Stuart–Landau, van der
// Pol): their periodic orbits continued in the model's parameter by shooting, with Floquet
// stability and special points (shooting/orbit_branches.h), written to /branches/periodic_orbits
// (apps/orbit_output.h) and summarized on `out`.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "apps/hdf5_file.h"
#include "apps/scene.h"

namespace rubcont {

// Appends a line to `failures` when the branch ends on a numerical failure or cannot start.
// `progress` receives one line per finished run (stderr, unless --quiet).
void RunOrbitsStage(const Scene& scene, ResultWriter& writer,
                    const std::function<void(const std::string&)>& progress, std::ostream& out,
                    std::vector<std::string>& failures);

}  // namespace rubcont
