"""Markers in a recorded bag: stable ids, and nothing of an extinguished fire or a crashed UAV stays
drawn. The bag is written by the recording package from the world node's own marker and tf
conversion over the real World and Agents (in-process harness), then read back and replayed with
the Marker semantics (tests/marker_replay.py)."""

from __future__ import annotations

from types import SimpleNamespace

import fire_uav_recording as bag_io
import pytest
from fire_uav_agent.testing.harness import Harness, scenario_path
from fire_uav_common import topics
from fire_uav_common.constants import FireStatus, VehicleStatus
from fire_uav_common.scenario import load_scenario
from fire_world_sim import viz
from marker_replay import replay, stale_fire_markers

rclpy_msgs = pytest.importorskip("visualization_msgs.msg")
world_node = pytest.importorskip("fire_world_sim.world_node")
ros_messages = pytest.importorskip("fire_world_sim.ros_messages")
from rclpy.serialization import serialize_message  # noqa: E402


def _record(tmp_path, scenario: str, max_steps: int, **overrides):
    sc = load_scenario(scenario_path(scenario), overrides=overrides or None)
    h = Harness(sc)
    fake = SimpleNamespace(world=h.world, _marker_book=viz.MarkerBook())
    ts = bag_io.fleet_typestore()
    bag = tmp_path / "bag"
    with bag_io.BagWriter(bag) as w:
        conns = {
            spec.name: w.add_connection(spec.name, spec.type, typestore=ts)
            for spec in (topics.VIZ_WORLD_SPEC, topics.WORLD_TRUTH_SPEC, topics.TF_SPEC)
        }
        for _ in range(max_steps):
            r = h.step()
            if r.step % 5 == 0 or r.complete:  # /viz at 2 Hz of a 10 Hz control step, as the node
                w.write(
                    conns[topics.VIZ_WORLD],
                    r.stamp_ns,
                    serialize_message(world_node.WorldNode._markers(fake, r)),
                )
                w.write(conns[topics.TF], r.stamp_ns, serialize_message(ros_messages.tf_msg(r)))
            w.write(
                conns[topics.WORLD_TRUTH],
                r.stamp_ns,
                serialize_message(ros_messages.truth_msg(r)),
            )
            if r.complete:
                break
    return bag, r


def _read(bag, topic):
    with bag_io.open_bag(bag) as b:
        return list(b.messages([topic]))


def test_no_marker_of_an_extinguished_fire_remains_in_the_bag(tmp_path):
    bag, last = _record(tmp_path, "tiny_test", 2000)
    assert [f.status for f in last.fires] == [FireStatus.EXTINGUISHED]  # the fire did go out
    viz_msgs, truth = _read(bag, topics.VIZ_WORLD), _read(bag, topics.WORLD_TRUTH)
    frames = replay(viz_msgs)
    assert any(("fire", 0) in drawn for _, drawn in frames)  # it was drawn while it burned
    assert stale_fire_markers(viz_msgs, truth) == []
    _, end = frames[-1]
    assert not any(ns == "fire" for ns, _ in end)
    # stable ids: one arrow per UAV, id = uav id, in every frame
    for _, drawn in frames:
        assert sorted(i for ns, i in drawn if ns in ("uav", "crash")) == [0, 1]
    # the legend names every colour the world uses
    assert {d.marker.text for (ns, _), d in end.items() if ns == "legend"} == {t for _, t in viz.LEGEND}


def test_the_checker_sees_a_stale_fire(tmp_path):
    """Without DELETE (the old numbering by position) the same mission leaves the fire drawn."""
    bag, _ = _record(tmp_path, "tiny_test", 2000)
    viz_msgs, truth = _read(bag, topics.VIZ_WORLD), _read(bag, topics.WORLD_TRUTH)
    for _t, _ns, arr in viz_msgs:
        arr.markers = [m for m in arr.markers if m.action != 2]  # drop the DELETEs
    assert stale_fire_markers(viz_msgs, truth)


def test_tf_has_a_frame_per_uav_from_the_truth(tmp_path):
    bag, last = _record(tmp_path, "tiny_test", 60)
    tf = _read(bag, topics.TF)
    assert tf
    _, _, msg = tf[-1]
    frames = {t.child_frame_id: t for t in msg.transforms}
    assert set(frames) == {"uav_0", "uav_1"} and all(t.header.frame_id == "map" for t in frames.values())
    truth = _read(bag, topics.WORLD_TRUTH)
    by_stamp = {(m.header.stamp.sec, m.header.stamp.nanosec): m for _, _, m in truth}
    v = by_stamp[(msg.transforms[0].header.stamp.sec, msg.transforms[0].header.stamp.nanosec)].vehicles
    for veh in v:
        t = frames[f"uav_{veh.uav_id}"].transform
        assert (t.translation.x, t.translation.y, t.translation.z) == (veh.x_m, veh.y_m, veh.z_m)


def test_a_crashed_uav_loses_its_arrow():
    book = viz.MarkerBook()
    fly = SimpleNamespace(uav_id=3, status=VehicleStatus.AIRBORNE, x_m=0.0, y_m=0.0, z_m=50.0, yaw_rad=0.0)
    crashed = SimpleNamespace(**{**vars(fly), "status": VehicleStatus.CRASHED})
    first = book.frame(viz.world_markers([fly], [], [], draw_fires=True, legend_xy_m=(0, 0)))
    assert ("uav", 3) in {m.key for m in first}
    second = book.frame(viz.world_markers([crashed], [], [], draw_fires=True, legend_xy_m=(0, 0)))
    assert viz.MarkerSpec("uav", 3, action="delete") in second
    assert ("crash", 3) in {m.key for m in second if m.action == "add"}


def test_duplicate_marker_ids_are_an_error():
    with pytest.raises(ValueError, match="marker ids not unique"):
        viz.MarkerBook().frame([viz.MarkerSpec("uav", 1), viz.MarkerSpec("uav", 1)])
