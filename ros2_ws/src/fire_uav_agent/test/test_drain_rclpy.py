"""``topics.subscription(..., drain=True)`` on real rclpy: a burst is handled in one callback.

Private context and domain, one process; the publisher is reliable with the fleet QoS, so all
messages are queued once matched.
"""

from __future__ import annotations

import time

import pytest

rclpy = pytest.importorskip("rclpy")
from fire_uav_common import topics  # noqa: E402
from fire_uav_msgs.msg import UavState  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402


@pytest.fixture
def node(ros_context):
    n = rclpy.create_node("drain_test", context=ros_context)
    ex = SingleThreadedExecutor(context=ros_context)
    ex.add_node(n)
    try:
        yield n, ex
    finally:
        ex.shutdown()
        n.destroy_node()


def _burst(node, drain: bool) -> tuple[list[int], list[int]]:
    n, ex = node
    got: list[int] = []
    calls: list[int] = []
    sub = topics.subscription(n, topics.FLEET_STATE_SPEC, lambda m: got.append(int(m.step)), drain=drain)
    outer = sub.callback
    sub.callback = lambda m: (calls.append(1), outer(m))  # count the executor's callbacks
    pub = topics.publisher(n, topics.FLEET_STATE_SPEC)
    end = time.monotonic() + 10.0
    while pub.get_subscription_count() == 0 and time.monotonic() < end:
        ex.spin_once(timeout_sec=0.05)
    assert pub.get_subscription_count() == 1
    for k in range(30):
        pub.publish(UavState(uav_id=1, step=k))
    time.sleep(0.3)  # all delivered to the reader's history
    end = time.monotonic() + 10.0
    while len(got) < 30 and time.monotonic() < end:
        ex.spin_once(timeout_sec=0.05)
    n.destroy_subscription(sub)
    n.destroy_publisher(pub)
    return got, calls


def test_a_drained_subscription_takes_the_burst_in_one_callback_and_in_order(node):
    got, calls = _burst(node, drain=True)
    assert got == list(range(30))
    assert len(calls) == 1


def test_without_drain_the_executor_calls_back_once_per_message(node):
    got, calls = _burst(node, drain=False)
    assert got == list(range(30))
    assert len(calls) == 30


def test_the_helpers_add_no_qos_event_handlers(node):
    n, _ = node
    sub = topics.subscription(n, topics.FLEET_STATE_SPEC, lambda m: None)
    pub = topics.publisher(n, topics.FLEET_STATE_SPEC)
    assert sub.event_handlers == [] and pub.event_handlers == []
    plain = n.create_subscription(UavState, "/plain", lambda m: None, 10)
    assert len(plain.event_handlers) >= 1  # rclpy's default, for comparison
