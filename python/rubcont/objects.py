"""The objects of a result: branches with their special points, sweeps, loops, orbit and torus
families, each over the arrays of a :class:`rubcont.Result` (docs/result_files.md) and drawn by
:mod:`rubcont.plots` (the code of the command line's figures).

    result = rubcont.branches("scenes/thesis_A_a.toml")
    branch = result.branches[1]
    branch.special_points[0]          # SpecialPoint(type='event', speed_rpm=50.689, ...)
    fig = branch.plot()
"""
from __future__ import annotations

import html
import io
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Optional

import numpy as np

if TYPE_CHECKING:
    from . import Result

# Columns of a special-point table that say what the point is (the rest are its state).
_POINT_IDENTITY = ("type", "label", "speed_rpm", "precession_hz", "frequency_hz", "note")


@dataclass(frozen=True)
class SpecialPoint:
    """A located point on a branch or family: its type ("event", "fold", "Hopf", "branch
    point", "period doubling", "Neimark-Sacker", ...), label, running speed [rpm], frequency [Hz]
    (the precession of a rotating wave, the modulation of an orbit) and `state`: every other
    quantity stored for it (forces, penetrations, slip velocities, modes, multipliers, ...)."""

    type: str
    label: str
    speed_rpm: float
    frequency_hz: float
    state: dict = field(repr=False)
    owner: str = ""  # the group of the branch or family, e.g. "branches/branch2"
    index: int = 0   # the row of its table

    @property
    def nonsmooth_fold(self) -> bool:
        return bool(self.state.get("nonsmooth_fold", False))


class _Group:
    """The arrays and attributes of one group of a Result."""

    kind = "group"

    def __init__(self, result: "Result", path: str):
        self.result = result
        self.path = path.strip("/")
        self.name = self.path.rsplit("/", 1)[-1]

    @property
    def attrs(self) -> dict:
        return self.result.attrs(self.path)

    def keys(self) -> list[str]:
        """The datasets directly in the group."""
        prefix = self.path + "/"
        return [k[len(prefix):] for k in self.result.keys()
                if k.startswith(prefix) and "/" not in k[len(prefix):]]

    def __getitem__(self, key: str) -> np.ndarray:
        return self.result[f"{self.path}/{key}"]

    def __contains__(self, key: str) -> bool:
        return f"{self.path}/{key}" in self.result

    @property
    def speed_rpm(self) -> np.ndarray:
        return self["speed_rpm"]

    def _open(self):
        return self.result._h5()

    def _table_rows(self) -> list[tuple[str, str]]:
        return []

    def _repr_html_(self) -> str:
        rows = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>"
                       for k, v in [("group", "/" + self.path)] + self._table_rows())
        return f"<b>rubcont.{type(self).__name__}</b> {html.escape(self.name)}<table>{rows}</table>"

    def __repr__(self) -> str:
        return f"<rubcont.{type(self).__name__} /{self.path}>"


def _points(group: _Group, frequency_key: str) -> list[SpecialPoint]:
    table = f"{group.path}/special_points"
    if f"{table}/type" not in group.result:
        return []
    columns = {k[len(table) + 1:]: group.result[k] for k in group.result.keys()
               if k.startswith(table + "/") and "/" not in k[len(table) + 1:]}
    points = []
    for i, kind in enumerate(columns["type"]):
        state = {k: v[i] for k, v in columns.items() if k not in _POINT_IDENTITY and len(v) > i}
        kind = str(kind)
        if kind == "event" and bool(state.get("nonsmooth_fold", False)):
            kind = "non_smooth_fold"
        frequency = columns[frequency_key][i] if frequency_key in columns else np.nan
        points.append(SpecialPoint(type=kind, label=str(columns.get("label", [""] * (i + 1))[i]),
                                   speed_rpm=float(columns["speed_rpm"][i]),
                                   frequency_hz=float(frequency), state=state, owner=group.path,
                                   index=i))
    return points


def _axes(ax, figsize=(8, 5)):
    """(fig, ax): the given Axes and its Figure, or a new pyplot Figure with one Axes."""
    from .plots.common import new_figure

    if ax is not None:
        return ax.figure, ax
    fig = new_figure(None, figsize=figsize)
    return fig, fig.subplots()


class Branch(_Group):
    """A rotating-wave branch (L1): speed, precession frequency, stability and the per-contact
    arrays of /branches/branchN (or /orbits/rotating_waves/branchN, /sweeps/branches/branchN)."""

    kind = "rotating_wave"

    @property
    def precession_hz(self) -> np.ndarray:
        return self["precession_hz"]

    @property
    def stable(self) -> np.ndarray:
        """True where the wave is stable (the file's coded `stable` as booleans)."""
        return self["stable"].astype(bool)

    @property
    def mode(self) -> str:
        return str(self.attrs.get("mode", ""))

    @property
    def special_points(self) -> list[SpecialPoint]:
        return _points(self, "precession_hz")

    def plot(self, ax=None):
        """Precession against speed (stable solid, unstable dashed, special points marked),
        on `ax` or a new Figure; returns the Figure."""
        from .plots import branches

        fig, ax = _axes(ax)
        with self._open() as f:
            branches.draw_branch(ax, f[self.path])
        ax.set_xlabel("running speed ω [rpm]")
        ax.set_ylabel("backward precession frequency Ω/2π [Hz]")
        return fig

    def _table_rows(self):
        s = self.speed_rpm
        return [("mode", self.mode), ("points", str(len(s))),
                ("speed", f"{s.min():.4g} … {s.max():.4g} rpm" if len(s) else "—"),
                ("stable points", str(int(self.stable.sum()))),
                ("special points", ", ".join(f"{p.type} {p.speed_rpm:.4g} rpm" for p in self.special_points)
                 or "none"), ("status", str(self.attrs.get("status", "")))]


class OrbitFamily(_Group):
    """A family of periodic orbits (L2): /orbits/<family> of the rub models (modulated whirl and
    whip: modulation frequency, Floquet stability) or /branches/branchN of kind periodic_orbit."""

    kind = "periodic_orbit"

    @property
    def stable(self) -> np.ndarray:
        return self["stable"].astype(bool)

    @property
    def modulation_hz(self) -> np.ndarray:
        return self["modulation_hz"] if "modulation_hz" in self else 1.0 / self["period"]

    @property
    def special_points(self) -> list[SpecialPoint]:
        return _points(self, "modulation_hz")

    def plot(self, ax=None):
        """The carrier precession (or the first measure) against speed, on `ax` or a new Figure."""
        from .plots.branches import plot_lines

        fig, ax = _axes(ax)
        y_key = "precession_hz" if "precession_hz" in self else "max_multiplier_modulus"
        x_key = "speed_rpm" if "speed_rpm" in self else str(self.attrs.get("parameter_name", ""))
        plot_lines(ax, self[x_key], self[y_key], self["stable"], "#7b2cbf")
        for p in self.special_points:
            ax.plot(p.speed_rpm, self[y_key][int(p.state.get("point_index", 0))], "*", ms=9,
                    mfc="white", mec="black")
        ax.set_xlabel("running speed [rpm]" if x_key == "speed_rpm" else x_key)
        ax.set_ylabel(y_key.replace("_", " "))
        ax.set_title(f"orbit family {self.name}", fontsize=10)
        return fig

    def _table_rows(self):
        s = self["speed_rpm"] if "speed_rpm" in self else np.array([])
        start = {k: v for k, v in self.attrs.items() if k.endswith("_speed_rpm")}
        return [("orbits", str(len(self["stable"]))),
                ("speed", f"{s.min():.4g} … {s.max():.4g} rpm" if len(s) else "—"),
                ("start", ", ".join(f"{k} {v:.4g}" for k, v in start.items()) or "—"),
                ("special points", ", ".join(f"{p.type} {p.speed_rpm:.4g} rpm" for p in self.special_points)
                 or "none")]


class TorusFamily(_Group):
    """A family of invariant 2-tori (L2 tori, /tori/<family>): the two frequencies, the
    rotation number and the stability by Lyapunov exponents (1, 0 or -1 undecided)."""

    kind = "torus"

    @property
    def rotation_number(self) -> np.ndarray:
        return self["rotation_number"]

    @property
    def stable(self) -> np.ndarray:
        return self["stable"]

    @property
    def special_points(self) -> list[SpecialPoint]:
        return _points(self, "first_hz")

    def plot(self, ax=None):
        """The two frequencies f1, f2 against speed (filled: stable), on `ax` or a new Figure."""
        from .plots.rub_tori import scatter_stable

        fig, ax = _axes(ax)
        scatter_stable(ax, self.speed_rpm, self["first_hz"], self["stable"], "#000000", "f1 = 1/T")
        scatter_stable(ax, self.speed_rpm, self["second_hz"], self["stable"], "#b8860b", "f2 = ρ/T")
        ax.set_xlabel("running speed [rpm]")
        ax.set_ylabel("modulation frequencies [Hz]")
        ax.legend(fontsize=8)
        return fig

    def _table_rows(self):
        rho = self.rotation_number
        return [("tori", str(len(rho))),
                ("rotation number", f"{np.nanmin(rho):.4g} … {np.nanmax(rho):.4g}" if len(rho) else "—")]


class Sweep(_Group):
    """The L3 sweeps of a file (/sweeps): each direction's speeds and per-contact arrays, the
    jump table, and the branches of the sweeps' friction law."""

    kind = "sweeps"

    @property
    def directions(self) -> list[str]:
        return [d for d in ("up", "down") if f"{self.path}/{d}/speed_rpm" in self.result]

    def direction(self, name: str) -> _Group:
        """The arrays of one direction ("up" or "down")."""
        if name not in self.directions:
            raise KeyError(f"no {name} sweep in this file (directions: {self.directions})")
        return _Group(self.result, f"{self.path}/{name}")

    @property
    def jumps(self) -> dict:
        """The jump table as columns (direction, speed_from_rpm, speed_to_rpm, bifurcation, ...)."""
        prefix = f"{self.path}/jump_table/"
        return {k[len(prefix):]: self.result[k] for k in self.result.keys() if k.startswith(prefix)}

    @property
    def branches(self) -> list[Branch]:
        return _branches_under(self.result, f"{self.path}/branches")

    def plot(self, ax=None):
        """BP of the sweeps over the branches (the left panel of sweep_precession), on `ax` or a
        new Figure."""
        from .plots import sweep

        fig, ax = _axes(ax, figsize=(9, 6))
        with self._open() as f:
            handles = sweep.draw_sweeps(f, ax)
            sweep.draw_branches(f, ax)
        ax.set_xlabel("running speed [rpm]")
        ax.set_ylabel("backward precession (BP) frequency [Hz]")
        ax.legend(handles=handles, fontsize=8, loc="upper left")
        return fig

    def _table_rows(self):
        rows = [(d, f"{len(self.direction(d).speed_rpm)} speeds") for d in self.directions]
        return rows + [("jumps", str(len(self.jumps.get("direction", []))))]


class Loop(_Group):
    """The explained hysteresis loop (/loop): its corners (the jumps with cause and level) and
    the run-up and run-down."""

    kind = "loop"

    @property
    def corners(self) -> dict:
        prefix = f"{self.path}/corners/"
        return {k[len(prefix):]: self.result[k] for k in self.result.keys() if k.startswith(prefix)}

    def plot(self, ax=None):
        """The loop figure (one page per contact; rubcont.plots.loop). `ax` must be None: the
        figure has its own layout."""
        from .plots import loop

        if ax is not None:
            raise ValueError("Loop.plot draws a page per contact: call it without ax")
        with self._open() as f:
            return loop.figure(f)

    def _table_rows(self):
        c = self.corners
        return [(f"corner {i + 1}", f"{c['direction'][i]} {c['kind'][i]} at {c['speed_rpm'][i]:.4g} rpm: "
                 f"{c['cause'][i]} ({c['level'][i]})") for i in range(len(c.get("direction", [])))]


def _branches_under(result: "Result", path: str) -> list[Branch]:
    names = [n for n in result.groups(path) if f"{path}/{n}/speed_rpm" in result
             and str(result.attrs(f"{path}/{n}").get("kind", "rotating_wave")) != "periodic_orbit"]
    return [Branch(result, f"{path}/{n}") for n in sorted(names, key=_numeric)]


def _numeric(name: str):
    digits = "".join(ch for ch in name if ch.isdigit())
    return (int(digits) if digits else 0, name)


def objects_of(result: "Result") -> dict[str, Any]:
    """Every object of a result, by kind: branches, orbit_families, torus_families, sweep, loop."""
    families = [OrbitFamily(result, f"orbits/{n}") for n in result.groups("orbits")
                if str(result.attrs(f"orbits/{n}").get("kind", "")) == "periodic_orbit"]
    families += [OrbitFamily(result, f"branches/{n}") for n in result.groups("branches")
                 if str(result.attrs(f"branches/{n}").get("kind", "")) == "periodic_orbit"]
    tori = [TorusFamily(result, f"tori/{n}") for n in result.groups("tori")
            if f"tori/{n}/rotation_number" in result]
    return {
        "branches": _branches_under(result, "branches"),
        "orbit_families": families,
        "torus_families": tori,
        "sweep": Sweep(result, "sweeps") if "sweeps" in result.groups() else None,
        "loop": Loop(result, "loop") if "loop" in result.groups() else None,
    }


# --- progress as events ------------------------------------------------------------------------

@dataclass(frozen=True)
class ProgressEvent:
    """One progress line as an event: the stage ("branches", "sweep up", "map", ...), how much
    is done of how much (None when the line gives no count) and the line itself."""

    stage: str
    done: Optional[int]
    total: Optional[int]
    line: str


_STAGE = __import__("re").compile(r"^(?:rubcont: )?\[([^\]]+)\]\s*(.*)$")
_COUNT = __import__("re").compile(r"\b(\d+)\s*(?:/|of)\s*(\d+)\b")


def parse_progress(line: str) -> ProgressEvent:
    """The event of a progress line ("rubcont: [sweep up] 3/6 44.0 rpm: ..." → ("sweep up", 3,
    6)); a line without a stage is stage ""."""
    match = _STAGE.match(line)
    stage, rest = (match.group(1), match.group(2)) if match else ("", line)
    count = _COUNT.search(rest)
    done, total = (int(count.group(1)), int(count.group(2))) if count else (None, None)
    return ProgressEvent(stage, done, total, line)


def events(callback: Callable[[ProgressEvent], Any]) -> Callable[[str], None]:
    """A `progress=` callback that hands each line to `callback` as a :class:`ProgressEvent`."""
    return lambda line: callback(parse_progress(line))


class TqdmProgress:
    """Progress bars (tqdm, Debian's python3-tqdm), one per stage that reports counts:
    ``rubcont.sweep(scene, progress=rubcont.TqdmProgress())``. Lines without a count go to
    tqdm.write. ImportError without tqdm."""

    def __init__(self, **tqdm_options: Any):
        from tqdm import tqdm  # optional: only this class needs it

        self._tqdm, self._options, self._bars = tqdm, tqdm_options, {}

    def __call__(self, line: str) -> None:
        event = parse_progress(line)
        if event.total is None:
            self._tqdm.write(line)
            return
        bar = self._bars.get(event.stage)
        if bar is None or bar.total != event.total:
            bar = self._bars[event.stage] = self._tqdm(total=event.total, desc=event.stage,
                                                       **self._options)
        bar.update(event.done - bar.n)

    def close(self) -> None:
        for bar in self._bars.values():
            bar.close()


def h5_of(data: bytes):
    """An h5py File over the bytes of a result (read-only)."""
    import h5py

    return h5py.File(io.BytesIO(data), "r")
