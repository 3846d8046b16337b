"""``run_mission --set`` leaves the run's scenario in the run folder; its relative file paths
(a landscape, a wind grid) must still name the files beside the original scenario."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml
from fire_mission.runner import write_scenario
from fire_uav_common.scenario import ScenarioError, load_scenario

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "ros2_ws/src/fire_world_sim/scenarios/worcester_vt.yaml"


def _own_landscape_scenario(folder: Path) -> Path:
    """worcester_vt as a user keeps it: the landscape in a folder beside the scenario file."""
    shutil.copytree(ROOT / "data/landscapes/worcester_vt", folder / "my_ground")
    raw = yaml.safe_load(SHIPPED.read_text())
    raw["fires"]["raster"]["landscape"]["source"] = "my_ground"  # relative to the scenario file
    src = folder / "mine.yaml"
    src.write_text(yaml.safe_dump(raw, sort_keys=False))
    return src


def test_the_copy_in_the_run_folder_reads_the_landscape_beside_the_original(tmp_path: Path) -> None:
    src = _own_landscape_scenario(tmp_path / "user")
    run = tmp_path / "runs/r1"
    run.mkdir(parents=True)
    dst = write_scenario(src, {"seed": 4}, run / "scenario.yaml")
    copy, original = load_scenario(dst), load_scenario(src)
    assert copy.seed == 4
    assert copy.fires.raster.landscape.source == original.fires.raster.landscape.source
    assert Path(copy.fires.raster.landscape.source).parent == tmp_path / "user"


def test_a_given_paths_relative_to_is_kept(tmp_path: Path) -> None:
    src = _own_landscape_scenario(tmp_path / "user")
    raw = yaml.safe_load(src.read_text())
    raw["paths_relative_to"] = str(tmp_path / "user")
    moved = tmp_path / "elsewhere/moved.yaml"
    moved.parent.mkdir()
    moved.write_text(yaml.safe_dump(raw))
    assert Path(load_scenario(moved).fires.raster.landscape.source).parent == tmp_path / "user"


@pytest.mark.parametrize(
    ("value", "message"),
    [("relative/dir", "paths_relative_to: must be an absolute path"), ("/no/such/dir", "is not a directory")],
)
def test_a_bad_paths_relative_to_is_named(tmp_path: Path, value: str, message: str) -> None:
    raw = yaml.safe_load(SHIPPED.read_text())
    raw["paths_relative_to"] = value
    f = tmp_path / "bad.yaml"
    f.write_text(yaml.safe_dump(raw))
    with pytest.raises(ScenarioError, match=message):
        load_scenario(f)


def test_a_study_mission_on_a_worker_reads_the_landscape_beside_the_study_scenario(tmp_path: Path) -> None:
    """A study sends a scenario file to its workers as text, written there into a temporary
    folder: with the client's folder (``scenario_dir``) its relative landscape path still works."""
    from fire_study.mission import run_mission

    src = _own_landscape_scenario(tmp_path / "user")
    row = run_mission(
        src.name, uavs=1, seed=1, overrides=(("timing.max_duration_s", 1.0),),
        scenario_yaml=src.read_text(), scenario_dir=str(src.parent),
    )  # fmt: skip
    assert row["mission_time_s"] == pytest.approx(1.0, abs=0.2)
