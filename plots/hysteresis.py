#!/usr/bin/python3
"""The hysteresis loop of one scene on one page: states, sweeps and the four corners.

Usage: /usr/bin/python3 plots/hysteresis.py --orbits ORBITS.h5 --sweep SWEEP.h5
                                            [--lifetime LIFETIME.h5] --out FIGURE.png
Draws, against running speed, the backward precession (BP) at the left contact:
  - the rolling line BP = (R/C)·speed, the rotating waves of the sweep file (/branches, the exact
    friction law: stable solid blue, unstable dashed red);
  - the periodic-orbit families of /orbits (the modulated whip and its side branches): the carrier
    (mean precession) and, for the first family where it is stable, the band of instantaneous
    precession;
  - the speed-up and speed-down sweeps of /sweeps (markers per speed) and their jumps (arrows);
  - the four corners, numbered on the figure and listed in a box: each jump of the sweeps' jump
    table at the bifurcation that predicts it (/sweeps/jump_table), and the end of the speed-up whip
    from the lifetime file's crisis law (/lifetime/crisis: the critical speed and its 95 % interval)
    when one is given.
Reads HDF5 files only (layouts: apps/orbit_output.h, apps/sweep_output.h, apps/lifetime_command.h).
Exit status 3 when numpy, h5py or matplotlib cannot be imported.
"""
import argparse
import sys
import tomllib

try:
    import h5py
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as error:
    print(f"hysteresis.py: {error}", file=sys.stderr)
    sys.exit(3)

CONTACT = "left"


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def lines(ax, x, y, stable, color, lw, label=None):
    """Stable pieces solid, unstable dashed (each piece drawn up to the next point)."""
    start = 0
    for i in range(1, len(x) + 1):
        if i == len(x) or stable[i] != stable[start]:
            end = min(i + 1, len(x))
            ax.plot(x[start:end], y[start:end], color=color, lw=lw, ls="-" if stable[start] else "--",
                    label=label if start == 0 else None)
            label = None if start == 0 else label
            start = i


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orbits", required=True)
    parser.add_argument("--sweep", required=True)
    parser.add_argument("--lifetime")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()

    fig, ax = plt.subplots(figsize=(11.0, 6.6))
    with h5py.File(args.sweep, "r") as s:
        scene = tomllib.loads(text(s.attrs["scene_toml"]))
        name = text(s.attrs["scene_name"])
        ratio = scene["contact"]["radius"][0] / scene["contact"]["clearance"][0]
        low, high = 1e9, 0.0
        for direction, colour, marker in (("up", "tab:orange", "^"), ("down", "tab:purple", "v")):
            g = s[f"sweeps/{direction}"]
            rpm, bp = g["speed_rpm"][()], g[f"precession_hz_{CONTACT}"][()]
            low, high = min(low, rpm.min()), max(high, rpm.max())
            ax.plot(rpm, bp, marker, color=colour, ms=4, alpha=0.8, ls="none",
                    label=f"speed-{direction} sweep (L3)")
            j = g["jumps"]
            for i in range(len(j["kind"])):
                if text(j["contact"][i]) != CONTACT:
                    continue
                ax.annotate("", xy=(j["speed_to_rpm"][i], j["precession_to_hz"][i]),
                            xytext=(j["speed_from_rpm"][i], j["precession_from_hz"][i]),
                            arrowprops=dict(arrowstyle="->", color=colour, lw=1.6))
        table = s["sweeps/jump_table"]
        corners = []
        for i in range(len(table["kind"])):
            if text(table["contact"][i]) != CONTACT:
                continue
            corners.append((text(table["direction"][i]), text(table["kind"][i]), text(table["bifurcation"][i]),
                            table["bifurcation_speed_rpm"][i], table["bifurcation_precession_hz"][i],
                            table["speed_from_rpm"][i], table["precession_from_hz"][i]))

    grid = np.linspace(low, high, 200)
    ax.plot(grid, ratio * grid / 60.0, color="0.6", lw=0.8, ls=":", label=f"rolling line BP = {ratio:g}·speed")

    with h5py.File(args.sweep, "r") as s:
        waves = s["branches"]
        seen = set()
        for key in waves:
            g = waves[key]
            if not isinstance(g, h5py.Group) or "speed_rpm" not in g:
                continue
            stable = g["stable"][()].astype(bool)
            for piece, colour, label in ((stable, "tab:blue", "stable rotating waves (L1)"),
                                         (~stable, "tab:red", "unstable rotating waves (L1)")):
                y = np.where(piece, g["precession_hz"][()], np.nan)
                ax.plot(g["speed_rpm"][()], y, color=colour, lw=1.2, ls="-" if colour == "tab:blue" else "--",
                        label=None if label in seen else label)
                seen.add(label)
    with h5py.File(args.orbits, "r") as f:
        first = True
        for key in f["orbits"]:
            g = f["orbits"][key]
            if key == "rotating_waves" or not isinstance(g, h5py.Group) or "speed_rpm" not in g:
                continue
            rpm, stable = g["speed_rpm"][()], g["stable"][()].astype(bool)
            lines(ax, rpm, g["precession_hz"][()], stable, "k", 1.6,
                  "modulated whip, carrier (L2)" if first else None)
            lo, hi = g[f"min_precession_hz_{CONTACT}"][()], g[f"max_precession_hz_{CONTACT}"][()]
            if first:
                ax.fill_between(rpm, lo, hi, where=stable, color="0.3", alpha=0.08, lw=0,
                                label="its precession band where stable")
            sp = g["special_points"]
            for k in range(len(sp["type"])):
                kind = text(sp["type"][k])
                if kind in ("period doubling", "fold") and sp["converged"][k]:
                    ax.plot(sp["speed_rpm"][k], sp["precession_hz"][k], "s", color="k", ms=4)
                    ax.annotate(f"{'PD' if kind == 'period doubling' else 'fold'} {sp['speed_rpm'][k]:.1f}",
                                (sp["speed_rpm"][k], sp["precession_hz"][k]), textcoords="offset points",
                                xytext=(-10, -14 if kind == "fold" else 8), fontsize=7)
            first = False

    # The corners: where each sweep jumps, and what predicts it.
    crisis = None
    if args.lifetime:
        with h5py.File(args.lifetime, "r") as f:
            c = f["lifetime/crisis"].attrs
            if text(c["status"]) == "located":
                crisis = (c["critical_speed_rpm"], c["critical_lower_rpm"], c["critical_upper_rpm"])
    done, listing = set(), []
    for direction, kind, bifurcation, speed, bp, jump_rpm, jump_bp in corners:
        if (direction, kind) in done:
            continue
        done.add((direction, kind))
        number = len(done)
        jump = f"{direction} {kind.replace('_to_', ' → ')}"
        if bifurcation:
            where, colour = (speed, bp), "k"
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: {bifurcation} at {speed:.2f} rpm (L1)")
        elif direction == "up" and kind == "whip_to_whirl" and crisis:
            pc, lo, hi = crisis
            where, colour = (pc, jump_bp), "tab:green"
            ax.axvspan(lo, hi, color="tab:green", alpha=0.2)
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: crisis of the chaotic whip at {pc:.2f} rpm, "
                           f"95 % {lo:.2f} … {hi:.2f} (L3 lifetimes)")
        else:
            where, colour = (jump_rpm, jump_bp), "tab:red"
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: not predicted")
        ax.plot(*where, "o", mfc="none", mec=colour, ms=10, mew=1.5, zorder=5)
        ax.annotate(str(number), where, textcoords="offset points", xytext=(0, 14 if direction == "up" else -18),
                    ha="center", va="center", fontsize=9, fontweight="bold", color=colour, zorder=6)
    ax.text(0.99, 0.02, "the corners of the loop (left contact)\n" + "\n".join(listing), transform=ax.transAxes,
            ha="right", va="bottom", fontsize=8, bbox=dict(boxstyle="round", fc="w", ec="0.6"))

    ax.set_xlim(low, high)
    ax.set_ylim(0.0, min(ratio * high / 60.0, 450.0))
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel(f"backward precession at the {CONTACT} contact [Hz]")
    ax.set_title(f"{name}: the hysteresis loop — states (L1, L2), sweeps (L3) and the bifurcations at its corners",
                 fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(args.out, dpi=130)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
