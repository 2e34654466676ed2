#!/usr/bin/python3
"""Figures of the time-marching sweeps (level L3), read from the HDF5 file only.

Usage: /usr/bin/python3 plots/sweep.py RESULT.h5 OUTDIR
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
      BP frequency against speed, speed-up and speed-down, per contact, with the rolling lines
      BP = RCI*speed, the detected jumps, and the continuation branches when the file has
      /branches (stable solid, unstable dashed, special points marked).
  sweep_slip_velocity.png
      mean slip velocity per contact over the time in contact (min-max band), both directions.
Exit status 3 when numpy, h5py or matplotlib cannot be imported (rubcont then keeps the HDF5
file and warns).
"""
import os
import sys

try:
    import h5py
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as error:  # rubcont reports exit status 3 as "modules missing"
    print(f"sweep.py: {error}", file=sys.stderr)
    sys.exit(3)

SIDES = ("left", "right")
DIRECTIONS = ("up", "down")
COLORS = {"up": "#b22222", "down": "#1f5fa8"}
MARKERS = {"up": "^", "down": "v"}
BRANCH_COLORS = ["#2e8b57", "#6a5acd", "#8b4513", "#ff8c00", "#008b8b", "#c71585", "#556b2f"]
SPECIAL_MARKERS = {"fold": "s", "hopf": "D", "branch_point": "X", "stick_slip": "o",
                   "slip_stick": "o", "contact_loss": "x", "contact_regain": "+"}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def texts(dataset):
    return [text(v) for v in dataset[()]]


def rci(f):
    """(RCI_L, RCI_R) from the resolved scene stored in the file, or None."""
    try:
        import tomllib
    except ImportError:
        return None
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


def spectrum_map(f, direction, outdir, name):
    g = f["sweeps"][direction]
    speed = g["speed_rpm"][()]
    if len(speed) < 2:
        return
    freq = g["spectrum_frequency_hz"][()]
    sides = ["left"] if same_contacts(g) else list(SIDES)
    fig, axes = plt.subplots(1, len(sides), figsize=(7.5 * len(sides), 6), squeeze=False)
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
    fig.savefig(os.path.join(outdir, f"sweep_spectrum_map_{direction}.png"), dpi=110)
    plt.close(fig)


def waterfall(f, direction, outdir, name):
    g = f["sweeps"][direction]
    speed = g["speed_rpm"][()]
    if len(speed) == 0:
        return
    freq = g["spectrum_frequency_hz"][()]
    sides = ["left"] if same_contacts(g) else list(SIDES)
    fig, axes = plt.subplots(1, len(sides), figsize=(7.5 * len(sides), 8.5), squeeze=False)
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
    fig.savefig(os.path.join(outdir, f"sweep_waterfall_{direction}.png"), dpi=110)
    plt.close(fig)


def branches(f, ax):
    """Draws /branches/<name> when present; returns whether anything was drawn."""
    if "branches" not in f:
        return False
    drawn = False
    for index, name in enumerate(sorted(f["branches"].keys())):
        b = f["branches"][name]
        if not all(k in b for k in ("speed_rpm", "precession_hz", "stable")):
            continue
        rpm, hz = b["speed_rpm"][()], b["precession_hz"][()]
        stable = b["stable"][()].astype(bool)
        color = BRANCH_COLORS[index % len(BRANCH_COLORS)]
        # Runs of equal stability, joined at their ends.
        start = 0
        for i in range(1, len(rpm) + 1):
            if i == len(rpm) or stable[i] != stable[start]:
                stop = min(i + 1, len(rpm))
                ax.plot(rpm[start:stop], hz[start:stop], color=color, lw=1.3,
                        ls="-" if stable[start] else "--", alpha=0.8, zorder=2,
                        label=(f"branch {name}" if start == 0 else None))
                start = i
        drawn = True
        if "special_points" in b:
            sp = b["special_points"]
            kinds = texts(sp["type"]) if "type" in sp else []
            for kind, r, h in zip(kinds, sp["speed_rpm"][()], sp["precession_hz"][()]):
                ax.plot([r], [h], SPECIAL_MARKERS.get(kind, "*"), color=color, ms=7, mfc="none",
                        mew=1.5, zorder=6)
                ax.annotate(kind, (r, h), textcoords="offset points", xytext=(4, 4), fontsize=7,
                            color=color)
    return drawn


def precession(f, outdir, name):
    fig, ax = plt.subplots(figsize=(10, 6.5))
    top = 0.0
    lo, hi = np.inf, -np.inf
    for direction in DIRECTIONS:
        if direction not in f.get("sweeps", {}):
            continue
        g = f["sweeps"][direction]
        speed = g["speed_rpm"][()]
        if len(speed) == 0:
            continue
        lo, hi = min(lo, speed.min()), max(hi, speed.max())
        both = np.allclose(g["precession_hz_left"][()], g["precession_hz_right"][()], rtol=0.0,
                           atol=0.1, equal_nan=True)  # within 0.1 Hz: one marker per speed
        for side in (["left"] if both else SIDES):
            bp = g["precession_hz_" + side][()].copy()
            regime = texts(g["regime_" + side])
            bp[[r in ("no_contact", "unknown") for r in regime]] = np.nan
            top = max(top, np.nanmax(bp) if np.isfinite(bp).any() else 0.0)
            ax.plot(speed, bp, MARKERS[direction], color=COLORS[direction], ms=6 if side == "left" else 8,
                    mfc=COLORS[direction] if side == "left" else "none", alpha=0.85, zorder=4,
                    label=f"speed-{direction}, " + ("both contacts" if both else f"{side} contact"))
        if "jumps" in g:
            j = g["jumps"]
            merged = {}  # one label per change, naming the contacts that make it
            for kind, side, r0, r1 in zip(texts(j["kind"]), texts(j["contact"]),
                                          j["speed_from_rpm"][()], j["speed_to_rpm"][()]):
                if kind in ("contact_lost", "contact_regained"):
                    continue
                merged.setdefault((kind, float(r0), float(r1)), []).append(side)
            for (kind, r0, r1), contacts in merged.items():
                r = 0.5 * (r0 + r1)
                where = "both" if len(contacts) == 2 else contacts[0]
                ax.axvline(r, color=COLORS[direction], lw=0.6, ls=":", zorder=1)
                up = direction == "up"
                ax.annotate(f"{direction}: {kind.replace('_', ' ')} ({where}) {r0:g}→{r1:g} rpm",
                            (r, 0.01 if up else 0.99), xycoords=("data", "axes fraction"),
                            rotation=90, fontsize=6.5, color=COLORS[direction], xytext=(2, 0),
                            textcoords="offset points", va="bottom" if up else "top")
    ratios = rci(f)
    if ratios is not None and np.isfinite(lo):
        rpm = np.linspace(0.0, hi, 2)
        for side, ratio in zip(SIDES, ratios):
            ax.plot(rpm, ratio * rpm / 60.0, color="#888888", lw=0.8, ls=(0, (1, 2)), zorder=1)
            ax.annotate(f"rolling, RCI {ratio:.0f}", (hi, ratio * hi / 60.0), fontsize=7,
                        color="#666666", ha="right", va="bottom")
            if ratios[0] == ratios[1]:
                break
    has_branches = branches(f, ax)
    ax.set_xlim(0.0 if not np.isfinite(lo) else max(0.0, lo - 5.0), hi + 5.0 if np.isfinite(hi) else 1.0)
    ax.set_ylim(0.0, 1.15 * top if top > 0 else 1.0)
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel("backward precession (BP) frequency [Hz]")
    title = f"{name}: BP frequency, time-marching sweeps (L3)"
    title += " over the continuation branches" if has_branches else ""
    ax.set_title(title, fontsize=11)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right", ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "sweep_precession.png"), dpi=110)
    plt.close(fig)


def slip_velocity(f, outdir, name):
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
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
                import tomllib
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
    fig.savefig(os.path.join(outdir, "sweep_slip_velocity.png"), dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        print("usage: sweep.py RESULT.h5 OUTDIR", file=sys.stderr)
        return 2
    path, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    with h5py.File(path, "r") as f:
        if "sweeps" not in f:
            print(f"sweep.py: {path} has no /sweeps group", file=sys.stderr)
            return 1
        name = text(f.attrs.get("scene_name", os.path.splitext(os.path.basename(path))[0]))
        for direction in DIRECTIONS:
            if direction in f["sweeps"]:
                waterfall(f, direction, outdir, name)
                spectrum_map(f, direction, outdir, name)
        precession(f, outdir, name)
        slip_velocity(f, outdir, name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
