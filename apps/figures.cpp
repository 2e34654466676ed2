#include "apps/figures.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ostream>
#include <system_error>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/ostream.h>

extern char** environ;

namespace rubcont {
namespace {

// The exit status of kBootstrap when matplotlib, h5py or numpy cannot be imported.
constexpr int kMissingModulesStatus = 3;

// `python3 -c kBootstrap MODULE ARGS...` is `python3 -m MODULE ARGS...` after a check that the
// modules a figure needs import (`rubcont` itself imports numpy and h5py before any figure
// module could report them missing).
constexpr char kBootstrap[] = R"(import sys
try:
    import h5py, matplotlib, numpy
except ImportError as error:
    print(f"rubcont figures: {error}", file=sys.stderr)
    sys.exit(3)
import runpy
sys.argv = sys.argv[1:]
runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
)";

std::filesystem::path ExecutableDirectory() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

// The environment of the child: this one with `directory` first on PYTHONPATH.
std::vector<std::string> ChildEnvironment(const std::filesystem::path& directory) {
  std::vector<std::string> environment;
  std::string python_path = "PYTHONPATH=" + directory.string();
  for (char** entry = environ; entry != nullptr && *entry != nullptr; ++entry) {
    if (std::strncmp(*entry, "PYTHONPATH=", 11) == 0) {
      if ((*entry)[11] != '\0') python_path += std::string(":") + (*entry + 11);
    } else {
      environment.emplace_back(*entry);
    }
  }
  environment.push_back(python_path);
  return environment;
}

std::vector<char*> Pointers(std::vector<std::string>& strings) {
  std::vector<char*> pointers;
  for (std::string& s : strings) pointers.push_back(s.data());
  pointers.push_back(nullptr);
  return pointers;
}

}  // namespace

std::filesystem::path PythonPackageDirectory() {
  if (const char* env = std::getenv("RUBCONT_PYTHON_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const std::filesystem::path exe_dir = ExecutableDirectory();
  if (!exe_dir.empty()) {
    const std::filesystem::path installed = exe_dir.parent_path() / RUBCONT_INSTALL_PYTHON_DIR;
    if (std::filesystem::is_directory(installed / "rubcont" / "plots", ec)) return installed;
  }
  return RUBCONT_SOURCE_PYTHON_DIR;
}

std::string PythonInterpreter() {
  if (const char* env = std::getenv("RUBCONT_PYTHON"); env != nullptr && *env != '\0') return env;
  return "/usr/bin/python3";
}

FigureOutcome MakeFigures(const std::string& module, const std::filesystem::path& h5_file,
                          const std::filesystem::path& out_dir, const std::string& format) {
  FigureOutcome outcome;
  const std::string python = PythonInterpreter();
  const std::filesystem::path package = PythonPackageDirectory();
  const std::filesystem::path source = package / "rubcont" / "plots" / (module + ".py");
  const std::string keep = "; the HDF5 result is complete: " + h5_file.string();
  if (std::find(kFigureFormats.begin(), kFigureFormats.end(), format) == kFigureFormats.end()) {
    outcome.warning = "figures not made: format \"" + format + "\" is not png, pdf or svg" + keep;
    return outcome;
  }
  if (access(python.c_str(), X_OK) != 0) {
    outcome.warning = "figures not made: Python interpreter " + python + " not found" + keep;
    return outcome;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(source, ec)) {
    outcome.warning = "figures not made: plotting module " + source.string() + " not found" + keep;
    return outcome;
  }
  const std::string name = "rubcont.plots." + module;
  std::vector<std::string> args = {python,          "-c",         kBootstrap,  name, h5_file.string(),
                                   out_dir.string(), "--format", format};
  std::vector<std::string> environment = ChildEnvironment(package);
  // Built before fork: the child only calls execve (the parent may run threads).
  std::vector<char*> argv = Pointers(args);
  std::vector<char*> envp = Pointers(environment);
  const pid_t pid = fork();
  if (pid < 0) {
    outcome.warning = "figures not made: cannot start " + python + keep;
    return outcome;
  }
  if (pid == 0) {
    execve(python.c_str(), argv.data(), envp.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    outcome.made = true;
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == kMissingModulesStatus) {
    outcome.warning = "figures not made: " + python + " lacks matplotlib, h5py or numpy "
                      "(Debian: apt-get install python3-matplotlib python3-h5py)" + keep;
  } else {
    outcome.warning = "figures not made: " + python + " -m " + name + " failed (" +
                      (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                         : std::string("killed by a signal")) +
                      ")" + keep;
  }
  return outcome;
}

void DrawFigures(const std::string& module, const std::filesystem::path& h5_file,
                 const std::string& format, std::ostream& out, std::ostream& err) {
  const std::filesystem::path out_dir = h5_file.parent_path().empty() ? "." : h5_file.parent_path();
  const FigureOutcome figures = MakeFigures(module, h5_file, out_dir, format);
  if (figures.made) {
    fmt::print(out, "wrote figures ({}) in {}\n", module, out_dir.string());
  } else {
    fmt::print(err, "rubcont: warning: {}\n", figures.warning);
  }
}

}  // namespace rubcont
