"""The agent's parameters: declared in one place, an unknown name refused with a one-line error."""

from __future__ import annotations

import pytest

pytest.importorskip("rclpy")

from fire_uav_agent.agent_params import declare_agent_parameters, unknown_parameters
from fire_uav_agent.errors import AgentError, ConfigError
from fire_uav_agent.testing.harness import scenario_path


def test_unknown_names_are_those_not_declared() -> None:
    known = [name for name, _, _ in declare_agent_parameters()]
    given = [
        "uav_id",
        "monitor_circling",
        "use_sim_time",
        "qos_overrides./fleet/state.publisher.depth",
        "sead",
    ]
    assert unknown_parameters(given, known) == ["monitor_circling", "sead"]
    assert unknown_parameters(known, known) == []


def test_config_error_is_an_agent_error_and_a_value_error() -> None:
    assert issubclass(ConfigError, AgentError) and issubclass(ConfigError, ValueError)


def _node_args(*params: str) -> list[str]:
    args = [
        "--ros-args",
        "-p",
        f"scenario_file:={scenario_path('tiny_test')}",
        "-p",
        "uav_id:=0",
        "-p",
        "auth:=false",
    ]
    for p in params:
        args += ["-p", p]
    return args


def test_the_node_refuses_a_misspelt_parameter() -> None:
    """``monitor_circling`` is an AgentConfig field, not a parameter (that is ``monitor_planner``):
    given to the node it used to be ignored, and the run flew the importance planner."""
    import rclpy
    from fire_uav_agent.agent_node import UavAgentNode

    ctx = rclpy.Context()
    rclpy.init(context=ctx)
    try:
        with pytest.raises(
            ConfigError, match=r"^unknown parameter monitor_circling given to uav_agent \(known: "
        ):
            UavAgentNode(context=ctx, cli_args=_node_args("monitor_circling:=true"))
        node = UavAgentNode(context=ctx, cli_args=_node_args("monitor_planner:=circling"))
        try:
            assert node.cfg.monitor_circling and node.config.mode == "lockstep" and node.auth is None
            assert node.get_parameter("use_sim_time").value is True
        finally:
            node.destroy_node()
    finally:
        rclpy.try_shutdown(context=ctx)


def test_main_exits_2_with_one_line_naming_the_parameter(capfd) -> None:
    from fire_uav_agent.agent_node import main

    assert main(_node_args("monitor_circling:=true")) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown parameter monitor_circling given to uav_agent" in err[0], err


def _values(**over) -> dict:
    v = {name: default for name, default, _ in declare_agent_parameters()}
    v.update(scenario_file=str(scenario_path("tiny_test")), uav_id=1, auth=False)
    v.update(over)
    return v


def test_node_config_reads_the_defaults_and_the_namespace() -> None:
    from fire_uav_agent.agent_params import node_config

    cfg = node_config(_values(uav_id=-1), "/uav_1")
    assert cfg.uav_id == 1 and cfg.mode == "lockstep" and cfg.authenticator is None
    assert cfg.search.mode == "off" and cfg.offline_schedule == () and not cfg.agent.monitor_circling


@pytest.mark.parametrize(
    ("over", "namespace", "message"),
    [
        ({"uav_id": -1}, "/", r"^parameter uav_id not set and namespace '/' is not /uav_<id>$"),
        ({"uav_id": 5}, "/uav_1", r"^uav_id must be in 0..uav_count-1, got uav_id=5, uav_count=2$"),
        ({"mode": "fast"}, "/uav_1", r"^parameter mode must be 'lockstep' or 'realtime', got 'fast'$"),
        ({"scenario_file": ""}, "/uav_1", r"^parameter scenario_file is required"),
        (
            {"monitor_planner": "circle"},
            "/uav_1",
            r"^parameter monitor_planner must be 'importance' or 'circling'",
        ),
        ({"outage_from": [0, 1], "outage_to": [1]}, "/uav_1", r"equal lengths, got 2/1/1/1$"),
        ({"prior_fires": [1.0, 2.0]}, "/uav_1", r"^parameter prior_fires: 2 numbers, expected"),
        ({"offline_schedule": "x@1"}, "/uav_1", r"^parameter offline_schedule: "),
        ({"auth": True}, "/uav_1", r"^parameter fleet_key is required when auth is true"),
        ({"auth": True, "fleet_key": "abc"}, "/uav_1", r"^parameter fleet_key: "),
        (
            {"search_mode": "grid"},
            "/uav_1",
            r"^parameter search_mode must be auto, bo, random or off, got 'grid'$",
        ),
    ],
)
def test_node_config_names_the_bad_parameter(over: dict, namespace: str, message: str) -> None:
    from fire_uav_agent.agent_params import node_config

    with pytest.raises(ConfigError, match=message):
        node_config(_values(**over), namespace)
