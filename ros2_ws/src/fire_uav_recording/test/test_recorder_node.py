"""The recorder node's memory budget: a flood is dropped while it runs, nothing is at a stop
(rclpy in this process, a private ROS domain; no other process)."""

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
