"""The one spin loop of the project's nodes and helper processes (imports rclpy when called).

ROS adapter module (the layering test lets ``ros_io.py`` import rclpy); the rest of
fire_uav_common stays ROS-free.
"""

from __future__ import annotations

import contextlib
import inspect
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from .errors import ExecutorAwaitError, ExecutorError

__all__ = [
    "LeanExecutor",
    "PublishCounts",
    "StopSignals",
    "make_executor",
    "private_context",
    "spin",
    "unacked_topics",
]

EXECUTOR_ENV = "FIRE_UAV_EXECUTOR"  # "lean" (the default) or "rclpy": which executor make_executor gives


def _run(result: Any, what: str) -> Any:
    """Finish a callback's result: a coroutine (rclpy's waitables' ``execute``) is run to its end
    (it must not wait on anything, as nothing here would wake it)."""
    if not inspect.iscoroutine(result):
        return result
    try:
        result.send(None)
    except StopIteration as done:
        return done.value
    result.close()
    raise ExecutorAwaitError(f"LeanExecutor: the coroutine of {what} awaited something; use rclpy's executor")


def _refuse_clients(node: Any) -> None:
    if list(node.clients):
        raise ExecutorError(f"LeanExecutor: node {node.get_name()} has service clients; use rclpy's executor")


class LeanExecutor:
    """A single-threaded executor for one node, with a wait set built once (it pays at fleet scale).

    rclpy's ``SingleThreadedExecutor`` rebuilds its wait set in Python at every wait: it
    re-collects every entity of the node, enters each handle's context, makes a new wait set,
    and wraps each ready callback in a Task. That came to ~175 us per wake on an agent's node (6
    subscriptions, 2 timers, 7 parameter services), and an agent of a 20-UAV fleet wakes many
    times per step. This one keeps the wait set and re-adds the same handles (~15-20 us), and
    rebuilds only when the node's set of entities changes.

    Each wait is then handled in rclpy's order within a group: the ready timers, guard
    conditions, waitables (QoS event handlers) and services, then the subscriptions (one message
    each, as rclpy takes them: a drained subscription takes the rest of its queue itself,
    ``topics.drain_queue``). All ready entities of one wait are run before the next wait.
    Callbacks run plainly, with no Task or Future: a coroutine callback must finish without
    awaiting (a ``RuntimeError`` names it otherwise); clients are refused when the node is added
    (none of the project's nodes has one). An error raised by a callback, or by rclpy's
    ``take_message`` (a message it cannot convert), leaves ``spin_once`` as it does rclpy's.
    ``FIRE_UAV_EXECUTOR=rclpy`` selects rclpy's executor instead (:func:`make_executor`).
    """

    def __init__(self, context: Any = None) -> None:
        import rclpy
        from rclpy.executors import ExternalShutdownException
        from rclpy.guard_condition import GuardCondition
        from rclpy.signals import SignalHandlerGuardCondition

        self._shutdown_error = ExternalShutdownException  # raised by spin_once, as rclpy's executors do
        self._context: Any = context or rclpy.get_default_context()
        self._guard: Any = GuardCondition(None, None, context=self._context)  # wake()
        self._sigint: Any = SignalHandlerGuardCondition(self._context)  # Ctrl-C wakes the wait
        self._context.on_shutdown(self.wake)
        self._node: Any = None
        self._key: tuple | None = None
        self._ws: Any = None

    # --- rclpy's executor interface, the part the project uses ------------------------------------
    @property
    def context(self) -> Any:
        return self._context

    def add_node(self, node: Any) -> bool:
        if self._node is not None and self._node is not node:
            raise ExecutorError("LeanExecutor spins one node; use rclpy's executor for several")
        _refuse_clients(node)
        self._node = node
        self._key = None
        return True

    def remove_node(self, node: Any) -> None:
        if node is self._node:
            self._node, self._key, self._ws = None, None, None

    def get_nodes(self) -> list:
        return [] if self._node is None else [self._node]

    def wake(self) -> None:
        if self._guard is not None:
            self._guard.trigger()

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        self._node, self._key, self._ws = None, None, None
        for gc in (self._guard, self._sigint):
            if gc is not None:
                gc.destroy()
        self._guard = self._sigint = None
        return True

    def spin(self) -> None:
        """Spin until the context is shut down (``ExternalShutdownException``, as rclpy's)."""
        while self._node is not None:
            self.spin_once()

    def spin_until_future_complete(self, future: Any, timeout_sec: float | None = None) -> None:
        """Spin until ``future`` is done (checked after every wait, at most 0.1 s apart)."""
        import time

        end = None if timeout_sec is None or timeout_sec < 0 else time.monotonic() + timeout_sec
        while not future.done():  # spin_once raises once the context is shut down
            left = None if end is None else end - time.monotonic()
            if left is not None and left <= 0:
                return
            self.spin_once(0.1 if left is None else min(0.1, left))

    # --- the wait ---------------------------------------------------------------------------------
    def _build(self) -> None:
        """Rebuild the wait set if the node's entities changed since the last wait (every wait
        compares the entity lists; the imports and the new WaitSet only on a change)."""
        n = self._node
        subs, tmrs, srvs = list(n.subscriptions), list(n.timers), list(n.services)
        gcs, wts = list(n.guards), list(n.waitables)
        key = tuple(tuple(map(id, group)) for group in (subs, tmrs, srvs, gcs, wts))
        if key == self._key:
            return
        from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
        from rclpy.waitable import NumberOfEntities

        _refuse_clients(n)
        count = NumberOfEntities(len(subs), len(gcs) + 2, len(tmrs), 0, len(srvs), 0)
        for w in wts:
            count += w.get_num_entities()
        self._ws = _rclpy.WaitSet(
            count.num_subscriptions, count.num_guard_conditions, count.num_timers,
            count.num_clients, count.num_services, count.num_events, self._context.handle,
        )  # fmt: skip
        self._subs, self._tmrs, self._srvs, self._gcs, self._wts = subs, tmrs, srvs, gcs, wts
        self._sub_at = {s.handle.pointer: s for s in subs}
        self._tmr_at = {t.handle.pointer: t for t in tmrs}
        self._srv_at = {s.handle.pointer: s for s in srvs}
        self._key = key

    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Wait up to ``timeout_sec`` (None or < 0: until something is ready), then run every ready
        callback. Raises rclpy's ``ExternalShutdownException`` once the context is shut down (a
        signal, ``rclpy.shutdown``), as rclpy's executors do."""
        if not self._context.ok():
            raise self._shutdown_error()
        if self._node is None:
            return
        self._build()
        ws = self._ws
        ws.clear_entities()
        for s in self._subs:
            ws.add_subscription(s.handle)
        for s in self._srvs:
            ws.add_service(s.handle)
        for t in self._tmrs:
            ws.add_timer(t.handle)
        for g in self._gcs:
            ws.add_guard_condition(g.handle)
        ws.add_guard_condition(self._guard.handle)
        ws.add_guard_condition(self._sigint.handle)
        for w in self._wts:
            w.add_to_wait_set(ws)
        timeout_ns = -1 if timeout_sec is None or timeout_sec < 0 else int(timeout_sec * 1e9)
        with self._context.handle:
            ws.wait(timeout_ns)
        if not self._context.ok():
            raise self._shutdown_error()
        for p in ws.get_ready_entities("timer"):
            t = self._tmr_at.get(p)
            if t is not None and t.handle.is_timer_ready():  # rclpy checks too (cancelled timers)
                t.handle.call_timer()
                _run(t.callback(), f"timer {t}")
        ready_gcs = ws.get_ready_entities("guard_condition")
        for g in self._gcs:
            if g.handle.pointer in ready_gcs and g.callback is not None:
                _run(g.callback(), f"guard condition {g}")
        for w in [w for w in self._wts if w.is_ready(ws)]:
            data = w.take_data()
            _run(w.execute(data), f"waitable {w}")
        for p in ws.get_ready_entities("service"):
            srv = self._srv_at.get(p)
            if srv is None:
                continue
            request, header = srv.handle.service_take_request(srv.srv_type.Request)
            if header is not None:
                response = _run(srv.callback(request, srv.srv_type.Response()), f"service {srv.srv_name}")
                srv.send_response(response, header)
        for p in ws.get_ready_entities("subscription"):
            sub = self._sub_at.get(p)
            if sub is None:
                continue
            got = sub.handle.take_message(sub.msg_type, sub.raw)
            if got is None:
                continue
            if sub._callback_type is type(sub).CallbackType.MessageOnly:
                _run(sub.callback(got[0]), f"subscription {sub.topic_name}")
            else:
                _run(sub.callback(*got), f"subscription {sub.topic_name}")


def make_executor(context: Any = None) -> Any:
    """The executor the project's nodes spin on: :class:`LeanExecutor`, or rclpy's
    ``SingleThreadedExecutor`` when ``FIRE_UAV_EXECUTOR=rclpy`` (an error names other values)."""
    import os

    kind = os.environ.get(EXECUTOR_ENV, "lean").strip().lower() or "lean"
    if kind == "lean":
        return LeanExecutor(context=context)
    if kind == "rclpy":
        from rclpy.executors import SingleThreadedExecutor

        return SingleThreadedExecutor(context=context)
    raise ExecutorError(f"{EXECUTOR_ENV}={kind!r}: expected 'lean' or 'rclpy'")


def spin(node: Any, on_exit: Callable[[], None] | None = None) -> None:
    """Spin ``node`` on :func:`make_executor`'s executor until Ctrl-C, an external shutdown or a
    ``SystemExit`` raised by a callback (a process ending itself), then call ``on_exit`` (if given), destroy the node and shut rclpy
    down (``try_shutdown``: a no-op when a signal handler already did)."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    executor = make_executor()
    try:
        executor.add_node(node)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException, SystemExit):
        pass
    finally:
        if on_exit is not None:
            on_exit()
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()


# --- the end of a node: its last messages acknowledged (fire_uav_common.final_acks) ----------------
def unacked_topics(publishers: Iterable[Any]) -> list[str]:
    """The topics of ``publishers`` whose messages some matched reader has not acknowledged yet
    (``Publisher.wait_for_all_acked`` with no wait; a best-effort publisher never counts)."""
    from rclpy.duration import Duration

    now = Duration(seconds=0)
    return sorted({p.topic_name for p in publishers if not p.wait_for_all_acked(now)})


class StopSignals:
    """SIGINT/SIGTERM as a request to stop that leaves the rclpy context alive.

    rclpy's own handlers shut the context down at the signal, and a shut-down context has no
    publisher any more: nothing can then wait for a reader's acknowledgements
    (:func:`unacked_topics`). With ``rclpy.init(signal_handler_options=SignalHandlerOptions.NO)``
    these handlers only count (``count``; a second signal cuts the final wait short), and a small
    thread wakes the executor's wait (``executor.wake()``: a signal alone does not end an
    ``rcl_wait``), so a spin loop that asks ``count`` ends at once. :meth:`uninstall` puts the
    previous handlers back (a process that goes on, e.g. a test calling a node's ``main``).
    """

    def __init__(self) -> None:
        self.count = 0
        self._executor: Any = None
        self._lock = threading.Lock()
        self._restore: list[tuple[int, Any]] = []
        self._old_fd = -1
        self._write_fd: int | None = None

    def __call__(self, signum: int, frame: object) -> None:
        self.count += 1

    def install(self, executor: Any) -> None:
        """Count SIGINT/SIGTERM from now on and wake ``executor`` at each (main thread only)."""
        import os
        import signal

        self._executor = executor
        r, w = os.pipe()
        os.set_blocking(w, False)
        self._write_fd = w
        self._old_fd = signal.set_wakeup_fd(w, warn_on_full_buffer=False)  # a byte per signal
        for sig in (signal.SIGINT, signal.SIGTERM):
            self._restore.append((sig, signal.signal(sig, self)))
        threading.Thread(target=self._wake_on_signal, args=(r,), name="stop-signals", daemon=True).start()

    def _wake_on_signal(self, fd: int) -> None:
        import os

        try:
            while os.read(fd, 64):  # b"": the write end is closed (uninstall)
                with self._lock:
                    if self._executor is not None:
                        self._executor.wake()
        finally:
            os.close(fd)

    def detach(self) -> None:
        """Stop waking the executor (before it is shut down); the signals are still counted."""
        with self._lock:
            self._executor = None

    def uninstall(self) -> None:
        """The previous handlers and wakeup fd back (main thread only); idempotent."""
        import os
        import signal

        self.detach()
        if self._write_fd is None:
            return
        signal.set_wakeup_fd(self._old_fd)
        for sig, old in reversed(self._restore):
            if old is not None:  # None: a handler not set from Python, which cannot be put back
                signal.signal(sig, old)
        self._restore.clear()
        os.close(self._write_fd)
        self._write_fd = None


class PublishCounts:
    """How many messages each wrapped publisher has published, per topic (``by_topic``): the
    truth a reader's record of those topics is checked against (``final_acks.published_line``)."""

    def __init__(self) -> None:
        self.by_topic: dict[str, int] = {}

    def wrap(self, publisher: Any) -> Any:
        """Count what ``publisher`` publishes from now on (its ``publish`` wrapped); returns it."""
        topic = publisher.topic_name
        self.by_topic.setdefault(topic, 0)
        inner = publisher.publish

        def publish(msg: Any) -> None:
            inner(msg)
            self.by_topic[topic] += 1  # once published (a publish that raised sent nothing)

        publisher.publish = publish
        return publisher


@contextlib.contextmanager
def private_context(domain_id: int) -> Iterator[Any]:
    """An initialised ``rclpy.Context`` on ``domain_id``, shut down on exit: for tests that talk DDS
    inside one process (the domain claimed by ``fire_mission.procs.claim_domain``)."""
    import rclpy

    ctx = rclpy.Context()
    rclpy.init(context=ctx, domain_id=domain_id)
    try:
        yield ctx
    finally:
        rclpy.try_shutdown(context=ctx)
