"""``RawTopicFollower``'s raw subscriptions are deep enough and drained, ``take_queued`` hands
over what is still queued at a stop (waiting on the executor for an expected message), even
after the context is shut down, and the topics it follows up front keep a publisher's first
messages, are announced once with the publishers' QoS and warn of publishers they cannot match
(rclpy in this process, a private ROS domain; no other process)."""

from __future__ import annotations

import time

import pytest

BURST = 300  # messages: more than one drained callback takes (1 + topics.DRAIN_LIMIT)


@pytest.fixture
def ros_context():
    """A private rclpy context on a ROS domain no other test or run on this host holds."""
    pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain
    from fire_uav_common.ros_io import private_context

    with claim_domain() as domain, private_context(domain) as ctx:
        yield ctx


@pytest.fixture
def follower(ros_context):
    """``(follower, publish, got)``: a follower of ``/fleet/state`` on one node, matched with a
    publisher on another; ``publish(n)`` sends ``n`` raw messages (``sequence`` counting on) and
    waits until the follower's reader has them all; ``got`` is the bytes its handler was given."""
    rclpy = pytest.importorskip("rclpy")
    import fire_uav_recording as rec
    from fire_uav_common import topics
    from fire_uav_msgs.msg import UavState
    from fire_uav_recording.raw_topics import RawTopicFollower
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
    from fire_uav_recording.raw_topics import MIN_DEPTH, spec_of, subscription_qos
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


@pytest.fixture
def upfront(ros_context):
    """``(follower, sender, announced)``: a follower (of the fleet's topics but ``/viz/*``) on
    node ``recorder`` that has not polled the graph yet, a node ``sender`` in the same context for publishers, and the topics its
    ``on_topic`` was given, in order; ``follower.got[topic]`` is the bytes each handler took."""
    rclpy = pytest.importorskip("rclpy")
    import fire_uav_recording as rec
    from fire_uav_recording.raw_topics import RawTopicFollower, spec_of

    sender = rclpy.create_node("sender", context=ros_context)
    recorder = rclpy.create_node("recorder", context=ros_context)
    announced = []
    got: dict[str, list[bytes]] = {}

    def on_topic(topic):
        announced.append(topic)
        return got.setdefault(topic.name, []).append

    def wants(topic: str) -> bool:  # the fleet's topics (not /rosout), but /viz/*
        return spec_of(topic) is not None and not topic.startswith("/viz/")

    f = RawTopicFollower(recorder, wants, rec.fleet_typestore(), on_topic)
    f.got = got
    try:
        yield f, sender, announced
    finally:
        sender.destroy_node()
        recorder.destroy_node()


def _until(what, timeout_s: float = 20.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not what():
        assert time.monotonic() < deadline, "not within 20 s"
        time.sleep(0.02)


def test_follow_subscribes_wanted_fleet_names_only_with_the_spec_qos(upfront):
    from fire_uav_common import topics
    from fire_uav_recording.raw_topics import MIN_DEPTH, fleet_topic_names
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy

    f, _, announced = upfront
    names = fleet_topic_names(2)
    assert names[:3] == ["/clock", "/uav_0/sensors", "/uav_1/sensors"] and "/world/truth" in names
    assert len(names) == len(topics.ALL_TOPICS) + 4  # sensors, cmd, payload, viz for a second vehicle
    made = f.follow(["/foreign/topic", *names, "/uav_0/cmd"])  # a foreign name: left to discovery
    assert made == len(names) - 3  # /viz/world, /viz/fire_grid, /viz/perimeter are not wanted
    assert list(f.subscriptions) == [t for t in names if not t.startswith("/viz/")]  # in that order
    assert f.follow(names) == 0 and announced == []  # nothing announced before a publisher or message
    events = f.subscriptions["/fleet/events"].qos_profile
    assert events.durability == DurabilityPolicy.TRANSIENT_LOCAL and events.depth == 1000
    viz = f.subscriptions["/uav_1/viz"].qos_profile
    assert viz.reliability == ReliabilityPolicy.BEST_EFFORT and viz.depth == MIN_DEPTH
    assert f.subscriptions["/fleet/state"].qos_profile.depth == topics.FLEET_STATE_SPEC.qos().depth


def test_follow_keeps_the_messages_a_publisher_sends_before_the_graph_is_polled(upfront):
    from fire_uav_common import topics
    from fire_uav_msgs.msg import UavState
    from rclpy.duration import Duration
    from rclpy.qos import HistoryPolicy
    from rclpy.serialization import serialize_message

    f, sender, announced = upfront
    f.follow(["/fleet/state"])
    pub = topics.publisher(sender, topics.FLEET_STATE_SPEC)
    for k in range(BURST):  # from its first moment, no wait for a match
        pub.publish(serialize_message(UavState(sequence=k)))
    assert pub.wait_for_all_acked(Duration(seconds=20))
    assert f.take_queued(cap_wall_s=10.0) == ({"/fleet/state": BURST}, True)  # no discover() at all
    assert sequences(f.got["/fleet/state"]) == list(range(BURST))
    (topic,) = announced  # at its first message, with the publisher the graph shows
    assert topic.name == "/fleet/state" and topic.spec is topics.FLEET_STATE_SPEC
    assert [q.history for q in topic.offered] == [HistoryPolicy.UNKNOWN]  # the graph's form
    assert f.announced == {"/fleet/state": topic}
    f.discover()
    assert len(announced) == 1  # once


def test_follow_announces_at_discovery_a_topic_with_a_publisher_and_no_message(upfront):
    from fire_uav_common import topics

    f, sender, announced = upfront
    f.follow(["/fleet/front", "/fleet/fires"])
    topics.publisher(sender, topics.FLEET_FRONT_SPEC)

    def polled() -> bool:
        f.discover()
        return bool(announced)

    _until(polled)
    assert [t.name for t in announced] == ["/fleet/front"]  # /fleet/fires: nobody publishes, never
    assert f.got == {"/fleet/front": []}
    assert [q.reliability for q in announced[0].offered] == [topics.FLEET_FRONT_SPEC.qos().reliability]


def test_follow_warns_of_a_publisher_it_cannot_match(upfront, ros_context, monkeypatch):
    import rclpy
    from fire_uav_common import topics
    from fire_uav_msgs.msg import PerimeterMap
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    f, sender, announced = upfront
    warned: list[str] = []

    class Logger:
        def info(self, text: str) -> None:
            pass

        def warning(self, text: str) -> None:
            warned.append(text)

    monkeypatch.setattr(f, "_logger", Logger)
    f.follow(["/fleet/perimeter", "/uav_0/cmd"])
    best_effort = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
    sender.create_publisher(PerimeterMap, "/fleet/perimeter", best_effort)  # on a reliable fleet topic
    topics.publisher(sender, topics.FLEET_PERIMETER_SPEC)
    # another type under a fleet name (from another participant: one cannot have two types on a topic)
    other = rclpy.Context()
    rclpy.init(context=other, domain_id=ros_context.get_domain_id())
    try:
        foreign = rclpy.create_node("foreign", context=other)
        foreign.create_publisher(PerimeterMap, "/uav_0/cmd", 10)

        def polled() -> bool:
            f.discover()
            return len(warned) == 2

        _until(polled)
    finally:
        rclpy.try_shutdown(context=other)
    (perimeter,) = [w for w in warned if "/fleet/perimeter" in w]
    assert "/sender (fire_uav_msgs/msg/PerimeterMap, best_effort, volatile)" in perimeter
    (cmd,) = [w for w in warned if "/uav_0/cmd" in w]
    assert "['fire_uav_msgs/msg/PerimeterMap']" in cmd and "geometry_msgs/msg/TwistStamped" in cmd
    assert [t.name for t in announced] == ["/fleet/perimeter"]  # /uav_0/cmd: no publisher of its type
    f.discover()
    assert len(warned) == 2  # once each


def test_take_queued_announces_a_followed_topic_after_the_context_is_shut_down(upfront, ros_context):
    import rclpy
    from fire_uav_common import topics
    from fire_uav_msgs.msg import UavState
    from fire_uav_recording.raw_topics import fleet_offered_qos
    from rclpy.duration import Duration
    from rclpy.serialization import serialize_message

    f, sender, announced = upfront
    f.follow(["/fleet/state"])
    pub = topics.publisher(sender, topics.FLEET_STATE_SPEC)
    pub.publish(serialize_message(UavState(sequence=7)))
    assert pub.wait_for_all_acked(Duration(seconds=20))
    rclpy.shutdown(context=ros_context)  # the graph cannot be asked any more
    assert f.take_queued(cap_wall_s=10.0) == ({"/fleet/state": 1}, True)
    assert sequences(f.got["/fleet/state"]) == [7]
    (topic,) = announced  # what a fleet publisher offers, in the graph's form
    assert topic.offered == (fleet_offered_qos(topics.FLEET_STATE_SPEC),)
    assert topic.offered[0].reliability == topics.FLEET_STATE_SPEC.qos().reliability


def test_take_queued_waits_on_the_executor_for_what_is_expected(follower, ros_context):
    """The recorder's stop with its executor as the wait: a message that is expected (as the
    world's final truth once MISSION_COMPLETE is in) and comes after five quiet periods is still
    taken, by the executor's callback, and counted; then it ends after one quiet period."""
    import threading

    from fire_uav_common.ros_io import LeanExecutor
    from fire_uav_recording.raw_topics import STOP_QUIET_WALL_S

    f, publish, got = follower
    executor = LeanExecutor(context=ros_context)
    executor.add_node(f._node)
    late = threading.Timer(5 * STOP_QUIET_WALL_S, publish, args=(1,))
    waits: list[float] = []

    def wait(timeout_s: float) -> bool:
        waits.append(timeout_s)
        executor.spin_once(timeout_sec=timeout_s)
        return True

    late.start()
    try:
        taken, done = f.take_queued(
            cap_wall_s=30.0, wait=wait, expecting=lambda: None if got else "the late message"
        )
    finally:
        late.join()
        executor.shutdown()
    assert (taken, done) == ({"/fleet/state": 1}, True)
    assert sequences(got) == [0]
    assert waits[0] > 25.0  # while something is expected: up to the cap, woken by its arrival
