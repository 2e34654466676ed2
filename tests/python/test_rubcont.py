"""`import rubcont` (python/): scenes, stages, results, errors, progress and the GIL.

Run by ctest with PYTHONPATH=<build>/python and RUBCONT_BINARY_DIR=<build> (tests/CMakeLists.txt),
from the repository root.
"""

import os
import subprocess
import threading
import time

import numpy as np
import pytest

import rubcont

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BINARY_DIR = os.environ.get("RUBCONT_BINARY_DIR", os.path.join(ROOT, "build"))
A_A = os.path.join(ROOT, "scenes", "thesis_A_a.toml")


def test_a_scene_from_a_file_a_dict_and_text_is_the_same_scene():
    from_file = rubcont.load_scene(A_A)
    assert from_file.name == "thesis_A_a"
    assert from_file.model == "two_point"
    assert from_file.stages == ["analytic", "branches"]
    from_dict = rubcont.scene(from_file.to_dict())
    from_text = rubcont.scene(from_file.toml)

    def body(scene):  # the first line names the source
        return scene.toml.split("\n", 1)[1]

    assert body(from_dict) == body(from_file)
    assert body(from_text) == body(from_file)
    assert from_dict.source == "<dict>"
    assert rubcont.default_scene().name == "default"


def test_with_values_changes_one_key_and_validates_again():
    base = rubcont.load_scene(A_A)
    changed = base.with_values({"contact": {"friction": 0.3}})
    assert changed.to_dict()["contact"]["friction"] == 0.3
    assert base.to_dict()["contact"]["friction"] == 0.5
    with pytest.raises(rubcont.SceneError, match=r"contact\.friction = -1: must be non-negative"):
        base.with_values({"contact": {"friction": -1}})


def test_a_bad_scene_raises_scene_error_with_key_value_and_rule():
    with pytest.raises(rubcont.SceneError) as error:
        rubcont.scene({"rotor": {"mass": "heavy"}})
    assert isinstance(error.value, ValueError)
    assert "rotor.mass" in str(error.value)
    with pytest.raises(rubcont.SceneError, match="rotor.inertia: missing; required"):
        rubcont.scene({"rotor": {"mass": 1.0}})
    with pytest.raises(TypeError, match=r"rotor\.mass = <object"):
        rubcont.scene({"rotor": {"mass": object()}})


def test_branches_give_the_numbers_and_names_of_the_command_line(tmp_path):
    result = rubcont.branches(A_A)
    assert result.status == "success" and result.failures == []
    assert result.file is None  # a temporary directory, gone
    # The same scene through the executable: the same datasets, the same numbers.
    subprocess.run([os.path.join(BINARY_DIR, "rubcont"), "branches", A_A, "--quiet", "--out",
                    str(tmp_path / "cli.h5")], check=True, capture_output=True)
    cli = rubcont.read(tmp_path / "cli.h5")
    assert sorted(result.keys()) == sorted(cli.keys())
    for key in ["branches/branch2/speed_rpm", "branches/branch2/precession_hz",
                "branches/branch2/special_points/speed_rpm", "analytic/mode1/precession_hz"]:
        assert np.array_equal(result[key], cli[key]), key
    # The speed-up whirl → whip event of A(a) (docs/studies/rotating_waves.md: 50.689 rpm).
    points = "branches/branch2/special_points/"
    labels = list(result[points + "label"])
    event = labels.index("left stick to slip+")
    assert result[points + "speed_rpm"][event] == pytest.approx(50.689, abs=5e-4)
    assert result.attrs("branches/branch2")["message"].startswith("backward: reached λ min")
    assert "branches" in result.groups() and "branch2" in result.groups("branches")
    assert "wrote" in result.log


def test_write_saves_the_bytes_and_read_reopens_them(tmp_path):
    result = rubcont.analytic(A_A)
    result.write(tmp_path / "a.h5")
    assert not os.path.exists(tmp_path / "a.h5.tmp")
    again = rubcont.read(tmp_path / "a.h5")
    assert again.file == str(tmp_path / "a.h5")
    assert again.keys() == result.keys()
    assert np.array_equal(again["analytic/mode2/precession_hz"],
                          result["analytic/mode2/precession_hz"])
    # The stored scene: the one that ran (its stages set to the one stage).
    ran = rubcont.load_scene(A_A).with_values({"analysis": {"stages": ["analytic"]}})
    assert again.scene.to_dict() == ran.to_dict()


def test_out_keeps_the_files_where_the_command_line_puts_them(tmp_path):
    result = rubcont.analytic(A_A, out=tmp_path)
    assert result.file == str(tmp_path / "thesis_A_a" / "thesis_A_a.h5")
    assert os.path.exists(result.file)


def test_progress_lines_reach_the_callback_and_its_error_is_raised():
    lines = []
    rubcont.branches(A_A, progress=lines.append)
    assert any("[branches]" in line for line in lines)
    assert all("\n" not in line for line in lines)

    def fails(line):
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        rubcont.branches(A_A, progress=fails)


def test_the_gil_is_released_while_a_stage_runs():
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=tick)
    thread.start()
    start = time.perf_counter()
    try:
        rubcont.branches(A_A)  # no progress callback: the GIL is never taken back
    finally:
        end = time.perf_counter()
        done.set()
        thread.join()
    during = [t for t in ticks if start < t < end]
    assert end - start > 0.05
    assert len(during) >= 10, f"{len(during)} ticks in {end - start:.3f} s"


def test_a_numerical_failure_is_a_status_not_an_exception():
    tanh = os.path.join(ROOT, "scenes", "thesis_A_a_tanh.toml")
    result = rubcont.map(tanh, parameter="friction", eta_range=(0.45, 0.55), eta_points=3,
                         speed_points=41, threads=2)
    assert result.status == "failure" and result.exit_code == 1
    assert any("could not be corrected" in failure for failure in result.failures)
    assert result["maps/friction/eta"].tolist() == [0.45, 0.5, 0.55]
    assert result["maps/friction/stable_count"].shape == (3, 41)


def test_a_fit_from_a_dict_of_targets_over_threads():
    targets = {
        "parameter": [{"name": "friction", "range": [0.3, 0.7]}],
        "target": [{"family": "mode1", "event": "stick to slip+", "quantity": "speed_rpm",
                    "value": 50.688697, "uncertainty": 0.01}],
        "fit": {"global": "multistart", "global_evaluations": 12, "local_starts": 2,
                "local_evaluations": 30},
    }
    lines = []
    result = rubcont.fit(rubcont.default_scene(), targets, threads=2, progress=lines.append)
    assert result.status == "success"
    assert result.attrs("fit")["global_method"] == "multistart"
    assert result.attrs("fit")["local_runs"] == 2
    assert abs(result["fit/values"][0] - 0.5) < 1e-5  # the default scene's own μ
    assert any("population of 12 evaluated" in line for line in lines)


def test_bad_arguments_raise_value_error():
    with pytest.raises(ValueError, match='"bogus": must be one of friction'):
        rubcont.map(A_A, parameter="bogus")
    with pytest.raises(ValueError, match="must be up, down or both"):
        rubcont.sweep(A_A, direction="sideways")
    with pytest.raises(rubcont.SceneError, match="analysis.stages"):
        rubcont.run(A_A, stages=["nonsense"])


def test_absurd_work_is_refused_unless_forced(tmp_path):
    huge = rubcont.load_scene(A_A).with_values({"analysis": {"sweep": {"up_range_rpm": [20.0, 1e9]}}})
    with pytest.raises(ValueError, match=r"analysis.sweep.up_range_rpm.*--force to run it anyway"):
        rubcont.sweep(huge, direction="up")
    with pytest.raises(ValueError, match=r"--force to run it anyway"):
        rubcont.lifetime(A_A, from_rpm=48.0, to_rpm=50.0, step_rpm=0.5, copies=100000, duration=100.0)
    # Forced, the sweep gets past the check to the next one: an output that cannot be written.
    (tmp_path / "taken").mkdir()
    with pytest.raises(rubcont.RubcontError, match=r"(?s)running it anyway \(--force\).*Is a directory"):
        rubcont.sweep(huge, direction="up", force=True, out=tmp_path / "taken")


def test_the_loop_gives_the_table_of_jumps_with_causes():
    window = rubcont.load_scene(A_A).with_values(
        {"analysis": {"sweep": {"up_range_rpm": [40.0, 64.0], "down_range_rpm": [40.0, 120.0],
                                "speed_step_rpm": 4.0, "dwell": 0.75}}})
    lines = []
    result = rubcont.loop(window, budget=0.4, threads=2, progress=lines.append)
    assert result.status == "success"
    corners = {key: [rubcont_text(v) for v in result[f"loop/corners/{key}"]]
               for key in ("direction", "kind", "cause", "level")}
    assert list(zip(corners["direction"], corners["kind"], corners["cause"], corners["level"])) == [
        ("up", "whirl_to_whip", "knee", "L1"), ("down", "whirl_to_whip", "Hopf", "L1"),
        ("down", "whip_to_whirl", "knee", "L1")]
    assert abs(result["loop/corners/speed_rpm"][1] - 67.04) < 0.01
    assert any("L1:" in line for line in lines)


def rubcont_text(value):
    return value.decode() if isinstance(value, bytes) else str(value)
