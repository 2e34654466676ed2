"""Figure of an ensemble (rubcont ensemble): how long the state a sweep reached lasts.

Usage: python3 -m rubcont.plots.ensemble RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/ensemble_command.h):
  OUTDIR/<file stem>.png  left: the share of copies not yet in the target regime against time
                          (a survival curve; copies that never arrive stay in it to the end);
                          right, per contact: the backward precession (BP) of every copy in each
                          stretch, coloured by the stretch's regime.
From Python: ``figure(f)`` returns the Figure.
"""
import sys

import numpy as np

from .common import MissingData, command_line, one_figure, new_figure, text

DPI = 120

# RubRegime codes (sweeps/rub_sweep.h) and their colours.
REGIMES = {0: ("unknown", "0.5"), 1: ("no contact", "tab:gray"), 2: ("intermittent", "tab:orange"),
           3: ("whirl", "tab:blue"), 4: ("whip", "tab:red")}


def figure(f, fig=None):
    """The figure of the file's /ensemble."""
    if "ensemble" not in f:
        raise MissingData("no /ensemble group")
    g = f["ensemble"]
    a = g.attrs
    time = g["time_s"][()]
    arrival = g["arrival_time_s"][()]
    contacts = sorted(k[len("precession_hz_"):] for k in g if k.startswith("precession_hz_"))
    fig = new_figure(fig, figsize=(5.0 + 4.5 * len(contacts), 4.2))
    axes = fig.subplots(1, 1 + len(contacts))
    ax = axes[0]
    copies = len(arrival)
    grid = np.concatenate([[0.0], time])
    alive = [np.sum(~(arrival <= t)) / copies for t in grid]
    ax.step(grid, alive, where="post", color="k")
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel("time at this speed [s]")
    ax.set_ylabel(f"share of copies not yet {text(a['arrival'] if 'arrival' in a else a['until'])}")
    ax.set_title(f"{copies} copies at {a['speed_rpm']:g} rpm", fontsize=10)
    ax.grid(alpha=0.3)
    for ax, side in zip(axes[1:], contacts):
        bp = g[f"precession_hz_{side}"][()]
        regime = g[f"regime_{side}"][()]
        for c in range(bp.shape[0]):
            ax.plot(time, bp[c], color="0.8", lw=0.6, zorder=1)
        for code, (name, colour) in REGIMES.items():
            mask = regime == code
            if mask.any():
                ax.scatter(np.broadcast_to(time, bp.shape)[mask], bp[mask], s=6, color=colour,
                           label=name, zorder=2)
        ax.set_xlabel("time at this speed [s]")
        ax.set_ylabel(f"BP at the {side} contact [Hz]")
        ax.legend(fontsize=8, loc="best")
        ax.grid(alpha=0.3)
    start = text(a["approach_regime_" + contacts[0]]) if contacts else ""
    fig.suptitle(f"{text(f.attrs['scene_name'])}: from the {text(a['direction'])} sweep's state "
                 f"at {a['approach_to_rpm']:g} rpm ({start}), perturbed by "
                 f"{a['perturbation']:g} × scale", fontsize=10)
    fig.tight_layout()
    return fig


figures = one_figure(figure)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
