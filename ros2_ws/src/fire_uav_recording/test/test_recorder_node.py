"""The recorder node's memory budget: a flood is dropped while it runs, nothing is at a stop; its
up-front subscriptions, ``/world/truth`` last; its ``uav_count`` bound (rclpy in this process, a
private ROS domain; no other process)."""

from __future__ import annotations

import pytest


@pytest.fixture
def recorder(tmp_path):
    """A ``RecorderNode`` writing ``tmp_path/bag`` with a 1 MiB budget, on its own ROS domain."""
    rclpy = pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain
    from fire_uav_recording.recorder_node import RecorderNode

    with claim_domain() as domain:
        ctx_args = ["--ros-args", "-p", f"output:={tmp_path / 'bag'}", "-p", "max_pending_mib:=1"]
        rclpy.init(args=ctx_args, domain_id=domain)
        node = None
        try:
            node = RecorderNode()
            yield node
        finally:
            if node is not None:
                node.close_bag()
                node.destroy_node()
            rclpy.try_shutdown()


def test_over_the_budget_a_running_recorder_drops_and_a_stopping_one_flushes(recorder, tmp_path):
    import fire_uav_recording as rec

    conn = recorder._writer.add_connection(
        "/fleet/state", "fire_uav_msgs/msg/UavState", typestore=recorder._typestore
    )
    blob = bytes(200 * 1024)  # 5 fill the 1 MiB budget, the 6th would pass it
    for _ in range(6):
        recorder._on_message(conn, blob)
    assert recorder.messages_written == 5 and recorder.messages_dropped == {"/fleet/state": 1}
    recorder._stopping = True  # as take_queued sets it
    for _ in range(6):
        recorder._on_message(conn, blob)
    assert recorder.messages_written == 11 and recorder.messages_dropped == {"/fleet/state": 1}
    recorder.close_bag()
    with rec.open_bag(tmp_path / "bag") as b:
        assert sum(c.msgcount for c in b.connections(["/fleet/state"])) == 11


def test_the_recorder_subscribes_to_the_fleet_up_front_world_truth_last(tmp_path, own_domain):
    import rclpy
    from fire_uav_common import topics
    from fire_uav_recording.recorder_node import RecorderNode, up_front_topics

    names = up_front_topics(3)
    assert names[-1] == "/world/truth" and names.count("/world/truth") == 1
    per_vehicle = [s.for_uav(k) for s in topics.ALL_TOPICS if s.per_uav for k in range(3)]
    assert sorted(names) == sorted([s.name for s in topics.ALL_TOPICS if not s.per_uav] + per_vehicle)
    args = ["-p", f"output:={tmp_path / 'bag'}", "-p", "uav_count:=3", "-p", "exclude:=['/viz/.*']"]
    rclpy.init(args=["--ros-args", *args], domain_id=own_domain)
    node = RecorderNode()
    try:
        wanted = [t for t in names if not t.startswith("/viz/")]
        assert "/uav_2/cmd" in wanted and "/uav_3/cmd" not in wanted
        assert list(node._follower.subscriptions) == wanted
        # the node's subscriptions in the order made (its /clock time source's first): /world/truth last
        assert [s.topic_name for s in node.subscriptions][-len(wanted) :] == wanted
        assert node._follower.announced == {} and node._writer.connections == []  # no publisher yet
    finally:
        node.close_bag()
        node.destroy_node()


def test_uav_count_above_the_uint8_ids_is_a_parameter_error(tmp_path, own_domain):
    import rclpy
    from fire_uav_recording.errors import ConfigError
    from fire_uav_recording.recorder_node import RecorderNode

    args = ["-p", f"output:={tmp_path / 'bag'}", "-p", "uav_count:=256"]
    rclpy.init(args=["--ros-args", *args], domain_id=own_domain)
    with pytest.raises(ConfigError, match=r"uav_count: must be <= 255 \(uint8 ids\), got 256"):
        RecorderNode()
    assert not (tmp_path / "bag").exists()
