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
    assert {"3D", "Plot", "RawMessages", "Map"} <= kinds
    three_d = panels["3D!mission"]
    assert three_d["followTf"] == "map"
    for t in three_d["topics"]:
        assert _spec(t).type in ("visualization_msgs/msg/MarkerArray", "nav_msgs/msg/OccupancyGrid")
    assert {"/viz/world", "/viz/fire_grid"} <= set(three_d["topics"])
    for key, cfg in panels.items():
        if key.startswith("Map!"):
            continue  # its topics are the geographic ones (test_map_panel_shows_what_the_bridge_serves)
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


def test_map_panel_shows_what_the_bridge_serves() -> None:
    """The Map panel names exactly the topics the bridge serves for a mission on a landscape: a
    NavSatFix per UAV (as many as the 3D panel's agents) made from a real ``/world/truth`` of
    worcester_vt, and the burned area's GeoJSON; it follows UAV 0 and hides none of them."""
    import math

    import fire_uav_recording as rec
    from fire_uav_recording.geo import FIRE_AREA_TOPIC, GeoView, geo_frame_of_scenario_file

    doc = json.loads(LAYOUT.read_text())
    cfg = doc["configById"]["Map!geo"]
    assert cfg["layer"] in ("map", "satellite", "custom")
    agents = [
        t for t in doc["configById"]["3D!mission"]["topics"] if t.endswith("/viz") and t.startswith("/uav_")
    ]
    frame = geo_frame_of_scenario_file(ROOT / "ros2_ws/src/fire_world_sim/scenarios/worcester_vt.yaml")
    assert frame is not None
    ts = rec.fleet_typestore()
    T = ts.types
    vehicles = [
        T["fire_uav_msgs/msg/VehicleTruth"](
            uav_id=k, status=1, x_m=100.0 * k, y_m=500.0, z_m=400.0, yaw_rad=0.0, v_lin_mps=0.0, v_z_mps=0.0,
            omega_z_radps=0.0, water_kg=0.0, commands_clamped=0, commands_missed=0,
        )
        for k in range(len(agents))
    ]  # fmt: skip
    truth = T["fire_uav_msgs/msg/WorldTruth"](
        header=T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](sec=1, nanosec=0), frame_id="map"),
        step=1, min_separation_m=math.inf, collisions=0, vehicles=vehicles, fires=[],
    )  # fmt: skip
    served = {
        name
        for name, _ in GeoView(ts, frame).on_truth(
            bytes(ts.serialize_cdr(truth, "fire_uav_msgs/msg/WorldTruth"))
        )
    }
    served.add(FIRE_AREA_TOPIC)
    assert len(served) == len(agents) + 1
    assert set(cfg["topicColors"]) == served
    assert cfg["followTopic"] in served and cfg["followTopic"].startswith("/uav_0/")
    assert not set(cfg["disabledTopics"]) & served
    assert all(re.fullmatch(r"#[0-9a-f]{6}", c) for c in cfg["topicColors"].values())
