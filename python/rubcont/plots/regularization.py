#!/usr/bin/python3
"""ε → 0 convergence of the regularized whirl → whip transition (bench/branches_bench CSV).

    /usr/bin/python3 plots/regularization.py results/regularization/thesis_A_a.csv OUT.png
"""
import sys

try:
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as error:
    print(f"regularization.py: {error}", file=sys.stderr)
    sys.exit(3)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    lines = [l for l in open(argv[1]) if not l.startswith("#")]
    data = np.genfromtxt(lines, delimiter=",", names=True)
    eps = data["eps_m_per_s"]
    fig, ax = plt.subplots(figsize=(6.8, 4.6), dpi=150)
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
    fig.savefig(argv[2])
    print(f"wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
