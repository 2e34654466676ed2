#include "apps/figures.h"

#include <cstdlib>
#include <ostream>
#include <system_error>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/ostream.h>

namespace rubcont {
namespace {

// The exit status plots/*.py use when matplotlib, h5py or numpy cannot be imported.
constexpr int kMissingModulesStatus = 3;

std::filesystem::path ExecutableDirectory() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

}  // namespace

std::filesystem::path PlotsDirectory() {
  if (const char* env = std::getenv("RUBCONT_PLOTS_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const std::filesystem::path exe_dir = ExecutableDirectory();
  if (!exe_dir.empty()) {
    const std::filesystem::path installed = exe_dir.parent_path() / RUBCONT_INSTALL_DATADIR / "plots";
    if (std::filesystem::is_directory(installed, ec)) return installed;
  }
  return RUBCONT_SOURCE_PLOTS_DIR;
}

std::string PythonInterpreter() {
  if (const char* env = std::getenv("RUBCONT_PYTHON"); env != nullptr && *env != '\0') return env;
  return "/usr/bin/python3";
}

FigureOutcome MakeFigures(const std::string& script, const std::filesystem::path& h5_file,
                          const std::filesystem::path& out_dir) {
  FigureOutcome outcome;
  const std::string python = PythonInterpreter();
  const std::filesystem::path script_path = PlotsDirectory() / script;
  const std::string keep = "; the HDF5 result is complete: " + h5_file.string();
  if (access(python.c_str(), X_OK) != 0) {
    outcome.warning = "figures not made: Python interpreter " + python + " not found" + keep;
    return outcome;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(script_path, ec)) {
    outcome.warning = "figures not made: plotting script " + script_path.string() + " not found" + keep;
    return outcome;
  }
  std::vector<std::string> args = {python, script_path.string(), h5_file.string(), out_dir.string()};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    outcome.warning = "figures not made: cannot start " + python + keep;
    return outcome;
  }
  if (pid == 0) {
    execv(python.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    outcome.made = true;
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == kMissingModulesStatus) {
    outcome.warning = "figures not made: " + python + " lacks matplotlib, h5py or numpy "
                      "(Debian: apt-get install python3-matplotlib python3-h5py)" + keep;
  } else {
    outcome.warning = "figures not made: " + script_path.string() + " failed (" +
                      (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                         : std::string("killed by a signal")) +
                      ")" + keep;
  }
  return outcome;
}

void DrawFigures(const std::string& script, const std::filesystem::path& h5_file, std::ostream& out,
                 std::ostream& err) {
  const std::filesystem::path out_dir = h5_file.parent_path().empty() ? "." : h5_file.parent_path();
  const FigureOutcome figures = MakeFigures(script, h5_file, out_dir);
  if (figures.made) {
    fmt::print(out, "wrote figures ({}) in {}\n", script, out_dir.string());
  } else {
    fmt::print(err, "rubcont: warning: {}\n", figures.warning);
  }
}

}  // namespace rubcont
