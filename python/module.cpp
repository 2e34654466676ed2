// _rubcont: the compiled half of `import rubcont` (python/rubcont/__init__.py is the other).
//
// It binds what the command line does, not a second API: a scene is parsed by the same loader
// (a bad one raises rubcont.SceneError with the loader's key / value / rule message), and each
// stage runs through the same command as `rubcont <command>` (apps/commands.h), with the GIL
// released, its stdout and stderr captured, and every stderr line (progress, warnings) passed to a
// Python callback as it is written. The package reads the HDF5 file the command wrote.
//
// A command runs in a child process (fork) that the caller's thread watches: Ctrl-C (a notebook's
// "interrupt") raises KeyboardInterrupt within the watch's 0.1 s and kills the child, whose result
// was never renamed to its real name (apps/atomic_file.h) — the numerical code has no point at
// which it could be stopped from inside. Under mpirun the command runs in this process (a child
// of an MPI rank cannot take part in its communicator), and Ctrl-C waits for it.
#include <cerrno>
#include <csignal>
#include <memory>
#include <optional>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include "apps/attractor_command.h"
#include "apps/batch_command.h"
#include "apps/commands.h"
#include "apps/ensemble_command.h"
#include "apps/fit_command.h"
#include "apps/flexible_command.h"
#include "apps/lifetime_command.h"
#include "apps/loop_command.h"
#include "apps/map_command.h"
#include "apps/ranks.h"
#include "apps/ross_import.h"
#include "apps/scene.h"
#include "apps/version.h"

namespace py = pybind11;

namespace rubcont {
namespace {

// A stream buffer that keeps what is written and hands each finished line to `on_line` (with the
// GIL taken: the command runs without it). A callback that raises stops being called; its error
// is raised when the command returns.
class LineTap : public std::streambuf {
 public:
  explicit LineTap(py::object on_line) : on_line_(std::move(on_line)) {}

  const std::string& text() const { return text_; }
  // Raises the callback's error, if it raised one.
  void RethrowCallbackError() {
    if (error_) {
      py::gil_scoped_acquire gil;
      error_->restore();
      error_.reset();
      throw py::error_already_set();
    }
  }

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = static_cast<char>(c);
    text_.push_back(ch);
    if (ch == '\n') {
      Emit(line_);
      line_.clear();
    } else {
      line_.push_back(ch);
    }
    return c;
  }

 private:
  void Emit(const std::string& line) {
    if (on_line_.is_none() || error_) return;
    py::gil_scoped_acquire gil;
    try {
      on_line_(line);
    } catch (py::error_already_set& e) {
      error_ = std::make_unique<py::error_already_set>(std::move(e));
    }
  }

  py::object on_line_;
  std::string text_;
  std::string line_;
  std::unique_ptr<py::error_already_set> error_;
};

// What a command returned: its exit code and its stdout and stderr text.
struct CommandOutcome {
  int exit_code = 0;
  std::string out;
  std::string err;
};

// A stream buffer that writes straight to a file descriptor (the child's end of a pipe).
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) {}

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = static_cast<char>(c);
    return WriteAll(&ch, 1) ? c : traits_type::eof();
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return WriteAll(s, static_cast<size_t>(n)) ? n : 0;
  }

 private:
  bool WriteAll(const char* s, size_t n) {
    while (n > 0) {
      const ssize_t written = ::write(fd_, s, n);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) return false;
      s += written;
      n -= static_cast<size_t>(written);
    }
    return true;
  }
  int fd_;
};

// Runs `command(out, err)` in this process without the GIL (under mpirun).
template <class Command>
CommandOutcome CallInProcess(py::object progress, Command&& command) {
  LineTap out_tap{py::none()};
  LineTap err_tap(std::move(progress));
  std::ostream out(&out_tap);
  std::ostream err(&err_tap);
  CommandOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome.exit_code = command(out, err);
  }
  out.flush();
  err.flush();
  err_tap.RethrowCallbackError();
  outcome.out = out_tap.text();
  outcome.err = err_tap.text();
  return outcome;
}

// How often the watching thread looks for Ctrl-C [s].
constexpr int kWatchMilliseconds = 100;

// Runs `command(out, err)` in a child process, its stderr lines to `progress` (None: none) as they
// come, and watches for Ctrl-C: then the child is killed and KeyboardInterrupt raised.
template <class Command>
CommandOutcome Call(py::object progress, Command&& command) {
  if (LaunchedByMpi()) return CallInProcess(std::move(progress), std::forward<Command>(command));
  LineTap out_tap{py::none()};
  LineTap err_tap(std::move(progress));
  int out_pipe[2], err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0 || pipe2(err_pipe, O_CLOEXEC) != 0) {
    throw std::runtime_error(fmt::format("cannot start the command: pipe: {}", std::strerror(errno)));
  }
  CommandOutcome outcome;
  std::unique_ptr<py::error_already_set> interrupt;
  const auto check_signals = [&interrupt] {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) interrupt = std::make_unique<py::error_already_set>();
  };
  {
    py::gil_scoped_release release;
    const pid_t pid = fork();
    if (pid == 0) {  // the child: C++ only, never Python; ends with _exit
      std::signal(SIGINT, SIG_DFL);
      ::close(out_pipe[0]);
      ::close(err_pipe[0]);
      DescriptorBuffer out_buffer(out_pipe[1]), err_buffer(err_pipe[1]);
      std::ostream out(&out_buffer), err(&err_buffer);
      const int code = command(out, err);
      out.flush();
      err.flush();
      _exit(code);
    }
    ::close(out_pipe[1]);
    ::close(err_pipe[1]);
    if (pid < 0) {
      ::close(out_pipe[0]);
      ::close(err_pipe[0]);
      py::gil_scoped_acquire gil;
      throw std::runtime_error(fmt::format("cannot start the command: fork: {}", std::strerror(errno)));
    }
    pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
    LineTap* taps[2] = {&out_tap, &err_tap};
    char buffer[4096];
    while (fds[0].fd >= 0 || fds[1].fd >= 0) {
      const int ready = poll(fds, 2, kWatchMilliseconds);
      for (int k = 0; k < 2 && ready > 0; ++k) {
        if (fds[k].fd < 0 || fds[k].revents == 0) continue;
        const ssize_t n = ::read(fds[k].fd, buffer, sizeof buffer);
        if (n > 0) {
          taps[k]->sputn(buffer, n);
        } else if (n == 0 || errno != EINTR) {
          ::close(fds[k].fd);
          fds[k].fd = -1;  // poll ignores negative descriptors
        }
      }
      check_signals();
      if (interrupt) {
        ::kill(pid, SIGKILL);
        break;
      }
    }
    for (const pollfd& fd : fds) {
      if (fd.fd >= 0) ::close(fd.fd);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!interrupt) check_signals();  // a Ctrl-C that also ended the child (a terminal's)
    if (WIFEXITED(status)) {
      outcome.exit_code = WEXITSTATUS(status);
    } else if (!interrupt) {
      outcome.exit_code = 128 + WTERMSIG(status);
      const std::string line = fmt::format("rubcont: the command ended by signal {} ({})\n",
                                           WTERMSIG(status), strsignal(WTERMSIG(status)));
      err_tap.sputn(line.data(), static_cast<std::streamsize>(line.size()));
    }
  }
  if (interrupt) throw *interrupt;
  err_tap.RethrowCallbackError();
  outcome.out = out_tap.text();
  outcome.err = err_tap.text();
  return outcome;
}

// A Python dict (nested dicts, lists, str, bool, int, float) as a TOML table; anything else is a
// TypeError naming the key.
toml::array ToTomlArray(const py::sequence& items, const std::string& key);

template <class Insert>
void InsertValue(const py::handle& value, const std::string& key, Insert&& insert);

toml::table ToTomlTable(const py::dict& dict, const std::string& prefix) {
  toml::table table;
  for (const auto& [k, v] : dict) {
    if (!py::isinstance<py::str>(k)) {
      throw py::type_error(fmt::format("scene dict: key {} of [{}] is not a string",
                                       std::string(py::repr(k)), prefix));
    }
    const std::string key = k.cast<std::string>();
    const std::string full = prefix.empty() ? key : prefix + "." + key;
    InsertValue(v, full, [&](auto&& node) { table.insert_or_assign(key, std::move(node)); });
  }
  return table;
}

toml::array ToTomlArray(const py::sequence& items, const std::string& key) {
  toml::array array;
  for (const py::handle item : items) {
    InsertValue(item, key, [&](auto&& node) { array.push_back(std::move(node)); });
  }
  return array;
}

template <class Insert>
void InsertValue(const py::handle& value, const std::string& key, Insert&& insert) {
  // bool before int: Python's bool is an int.
  if (py::isinstance<py::bool_>(value)) {
    insert(value.cast<bool>());
  } else if (py::isinstance<py::int_>(value)) {
    insert(value.cast<int64_t>());
  } else if (py::isinstance<py::float_>(value)) {
    insert(value.cast<double>());
  } else if (py::isinstance<py::str>(value)) {
    insert(value.cast<std::string>());
  } else if (py::isinstance<py::dict>(value)) {
    insert(ToTomlTable(value.cast<py::dict>(), key));
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    insert(ToTomlArray(value.cast<py::sequence>(), key));
  } else if (py::hasattr(value, "tolist")) {  // numpy scalars and arrays
    InsertValue(value.attr("tolist")(), key, std::forward<Insert>(insert));
  } else {
    throw py::type_error(fmt::format("scene dict: {} = {}: must be a dict, list, str, bool, int "
                                     "or float",
                                     key, std::string(py::repr(value))));
  }
}

// The parsed scene as the package needs it: name, model, the resolved TOML.
py::dict Described(const Scene& scene) {
  py::dict d;
  d["name"] = scene.name;
  d["model"] = std::string(ToString(scene.model));
  d["source"] = scene.source;
  d["toml"] = ResolvedSceneToml(scene);
  py::list stages;
  for (Stage stage : scene.analysis.stages) stages.append(std::string(ToString(stage)));
  d["stages"] = stages;
  d["defaulted_keys"] = scene.defaulted_keys;
  return d;
}

}  // namespace
}  // namespace rubcont

PYBIND11_MODULE(_rubcont, m) {
  using namespace rubcont;
  m.doc() = "rubcont's compiled core: scene parsing and the commands (use `import rubcont`).";
  m.attr("__version__") = Version();

  static py::exception<SceneError> scene_error(m, "SceneError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneError& e) {
      scene_error(e.what());
    }
  });

  py::class_<CommandOutcome>(m, "CommandOutcome")
      .def_readonly("exit_code", &CommandOutcome::exit_code)
      .def_readonly("out", &CommandOutcome::out)
      .def_readonly("err", &CommandOutcome::err);

  m.def("parse_scene",
        [](const std::string& text, const std::string& source, const std::string& default_name) {
          return Described(ParseScene(text, source, default_name));
        },
        py::arg("text"), py::arg("source"), py::arg("default_name"),
        "Parses and validates scene TOML; raises SceneError with every problem.");
  m.def("load_scene", [](const std::string& file) { return Described(LoadScene(file)); },
        py::arg("file"));
  m.def("default_scene", [] { return Described(DefaultScene()); });
  m.def("dict_to_toml",
        [](const py::dict& dict) {
          std::ostringstream text;
          text << ToTomlTable(dict, "");
          return text.str();
        },
        py::arg("dict"), "A dict of scene keys as TOML text (not validated).");

  m.def("run",
        [](const std::string& scene_file, const std::string& out_dir, bool resume, bool fresh,
           bool figures, py::object progress, bool force) {
          RunRequest request;
          request.force = force;
          request.scene_file = scene_file;
          request.out_dir = out_dir;
          request.resume = resume;
          request.fresh = fresh;
          request.figures = figures;
          request.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) {
            return RunCommand(request, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_dir"), py::arg("resume"), py::arg("fresh"),
        py::arg("figures"), py::arg("progress"), py::arg("force") = false);
  m.def("sweep",
        [](const std::string& scene_file, const std::string& out_file, const std::string& direction,
           bool resume, bool fresh, bool figures, py::object progress, bool force) {
          SweepRequest request;
          request.force = force;
          request.scene_file = scene_file;
          request.out_file = out_file;
          request.direction = direction;
          request.resume = resume;
          request.fresh = fresh;
          request.figures = figures;
          request.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) {
            return SweepCommand(request, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_file"), py::arg("direction"), py::arg("resume"),
        py::arg("fresh"), py::arg("figures"), py::arg("progress"), py::arg("force") = false);
  m.def("map",
        [](const std::string& scene_file, const std::string& out_file, const std::string& parameter,
           std::optional<double> eta_min, std::optional<double> eta_max, int eta_points,
           int speed_points, int threads, py::object progress, bool force) {
          MapRequest request;
          request.force = force;
          request.scene_file = scene_file;
          request.out_file = out_file;
          request.parameter = parameter;
          request.eta_min = eta_min;
          request.eta_max = eta_max;
          request.eta_points = eta_points;
          request.speed_points = speed_points;
          request.threads = threads;
          request.figures = false;
          request.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) {
            return MapCommand(request, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_file"), py::arg("parameter"), py::arg("eta_min"),
        py::arg("eta_max"), py::arg("eta_points"), py::arg("speed_points"), py::arg("threads"),
        py::arg("progress"), py::arg("force") = false);
  m.def("loop",
        [](const std::string& scene_file, const std::string& out_file, std::optional<double> step_rpm,
           std::optional<double> dwell, std::optional<double> budget, int threads, bool figures,
           py::object progress, bool force) {
          LoopRequest request;
          request.force = force;
          request.scene_file = scene_file;
          request.out_file = out_file;
          request.step_rpm = step_rpm;
          request.dwell = dwell;
          request.budget = budget;
          request.threads = threads;
          request.figures = figures;
          request.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) {
            return LoopCommand(request, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_file"), py::arg("step_rpm"), py::arg("dwell"), py::arg("budget"),
        py::arg("threads"), py::arg("figures"), py::arg("progress"), py::arg("force") = false);
  m.def("import_ross",
        [](const std::string& ross_file, const std::string& base_scene, int left, int right) {
          ImportRossRequest request;
          request.ross_file = ross_file;
          request.base_scene = base_scene;
          request.contact_stations = {left, right};
          return Call(py::none(), [&](std::ostream& out, std::ostream& err) {
            return ImportRossCommand(request, out, err);
          });
        },
        py::arg("ross_file"), py::arg("base_scene"), py::arg("left"), py::arg("right"));
  m.def("scene_matrices",
        [](const std::string& scene_file, const std::string& out_path) {
          return Call(py::none(), [&](std::ostream& out, std::ostream& err) {
            return SceneMatricesCommand(scene_file, out_path, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_path"));
  m.def("fit",
        [](const std::string& scene_file, const std::string& out_file,
           const std::string& targets_file, int threads, py::object progress) {
          FitRequest request;
          request.scene_file = scene_file;
          request.out_file = out_file;
          request.targets_file = targets_file;
          request.threads = threads;
          request.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) {
            return FitCommand(request, out, err);
          });
        },
        py::arg("scene_file"), py::arg("out_file"), py::arg("targets_file"), py::arg("threads"),
        py::arg("progress"));

  // The commands whose options are many: their request structs, filled field by field from
  // Python (rubcont.ensemble(scene, speed_rpm=..., copies=...), ...), then run as the others.
  py::class_<EnsembleRequest>(m, "EnsembleRequest")
      .def(py::init<>())
      .def_readwrite("scene_file", &EnsembleRequest::scene_file)
      .def_readwrite("speed_rpm", &EnsembleRequest::speed_rpm)
      .def_readwrite("direction", &EnsembleRequest::direction)
      .def_readwrite("copies", &EnsembleRequest::copies)
      .def_readwrite("duration", &EnsembleRequest::duration)
      .def_readwrite("window", &EnsembleRequest::window)
      .def_readwrite("perturbation", &EnsembleRequest::perturbation)
      .def_readwrite("seed", &EnsembleRequest::seed)
      .def_readwrite("threads", &EnsembleRequest::threads)
      .def_readwrite("until", &EnsembleRequest::until)
      .def_readwrite("until_above_hz", &EnsembleRequest::until_above_hz)
      .def_readwrite("until_contacts", &EnsembleRequest::until_contacts)
      .def_readwrite("out_file", &EnsembleRequest::out_file)
      .def_readwrite("quiet", &EnsembleRequest::quiet)
      .def_readwrite("force", &EnsembleRequest::force)
      .def_readwrite("figure_format", &EnsembleRequest::figure_format);
  m.def("ensemble",
        [](const EnsembleRequest& request, py::object progress) {
          EnsembleRequest r = request;
          r.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) { return EnsembleCommand(r, out, err); });
        },
        py::arg("request"), py::arg("progress"));
  py::class_<LifetimeRequest>(m, "LifetimeRequest")
      .def(py::init<>())
      .def_readwrite("scene_file", &LifetimeRequest::scene_file)
      .def_readwrite("from_rpm", &LifetimeRequest::from_rpm)
      .def_readwrite("to_rpm", &LifetimeRequest::to_rpm)
      .def_readwrite("step_rpm", &LifetimeRequest::step_rpm)
      .def_readwrite("direction", &LifetimeRequest::direction)
      .def_readwrite("copies", &LifetimeRequest::copies)
      .def_readwrite("duration", &LifetimeRequest::duration)
      .def_readwrite("window", &LifetimeRequest::window)
      .def_readwrite("perturbation", &LifetimeRequest::perturbation)
      .def_readwrite("seed", &LifetimeRequest::seed)
      .def_readwrite("threads", &LifetimeRequest::threads)
      .def_readwrite("until", &LifetimeRequest::until)
      .def_readwrite("until_above_hz", &LifetimeRequest::until_above_hz)
      .def_readwrite("until_contacts", &LifetimeRequest::until_contacts)
      .def_readwrite("check_copies", &LifetimeRequest::check_copies)
      .def_readwrite("check_step_rpm", &LifetimeRequest::check_step_rpm)
      .def_readwrite("check_dwell", &LifetimeRequest::check_dwell)
      .def_readwrite("out_file", &LifetimeRequest::out_file)
      .def_readwrite("quiet", &LifetimeRequest::quiet)
      .def_readwrite("resume", &LifetimeRequest::resume)
      .def_readwrite("fresh", &LifetimeRequest::fresh)
      .def_readwrite("force", &LifetimeRequest::force)
      .def_readwrite("figure_format", &LifetimeRequest::figure_format);
  m.def("lifetime",
        [](const LifetimeRequest& request, py::object progress) {
          LifetimeRequest r = request;
          r.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) { return LifetimeCommand(r, out, err); });
        },
        py::arg("request"), py::arg("progress"));
  py::class_<AttractorRequest>(m, "AttractorRequest")
      .def(py::init<>())
      .def_readwrite("scene_file", &AttractorRequest::scene_file)
      .def_readwrite("from_rpm", &AttractorRequest::from_rpm)
      .def_readwrite("to_rpm", &AttractorRequest::to_rpm)
      .def_readwrite("step_rpm", &AttractorRequest::step_rpm)
      .def_readwrite("direction", &AttractorRequest::direction)
      .def_readwrite("approach", &AttractorRequest::approach)
      .def_readwrite("duration", &AttractorRequest::duration)
      .def_readwrite("discard", &AttractorRequest::discard)
      .def_readwrite("interval", &AttractorRequest::interval)
      .def_readwrite("sample_interval", &AttractorRequest::sample_interval)
      .def_readwrite("exponents", &AttractorRequest::exponents)
      .def_readwrite("tolerance", &AttractorRequest::tolerance)
      .def_readwrite("out_file", &AttractorRequest::out_file)
      .def_readwrite("quiet", &AttractorRequest::quiet)
      .def_readwrite("force", &AttractorRequest::force)
      .def_readwrite("figure_format", &AttractorRequest::figure_format);
  m.def("attractor",
        [](const AttractorRequest& request, py::object progress) {
          AttractorRequest r = request;
          r.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) { return AttractorCommand(r, out, err); });
        },
        py::arg("request"), py::arg("progress"));
  py::class_<FlexibleRequest>(m, "FlexibleRequest")
      .def(py::init<>())
      .def_readwrite("scene_file", &FlexibleRequest::scene_file)
      .def_readwrite("modes", &FlexibleRequest::modes)
      .def_readwrite("gyroscopic", &FlexibleRequest::gyroscopic)
      .def_readwrite("out_file", &FlexibleRequest::out_file)
      .def_readwrite("quiet", &FlexibleRequest::quiet);
  m.def("flexible",
        [](const FlexibleRequest& request, py::object progress) {
          FlexibleRequest r = request;
          r.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) { return FlexibleCommand(r, out, err); });
        },
        py::arg("request"), py::arg("progress"));
  py::class_<BatchRequest>(m, "BatchRequest")
      .def(py::init<>())
      .def_readwrite("jobs_file", &BatchRequest::jobs_file)
      .def_readwrite("out_dir", &BatchRequest::out_dir)
      .def_readwrite("quiet", &BatchRequest::quiet);
  m.def("batch",
        [](const BatchRequest& request, py::object progress) {
          BatchRequest r = request;
          r.quiet = progress.is_none();
          return Call(progress, [&](std::ostream& out, std::ostream& err) { return BatchCommand(r, out, err); });
        },
        py::arg("request"), py::arg("progress"));
}
