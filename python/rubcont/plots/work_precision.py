"""Work-precision chart of bench/work_precision_bench: error against CPU time, log-log, one panel per
question, one curve per method (points of one setting series joined in the order they were run).

Usage: python3 -m rubcont.plots.work_precision OUTDIR [--format png|pdf|svg]   (reads
OUTDIR/work_precision.csv and OUTDIR/summary.txt, writes OUTDIR/work_precision.png)
From Python: ``figure(directory)`` returns the Figure.

Filled markers: the method reported its answer as ok. Open markers: answered, but with a warning
(a sweep speed that ran to its dwell, a regularization bias above the flag). Answers with an error
of zero (the reference itself) sit on the panel's floor, marked "reference". What has no answer
(no_answer, failed, not_applicable) is listed under the panel with its count.
"""
import argparse
import csv
import math
import os
import sys
import textwrap

from .common import FORMATS, new_figure

DPI = 110

QUESTIONS = [
    ("q1", "q1: dominant precession at the q1 speed", "Hz"),
    ("q2", "q2: speed-up whirl → whip jump", "rpm"),
    ("q3", "q3: speed-down jump", "rpm"),
]
# Settings of one sweep series share the name before ':' (bench/work_precision_bench.cpp); the
# series that vary the main knob are drawn as curves, the other sweep settings as points.
SWEEP_SERIES = {"step", "dwell", "longest windows"}
STYLE = {
    "L0": ("black", "D"),
    "L1": ("tab:blue", "o"),
    "L2": ("tab:green", "s"),
    "L3": ("tab:red", "^"),
}


def curve_key(row):
    level, method, setting = row["level"], row["method"], row["setting"]
    if level == "L3":
        series = setting.split(":")[0]
        return (level, "sweep: " + series if series in SWEEP_SERIES else "sweep: other settings")
    if level == "L1" and method.startswith("rotating waves, tanh ε"):
        return (level, method + ", location tolerance")
    if level == "L1" and method == "rotating waves, tanh":
        return (level, "rotating waves, tanh over ε")
    return (level, method)


def color_of(key):
    level, label = key
    if level == "L1":
        if "over ε" in label:
            return "tab:purple"
        if "location" in label:
            return "tab:blue"
        return "tab:cyan"
    if level == "L3":
        return {"sweep: step": "tab:red", "sweep: dwell": "tab:gray",
                "sweep: longest windows": "tab:brown"}.get(label, "tab:orange")
    if level == "L2":
        if "Gauss" in label:
            return "tab:pink"
        return "tab:green" if "single" in label else "tab:olive"
    return STYLE[level][0]


def figure(out_dir, fig=None):
    """The chart of `out_dir`/work_precision.csv (its scene from `out_dir`/summary.txt)."""
    with open(os.path.join(out_dir, "work_precision.csv")) as f:
        rows = list(csv.DictReader(f))
    scene = ""
    summary = os.path.join(out_dir, "summary.txt")
    if os.path.exists(summary):
        with open(summary) as f:
            scene = f.readline().strip().replace("work_precision_bench: ", "")
    fig = new_figure(fig, figsize=(17, 7.2))
    axes = fig.subplots(1, 3)
    legend = {}
    for ax, (question, title, unit) in zip(axes, QUESTIONS):
        answered = [r for r in rows if r["question"] == question and r["status"] in
                    ("ok", "not_settled", "bias_flagged") and math.isfinite(float(r["error"]))]
        missing = [r for r in rows if r["question"] == question and r not in answered]
        positive = [float(r["error"]) for r in answered if float(r["error"]) > 0]
        floor = min(positive) / 10 if positive else 1e-12
        curves = {}
        for r in answered:
            curves.setdefault(curve_key(r), []).append(r)
        for key, points in curves.items():
            level, label = key
            color, marker = color_of(key), STYLE[level][1]
            x = [float(p["cpu_s"]) for p in points]
            y = [max(float(p["error"]), floor) for p in points]
            if len(points) > 1:
                ax.plot(x, y, "-", color=color, lw=1.2, alpha=0.8)
            for p, xi, yi in zip(points, x, y):
                ok = p["status"] == "ok"
                ax.plot(xi, yi, marker, color=color, ms=7, mfc=color if ok else "none", mew=1.4)
            legend.setdefault(f"{level} {label}", ax.plot([], [], marker + "-", color=color)[0])
        # One label for the reference, however many answers equal it (q2's four tanh answers at
        # ε = 0.001 m/s, location 1e-8 … 1e-12, sit on one spot): at the cheapest of them.
        reference = [float(r["cpu_s"]) for r in answered if float(r["error"]) == 0]
        if reference:
            ax.annotate("reference", (min(reference), floor), textcoords="offset points",
                        xytext=(4, 6), fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time [s]")
        ax.set_ylabel(f"|error| [{unit}]")
        ax.set_title(title, fontsize=11)
        ax.grid(True, which="both", alpha=0.3)
        if missing:
            lines = {}
            for r in missing:
                lines.setdefault(f"{r['level']} {r['method']}: {r['status']}", 0)
                lines[f"{r['level']} {r['method']}: {r['status']}"] += 1
            text = textwrap.fill("no answer: " + "; ".join(f"{k} ({n})" for k, n in lines.items()), 70)
            ax.text(0.0, -0.13, text, transform=ax.transAxes, fontsize=7, va="top")
    labels = sorted(legend)
    fig.legend([legend[k] for k in labels], labels, loc="lower center", ncol=4, fontsize=8)
    fig.suptitle(f"Work-precision, {scene}: error against the reference, CPU time of one answer "
                 "(open markers: answered with a warning)", fontsize=12)
    fig.tight_layout(rect=(0, 0.13, 1, 0.95))
    return fig


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    parser = argparse.ArgumentParser(prog="python3 -m rubcont.plots.work_precision",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", metavar="OUTDIR")
    parser.add_argument("--format", choices=FORMATS, default="png")
    args = parser.parse_args(argv)
    figure(args.out_dir).savefig(os.path.join(args.out_dir, f"work_precision.{args.format}"), dpi=DPI)
    return 0


if __name__ == "__main__":
    sys.exit(main())
