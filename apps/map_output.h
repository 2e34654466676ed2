// Hysteresis maps in result files (layout: apps/map_command.h) and the default parameter ranges.
#pragma once

#include <utility>

#include "apps/hdf5_file.h"
#include "studies/hysteresis_map.h"

namespace rubcont {

// The default η range for a parameter whose scene value is `base`: [0.5, 1.5]·base (friction,
// damping, stiffness; [0, 2·typical] when base is 0) and [0.75, 1.35]·base for rci_ratio (the
// thesis's RCI pairs 100/125 and 125/100 are ratios 1.25 and 0.8).
std::pair<double, double> DefaultMapRange(DesignParameter parameter, double base);

// Writes the map under /maps/<parameter>/.
void WriteHysteresisMap(ResultWriter& writer, const HysteresisMap& map, FrictionLawKind law);

}  // namespace rubcont
