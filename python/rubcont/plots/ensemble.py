#!/usr/bin/python3
"""Figure of an ensemble (rubcont ensemble): how long the state a sweep reached lasts.

Usage: /usr/bin/python3 plots/ensemble.py RESULT.h5 OUTDIR
Writes, from the HDF5 file only (layout: apps/ensemble_command.h):
  OUTDIR/<file stem>.png  left: the share of copies not yet in the target regime against time
                          (a survival curve; copies that never arrive stay in it to the end);
                          right, per contact: the backward precession (BP) of every copy in each
                          stretch, coloured by the stretch's regime.
Exit status 3 when numpy, h5py or matplotlib cannot be imported.
"""
import os
import sys

try:
    import h5py
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as error:
    print(f"ensemble.py: {error}", file=sys.stderr)
    sys.exit(3)

# RubRegime codes (sweeps/rub_sweep.h) and their colours.
REGIMES = {0: ("unknown", "0.5"), 1: ("no contact", "tab:gray"), 2: ("intermittent", "tab:orange"),
           3: ("whirl", "tab:blue"), 4: ("whip", "tab:red")}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with h5py.File(sys.argv[1], "r") as f:
        if "ensemble" not in f:
            print("ensemble.py: no /ensemble in the file", file=sys.stderr)
            return 1
        g = f["ensemble"]
        a = g.attrs
        time = g["time_s"][()]
        arrival = g["arrival_time_s"][()]
        contacts = sorted(k[len("precession_hz_"):] for k in g if k.startswith("precession_hz_"))
        fig, axes = plt.subplots(1, 1 + len(contacts), figsize=(5.0 + 4.5 * len(contacts), 4.2))
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
        stem = os.path.splitext(os.path.basename(sys.argv[1]))[0]
        fig.savefig(os.path.join(sys.argv[2], f"{stem}.png"), dpi=120)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
