"""Figure of the modulated whirl and whip (L2, shooting) over the rotating waves they are born from.

Usage: python3 -m rubcont.plots.rub_orbits RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/orbits_stage.h):
  OUTDIR/orbits.png  against running speed, over the speeds around the orbits:
                     top: precession frequency (±25 Hz around the orbits) — the tanh-law
                     rotating waves (stable solid,
                     unstable dashed, special points marked) and, for each family of modulated
                     orbits, its carrier (thick) and the band of instantaneous precession at the
                     first contact (thin);
                     middle: normal force at the first contact — rotating waves, and the min/max
                     over each orbit;
                     then the largest Floquet multiplier modulus of the orbits, |mu| = 1 drawn;
                     bottom (left–right symmetric rotors): the orbits' asymmetry (0 on orbits
                     whose two contacts move alike, /orbits/<family>/asymmetry).
                     Families from a Hopf point start at a filled circle, the branches followed
                     from a branch point (<family>_bp<k>) at a cross, the family through a
                     transient's orbit (/orbits/transient) at a filled square. The speeds shown
                     reach 10 rpm beyond the orbits, or, where no family starts at a Hopf point,
                     a quarter of their span (a locked family spans tenths of an rpm).
From Python: ``figure(f)`` returns the Figure.
"""
import sys

import h5py
import numpy as np
from matplotlib.lines import Line2D

from .branches import (MARKERS, MODE_COLORS, contacts_of, mark, plot_lines, special_points,
                       stable_runs)
from .common import MissingData, command_line, one_figure, keep_inside, new_figure, text

DPI = 130

ORBIT_COLORS = ["#000000", "#7b2cbf", "#b8860b", "#008b8b"]
ORBIT_MARKERS = {"fold": "^", "period doubling": "v", "Neimark-Sacker": "*",
                 "branch point": "X", "multiplier +1": "D", "grazing": "s"}


def orbit_special_points(group):
    sp = group["special_points"]
    if "type" not in sp or len(sp["type"]) == 0:
        return []
    return [(text(t), float(r), k) for k, (t, r) in enumerate(zip(sp["type"][()], sp["speed_rpm"][()]))]


START_KEYS = (("hopf_speed_rpm", "hopf_precession_hz"),
              ("transient_speed_rpm", "start_carrier_hz"),
              ("branch_point_speed_rpm", "branch_point_precession_hz"))


def start_of(group):
    """Where a family starts (speed [rpm], carrier [Hz], attribute kind): its Hopf point, the
    transient's orbit, or the branch point it was followed from."""
    for speed, precession in START_KEYS:
        if speed in group.attrs:
            return float(group.attrs[speed]), float(group.attrs[precession]), speed
    return 0.0, float("nan"), ""


def start_speed(group):
    return start_of(group)[0]


def figure(f, fig=None):
    """The figure of the file's /orbits/rotating_waves group."""
    if "orbits" not in f or "rotating_waves" not in f["orbits"]:
        raise MissingData("no /orbits/rotating_waves group")
    group = f["orbits"]
    waves = [(n, g) for n, g in group["rotating_waves"].items()
             if isinstance(g, h5py.Group) and "speed_rpm" in g]
    orbits = [(n, g) for n, g in group.items()
              if isinstance(g, h5py.Group) and text(g.attrs.get("kind", "")) == "periodic_orbit"]
    contact = contacts_of(waves[0][1])[0] if waves else "left"

    # Speeds shown: around the Hopf points followed and the orbits.
    speeds = [start_speed(g) for _, g in orbits]
    speeds += [v for _, g in orbits for v in g["speed_rpm"][()]]
    from_hopf = any(start_of(g)[2] == "hopf_speed_rpm" for _, g in orbits)
    margin = (10.0 if from_hopf else max(0.05, 0.25 * (max(speeds) - min(speeds)))) if speeds else 0.0
    lo, hi = (min(speeds) - margin, max(speeds) + margin) if speeds else (None, None)

    symmetric = any("asymmetry" in g for _, g in orbits)
    ratios = [3, 2, 1.2] + ([1.2] if symmetric else [])
    fig = new_figure(fig, figsize=(9, 10 + 1.5 * symmetric))
    axes = fig.subplots(len(ratios), 1, sharex=True, gridspec_kw={"height_ratios": ratios})
    top, middle, bottom = axes[:3]
    modes, types = set(), set()
    for _, g in waves:
        mode = text(g.attrs.get("mode", "mode1"))
        color = MODE_COLORS.get(mode, "#1f5fa8")
        modes.add(mode)
        rpm, stable = g["speed_rpm"][()], g["stable"][()]
        plot_lines(top, rpm, g["precession_hz"][()], stable, color)
        plot_lines(middle, rpm, g[f"normal_force_{contact}"][()], stable, color)
        points = special_points(g)
        types.update(p["type"] for p in points)
        mark(top, points, "rpm", lambda p: p["hz"], color)

    handles = []
    for k, (name, g) in enumerate(sorted(orbits, key=lambda item: start_speed(item[1]))):
        color = ORBIT_COLORS[k % len(ORBIT_COLORS)]
        rpm, stable = g["speed_rpm"][()], g["stable"][()]
        plot_lines(top, rpm, g["precession_hz"][()], stable, color)
        for side in ("min", "max"):
            for start, end, is_stable in stable_runs(stable):
                top.plot(rpm[start:end + 1], g[f"{side}_precession_hz_{contact}"][()][start:end + 1],
                         color=color, lw=0.7, alpha=0.6, ls="-" if is_stable else (0, (2, 2)))
            plot_lines(middle, rpm, g[f"{side}_normal_force_{contact}"][()], stable, color)
        bottom.semilogy(rpm, g["max_multiplier_modulus"][()], color=color, lw=1.2)
        if symmetric and "asymmetry" in g:
            axes[3].semilogy(rpm, np.maximum(g["asymmetry"][()], 1e-16), color=color, lw=1.2)
        start, start_hz, kind = start_of(g)
        from_hopf = kind == "hopf_speed_rpm"
        transient = kind == "transient_speed_rpm"
        top.plot(start, start_hz, "o" if from_hopf else "s" if transient else "X", ms=7,
                 mfc=color, mec=color)
        for t, r, i in orbit_special_points(g):
            y = g["special_points"]["precession_hz"][()][i]
            top.plot(r, y, ORBIT_MARKERS.get(t, "P"), ms=8, mfc="white", mec=color, mew=1.4, zorder=6)
            bottom.axvline(r, color=color, lw=0.8, ls=":")
            types.add(t)
        doubled = "period_doubling_multiplier" in g.attrs
        laps = int(g.attrs.get("laps", 1))
        origin = (f"the Hopf point at {start:.2f} rpm" if from_hopf else
                  f"the transient's orbit at {start:.2f} rpm"
                  + (f" ({laps} modulation periods: locked)" if laps > 1 else "") if transient else
                  f"the period doubling at {start:.2f} rpm (period 2T)" if doubled else
                  f"the branch point at {start:.2f} rpm"
                  + (", one of two mirror images" if "mirror" in text(g.attrs.get("branch_point_note", ""))
                     else ""))
        handles.append(Line2D([], [], color=color, lw=1.6,
                              label=f"modulated orbits from {origin} "
                                    f"({g['speed_rpm'][()].size} orbits)"))

    handles += [Line2D([], [], color=MODE_COLORS[m], lw=1.6, label=f"rotating wave ({m})")
                for m in sorted(modes)]
    handles += [Line2D([], [], color="0.2", lw=1.6, label="stable"),
                Line2D([], [], color="0.2", lw=1.0, ls=(0, (4, 2)), label="unstable")]
    for t in sorted(types):
        marker = ORBIT_MARKERS.get(t) or MARKERS.get(t, ("P", t))[0]
        handles.append(Line2D([], [], ls="none", marker=marker, mfc="white", mec="0.2", label=t))
    top.legend(handles=handles, loc="best", fontsize=7)
    scene = text(f.attrs.get("scene_name", ""))
    eps = group.attrs.get("velocity_scale", float("nan"))
    top.set_title(f"{scene}: rotating waves and modulated orbits (tanh friction, ε = {eps:g} m/s)")
    top.set_ylabel(f"precession [Hz] (band: {contact} contact)")
    middle.set_ylabel(f"normal force, {contact} contact [N]")
    bottom.axhline(1.0, color="black", lw=0.8)
    bottom.set_ylabel("max |Floquet multiplier|")
    if symmetric:
        axes[3].set_ylabel("asymmetry\n(left–right)")
        axes[3].set_ylim(1e-13, 1.0)
    axes[-1].set_xlabel("running speed [rpm]")
    if lo is not None:
        axes[-1].set_xlim(lo, hi)
        band = [v for _, g in orbits for key in (f"min_precession_hz_{contact}",
                                                 f"max_precession_hz_{contact}")
                for v in g[key][()] if np.isfinite(v)]
        band += [float(g.attrs["hopf_precession_hz"]) for _, g in orbits if "hopf_precession_hz" in g.attrs]
        top.set_ylim(min(band) - 25.0, max(band) + 25.0)
        _fit_y(middle, waves, orbits, lo, hi, f"normal_force_{contact}",
               [f"min_normal_force_{contact}", f"max_normal_force_{contact}"])
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    if keep_inside(fig, top.title):
        fig.tight_layout()
    return fig


figures = one_figure(figure, "orbits")

main = command_line(figures, DPI, __doc__, __spec__.name)


def _fit_y(ax, waves, orbits, lo, hi, wave_key, orbit_keys):
    """y-limits from what lies in [lo, hi] only."""
    values = []
    for _, g in waves:
        rpm = g["speed_rpm"][()]
        values.extend(g[wave_key][()][(rpm >= lo) & (rpm <= hi)])
    for _, g in orbits:
        for key in orbit_keys:
            values.extend(g[key][()])
    values = np.asarray([v for v in values if np.isfinite(v)])
    if values.size:
        pad = 0.05 * (values.max() - values.min() + 1e-9)
        ax.set_ylim(values.min() - pad, values.max() + pad)


if __name__ == "__main__":
    sys.exit(main())
