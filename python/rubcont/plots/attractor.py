"""Figure of an attractor scan (rubcont attractor): what the motion is, speed by speed.

Usage: python3 -m rubcont.plots.attractor RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/attractor_command.h):
  OUTDIR/<file stem>.png  top left: the Poincaré section against speed (a bifurcation diagram):
                          the normal force at every penetration maximum of each contact (one per
                          modulation or impact); top right: the leading Lyapunov exponents with
                          3 standard errors, the band within which an exponent counts as zero
                          shaded, and the verdict at each speed; bottom left: return maps
                          (N_j, N_j+1) of the first contact, coloured by speed; bottom right: the
                          running estimate of the largest exponent against counted time.
From Python: ``figure(f)`` returns the Figure.
"""
import sys

import matplotlib.pyplot as plt
import numpy as np

from .common import MissingData, command_line, one_figure, new_figure, text

DPI = 120

SIDES = ("tab:blue", "tab:red", "tab:green", "tab:purple")
# The verdicts of RubMotion (sweeps/rub_sweep.h), by how they begin (the longest match wins).
MOTION_COLOURS = {"relative periodic orbit": "tab:blue",
                  "relative periodic orbit near a bifurcation": "tab:purple",
                  "relative periodic orbit, period": "tab:cyan", "relative 2-torus": "tab:orange",
                  "chaotic": "tab:red", "unsettled": "tab:gray", "rotating wave": "tab:green",
                  "equilibrium": "0.6"}


def kind(motion):
    """The key of MOTION_COLOURS that a verdict begins with (the longest), or the verdict itself."""
    keys = [k for k in MOTION_COLOURS if motion.startswith(k)]
    return max(keys, key=len) if keys else motion


def figure(f, fig=None):
    """The figure of the file's /attractor."""
    if "attractor" not in f:
        raise MissingData("no /attractor group")
    g = f["attractor"]
    a = g.attrs
    speed = g["speed_rpm"][()]
    exponents = g["exponents"][()]
    errors = g["standard_errors"][()]
    motion = [text(m) for m in g["motion"][()]]
    contacts = sorted(k[len("section_speed_rpm_"):] for k in g if k.startswith("section_speed_rpm_"))
    fig = new_figure(fig, figsize=(12.0, 8.5))
    axes = fig.subplots(2, 2)

    ax = axes[0, 0]
    for side, colour in zip(contacts, SIDES):
        ax.scatter(g[f"section_speed_rpm_{side}"][()], g[f"section_normal_force_{side}"][()], s=2,
                   color=colour, alpha=0.5, label=f"{side} contact", rasterized=True)
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel("normal force at each penetration maximum [N]")
    ax.set_title("Poincaré section (one point per modulation or impact)", fontsize=10)
    ax.legend(fontsize=8, markerscale=4)
    ax.grid(alpha=0.3)

    ax = axes[0, 1]
    band = a["zero_tolerance"]
    ax.axhspan(-band, band, color="0.9", zorder=0, label=f"|λ| ≤ {band:g}/s: zero")
    for j in range(exponents.shape[1]):
        ax.errorbar(speed, exponents[:, j], yerr=3 * errors[:, j], fmt="o-", ms=3, lw=0.8, capsize=2,
                    label=f"λ{j + 1}")
    top = np.nanmax(exponents + 3 * errors) if exponents.size else 1.0
    kinds = [kind(m) for m in motion]
    for s, k in zip(speed, kinds):
        ax.plot(s, top * 1.1 + 1.0, "s", ms=6, color=MOTION_COLOURS.get(k, "k"))
    for k, colour in MOTION_COLOURS.items():
        if k in kinds:
            ax.plot([], [], "s", color=colour, label=k)
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel("Lyapunov exponent [1/s] (± 3 standard errors)")
    ax.set_title("leading exponents and the verdict (squares)", fontsize=10)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)

    ax = axes[1, 0]
    if contacts:
        side = contacts[0]
        s = g[f"section_speed_rpm_{side}"][()]
        force = g[f"section_normal_force_{side}"][()]
        same = s[1:] == s[:-1]
        points = ax.scatter(force[:-1][same], force[1:][same], c=s[:-1][same], s=3, cmap="viridis",
                            rasterized=True)
        fig.colorbar(points, ax=ax, label="running speed [rpm]")
        ax.set_xlabel(f"N at maximum j, {side} contact [N]")
        ax.set_ylabel("N at maximum j + 1 [N]")
    ax.set_title("return maps: a point is periodic, a closed curve a torus, a cloud chaos", fontsize=10)
    ax.grid(alpha=0.3)

    ax = axes[1, 1]
    colours = plt.cm.viridis(np.linspace(0.0, 1.0, max(len(speed), 1)))
    for i, s in enumerate(speed):
        key = f"running/{i}"
        if key in g and g[key].shape[1] > 0:
            ax.plot(g[f"running/{i}_time_s"][()], g[key][0], color=colours[i], lw=0.8,
                    label=f"{s:g} rpm" if i in (0, len(speed) - 1) else None)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("counted time [s]")
    ax.set_ylabel("running estimate of λ1 [1/s]")
    ax.set_title("convergence of the largest exponent", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)

    fig.suptitle(f"{text(f.attrs['scene_name'])}: {len(speed)} speed(s) after the {text(a['direction'])} "
                 f"sweep to {a['approach_to_rpm']:g} rpm; {a['discard']:g} s discarded + {a['duration']:g} s "
                 f"counted per speed, {text(a['integrator'])} at rtol {a['relative_tolerance']:g}",
                 fontsize=10)
    fig.tight_layout()
    return fig


figures = one_figure(figure)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
