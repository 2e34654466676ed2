"""What the figure modules of rubcont.plots share: text decoding, a figure to draw on, and the
command line every module's ``main`` runs.

A module's figures come from ``figures(f, stem)``: (name, Figure) pairs drawn from an open h5py
file, each saved by :func:`main` as ``OUTDIR/<name>.<format>`` at the module's ``DPI``. Drawing
functions take the h5py file or group and an optional ``fig`` (a matplotlib Figure to draw into;
None: a new pyplot figure) and return the Figure, so ``rubcont``'s objects (``Branch.plot()``, ...)
and the command line's figures (apps/figures.cpp) draw with the same code.
"""
from __future__ import annotations

import argparse
import os
import sys
import textwrap
from typing import Any, Callable, Iterator, Sequence

FORMATS = ("png", "pdf", "svg")


class MissingData(LookupError):
    """The file lacks the group a module draws (the command line's exit status 1)."""


def text(value: Any) -> str:
    """An HDF5 string (bytes or str) as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


def new_figure(fig: Any = None, **kwargs: Any) -> Any:
    """`fig` itself (cleared of nothing: the caller's Figure), or a new pyplot Figure made with
    `kwargs` (figsize, dpi)."""
    if fig is not None:
        return fig
    import matplotlib.pyplot as plt

    return plt.figure(**kwargs)


def keep_inside(fig: Any, artist: Any, min_width: int = 20) -> bool:
    """Wraps the text of `artist` (a title) into as many lines as keep it inside the figure's
    width (a long scene name pushed one-line titles past the edges). Returns whether it changed
    (then the caller lays the figure out again)."""
    renderer = fig.canvas.get_renderer()
    title, width, changed = artist.get_text(), len(artist.get_text()), False
    while True:
        box = artist.get_window_extent(renderer)
        if (box.x0 >= 0 and box.x1 <= fig.bbox.width) or width <= min_width:
            return changed
        width = int(width * 0.9)
        artist.set_text(textwrap.fill(title, width))
        changed = True


def stem_of(path: str) -> str:
    """A file's name without folder and extension (the name of figures named after their file)."""
    return os.path.splitext(os.path.basename(path))[0]


Figures = Callable[[Any, str], Iterator[tuple[str, Any]]]


def one_figure(draw: Callable[[Any], Any], name: str | None = None) -> Figures:
    """The `figures` of a module with one figure: `name`, or the file's stem when None."""

    def figures(f: Any, stem: str = "") -> Iterator[tuple[str, Any]]:
        yield (stem if name is None else name), draw(f)

    return figures


def command_line(figures: Figures, dpi: float, doc: str | None,
                 module: str) -> Callable[..., int]:
    """A module's ``main(argv=None)``: :func:`main` on its figures."""
    return lambda argv=None: main(figures, dpi, doc, module, argv)


def main(figures: Figures, dpi: float, doc: str | None, module: str,
         argv: Sequence[str] | None = None) -> int:
    """``python3 -m <module> RESULT.h5 OUTDIR [--format png|pdf|svg]``: draws `figures` of the
    file into OUTDIR. Exit status 0, 1 when the file lacks the module's data, 2 on bad arguments
    (argparse)."""
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    parser = argparse.ArgumentParser(prog=f"python3 -m {module}", description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("result", metavar="RESULT.h5", help="a rubcont result file")
    parser.add_argument("out_dir", metavar="OUTDIR", help="where the figures go (made if missing)")
    parser.add_argument("--format", choices=FORMATS, default="png", help="file format (png)")
    args = parser.parse_args(argv)
    os.makedirs(args.out_dir, exist_ok=True)
    with h5py.File(args.result, "r") as f:
        try:
            for name, fig in figures(f, stem_of(args.result)):
                fig.savefig(os.path.join(args.out_dir, f"{name}.{args.format}"), dpi=dpi)
                plt.close(fig)
        except MissingData as error:
            print(f"{module}: {args.result}: {error}", file=sys.stderr)
            return 1
    return 0
