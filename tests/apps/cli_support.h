// Running the rubcont executable from tests as a user runs it: a temporary directory, the
// captured exit code, stdout and stderr. Shared by the command-line tests of tests/apps/.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace rubcont::testing {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary directory, removed with everything in it.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("rubcont_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  static inline int counter = 0;
};

inline std::string Slurp(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Python that cannot be found: figures are skipped with a warning (and the tests stay fast).
inline const std::string kNoPython = "RUBCONT_PYTHON=/nonexistent/python3";

// Runs `<env> rubcont <args>` from the repository root (the tests' working directory), with the
// executable from $RUBCONT_BINARY_DIR (default build/).
inline Outcome Rubcont(const std::string& args, const std::string& env = "") {
  const char* binary_dir = std::getenv("RUBCONT_BINARY_DIR");
  const std::string binary = std::string(binary_dir ? binary_dir : "build") + "/rubcont";
  TempDir capture;
  const fs::path out = capture.path / "out", err = capture.path / "err";
  const std::string command =
      env + " " + binary + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(command.c_str());
  Outcome outcome;
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.out = Slurp(out);
  outcome.err = Slurp(err);
  return outcome;
}

// The same without figures.
inline Outcome RubcontNoPython(const std::string& args) { return Rubcont(args, kNoPython); }

// A committed scene's model (its text up to [analysis]) followed by `analysis`: the structure of a
// thesis scene with the tests' own, cheaper analysis.
inline std::string SceneWithAnalysis(const fs::path& scene, const std::string& analysis) {
  const std::string text = Slurp(scene);
  return text.substr(0, text.find("[analysis]")) + analysis;
}

// `rubcont run` of `text`, written as `name`.toml in `dir`, quietly and without figures; the
// results land in dir/name/.
inline Outcome RunQuiet(const TempDir& dir, const std::string& name, const std::string& text) {
  const fs::path scene = dir.path / (name + ".toml");
  std::ofstream(scene) << text;
  return RubcontNoPython("run " + scene.string() + " --quiet --out " + dir.path.string());
}

// Case A(a) in `dir` with a speed-up schedule 40, 44, 48 rpm (the whirl: it rolls from the impulse
// on), 0.75 s per speed.
inline fs::path WhirlScene(const fs::path& dir) {
  std::string text = Slurp("scenes/thesis_A_a.toml");
  text = text.substr(0, text.find("[analysis.sweep]")) +
         "[analysis.sweep]\nup_range_rpm = [40.0, 48.0]\nspeed_step_rpm = 4.0\ndwell = 0.75\n";
  const fs::path file = dir / "thesis_A_a.toml";
  std::ofstream(file) << text;
  return file;
}

}  // namespace rubcont::testing
