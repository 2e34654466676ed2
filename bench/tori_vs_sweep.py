#!/usr/bin/python3
"""The lines of a sweep's spectra against the tori's (bench/tori_vs_sweep.sh).

Usage: /usr/bin/python3 bench/tori_vs_sweep.py TORI.h5 SWEEP.h5 [GROUP[,GROUP...]] [--lines L,K;L,K;...]
GROUP: the torus family's group (default tori/branch1_hopf2_ns1); several, comma-separated, are
read as one family (a family continued both ways from a transient's torus).
--lines: the lines to compare (l, k), in place of the default list below.
For every speed of the speed-up sweep inside the torus family's range, the tori's frequencies
interpolated (linearly) to that speed, and the sweep's peak nearest to each of the torus's lines
f = f_carrier - (k + l rho)/T, (l, k) in {(0, 0), (0, -1), (0, 1), (-1, 1), (1, -3), (-1, -2)} (the
carrier, carrier + f1, carrier - f1, carrier - f1 + f2, carrier + 3 f1 - f2, carrier + 2 f1 + f2:
C(c)'s right contact's strongest), refined by a parabola through
the log magnitudes of the peak bin and its neighbours. Backward precession is positive here; the
spectra store it at negative frequency.
"""
import sys

import h5py
import numpy as np

LINES = [(0, 0), (0, -1), (0, 1), (-1, 1), (1, -3), (-1, -2)]


def peak_near(freq, magnitude, target, window):
    pick = np.where(np.abs(freq - target) <= window)[0]
    if len(pick) == 0:
        return np.nan, 0.0
    i = pick[np.argmax(magnitude[pick])]
    if 0 < i < len(freq) - 1:
        a, b, c = np.log(magnitude[i - 1:i + 2] + 1e-300)
        shift = 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c != 0 else 0.0
        return freq[i] + shift * (freq[1] - freq[0]), magnitude[i]
    return freq[i], magnitude[i]


def main(argv):
    lines = LINES
    if "--lines" in argv:
        at = argv.index("--lines")
        if at + 1 >= len(argv):
            print(__doc__, file=sys.stderr)
            return 2
        lines = [tuple(int(v) for v in pair.split(",")) for pair in argv[at + 1].split(";") if pair]
        argv = argv[:at] + argv[at + 2:]
    if len(argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    groups = (argv[3] if len(argv) == 4 else "tori/branch1_hopf2_ns1").split(",")
    with h5py.File(argv[1], "r") as tori_file, h5py.File(argv[2], "r") as sweep_file:
        names = ("speed_rpm", "carrier_hz", "first_hz", "rotation_number")
        read = {name: np.concatenate([tori_file[g][name][()] for g in groups]) for name in names}
        # A family continued both ways repeats its first torus: one of each speed.
        rpm, unique = np.unique(read["speed_rpm"], return_index=True)
        columns = {name: read[name][unique] for name in names[1:]}
        up = sweep_file["sweeps/up"]
        freq = up["spectrum_frequency_hz"][()]
        bin_hz = freq[1] - freq[0]
        print(f"tori {rpm[0]:.4f}-{rpm[-1]:.4f} rpm ({len(rpm)}); sweep bins {bin_hz:.4f} Hz; "
              "lines as backward precession [Hz], sweep - torus in brackets")
        print(f"{'rpm':>7} {'settled':>7} {'f1':>9} {'f2':>8}  " +
              "  ".join(f"{f'({l},{k}) left / right':>34}" for l, k in lines))
        worst = 0.0
        for s, speed in enumerate(up["speed_rpm"][()]):
            if not rpm[0] <= speed <= rpm[-1]:
                continue
            carrier, f1, rho = (np.interp(speed, rpm, columns[n])
                                for n in ("carrier_hz", "first_hz", "rotation_number"))
            cells = []
            for l, k in lines:
                line = carrier - (k + l * rho) * f1
                found = []
                for contact in ("left", "right"):
                    magnitude = up["spectrum_magnitude_" + contact][s]
                    at, _ = peak_near(-freq, magnitude, line, 3 * bin_hz)
                    found.append(at)
                    if np.isfinite(at):
                        worst = max(worst, abs(at - line))
                cells.append(f"{line:9.3f}: {found[0]:9.3f} [{found[0] - line:+.3f}] / "
                             f"[{found[1] - line:+.3f}]")
            print(f"{speed:7.3f} {str(bool(up['settled'][s])):>7} {f1:9.3f} {rho * f1:8.3f}  " +
                  "  ".join(cells))
        print(f"largest |sweep - torus| over these lines: {worst:.3f} Hz ({worst / bin_hz:.2f} bins)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
