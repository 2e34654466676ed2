"""Figures of the time-marching sweeps (level L3), read from the HDF5 file only.

Usage: python3 -m rubcont.plots.sweep RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes into OUTDIR, for the directions the file holds (/sweeps/up, /sweeps/down; layout in
apps/sweep_output.h):
  sweep_waterfall_up.png, sweep_waterfall_down.png
      two-sided amplitude spectrum of each contact's relative motion d = u_r - u_s against running
      speed (Kumar 2010, Figure 14(d)): one trace per speed, offset by its speed; negative
      frequencies are backward precession.
  sweep_spectrum_map_up.png, sweep_spectrum_map_down.png
      the same spectra as a map of log10 amplitude: the small sidebands of modulated whip and
      partial rub show here.
  sweep_precession.png
      BP frequency against speed, speed-up and speed-down, per contact, over the continuation
      branches of /sweeps/branches (the sweeps' tanh friction law; /branches when absent;
      rubcont.plots.branches colours: by family; stable solid, unstable dashed;
      events, non-smooth folds, Hopf and branch points marked) and the rolling lines
      BP = RCI*speed; each jump of /sweeps/jump_table is an arrow from the bifurcation that
      predicts it to the middle of the jump's speed interval. Right panel: zoom on the jumps.
  sweep_slip_velocity.png
      mean slip velocity per contact over the time in contact (min-max band), both directions.
From Python: ``waterfall(f, "up")``, ``spectrum_map(f, "up")``, ``precession(f)``,
``slip_velocity(f)`` return the Figures (None where the direction has too few speeds).
"""
import sys
import tomllib

import numpy as np
from matplotlib.lines import Line2D

from . import branches as branch_plots  # the same colours and markers
from .common import MissingData, command_line, new_figure, text

DPI = 110
SIDES = ("left", "right")
DIRECTIONS = ("up", "down")
COLORS = {"up": "#b22222", "down": "#1f5fa8"}
MARKERS = {"up": "^", "down": "v"}


def texts(dataset):
    return [text(v) for v in dataset[()]]


def rci(f):
    """(RCI_L, RCI_R) from the resolved scene stored in the file, or None."""
    try:
        scene = tomllib.loads(text(f.attrs["scene_toml"]))
        c = scene["contact"]
        return tuple(r / cl for r, cl in zip(c["radius"], c["clearance"]))
    except Exception:  # figures never fail for want of a decoration
        return None


def same_contacts(g):
    """True when both contacts carry the same signal to plotting accuracy (a symmetric rotor)."""
    a, b = g["spectrum_magnitude_left"][()], g["spectrum_magnitude_right"][()]
    if a.shape != b.shape or not np.isfinite(a).any():
        return False
    return bool(np.nanmax(np.abs(a - b)) <= 1e-3 * np.nanmax(np.abs(a)))


def scene_name(f):
    """The scene's name stored in the file ('' when it has none)."""
    return text(f.attrs.get("scene_name", ""))


def spectrum_map(f, direction, fig=None, name=None):
    """log10 spectrum of d = u_r - u_s over speed and frequency, one direction (None: < 2 speeds)."""
    name = scene_name(f) if name is None else name
    g = f["sweeps"][direction]
    speed = g["speed_rpm"][()]
    if len(speed) < 2:
        return None
    freq = g["spectrum_frequency_hz"][()]
    sides = ["left"] if same_contacts(g) else list(SIDES)
    fig = new_figure(fig, figsize=(7.5 * len(sides), 6))
    axes = fig.subplots(1, len(sides), squeeze=False)
    order = np.argsort(speed)
    for ax, side in zip(axes[0], sides):
        spectra = g["spectrum_magnitude_" + side][()][order] * 1e6
        peak = np.nanmax(spectra) if np.isfinite(spectra).any() else 1.0
        level = np.log10(np.maximum(spectra, peak * 1e-6))
        image = ax.pcolormesh(freq, speed[order], level, shading="nearest", cmap="magma",
                              vmin=np.log10(peak) - 5, vmax=np.log10(peak))
        fig.colorbar(image, ax=ax, label="log10 amplitude [µm]")
        ax.set_xlabel("frequency [Hz]   (negative: backward precession)")
        ax.set_ylabel("running speed [rpm]")
        label = "both contacts (identical)" if len(sides) == 1 else f"{side} contact"
        ax.set_title(label, fontsize=9)
    fig.suptitle(f"{name}: two-sided spectrum of d = u_r − u_s, speed-{direction} sweep "
                 f"(5 decades)", fontsize=11)
    fig.tight_layout()
    return fig


def waterfall(f, direction, fig=None, name=None):
    """The spectra of one direction as traces offset by their speed (None: no speed)."""
    name = scene_name(f) if name is None else name
    g = f["sweeps"][direction]
    speed = g["speed_rpm"][()]
    if len(speed) == 0:
        return None
    freq = g["spectrum_frequency_hz"][()]
    sides = ["left"] if same_contacts(g) else list(SIDES)
    fig = new_figure(fig, figsize=(7.5 * len(sides), 8.5))
    axes = fig.subplots(1, len(sides), squeeze=False)
    step = float(np.median(np.abs(np.diff(speed)))) if len(speed) > 1 else 1.0
    order = np.argsort(speed)[::-1]  # draw the back (high speeds) first
    for ax, side in zip(axes[0], sides):
        spectra = g["spectrum_magnitude_" + side][()] * 1e6  # µm
        peak = np.nanmax(spectra) if np.isfinite(spectra).any() else 1.0
        scale = 4.0 * step / peak  # the largest peak spans four speed steps
        for i in order:
            if not np.isfinite(spectra[i]).any():
                continue
            y = speed[i] + scale * spectra[i]
            ax.fill_between(freq, speed[i], y, color="white", zorder=2 * (len(speed) - i))
            ax.plot(freq, y, color="#202020", lw=0.6, zorder=2 * (len(speed) - i) + 1)
        ax.axvline(0.0, color="#999999", lw=0.5, zorder=0)
        ax.set_xlim(freq[0], freq[-1])
        ax.set_xlabel("frequency [Hz]   (negative: backward precession)")
        ax.set_ylabel("running speed [rpm]   (traces: amplitude of d = u_r − u_s)")
        label = "both contacts (identical)" if len(sides) == 1 else f"{side} contact"
        ax.set_title(f"{label}: largest peak {peak:.0f} µm = {4 * step:g} rpm of offset", fontsize=9)
        ax.grid(alpha=0.2)
    fig.suptitle(f"{name}: two-sided spectrum, speed-{direction} sweep", fontsize=11)
    fig.tight_layout()
    return fig


def draw_branches(f, ax):
    """Draws /sweeps/branches (the branches of the sweeps' tanh law; else /branches): colour by
    family, stable solid, unstable dashed, special points marked. Returns (modes, special point
    types) drawn, for the legend."""
    modes, types = [], []
    # The branches of the sweeps' own friction law (tanh) when the file has them, else /branches.
    if "branches" in f.get("sweeps", {}):
        source = {"branches": f["sweeps"]["branches"]}
    elif "branches" in f:
        source = f
    else:
        return modes, types
    # Mode 1 on top: the whirls of every family share the rolling line.
    order = {"left_only": 0, "right_only": 1, "single": 2, "mode2": 3, "mode1": 4}
    for name, b in sorted(branch_plots.branches_of(source),
                          key=lambda item: order.get(text(item[1].attrs.get("mode", "single")), 2)):
        if not all(k in b for k in ("speed_rpm", "precession_hz", "stable")) or len(b["speed_rpm"]) < 2:
            continue
        mode = text(b.attrs.get("mode", "single"))
        color = branch_plots.MODE_COLORS.get(mode, "#555555")
        branch_plots.plot_lines(ax, b["speed_rpm"][()], b["precession_hz"][()], b["stable"][()], color)
        if mode not in modes:
            modes.append(mode)
        points = branch_plots.special_points(b) if "special_points" in b else []
        branch_plots.mark(ax, points, "rpm", lambda p: p["hz"], color)
        for p in points:
            if p["type"] not in types:
                types.append(p["type"])
    return modes, types


def draw_sweeps(f, ax):
    """BP of the up and down sweeps (one marker per speed and contact); returns the legend handles."""
    handles = []
    for direction in DIRECTIONS:
        if direction not in f.get("sweeps", {}):
            continue
        g = f["sweeps"][direction]
        speed = g["speed_rpm"][()]
        if len(speed) == 0:
            continue
        both = np.allclose(g["precession_hz_left"][()], g["precession_hz_right"][()], rtol=0.0,
                           atol=0.1, equal_nan=True)  # within 0.1 Hz: one marker per speed
        for side in (["left"] if both else SIDES):
            bp = g["precession_hz_" + side][()].copy()
            regime = texts(g["regime_" + side])
            bp[[r in ("no_contact", "intermittent", "unknown") for r in regime]] = np.nan
            line, = ax.plot(speed, bp, MARKERS[direction], color=COLORS[direction],
                            ms=6 if side == "left" else 8,
                            mfc=COLORS[direction] if side == "left" else "none", alpha=0.85, zorder=7,
                            label=f"sweep {direction}, " + ("both contacts" if both else f"{side} contact"))
            handles.append(line)
            # Untrusted speeds (a penetration beyond max_penetration × the clearance): crossed out.
            untrusted = np.array([bool(u) for u in texts(g["untrusted"])]) if "untrusted" in g else None
            if untrusted is not None and untrusted.any():
                cross, = ax.plot(speed[untrusted], g["precession_hz_" + side][()][untrusted], "x", color="red",
                                 ms=11, mew=2, zorder=9, label="untrusted speed (penetration; see the file)")
                if side == "left" or both:
                    handles.append(cross)
    return handles


def draw_predictions(f, ax):
    """Each jump of /sweeps/jump_table: a dotted arrow from the predicting bifurcation to the middle
    of the jump's speed interval, at the bifurcation's frequency."""
    if "jump_table" not in f.get("sweeps", {}):
        return
    t = f["sweeps"]["jump_table"]
    if len(t["direction"]) == 0:
        return
    seen = set()
    for d, r0, r1, br, bh in zip(texts(t["direction"]), t["speed_from_rpm"][()], t["speed_to_rpm"][()],
                                 t["bifurcation_speed_rpm"][()], t["bifurcation_precession_hz"][()]):
        if not np.isfinite(br) or (d, r0, r1) in seen:
            continue
        seen.add((d, r0, r1))
        mid = 0.5 * (r0 + r1)
        ax.annotate("", (mid, bh), (br, bh), zorder=8,
                    arrowprops=dict(arrowstyle="->", color=COLORS[d], lw=1.2, ls=":"))
        ax.plot([mid], [bh], "|", color=COLORS[d], ms=14, mew=2, zorder=8)


def precession(f, fig=None, name=None):
    """BP of both sweeps over the branches, whole range and zoom on the jumps."""
    name = scene_name(f) if name is None else name
    fig = new_figure(fig, figsize=(15, 6.5))
    axes = fig.subplots(1, 2, gridspec_kw=dict(width_ratios=[1.1, 1]))
    top, lo, hi = 0.0, np.inf, -np.inf
    for ax in axes:
        ratios = rci(f)
        sweep_handles = draw_sweeps(f, ax)
        modes, types = draw_branches(f, ax)
        draw_predictions(f, ax)
        for direction in DIRECTIONS:
            if direction in f.get("sweeps", {}) and len(f["sweeps"][direction]["speed_rpm"]) > 0:
                g = f["sweeps"][direction]
                lo, hi = min(lo, g["speed_rpm"][()].min()), max(hi, g["speed_rpm"][()].max())
                for side in SIDES:
                    bp = g["precession_hz_" + side][()]
                    if np.isfinite(bp).any():
                        top = max(top, np.nanmax(bp))
        if ratios is not None and np.isfinite(hi):
            rpm = np.linspace(0.0, hi + 10.0, 2)
            for ratio in sorted(set(ratios)):
                ax.plot(rpm, ratio * rpm / 60.0, color="#888888", lw=0.8, ls=(0, (1, 2)), zorder=1)
        ax.set_xlabel("running speed [rpm]")
        ax.set_ylabel("backward precession (BP) frequency [Hz]")
        ax.grid(alpha=0.3)
    if not np.isfinite(lo):
        lo, hi = 0.0, 1.0
    axes[0].set_xlim(max(0.0, lo - 5.0), hi + 5.0)
    axes[0].set_ylim(0.0, 1.1 * top if top > 0 else 1.0)
    axes[0].set_title("whole sweep range", fontsize=10)
    # The zoom: where the predicted jumps are (their intervals and bifurcations).
    zoom_lo, zoom_hi, f_lo, f_hi = 40.0, 100.0, 60.0, 160.0
    if "jump_table" in f.get("sweeps", {}) and len(f["sweeps"]["jump_table"]["direction"]) > 0:
        t = f["sweeps"]["jump_table"]
        keep = np.isfinite(t["bifurcation_speed_rpm"][()])  # the predicted jumps, if any
        if not keep.any():
            keep[:] = True
        speeds = np.concatenate([t["speed_from_rpm"][()][keep], t["speed_to_rpm"][()][keep],
                                 t["bifurcation_speed_rpm"][()][keep]])
        freqs = np.concatenate([t["precession_from_hz"][()][keep], t["precession_to_hz"][()][keep],
                                t["bifurcation_precession_hz"][()][keep]])
        speeds, freqs = speeds[np.isfinite(speeds)], freqs[np.isfinite(freqs)]
        if len(speeds):
            zoom_lo, zoom_hi = max(0.0, speeds.min() - 10.0), speeds.max() + 10.0
        if len(freqs):
            f_lo, f_hi = max(0.0, freqs.min() - 20.0), freqs.max() + 20.0
    axes[1].set_xlim(zoom_lo, zoom_hi)
    axes[1].set_ylim(f_lo, f_hi)
    axes[1].set_title("zoom on the predicted jumps: arrows run from the bifurcation (L1) to the "
                      "middle of the jump (L3)", fontsize=9)
    handles = sweep_handles + branch_plots.legend_handles(modes, types)
    handles.append(Line2D([], [], color="#888888", lw=0.8, ls=(0, (1, 2)), label="rolling: BP = RCI·speed"))
    axes[1].legend(handles=handles, fontsize=7, loc="upper left", ncol=2)
    law = ""
    for group in (f.get("sweeps", {}).get("branches"), f.get("branches")):
        if group is not None and "friction_law" in group.attrs:
            law = f", {text(group.attrs['friction_law'])} friction"
            break
    fig.suptitle(f"{name}: BP frequency of the speed-up and speed-down sweeps (L3) over the "
                 f"continuation branches (L1{law})", fontsize=11)
    fig.tight_layout()
    return fig


def slip_velocity(f, fig=None, name=None):
    """Mean slip velocity (min-max band) per contact, both directions."""
    name = scene_name(f) if name is None else name
    fig = new_figure(fig, figsize=(12, 5))
    axes = fig.subplots(1, 2, sharey=True)
    ratios = rci(f)
    for ax, side in zip(axes, SIDES):
        hi = 0.0
        for direction in DIRECTIONS:
            if direction not in f.get("sweeps", {}):
                continue
            g = f["sweeps"][direction]
            speed = g["speed_rpm"][()]
            if len(speed) == 0:
                continue
            hi = max(hi, speed.max())
            order = np.argsort(speed)
            mean = g["slip_velocity_" + side][()][order]
            vmin = g["slip_velocity_min_" + side][()][order]
            vmax = g["slip_velocity_max_" + side][()][order]
            ax.fill_between(speed[order], vmin, vmax, color=COLORS[direction], alpha=0.12, lw=0)
            ax.plot(speed[order], mean, MARKERS[direction], ls="-", lw=0.7, ms=4,
                    color=COLORS[direction], label=f"speed-{direction}: mean (band: min–max)")
        if ratios is not None and hi > 0:
            try:
                scene = tomllib.loads(text(f.attrs["scene_toml"]))
                radius = scene["contact"]["radius"][SIDES.index(side)]
                rpm = np.linspace(0.0, hi, 2)
                ax.plot(rpm, radius * rpm * 2 * np.pi / 60.0, color="#888888", ls=(0, (1, 2)),
                        lw=0.8, label="ωR (no precession)")
            except Exception:
                pass
        ax.axhline(0.0, color="#444444", lw=0.6)
        ax.set_xlabel("running speed [rpm]")
        ax.set_title(f"{side} contact", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    axes[0].set_ylabel("slip velocity V while in contact [m/s]   (0: rolling)")
    fig.suptitle(f"{name}: slip velocity at the contacts (Kumar 2010, Figure 14(b), (c))", fontsize=11)
    fig.tight_layout()
    return fig


def figures(f, stem):
    """The waterfall and spectrum map of each direction, the precession and the slip velocity."""
    if "sweeps" not in f:
        raise MissingData("no /sweeps group")
    name = text(f.attrs.get("scene_name", stem))
    for direction in DIRECTIONS:
        if direction in f["sweeps"]:
            for figure_name, draw in ((f"sweep_waterfall_{direction}", waterfall),
                                      (f"sweep_spectrum_map_{direction}", spectrum_map)):
                fig = draw(f, direction, name=name)
                if fig is not None:
                    yield figure_name, fig
    yield "sweep_precession", precession(f, name=name)
    yield "sweep_slip_velocity", slip_velocity(f, name=name)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
