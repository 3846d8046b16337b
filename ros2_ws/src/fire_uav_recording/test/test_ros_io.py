"""``RawTopicFollower``'s raw subscriptions are deep enough and drained, and ``take_queued`` hands
over what is still queued at a stop, even after the context is shut down (rclpy in this process,
a private ROS domain; no other process)."""

from __future__ import annotations

import time

import pytest

BURST = 300  # messages: more than one drained callback takes (1 + topics.DRAIN_LIMIT)


@pytest.fixture
def ros_context():
    """A private rclpy context on a ROS domain no other test or run on this host holds."""
    rclpy = pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain

    with claim_domain() as domain:
        ctx = rclpy.Context()
        rclpy.init(context=ctx, domain_id=domain)
        try:
            yield ctx
        finally:
            rclpy.try_shutdown(context=ctx)


@pytest.fixture
def follower(ros_context):
    """``(follower, publish, got)``: a follower of ``/fleet/state`` on one node, matched with a
    publisher on another; ``publish(n)`` sends ``n`` raw messages (``sequence`` counting on) and
    waits until the follower's reader has them all; ``got`` is the bytes its handler was given."""
    rclpy = pytest.importorskip("rclpy")
    import fire_uav_recording as rec
    from fire_uav_common import topics
    from fire_uav_msgs.msg import UavState
    from fire_uav_recording.ros_io import RawTopicFollower
    from rclpy.duration import Duration
    from rclpy.serialization import serialize_message

    sender = rclpy.create_node("sender", context=ros_context)
    recorder = rclpy.create_node("recorder", context=ros_context)
    pub = topics.publisher(sender, topics.FLEET_STATE_SPEC)
    got: list[bytes] = []
    f = RawTopicFollower(recorder, lambda t: t == "/fleet/state", rec.fleet_typestore(), lambda t: got.append)
    deadline = time.monotonic() + 20.0
    while "/fleet/state" not in f.subscriptions or pub.get_subscription_count() < 1:
        assert time.monotonic() < deadline, "the follower did not find /fleet/state within 20 s"
        f.discover()
        time.sleep(0.05)
    sent = [0]

    def publish(n: int) -> None:
        for _ in range(n):
            pub.publish(serialize_message(UavState(sequence=sent[0])))
            sent[0] += 1
        assert pub.wait_for_all_acked(Duration(seconds=20))  # in the follower's reader history

    try:
        yield f, publish, got
    finally:
        sender.destroy_node()
        recorder.destroy_node()


def sequences(got: list[bytes]) -> list[int]:
    from fire_uav_msgs.msg import UavState
    from rclpy.serialization import deserialize_message

    assert all(isinstance(b, bytes) for b in got)  # raw: the CDR bytes, never deserialized
    return [deserialize_message(b, UavState).sequence for b in got]


def test_tf_is_followed_deep_enough_for_a_20_uav_hold_up():
    pytest.importorskip("rclpy")
    from fire_uav_common import topics
    from fire_uav_recording.ros_io import MIN_DEPTH, spec_of, subscription_qos
    from rclpy.qos import HistoryPolicy

    qos = subscription_qos([topics.TF_SPEC.qos()], spec_of("/tf"))
    assert qos.history == HistoryPolicy.KEEP_LAST and qos.depth == MIN_DEPTH
    assert MIN_DEPTH >= 21 * 15 * 3  # 21 publishers, ~15 steps/s: 3 s of /tf at 20 UAVs
    assert subscription_qos([], spec_of("/fleet/state")).depth == topics.FLEET_STATE_SPEC.qos().depth


def test_a_raw_subscription_is_drained(follower, ros_context):
    from fire_uav_common import topics
    from fire_uav_common.ros_io import LeanExecutor

    f, publish, got = follower
    publish(BURST)
    executor = LeanExecutor(context=ros_context)
    executor.add_node(f._node)
    try:
        executor.spin_once(timeout_sec=5.0)  # one wake: one callback takes up to its limit
    finally:
        executor.shutdown()
    assert sequences(got) == list(range(1 + topics.DRAIN_LIMIT))


def test_take_queued_hands_over_the_whole_queue_without_an_executor(follower):
    f, publish, got = follower
    publish(BURST)
    taken, empty = f.take_queued(cap_wall_s=10.0)
    assert taken == {"/fleet/state": BURST} and empty
    assert sequences(got) == list(range(BURST))
    assert f.take_queued(cap_wall_s=10.0) == ({}, True)  # nothing left: ends after the quiet period


def test_take_queued_works_after_the_context_is_shut_down(follower, ros_context):
    import rclpy

    f, publish, got = follower
    publish(BURST)
    rclpy.shutdown(context=ros_context)  # as rclpy's own signal handlers do at a SIGINT
    assert f.take_queued(cap_wall_s=10.0) == ({"/fleet/state": BURST}, True)
    assert sequences(got) == list(range(BURST))


def test_take_queued_is_cut_short_by_its_cap_and_by_cancelled(follower):
    f, publish, got = follower
    publish(BURST)
    assert f.take_queued(cap_wall_s=0.0) == ({}, False)
    calls = []

    def cancelled() -> bool:
        calls.append(1)
        return len(calls) > 10

    assert f.take_queued(cap_wall_s=10.0, cancelled=cancelled) == ({"/fleet/state": 10}, False)
    assert f.take_queued(cap_wall_s=10.0) == ({"/fleet/state": BURST - 10}, True)
    assert sequences(got) == list(range(BURST))
