#!/usr/bin/python3
"""Every figure of issue 49 in one run: rubcont against AUTO-07p and a plain-C Dormand–Prince.

Usage: bench/against_peers.py [BUILD] [--out FILE] [--quick]

Runs, one after the other on this machine, and writes FILE (default
results/bench/against_peers.txt; written to FILE.tmp and renamed when complete):
  0. time marching first (bench/march_bench --repeats 5 --schedule; printed as section 4): its
     plain-C schedule, code that does not change with rubcont, against the same schedule's 16.6 s
     on the day AUTO-07p was measured, gives this machine's speed against that day's;
  1. the Duffing scene as a whole process (`rubcont run scenes/duffing.toml`, figures off), the
     median CPU of 5, against AUTO-07p's whole process;
  2. A(a)'s modulated whip family (bench/whip_family_bench) from its Hopf point to 63 rpm and to its
     grazing, with the stage's settings and with each lever (curved predictor, adapted mesh), and
     the 1600-interval uniform mesh as the landmarks' reference; the cost past the grazing;
  3. the flexible A(a)'s modulated whip (scenes/thesis_A_a_modulated_whip_flexible.toml, its first
     25 orbits) with the stage's settings and with both levers: CPU per orbit;
  4. time marching (bench/march_bench --repeats 5 --schedule): CPU per simulated second against
     the plain C, per regime;
  5. the work-precision charts (scripts/work-precision.sh with this build).
AUTO-07p's and the issue's figures are not re-run here: they are quoted from ../shared/peer-anchors
(AUTO-07p built from source, measured on this machine kind on 2026-11-28, loaded), so the ratios
against them compare runs made on different days and machines. Each is given twice: against AUTO's
quoted CPU, and against that CPU scaled by the plain C's (its schedule here over its 16.6 s of
2026-11-28) — an estimate of what AUTO would take here, resting on one program's speed; the ratios
within this file are measured in one run. CPU time is user + system of the child processes
(resource.getrusage), the figure to read on the shared 2-core machine. The "s wall so far" lines
count in the order run (time marching first). --quick: the short variants only (checks the
harness, ~1 min).
"""
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Issue 49's and ../shared/peer-anchors.md's figures (CPU s, 2026-11-28, loaded machine).
AUTO_DUFFING = (0.21, 0.27)
AUTO_TO_63 = 16.4         # 36 orbits, NTST 400
AUTO_TO_GRAZING = 85.2    # 136 orbits
PLAIN_C_SCHEDULE = 16.6  # the plain-C schedule 44 → 184 rpm beside AUTO-07p, 2026-11-28
AUTO_LANDMARKS = "branch points 57.00496, 72.558; period doubling 128.350; contact loss 132.531"


def child_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(args, **kwargs):
    """Runs args; returns (stdout, CPU seconds of the child)."""
    before = child_cpu()
    done = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, check=True, **kwargs)
    return done.stdout, child_cpu() - before


def load():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def scaled(cpu, auto, machine):
    """The ratio to AUTO's quoted CPU and, where the machine's factor is known, to it scaled."""
    raw = f"{cpu / auto:.2f}"
    return f"{raw} ({cpu / (auto * machine):.2f} scaled)" if machine else raw


def duffing(build, out, quick, machine):
    cpus = []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(2 if quick else 5):
            summary, cpu = run([f"{build}/rubcont", "run", "scenes/duffing.toml", "--out", tmp,
                                "--no-figures", "-q"])
            cpus.append(cpu)
    median = statistics.median(cpus)
    out.append("## 1. Duffing scene, whole process (`rubcont run scenes/duffing.toml --no-figures -q`)")
    out.append(f"CPU s of {len(cpus)} runs: {' '.join(f'{c:.3f}' for c in cpus)}; median {median:.3f}")
    out.append(f"AUTO-07p whole process {AUTO_DUFFING[0]}–{AUTO_DUFFING[1]} s: ratio "
               f"{scaled(median, AUTO_DUFFING[1], machine)} – {scaled(median, AUTO_DUFFING[0], machine)}")
    folds = [line.strip() for line in summary.splitlines() if "fold" in line.lower()]
    out.extend(f"  {line}" for line in folds[:4])


WHIP_RUNS = [
    # (label, arguments, AUTO's CPU for the ratio or None)
    ("Hopf → 63 rpm, the stage's settings (tangent, uniform 400)", [], AUTO_TO_63),
    ("Hopf → 63 rpm, curved predictor, adapted mesh", ["--curved-predictor", "--adapt-mesh", "3"],
     AUTO_TO_63),
    ("the same without the defect check (AUTO's work)",
     ["--curved-predictor", "--adapt-mesh", "3", "--no-defect-check"], AUTO_TO_63),
    ("Hopf → grazing, the stage's settings (tangent, uniform 400)",
     ["--to", "133.5", "--stop-at-grazing"], AUTO_TO_GRAZING),
    ("Hopf → grazing, curved predictor, uniform 400",
     ["--to", "133.5", "--stop-at-grazing", "--curved-predictor"], AUTO_TO_GRAZING),
    ("Hopf → grazing, tangent, adapted 400",
     ["--to", "133.5", "--stop-at-grazing", "--adapt-mesh", "3"], AUTO_TO_GRAZING),
    ("Hopf → grazing, curved predictor, adapted 400",
     ["--to", "133.5", "--stop-at-grazing", "--curved-predictor", "--adapt-mesh", "3"],
     AUTO_TO_GRAZING),
    ("the same without the defect check (AUTO's work)",
     ["--to", "133.5", "--stop-at-grazing", "--curved-predictor", "--adapt-mesh", "3",
      "--no-defect-check"], AUTO_TO_GRAZING),
    ("reference: Hopf → grazing, curved predictor, uniform 1600",
     ["--to", "133.5", "--stop-at-grazing", "--curved-predictor", "--intervals", "1600"], None),
]


def whip_family(build, out, quick, machine):
    out.append("## 2. A(a)'s modulated whip family (bench/whip_family_bench), AUTO-07p NTST 400")
    out.append(f"AUTO-07p: Hopf → 63 rpm {AUTO_TO_63} s (36 orbits), Hopf → contact loss "
               f"{AUTO_TO_GRAZING} s (136 orbits); {AUTO_LANDMARKS}")
    out.append("The defect check: every orbit integrated again by Dormand–Prince 5(4) at 1e-12 (its CPU "
               "within the run's), which AUTO-07p does not do; the rows without it are AUTO's work.")
    rows = []
    runs = WHIP_RUNS[:3] if quick else WHIP_RUNS
    for label, args, auto in runs:
        text, _ = run([f"{build}/bench/whip_family_bench", *args])
        head = re.search(r"(\d+) orbits, (\d+) Newton iterations, \d+ integrator steps, ([\d.]+) s CPU", text)
        orbits, newton, cpu = int(head.group(1)), int(head.group(2)), float(head.group(3))
        marks = re.findall(r"^  (branch point|period doubling|grazing)\s+([\d.]+) rpm( \(guess\))?", text, re.M)
        landmarks = ", ".join(f"{kind} {rpm}{' (guess)' if guess else ''}" for kind, rpm, guess in marks)
        past = re.search(r"([\d.]+) s CPU and (\d+) orbits from the last orbit before it", text)
        check = re.search(r"the orbits' measures: .*?, defect ([\d.]+) s", text)
        rows.append((label, orbits, newton, cpu, check, auto, landmarks, past))
    out.append("| run | orbits | Newton | CPU s | of it the defect check | / AUTO | landmarks, rpm | past the grazing |")
    out.append("|---|---|---|---|---|---|---|---|")
    for label, orbits, newton, cpu, check, auto, landmarks, past in rows:
        ratio = scaled(cpu, auto, machine) if auto else "–"
        beyond = f"{past.group(1)} s, {past.group(2)} orbits" if past else "–"
        checked = f"{check.group(1)} s" if check else "–"
        out.append(f"| {label} | {orbits} | {newton} | {cpu:.2f} | {checked} | {ratio} | {landmarks} | {beyond} |")


def flexible(build, out, quick):
    out.append("## 3. The flexible A(a)'s modulated whip, CPU per orbit (first 25 orbits, 20 → 75 rpm)")
    base = open(os.path.join(ROOT, "scenes", "thesis_A_a_modulated_whip_flexible.toml")).read()
    variants = [("the stage's settings (tangent, uniform 400)", ""),
                ("curved predictor, adapted 400", 'predictor = "curved"\nmesh = "adapted"\n')]
    orbits_wanted = 5 if quick else 25
    for label, extra in variants:
        scene = re.sub(r"^max_steps = \d+", f"max_steps = {orbits_wanted}\n{extra}", base, flags=re.M)
        scene = re.sub(r"^speed_range_rpm = .*$", "speed_range_rpm = [20.0, 75.0]", scene, flags=re.M)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "thesis_A_a_modulated_whip_flexible.toml")
            open(path, "w").write(scene)
            summary, cpu = run([f"{build}/rubcont", "run", path, "--out", tmp, "--no-figures", "-q"])
        points = sum(int(n) for n in re.findall(r"branch: (\d+) points", summary))
        reached = re.findall(r"λ ∈ \[[\d.]+, ([\d.]+)\]", summary)
        out.append(f"  {label}: {points} orbits in {cpu:.1f} s CPU (the whole run, L1 included): "
                   f"{cpu / max(points, 1):.2f} s per orbit; families reach λ = {', '.join(reached)} rad/s")


def marching(build, out, quick):
    """Section 4, run first; returns this machine's speed against 2026-11-28's (plain C's schedule
    CPU over PLAIN_C_SCHEDULE), or None without the schedule (--quick)."""
    out.append("## 4. Time marching against the plain-C Dormand–Prince (bench/march_bench; run first)")
    args = [f"{build}/bench/march_bench", "--repeats", "1" if quick else "5"]
    if quick:
        args += ["--regime", "whirl"]
    else:
        args += ["--schedule"]
    text, _ = run(args)
    out.append(text.rstrip())
    plain = re.search(r"^  plain C\s+([\d.]+) s CPU for", text, re.M)
    if not plain:
        return None
    machine = float(plain.group(1)) / PLAIN_C_SCHEDULE
    out.append(f"this machine against 2026-11-28's: the plain-C schedule {plain.group(1)} s of CPU "
               f"against {PLAIN_C_SCHEDULE} s, factor {machine:.2f} (AUTO's CPU scaled by it below)")
    return machine


def work_precision(build, out, quick):
    out.append("## 5. The work-precision charts (scripts/work-precision.sh)")
    if quick:
        out.append("  skipped (--quick)")
        return
    start = time.time()
    text, cpu = run(["scripts/work-precision.sh"], env={**os.environ, "BUILD": build})
    out.append(f"  regenerated results/bench/default/ and results/bench/thesis_C_a/ in "
               f"{time.time() - start:.0f} s wall, {cpu:.0f} s CPU")
    out.append("  " + text.strip().splitlines()[-1])


def main(argv):
    build = "build"
    target = "results/bench/against_peers.txt"
    quick = False
    rest = list(argv)
    while rest:
        a = rest.pop(0)
        if a == "--out":
            target = rest.pop(0)
        elif a == "--quick":
            quick = True
        else:
            build = a
    describe = subprocess.run(["git", "describe", "--tags", "--dirty", "--always"], cwd=ROOT,
                              capture_output=True, text=True).stdout.strip()
    out = [f"# bench/against_peers.py {build} at {describe}, {time.strftime('%Y-%m-%d %H:%M')} UTC, "
           f"load at the start {load()}", ""]
    start = time.time()
    sections = {name: [] for name in ("duffing", "whip", "flexible", "marching", "work")}  # printed order

    def stamp(text):
        text.append(f"(load {load()}, {time.time() - start:.0f} s wall so far)")
        text.append("")

    machine = marching(build, sections["marching"], quick)  # first: the machine's speed
    stamp(sections["marching"])
    duffing(build, sections["duffing"], quick, machine)
    stamp(sections["duffing"])
    whip_family(build, sections["whip"], quick, machine)
    stamp(sections["whip"])
    flexible(build, sections["flexible"], quick)
    stamp(sections["flexible"])
    work_precision(build, sections["work"], quick)
    stamp(sections["work"])
    for text in sections.values():
        out.extend(text)
    path = os.path.join(ROOT, target)
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(path + ".tmp", path)
    print(f"wrote {target} ({time.time() - start:.0f} s wall)")


if __name__ == "__main__":
    main(sys.argv[1:])
