"""Shared fixtures: a private ROS_DOMAIN_ID per test and a process group that always ends.

System tests (marked ``system``) need the environment of ``scripts/env.sh``; ``scripts/test``
provides it. Every process a test starts is ended by PID (SIGINT, then SIGKILL) in the
fixture's teardown, even when the test fails; its log is attached to the failure report.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
from fire_mission.procs import ProcessGroup, claim_domain


def _need_ros_env() -> None:
    if "AMENT_PREFIX_PATH" not in os.environ or "fire_uav_msgs" not in os.environ.get(
        "AMENT_PREFIX_PATH", ""
    ):
        pytest.fail(
            "system test needs the ROS environment: run scripts/test, or `source scripts/env.sh` first",
            pytrace=False,
        )


@pytest.fixture
def ros_env(tmp_path: Path):
    """Environment for child ROS processes: a ROS domain claimed for this test alone on the host
    (``FIRE_UAV_DOMAIN_ID`` tells a runner started with it that the claim is held), logs under
    tmp_path."""
    _need_ros_env()
    with claim_domain() as domain:
        env = dict(os.environ)
        env["ROS_DOMAIN_ID"] = env["FIRE_UAV_DOMAIN_ID"] = str(domain)
        env["ROS_LOG_DIR"] = str(tmp_path / "ros_log")
        env["PYTHONUNBUFFERED"] = "1"
        env.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        yield env


@pytest.fixture
def procs(tmp_path: Path, ros_env: dict[str, str], request: pytest.FixtureRequest):
    """A :class:`ProcessGroup` on the test's private domain; ended in teardown, logs kept."""
    group = ProcessGroup(tmp_path / "logs", ros_env, grace_s=5.0)
    try:
        yield group
    finally:
        group.stop_all()
        leftovers = [pid for pid in group.pids() if _pid_alive(pid)]
        rep = getattr(request.node, "rep_call", None)
        if rep is not None and rep.failed:
            for name in group.children:
                sys.stderr.write(f"\n----- log of {name} (last 40 lines) -----\n{group.tail(name, 40)}\n")
        assert not leftovers, f"processes outlived the test: {leftovers}"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # a zombie is not alive; the group reaps its children, so this is a real process
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except OSError:
        return False


@pytest.hookimpl(tryfirst=True, hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    setattr(item, "rep_" + rep.when, rep)
