"""``ros_io.StopSignals``: a signal ends a blocked spin and leaves the context alive, so a node's
publishers can still be asked for their acknowledgements (in-process, rclpy, no other process)."""

from __future__ import annotations

import os
import signal
import threading

import pytest

rclpy = pytest.importorskip("rclpy")


@pytest.fixture
def context():
    from rclpy.signals import SignalHandlerOptions

    ctx = rclpy.context.Context()
    rclpy.init(context=ctx, signal_handler_options=SignalHandlerOptions.NO)
    try:
        yield ctx
    finally:
        rclpy.try_shutdown(context=ctx)


def test_a_signal_ends_a_blocked_spin_and_the_publishers_stay_usable(context) -> None:
    from fire_uav_common.ros_io import LeanExecutor, PublishCounts, StopSignals, unacked_topics
    from std_msgs.msg import String

    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    node = rclpy.create_node("stop_signals_test", context=context)
    executor = LeanExecutor(context=context)
    stop = StopSignals()
    try:
        counts = PublishCounts()
        pub = counts.wrap(node.create_publisher(String, "/stop_signals_test", 10))
        executor.add_node(node)
        stop.install(executor)
        # nothing else would ever wake this wait: only the signal can end the spin
        timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGTERM))
        timer.start()
        spins = 0
        while not stop.count:
            executor.spin_once()  # no timeout
            spins += 1
        timer.join()
        assert stop.count == 1 and spins >= 1
        assert context.ok()  # rclpy's handlers would have shut it down
        pub.publish(String(data="last"))  # a shut-down context refuses this ("context is invalid")
        pub.publish(String(data="last but not least"))
        assert counts.by_topic == {"/stop_signals_test": 2}
        assert unacked_topics(node.publishers) == []  # no reader matched: nothing to wait for
        stop.detach()
    finally:
        stop.uninstall()
        executor.shutdown()
        node.destroy_node()
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
    stop.uninstall()  # idempotent
