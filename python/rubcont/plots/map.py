"""Figure of a hysteresis map (rubcont map): regions in (running speed, design parameter).

Usage: python3 -m rubcont.plots.map RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/map_command.h), for every /maps/<parameter>:
  OUTDIR/map_<parameter>.png  the number of coexisting stable circular rub states on the grid
                              (all families, then the Mode 1 and Mode 2 families alone)
                              (grey: none, white: one, blue: two or more = hysteresis), the special
                              points of the branch sets at every grid value (markers), and the
                              continued event, fold and Hopf curves (lines; cusps, Bogdanov-
                              Takens, zero-Hopf, double-Hopf and generalized Hopf points
                              marked).
From Python: ``map_figure(f["maps"]["friction"], "friction")`` returns the Figure.
"""
import sys

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap, BoundaryNorm

from .common import MissingData, command_line, keep_inside, new_figure, text

DPI = 120

MARKERS = {"event": ("o", "stick/slip switch or contact change"),
           "non_smooth_fold": ("s", "non-smooth fold"),
           "fold": ("^", "fold"), "Hopf": ("*", "Hopf"),
           "real eigenvalue crossing": ("D", "real eigenvalue crossing")}


# Codimension-two points on the continued curves (and where a Hopf curve meets a switch).
CURVE_POINT_MARKERS = {"cusp": "P", "Bogdanov-Takens": "^", "zero-Hopf": "s", "double Hopf": "h",
                       "generalized Hopf": "v", "event": "o"}


def draw_panel(ax, group, count, title, pattern=None):
    eta = group["eta"][()]
    speed = group["speed_rpm"][()]
    cmap = ListedColormap(["#666666", "#c8c8c8", "#ffffff", "#8fbbe6"])
    norm = BoundaryNorm([-1.5, -0.5, 0.5, 1.5, 2.5], cmap.N)
    ax.pcolormesh(speed, eta, np.minimum(count, 2), cmap=cmap, norm=norm, shading="nearest")
    points = group["points"]
    if pattern is None and len(points["eta"]) > 0:
        types = [text(t) for t in points["type"][()]]
        for kind, (marker, label) in MARKERS.items():
            sel = np.array([t == kind for t in types])
            if sel.any():
                ax.plot(points["speed_rpm"][()][sel], points["eta"][()][sel], marker, ms=3,
                        mfc="none", color="0.35", label=label, linestyle="none")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    turns = ([], [])
    for index, curve_name in enumerate(sorted(group["curves"].keys(), key=lambda s: int(s[5:]))):
        curve = group["curves"][curve_name]
        if len(curve["eta"]) == 0:
            continue
        if pattern is not None and text(curve.attrs.get("pattern", "")) != pattern:
            continue
        color = colors[index % len(colors)]
        kind = text(curve.attrs["kind"])
        label = (f"{curve_name} ({text(curve.attrs.get('pattern', ''))}): {kind} "
                 f"\"{text(curve.attrs['label'])}\"")
        style = {"event": "-", "fold": "--", "hopf": "-."}.get(kind, ":")
        ax.plot(curve["speed_rpm"][()], curve["eta"][()], style, color=color, lw=1.3, label=label)
        sp = curve["special_points"]
        for t, e, s in zip(sp["type"][()], sp["eta"][()], sp["speed_rpm"][()]):
            marker = CURVE_POINT_MARKERS.get(text(t))
            if marker is not None and (kind == "hopf" or text(t) != "event"):
                ax.plot(s, e, marker, color="k", ms=8, mfc="none", mew=1.2)
        if "extrema" in curve and len(curve["extrema"]["eta"]) > 0:
            turns[0].extend(curve["extrema"]["speed_rpm"][()])
            turns[1].extend(curve["extrema"]["eta"][()])
    if turns[0]:
        ax.plot(turns[0], turns[1], "kX", ms=7, linestyle="none",
                label="turning point of a jump curve (the jump disappears)")
    ax.axhline(group.attrs["base_value"], color="k", lw=0.6, ls=":")
    ax.set_xlim(speed[0], speed[-1])
    ax.set_ylim(eta[0], eta[-1])
    ax.set_xlabel("running speed [rpm]")
    ax.set_title(title, fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=5.5, loc="upper right", framealpha=0.85)


def map_figure(group, name, fig=None):
    """The map of one /maps/<name> group."""
    unit = text(group.attrs.get("unit", ""))
    panels = [(group["stable_count"][()], "all circular rub states", None)]
    for pattern, title in (("mode1", "Mode 1 family only (what a sweep from a Mode 1 whirl follows)"),
                           ("mode2", "Mode 2 family only")):
        if "by_pattern" in group and pattern in group["by_pattern"]:
            panels.append((group["by_pattern"][pattern]["stable_count"][()], title, pattern))
    fig = new_figure(fig, figsize=(6.5 * len(panels), 6.5))
    axes = fig.subplots(1, len(panels), squeeze=False)
    for ax, (count, title, pattern) in zip(axes[0], panels):
        draw_panel(ax, group, count, title, pattern)
    axes[0][0].set_ylabel(f"{name} [{unit}]")
    title = (f"Hysteresis map ({text(group.attrs.get('level', 'L1'))}, "
             f"{text(group.attrs.get('friction_law', ''))} friction): white one stable circular "
             "state, blue two or more coexisting (hysteresis), light grey none, dark grey failed; "
             f"lines: continued switch (solid), fold (dashed) and Hopf (dash-dot) curves, their "
             f"codimension-two points (black: + cusp, △ Bogdanov-Takens, □ zero-Hopf, ⬡ double "
             f"Hopf, ▽ generalized Hopf, ○ a Hopf curve meets a switch); grey markers: special "
             f"points of the branch set at each grid value; dotted: scene value "
             f"{group.attrs['base_value']:g}")
    keep_inside(fig, fig.suptitle(title, fontsize=9))
    fig.tight_layout()
    return fig


def figures(f, stem=""):
    """map_<parameter> for every /maps/<parameter>."""
    if "maps" not in f:
        raise MissingData("no /maps group")
    for name in f["maps"]:
        yield f"map_{name}", map_figure(f["maps"][name], name)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
