"""rubcont's figures: one module per kind of result, each drawing from an open h5py file.

Every module has ``figures(f, stem)`` — the (name, Figure) pairs the command line saves as
``<name>.<format>`` — drawing functions that take the file (or a group) and an optional Figure to
draw into and return the Figure, and ``main``: ``python3 -m rubcont.plots.<module> FILE.h5 OUTDIR
[--format png|pdf|svg]`` is what the executable runs after writing a result (apps/figures.h)::

    import h5py
    from rubcont.plots import branches
    with h5py.File("results/thesis_A_a/thesis_A_a.h5") as f:
        fig = branches.precession_figure(f)

The modules: analytic (L0), branches (L1), orbits (L2 of the oscillator models), rub_orbits and
rub_tori (L2 of the rub models), sweep, ensemble, lifetime, attractor (L3), map, loop; and, from
files other than one result, hysteresis (a sweep with its orbits and lifetime files),
regularization and work_precision (the benchmarks' CSV files).
"""
from __future__ import annotations

import importlib
from typing import Any, Iterator

from .common import FORMATS, MissingData, text

__all__ = ["FORMATS", "MissingData", "modules_for", "figures", "text"]


def _has_periodic_orbits(f: Any) -> bool:
    return "branches" in f and any(
        text(group.attrs.get("kind", "")) == "periodic_orbit" for group in f["branches"].values()
        if hasattr(group, "attrs"))


# The module drawing each kind of group a result file may hold, in the order the command line
# draws them (apps/commands.cpp, apps/*_command.cpp).
_RULES = (
    ("analytic", lambda f: "analytic" in f),
    ("sweep", lambda f: "sweeps" in f),
    ("branches", lambda f: "branches" in f and not _has_periodic_orbits(f)),
    ("orbits", _has_periodic_orbits),
    ("rub_orbits", lambda f: "orbits" in f and "rotating_waves" in f["orbits"]),
    ("rub_tori", lambda f: "tori" in f),
    ("loop", lambda f: "loop" in f),
    ("map", lambda f: "maps" in f),
    ("ensemble", lambda f: "ensemble" in f),
    ("lifetime", lambda f: "lifetime" in f),
    ("attractor", lambda f: "attractor" in f),
)


def modules_for(f: Any) -> list[str]:
    """The modules that draw what the open file `f` holds, as the command line picks them."""
    return [name for name, applies in _RULES if applies(f)]


def figures(f: Any, stem: str = "") -> Iterator[tuple[str, Any]]:
    """Every figure the command line draws from the open file `f`, as (name, Figure) pairs."""
    for name in modules_for(f):
        module = importlib.import_module(f"{__name__}.{name}")
        yield from module.figures(f, stem)
