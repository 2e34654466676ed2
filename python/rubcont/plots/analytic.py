"""Figures of the analytic level (L0): required friction against precession frequency.

Usage: python3 -m rubcont.plots.analytic RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes OUTDIR/analytic_mode1.png and OUTDIR/analytic_mode2.png (or analytic_single.png for the
single-contact Jeffcott scene), one per mode, to be read beside
Kumar (2010) Figures 5-10: mu_req = F/N at both contacts against the precession frequency, the
available mu as a line, the bands where a contact is lost (N <= 0) shaded, every transition
labelled with its frequency. Reads only the HDF5 file (layout: apps/analytic_output.h).
From Python: ``mode_figure(f, "mode1")`` returns the Figure of one mode.
"""
import sys

import numpy as np

from .common import MissingData, command_line, new_figure, text

DPI = 150

SIDES = ("left", "right")
COLORS = {"left": "#1f5fa8", "right": "#d2691e"}
STYLES = {"left": "-", "right": (0, (5, 2.5))}
COLORS["contact"] = "black"
STYLES["contact"] = "-"
MODE_TITLES = {"mode1": "Mode 1 (contact normals in phase)",
               "mode2": "Mode 2 (contact normals in antiphase)",
               "single": "one contact (Jeffcott rotor, elastic stator)"}


def read_transitions(group):
    t = group["transitions"]
    return [dict(type=text(kind), contact=text(side), hz=float(hz), direction=int(d))
            for kind, side, hz, d in zip(t["type"][()], t["contact"][()],
                                         t["precession_hz"][()], t["direction"][()])]


def loss_intervals(hz, lost):
    """[(start, end)] of runs where `lost` is true, edges halfway between grid points."""
    intervals = []
    i, n = 0, len(hz)
    while i < n:
        if lost[i]:
            j = i
            while j + 1 < n and lost[j + 1]:
                j += 1
            start = hz[0] if i == 0 else 0.5 * (hz[i - 1] + hz[i])
            end = hz[-1] if j == n - 1 else 0.5 * (hz[j] + hz[j + 1])
            intervals.append((start, end))
            i = j + 1
        else:
            i += 1
    return intervals


def broken_at_poles(mu, normal):
    """mu_req with NaN inserted where N changes sign, so poles draw no vertical line."""
    mu = mu.copy()
    flips = np.nonzero(np.sign(normal[:-1]) != np.sign(normal[1:]))[0]
    mu[flips] = np.nan
    return mu


def snap(value, transitions, kinds):
    """A band edge moved onto the located transition nearest to it (exact, not grid-rounded)."""
    candidates = [t["hz"] for t in transitions if t["type"] in kinds]
    if not candidates:
        return value
    nearest = min(candidates, key=lambda hz: abs(hz - value))
    return nearest if abs(nearest - value) < 1.0 else value


def fmt_number(value):
    """A number with a real minus sign."""
    return f"{value:g}".replace("-", "\u2212")


def mode_figure(result, mode, fig=None):
    """mu_req of one mode ("mode1", "mode2" or "single") of the file's /analytic."""
    analytic = result["analytic"]
    group = analytic[mode]
    hz = group["precession_hz"][()]
    mu_available = float(analytic.attrs["friction"])
    center_damping = float(analytic.attrs.get("center_damping", 0.0))
    scene = text(result.attrs["scene_name"])
    transitions = read_transitions(group)
    single = mode == "single"
    present = ("contact",) if single else SIDES
    normal = {side: group[f"normal_force_{side}"][()] for side in present}
    mu = {side: group[f"mu_required_{side}"][()] for side in present}
    # Equal forces at both contacts (a symmetric rotor): draw one curve and label once.
    symmetric = single or (
        np.allclose(normal["left"], normal["right"], rtol=1e-9, atol=1e-9) and
        np.allclose(mu["left"], mu["right"], rtol=1e-9, atol=1e-12, equal_nan=True))
    sides = present[:1] if symmetric else SIDES

    def color(side):
        return "black" if symmetric else COLORS[side]

    limit = 3.0 * mu_available if mu_available > 0 else 1.0
    span = hz[-1] - hz[0]
    fig = new_figure(fig, figsize=(8.4, 5.6), dpi=DPI)
    ax = fig.subplots()

    # Contact-loss bands: both contacts (grey), one contact only (its colour).
    lost = {side: normal[side] <= 0.0 for side in present}
    if single:
        bands = [(lost["contact"], "0.55", "contact lost (N ≤ 0)")]
    else:
        bands = [(lost["left"] & lost["right"], "0.55", "contact lost (N ≤ 0)" if symmetric else
                  "contact lost at both (N ≤ 0)"),
                 (lost["left"] & ~lost["right"], COLORS["left"], "contact lost at left only"),
                 (lost["right"] & ~lost["left"], COLORS["right"], "contact lost at right only")]
    loss_kinds = ("contact_loss", "contact_regain")
    for mask, band_color, label in bands:
        for k, (start, end) in enumerate(loss_intervals(hz, mask)):
            start, end = snap(start, transitions, loss_kinds), snap(end, transitions, loss_kinds)
            ax.axvspan(start, end, color=band_color, alpha=0.17, lw=0, label=label if k == 0 else None)

    clip = 10 * limit  # keeps matplotlib away from the poles' huge values
    # Thesis form (no centre damper), thin, when the scene's damper makes it differ.
    differs = "without_center_damper" in group and any(
        not np.allclose(group["without_center_damper"][f"friction_force_{side}"][()],
                        group[f"friction_force_{side}"][()], rtol=1e-12, atol=0.0) for side in SIDES)
    if differs:  # (in Mode 2 with equal clearances the damper does nothing)
        reference = group["without_center_damper"]
        for side in sides:
            curve = broken_at_poles(reference[f"mu_required_{side}"][()],
                                    reference[f"normal_force_{side}"][()])
            curve = np.where(normal[side] > 0.0, curve, np.nan)  # N does not depend on c_d
            ax.plot(hz, np.clip(curve, -clip, clip), color=color(side), lw=0.8, ls=":",
                    label="thesis form c_d = 0" + ("" if symmetric else f", {side}"))

    for side in sides:
        curve = broken_at_poles(mu[side], normal[side])
        in_contact = np.where(normal[side] > 0.0, curve, np.nan)
        out_of_contact = np.where(normal[side] > 0.0, np.nan, curve)
        label = "μ_req" if single else ("μ_req, left = right" if symmetric else f"μ_req, {side}")
        ax.plot(hz, np.clip(in_contact, -clip, clip), color=color(side), ls=STYLES[side], lw=1.8,
                label=label)
        ax.plot(hz, np.clip(out_of_contact, -clip, clip), color=color(side), ls=STYLES[side],
                lw=1.0, alpha=0.3)

    ax.axhline(mu_available, color="black", lw=1.0, ls=(0, (8, 3)),
               label=f"available μ = {fmt_number(mu_available)}")
    if any(t["type"] == "negative_mu_crossing" for t in transitions):
        ax.axhline(-mu_available, color="black", lw=0.8, ls=(0, (2, 2)),
                   label=f"−μ = {fmt_number(-mu_available)}")
    ax.axhline(0.0, color="0.6", lw=0.6)

    # Transitions. A crossing of μ_req = +μ, −μ or 0 (diamond) is marked on its line and labelled
    # on one side of it (+μ: below; −μ, 0: above), horizontally away from the curve (a rising
    # crossing of +μ has the curve on its left below the line, so its label goes right). Contact loss and regain are ticks hanging from
    # the top edge. Labels close in frequency are staggered.
    box = dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85)
    placed = {"mu": [], "contact": []}
    for t in transitions:
        side = t["contact"]
        if side not in sides:
            continue
        if t["type"] in ("mu_crossing", "negative_mu_crossing", "zero_mu_crossing"):
            # +μ: label below the line; −μ and 0: label above it.
            y = {"mu_crossing": mu_available, "negative_mu_crossing": -mu_available,
                 "zero_mu_crossing": 0.0}[t["type"]]
            positive = t["type"] == "mu_crossing"
            marker = "o" if t["type"] != "zero_mu_crossing" else "D"
            ax.plot(t["hz"], y, marker, ms=4.5 if marker == "o" else 3.5, mfc="white",
                    mec=color(side), mew=1.4, zorder=5)
            right = (t["direction"] > 0) == positive
            if t["hz"] - hz[0] < 0.04 * span or hz[-1] - t["hz"] < 0.04 * span:
                right = t["hz"] - hz[0] < 0.5 * span  # keep labels off the axes' edges
            near = sum(1 for hz0, y0 in placed["mu"] if abs(hz0 - t["hz"]) < 0.03 * span and y0 == y)
            dy = -(5 + 40 * near) if positive else 5 + 40 * near
            ax.annotate(f"{t['hz']:.2f} Hz", (t["hz"], y), xytext=(5 if right else -5, dy),
                        textcoords="offset points", fontsize=7.5, rotation=90,
                        ha="left" if right else "right", va="top" if positive else "bottom",
                        color=color(side), bbox=box, zorder=6)
            placed["mu"].append((t["hz"], y))
        else:
            ax.axvline(t["hz"], ymin=0.96, color=color(side), lw=1.0)
            near = sum(1 for hz0 in placed["contact"] if abs(hz0 - t["hz"]) < 0.025 * span)
            ax.annotate(f"{t['hz']:.2f}", (t["hz"], limit), xytext=(0, -9 - 27 * (near % 3)),
                        textcoords="offset points", fontsize=7, rotation=90, ha="center", va="top",
                        color=color(side), bbox=box, zorder=6)
            placed["contact"].append(t["hz"])

    # Natural frequencies on the top axis: P = rotor and stator pinned, S = stator alone.
    nf = analytic["natural_frequencies"].attrs
    top = ax.secondary_xaxis("top")
    if single:
        ticks = [(float(nf["rotor_hz"]), "R"), (float(nf["combined_hz"]), "P"),
                 (float(nf["stator_hz"]), "S")]
    else:
        ticks = [(float(nf["pinned_bounce_hz"]), "P$_b$"), (float(nf["pinned_pitch_hz"]), "P$_p$"),
                 (float(nf["stator_bounce_hz"]), "S$_b$"), (float(nf["stator_pitch_hz"]), "S$_p$")]
    ticks = [(x, name) for x, name in ticks if hz[0] <= x <= hz[-1]]
    top.set_xticks([x for x, _ in ticks])
    top.set_xticklabels([name for _, name in ticks], fontsize=8)
    top.tick_params(direction="in", length=5, pad=2)

    ax.set_xlim(hz[0], hz[-1])
    ax.set_ylim(-limit, limit)
    ax.set_xlabel("precession frequency Ω/2π [Hz]")
    ax.set_ylabel("required friction μ_req = F/N")
    ax.set_title(f"{scene}: {MODE_TITLES[mode]}", fontsize=11.5, pad=30)
    note = ("level L0 closed form (Black 1968, Crandall 1990);  top ticks: natural frequencies, "
            "R rotor alone / P rotor and stator pinned / S stator alone") if single else (
        f"level L0 closed form, centre damper c_d = {fmt_number(center_damping)} N·s/m;  "
        "top ticks: natural frequencies, P pinned rotor and stator / S stator alone, "
        "b bounce / p pitch")
    ax.annotate(note, (0.5, 1.0), xycoords="axes fraction", xytext=(0, 17),
                textcoords="offset points", ha="center", va="bottom", fontsize=7, color="0.3")
    ax.grid(True, lw=0.3, alpha=0.5)
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7.5, frameon=False,
               bbox_to_anchor=(0.5, 0.0))
    rows = (len(labels) + 2) // 3
    fig.tight_layout(rect=(0, 0.03 * rows + 0.01, 1, 1))
    return fig


def figures(result, stem=""):
    """analytic_<mode> for every mode in /analytic."""
    if "analytic" not in result:
        raise MissingData("no /analytic group")
    for mode in ("mode1", "mode2", "single"):
        if mode in result["analytic"]:
            yield f"analytic_{mode}", mode_figure(result, mode)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
