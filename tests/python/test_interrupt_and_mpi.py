"""Ctrl-C during a stage (issue 50 item 8): a sweep running in `python3` gets SIGINT; the script
ends with KeyboardInterrupt within a second or so, and no result lies under the real name (nor a
temporary beside it). The time to stop is printed (pytest -s), not asserted: the machine is shared.

Run by ctest with the other tests of tests/python (PYTHONPATH=<build>/python).
"""
import os
import signal
import subprocess
import sys
import textwrap
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

SCRIPT = textwrap.dedent("""
    import sys
    import rubcont
    scene = rubcont.load_scene("scenes/thesis_A_a.toml").with_values(
        {"analysis": {"sweep": {"up_range_rpm": [40.0, 200.0], "down_range_rpm": [40.0, 120.0],
                                "speed_step_rpm": 2.0, "dwell": 2.0}}})

    def progress(line):
        if "[sweep up] 1/" in line:
            print("running", flush=True)

    try:
        rubcont.sweep(scene, direction="up", out=sys.argv[1], progress=progress)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


def test_ctrl_c_stops_a_sweep_and_writes_nothing_under_the_real_name(tmp_path):
    out = tmp_path / "sweep.h5"
    child = subprocess.Popen([sys.executable, "-c", SCRIPT, str(out)], cwd=ROOT,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "running", child.stderr.read()
        time.sleep(0.5)  # well inside the sweep: it takes minutes
        sent = time.perf_counter()
        child.send_signal(signal.SIGINT)
        rest, errors = child.communicate(timeout=60)
        stopped = time.perf_counter() - sent
    finally:
        if child.poll() is None:
            child.kill()
    print(f"\nstopped {stopped:.2f} s after SIGINT")
    assert rest.strip() == "KeyboardInterrupt", (rest, errors)
    assert child.returncode == 130
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if ".tmp" in p.name] == []


MPI_SCRIPT = textwrap.dedent("""
    from mpi4py import MPI  # initialises MPI before rubcont does
    import rubcont
    result = rubcont.map("scenes/thesis_A_a.toml", parameter="friction", eta_range=(0.45, 0.55),
                         eta_points=3, speed_points=41, threads=1)
    print(f"rank {MPI.COMM_WORLD.Get_rank()} of {MPI.COMM_WORLD.Get_size()}: {result.status}",
          flush=True)
""")


def test_a_script_that_imported_mpi4py_first_runs_a_map_under_mpirun():
    """rubcont's MPI start (apps/ranks.cpp) sees MPI running and does not initialise it again
    (which aborted the job: "ORTE_ERROR_LOG", no result)."""
    import shutil

    import pytest

    pytest.importorskip("mpi4py", reason="Debian: apt-get install python3-mpi4py")
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        pytest.skip("no mpirun (Debian: openmpi-bin)")
    run = subprocess.run([mpirun, "--allow-run-as-root", "-n", "1", sys.executable, "-c", MPI_SCRIPT],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "rank 0 of 1: success" in run.stdout, run.stdout + run.stderr
