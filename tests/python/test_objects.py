"""rubcont's objects (python/rubcont/objects.py): branches with typed special points, sweeps,
loops, orbit and torus families, their plot() through rubcont.plots, _repr_html_, progress as
events, continue_from (from a Hopf point of the tanh waves, and its refusals), and the commands
with many options (ensemble, lifetime, attractor, flexible, batch). Committed result files are
read where a run would cost minutes.
"""
import os
import subprocess
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import rubcont  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
A_A = os.path.join(ROOT, "scenes", "thesis_A_a.toml")
RESULTS = os.path.join(ROOT, "results")


def test_a_branch_is_its_arrays_with_stability_and_typed_special_points():
    result = rubcont.branches(A_A)
    branch = next(b for b in result.branches if b.name == "branch2")
    assert np.array_equal(branch.speed_rpm, result["branches/branch2/speed_rpm"])
    assert np.array_equal(branch.stable, result["branches/branch2/stable"] == 1)
    assert branch.mode == "mode1"
    event = next(p for p in branch.special_points if p.label == "left stick to slip+")
    assert event.type == "event" and event.speed_rpm == pytest.approx(50.689, abs=5e-4)
    assert event.frequency_hz == pytest.approx(result["branches/branch2/special_points/precession_hz"][0])
    assert "normal_force_left" in event.state and "type" not in event.state
    assert [b.name for b in result.branches][:3] == ["branch1", "branch2", "branch3"]  # numeric order
    fig = branch.plot()
    assert isinstance(fig, Figure) and fig.axes[0].lines
    fig2, ax = matplotlib.pyplot.subplots()
    assert branch.plot(ax=ax) is fig2
    assert "left stick to slip+" not in branch._repr_html_() and "event 50.69 rpm" in branch._repr_html_()
    assert "11 branches" in result._repr_html_()


def test_sweep_loop_orbit_and_torus_families_from_the_committed_files():
    sweep = rubcont.read(os.path.join(RESULTS, "thesis_A_a", "sweep.h5")).sweep
    assert sweep.directions == ["up", "down"]
    assert len(sweep.direction("up").speed_rpm) > 10 and "speed_from_rpm" in sweep.jumps
    assert isinstance(sweep.plot(), Figure)
    loop = rubcont.read(os.path.join(RESULTS, "thesis_A_a", "loop.h5")).loop
    assert list(loop.corners["level"][:1]) == ["L1"] and isinstance(loop.plot(), Figure)
    assert "corner 1" in loop._repr_html_()
    whip = rubcont.read(os.path.join(RESULTS, "thesis_A_a_modulated_whip", "thesis_A_a_modulated_whip.h5"))
    family = whip.orbit_families[0]
    assert family.name == "branch2_hopf2"
    assert family.special_points[0].type == "branch point"
    assert isinstance(family.plot(), Figure)
    tori = rubcont.read(os.path.join(RESULTS, "thesis_C_a_tori", "thesis_C_a_tori.h5")).torus_families
    assert tori[0].name == "branch1_hopf2_ns1" and np.all(tori[0].rotation_number > 0)
    assert isinstance(tori[0].plot(), Figure)


def test_result_plot_draws_what_the_command_line_draws():
    figures = rubcont.read(os.path.join(RESULTS, "jeffcott", "jeffcott.h5")).plot()
    assert sorted(figures) == ["analytic_single", "branches_mu", "branches_precession", "branches_slip"]


def test_progress_lines_as_events_that_drive_a_bar():
    event = rubcont.parse_progress("rubcont: [sweep up] 3/6 44.0 rpm: BP 73.29/73.29 Hz")
    assert (event.stage, event.done, event.total) == ("sweep up", 3, 6)
    assert rubcont.parse_progress("rubcont: [analytic] L0 closed form").done is None
    seen = []
    rubcont.branches(A_A, progress=rubcont.events(seen.append))
    counted = [e for e in seen if e.stage == "branches" and e.total is not None]
    assert counted and counted[-1].done <= counted[-1].total == 21
    pytest.importorskip("tqdm")
    bars = rubcont.TqdmProgress(disable=True)
    rubcont.branches(A_A, progress=bars)
    assert bars._bars["branches"].total == 21
    bars.close()


def test_continue_from_names_the_points_it_cannot_start_from():
    result = rubcont.read(os.path.join(RESULTS, "thesis_A_a", "thesis_A_a.h5"))
    event = result.branches[1].special_points[0]
    with pytest.raises(ValueError, match="a 'event' point .* starts orbit families from Hopf points only"):
        rubcont.continue_from(event, result)
    hopf = next(p for b in result.branches for p in b.special_points if p.type == "Hopf")
    with pytest.raises(ValueError, match="lies on /branches/.*tanh-law"):
        rubcont.continue_from(hopf, result)


def test_continue_from_a_hopf_point_of_the_tanh_waves_gives_the_family_born_there():
    # A short orbits stage (two steps of 100 intervals a family) makes the point to start from.
    short = rubcont.load_scene(A_A).with_values({"analysis": {
        "stages": ["orbits"], "speed_range_rpm": [20.0, 100.0],
        "orbits": {"hopf_points": 1, "max_steps": 2, "collocation_intervals": 100}}})
    result = rubcont.orbits(short)
    waves = [rubcont.Branch(result, f"orbits/rotating_waves/{n}") for n in result.groups("orbits/rotating_waves")]
    hopf = [p for w in waves for p in w.special_points if p.type == "Hopf"]
    mode1 = min(hopf, key=lambda p: abs(p.speed_rpm - 51.6847))  # the whirl's, A(a)'s modulated whip
    family = rubcont.continue_from(mode1, result)
    assert isinstance(family, rubcont.OrbitFamily)
    assert abs(family.attrs["hopf_speed_rpm"] - mode1.speed_rpm) < 1e-9
    assert len(family.speed_rpm) >= 1 and abs(family.speed_rpm[0] - mode1.speed_rpm) < 0.5


def test_ensemble_lifetime_attractor_flexible_and_batch_are_reachable(tmp_path):
    small = rubcont.load_scene(A_A).with_values(
        {"analysis": {"sweep": {"up_range_rpm": [40.0, 64.0], "speed_step_rpm": 4.0, "dwell": 0.75}}})
    # From 44 rpm: the approach is one speed of the sweep (40 rpm).
    ensemble = rubcont.ensemble(small, speed_rpm=44.0, copies=2, duration=0.2, threads=2)
    assert ensemble.status == "success" and ensemble["ensemble/arrival_time_s"].shape == (2,)
    lifetime = rubcont.lifetime(small, from_rpm=44.0, to_rpm=48.0, step_rpm=4.0, copies=2,
                                duration=0.2, check_copies=0, threads=2)
    assert list(lifetime["lifetime/speed_rpm"]) == [44.0, 48.0]
    attractor = rubcont.attractor(small, from_rpm=44.0, duration=0.2, discard=0.1, exponents=2)
    assert attractor["attractor/exponents"].shape == (1, 2)
    assert rubcont.flexible(A_A, modes=2).status == "success"
    with pytest.raises(TypeError, match="unknown option 'copys'; options: copies"):
        rubcont.ensemble(small, speed_rpm=44.0, copys=2)
    with pytest.raises((ValueError, rubcont.RubcontError), match="missing.toml"):
        rubcont.batch(tmp_path / "missing.toml", out=tmp_path)
    jobs = tmp_path / "jobs.toml"
    jobs.write_text(f'[[job]]\nname = "waves"\ncommand = "analytic"\nscene = "{A_A}"\n')
    summary = rubcont.batch(jobs, out=tmp_path / "batch")
    assert "1 done, 0 failed" in summary
    assert rubcont.read(tmp_path / "batch" / "waves" / "waves.h5").status == "success"


def test_a_ross_rotor_and_an_fe_models_matrices_come_in(tmp_path):
    ross = os.path.join(ROOT, "tests", "apps", "ross")
    imported = rubcont.import_ross(os.path.join(ross, "rotor.toml"), os.path.join(ross, "base.toml"), (1, 5))
    with pytest.raises(ValueError, match="--contact-stations 1 7: must be ROSS nodes"):
        rubcont.import_ross(os.path.join(ross, "rotor.toml"), os.path.join(ross, "base.toml"), (1, 7))
    # The imported rotor assembles to the matrices of the same rotor written by hand.
    section = rubcont.scene_matrices(imported, tmp_path / "imported.h5")
    assert "[flexible.matrices]" in section
    rubcont.scene_matrices(os.path.join(ross, "rotor_by_hand.toml"), tmp_path / "by_hand.h5")
    with h5py.File(tmp_path / "imported.h5") as a, h5py.File(tmp_path / "by_hand.h5") as b:
        for name in ("mass", "damping", "stiffness", "gyroscopic"):
            assert np.array_equal(a[name][()], b[name][()]), name


def test_the_package_is_typed():
    assert os.path.exists(os.path.join(os.path.dirname(rubcont.__file__), "py.typed"))


def test_the_example_runs(tmp_path):
    out = tmp_path / "loop.png"
    subprocess.run([sys.executable, os.path.join(ROOT, "python", "examples", "hysteresis.py"), str(out)],
                   cwd=ROOT, check=True, capture_output=True, timeout=120)
    assert out.stat().st_size > 20000
