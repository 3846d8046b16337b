"""The world and agent nodes' ``main`` (in this process, on a private ROS domain): a parameter
value rclpy refuses against its declared type is one error line naming it and exit status 2, the
project's rule for every bad input (before: rclpy's InvalidParameterTypeException as a traceback,
status 1)."""

from __future__ import annotations

import importlib

import pytest

pytest.importorskip("rclpy")


@pytest.fixture
def own_domain(monkeypatch):
    rclpy = pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain

    with claim_domain() as domain:
        monkeypatch.setenv("ROS_DOMAIN_ID", str(domain))  # main() inits rclpy's context from it
        try:
            yield domain
        finally:
            rclpy.try_shutdown()


@pytest.mark.parametrize(
    ("module", "param"),
    [
        ("fire_uav_agent.agent_node", "uav_id:=abc"),
        ("fire_world_sim.world_node", "seed:=abc"),
        ("fire_world_sim.world_node", "uav_count:=2.5"),
    ],
)
def test_a_value_of_the_wrong_type_is_one_line_and_status_2(module, param, own_domain, capfd):
    rc = importlib.import_module(module).main(["--ros-args", "-p", param])
    err = capfd.readouterr().err
    assert rc == 2, err
    assert "Traceback" not in err, err
    lines = [ln for ln in err.splitlines() if "[ERROR]" in ln]
    name = param.split(":=")[0]
    assert len(lines) == 1 and f"parameter '{name}'" in lines[0], err
