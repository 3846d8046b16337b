"""``fire_uav_common.ros_io.LeanExecutor`` on real rclpy: what the project's nodes need of an executor.

Messages in order (with and without ``MessageInfo``), timers (one that destroys itself and one
made in a callback: the wait set is rebuilt), a parameter service answered, ``wake``, shutdown
as rclpy's executors report it, and the clear errors. Private context and domain, one process.
"""

from __future__ import annotations

import threading
import time

import pytest

rclpy = pytest.importorskip("rclpy")
from fire_uav_common import topics  # noqa: E402
from fire_uav_common.ros_io import EXECUTOR_ENV, LeanExecutor, make_executor  # noqa: E402
from fire_uav_msgs.msg import UavState  # noqa: E402
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor  # noqa: E402


@pytest.fixture
def ctx(ros_context):
    return ros_context


@pytest.fixture
def lean(ctx):
    """``lean(name, **node_kwargs) -> (node, executor)``; every pair is torn down after the test."""
    made = []

    def make(name: str, **kw):
        n = rclpy.create_node(name, context=ctx, **kw)
        ex = LeanExecutor(context=ctx)
        ex.add_node(n)
        made.append((n, ex))
        return n, ex

    yield make
    for n, ex in reversed(made):
        ex.shutdown()
        n.destroy_node()


def _spin_until(ex, cond, timeout_s: float = 10.0) -> None:
    end = time.monotonic() + timeout_s
    while not cond() and time.monotonic() < end:
        ex.spin_once(timeout_sec=0.05)
    assert cond()


def test_messages_arrive_in_order_with_and_without_message_info(lean):
    n, ex = lean("lean_subs")
    plain: list[int] = []
    infos: list[tuple[int, bool]] = []
    topics.subscription(n, topics.FLEET_STATE_SPEC, lambda m: plain.append(int(m.step)))
    n.create_subscription(
        UavState,
        topics.FLEET_STATE_SPEC.name,
        lambda m, info: infos.append((int(m.step), info["source_timestamp"] > 0)),
        topics.qos(topics.FLEET_STATE_SPEC.qos_kind),
    )
    pub = topics.publisher(n, topics.FLEET_STATE_SPEC)
    _spin_until(ex, lambda: pub.get_subscription_count() == 2)
    for k in range(25):
        pub.publish(UavState(uav_id=1, step=k))
    _spin_until(ex, lambda: len(plain) == 25 and len(infos) == 25)
    assert plain == list(range(25))
    assert infos == [(k, True) for k in range(25)]


def test_timers_fire_and_timers_made_or_destroyed_in_callbacks_are_waited_on(lean):
    n, ex = lean("lean_timers")
    ticks: list[str] = []

    def once() -> None:
        ticks.append("once")
        n.destroy_timer(first)
        n.create_timer(0.01, lambda: ticks.append("later"))  # a new entity: the wait set is rebuilt

    first = n.create_timer(0.01, once)
    _spin_until(ex, lambda: ticks.count("later") >= 3)
    assert ticks.count("once") == 1 and ticks[0] == "once"


def test_a_parameter_service_is_answered(ctx):
    from rcl_interfaces.srv import GetParameters

    server = rclpy.create_node("lean_server", context=ctx, parameter_overrides=[])
    server.declare_parameter("speed_mps", 17.5)
    ex = LeanExecutor(context=ctx)
    ex.add_node(server)
    client_node = rclpy.create_node("lean_client", context=ctx)
    cli = client_node.create_client(GetParameters, "/lean_server/get_parameters")
    other = SingleThreadedExecutor(context=ctx)
    other.add_node(client_node)
    stop = threading.Event()
    t = threading.Thread(target=lambda: [other.spin_once(timeout_sec=0.05) for _ in iter(stop.is_set, True)])
    t.start()
    try:
        _spin_until(ex, lambda: cli.service_is_ready())
        future = cli.call_async(GetParameters.Request(names=["speed_mps"]))
        _spin_until(ex, future.done)
        assert future.result().values[0].double_value == 17.5
    finally:
        stop.set()
        t.join(5.0)
        other.shutdown()
        ex.shutdown()
        client_node.destroy_node()
        server.destroy_node()


def test_wake_ends_a_blocking_wait_and_shutdown_raises_as_rclpy_does(ctx, lean):
    n, ex = lean("lean_wake")
    threading.Timer(0.2, ex.wake).start()
    t0 = time.monotonic()
    ex.spin_once()  # no timeout: only the wake ends it
    assert time.monotonic() - t0 < 5.0
    threading.Timer(0.2, lambda: rclpy.shutdown(context=ctx)).start()
    with pytest.raises(ExternalShutdownException):
        ex.spin()
    with pytest.raises(ExternalShutdownException):
        ex.spin_once(timeout_sec=0.0)


def test_clear_errors_for_what_it_does_not_do(ctx, monkeypatch):
    from std_srvs.srv import Trigger

    a = rclpy.create_node("lean_a", context=ctx)
    b = rclpy.create_node("lean_b", context=ctx)
    ex = LeanExecutor(context=ctx)
    ex.add_node(a)
    with pytest.raises(ValueError, match="spins one node"):
        ex.add_node(b)
    b.create_client(Trigger, "/nowhere")
    with pytest.raises(ValueError, match="lean_b has service clients"):
        LeanExecutor(context=ctx).add_node(b)

    async def waits() -> None:
        import asyncio

        await asyncio.sleep(0)

    a.create_timer(0.01, waits)
    with pytest.raises(RuntimeError, match="awaited something"):
        _spin_until(ex, lambda: False, timeout_s=2.0)
    ex.shutdown()
    a.destroy_node()
    b.destroy_node()
    monkeypatch.setenv(EXECUTOR_ENV, "rclpy")
    assert isinstance(make_executor(ctx), SingleThreadedExecutor)
    monkeypatch.delenv(EXECUTOR_ENV)
    assert isinstance(make_executor(ctx), LeanExecutor)
    monkeypatch.setenv(EXECUTOR_ENV, "events")
    with pytest.raises(ValueError, match=r"^FIRE_UAV_EXECUTOR='events': expected 'lean' or 'rclpy'$"):
        make_executor(ctx)
