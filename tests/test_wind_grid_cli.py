"""A bad wind grid in a scenario stops the in-process runner with one line naming the file and
the field, exit status 2, before any mission starts (the loader's check: test_scenario_wind_grid)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "ros2_ws/src/fire_world_sim/scenarios/worcester_vt.yaml"


def test_a_direction_outside_0_360_is_one_line_and_exit_2(tmp_path: Path) -> None:
    header = "ncols 2\nnrows 2\nxllcorner 1847000\nyllcorner 2602000\ncellsize 3000\nNODATA_value -9999\n"
    (tmp_path / "w_vel.asc").write_text(header + "4 4\n4 4\n")
    (tmp_path / "w_ang.asc").write_text(header + "270 270\n270 400\n")
    prj = (ROOT / "data/wind/worcester_vt/worcester_vt_270_8_120m_vel.prj").read_text()
    for name in ("w_vel.prj", "w_ang.prj"):
        (tmp_path / name).write_text(prj)
    d = yaml.safe_load(SCENARIO.read_text())
    d["fires"]["raster"]["wind"] = [{"start_s": -600, "grid": {"vel": "w_vel.asc", "ang": "w_ang.asc"}}]
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(d))
    r = subprocess.run(
        [sys.executable, "-m", "fire_mission.inprocess", str(tmp_path / "s.yaml"), "--uavs", "1"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    assert "s.yaml: fires.raster.wind[0].grid:" in lines[0] and "w_ang.asc: direction 400 deg" in lines[0], (
        lines[0]
    )
