"""Figures of the rotating-wave level (L1): the whirl and whip branches against running speed.

Usage: python3 -m rubcont.plots.branches RESULT.h5 OUTDIR [--format png|pdf|svg]
Writes, from the HDF5 file only (layout: apps/branch_output.h, apps/analytic_output.h):
  OUTDIR/branches_precession.png  precession (BP) frequency against speed, every branch, stable
                                  solid and unstable dashed, special points marked, the rolling
                                  line Omega = RCI*omega and the analytic whip frequencies drawn in;
  OUTDIR/branches_slip.png        slip velocity at each contact against speed (thesis Fig. 14(b, c));
  OUTDIR/branches_mu.png          mu_req(Omega) of the closed form with the branches' F/N and their
                                  stick/slip switch points placed on it.
From Python: ``precession_figure(f)``, ``slip_figure(f)``, ``mu_figure(f)`` return the Figures;
``draw_branch(ax, group)`` draws one branch onto an Axes.
"""
import sys
import tomllib

import h5py
import numpy as np
from matplotlib.lines import Line2D

from .common import MissingData, command_line, keep_inside, new_figure, text

DPI = 150

MODE_COLORS = {"mode1": "#1f5fa8", "mode2": "#c0392b", "left_only": "#2e8b57",
               "right_only": "#d2691e", "single": "#1f5fa8"}
MODE_NAMES = {"mode1": "Mode 1 family", "mode2": "Mode 2 family",
              "left_only": "left contact only", "right_only": "right contact only",
              "single": "whirl / whip"}
MARKERS = {"event": ("o", "stick/slip switch or contact change"),
           "non_smooth_fold": ("s", "non-smooth fold (branch turns back)"),
           "fold": ("^", "fold"), "Hopf": ("*", "Hopf"),
           "real eigenvalue crossing": ("D", "real eigenvalue crossing"),
           "branch point": ("X", "branch point")}


def contacts_of(group):
    return [c for c in ("left", "right", "contact") if f"slip_velocity_{c}" in group]


def branches_of(result):
    """[(name, group)] of the file's /branches in numeric order (branch2 before branch10)."""
    if "branches" not in result:
        raise MissingData("no /branches group")
    out = []
    for name, group in result["branches"].items():
        if not isinstance(group, h5py.Group) or "speed_rpm" not in group:
            continue
        out.append((name, group))
    return sorted(out, key=lambda item: int("".join(ch for ch in item[0] if ch.isdigit()) or 0))


def stable_runs(stable):
    """[(start, end, is_stable)] runs of constant stability, sharing their end points."""
    runs, i, n = [], 0, len(stable)
    while i < n - 1:
        j = i
        while j + 1 < n and stable[j + 1] == stable[i]:
            j += 1
        runs.append((i, min(j + 1, n - 1), stable[i] == 1))
        i = j if j > i else i + 1
    return runs


def plot_lines(ax, x, y, stable, color):
    for start, end, is_stable in stable_runs(stable):
        ax.plot(x[start:end + 1], y[start:end + 1], color=color, lw=1.6 if is_stable else 1.0,
                ls="-" if is_stable else (0, (4, 2)))


def special_points(group):
    sp = group["special_points"]
    if "type" not in sp or len(sp["type"]) == 0:
        return []
    total = total_normal_force(sp)
    return [dict(type="non_smooth_fold" if n else text(t), label=text(l), rpm=float(r),
                 hz=float(h), total_normal=float(f))
            for t, l, r, h, n, f in zip(sp["type"][()], sp["label"][()], sp["speed_rpm"][()],
                                        sp["precession_hz"][()], sp["nonsmooth_fold"][()], total)]


def mark(ax, points, x_key, y_of, color):
    for p in points:
        marker, _ = MARKERS.get(p["type"], ("P", p["type"]))
        y = y_of(p)
        if y is None:
            continue
        ax.plot(p[x_key], y, marker, ms=6 if marker != "*" else 9, mfc="white", mec=color,
                mew=1.3, zorder=5)


def legend_handles(modes, types):
    handles = [Line2D([], [], color=MODE_COLORS[m], lw=1.6, label=MODE_NAMES[m]) for m in modes]
    handles += [Line2D([], [], color="0.2", lw=1.6, label="stable"),
                Line2D([], [], color="0.2", lw=1.0, ls=(0, (4, 2)), label="unstable")]
    for t in types:
        marker, label = MARKERS.get(t, ("P", t))
        handles.append(Line2D([], [], ls="none", marker=marker, mfc="white", mec="0.2", label=label))
    return handles


def title(result, what):
    return f"{text(result.attrs['scene_name'])}: {what}"


def total_normal_force(group):
    """Σ_k N_k [N] over the contacts in touch: separates families that share the whirl line."""
    total = np.zeros(len(group["type"] if "type" in group else group["speed_rpm"]))
    for contact in contacts_of(group):
        touching = group[f"mode_{contact}"][()] != 0
        total += np.where(touching, group[f"normal_force_{contact}"][()], 0.0)
    return total


def draw_branch(ax, group, color=None, y="precession_hz"):
    """One branch's `y` against speed on `ax` (stable solid, unstable dashed, special points
    marked); the family's colour unless `color`. Returns the special points drawn."""
    color = color or MODE_COLORS.get(text(group.attrs.get("mode", "")), "0.3")
    plot_lines(ax, group["speed_rpm"][()], group[y][()], group["stable"][()], color)
    points = special_points(group)
    if y == "precession_hz":
        mark(ax, points, "rpm", lambda p: p["hz"], color)
    return points


def precession_figure(result, fig=None):
    """Precession frequency and total normal force of every branch against speed."""
    branches = branches_of(result)
    fig = new_figure(fig, figsize=(8.6, 8.4), dpi=DPI)
    ax, ax_n = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    modes, types = [], set()
    speed_range = result["branches"]["speed_range_rpm"][()]
    rpm = np.linspace(speed_range[0], speed_range[1], 2)
    scene_rci = rci_of(result)
    for rci in sorted(set(scene_rci)):
        ax.plot(rpm, rci * rpm / 60.0, color="0.55", lw=0.8, ls=":",
                label=f"rolling Ω = RCI·ω (RCI {rci:g})")
    for whip in whip_frequencies(result):
        ax.axhline(whip, color="0.75", lw=0.7, ls="-.")
    for name, group in branches:
        mode = text(group.attrs["mode"])
        color = MODE_COLORS.get(mode, "0.3")
        if mode not in modes:
            modes.append(mode)
        points = draw_branch(ax, group, color)
        x, stable = group["speed_rpm"][()], group["stable"][()]
        plot_lines(ax_n, x, total_normal_force(group), stable, color)
        types.update(p["type"] for p in points)
        mark(ax_n, points, "rpm", lambda p: p["total_normal"], color)
    handles = legend_handles(modes, sorted(types))
    handles += [Line2D([], [], color="0.55", lw=0.8, ls=":", label="rolling Ω = RCI·ω"),
                Line2D([], [], color="0.75", lw=0.7, ls="-.", label="closed-form whip (μ_req = μ)")]
    ax_n.set_xlim(speed_range[0], speed_range[1])
    ax_n.set_xlabel("running speed ω [rpm]")
    ax.set_ylabel("backward precession frequency Ω/2π [Hz]")
    ax_n.set_ylabel("total normal force Σ N [N]")
    ax_n.set_yscale("symlog", linthresh=10.0)
    ax_n.set_ylim(bottom=0.0)
    ax.set_title(title(result, "rotating waves (L1) against running speed"), fontsize=11)
    for a in (ax, ax_n):
        a.grid(True, lw=0.3, alpha=0.5)
    ax.legend(handles=handles, fontsize=7, loc="upper left", ncol=2, framealpha=0.9)
    fig.tight_layout()
    return fig


def slip_figure(result, fig=None):
    """Slip velocity at each contact against speed, every branch."""
    branches = branches_of(result)
    contacts = contacts_of(branches[0][1])
    fig = new_figure(fig, figsize=(8.6, 3.0 + 2.4 * len(contacts)), dpi=DPI)
    axes = fig.subplots(len(contacts), 1, sharex=True, squeeze=False)
    modes = []
    for k, contact in enumerate(contacts):
        ax = axes[k][0]
        for name, group in branches:
            mode = text(group.attrs["mode"])
            color = MODE_COLORS.get(mode, "0.3")
            if mode not in modes:
                modes.append(mode)
            x, v = group["speed_rpm"][()], group[f"slip_velocity_{contact}"][()]
            touching = group[f"mode_{contact}"][()] != 0
            plot_lines(ax, x, np.where(touching, v, np.nan), group["stable"][()], color)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"slip velocity V, {contact} [m/s]")
        ax.grid(True, lw=0.3, alpha=0.5)
    speed_range = result["branches"]["speed_range_rpm"][()]
    axes[-1][0].set_xlim(speed_range[0], speed_range[1])
    axes[-1][0].set_xlabel("running speed ω [rpm]")
    axes[0][0].set_title(title(result, "slip velocity of the rotor surface over the stator "
                                       "(0: rolling; contacts out of touch not drawn)"), fontsize=10)
    axes[0][0].legend(handles=legend_handles(modes, []), fontsize=7, loc="upper left")
    fig.tight_layout()
    if keep_inside(fig, axes[0][0].title):
        fig.tight_layout()
    return fig


def mu_figure(result, fig=None):
    """mu_req of the closed form with the branches' F/N and their stick/slip switches."""
    branches = branches_of(result)
    analytic = result.get("analytic")
    mu = float(analytic.attrs["friction"]) if analytic is not None else None
    fig = new_figure(fig, figsize=(8.6, 5.6), dpi=DPI)
    ax = fig.subplots()
    limit = 3 * mu if mu else 1.5
    if analytic is not None:
        for mode in ("mode1", "mode2", "single"):
            if mode not in analytic:
                continue
            group = analytic[mode]
            hz = group["precession_hz"][()]
            for contact in ("left", "right", "contact"):
                key = f"mu_required_{contact}"
                if key not in group:
                    continue
                curve = np.where(group[f"normal_force_{contact}"][()] > 0, group[key][()], np.nan)
                ax.plot(hz, np.clip(curve, -10 * limit, 10 * limit),
                        color=MODE_COLORS[mode], lw=0.9, alpha=0.6,
                        ls="-" if contact != "right" else (0, (5, 2)),
                        label=f"closed form {mode} μ_req" + ("" if contact == "contact" else f", {contact}"))
        ax.axhline(mu, color="black", lw=1.0, ls=(0, (8, 3)), label=f"available μ = {mu:g}")
    for name, group in branches:
        mode = text(group.attrs["mode"])
        color = MODE_COLORS.get(mode, "0.3")
        for contact in contacts_of(group):
            ratio = group[f"mu_ratio_{contact}"][()]
            ax.plot(group["precession_hz"][()], ratio, ".", ms=2.0, color=color, alpha=0.7)
        for p in special_points(group):
            if p["type"] in ("event", "non_smooth_fold") and "slip" in p["label"] and mu:
                marker, _ = MARKERS[p["type"]]
                ax.plot(p["hz"], mu, marker, ms=7, mfc="white", mec=color, mew=1.4, zorder=6)
                ax.annotate(f"{p['hz']:.3f} Hz", (p["hz"], mu), xytext=(4, 6),
                            textcoords="offset points", fontsize=7, rotation=90, color=color)
    ax.plot([], [], ".", color="0.3", label="F/N along the L1 branches")
    ax.plot([], [], "o", mfc="white", mec="0.3", label="located stick ↔ slip switches")
    ax.set_ylim(-limit, limit)
    ax.set_xlabel("precession frequency Ω/2π [Hz]")
    ax.set_ylabel("required friction μ_req = F/N")
    ax.set_title(title(result, "closed form (L0) and rotating waves (L1)"), fontsize=11)
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.legend(fontsize=7, loc="lower right", ncol=2)
    fig.tight_layout()
    return fig


def rci_of(result):
    """The contacts' R/C from the scene stored in the file."""
    scene = tomllib.loads(text(result.attrs["scene_toml"]))
    if "jeffcott" in scene:
        return [scene["jeffcott"]["R"] / scene["jeffcott"]["C"]]
    contact = scene["contact"]
    return [r / c for r, c in zip(contact["radius"], contact["clearance"])]


def whip_frequencies(result):
    analytic = result.get("analytic")
    if analytic is None:
        return []
    out = []
    for mode in ("mode1", "mode2", "single"):
        if mode in analytic:
            t = analytic[mode]["transitions"]
            out += [float(hz) for kind, hz in zip(t["type"][()], t["precession_hz"][()])
                    if text(kind) == "mu_crossing"]
    return sorted(set(round(hz, 6) for hz in out))


def figures(result, stem=""):
    """branches_precession, branches_slip and branches_mu."""
    if not branches_of(result):
        raise MissingData("no branch in /branches")
    yield "branches_precession", precession_figure(result)
    yield "branches_slip", slip_figure(result)
    yield "branches_mu", mu_figure(result)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
