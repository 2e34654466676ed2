// Figures: the executable writes the HDF5 file, then runs a module of the Python package
// rubcont.plots (python/rubcont/plots/) on it with the system Python (matplotlib and h5py from
// Debian): `python3 -m rubcont.plots.<module> FILE.h5 OUTDIR --format png|pdf|svg`, with the
// package's directory put first on PYTHONPATH. The same modules draw the figures of the Python
// objects (Branch.plot(), ...): one implementation. Figures are a convenience on top of the data:
// when Python, matplotlib or the module is missing, or the module fails, the result is a warning
// and the HDF5 file stays — data is never lost for a figure.
#pragma once

#include <array>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>

namespace rubcont {

// The file formats a figure can be written in (--format), the first the default.
inline constexpr std::array<std::string_view, 3> kFigureFormats = {"png", "pdf", "svg"};

// The directory that holds the package rubcont/ (rubcont/plots/*.py), first match wins:
//   1. $RUBCONT_PYTHON_DIR;
//   2. <executable>/../<the Python install directory> (an installed rubcont, relocatable; the
//      package's pure-Python files are installed with or without the compiled module);
//   3. <source tree>/python (a build tree or a fresh clone; the path is fixed at build time).
std::filesystem::path PythonPackageDirectory();

// $RUBCONT_PYTHON, else /usr/bin/python3 (not the python3 on PATH: that may be a pyenv without
// the Debian modules).
std::string PythonInterpreter();

struct FigureOutcome {
  bool made = false;
  std::string warning;  // why not, when !made
};

// Runs rubcont.plots.<module> on `h5_file` into `out_dir` in `format` and waits for it. Never
// throws for a missing interpreter, a failing module or an unknown format (see FigureOutcome).
FigureOutcome MakeFigures(const std::string& module, const std::filesystem::path& h5_file,
                          const std::filesystem::path& out_dir, const std::string& format);

// MakeFigures into the directory of `h5_file` (or "."), then "wrote figures (<module>) in <dir>"
// on `out`, or the warning on `err` ("rubcont: warning: ...").
void DrawFigures(const std::string& module, const std::filesystem::path& h5_file,
                 const std::string& format, std::ostream& out, std::ostream& err);

}  // namespace rubcont
