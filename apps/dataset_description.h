// What a result file's dataset holds, by its name: the unit of a physical quantity, or the codes of
// an integer flag, or neither. The writer (apps/hdf5_file.h) attaches it to every numeric dataset
// it writes, so a file describes itself without the documentation: a `units` attribute ("rpm",
// "Hz", "N", "m", "m/s", "s", "1/s", "degree", "rad"; "1" for a dimensionless number or a code),
// and `flag_values` / `flag_meanings` (the CF conventions' names; meanings are blank-separated
// words) on coded integers such as `stable` (−1 not computed, 0 unstable, 1 stable) and
// `mode_<c>` (0 free, 1 stick, 2 slip+, 3 slip−). Text datasets get none.
//
// One table (dataset_description.cpp), matched on the dataset's name (the last path component;
// the per-contact suffix _left, _right or _contact is part of the pattern) and, for a few names,
// its place ("period" is in seconds in the rub's /orbits and /tori, in the model's own time in a
// textbook scene's /branches/periodic_orbits). Every name a committed result holds is in it:
// tests/apps/dataset_description_test.cpp walks results/*.h5 and fails on an unknown one, so a
// new dataset is described when it is added.
#pragma once

#include <string>
#include <vector>

#include "waves/rotating_wave_parameters.h"

namespace rubcont {

struct DatasetDescription {
  enum class Kind {
    kUnknown,        // not in the table: a dataset added without its description
    kUnit,           // a physical quantity in `unit`
    kDimensionless,  // a ratio, count, scaled quantity, text, or columns of mixed units
    kFlag,           // a coded integer: flag_values and flag_meanings
    kContext,        // the unit depends on the run (a map's η): the writer's caller sets it
  };
  Kind kind = Kind::kUnknown;
  std::string unit;                   // kUnit
  std::vector<int> flag_values;       // kFlag, ascending
  std::string flag_meanings;          // kFlag: one word per value, blank-separated
};

// The description of the dataset at the absolute HDF5 path `path` ("/branches/branch2/speed_rpm").
DatasetDescription DescribeDataset(const std::string& path);

// The `units` of a map's η (kContext): the parameter's unit (UnitOf) as a units attribute:
// "1" for a ratio, "N s/m" for a damping, "N/m" for a stiffness.
std::string DesignParameterUnits(DesignParameter parameter);

}  // namespace rubcont
