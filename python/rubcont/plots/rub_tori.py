"""Figure of the whips modulated at two frequencies (L2 tori) over the modulated orbits they are born from.

Usage: python3 -m rubcont.plots.rub_tori RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/tori_stage.h):
  OUTDIR/tori.png  against running speed, over the speeds of the orbits and tori:
                   top: modulation frequencies — each modulated family's 1/T (stable solid,
                   unstable dashed, its Neimark–Sacker points starred) and each torus family's
                   f1 = 1/T and f2 = rho/T (filled markers: stable by its Lyapunov exponents,
                   open: unstable, grey: undecided within the estimate's error or not computed);
                   second: the tori's rotation number rho, with the rationals p/q (q <= 2K + 1, 17)
                   near it drawn, the end of each family labelled (phase locking / breakdown),
                   and where a family locks, its q-lap orbits at p/q (stable solid, unstable
                   dashed) between their folds, the tongue's edges (also on the top panel:
                   q / their period);
                   third: each contact's strongest line of precession besides the carrier
                   (fixed frame) and the carrier;
                   bottom: the circle's Fourier tail, invariance error and radius (log).
                   Where a family shrinks onto its centre, the orbits there (1/T, top; their
                   carrier, third; stable solid, unstable dashed, over the speeds they were
                   followed), their folds (triangle, top) and their Neimark–Sacker point (star,
                   second) are drawn.
From Python: ``figure(f)`` returns the Figure.
"""
import sys
from fractions import Fraction

import numpy as np

from .branches import stable_runs
from .common import MissingData, command_line, one_figure, new_figure, text

DPI = 130

COLORS = ["#000000", "#7b2cbf", "#b8860b", "#008b8b"]
CONTACT_COLORS = ["#1f77b4", "#d62728", "#2ca02c"]


def line_contacts(group):
    return [c for c in ("left", "right", "contact") if f"line_hz_{c}" in group]


def torus_families(tori):
    return sorted(name for name in tori
                  if name != "orbits" and not name.endswith(("_locked", "_centre")))


def scatter_stable(ax, x, y, stable, color, label):
    """Filled where stable (1), open where unstable (0), grey where undecided or not computed (-1)."""
    for flag, face, edge in ((1, color, color), (0, "none", color), (-1, "none", "#999999")):
        pick = stable == flag
        if np.any(pick):
            ax.plot(x[pick], y[pick], "o", ms=4, mfc=face, mec=edge, lw=0, label=label)
            label = None


def figure(f, fig=None):
    """The figure of the file's /tori group."""
    if "tori" not in f:
        raise MissingData("no /tori group")
    tori = f["tori"]
    families = torus_families(tori)
    orbits = tori["orbits"] if "orbits" in tori else {}
    fig = new_figure(fig, figsize=(8.5, 12.5))
    axes = fig.subplots(4, 1, sharex=True, gridspec_kw={"height_ratios": [3, 2, 2, 1.6]})
    ax_f, ax_rho, ax_lines, ax_tail = axes
    speeds, focus = [], []
    for i, name in enumerate(sorted(orbits)):
        g = orbits[name]
        rpm, modulation = g["speed_rpm"][()], g["modulation_hz"][()]
        color = COLORS[i % len(COLORS)]
        for a, b, stable in stable_runs(g["stable"][()]):
            ax_f.plot(rpm[a:b + 1], modulation[a:b + 1], "-" if stable else "--", color=color,
                      lw=1.6, label=f"{name}: 1/T of the modulated whip" if a == 0 else None)
        sp = g["special_points"]
        if "type" in sp:
            for t, r, m in zip(sp["type"][()], sp["speed_rpm"][()], sp["modulation_hz"][()]):
                if text(t) == "Neimark-Sacker":
                    ax_f.plot([r], [m], "*", ms=13, color="#e07000", zorder=5,
                              label="Neimark–Sacker point")
        speeds.append(rpm)
    for j, name in enumerate(families):
        g = tori[name]
        rpm = g["speed_rpm"][()]
        if len(rpm) == 0:
            continue
        speeds.append(rpm)
        focus.append(rpm)
        stable = g["stable"][()]
        color = COLORS[(j + 1) % len(COLORS)]
        scatter_stable(ax_f, rpm, g["first_hz"][()], stable, color, f"{name}: f1 = 1/T")
        scatter_stable(ax_f, rpm, g["second_hz"][()], stable, "#e07000", f"{name}: f2 = ρ/T")
        rho = g["rotation_number"][()]
        ax_rho.plot(rpm, rho, "-", color=color, lw=1.2)
        scatter_stable(ax_rho, rpm, rho, stable, color, name)
        harmonics = int(g.attrs.get("harmonics", 8))
        low, high = float(np.min(rho)), float(np.max(rho))
        pad = 0.15 * max(high - low, 0.01)
        # Orders above 17 (K = 8's 2K + 1) fill the panel where K is refined (K = 32: q ≤ 65).
        for q in range(1, min(2 * harmonics + 1, 17) + 1):
            for p in range(0, q + 1):
                if np.gcd(p, q) != 1:
                    continue
                value = p / q
                if low - pad <= value <= high + pad:
                    ax_rho.axhline(value, color="#bbbbbb", lw=0.7, zorder=0)
                    ax_rho.annotate(str(Fraction(p, q)), (rpm[0], value), fontsize=7,
                                    color="#777777", va="bottom")
        if name + "_locked" in tori:
            lock = tori[name + "_locked"]
            p, q = int(lock.attrs["resonance_p"]), int(lock.attrs["resonance_q"])
            lrpm = lock["speed_rpm"][()]
            focus.append(lrpm)
            for a, b, stable_run in stable_runs(lock["stable"][()]):
                ax_rho.plot(lrpm[a:b + 1], np.full(b - a + 1, p / q), "-" if stable_run else "--",
                            color="#c00000", lw=2.5,
                            label=f"{q}-lap locked orbits ({p}:{q})" if a == 0 else None)
                ax_f.plot(lrpm[a:b + 1], q / lock["period"][()][a:b + 1],
                          "-" if stable_run else "--", color="#c00000", lw=2.0,
                          label=f"{q}-lap locked orbits: q / their period" if a == 0 else None)
            for fold in np.atleast_1d(lock.attrs.get("fold_speeds_rpm", [])):
                ax_rho.axvline(float(fold), color="#c00000", lw=0.8, ls=":")
            ax_rho.legend(fontsize=7, loc="best")
        if name + "_centre" in tori:
            centre = tori[name + "_centre"]
            crpm = centre["speed_rpm"][()]
            focus.append(crpm)
            for a, b, stable_run in stable_runs(centre["stable"][()]):
                ax_f.plot(crpm[a:b + 1], 1.0 / centre["period"][()][a:b + 1],
                          "-" if stable_run else "--", color="#6a3d9a", lw=2.0,
                          label=("the orbits the tori shrink onto: 1/T (stable solid)"
                                 if a == 0 else None))
                if "precession_hz" in centre:  # files made before their rub measures have none
                    ax_lines.plot(crpm[a:b + 1], centre["precession_hz"][()][a:b + 1],
                                  "-" if stable_run else "--", color="#6a3d9a", lw=1.5,
                                  label=("the orbits the tori shrink onto: carrier"
                                         if a == 0 else None))
            # Where the orbits at the centre turn back (a fold: the stable whip ends there).
            sp = centre.get("special_points")
            if sp is not None and "type" in sp and "period" in sp:
                folds = [(float(r), float(T)) for t, r, T in
                         zip(sp["type"][()], sp["speed_rpm"][()], sp["period"][()])
                         if text(t) == "fold"]
                for k, (r, T) in enumerate(folds):
                    ax_f.plot([r], [1.0 / T], "^", ms=7, mfc="white", mec="#6a3d9a", mew=1.3,
                              zorder=5, label="fold of the orbits at the centre" if k == 0 else None)
            ns = float(centre.attrs.get("neimark_sacker_speed_rpm", np.nan))
            if np.isfinite(ns):
                angle = float(centre.attrs["neimark_sacker_rotation_number"])
                # The circle's orientation is its fit's: the multiplier's angle as ρ or 1 − ρ.
                shown = angle if abs(angle - rho[-1]) <= abs(1 - angle - rho[-1]) else 1 - angle
                ax_rho.plot([ns], [shown], "*", ms=13, color="#6a3d9a", zorder=5,
                            label="Neimark–Sacker point of the orbits at the centre")
                ax_rho.legend(fontsize=7, loc="best")
        end = text(g.attrs.get("end", ""))
        # Stacked by family: a transient's two families can end within a hair of each other.
        ax_rho.annotate(end, (rpm[-1], rho[-1]), fontsize=8, xytext=(-60, -4 + 10 * (j % 3)),
                        textcoords="offset points", color=color)
        carrier = g["carrier_hz"][()]
        ax_lines.plot(rpm, carrier, "-", color="#555555", lw=1.2,
                      label="carrier" if j == 0 else None)
        for c, contact in enumerate(line_contacts(g)):
            ax_lines.plot(rpm, g["line_hz_" + contact][()], "o-", ms=3, lw=1,
                          color=CONTACT_COLORS[c % len(CONTACT_COLORS)],
                          label=f"{contact}: strongest line besides the carrier" if j == 0 else None)
        ax_tail.semilogy(rpm, g["fourier_tail"][()], "o-", ms=3, color=color,
                         label="Fourier tail (last harmonic / largest)" if j == 0 else None)
        ax_tail.semilogy(rpm, g["invariance_error"][()], "s--", ms=3, color="#888888",
                         label="invariance error between the points" if j == 0 else None)
        if "radius" in g:  # files made before the radius measure have none
            ax_tail.semilogy(rpm, g["radius"][()], "^-", ms=3, color="#222222",
                             label="circle radius (scaled state)" if j == 0 else None)
    if not families:
        ax_f.text(0.5, 0.5, "no Neimark–Sacker point bounds a stable modulated whip: no tori",
                  transform=ax_f.transAxes, ha="center")
    # From the families' start to a little past the tori and locked orbits (the modulated
    # families run on beyond, unstable).
    if speeds:
        every = np.concatenate(speeds)
        low = every.min()
        high = np.concatenate(focus).max() if focus else every.max()
        span = max(high - low, 1e-3)
        ax_tail.set_xlim(low - 0.05 * span, high + 0.25 * span)
    ax_f.set_ylabel("modulation frequency [Hz]\n(co-rotating frame)")
    ax_f.legend(fontsize=7, loc="best")
    ax_f.set_title(f"{text(f.attrs.get('scene_name', ''))}: whips modulated at two frequencies (L2 tori)")
    ax_rho.set_ylabel("rotation number ρ")
    ax_lines.set_ylabel("backward precession [Hz]\n(fixed frame)")
    ax_lines.legend(fontsize=7, loc="best")
    ax_tail.set_ylabel("circle size measures")
    ax_tail.set_xlabel("running speed [rpm]")
    ax_tail.legend(fontsize=7, loc="best")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


figures = one_figure(figure, "tori")

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
