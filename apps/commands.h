// The rubcont commands, independent of argument parsing (main.cpp holds CLI11). Each returns the
// process exit code and writes results to `out` (stdout) and progress, warnings and errors to
// `err` (stderr).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

constexpr int kExitSuccess = 0;
constexpr int kExitFailure = 1;   // numerical failure or I/O error, with the reason on stderr
constexpr int kExitBadInput = 2;  // bad scene or bad arguments

struct RunRequest {
  std::optional<std::string> scene_file;  // none: the built-in default scene
  std::string out_dir = "results";        // results go to <out_dir>/<scene name>/
  bool quiet = false;                     // no progress on stderr (warnings and errors still)
  bool resume = false;                    // sweeps continue from their checkpoints, if any
  bool fresh = false;                     // sweeps start again, discarding their checkpoints
  bool figures = true;                    // draw the figures after the HDF5 file (--no-figures)
  std::string figure_format = "png";      // their file format: png, pdf or svg (--format)
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
};

// `rubcont run [SCENE]`: every stage the scene lists, into <out_dir>/<name>/<name>.h5 + figures.
int RunCommand(const RunRequest& request, std::ostream& out, std::ostream& err);

struct AnalyticRequest {
  std::string scene_file;
  std::optional<std::string> out_file;  // none: results/<scene name>/analytic.h5
  bool quiet = false;
  bool figures = true;  // draw the figures after the HDF5 file
  std::string figure_format = "png";  // their file format: png, pdf or svg (--format)
};

// `rubcont analytic SCENE`: the L0 stage only; figures next to the HDF5 file.
int AnalyticCommand(const AnalyticRequest& request, std::ostream& out, std::ostream& err);

struct SweepRequest {
  std::string scene_file;
  std::string direction = "both";       // "up", "down" or "both" (up first)
  std::optional<std::string> out_file;  // none: results/<scene name>/sweep.h5
  bool quiet = false;
  // Continue from `<out stem>.<direction>.checkpoint.h5` (written after every finished speed)
  // instead of starting again; a checkpoint of another scene or settings is an error.
  bool resume = false;
  // Start again although a checkpoint exists (it is overwritten). With neither flag, an existing
  // checkpoint is refused (exit 2): an interrupted sweep's finished speeds are never lost unasked.
  bool fresh = false;
  bool figures = true;  // draw the figures after the HDF5 file (--no-figures)
  std::string figure_format = "png";  // their file format: png, pdf or svg (--format)
  bool force = false;   // run a plan the plan check refuses (apps/plan_check.h), with a warning
};

// `rubcont sweep SCENE`: the level-L3 time-marching sweeps of [analysis.sweep] (Kumar 2010 §3.5);
// figures next to the HDF5 file.
int SweepCommand(const SweepRequest& request, std::ostream& out, std::ostream& err);
// `rubcont branches SCENE`: the L0 and L1 stages (default file results/<name>/branches.h5).
int BranchesCommand(const AnalyticRequest& request, std::ostream& out, std::ostream& err);

// `rubcont scene check FILE`: validates and prints the resolved values with units.
int SceneCheckCommand(const std::string& file, std::ostream& out, std::ostream& err);

// `rubcont scene matrices FILE --out PATH`: writes the full matrices of a scene's flexible
// structure (apps/structure_file.h: PATH.h5, or a directory of .mtx files) and prints the
// [flexible.matrices] section that loads them back.
int SceneMatricesCommand(const std::string& file, const std::string& out_path, std::ostream& out,
                         std::ostream& err);

// Refuses (std::invalid_argument: exit 2) to start over `checkpoint`, the finished speeds of an
// interrupted `what` ("up sweep", "lifetime study"), when neither --resume nor --fresh is given:
// they are never lost unasked.
void RefuseUnaskedCheckpoint(const std::filesystem::path& checkpoint, const std::string& what, bool resume,
                             bool fresh);

// `rubcont scene keys`: the key reference (markdown) that scenes/README.md embeds.
int SceneKeysCommand(std::ostream& out);

}  // namespace rubcont
