#!/usr/bin/python3
"""Fault injection: runs of `rubcont sweep`, `lifetime` and `batch` killed at random moments and
resumed, counting what a kill costs (issue 50; docs/robustness.md, "Killed runs").

Usage: /usr/bin/python3 scripts/fault_campaign.py BUILD_DIR [--trials N] [--seed S] [--out FILE]

Each trial starts one command in a fresh directory, kills it with SIGKILL after a random time
(uniform between 2 % and 100 % of that command's uninterrupted wall time, measured first), 1 to 3
times in a row, each time starting it again with --resume (batch: the same command), and lets
the last run finish. After every kill it counts
  - unreadable files: every HDF5 file in the directory (results, checkpoints; not the temporaries
    of the write in progress, `*.tmp.*`) must open with h5py and every dataset be readable;
  - finished items lost: what the kill left finished — the checkpoint's speeds (sweep), the
    checkpoint's approach and speeds (lifetime), the jobs with an outcome and the speeds of a sweep
    job's checkpoint (batch) — against what the next run took over: its "resuming from ...: N"
    line (sweep, lifetime), the finished speeds' recorded wall_seconds unchanged in the final file
    (a speed integrated again would carry a new one: sweep, batch's sweep job), and each finished
    job's outcome and result files untouched (batch);
and at the end the temporaries left (`*.tmp.*`) and whether the final result equals the uninterrupted run's (scripts/compare_results.py:
numbers to 1e-12 relative; recorded durations not compared). The scenes are small (case A(a) with a
20 rpm sweep, the default scene) so that a trial takes seconds. Exit status 0 when nothing was
lost, unreadable or different.
"""
import argparse
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
NO_FIGURES = {"RUBCONT_PYTHON": "/nonexistent/python3"}  # lifetime and batch jobs draw none

SWEEP_SCENE_TAIL = "[analysis.sweep]\nup_range_rpm = [40.0, 60.0]\nspeed_step_rpm = 2.0\ndwell = 0.75\n"
LIFETIME_ARGS = ["--from", "50", "--to", "52", "--step", "0.5", "--copies", "4", "--duration", "0.4",
                 "--until", "whip", "--check-copies", "2", "--check-dwell", "0.2", "--threads", "1"]
JOBS = """out = "{out}"
[[job]]
name = "analytic"
command = "analytic"
scene = "{default}"
[[job]]
name = "branches"
command = "branches"
scene = "{default}"
[[job]]
name = "sweep_up"
command = "sweep"
scene = "{scene}"
direction = "up"
"""


def write_scene(directory):
    text = (ROOT / "scenes" / "thesis_A_a.toml").read_text()
    path = directory / "campaign.toml"
    path.write_text(text[: text.index("[analysis.sweep]")] + SWEEP_SCENE_TAIL)
    return path


def command(kind, build, work, scene, resume):
    rubcont = str(Path(build) / "rubcont")
    if kind == "sweep":
        return [rubcont, "sweep", str(scene), "--direction", "up", "--no-figures", "--out",
                str(work / "sweep.h5")] + (["--resume"] if resume else [])
    if kind == "lifetime":
        return [rubcont, "lifetime", str(scene)] + LIFETIME_ARGS + ["--out", str(work / "lifetime.h5")] + (
            ["--resume"] if resume else [])
    jobs = work / "jobs.toml"
    if not jobs.exists():
        jobs.write_text(JOBS.format(out=work / "batch", scene=scene, default=ROOT / "scenes" / "default.toml"))
    return [rubcont, "batch", str(jobs)]


def final_file(kind, work):
    return {"sweep": work / "sweep.h5", "lifetime": work / "lifetime.h5",
            "batch": work / "batch" / "sweep_up" / "sweep_up.h5"}[kind]


def readable(path):
    """Whether every dataset of the HDF5 file reads."""
    try:
        with h5py.File(path, "r") as f:
            def visit(_, node):
                if isinstance(node, h5py.Dataset):
                    node[()]
            f.visititems(visit)
        return True
    except Exception:  # any failure to open or read is what is counted
        return False


def sweep_checkpoint(path):
    """The finished speeds' wall_seconds in a sweep checkpoint (empty: none)."""
    if not path.exists():
        return []
    with h5py.File(path, "r") as f:
        return list(f["sweeps/up/wall_seconds"][()])


def lifetime_checkpoint(path):
    """(approach done, speeds done) in a lifetime checkpoint."""
    if not path.exists():
        return (False, 0)
    with h5py.File(path, "r") as f:
        return (True, sum(1 for name in f["checkpoint"] if name.startswith("speed")))


def finished_jobs(batch):
    """Each finished job's outcome text and its files' (size, mtime_ns)."""
    done = {}
    for outcome in sorted(batch.glob("*.outcome")):
        name = outcome.stem
        result = batch / name / f"{name}.h5"
        if result.exists():
            done[name] = (outcome.read_text(), outcome.stat().st_mtime_ns, result.stat().st_mtime_ns)
    return done


def snapshot(kind, work, final=False):
    """What is finished in `work` now: after a kill, its checkpoints and outcomes; at the end (final),
    the result file's speeds."""
    if kind == "sweep":
        if final:
            with h5py.File(work / "sweep.h5", "r") as f:
                return {"speeds": list(f["sweeps/up/wall_seconds"][()])}
        return {"speeds": sweep_checkpoint(work / "sweep.up.checkpoint.h5")}
    if kind == "lifetime":
        return {"lifetime": lifetime_checkpoint(work / "lifetime.checkpoint.h5")}
    batch = work / "batch"
    result = batch / "sweep_up" / "sweep_up.h5"
    if final or (result.exists() and not (batch / "sweep_up" / "sweep_up.up.checkpoint.h5").exists()):
        with h5py.File(result, "r") as f:
            speeds = list(f["sweeps/up/wall_seconds"][()])
    else:
        speeds = sweep_checkpoint(batch / "sweep_up" / "sweep_up.up.checkpoint.h5")
    return {"jobs": finished_jobs(batch), "speeds": speeds}


def lost_items(kind, before, after, log, final):
    """Finished items of `before` (the state a kill left) that the next run did not take over, as
    seen in `after` (the state after that run: killed again, or at the end) and its log."""
    lost, notes = 0, []
    if kind in ("sweep", "batch") and before["speeds"]:
        n = len(before["speeds"])
        same = sum(1 for a, b in zip(before["speeds"], after["speeds"]) if a == b)
        lost += n - same
        notes.append(f"{same}/{n} speeds kept")
    if kind == "sweep" and before["speeds"]:
        m = re.search(r"resuming from \S+: (\d+) speeds done", log)
        if m and int(m.group(1)) != len(before["speeds"]):
            lost += len(before["speeds"]) - int(m.group(1))
            notes.append(f"resumed from {m.group(1)}")
        elif not m and final:
            lost += len(before["speeds"])
            notes.append("no resume line")
    if kind == "lifetime":
        approached, n = before["lifetime"]
        m = re.search(r"resuming from \S+: the approach and (\d+) speed", log)
        if approached and m:
            taken = int(m.group(1))
            lost += max(n - taken, 0)
            notes.append(f"approach + {taken}/{n} speeds kept")
        elif approached and final:
            lost += n + 1
            notes.append("no resume line")
        elif approached and after["lifetime"][1] < n:
            lost += n - after["lifetime"][1]
            notes.append(f"checkpoint shrank to {after['lifetime'][1]} of {n}")
    if kind == "batch":
        kept = sum(1 for name, files in before["jobs"].items() if after["jobs"].get(name) == files)
        lost += len(before["jobs"]) - kept
        notes.append(f"{kept}/{len(before['jobs'])} jobs kept")
    return lost, notes


def compare(reference, final):
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_results.py"), str(reference), str(final),
                             "--rtol", "1e-12", "--atol", "1e-15"], capture_output=True, text=True)
    return result.returncode == 0, result.stdout


def run_to_end(cmd, env):
    return subprocess.run(cmd, env=env, capture_output=True, text=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build")
    parser.add_argument("--trials", type=int, default=54)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default=str(ROOT / "results" / "bench" / "fault_campaign.txt"))
    args = parser.parse_args()
    rng = random.Random(args.seed)
    env = dict(os.environ, **NO_FIGURES)
    top = Path(tempfile.mkdtemp(prefix="fault_campaign."))
    scene = write_scene(top)
    kinds = ["sweep", "lifetime", "batch"]

    # The uninterrupted runs: the references and each command's wall time.
    reference, wall = {}, {}
    for kind in kinds:
        work = top / f"reference_{kind}"
        work.mkdir()
        start = time.monotonic()
        done = run_to_end(command(kind, args.build, work, scene, False), env)
        wall[kind] = time.monotonic() - start
        if done.returncode != 0:
            print(f"reference {kind} failed ({done.returncode}):\n{done.stderr}", file=sys.stderr)
            return 1
        reference[kind] = final_file(kind, work)

    lines, totals = [], {"kills": 0, "lost": 0, "unreadable": 0, "different": 0, "leftovers": 0}
    for trial in range(args.trials):
        kind = kinds[trial % len(kinds)]
        work = top / f"trial{trial:03d}"
        work.mkdir()
        planned = rng.randint(1, 3)  # kills in a row, then a run to the end
        kills, lost, unreadable, notes = 0, 0, 0, []
        before = None  # what the last kill left finished
        while True:
            cmd = command(kind, args.build, work, scene, resume=kills > 0)
            if kills < planned:
                process = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                try:
                    _, err = process.communicate(timeout=rng.uniform(0.02, 1.0) * wall[kind])
                    finished = True
                except subprocess.TimeoutExpired:
                    process.send_signal(signal.SIGKILL)
                    _, err = process.communicate()
                    finished = False
            else:
                done = run_to_end(cmd, env)
                err, finished = done.stderr, True
            if not finished:
                kills += 1
                for h5 in work.rglob("*.h5"):
                    if ".tmp." not in h5.name and not readable(h5):
                        unreadable += 1
                        notes.append(f"unreadable {h5.relative_to(work)}")
            now = snapshot(kind, work, final=finished)
            if before is not None:
                l, n = lost_items(kind, before, now, err, finished)
                lost += l
                if finished:
                    notes += n
            if finished:
                break
            before = now
        leftovers = [p for p in work.rglob("*") if ".tmp." in p.name]
        if leftovers:
            notes.append(f"{len(leftovers)} temporaries left")
        totals["leftovers"] += len(leftovers)
        final = final_file(kind, work)
        same, diff = compare(reference[kind], final) if final.exists() else (False, "no final file")
        totals["kills"] += kills
        totals["lost"] += lost
        totals["unreadable"] += unreadable
        totals["different"] += 0 if same else 1
        line = (f"trial {trial:3d} {kind:8s} kills {kills}  lost {lost}  unreadable {unreadable}  "
                f"final {'= reference' if same else 'DIFFERS'}  {'; '.join(notes)}")
        if not same:
            line += "\n    " + diff.strip().replace("\n", "\n    ")
        print(line, flush=True)
        lines.append(line)

    version = subprocess.run([str(Path(args.build) / "rubcont"), "--version"], capture_output=True, text=True).stdout
    head = [version.strip(),
            f"fault_campaign.py (seed {args.seed}): {args.trials} trials of sweep, lifetime and batch; "
            f"uninterrupted wall {', '.join(f'{k} {wall[k]:.1f} s' for k in kinds)}",
            f"kills {totals['kills']}, finished items lost {totals['lost']}, unreadable files {totals['unreadable']}, "
            f"final results differing from the uninterrupted run {totals['different']}, temporaries left at the "
            f"end {totals['leftovers']}"]
    print("\n".join(head))
    Path(args.out).write_text("\n".join(head + lines) + "\n")
    shutil.rmtree(top)
    return 0 if totals["lost"] == totals["unreadable"] == totals["different"] == totals["leftovers"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
