"""Figures of periodic-orbit branches (L2, shooting): amplitude and multipliers against the
continuation parameter.

Usage: python3 -m rubcont.plots.orbits RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/orbit_output.h):
  OUTDIR/orbits.png  top: the orbit's extent (its amplitude or mean radius where the branch has
                     that measure, else the max and min of its first state)
                     against the parameter, stable solid and unstable dashed, special points
                     marked; bottom: the largest Floquet multiplier modulus (log scale) with the
                     unit circle |mu| = 1 drawn in.
From Python: ``figure(f)`` returns the Figure.
"""
import sys

import h5py
import numpy as np

from .common import MissingData, command_line, one_figure, new_figure, text

DPI = 130

MARKERS = {"fold": ("^", "fold"), "period doubling": ("v", "period doubling"),
           "Neimark-Sacker": ("*", "Neimark–Sacker"), "branch point": ("X", "branch point"),
           "multiplier +1": ("D", "multiplier +1"), "grazing": ("s", "grazing")}


def segments_by_stability(x, y, stable):
    """Consecutive runs of equal stability, each extended by one point so that runs touch."""
    runs, start = [], 0
    for i in range(1, len(x) + 1):
        if i == len(x) or stable[i] != stable[start]:
            end = min(i + 1, len(x))
            runs.append((x[start:end], y[start:end], stable[start]))
            start = i
    return runs


def figure(f, fig=None):
    """The figure of the file's /branches group."""
    if "branches" not in f:
        raise MissingData("no /branches group")
    fig = new_figure(fig, figsize=(8, 7))
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    scene = text(f.attrs.get("scene_name", ""))
    seen = set()
    for name, group in f["branches"].items():
        if not isinstance(group, h5py.Group) or text(group.attrs.get("kind", "")) != "periodic_orbit":
            continue
        pname = text(group.attrs["parameter_name"])
        p = group[pname][()]
        stable = group["stable"][()]
        if "mean_radius" in group:
            curves = ["mean_radius"]
        elif "amplitude_x" in group:
            curves = ["amplitude_x"]
        else:
            state = "x" if "max_x" in group else "x0"
            curves = [f"max_{state}", f"min_{state}"]
        for dataset in curves:
            for xs, ys, s in segments_by_stability(p, group[dataset][()], stable):
                top.plot(xs, ys, "-" if s == 1 else "--", color="#1f5fa8" if s == 1 else "#c0392b",
                         lw=1.5)
        bottom.semilogy(p, group["max_multiplier_modulus"][()], color="#444444", lw=1.2)
        sp = group["special_points"]
        types = [text(t) for t in sp["type"][()]]
        sp_p = sp[pname][()]
        for k, t in enumerate(types):
            marker, label = MARKERS.get(t, ("o", t))
            y = sp[curves[0]][()][k] if curves[0] in sp else np.nan
            top.plot(sp_p[k], y, marker, color="black", ms=8,
                     label=label if label not in seen else None)
            bottom.axvline(sp_p[k], color="#999999", lw=0.8, ls=":")
            seen.add(label)
    top.plot([], [], "-", color="#1f5fa8", label="stable")
    top.plot([], [], "--", color="#c0392b", label="unstable")
    top.set_ylabel(" / ".join(curves).replace("_", " "))
    top.set_title(f"{scene}: periodic orbits (shooting, Floquet stability)")
    top.legend(loc="best", fontsize=8)
    top.grid(alpha=0.3)
    bottom.axhline(1.0, color="black", lw=0.8)
    bottom.set_ylabel("max |Floquet multiplier|")
    bottom.set_xlabel(pname)
    bottom.grid(alpha=0.3, which="both")
    fig.tight_layout()
    return fig


figures = one_figure(figure, "orbits")

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
