#!/usr/bin/env python3
"""Every torus of a result file's transient families: speed, K, Fourier tail, invariance error.

Usage: bench/tori_tails.py FILE.h5 (runs under /usr/bin/python3, which has h5py). A summary prints
the tails only where a family refines in K (max_harmonics > 0); this reads them from the file.
"""
import sys

import h5py


def main(path):
    with h5py.File(path, "r") as f:
        for name in ("transient_down", "transient_up"):
            if "tori/" + name not in f:
                continue
            g = f["tori/" + name]
            print(f"  {name}: speed [rpm], K, Fourier tail, invariance error (scaled)")
            for s, k, t, e in zip(g["speed_rpm"][()], g["harmonics"][()], g["fourier_tail"][()],
                                  g["invariance_error"][()]):
                print(f"    {s:9.4f}  {int(k):3d}  {t:.2g}  {e:.2g}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: bench/tori_tails.py FILE.h5")
    main(sys.argv[1])
