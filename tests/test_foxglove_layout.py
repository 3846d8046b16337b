"""The shipped Foxglove layout names only topics the fleet publishes and fields their messages have."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from fire_uav_common import topics

ROOT = Path(__file__).resolve().parents[1]
LAYOUT = ROOT / "config/foxglove/mission_layout.json"


def _fields(ros_type: str) -> set[str]:
    pkg, _, name = ros_type.split("/")
    msg = pytest.importorskip(f"{pkg}.msg")
    return set(getattr(msg, name).get_fields_and_field_types())


def _spec(topic: str) -> topics.TopicSpec:
    return topics.topic_by_name(topic)  # KeyError: the layout names a topic nobody publishes


def test_layout_panels_and_topics():
    doc = json.loads(LAYOUT.read_text())
    panels = doc["configById"]
    kinds = {k.split("!")[0] for k in panels}
    assert {"3D", "Plot", "RawMessages"} <= kinds
    three_d = panels["3D!mission"]
    assert three_d["followTf"] == "map"
    for t in three_d["topics"]:
        assert _spec(t).type in ("visualization_msgs/msg/MarkerArray", "nav_msgs/msg/OccupancyGrid")
    assert {"/viz/world", "/viz/fire_grid"} <= set(three_d["topics"])
    for key, cfg in panels.items():
        paths = [p["value"] for p in cfg.get("paths", [])] + (
            [cfg["topicPath"]] if "topicPath" in cfg else []
        )
        for path in paths:
            m = re.fullmatch(r"(/[\w/]+)(\{[^}]*\})?((?:\.\w+(?:\[:\])?)*)", path)
            assert m, f"{key}: unparsed message path {path}"
            spec = _spec(m.group(1))
            field = m.group(3).split(".")[1:] if m.group(3) else []
            if field:
                assert field[0].replace("[:]", "") in _fields(spec.type), f"{key}: {path}"
    # every panel in the configuration is placed in the layout tree
    placed = set(re.findall(r'"([\w]+![\w]+)"', json.dumps(doc["layout"])))
    assert placed == set(panels)
