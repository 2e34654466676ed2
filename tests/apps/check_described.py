#!/usr/bin/python3
"""A result file opens in Python as it describes itself (apps/hdf5_file.h): h5py lists the
branches in the order written, xarray (engine "h5netcdf") opens a branch with speed_rpm as its
dimension coordinate, an analytic curve with precession_hz and a textbook model's orbit family with
its parameter, and every numeric dataset carries `units`.

    /usr/bin/python3 tests/apps/check_described.py BUILD_DIR

Runs `BUILD_DIR/rubcont run` on scenes/thesis_A_a.toml and scenes/stuart_landau.toml (< 1 s
each, no figures) into a temporary directory, from the repository root. Exit code 0 when all
holds, 1 with the reasons otherwise.
"""
import os
import re
import subprocess
import sys
import tempfile

import h5py
import xarray


def main(build_dir):
    problems = []
    with tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, RUBCONT_PYTHON="/nonexistent/python3")  # no figures
        subprocess.run([os.path.join(build_dir, "rubcont"), "run", "scenes/thesis_A_a.toml",
                        "--out", out, "--quiet"], check=True, env=env, capture_output=True)
        path = os.path.join(out, "thesis_A_a", "thesis_A_a.h5")
        with h5py.File(path, "r") as f:
            branches = [name for name in f["branches"] if name.startswith("branch")]
            numbers = [int(re.sub(r"\D", "", name)) for name in branches]
            if len(numbers) < 10 or numbers != list(range(1, len(numbers) + 1)):
                problems.append(f"h5py lists the branches as {branches}")

            def visit(name, obj):
                numeric = isinstance(obj, h5py.Dataset) and obj.dtype.kind in "iuf"
                if numeric and "units" not in obj.attrs:
                    problems.append(f"/{name} has no units")
            f.visititems(visit)

        branch = xarray.open_dataset(path, engine="h5netcdf", group="branches/branch2")
        if list(branch.dims) != ["speed_rpm"] or "speed_rpm" not in branch.coords:
            problems.append(f"branch2's dimensions are {dict(branch.dims)}, "
                            f"coordinates {list(branch.coords)}")
        units = branch["precession_hz"].attrs.get("units")
        if units != "Hz":
            problems.append(f"branch2's precession_hz has units {units!r}")
        meanings = branch["mode_left"].attrs.get("flag_meanings")
        if meanings != "free stick slip+ slip-":
            problems.append(f"branch2's mode_left has flag_meanings {meanings!r}")
        # The whirl rolls (mode_left 1: stick) on the line BP = RCI × speed = 100 × speed_rpm/60 Hz,
        # read through the coordinate.
        rolling = branch["precession_hz"].where(branch["mode_left"] == 1, drop=True)
        ratio = (rolling / rolling["speed_rpm"]).values
        if rolling.size == 0 or abs(ratio - 100 / 60).max() > 1e-3:
            problems.append(f"branch2 rolls at BP/speed {ratio} Hz/rpm, not 100/60")
        branch.close()
        curve = xarray.open_dataset(path, engine="h5netcdf", group="analytic/mode1")
        if list(curve.dims) != ["precession_hz"]:
            problems.append(f"analytic/mode1's dimensions are {dict(curve.dims)}")
        curve.close()

        # A textbook model's orbit family: its parameter is the dimension; the multipliers
        # (orbits × multipliers, second axis unlabelled) are left unlabelled on both axes, which
        # h5netcdf accepts with phony dimensions (it refuses a half-labelled variable).
        subprocess.run([os.path.join(build_dir, "rubcont"), "run", "scenes/stuart_landau.toml",
                        "--out", out, "--quiet"], check=True, env=env, capture_output=True)
        path = os.path.join(out, "stuart_landau", "stuart_landau.h5")
        orbits = xarray.open_dataset(path, engine="h5netcdf", group="branches/periodic_orbits",
                                     phony_dims="sort")
        if orbits["period"].dims != ("lambda",) or "lambda" not in orbits.coords:
            problems.append(f"the Stuart-Landau orbits' period has dims {orbits['period'].dims}")
        orbits.close()
    for p in problems:
        print(p)
    print(f"described: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
