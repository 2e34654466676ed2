"""The hysteresis loop of a scene, explained (rubcont loop): one page per contact.

Usage: python3 -m rubcont.plots.loop LOOP.h5 OUTDIR [--format png|pdf|svg]
Writes OUTDIR/<file stem>.png from the HDF5 file only (layout: apps/loop_output.h). Against running
speed, the backward precession (BP) at each contact:
  - the rolling line BP = (R/C)·speed, and the rotating waves (L1: stable solid, unstable dashed,
    where the contact touches);
  - the run-up and the run-down as the loop followed them: a marker per speed integrated (L3), a
    line along each wave the run was moved on by L1 (its stable stretch), and an arrow for each jump;
  - every corner numbered at its speed, its interval as a bar (the regularization's for L1, the
    5–95 % of the speed a run of the schedule leaves at for L3, with the crisis's p_c beside it);
  - the corners listed in a box: run, jump, speed and interval, cause, level;
  - L2's orbit families (/loop/orbits: the modulated state's family, period T, green; the doubled
    family from the period doubling the run meets on it, period 2T, brown), stable solid and
    unstable dashed: their carrier precession on the page, and below it, on the same speed axis,
    their modulation frequency with the special points that end a state (period doubling, fold,
    Neimark–Sacker, branch point, grazing) marked and named.
One page when both contacts show the same loop. From Python: ``figure(f)`` returns the Figure.
"""
import os
import sys
import tomllib

import numpy as np

from .common import MissingData, command_line, new_figure, text

DPI = 100

RUN_COLOR = {"up": "tab:orange", "down": "tab:purple"}
RUN_MARKER = {"up": "^", "down": "v"}
KIND_WORDS = {"whirl_to_whip": "whirl → whip", "whip_to_whirl": "whip → whirl", "contact_lost": "contact lost",
              "contact_regained": "contact regained", "frequency_jump": "frequency jump"}


def strings(dataset):
    return [text(v) for v in dataset[()]]


def pieces(ax, x, y, stable, touching, color, lw):
    """Stable pieces solid, unstable dashed; only where the contact touches."""
    start = 0
    n = len(x)
    for i in range(1, n + 1):
        if i == n or stable[i] != stable[start] or touching[i] != touching[start]:
            end = min(i + 1, n)
            if touching[start]:
                ax.plot(x[start:end], y[start:end], color=color, lw=lw, ls="-" if stable[start] else "--")
            start = i


ORBIT_COLOR = {False: "tab:green", True: "tab:brown"}
ORBIT_WORDS = {False: "modulated state, period T (L2)", True: "its doubled orbits, period 2T (L2)"}
# The special points that end a state (studies/loop.h, EndsState), as marked on the families.
ENDS_STATE = {"fold": "fold", "period doubling": "PD", "Neimark-Sacker": "NS", "branch point": "BP",
              "multiplier +1": "+1", "grazing": "grazing"}


def has_families(loop):
    return "orbits" in loop and any("speed_rpm" in loop["orbits"][n] for n in loop["orbits"])


def orbit_families(ax, loop, quantity="precession_hz", marks=True, span=None):
    """L2's families: period T and the doubled ones, `quantity` against speed, stable solid, unstable
    dashed; with `marks` the points that end a state marked and named — each once (a family that
    comes back along itself passes its points again) and, where they lie within 3 % of `span` (the
    speed axis's width) of each other, in one label listing them (C(b)'s doubled whip: five points
    within 0.06 rpm). Returns the largest value drawn (0 without families)."""
    top = 0.0
    if "orbits" not in loop:
        return top
    drawn = set()
    named = []  # (speed, value, text, color) of every point named
    for name in sorted(loop["orbits"], key=lambda n: (len(n), n)):
        g = loop["orbits"][name]
        if "speed_rpm" not in g or "precession_hz" not in g:
            continue
        doubled = "_pd" in name
        color = ORBIT_COLOR[doubled]
        x, y = g["speed_rpm"][()], g[quantity][()]
        order = np.argsort(g["arclength"][()]) if "arclength" in g else np.arange(len(x))
        x, y, stable = x[order], y[order], (g["stable"][()] > 0)[order]
        pieces(ax, x, y, stable, np.ones(len(x), bool), color, 1.8)
        if np.isfinite(y).any():
            top = max(top, np.nanmax(y))
        if doubled not in drawn:
            drawn.add(doubled)
            ax.plot([], [], color=color, lw=1.8, label=ORBIT_WORDS[doubled] + ", stable")
            ax.plot([], [], color=color, lw=1.8, ls="--", label=ORBIT_WORDS[doubled] + ", unstable")
        sp = g["special_points"]
        if not marks or "type" not in sp or quantity not in sp:
            continue
        for k, kind in enumerate(strings(sp["type"])):
            if kind not in ENDS_STATE:
                continue
            xs, ys = sp["speed_rpm"][k], sp[quantity][k]
            text = f"{ENDS_STATE[kind]} {xs:.2f}"
            if any(t == text and c == color for _, _, t, c in named):
                continue
            ax.plot([xs], [ys], "D", color=color, mec="k", ms=5)
            named.append((xs, ys, text, color))
    # A family's neighbouring points share one label above the highest of them, three names a line,
    # in speed order (without a span, each its own).
    gap = 0.03 * span if span else 0.0
    named.sort(key=lambda m: (m[3], m[0]))
    group = []
    for i, mark in enumerate(named):
        group.append(mark)
        if i + 1 == len(named) or named[i + 1][3] != mark[3] or named[i + 1][0] - mark[0] > gap:
            names = [m[2] for m in group]
            text = "\n".join(", ".join(names[j:j + 3]) for j in range(0, len(names), 3))
            ax.annotate(text, (np.mean([m[0] for m in group]), max(m[1] for m in group)),
                        textcoords="offset points", xytext=(0, 8), ha="center", va="bottom",
                        fontsize=7, color=mark[3])
            group = []
    return top


def families_page(ax, loop, xlim):
    """Below a page: L2's families against speed by their modulation frequency (the doubled orbits at
    half the period-1 one's), with their special points."""
    top = orbit_families(ax, loop, "modulation_hz", span=xlim[1] - xlim[0])
    ax.set_xlim(*xlim)
    ax.set_ylim(0.0, 1.5 * max(top, 1.0))
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel("modulation of L2's orbits [Hz]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)


def interval_text(lo, hi):
    if np.isnan(lo) and np.isnan(hi):
        return ""
    if np.isnan(lo):
        return f"below {hi:.2f}"
    if np.isnan(hi):
        return f"above {lo:.2f}"
    if lo == hi:
        return ""
    return f"{lo:.2f} … {hi:.2f}"


def contact_page(ax, f, contact, names, rci, corners, on_page):
    loop = f["loop"]
    runs = loop["runs"]
    top = 0.0
    # The rolling line and the waves.
    schedule = np.concatenate([runs[d]["schedule_rpm"][()] for d in ("up", "down")])
    speeds = np.linspace(schedule.min(), schedule.max(), 200)
    ax.plot(speeds, rci * speeds / 60.0, color="0.6", lw=0.8, ls=":", label=f"rolling line BP = {rci:g}·speed")
    for name in loop["branches"]:
        b = loop["branches"][name]
        if "precession_hz" not in b or f"normal_force_{contact}" not in b:
            continue
        pieces(ax, b["speed_rpm"][()], b["precession_hz"][()], b["stable"][()] > 0,
               b[f"normal_force_{contact}"][()] > 0.0, "tab:blue", 1.2)
    ax.plot([], [], color="tab:blue", lw=1.2, label="rotating waves, stable (L1)")
    ax.plot([], [], color="tab:blue", lw=1.2, ls="--", label="rotating waves, unstable (L1)")
    # The runs: points integrated, stretches along stable waves, jumps.
    for d in ("up", "down"):
        r = runs[d]
        x = r["speed_rpm"][()]
        y = r[f"precession_hz_{contact}"][()]
        color = RUN_COLOR[d]
        ax.plot(x, y, RUN_MARKER[d], color=color, ms=4, ls="none", label=f"run-{d}, integrated (L3)")
        if len(y) and np.isfinite(y).any():
            top = max(top, np.nanmax(y))
        skips = r["skips"]
        for k in range(len(skips["from_rpm"][()])):
            lo, hi = sorted((skips["from_rpm"][k], skips["to_rpm"][k]))
            b = loop["branches"][text(skips["branch"][k])]
            bx, by = b["speed_rpm"][()], b["precession_hz"][()]
            inside = (bx >= lo) & (bx <= hi) & (b["stable"][()] > 0)
            order = np.argsort(bx[inside])
            ax.plot(bx[inside][order], by[inside][order], color=color, lw=3, alpha=0.35,
                    label=f"run-{d}, moved along a stable wave (L1)" if k == 0 else None)
    top = max(top, orbit_families(ax, loop, marks=False))
    # Corners.
    listing = []
    for n, i in enumerate(on_page, start=1):
        c = {k: corners[k][i] for k in corners}
        d = text(c["direction"])
        color = RUN_COLOR[d]
        x0, x1 = c["seen_from_rpm"], c["seen_to_rpm"]
        y0, y1 = c["precession_from_hz"], c["precession_to_hz"]
        if np.isfinite(y0) and np.isfinite(y1):
            ax.annotate("", xy=(x1, y1), xytext=(x0, y0),
                        arrowprops=dict(arrowstyle="->", color=color, lw=1.6, shrinkA=0, shrinkB=0))
        ymark = y0 if np.isfinite(y0) else y1
        speed, lo, hi = c["speed_rpm"], c["lower_rpm"], c["upper_rpm"]
        level = text(c["level"])
        explained = level != ""
        ax.plot([speed], [ymark], "o", mfc="none", mec="k" if explained else "tab:red", ms=11, mew=1.6)
        ax.annotate(str(n), (speed, ymark), textcoords="offset points", xytext=(0, 10 if d == "up" else -16),
                    ha="center", fontsize=10, fontweight="bold")
        if np.isfinite(lo) and np.isfinite(hi) and hi > lo:
            if level == "L3" or level.endswith("(L3)"):
                ax.axvspan(lo, hi, color=color, alpha=0.12, lw=0)
            ax.plot([lo, hi], [ymark, ymark], color="k" if explained else "tab:red", lw=4, alpha=0.5,
                    solid_capstyle="butt")
        clo, chi = c["crisis_lower_rpm"], c["crisis_upper_rpm"]
        if np.isfinite(chi) or np.isfinite(clo):
            edge = chi if np.isfinite(chi) else clo
            ax.axvline(edge, color="tab:green", ls="--", lw=1.0)
            ax.annotate("p_c " + interval_text(clo, chi), (edge, ymark), textcoords="offset points",
                        xytext=(-4, 24), ha="right", fontsize=8, color="tab:green")
        span = interval_text(lo, hi)
        listing.append(f"{n}: run-{d} {KIND_WORDS.get(text(c['kind']), text(c['kind']))} ({text(c['contact'])}) "
                       f"at {speed:.2f} rpm{' [' + span + ']' if span else ''}: {text(c['cause'])}"
                       f"{' (' + level + ')' if level else ''}")
    ax.set_xlim(schedule.min(), schedule.max())
    ax.set_ylim(0.0, 1.1 * max(top, 1.0))
    ax.set_xlabel("running speed [rpm]")
    ax.set_ylabel(f"backward precession at the {contact} contact [Hz]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    if listing:
        ax.text(0.99, 0.02, "\n".join(listing), transform=ax.transAxes, ha="right", va="bottom", fontsize=8,
                bbox=dict(boxstyle="round", fc="white", ec="0.6", alpha=0.9))


def same_loop(f, names):
    """Both contacts' runs alike (the same precession at every speed integrated)."""
    runs = f["loop/runs"]
    for d in ("up", "down"):
        a = runs[d][f"precession_hz_{names[0]}"][()]
        for other in names[1:]:
            b = runs[d][f"precession_hz_{other}"][()]
            if not np.allclose(a, b, rtol=1e-3, atol=0.5, equal_nan=True):
                return False
    return True


def figure(f, fig=None):
    """The loop of the file's /loop: one page per contact (one when both are alike)."""
    if "loop" not in f:
        raise MissingData("no /loop group")
    scene = tomllib.loads(text(f.attrs["scene_toml"]))
    radius, clearance = scene["contact"]["radius"], scene["contact"]["clearance"]
    names = sorted({k[len("precession_hz_"):] for k in f["loop/runs/up"] if k.startswith("precession_hz_")},
                   key=lambda n: ("left", "right", "contact").index(n) if n in ("left", "right", "contact") else 9)
    corners = {k: f["loop/corners"][k][()] for k in f["loop/corners"]}
    count = len(corners.get("direction", []))
    one = len(names) > 1 and same_loop(f, names)
    pages = names[:1] if one or len(names) == 1 else names
    families = has_families(f["loop"])
    rows = 2 * len(pages) if families else len(pages)
    fig = new_figure(fig, figsize=(14, (11.2 if families else 8.4) * len(pages)))
    axes = fig.subplots(rows, 1, squeeze=False,
                        gridspec_kw={"height_ratios": [3, 1] * len(pages)} if families else None)
    for n, contact in enumerate(pages):
        ax = axes[2 * n if families else n, 0]
        k = names.index(contact)
        on_page = [i for i in range(count) if one or contact in text(corners["contact"][i]).split(", ")]
        contact_page(ax, f, contact, names, radius[k] / clearance[k], corners, on_page)
        if families:
            families_page(axes[2 * n + 1, 0], f["loop"], ax.get_xlim())
    a = f["loop"].attrs
    title = (f"{text(f.attrs['scene_name']) if 'scene_name' in f.attrs else os.path.basename(f.filename)}: "
             f"the hysteresis loop of a run with {a['step_rpm']:g} rpm steps and {a['dwell_s']:g} s per speed"
             f"{' (both contacts alike)' if one else ''}")
    fig.suptitle(title, fontsize=12)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    return fig


def figures(f, stem):
    """`rubcont loop` writes loop.h5 (→ loop); the stage "loop" of `rubcont run` writes it into
    <scene>.h5 beside the other stages' groups (→ loop too); another file name names its figure."""
    scene_name = text(f.attrs["scene_name"]) if "scene_name" in f.attrs else ""
    yield ("loop" if stem == scene_name else stem), figure(f)

main = command_line(figures, DPI, __doc__, __spec__.name)


if __name__ == "__main__":
    sys.exit(main())
