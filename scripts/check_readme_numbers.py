#!/usr/bin/python3
"""Numbers of the study pages (docs/studies/) read again from the committed result files.

    /usr/bin/python3 scripts/check_readme_numbers.py [RESULTS_DIR]

Each claim below computes values from the files under RESULTS_DIR (default: results/) and formats
the sentence its page must contain (CLAIMS names the page, relative to the repository root); the
check fails, naming the claim, the page and the sentence it expected, when the page no longer says
what the files hold (line breaks and repeated spaces do not matter). The sweeps' jump and cost
tables are read row by row (SWEEP_TABLES' page), and the thesis tables must be what
scripts/thesis_comparison.py computes (THESIS_TABLES' page). Exit code 0 when every claim holds, 1
otherwise.

A new number on a study page that a file holds gets a claim here, beside the page it is on.
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


def text(value):
    """An HDF5 string attribute or element as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


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
    return f"the Mode 1 whirl at {hopf:.4f} rpm"


def modulated_whip_in_sweeps(results):
    """The modulated whip's symmetry-breaking branch points, as the sweeps' reading cites them."""
    with h5(results, "thesis_A_a_modulated_whip/thesis_A_a_modulated_whip.h5") as f:
        g = f["orbits/branch2_hopf2"]
        bp = [s for t, s in zip(g["special_points/type"][()], g["special_points/speed_rpm"][()])
              if t == b"branch point"]
    return f"between its branch points at {bp[0]:.1f} and {bp[1]:.1f} rpm"


def modulated_whip_table(results):
    """The modulated whip's table: the first orbit and those nearest 53.6 … 100 rpm."""
    with h5(results, "thesis_A_a_modulated_whip/thesis_A_a_modulated_whip.h5") as f:
        g = f["orbits/branch2_hopf2"]
        rpm = g["speed_rpm"][()]
        mu = np.hypot(g["multipliers_real"][()], g["multipliers_imag"][()])
        rows = []
        for target in (rpm[0], 53.6, 56.1, 57.9, 62.8, 80.0, 100.0):
            i = int(np.argmin(np.abs(rpm - target)))
            rows.append(
                f"| {rpm[i]:.3f} | {g['modulation_hz'][i]:.2f} | {g['precession_hz'][i]:.4f} | "
                f"{g['min_precession_hz_left'][i]:.2f} – {g['max_precession_hz_left'][i]:.2f} | "
                f"{g['min_normal_force_left'][i]:.0f} – {g['max_normal_force_left'][i]:.0f} | "
                f"{np.nanmax(mu[i]):.4f} |")
    return tuple(rows)


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
    return f"{count} speeds of the committed sweeps (2026-11-30)\nare intermittent"


def whip_lifetimes(results):
    """The ensembles at the end of A(a)'s speed-up whip: one table row per committed file."""
    rows = []
    for rpm in (168, 172, 176, 180, 184):
        with h5(results, f"thesis_A_a/ensemble_{rpm}rpm.h5") as f:
            g = f["ensemble"]
            arrival = g["arrival_time_s"][()]
            reached = np.sort(arrival[np.isfinite(arrival)])
            regime = text(g.attrs["approach_regime_left"])
            if len(reached) == 0:
                times = "–"
            elif np.all(reached == reached[0]) and len(reached) == len(arrival):
                times = f"{reached[0]:.2f} s, all in the first stretch"
            else:
                q = np.quantile(reached, [0.25, 0.5, 0.75])
                times = (f"{reached[0]:.2f} / {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} / "
                         f"{reached[-1]:.2f} s")
            rows.append(f"| {rpm} rpm | {g.attrs['approach_to_rpm']:g} rpm, {regime} | "
                        f"{len(reached)} of {len(arrival)} | {times} | "
                        f"{np.median(g['cpu_seconds'][()]):.1f} s |")
    return tuple(rows)


def lifetime_rows(results, path):
    """The escape rates of a lifetime file (rubcont lifetime): one table row per speed, the crisis
    (its upper bound, or both limits) and exponent, and the check sweeps' speeds."""
    with h5(results, path) as f:
        g = f["lifetime"]
        rows = []
        for i, rpm in enumerate(g["speed_rpm"][()]):
            rate, lower, upper = g["escape_rate"][i], g["rate_lower"][i], g["rate_upper"][i]
            left = f"{g['escapes'][i]} of {g['escapes'][i] + g['stayed'][i]}"
            if rate == 0:
                rows.append(f"| {rpm:g} rpm | {left} | < {upper:.2g} | > {1 / upper:.3g} s |")
            else:
                rows.append(f"| {rpm:g} rpm | {left} | {rate:.3g} [{lower:.2g}, {upper:.3g}] | {1 / rate:.3g} s |")
        c = g["crisis"].attrs
        if c["lower_bounded"]:
            rows.append(f"**{c['critical_speed_rpm']:.2f} rpm,\n  95 % {c['critical_lower_rpm']:.2f} … "
                        f"{c['critical_upper_rpm']:.2f} rpm**")
        else:
            rows.append(f"**p_c < {c['critical_upper_rpm']:.2f} rpm at 95 %**")
        rows.append(f"γ = {c['exponent']:.2f}")
        jumps = ", ".join(f"{s:g}" for s in g["check/jump_speed_rpm"][()])
        rows.append(jumps[: jumps.rfind(", ")] + " and" + jumps[jumps.rfind(", ") + 1:])
    return tuple(rows)


def whip_end_lifetimes(results):
    """Where the speed-up whip ends, A(a) and B(a)."""
    return (lifetime_rows(results, "thesis_A_a_whip_end/lifetime_174_184rpm.h5")
            + lifetime_rows(results, "thesis_B_a_whip_end/lifetime_186_196rpm.h5"))


WHIP_END_FILES = {"A(a)": "thesis_A_a_whip_end/lifetime_174_184rpm.h5",
                  "A(b)": "thesis_A_b_whip_end/lifetime_158_170rpm.h5",
                  "B(a)": "thesis_B_a_whip_end/lifetime_186_196rpm.h5",
                  "B(b)": "thesis_B_b_whip_end/lifetime_158_170rpm.h5",
                  "B(c)": "thesis_B_c_whip_end/lifetime_182_194rpm.h5",
                  "C(a)": ("thesis_C_a_whip_end/lifetime_201_211rpm.h5",
                           "thesis_C_a_whip_end/lifetime_206_216rpm.h5"),
                  "C(b)": "thesis_C_b_whip_end/lifetime_162_174rpm.h5",
                  "C(c)": "thesis_C_c_whip_end/lifetime_202_214rpm.h5"}


def whip_end_row(results, case, path):
    """The start of a case's row in the table "The end of the speed-up whip in every case": the
    speeds, what a copy arrives at, the escapes per speed, the crisis and its exponent, the check
    sweeps and where the law predicts them, and the CPU time, all from the lifetime file."""
    with h5(results, path) as f:
        g = f["lifetime"]
        a = g.attrs
        rpm = g["speed_rpm"][()]
        step = rpm[1] - rpm[0] if len(rpm) > 1 else 0.0
        arrival = text(a["arrival"]) if "arrival" in a else "whirl on every contact"
        escapes = ", ".join(str(int(e)) for e in g["escapes"][()])
        copies = int(a["copies"])
        c = g["crisis"].attrs
        if text(c["status"]) != "located":
            crisis, exponent = f"{text(c['status'])}: {text(c['message'])}", "–"
        else:
            exponent = f"{c['exponent']:.2f}"
            if c["lower_bounded"] and c["upper_bounded"]:
                crisis = f"**{c['critical_speed_rpm']:.2f} rpm**, 95 % {c['critical_lower_rpm']:.2f} … {c['critical_upper_rpm']:.2f}"
            elif c["upper_bounded"]:
                crisis = f"**below {c['critical_upper_rpm']:.2f} rpm** (95 %; best fit {c['critical_speed_rpm']:.2f})"
            else:
                crisis = f"**above {c['critical_lower_rpm']:.2f} rpm** (95 %; best fit {c['critical_speed_rpm']:.2f})"
        checks, predicted = "–", "–"
        if "check" in g:
            left = g["check/jump_speed_rpm"][()]
            checks = ", ".join("stayed" if np.isnan(s) else f"{s:g}" for s in left)
            # As the command prints it (apps/lifetime_command.cpp): the first schedule speed at
            # which the cumulative leave probability reaches 5 %, 50 %, 95 %.
            schedule, leave = g["check/speed_rpm"][()], g["check/predicted_leave_probability"][()]
            cumulative = np.cumsum(leave)
            at = lambda q: next((f"{s:g}" for s, c in zip(schedule, cumulative) if c >= q), None)
            low, median, high = at(0.05), at(0.5), at(0.95)
            beyond = f"beyond {schedule[-1]:g}"
            predicted = (f"median {median or beyond}, 90 % {low}–{high}" if high
                         else f"median {median or beyond}, 90 % from {low or beyond} to {beyond}")
        return (f"| {case} | {rpm[0]:g}–{rpm[-1]:g} rpm, {step:g} rpm steps | {arrival} | {escapes} (of {copies}) | "
                f"{crisis} | {exponent} | {checks} | {predicted} | {a['cpu_seconds']:.0f} s |")


def whip_end_cases(results):
    """Where the speed-up whip ends, one row per thesis case whose lifetime file exists."""
    return tuple(whip_end_row(results, case, path) for case, paths in WHIP_END_FILES.items()
                 for path in ((paths,) if isinstance(paths, str) else paths)
                 if os.path.exists(os.path.join(results, path)))


def attractor_rows(results, case, names):
    """Case C(<case>)'s `rubcont attractor` files attractor_<name>rpm.h5, in the order given: for
    each speed (rpm, rounded to 0.01) the (motion, λ₁, its standard error) of every file that ran it."""
    rows = {}
    for name in names:
        with h5(results, f"thesis_C_{case}/attractor_{name}rpm.h5") as f:
            a = f["attractor"]
            for speed, motion, exponents, errors in zip(
                    a["speed_rpm"][()], a["motion"][()], a["exponents"][()], a["standard_errors"][()]):
                rows.setdefault(round(float(speed), 2), []).append((text(motion), exponents[0], errors[0]))
    return rows


def c_a_attractor(results):
    """C(a)'s speed-up whip by `rubcont attractor`: chaotic from 49.7 to 57.2 rpm, and λ₁ there and
    in the impacting whip from 82 rpm."""
    rows = {s: v[-1] for s, v in attractor_rows(results, "a", ("49_50", "49_60", "57_61", "62_98",
                                                                "100_124")).items()}
    chaotic = [s for s in rows if 49.7 <= s <= 57.25]
    verdict = ("chaotic" if all(rows[s][0] == "chaotic" for s in chaotic)
               else "not chaotic at every speed from 49.7 to 57.25 rpm (the files)")
    impacting = [rows[s][1] for s in rows if 100 <= s <= 124]
    return (f"**{verdict}**: +{rows[49.7][1]:.1f} ± {rows[49.7][2]:.1f} (49.7)",
            f"+{rows[57.25][1]:.1f} ± {rows[57.25][2]:.1f} (57.25)",
            f"+{rows[82.0][1]:.0f} ± {rows[82.0][2]:.0f} (82)",
            f"+{min(impacting):.0f} … +{max(impacting):.0f} (100–124)")


def c_bc_attractor(results):
    """C(b)'s and C(c)'s speed-up whips by `rubcont attractor`: the impacting chaos's λ₁ and where it
    starts, C(c)'s torus at every speed 58–70 rpm, C(b)'s weak chaos at 56 and 58 rpm."""
    b = attractor_rows(results, "b", ("40_112", "52_60"))
    c = attractor_rows(results, "c", ("44_112", "48_70"))
    b_high = [r[1] for s, v in b.items() if 80 <= s <= 112 for r in v]
    c_high = [r[1] for s, v in c.items() if 76 <= s <= 108 for r in v]
    torus = all(r[0] == "relative 2-torus" for s, v in c.items() if 58 <= s <= 70 for r in v)
    fine_b = {s: v[-1] for s, v in b.items()}  # the 1 rpm run where both ran
    return (f"| 80–112 | chaotic and impacting: +{min(b_high):.0f} … +{max(b_high):.0f} | chaotic and "
            f"impacting at 80–108 (+{min(c_high):.0f} … +{max(c_high):.0f})",
            f"**chaotic and impacting** (+{b[76.0][0][1]:.0f} ± {b[76.0][0][2]:.0f})",
            f"from 72 (+{c[72.0][0][1]:.0f} ± {c[72.0][0][2]:.0f} at 72",
            f"**chaotic** at 56 (+{fine_b[56.0][1]:.1f} ± {fine_b[56.0][2]:.1f}) and 58 "
            f"(+{fine_b[58.0][1]:.1f} ± {fine_b[58.0][2]:.1f})",
            "**relative 2-torus at every speed 58–70**" if torus
            else "C(c): not a torus at every speed 58–70 rpm (the files)")


# Each claim and the page (relative to the repository root) that must say it.
CLAIMS = [(stability_gap, "docs/studies/rotating_waves.md"), (intermittent_speeds, "docs/studies/sweeps.md"),
          (whip_contact_fraction, "docs/studies/sweeps.md"), (duffing_folds, "docs/studies/orbits.md"),
          (stuart_landau_errors, "docs/studies/orbits.md"), (forced_van_der_pol_folds, "docs/studies/orbits.md"),
          (modulated_whip, "docs/studies/orbits.md"), (modulated_whip_in_sweeps, "docs/studies/sweeps.md"),
          (modulated_whip_table, "docs/studies/orbits.md"), (whip_lifetimes, "docs/studies/whip_end.md"),
          (whip_end_lifetimes, "docs/studies/whip_end.md"), (whip_end_cases, "docs/studies/whip_end.md"),
          (c_a_attractor, "docs/studies/attractors.md"), (c_bc_attractor, "docs/studies/attractors.md")]
SWEEP_TABLES = "docs/studies/sweeps.md"     # the jump table and the cost table of the sweeps
THESIS_TABLES = "docs/studies/thesis_comparison.md"    # between thesis_comparison.py's markers


CASES = {"A(a)": "thesis_A_a", "A(b)": "thesis_A_b", "B(a)": "thesis_B_a", "B(b)": "thesis_B_b",
         "B(c)": "thesis_B_c", "C(a)": "thesis_C_a", "C(b)": "thesis_C_b", "C(c)": "thesis_C_c"}
CHAIN = re.compile(r"\d+(?: → \d+)+")
BPS = re.compile(r"\d+\.\d\d(?: / \d+\.\d\d)?(?: → \d+\.\d\d)+ Hz")
DIFFERENCE = re.compile(r"^([−+-]?\d+\.\d\d) rpm")


def jump_table_rows(results, page_text):
    """Each row of the sweeps' jump table against /sweeps/jump_table of its case's file: the
    row's BP before → after (either contact's, "x / y → z"; each step of a chain "x → y → z") must
    be that of a jump of its direction whose speeds are a step of a chain "a → b (→ c)" in the row's
    jump cell (any step, when the cell has none), and a numeric difference must be that jump's
    difference to its predictor."""
    problems, checked = [], 0
    for line in page_text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 7 or cells[0] not in CASES or cells[1] not in ("up", "down"):
            continue
        bps = BPS.search(cells[3])
        if not bps:
            problems.append(f"jump table row {cells[0]} {cells[1]}: no 'BP → BP Hz' in it")
            continue
        chain = bps.group(0)[:-3].split(" → ")
        pairs = [(before.split(" / "), after) for before, after in zip(chain, chain[1:])]
        steps = set()
        for chain in CHAIN.findall(cells[2]):
            speeds = chain.split(" → ")
            steps |= set(zip(speeds, speeds[1:]))
        with h5(results, f"{CASES[cells[0]]}/sweep.h5") as f:
            t = f["sweeps/jump_table"]
            rows = [dict(d=t["direction"][i].decode(), a=f"{t['speed_from_rpm'][i]:.0f}",
                         b=f"{t['speed_to_rpm'][i]:.0f}", p=f"{t['precession_from_hz'][i]:.2f}",
                         q=f"{t['precession_to_hz'][i]:.2f}", diff=t["difference_rpm"][i])
                    for i in range(len(t["direction"][()]))]
        difference = DIFFERENCE.search(cells[5].replace("−", "-"))
        def matches(befores, after):
            return [r for r in rows if r["d"] == cells[1] and r["p"] in befores and r["q"] == after
                    and (not steps or (r["a"], r["b"]) in steps)
                    and (not difference or abs(r["diff"] - float(difference.group(1))) <= 0.005)]
        checked += 1
        if not all(matches(befores, after) for befores, after in pairs):
            problems.append(f"jump table row {cells[0]} {cells[1]}, BP '{bps.group(0)}'"
                            f"{', difference ' + difference.group(1) if difference else ''}: no such "
                            f"jump in results/{CASES[cells[0]]}/sweep.h5")
    return checked, problems


COST = re.compile(r"^\| ([ABC]\([abc]\)) \| ([\d.]+) s, ([\d.e+]+), (\d+)(?: of \d+)? \| "
                  r"([\d.]+) s, ([\d.e+]+), (\d+)(?: of \d+)? \|")


def sweep_cost_rows(results, page_text):
    """The sweeps' cost table: integration wall time, BDF steps and unsettled speeds per direction,
    from /sweeps/<direction> of each case's file."""
    problems, checked = [], 0
    for line in page_text.splitlines():
        row = COST.match(line)
        if not row:
            continue
        checked += 1
        with h5(results, f"{CASES[row.group(1)]}/sweep.h5") as f:
            for k, direction in ((2, "up"), (5, "down")):
                g = f[f"sweeps/{direction}"]
                wall = f"{g.attrs['wall_seconds']:.1f}"
                steps = f"{g['steps'][()].sum():.2e}".replace("e+0", "e")
                unsettled = str(int((g["settled"][()] == 0).sum()))
                if (wall, steps, unsettled) != (row.group(k), row.group(k + 1), row.group(k + 2)):
                    problems.append(f"cost table row {row.group(1)} {direction}: the file gives "
                                    f"{wall} s, {steps}, {unsettled}")
    return checked, problems


def normalized(text):
    return re.sub(r"\s+", " ", text)


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    def page(path):
        return open(os.path.join(root, path)).read()
    failed = 0
    for claim, path in CLAIMS:
        expected = claim(results)
        said = normalized(page(path))
        for sentence in expected if isinstance(expected, tuple) else (expected,):
            if normalized(sentence) in said:
                print(f"holds   {claim.__name__}: {sentence}")
            else:
                failed += 1
                print(f"FAILS   {claim.__name__}: {path} should say: {sentence}")
    checked, problems = jump_table_rows(results, page(SWEEP_TABLES))
    for p in problems:
        failed += 1
        print(f"FAILS   {p}")
    print(f"{'holds' if not problems else 'FAILS'}   jump table ({SWEEP_TABLES}): {checked - len(problems)} "
          f"of {checked} rows are jumps of their sweep files")
    checked, problems = sweep_cost_rows(results, page(SWEEP_TABLES))
    for p in problems:
        failed += 1
        print(f"FAILS   {p}")
    print(f"{'holds' if not problems else 'FAILS'}   sweep cost table ({SWEEP_TABLES}): "
          f"{checked - len(problems)} of {checked} rows are their files' wall times, steps and unsettled speeds")
    tables = subprocess.run([sys.executable, os.path.join(root, "scripts/thesis_comparison.py"), results,
                             "--check", os.path.relpath(os.path.join(root, THESIS_TABLES))], capture_output=True, text=True)
    print(tables.stdout, end="")
    if tables.returncode != 0:
        failed += 1
        print(tables.stderr, end="")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
