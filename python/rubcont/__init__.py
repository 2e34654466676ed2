"""rubcont from Python: scenes, stages, and their results as numpy arrays.

Each stage runs through the same command as the ``rubcont`` executable (the scene loader, the
engine, the HDF5 writer), with the GIL released; the result is the HDF5 file that command writes,
read back with h5py into numpy arrays under the same paths and units as the file's layout
(docs/howto.md, "Python"). So a script and the command line give the same numbers, and a result made
either way reopens with :func:`read`.

    import rubcont
    scene = rubcont.load_scene("scenes/thesis_A_a.toml")
    result = rubcont.branches(scene)
    result["branches/branch2/speed_rpm"], result.attrs("branches/branch2")["message"]

Statuses are values, as in C++: a run whose continuation or integration fails returns a Result
with ``status == "failure"`` and the reasons in ``failures``. Bad input raises: a bad scene
:class:`SceneError` (a ValueError) with the loader's key / value / rule message, bad arguments
ValueError; an I/O error that leaves no result file raises RubcontError.
"""

import io
import os
import tempfile
import tomllib

import h5py
import numpy as np

try:
    from . import _rubcont
    from ._rubcont import SceneError, __version__
except ImportError as _error:  # a source tree, or the command line's figures: plots and read() work
    _rubcont = None
    _missing_core = _error
    __version__ = "unknown (rubcont._rubcont not built)"

    class SceneError(ValueError):
        """A scene that does not load (the compiled module's class when it is built)."""

from .objects import (Branch, Loop, OrbitFamily, ProgressEvent, SpecialPoint, Sweep,
                      TorusFamily, TqdmProgress, events, parse_progress)

__all__ = [
    "Scene", "Result", "SceneError", "RubcontError", "load_scene", "scene", "default_scene",
    "run", "analytic", "branches", "orbits", "sweep", "loop", "map", "fit", "read", "__version__",
    "Branch", "SpecialPoint", "Sweep", "Loop", "OrbitFamily", "TorusFamily", "continue_from",
    "ProgressEvent", "parse_progress", "events", "TqdmProgress",
    "ensemble", "lifetime", "attractor", "flexible", "batch", "import_ross", "scene_matrices",
]


def _core():
    """The compiled module, or ImportError saying it is not built (scenes and stages need it;
    :func:`read`, :class:`Result` and :mod:`rubcont.plots` do not)."""
    if _rubcont is None:
        raise ImportError(f"rubcont's compiled module is not built or not on this path "
                          f"(cmake -DRUBCONT_PYTHON=ON; PYTHONPATH=<build>/python): {_missing_core}")
    return _rubcont


class RubcontError(RuntimeError):
    """A command failed without a result to return (an I/O error, an internal error)."""


class Scene:
    """A validated scene: its name, model, stages and resolved TOML (every key, defaults
    included). Immutable; :meth:`with_values` returns a changed copy, validated again."""

    def __init__(self, described):
        self._d = dict(described)

    name = property(lambda self: self._d["name"])
    model = property(lambda self: self._d["model"])
    source = property(lambda self: self._d["source"])
    toml = property(lambda self: self._d["toml"], doc="the resolved scene as TOML text")
    stages = property(lambda self: list(self._d["stages"]))
    defaulted_keys = property(lambda self: list(self._d["defaulted_keys"]),
                              doc="keys the source left out (their documented defaults apply)")

    def to_dict(self):
        """The resolved scene as nested dicts (scene-file sections and keys)."""
        return tomllib.loads(self.toml)

    def with_values(self, values):
        """A copy with `values` (nested dicts of scene keys) merged in, e.g.
        ``scene.with_values({"contact": {"friction": 0.3}})``."""
        merged = _merged(self.to_dict(), values)
        return scene(merged, name=self.name)

    def __repr__(self):
        return f"<rubcont.Scene {self.name!r} model={self.model} stages={self.stages}>"


def _merged(base, changes):
    out = dict(base)
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merged(out[key], value)
        else:
            out[key] = value
    return out


def load_scene(path):
    """Reads and validates a scene file (SceneError on any problem)."""
    return Scene(_core().load_scene(os.fspath(path)))


def scene(source, name="scene"):
    """A scene from a dict of sections and keys, or from TOML text. `name` names the output
    when the scene sets no ``name``. SceneError on any problem, TypeError on a value that is
    not a dict, list, str, bool, int or float."""
    text = _core().dict_to_toml(source) if isinstance(source, dict) else str(source)
    origin = "<dict>" if isinstance(source, dict) else "<text>"
    return Scene(_core().parse_scene(text, origin, name))


def default_scene():
    """The built-in default scene (scenes/default.toml)."""
    return Scene(_core().default_scene())


class Result:
    """One result file: numpy arrays by path (``result["branches/branch1/speed_rpm"]``),
    attributes by path (``result.attrs("branches/branch1")``), the run's status and text.

    `file` is where it lies on disk (None when the run wrote to a temporary directory, which is
    gone: :meth:`write` saves the same bytes)."""

    def __init__(self, data, file=None, exit_code=0, log="", messages=""):
        self._bytes = data
        self.file = file
        self.exit_code = exit_code
        self.log = log            # what the command printed on stdout (the summary)
        self.messages = messages  # what it printed on stderr (progress, warnings, failures)
        self._arrays = {}
        self._attrs = {}
        with h5py.File(io.BytesIO(data), "r") as f:
            self._attrs[""] = _attributes(f)

            def visit(path, node):
                self._attrs[path] = _attributes(node)
                if isinstance(node, h5py.Dataset):
                    self._arrays[path] = _array(node)

            f.visititems(visit)

    @property
    def status(self):
        """"success" or "failure" (root attribute `status`)."""
        return self._attrs[""].get("status", "success")

    @property
    def failures(self):
        """One sentence per numerical failure of the run ("rubcont: numerical failure: ...")."""
        prefix = "rubcont: numerical failure: "
        return [line[len(prefix):] for line in self.messages.splitlines()
                if line.startswith(prefix)]

    @property
    def scene(self):
        """The scene the result was made from (root attribute `scene_toml`)."""
        return scene(self._attrs[""]["scene_toml"], name=self._attrs[""].get("scene_name", "scene"))

    def __getitem__(self, path):
        return self._arrays[path.strip("/")]

    def __contains__(self, path):
        return path.strip("/") in self._arrays

    def keys(self):
        """Every dataset path, e.g. 'branches/branch1/speed_rpm'."""
        return list(self._arrays)

    def groups(self, path=""):
        """The names of the groups directly under `path` ('' the root)."""
        prefix = path.strip("/") + "/" if path.strip("/") else ""
        return sorted(key[len(prefix):] for key in self._attrs
                      if key.startswith(prefix) and key[len(prefix):] and
                      "/" not in key[len(prefix):] and key not in self._arrays)

    def attrs(self, path=""):
        """The attributes of a group or dataset, strings decoded."""
        return dict(self._attrs[path.strip("/")])

    def write(self, path):
        """Saves the result file (the bytes the command wrote), atomically."""
        path = os.fspath(path)
        temporary = path + ".tmp"
        with open(temporary, "wb") as out:
            out.write(self._bytes)
        os.replace(temporary, path)

    def __repr__(self):
        where = self.file or "in memory"
        return f"<rubcont.Result {where}: {self.status}, {len(self._arrays)} datasets>"

    # The objects of the file (rubcont/objects.py), built from the arrays above.
    def _h5(self):
        from .objects import h5_of

        return h5_of(self._bytes)

    def _objects(self):
        from .objects import objects_of

        return objects_of(self)

    @property
    def branches(self) -> "list[Branch]":
        """The rotating-wave branches of /branches, in numeric order (branch2 before branch10)."""
        return self._objects()["branches"]

    @property
    def orbit_families(self) -> "list[OrbitFamily]":
        """The periodic-orbit families (/orbits/<family>, /branches/* of kind periodic_orbit)."""
        return self._objects()["orbit_families"]

    @property
    def torus_families(self) -> "list[TorusFamily]":
        """The torus families of /tori."""
        return self._objects()["torus_families"]

    @property
    def sweep(self) -> "Sweep | None":
        """The sweeps of /sweeps, or None."""
        return self._objects()["sweep"]

    @property
    def loop(self) -> "Loop | None":
        """The explained loop of /loop, or None."""
        return self._objects()["loop"]

    def plot(self):
        """Every figure the command line draws from this file, as {name: Figure}."""
        from . import plots

        with self._h5() as f:
            return dict(plots.figures(f, "result"))

    def _repr_html_(self):
        import html as _html

        objects = self._objects()
        counts = [f"{len(objects['branches'])} branches", f"{len(objects['orbit_families'])} orbit families",
                  f"{len(objects['torus_families'])} torus families"]
        counts += [k for k in ("sweep", "loop") if objects[k] is not None]
        scene_name = self._attrs[""].get("scene_name", "")
        return (f"<b>rubcont.Result</b> {_html.escape(str(scene_name))} ({_html.escape(self.status)}): "
                f"{_html.escape(', '.join(counts))}; {len(self._arrays)} datasets"
                + (f"<br><code>{_html.escape(self.file)}</code>" if self.file else ""))


def _decoded(value):
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.dtype.kind in "OS":
        return np.array([_decoded(v) for v in value.ravel()], dtype=object).reshape(value.shape)
    return value


def _attributes(node):
    return {key: _decoded(value) for key, value in node.attrs.items()}


def _array(dataset):
    if h5py.check_string_dtype(dataset.dtype) is not None:
        return np.asarray(dataset.asstr()[()], dtype=object)
    return dataset[()]


def read(path):
    """Reopens a result file (of this package or of the ``rubcont`` executable)."""
    path = os.fspath(path)
    with open(path, "rb") as f:
        data = f.read()
    return Result(data, file=path)


def _raise_bad_input(outcome):
    """ValueError with the command's message when it exited with 2 (bad input)."""
    if outcome.exit_code == 2:
        raise ValueError(outcome.err.strip().removeprefix("rubcont: "))


def _outcome(outcome, file, temporary):
    """The Result of a command, or the exception its exit code means."""
    _raise_bad_input(outcome)
    if not os.path.isfile(file):  # none written (an I/O error), or a directory in its place
        raise RubcontError(outcome.err.strip() or f"no result file {file}")
    with open(file, "rb") as f:
        data = f.read()
    return Result(data, file=None if temporary else file, exit_code=outcome.exit_code,
                  log=outcome.out, messages=outcome.err)


def _scene_file(scene_, work):
    """`scene_` (a Scene, a path, or None: the default scene) as a file in `work`."""
    if scene_ is None:
        scene_ = default_scene()
    if not isinstance(scene_, Scene):
        return os.fspath(scene_)
    path = os.path.join(work, scene_.name + ".toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(scene_.toml)
    return path


def _text_of(outcome, command):
    """The printed output of a command that writes no result file, or the exception its exit
    code means."""
    _raise_bad_input(outcome)
    if outcome.exit_code != 0:
        raise RubcontError(outcome.err.strip() or f"{command} failed (exit code {outcome.exit_code})")
    return outcome.out


def _command(scene_, out, default_file, call):
    """Writes the scene to a file the command reads, runs it, returns the Result. `out`: a
    directory (run) or file (the others); None: a temporary directory, removed afterwards."""
    if scene_ is None:
        scene_ = default_scene()
    if not isinstance(scene_, Scene):
        scene_ = load_scene(scene_)  # checked here, as SceneError
    with tempfile.TemporaryDirectory(prefix="rubcont-") as work:
        scene_file = _scene_file(scene_, work)
        target = os.fspath(out) if out is not None else default_file(work, scene_)
        outcome, file = call(scene_file, target)
        return _outcome(outcome, file, temporary=out is None)


def run(scene=None, stages=None, out=None, progress=None, figures=False, resume=False, fresh=False,
        force=False):
    """Every stage the scene lists (or `stages`), as ``rubcont run``: the result of
    <out>/<name>/<name>.h5 (`out` a directory; None: a temporary one). `progress`: called with
    each progress line. `figures`: draw the figures next to the file (needs `out`). A sweep's
    checkpoint left by an interrupted run is refused unless `resume` (continue from it) or `fresh`
    (start again over it). Work the plan check refuses (docs/robustness.md, "The plan check") raises
    ValueError naming the key and the estimate unless `force`."""
    if stages is not None:
        scene_ = scene if isinstance(scene, Scene) else (
            default_scene() if scene is None else load_scene(scene))
        scene = scene_.with_values({"analysis": {"stages": list(stages)}})

    def call(scene_file, out_dir):
        name = os.path.splitext(os.path.basename(scene_file))[0]
        outcome = _core().run(scene_file, out_dir, resume, fresh, figures and out is not None,
                               progress, force)
        return outcome, os.path.join(out_dir, name, name + ".h5")

    return _command(scene, out, lambda work, s: work, call)


def analytic(scene=None, **options):
    """The L0 closed-form Mode 1 / Mode 2 solutions (``/analytic``)."""
    return run(scene, stages=["analytic"], **options)


def branches(scene=None, **options):
    """L0, then the L1 rotating-wave branches in running speed (``/branches``)."""
    return run(scene, stages=["analytic", "branches"], **options)


def orbits(scene=None, **options):
    """The L2 periodic orbits of the scene (``/orbits``)."""
    return run(scene, stages=["orbits"], **options)


def sweep(scene=None, direction="both", out=None, progress=None, resume=False, figures=False,
          fresh=False, force=False):
    """The L3 time-marching sweeps of [analysis.sweep] with the branches, as ``rubcont sweep``
    (`out`: the HDF5 file; `resume` / `fresh` / `force` as in `run`)."""

    def call(scene_file, file):
        return _core().sweep(scene_file, file, direction, resume, fresh, figures and out is not None,
                              progress, force), file

    return _command(scene, out, lambda work, s: os.path.join(work, "sweep.h5"), call)


def loop(scene=None, schedule=None, budget=None, threads=0, out=None, progress=None, figures=False,
         force=False):
    """The hysteresis loop of the scene's rotor, explained, as ``rubcont loop`` (``/loop``; its
    table of jumps is ``/loop/corners``): `schedule` = (step_rpm, dwell_s) of the run (None: the
    scene's [analysis.sweep]), `budget` in G work units (None: the scene's
    [analysis.loop] budget, 4; studies/loop.h), the copies over `threads` threads
    (0: one per core); `out` the HDF5 file; `force` as in `run`."""
    step, dwell = schedule if schedule is not None else (None, None)

    def call(scene_file, file):
        return _core().loop(scene_file, file, step, dwell, budget, threads, figures and out is not None,
                             progress, force), file

    return _command(scene, out, lambda work, s: os.path.join(work, "loop.h5"), call)


def map(scene=None, parameter="friction", eta_range=None, eta_points=31, speed_points=481,
        threads=1, out=None, progress=None, force=False):
    """The hysteresis map in (running speed, `parameter`), as ``rubcont map`` (``/maps``); its
    grid over `threads` threads (0: one per core); `force` as in `run`."""
    eta_min, eta_max = eta_range if eta_range is not None else (None, None)

    def call(scene_file, file):
        return _core().map(scene_file, file, parameter, eta_min, eta_max, eta_points,
                            speed_points, threads, progress, force), file

    return _command(scene, out, lambda work, s: os.path.join(work, "map.h5"), call)


def fit(scene, targets, threads=1, out=None, progress=None):
    """Identification of design parameters from measured jumps, as ``rubcont fit``: `targets` a
    targets file or a dict of its sections (scenes/README.md, "Fit targets"); the batches of
    evaluations over `threads` threads (0: one per core; shared with global = "multistart")."""

    def call(scene_file, file):
        targets_file = os.fspath(targets) if not isinstance(targets, dict) else None
        if targets_file is None:
            targets_file = os.path.join(os.path.dirname(scene_file), "targets.toml")
            with open(targets_file, "w", encoding="utf-8") as f:
                f.write(_core().dict_to_toml(targets))
        return _core().fit(scene_file, file, targets_file, threads, progress), file

    return _command(scene, out, lambda work, s: os.path.join(work, "fit.h5"), call)



def _request(kind: str, command: str, fields: dict):
    """The compiled module's request `kind` with `fields` set; TypeError naming an unknown one."""
    request = getattr(_core(), kind)()
    for key, value in fields.items():
        if key in ("quiet", "out_file", "scene_file", "jobs_file", "out_dir") or not hasattr(request, key):
            known = sorted(k for k in dir(request) if not k.startswith("_") and k not in (
                "quiet", "out_file", "scene_file", "jobs_file", "out_dir"))
            raise TypeError(f"rubcont.{command}: unknown option {key!r}; options: {', '.join(known)}")
        setattr(request, key, value)
    return request


def _options_command(kind: str, command: str, default_name: str):
    """A Python function for a command with many options (`rubcont <command>`): the scene, the
    command's options as keywords (the fields of apps/<command>_command.h, the CLI's flags with _
    for -), `out` the HDF5 file (None: a temporary one), `progress` as for the others."""

    def run_command(scene=None, out=None, progress=None, figure_format: str = "png", **options) -> "Result":
        if command != "flexible":
            options["figure_format"] = figure_format

        def call(scene_file, file):
            request = _request(kind, command, options)
            request.scene_file = scene_file
            request.out_file = file
            return getattr(_core(), command)(request, progress), file

        return _command(scene, out, lambda work, s: os.path.join(work, default_name), call)

    run_command.__name__ = command
    return run_command


ensemble = _options_command("EnsembleRequest", "ensemble", "ensemble.h5")
ensemble.__doc__ = """How long the state a sweep reached at `speed_rpm` lasts: copies perturbed and
integrated (``rubcont ensemble``; ``/ensemble``). Options: speed_rpm (required), direction,
copies, duration, window, perturbation, seed, threads, until, until_above_hz, until_contacts,
force."""
lifetime = _options_command("LifetimeRequest", "lifetime", "lifetime.h5")
lifetime.__doc__ = """Escape rates over speeds and the fitted crisis law (``rubcont lifetime``;
``/lifetime``). Options: from_rpm, to_rpm (required), step_rpm, direction, copies, duration,
window, perturbation, seed, threads, until, until_above_hz, until_contacts, check_copies,
check_step_rpm, check_dwell, force, resume and fresh (with `out`: its checkpoint
`<stem>.checkpoint.h5`, as the CLI's --resume and --fresh)."""
attractor = _options_command("AttractorRequest", "attractor", "attractor.h5")
attractor.__doc__ = """Lyapunov exponents and Poincaré sections speed by speed (``rubcont
attractor``; ``/attractor``). Options: from_rpm (required), to_rpm, step_rpm, direction,
approach, duration, discard, interval, sample_interval, exponents, tolerance, force."""
flexible = _options_command("FlexibleRequest", "flexible", "flexible.h5")
flexible.__doc__ = """The rotor and stator as Timoshenko shafts reduced by Craig–Bampton, their
rotating waves against the rigid model's (``rubcont flexible``). Options: modes, gyroscopic."""


def batch(jobs, out=None, progress=None) -> str:
    """Many jobs from a jobs file (``rubcont batch JOBS.toml``; apps/batch_command.h) into the
    directory `out` (None: the jobs file's default): returns the command's summary text; the
    results are the files it names. RubcontError when it fails."""
    request = _request("BatchRequest", "batch", {})
    request.jobs_file = os.fspath(jobs)
    if out is not None:
        request.out_dir = os.fspath(out)
    return _text_of(_core().batch(request, progress), "batch")


def import_ross(ross_file, base, contact_stations) -> "Scene":
    """A ROSS rotor (``ross.Rotor.save``'s TOML) as the listed rotor of the scene `base` (a Scene
    or a scene file: its stator, contacts and analysis kept), the contacts at the ROSS nodes
    `contact_stations` = (left, right), as ``rubcont scene import-ross`` (docs/howto.md, "Bring
    your own rotor"). ValueError naming the element and the rule for what the rows cannot hold."""
    left, right = contact_stations
    with tempfile.TemporaryDirectory(prefix="rubcont-") as work:
        text = _text_of(_core().import_ross(os.fspath(ross_file), _scene_file(base, work), int(left), int(right)),
                        "import-ross")
    return scene(text)


def scene_matrices(scene_, out) -> str:
    """Writes the full M, C, K, G of a flexible scene's structure to `out` (FILE.h5, or a
    directory of MatrixMarket files), as ``rubcont scene matrices``; returns the
    [flexible.matrices] section that reads them back."""
    with tempfile.TemporaryDirectory(prefix="rubcont-") as work:
        return _text_of(_core().scene_matrices(_scene_file(scene_, work), os.fspath(out)), "scene matrices")


def continue_from(point: SpecialPoint, result: Result, out=None, progress=None) -> OrbitFamily:
    """The family continued from a special point of `result`, as the library can start one: the
    modulated orbits from a Hopf point of the tanh-law rotating waves (/orbits/rotating_waves of an
    orbits result; the stage follows the Hopf points bounding a stable piece of a wave, and the
    family born at this one is returned). Any other start raises ValueError naming the point's
    type: a fold, an event, a branch point of a rotating wave, or a Hopf point of the exact law's
    branches have no continuation the library can start there (a branch point of an orbit family
    is followed by the orbits stage itself, [analysis.orbits] branch_points = "follow")."""
    where = point.owner
    if point.type != "Hopf":
        raise ValueError(f"continue_from: a {point.type!r} point ({point.label or where}, "
                         f"{point.speed_rpm:.6g} rpm) cannot start a continuation: the library "
                         f"starts orbit families from Hopf points only")
    if not where.startswith("orbits/rotating_waves/"):
        raise ValueError(f"continue_from: the Hopf point at {point.speed_rpm:.6g} rpm lies on "
                         f"/{where}; the orbits stage starts from the Hopf points of the tanh-law "
                         f"rotating waves (/orbits/rotating_waves/* of rubcont.orbits(scene))")
    waves = [Branch(result, f"orbits/rotating_waves/{n}") for n in result.groups("orbits/rotating_waves")]
    count = sum(1 for w in waves for p in w.special_points if p.type == "Hopf")
    scene_ = result.scene.with_values({"analysis": {"stages": ["orbits"], "orbits": {"hopf_points": count}}})
    again = orbits(scene_, out=out, progress=progress)
    for family in again.orbit_families:
        born = family.attrs.get("hopf_speed_rpm")
        if born is not None and abs(float(born) - point.speed_rpm) <= 1e-6 * max(1.0, abs(point.speed_rpm)):
            return family
    raise ValueError(f"continue_from: no family starts at the Hopf point at {point.speed_rpm:.6g} rpm "
                     f"(the stage follows only the Hopf points that bound a stable piece of a wave; "
                     f"started: {[f.name for f in again.orbit_families]})")
