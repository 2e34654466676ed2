"""scripts/compare_results.py: a scene key added later at its older behaviour is not a difference."""
import importlib.util
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("compare_results", ROOT / "scripts" / "compare_results.py")
compare_results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_results)

OLD_SCENE = '[analysis.orbits]\nbranch_points = "follow"\n\n[analysis.loop]\nbudget = 300.0\n'


def written(path, scene):
    with h5py.File(path, "w") as f:
        f.attrs["scene_toml"] = scene
        f["x"] = [1.0, 2.0]
    return path


def differences(tmp_path, old_scene, new_scene):
    old = written(tmp_path / "old.h5", old_scene)
    new = written(tmp_path / "new.h5", new_scene)
    return compare_results.compare(old, new, 1e-9, 1e-12)


def with_line(line):
    return OLD_SCENE.replace('"follow"\n', f'"follow"\n{line}\n')


def test_an_added_key_at_its_older_behaviour_is_no_difference(tmp_path):
    assert differences(tmp_path, OLD_SCENE, with_line('at_grazing = "continue"')) == []


def test_an_added_key_at_another_value_is_a_difference(tmp_path):
    assert differences(tmp_path, OLD_SCENE, with_line('at_grazing = "stop"')) == [
        "/@scene_toml: text differs"]


def test_a_key_the_new_scene_lost_is_a_difference(tmp_path):
    assert differences(tmp_path, with_line('at_grazing = "continue"'), OLD_SCENE) == [
        "/@scene_toml: text differs"]


def test_other_lines_are_still_compared(tmp_path):
    changed = with_line('at_grazing = "continue"').replace("300.0", "600.0")
    assert differences(tmp_path, OLD_SCENE, changed) == ["/@scene_toml: text differs"]


def test_the_loop_budget_default_of_before_its_unit_changed_is_today_s(tmp_path):
    today = OLD_SCENE.replace("budget = 300.0", "budget = 4.0")
    assert differences(tmp_path, OLD_SCENE, today) == []
    assert differences(tmp_path, OLD_SCENE, today.replace("4.0", "5.0")) == ["/@scene_toml: text differs"]
