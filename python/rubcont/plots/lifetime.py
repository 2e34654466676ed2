"""Figure of a lifetime study (rubcont lifetime): where the state a sweep reached ceases to exist.

Usage: python3 -m rubcont.plots.lifetime RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/lifetime_command.h):
  OUTDIR/<file stem>.png  left: the escape rate κ per speed with its 95 % interval (arrows: a bound
                          only), the fitted crisis law and its critical speed with the interval;
                          middle: the share of copies still on the state against time, per speed
                          (log scale: an exponential lifetime is a straight line); right: where
                          the check sweeps left the state, against the law's prediction for them.
From Python: ``figure(f)`` returns the Figure.
"""
import sys

import matplotlib.pyplot as plt
import numpy as np

from .common import MissingData, command_line, one_figure, new_figure, text

DPI = 120


def figure(f, fig=None):
    """The figure of the file's /lifetime."""
    if "lifetime" not in f:
        raise MissingData("no /lifetime group")
    g = f["lifetime"]
    a = g.attrs
    speed = g["speed_rpm"][()]
    rate, lower, upper = g["escape_rate"][()], g["rate_lower"][()], g["rate_upper"][()]
    arrival = g["arrival_time_s"][()]
    crisis = g["crisis"].attrs
    has_check = "check" in g
    fig = new_figure(fig, figsize=(15.0 if has_check else 10.5, 4.4))
    axes = fig.subplots(1, 3 if has_check else 2)

    ax = axes[0]
    finite = np.isfinite(rate) & (rate > 0)
    if finite.any():
        ax.errorbar(speed[finite], rate[finite], yerr=[rate[finite] - lower[finite], upper[finite] - rate[finite]],
                    fmt="o", color="k", capsize=3, label="ensemble (95 %)")
    none = rate == 0
    if none.any():
        ax.plot(speed[none], upper[none], "v", color="tab:blue", label="no escape: κ below")
    immediate = np.isinf(rate)
    if immediate.any():
        ax.plot(speed[immediate], lower[immediate], "^", color="tab:red", label="all at once: κ above")
    if text(crisis["status"]) == "located":
        pc, gamma, amp = crisis["critical_speed_rpm"], crisis["exponent"], crisis["amplitude"]
        up = text(a["direction"]) == "up"
        grid = np.linspace(speed.min(), speed.max(), 400)
        u = (grid - pc) if up else (pc - grid)
        law = np.where(u > 0, amp * np.abs(u) ** gamma, np.nan)
        ax.plot(grid, law, color="tab:green", label=f"κ = A·|p − p_c|^{gamma:.2g}")
        ax.axvspan(crisis["critical_lower_rpm"], crisis["critical_upper_rpm"], color="tab:green", alpha=0.15)
        ax.axvline(pc, color="tab:green", ls="--", lw=1, label=f"p_c = {pc:.2f} rpm")
    else:
        ax.set_title(f"crisis law: {text(crisis['status'])}", fontsize=9)
    ax.set_yscale("log")
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel("escape rate κ [1/s]")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3, which="both")

    ax = axes[1]
    duration = a["duration"]
    grid = np.linspace(0.0, duration, 200)
    colours = plt.cm.viridis(np.linspace(0, 1, len(speed)))
    for i, s in enumerate(speed):
        times = arrival[i]
        alive = np.array([np.sum(~(times <= t)) for t in grid]) / arrival.shape[1]
        ax.step(grid, np.maximum(alive, 0.5 / arrival.shape[1]), where="post", color=colours[i], label=f"{s:g} rpm")
    ax.set_yscale("log")
    ax.set_xlabel("time at the speed [s]")
    ax.set_ylabel("share of copies not yet arrived")
    ax.set_title(f"arrived: {text(a['arrival'] if 'arrival' in a else a['until'] + ' on every contact')}", fontsize=9)
    ax.legend(fontsize=7, ncol=2, loc="lower left")
    ax.grid(alpha=0.3, which="both")

    if has_check:
        ax = axes[2]
        k = g["check"]
        schedule = k["speed_rpm"][()]
        predicted = k["predicted_leave_probability"][()]
        jumps = k["jump_speed_rpm"][()]
        step = k.attrs["step_rpm"]
        if np.isfinite(predicted).any():
            ax.bar(schedule, predicted, width=0.8 * step, color="tab:green", alpha=0.5,
                   label="predicted by the law")
        values, counts = np.unique(jumps[np.isfinite(jumps)], return_counts=True)
        ax.bar(values, counts / len(jumps), width=0.4 * step, color="k", label=f"{len(jumps)} sweeps")
        stayed = np.sum(~np.isfinite(jumps))
        ax.set_title(f"check sweeps, {k.attrs['dwell']:.3g} s per speed"
                     + (f" ({stayed} kept the state)" if stayed else ""), fontsize=9)
        ax.set_xlabel("speed at which the sweep left the state [rpm]")
        ax.set_ylabel("share of sweeps")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)

    fig.suptitle(f"{text(f.attrs['scene_name'])}: lifetime of the {text(a['direction'])} sweep's state at "
                 f"{a['approach_to_rpm']:g} rpm, {int(a['copies'])} copies × {duration:.3g} s per speed",
                 fontsize=10)
    fig.tight_layout()
    return fig


figures = one_figure(figure)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
