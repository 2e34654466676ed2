// _rubcont: the compiled half of `import rubcont` (python/rubcont/__init__.py is the other).
//
// It binds what the command line does, not a second API: a scene is parsed by the same loader
// (a bad one raises rubcont.SceneError with the loader's key / value / rule message), and each
// stage runs through the same command as `rubcont <command>` (apps/commands.h), with the GIL
// released, its stdout and stderr captured, and every stderr line (progress, warnings) passed to a
// Python callback as it is written. The package reads the HDF5 file the command wrote.
#include <memory>
#include <optional>
#include <sstream>
#include <streambuf>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include "apps/commands.h"
#include "apps/fit_command.h"
#include "apps/loop_command.h"
#include "apps/map_command.h"
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

// Runs `command(out, err)` without the GIL, stderr lines to `progress` (None: none).
template <class Command>
CommandOutcome Call(py::object progress, Command&& command) {
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
           bool figures, py::object progress) {
          RunRequest request;
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
        py::arg("figures"), py::arg("progress"));
  m.def("sweep",
        [](const std::string& scene_file, const std::string& out_file, const std::string& direction,
           bool resume, bool fresh, bool figures, py::object progress) {
          SweepRequest request;
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
        py::arg("fresh"), py::arg("figures"), py::arg("progress"));
  m.def("map",
        [](const std::string& scene_file, const std::string& out_file, const std::string& parameter,
           std::optional<double> eta_min, std::optional<double> eta_max, int eta_points,
           int speed_points, int threads, py::object progress) {
          MapRequest request;
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
        py::arg("progress"));
  m.def("loop",
        [](const std::string& scene_file, const std::string& out_file, std::optional<double> step_rpm,
           std::optional<double> dwell, std::optional<double> budget, int threads, bool figures,
           py::object progress) {
          LoopRequest request;
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
        py::arg("threads"), py::arg("figures"), py::arg("progress"));
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
}
