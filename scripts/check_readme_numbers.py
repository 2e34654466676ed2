#!/usr/bin/python3
"""Numbers of results/README.md read again from the committed result files.

    /usr/bin/python3 scripts/check_readme_numbers.py [RESULTS_DIR]

Each claim below computes values from the files under RESULTS_DIR (default: results/) and formats
the sentence the README must contain; the check fails, naming the claim and the sentence it
expected, when the README no longer says what the files hold (line breaks and repeated spaces in
the README do not matter). The thesis tables are checked too: they must be what
scripts/thesis_comparison.py computes. Exit code 0 when every claim holds, 1 otherwise.

A new number in results/README.md that a file holds gets a claim here.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

QUICK_WITH_BRANCHES = ["thesis_A_a", "thesis_A_b", "thesis_B_a", "thesis_B_b", "thesis_B_c",
                       "thesis_C_a", "thesis_C_b", "thesis_C_c", "overhung_beyond_right",
                       "jeffcott"]


def h5(results, path):
    return h5py.File(os.path.join(results, path), "r")


def stability_gap(results):
    """The positive leading growth rates of every rotating wave of the ten rub scenes."""
    rates = []
    for scene in QUICK_WITH_BRANCHES:
        with h5(results, f"{scene}/{scene}.h5") as f:
            for branch in f["branches"].values():
                if isinstance(branch, h5py.Group) and "leading_growth_rate" in branch:
                    r = branch["leading_growth_rate"][()]
                    rates += list(r[np.isfinite(r) & (r > 0)])
    rates = np.array(rates)
    marginal, unstable = rates[rates < 0.1], rates[rates >= 0.1]
    return (f"of all ten scenes the positive leading growth rates are either ≤ {marginal.max():.4f} "
            f"s⁻¹ (this drift; 4e-4 in C(a)) or ≥ {unstable.min():.2f} s⁻¹")


def whip_contact_fraction(results):
    """A(a)'s speed-up whip losing contact: the left contact's fraction of the time in contact."""
    with h5(results, "thesis_A_a/sweep.h5") as f:
        up = f["sweeps/up"]
        speed, fraction = up["speed_rpm"][()], up["contact_fraction_left"][()]
    at = {s: x for s, x in zip(speed, fraction)}
    late = fraction[(speed >= 156) & (speed <= 180)]
    return (f"A(a) from 148 rpm (contact fraction {at[148.0]:.2f} at 148 rpm and {at[152.0]:.2f} at "
            f"152 rpm, then {late.min():.3f}–{late.max():.3f} at the left contact from 156 to 180 rpm)")


def duffing_folds(results):
    with h5(results, "duffing/duffing.h5") as f:
        w = sorted(f["branches/periodic_orbits/special_points/frequency"][()], reverse=True)
    return (f"| upper (a sweep up jumps down) | w = 2.399649258756 | {w[0]:.12f} |", 
            f"| lower (a sweep down jumps up) | w = 1.329174352502 | {w[1]:.12f} |")


def stuart_landau_errors(results):
    with h5(results, "stuart_landau/stuart_landau.h5") as f:
        g = f["branches/periodic_orbits"]
        e = [np.nanmax(np.abs(g[f"closed_form_{k}_error"][()]))
             for k in ("radius", "period", "multiplier")]
    return f"max errors {e[0]:.1e}, {e[1]:.1e} and {e[2]:.1e}"


def forced_van_der_pol_folds(results):
    with h5(results, "forced_van_der_pol/forced_van_der_pol.h5") as f:
        sp = f["branches/periodic_orbits/special_points"]
        w = sorted(set(np.round(sp["frequency"][()], 12)))
    return f"w = {w[0]:.10g} and {w[1]:.10g} (the locking interval, {w[1] - w[0]:.4f} wide"


def modulated_whip(results):
    with h5(results, "thesis_A_a_modulated_whip/thesis_A_a_modulated_whip.h5") as f:
        g = f["orbits/branch2_hopf2"]
        hopf = g.attrs["hopf_speed_rpm"]
        bp = [s for t, s in zip(g["special_points/type"][()], g["special_points/speed_rpm"][()])
              if t == b"branch point"]
    return (f"the Mode 1 whirl at {hopf:.4f} rpm", f"already unstable past its branch point at "
            f"{bp[0]:.1f} rpm")


def intermittent_speeds(results):
    """The sweep speeds whose contact touched for less than 1 % of the time."""
    count = 0
    for scene in ["thesis_A_a", "thesis_A_b", "thesis_B_a", "thesis_B_b", "thesis_B_c",
                  "thesis_C_a", "thesis_C_b", "thesis_C_c"]:
        with h5(results, f"{scene}/sweep.h5") as f:
            for direction in ("up", "down"):
                for side in ("left", "right"):
                    count += int(sum(r == b"intermittent"
                                     for r in f[f"sweeps/{direction}/regime_{side}"][()]))
    words = {7: "Seven"}
    return f"{words.get(count, count)} speeds of the committed sweeps are intermittent"


CLAIMS = [stability_gap, intermittent_speeds, whip_contact_fraction, duffing_folds, stuart_landau_errors,
          forced_van_der_pol_folds, modulated_whip]


def normalized(text):
    return re.sub(r"\s+", " ", text)


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    readme = normalized(open(os.path.join(results, "README.md")).read())
    failed = 0
    for claim in CLAIMS:
        expected = claim(results)
        for sentence in expected if isinstance(expected, tuple) else (expected,):
            if normalized(sentence) in readme:
                print(f"holds   {claim.__name__}: {sentence}")
            else:
                failed += 1
                print(f"FAILS   {claim.__name__}: results/README.md should say: {sentence}")
    tables = subprocess.run([sys.executable, "scripts/thesis_comparison.py", results, "--check",
                             os.path.join(results, "README.md")], capture_output=True, text=True)
    print(tables.stdout, end="")
    if tables.returncode != 0:
        failed += 1
        print(tables.stderr, end="")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
