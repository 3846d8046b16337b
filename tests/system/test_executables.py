"""Each executable resolves through the ament index exactly as ``ros2 run`` resolves it."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from fire_mission.procs import MissionError, executable, ros_run_argv

pytestmark = pytest.mark.system

EXECUTABLES = [
    ("fire_world_sim", "world_node"),
    ("fire_uav_recording", "recorder"),
    ("fire_uav_recording", "replay"),
    ("fire_uav_agent", "uav_agent"),
    ("fire_perimeter_monitor", "perimeter_viewer"),
]


@pytest.mark.parametrize(("package", "exe"), EXECUTABLES)
def test_executable_resolves_through_ament_index(ros_env, package, exe):
    path = executable(package, exe)
    assert path.parts[-3:] == ("lib", package, exe)
    prefix = path.parents[2]
    assert (prefix / "share/ament_index/resource_index/packages" / package).is_file()
    # a colcon-generated console script for this package
    head = path.read_text().splitlines()[0]
    assert head.startswith("#!") and "python" in head, f"{path} is not a Python console script: {head}"
    argv = ros_run_argv(package, exe, ["-p", "x:=1"])
    assert argv[-3:] == ["--ros-args", "-p", "x:=1"]


def test_unknown_package_and_executable_are_named(ros_env):
    with pytest.raises(MissionError, match="package 'no_such_pkg' not found"):
        executable("no_such_pkg", "x")
    with pytest.raises(MissionError, match="has no executable 'nope'"):
        executable("fire_uav_agent", "nope")


def test_launch_agent_uses_the_same_executable(ros_env, tmp_path):
    """scripts/launch_agent --print shows the command it would run: ros2 run or the path."""
    root = Path(__file__).resolve().parents[2]
    env = dict(ros_env, FIRE_UAV_NO_ROS2_CLI="1")
    out = (
        subprocess.run(
            [str(root / "scripts/launch_agent"), "--print", "3", "-p", "seed:=7"],
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            check=True,
        )
        .stdout.strip()
        .splitlines()[-1]
    )
    assert out.split()[0] == str(executable("fire_uav_agent", "uav_agent"))
    assert "uav_id:=3" in out and "seed:=7" in out and "__ns:=/uav_3" in out
    assert os.access(out.split()[0], os.X_OK)
