#!/usr/bin/python3
"""The table of docs/studies/attractors.md, "What the whip is, speed by speed", from the result files.

Usage: /usr/bin/python3 scripts/attractor_table.py ATTRACTOR.h5 [ATTRACTOR.h5 ...] [--orbits ORBITS.h5]
Prints one markdown row per speed of the attractor files (rubcont attractor; layout
apps/attractor_command.h): the verdict, the four exponents with their standard errors, the
section (points per contact and the range of the normal force at the maxima), the CPU time. With
--orbits (a result file holding the stage "orbits", e.g. thesis_A_a_modulated_whip.h5), the
speeds inside the continued family also get its decay rates ln|μ|·f_mod of the two leading
non-trivial Floquet multipliers of the stable orbits of every family (linear interpolation in
speed between continuation points; the trivial ones are not stored) and the orbit's largest normal
force, to set beside λ3, λ4 and the section.
"""
import sys

try:
    import h5py
    import numpy as np
except ImportError as error:
    print(f"attractor_table.py: {error}", file=sys.stderr)
    sys.exit(3)


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def floquet(orbits_file):
    """The stable orbits of every family: speed, the two leading decay rates [1/s], max N (left)."""
    speed, rates, force = [], [], []
    with h5py.File(orbits_file, "r") as f:
        for name, g in f["orbits"].items():
            if "multipliers_real" not in g:
                continue
            stable = g["stable"][()].astype(bool)
            mu = g["multipliers_real"][()] + 1j * g["multipliers_imag"][()]
            rate = np.sort(np.log(np.abs(mu)) * g["modulation_hz"][()][:, None], axis=1)[:, ::-1]
            speed.append(g["speed_rpm"][()][stable])
            rates.append(rate[stable, :2])
            force.append(g["max_normal_force_left"][()][stable])
    speed, rates, force = np.concatenate(speed), np.concatenate(rates), np.concatenate(force)
    order = np.argsort(speed)
    return speed[order], rates[order], force[order]


def main():
    args = sys.argv[1:]
    orbits = None
    if "--orbits" in args:
        i = args.index("--orbits")
        orbits = floquet(args[i + 1])
        del args[i:i + 2]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    header = "| speed | verdict | λ1 … λ4 [1/s] (± standard error) | section per contact: points, N at the maxima [N] | CPU |"
    if orbits:
        header += " L2: ln\\|μ\\|·f_mod, leading two [1/s]; max N [N] |"
    print(header)
    print("|---" * (header.count("|") - header.count("\\|") - 1) + "|")
    for name in args:
        with h5py.File(name, "r") as f:
            g = f["attractor"]
            contacts = sorted(k[len("section_speed_rpm_"):] for k in g if k.startswith("section_speed_rpm_"))
            for i, speed in enumerate(g["speed_rpm"][()]):
                lam = g["exponents"][i]
                err = g["standard_errors"][i]
                exps = ", ".join(f"{l:+.2f} ± {e:.2f}" for l, e in zip(lam, err))
                sections = []
                for side in contacts:
                    s = g[f"section_speed_rpm_{side}"][()]
                    force = g[f"section_normal_force_{side}"][()][s == speed]
                    sections.append(f"{side} {len(force)}, {force.min():.0f}–{force.max():.0f}" if len(force)
                                    else f"{side} none")
                row = (f"| {speed:g} rpm | {text(g['motion'][i])} | {exps} | {'; '.join(sections)} | "
                       f"{g['cpu_seconds'][i]:.1f} s |")
                if orbits:
                    ospeed, rates, force = orbits
                    if ospeed.min() <= speed <= ospeed.max():
                        r = [np.interp(speed, ospeed, rates[:, j]) for j in range(2)]
                        n = np.interp(speed, ospeed, force)
                        row += f" {r[0]:.2f}, {r[1]:.2f}; {n:.0f} |"
                    else:
                        row += " – |"
                print(row)
    return 0


if __name__ == "__main__":
    sys.exit(main())
