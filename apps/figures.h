// Figures: the executable writes the HDF5 file, then runs a plotting script from plots/ on it with
// the system Python (matplotlib and h5py from Debian). Figures are a convenience on top of the
// data: when Python, matplotlib or the script is missing, or the script fails, the result is a
// warning and the HDF5 file stays — data is never lost for a figure.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

namespace rubcont {

// Where the plotting scripts are, first match wins:
//   1. $RUBCONT_PLOTS_DIR;
//   2. <executable>/../share/rubcont/plots (an installed rubcont, relocatable);
//   3. <source tree>/plots (a build tree; the path is fixed at build time).
std::filesystem::path PlotsDirectory();

// $RUBCONT_PYTHON, else /usr/bin/python3 (not the python3 on PATH: that may be a pyenv without
// the Debian modules).
std::string PythonInterpreter();

struct FigureOutcome {
  bool made = false;
  std::string warning;  // why not, when !made
};

// Runs `<python> <plots>/<script> <h5_file> <out_dir>` and waits for it. Never throws for a
// missing interpreter or a failing script (see FigureOutcome).
FigureOutcome MakeFigures(const std::string& script, const std::filesystem::path& h5_file,
                          const std::filesystem::path& out_dir);

// MakeFigures into the directory of `h5_file` (or "."), then "wrote figures (<script>) in <dir>" on
// `out`, or the warning on `err` ("rubcont: warning: ...").
void DrawFigures(const std::string& script, const std::filesystem::path& h5_file, std::ostream& out,
                 std::ostream& err);

}  // namespace rubcont
