"""The hysteresis loop of one scene on one page: states, sweeps and the four corners.

Usage: python3 -m rubcont.plots.hysteresis --sweep SWEEP.h5 [--orbits ORBITS.h5]
                                           [--lifetime LIFETIME.h5] --out FIGURE.{png,pdf,svg}
Draws, against running speed, the backward precession (BP) at the left contact:
  - the rolling line BP = (R/C)·speed, the rotating waves of the sweep file (/branches, the exact
    friction law: stable solid blue, unstable dashed red);
  - the periodic-orbit families of /orbits when given (the modulated whip and its side branches): the carrier
    (mean precession) and, for the first family where it is stable, the band of instantaneous
    precession;
  - the speed-up and speed-down sweeps of /sweeps (markers per speed) and their jumps (arrows);
  - the four corners, numbered on the figure and listed in a box: each jump of the sweeps' jump
    table at the bifurcation that predicts it (/sweeps/jump_table), and the end of the speed-up whip
    from the lifetime file's crisis law (/lifetime/crisis: the critical speed and its 95 % interval,
    shaded; when the likelihood leaves one end open, the other end as a line with an arrow towards
    the open side) when one is given.
Reads HDF5 files only (layouts: apps/orbit_output.h, apps/sweep_output.h, apps/lifetime_command.h).
From Python: ``figure(sweep, orbits=None, lifetime=None)`` (file paths) returns the Figure.
"""
import argparse
import sys
import tomllib
from contextlib import nullcontext
from types import SimpleNamespace

import h5py
import numpy as np

from .common import new_figure, text

DPI = 130

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


def read_crisis(path):
    """A lifetime file's located crisis as a dict (p_c, its 95 % limits and whether they are
    bounded, and what the copies arrived at: a precession above `above` Hz or the regime `until`,
    on the contacts `contacts`), or None."""
    if not path:
        return None
    with h5py.File(path, "r") as f:
        a, c = f["lifetime"].attrs, f["lifetime/crisis"].attrs
        if text(c["status"]) != "located":
            return None
        return dict(pc=c["critical_speed_rpm"], lo=c["critical_lower_rpm"], hi=c["critical_upper_rpm"],
                    lo_bounded=bool(c["lower_bounded"]), hi_bounded=bool(c["upper_bounded"]),
                    above=float(a["until_above_hz"]) if "until_above_hz" in a else 0.0,
                    until=text(a["until"]), contacts=text(a["until_contacts"]) if "until_contacts" in a else "every")


def crisis_row(table, contact, crisis):
    """The row of the jump table (on `contact`) that is the end of the speed-up whip whose crisis
    the lifetime file locates: the first speed-up jump of this contact to what the copies arrived at
    (its precession across `above`, or a whip → `until` jump); None on a contact the copies did
    not watch."""
    if crisis is None or crisis["contacts"] not in ("every", "any", contact):
        return None
    for i in contact_rows(table, contact):
        if text(table["direction"][i]) != "up":
            continue
        if crisis["above"] > 0.0:
            if table["precession_from_hz"][i] < crisis["above"] <= table["precession_to_hz"][i]:
                return i
        elif text(table["kind"][i]) == f"whip_to_{crisis['until']}":
            return i
    return None


def contact_rows(group, contact):
    """The rows of a table group (jumps, jump_table) that belong to `contact`."""
    names = [text(c) for c in group["contact"][()]]
    return [i for i, c in enumerate(names) if c == contact]


def same_contacts(s):
    """Whether both contacts of a sweep file show the same loop (a symmetric rotor): equal BP in
    both sweeps and the same jump table."""
    for direction in ("up", "down"):
        g = s[f"sweeps/{direction}"]
        if not np.allclose(g["precession_hz_left"][()], g["precession_hz_right"][()], rtol=1e-3, equal_nan=True):
            return False
    t = s["sweeps/jump_table"]
    key = lambda i: (text(t["direction"][i]), text(t["kind"][i]), t["speed_from_rpm"][i], t["speed_to_rpm"][i])
    return sorted(map(key, contact_rows(t, "left"))) == sorted(map(key, contact_rows(t, "right")))


def draw(ax, contact, args, crisis):
    """One contact's loop on `ax`."""
    with h5py.File(args.sweep, "r") as s:
        scene = tomllib.loads(text(s.attrs["scene_toml"]))
        k = 0 if contact == "left" else 1
        ratio = scene["contact"]["radius"][k] / scene["contact"]["clearance"][k]
        low, high = 1e9, 0.0
        for direction, colour, marker in (("up", "tab:orange", "^"), ("down", "tab:purple", "v")):
            g = s[f"sweeps/{direction}"]
            rpm, bp = g["speed_rpm"][()], g[f"precession_hz_{contact}"][()]
            low, high = min(low, rpm.min()), max(high, rpm.max())
            ax.plot(rpm, bp, marker, color=colour, ms=4, alpha=0.8, ls="none",
                    label=f"speed-{direction} sweep (L3)")
            j = g["jumps"]
            for i in contact_rows(j, contact):
                ax.annotate("", xy=(j["speed_to_rpm"][i], j["precession_to_hz"][i]),
                            xytext=(j["speed_from_rpm"][i], j["precession_from_hz"][i]),
                            arrowprops=dict(arrowstyle="->", color=colour, lw=1.6))
        table = s["sweeps/jump_table"]
        end = crisis_row(table, contact, crisis)
        corners = [(text(table["direction"][i]), text(table["kind"][i]), text(table["bifurcation"][i]),
                    table["bifurcation_speed_rpm"][i], table["bifurcation_precession_hz"][i],
                    table["speed_from_rpm"][i], table["precession_from_hz"][i], i == end)
                   for i in contact_rows(table, contact)]
        grid = np.linspace(low, high, 200)
        ax.plot(grid, ratio * grid / 60.0, color="0.6", lw=0.8, ls=":", label=f"rolling line BP = {ratio:g}·speed")
        seen = set()
        for key, g in s["branches"].items():
            if not isinstance(g, h5py.Group) or "speed_rpm" not in g:
                continue
            stable = g["stable"][()].astype(bool)
            for piece, colour, label in ((stable, "tab:blue", "stable rotating waves (L1)"),
                                         (~stable, "tab:red", "unstable rotating waves (L1)")):
                y = np.where(piece, g["precession_hz"][()], np.nan)
                ax.plot(g["speed_rpm"][()], y, color=colour, lw=1.2, ls="-" if colour == "tab:blue" else "--",
                        label=None if label in seen else label)
                seen.add(label)
    with h5py.File(args.orbits, "r") if args.orbits else nullcontext({"orbits": {}}) as f:
        first = True
        for key in f["orbits"]:
            g = f["orbits"][key]
            if key == "rotating_waves" or not isinstance(g, h5py.Group) or "speed_rpm" not in g:
                continue
            rpm, stable = g["speed_rpm"][()], g["stable"][()].astype(bool)
            lines(ax, rpm, g["precession_hz"][()], stable, "k", 1.6,
                  "modulated whip, carrier (L2)" if first else None)
            lo, hi = g[f"min_precession_hz_{contact}"][()], g[f"max_precession_hz_{contact}"][()]
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
    done, listing = set(), []
    for direction, kind, bifurcation, speed, bp, jump_rpm, jump_bp, whip_end in corners:
        key = "whip end" if whip_end else (direction, kind)
        if key in done:
            continue
        done.add(key)
        number = len(done)
        jump = f"{direction} {kind.replace('_to_', ' → ').replace('_', ' ')}"
        if bifurcation:
            where, colour = (speed, bp), "k"
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: {bifurcation} at {speed:.2f} rpm (L1)")
        elif whip_end:
            pc, lo, hi = crisis["pc"], crisis["lo"], crisis["hi"]
            lo_bounded, hi_bounded = crisis["lo_bounded"], crisis["hi_bounded"]
            where, colour = (pc, jump_bp), "tab:green"
            if lo_bounded and hi_bounded:
                ax.axvspan(lo, hi, color="tab:green", alpha=0.2)
            else:  # one end open: the bound, and an arrow towards the open side
                bound = hi if hi_bounded else lo
                where = (bound, jump_bp)
                ax.axvline(bound, color="tab:green", ls="--", lw=1.2)
                ax.annotate("", xy=(bound - 8.0 if hi_bounded else bound + 8.0, jump_bp + 25.0),
                            xytext=(bound, jump_bp + 25.0),
                            arrowprops=dict(arrowstyle="->", color="tab:green", lw=1.5))
            if lo_bounded and hi_bounded:
                interval = f"at {pc:.2f} rpm, 95 % {lo:.2f} … {hi:.2f}"
            elif hi_bounded:
                interval = f"below {hi:.2f} rpm (95 %; best fit {pc:.2f})"
            else:
                interval = f"above {lo:.2f} rpm (95 %; best fit {pc:.2f})"
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: the whip's end, a crisis {interval} "
                           "(L3 lifetimes)")
        else:
            where, colour = (jump_rpm, jump_bp), "tab:red"
            listing.append(f"{number}: {jump} at {jump_rpm:g} rpm: not predicted")
        ax.plot(*where, "o", mfc="none", mec=colour, ms=10, mew=1.5, zorder=5)
        ax.annotate(str(number), where, textcoords="offset points", xytext=(0, 14 if direction == "up" else -18),
                    ha="center", va="center", fontsize=9, fontweight="bold", color=colour, zorder=6)
    ax.text(0.99, 0.02, f"the corners of the loop ({contact} contact)\n" + "\n".join(listing),
            transform=ax.transAxes, ha="right", va="bottom", fontsize=8, bbox=dict(boxstyle="round", fc="w", ec="0.6"))
    ax.set_xlim(low, high)
    ax.set_ylim(0.0, min(ratio * high / 60.0, 450.0))
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel(f"backward precession at the {contact} contact [Hz]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")


def figure(sweep, orbits=None, lifetime=None, fig=None):
    """The loop from the sweep file `sweep`, the orbits file `orbits` and the lifetime file
    `lifetime` (paths; the last two optional)."""
    files = SimpleNamespace(sweep=sweep, orbits=orbits, lifetime=lifetime)
    with h5py.File(sweep, "r") as s:
        name = text(s.attrs["scene_name"])
        contacts = ["left"] if same_contacts(s) else ["left", "right"]
    fig = new_figure(fig, figsize=(11.0, 6.6 * len(contacts)))
    axes = fig.subplots(len(contacts), 1, squeeze=False)
    crisis = read_crisis(lifetime)
    for ax, contact in zip(axes[:, 0], contacts):
        draw(ax, contact, files, crisis)
    axes[0, 0].set_title(f"{name}: the hysteresis loop — states (L1, L2), sweeps (L3) and the bifurcations at its "
                         f"corners{'' if len(contacts) > 1 else ' (both contacts alike)'}", fontsize=10)
    fig.tight_layout()
    return fig


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    parser = argparse.ArgumentParser(prog="python3 -m rubcont.plots.hysteresis",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--orbits")
    parser.add_argument("--sweep", required=True)
    parser.add_argument("--lifetime")
    parser.add_argument("--out", required=True, help="the figure's file; its extension gives the format")
    args = parser.parse_args(argv)
    fig = figure(args.sweep, args.orbits, args.lifetime)
    fig.savefig(args.out, dpi=DPI)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
