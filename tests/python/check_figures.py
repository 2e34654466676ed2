"""Every figure the committed results make, drawn again (not saved) and checked: each text drawn
lies inside the figure (no title or label cut at an edge), and each legend's labels are unique
(no two entries named alike).

    PYTHONPATH=python /usr/bin/python3 tests/python/check_figures.py results [--verbose]

The figures: rubcont.plots.figures(f) of every results/**/*.h5 (what the command line draws from
it), results/*/hysteresis.png's (from the sweep file with the orbits and lifetime files
scripts/regenerate-results.sh gives it, read from there), and the charts of the benchmarks' CSV
files (work_precision, regularization). Exit status 1 with one line per defect, 0 when none.
"""
import argparse
import glob
import os
import re
import sys
import time

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.backends.backend_agg import RendererAgg  # noqa: E402
from matplotlib.legend import Legend  # noqa: E402
from matplotlib.text import Text  # noqa: E402

import rubcont.plots  # noqa: E402
from rubcont.plots import hysteresis, regularization, work_precision  # noqa: E402

# A text may reach this far past the figure's edge [pixels]: antialiasing, not a cut letter.
EDGE_TOLERANCE_PX = 1.0


class DrawnTexts:
    """Records the Text artists that put glyphs on the canvas while a figure draws (a text
    outside its axes' view, empty or invisible draws nothing and is not checked)."""

    def __init__(self):
        self.drawn = []
        self._stack = []

    def __enter__(self):
        self._text_draw, self._draw_text = Text.draw, RendererAgg.draw_text
        recorder = self

        def text_draw(artist, renderer):
            recorder._stack.append(artist)
            try:
                return recorder._text_draw(artist, renderer)
            finally:
                recorder._stack.pop()

        def draw_text(renderer, *args, **kwargs):
            if recorder._stack and (not recorder.drawn or recorder.drawn[-1] is not recorder._stack[-1]):
                recorder.drawn.append(recorder._stack[-1])
            return recorder._draw_text(renderer, *args, **kwargs)

        Text.draw, RendererAgg.draw_text = text_draw, draw_text
        return self

    def __exit__(self, *exc):
        Text.draw, RendererAgg.draw_text = self._text_draw, self._draw_text


# What the Agg renderer rasterizes besides text. A text's place does not depend on these pixels
# (the layouts ask the artists' extents), so they are not drawn: the 279 figures of the results took
# 98 s of CPU alone against 117 s painted (2026-11-30, one run each; matplotlib's layout is the rest).
PIXEL_METHODS = ("draw_path", "draw_markers", "draw_path_collection", "draw_quad_mesh",
                 "draw_gouraud_triangle", "draw_gouraud_triangles", "draw_image")


def _draw_nothing(*args, **kwargs):
    return None


def defects(fig):
    """One sentence per text outside the figure and per repeated legend label."""
    found = []
    renderer = fig.canvas.get_renderer()  # the one draw() reuses: the figure's size is unchanged
    for method in PIXEL_METHODS:
        setattr(renderer, method, _draw_nothing)
    with DrawnTexts() as texts:
        fig.canvas.draw()
    width, height = fig.bbox.width, fig.bbox.height
    for text in texts.drawn:
        box = text.get_window_extent(renderer)
        outside = {"left": -box.x0, "right": box.x1 - width, "bottom": -box.y0, "top": box.y1 - height}
        cut = {side: amount for side, amount in outside.items() if amount > EDGE_TOLERANCE_PX}
        if cut:
            where = ", ".join(f"{side} by {amount:.0f} px" for side, amount in cut.items())
            found.append(f"text {text.get_text()[:60]!r} outside the figure ({where})")
    for legend in fig.findobj(Legend):
        labels = [t.get_text() for t in legend.get_texts()]
        repeated = sorted({label for label in labels if labels.count(label) > 1})
        if repeated:
            found.append(f"legend labels repeated: {repeated}")
    return found


def result_figures(results):
    """(where, name, draw) of every figure: draw() returns the Figure."""
    for path in sorted(glob.glob(os.path.join(results, "**", "*.h5"), recursive=True)):
        with h5py.File(path, "r") as f:
            modules = rubcont.plots.modules_for(f)
        for module in modules:
            yield path, module, lambda path=path, module=module: _module_figures(path, module)
    for sweep_file, extra in _hysteresis_inputs(results):
        yield sweep_file, "hysteresis", lambda s=sweep_file, e=extra: [
            ("hysteresis", hysteresis.figure(s, e.get("--orbits"), e.get("--lifetime")))]
    for csv_file in sorted(glob.glob(os.path.join(results, "bench", "*", "work_precision.csv"))):
        directory = os.path.dirname(csv_file)
        yield directory, "work_precision", lambda d=directory: [("work_precision",
                                                                 work_precision.figure(d))]
    for csv_file in sorted(glob.glob(os.path.join(results, "regularization", "*.csv"))):
        yield csv_file, "regularization", lambda c=csv_file: [("convergence", regularization.figure(c))]


def _module_figures(path, module):
    import importlib

    with h5py.File(path, "r") as f:
        return list(importlib.import_module(f"rubcont.plots.{module}").figures(
            f, os.path.splitext(os.path.basename(path))[0]))


def _hysteresis_inputs(results):
    """The sweep files with their --orbits / --lifetime files, as regenerate-results.sh draws
    hysteresis.png (its case table, read from the script)."""
    script = os.path.join(os.path.dirname(os.path.abspath(results)), "scripts", "regenerate-results.sh")
    extras = {}
    if os.path.exists(script):
        with open(script) as f:
            text = f.read()
        for scene, body in re.findall(r"^\s*(\w+)\) extra=\((.*?)\) ;;", text, re.M | re.S):
            pairs = re.findall(r"(--\w+) results/(\S+)", body)
            extras[scene] = {flag: os.path.join(results, file) for flag, file in pairs}
    for png in sorted(glob.glob(os.path.join(results, "*", "hysteresis.png"))):
        scene = os.path.basename(os.path.dirname(png))
        sweep_file = os.path.join(results, scene, "sweep.h5")
        if os.path.exists(sweep_file):
            present = {k: v for k, v in extras.get(scene, {}).items() if os.path.exists(v)}
            yield sweep_file, present


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args(argv)
    count, problems, start = 0, [], time.process_time()
    for where, module, draw in result_figures(args.results):
        for name, fig in draw():
            count += 1
            for defect in defects(fig):
                problems.append(f"{where}: {name} ({module}): {defect}")
            plt.close(fig)
            if args.verbose:
                print(f"{where}: {name}", file=sys.stderr)
    for problem in problems:
        print(problem)
    print(f"{count} figures checked, {len(problems)} defects, {time.process_time() - start:.1f} s CPU")
    return 1 if problems or count == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
