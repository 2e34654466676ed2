"""ε → 0 convergence of the regularized whirl → whip transition (bench/branches_bench CSV).

    python3 -m rubcont.plots.regularization results/regularization/thesis_A_a.csv OUT.{png,pdf,svg}

From Python: ``figure(csv_path)`` returns the Figure.
"""
import sys

import numpy as np

from .common import new_figure

DPI = 150


def figure(csv_path, fig=None):
    """Relative error of the tanh transition against ε, from the bench's CSV."""
    with open(csv_path) as f:
        lines = [line for line in f if not line.startswith("#")]
    data = np.genfromtxt(lines, delimiter=",", names=True)
    eps = data["eps_m_per_s"]
    fig = new_figure(fig, figsize=(6.8, 4.6), dpi=DPI)
    ax = fig.subplots()
    ax.loglog(eps, np.abs(data["precession_rel_error"]), "o-", color="#1f5fa8",
              label="precession Ω_t (relative error)")
    ax.loglog(eps, np.abs(data["speed_rel_error"]), "s-", color="#c0392b",
              label="running speed ω_t (relative error)")
    ref = eps / eps[-1] * abs(data["precession_rel_error"][-1])
    ax.loglog(eps, ref, color="0.6", lw=0.8, ls=":", label="slope 1")
    ax.set_xlabel("friction regularization ε [m/s] in tanh(V/ε)")
    ax.set_ylabel("|tanh transition − exact stick→slip event| / exact")
    ax.set_title("case A(a), Mode 1 whirl → whip: ε → 0 convergence", fontsize=10)
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    figure(argv[0]).savefig(argv[1])
    print(f"wrote {argv[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
