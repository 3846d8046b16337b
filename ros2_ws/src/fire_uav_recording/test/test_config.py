"""The default YAML files list every declared parameter, and the recorder's topics default is the specs'."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml
from fire_uav_common.topics import recorded_patterns

PKG = Path(__file__).resolve().parents[1]


def declared(module: str) -> set[str]:
    text = (PKG / "fire_uav_recording" / module).read_text()
    return set(re.findall(r'declare_parameter\(\s*"(\w+)"', text))


@pytest.mark.parametrize(
    ("module", "config"),
    [
        ("recorder_node.py", "recorder.yaml"),
        ("replay_node.py", "replay.yaml"),
        ("foxglove_bridge_node.py", "foxglove_bridge.yaml"),
    ],
)
def test_config_lists_every_parameter(module: str, config: str) -> None:
    params = yaml.safe_load((PKG / "config" / config).read_text())["/**"]["ros__parameters"]
    names = declared(module)
    assert names, module
    assert names <= set(params), f"{config} misses {sorted(names - set(params))}"
    assert set(params) - names <= {"use_sim_time"}, f"{config} has unknown {sorted(set(params) - names)}"


@pytest.mark.parametrize("config", ["recorder.yaml", "foxglove_bridge.yaml"])
def test_default_topics_are_the_specs(config: str) -> None:
    params = yaml.safe_load((PKG / "config" / config).read_text())["/**"]["ros__parameters"]
    assert tuple(params["topics"]) == recorded_patterns()
    for p in params["topics"]:
        re.compile(p)
