"""Replay a mission bag on ROS topics, with its ``/clock``, at a chosen rate.

Parameters (read once; a bad one is one error line naming it and exit status 2, :func:`main`):
- ``bag`` (string, required): bag directory or ``.mcap`` file (an unfinished one is salvaged).
- ``rate`` (double, > 0, default 1.0): bag seconds per wall second.
- ``start_s`` (double, >= 0): skip the first ``start_s`` seconds of the bag [s, bag time].
- ``topics`` (string[]): replay only these topics (default: all). ``/clock`` is always
  replayed if the bag has it; if it has none, a ``/clock`` is generated from the bag time.
- ``tick_period_wall_s`` (0.005): wall timer period of the publishing loop [s].
- ``progress`` (true): progress bar on stderr.
- ``delay_s`` (double, >= 0, default 1.0): wall seconds between creating the publishers and the
  first message (as ``ros2 bag play --delay``). Publishers are volatile, so a subscriber that
  DDS discovery has not matched yet misses what is sent before; 1 s covers discovery on a quiet
  host, a loaded one may need more.

Messages are republished raw (CDR bytes as recorded): a topic of ``fire_uav_common.topics``
with its spec's QoS, any other with the QoS its recorded publishers offered.
The node uses the wall clock (``use_sim_time`` false): it is the clock authority of a replay.
It exits when the bag is done or on SIGINT/SIGTERM.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass

import rclpy
from builtin_interfaces.msg import Time as TimeMsg
from fire_uav_common.stamps import ns_to_s, s_to_ns, to_time_msg
from fire_uav_common.topics import CLOCK_SPEC
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosbags.interfaces import QosDurability, QosReliability

import fire_uav_recording as rec
from fire_uav_recording.errors import EXIT_BAD_PARAMETER, EXIT_BAG_ERROR, ConfigError, one_line
from fire_uav_recording.raw_topics import message_class, spec_of

CLOCK_TOPIC = CLOCK_SPEC.name


@dataclass(frozen=True)
class ReplayConfig:
    bag: str
    rate: float
    start_s: float
    topics: tuple[str, ...]
    tick_period_wall_s: float
    progress: bool
    delay_s: float = 1.0


def publisher_qos(conn: object) -> QoSProfile:
    """QoS for republishing: the topic spec's, else the recorded publishers' (reliable volatile depth 100 if unknown)."""
    spec = spec_of(conn.topic)  # type: ignore[attr-defined]
    if spec is not None and spec.type == conn.msgtype:  # type: ignore[attr-defined]
        return spec.qos()
    offered = rec.offered_qos(conn)  # type: ignore[arg-type]
    best_effort = any(q.reliability == QosReliability.BEST_EFFORT for q in offered)
    transient = bool(offered) and all(q.durability == QosDurability.TRANSIENT_LOCAL for q in offered)
    depth = max([1000 if transient else 100, *[q.depth for q in offered]])
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE,
    )


class ProgressBar:
    """A one-line progress bar redrawn on stderr at most every ``period_wall_s``."""

    def __init__(self, total_s: float, enabled: bool, period_wall_s: float = 0.25) -> None:
        self.total_s = max(total_s, 1e-9)
        self.enabled = enabled and sys.stderr is not None
        self.period = period_wall_s
        self._last = 0.0

    def update(self, done_s: float, count: int, rate: float, force: bool = False) -> None:
        now = time.monotonic()
        if not self.enabled or (not force and now - self._last < self.period):
            return
        self._last = now
        frac = min(1.0, max(0.0, done_s / self.total_s))
        bar = "#" * int(frac * 30)
        sys.stderr.write(f"\rreplay [{bar:<30}] {done_s:8.1f}/{self.total_s:.1f} s  x{rate:g}  {count} msgs ")
        sys.stderr.flush()

    def finish(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


class ReplayNode(Node):
    """Publishes a bag's messages when the wall clock (scaled by ``rate``) reaches their bag time."""

    def __init__(self) -> None:
        super().__init__("replay")
        self.config = self._read_config()
        self.finished: Future = Future()
        cm = rec.open_bag(self.config.bag)
        self._bag = cm.__enter__()
        self._bag_cm = cm
        for w in self._bag.warnings:
            self.get_logger().warning(w)
        try:
            self._setup()
        except BaseException:
            self.close()
            raise

    def _read_config(self) -> ReplayConfig:
        ro = ParameterDescriptor(read_only=True)
        self.declare_parameter("bag", "", ro)
        self.declare_parameter(
            "rate",
            1.0,
            ParameterDescriptor(
                read_only=True, floating_point_range=[FloatingPointRange(from_value=0.001, to_value=1000.0)]
            ),
        )
        self.declare_parameter("start_s", 0.0, ro)
        self.declare_parameter("topics", [""], ro)
        self.declare_parameter("tick_period_wall_s", 0.005, ro)
        self.declare_parameter("progress", True, ro)
        self.declare_parameter("delay_s", 1.0, ro)
        g = self.get_parameter
        bag = str(g("bag").value)
        if not bag:
            raise ConfigError("parameter bag: required (a bag directory or .mcap file)")
        start_s = float(g("start_s").value)
        if start_s < 0:
            raise ConfigError(f"parameter start_s: must be >= 0, got {start_s}")
        delay_s = float(g("delay_s").value)
        if not 0.0 <= delay_s <= 3600.0:
            raise ConfigError(f"parameter delay_s: must be in [0, 3600] s, got {delay_s}")
        tick = float(g("tick_period_wall_s").value)
        if not 0.0005 <= tick <= 1.0:
            raise ConfigError(f"parameter tick_period_wall_s: must be in [0.0005, 1] s, got {tick}")
        return ReplayConfig(
            bag=bag,
            rate=float(g("rate").value),
            start_s=start_s,
            topics=tuple(t for t in g("topics").value if t),
            tick_period_wall_s=tick,
            progress=bool(g("progress").value),
            delay_s=delay_s,
        )

    def _setup(self) -> None:
        bag = self._bag
        have = bag.topics
        if self.config.topics:
            missing = [t for t in self.config.topics if t not in have]
            if missing:
                raise ConfigError(f"parameter topics: {missing} not in the bag; it has {sorted(have)}")
            wanted = set(self.config.topics) | ({CLOCK_TOPIC} & set(have))
        else:
            wanted = set(have)
        self._pubs: dict[int, object] = {}
        for conn in bag.connections(sorted(wanted)):
            spec = spec_of(conn.topic)
            try:
                cls = (
                    spec.msg_class()
                    if spec is not None and spec.type == conn.msgtype
                    else message_class(conn.msgtype)
                )
            except (ImportError, AttributeError, ValueError) as err:
                self.get_logger().warning(
                    f"not replaying {conn.topic}: type {conn.msgtype} not importable ({err})"
                )
                continue
            self._pubs[conn.id] = self.create_publisher(cls, conn.topic, publisher_qos(conn))
        self._gen_clock = CLOCK_TOPIC not in have
        self._clock_pub = (
            self.create_publisher(CLOCK_SPEC.msg_class(), CLOCK_SPEC.name, CLOCK_SPEC.qos())
            if self._gen_clock
            else None
        )
        reader = bag.reader
        off = bag.log_time_offset_ns  # sim time throughout (raw_messages takes the offset off)
        self.bag_start_ns = reader.start_time - off
        self.bag_end_ns = max(reader.end_time - off, self.bag_start_ns)
        self.first_ns = self.bag_start_ns + s_to_ns(self.config.start_s)
        if self.first_ns >= self.bag_end_ns and reader.message_count:
            raise ConfigError(
                f"parameter start_s: {self.config.start_s} s is past the bag's end "
                f"({ns_to_s(self.bag_end_ns - self.bag_start_ns):.1f} s)"
            )
        self._iter: Iterator[tuple[object, int, bytes]] = bag.raw_messages(
            topics=sorted({self._topic_of(cid) for cid in self._pubs}), start_ns=self.first_ns
        )
        self._next = next(self._iter, None)
        self.count = 0
        self.done = False
        self._wall0: float | None = None
        self._start_wall = time.monotonic() + self.config.delay_s
        self._bar = ProgressBar(ns_to_s(self.bag_end_ns - self.first_ns), self.config.progress)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(self.config.tick_period_wall_s, self._tick, clock=wall)
        self.get_logger().info(
            f"replaying {len(self._pubs)} topics from {self.config.bag} at x{self.config.rate:g}, "
            f"{ns_to_s(self.bag_end_ns - self.first_ns):.1f} s of bag time"
        )

    def _topic_of(self, cid: int) -> str:
        return next(c.topic for c in self._bag.connections() if c.id == cid)

    def _tick(self) -> None:
        if self.done:
            return
        now = time.monotonic()
        if self._wall0 is None:
            if now < self._start_wall:  # discovery: let subscribers match first
                return
            self._wall0 = now
        target_ns = self.first_ns + s_to_ns((now - self._wall0) * self.config.rate)
        try:
            while self._next is not None and self._next[1] <= target_ns:
                conn, _t, raw = self._next
                pub = self._pubs.get(conn.id)  # type: ignore[attr-defined]
                if pub is not None:
                    pub.publish(raw)  # type: ignore[attr-defined]
                    self.count += 1
                self._next = next(self._iter, None)
        except rec.BagError as err:
            self.get_logger().error(str(err))
            self._finish()
            return
        if self._clock_pub is not None:
            msg = CLOCK_SPEC.msg_class()(clock=to_time_msg(min(target_ns, self.bag_end_ns), TimeMsg))
            self._clock_pub.publish(msg)
        self._bar.update(
            ns_to_s(min(target_ns, self.bag_end_ns - 1) - self.first_ns), self.count, self.config.rate
        )
        if self._next is None:
            self._bar.update(
                ns_to_s(self.bag_end_ns - self.first_ns), self.count, self.config.rate, force=True
            )
            self._finish()

    def _finish(self) -> None:
        self.done = True
        self._timer.cancel()
        self._bar.finish()
        self.finished.set_result(self.count)

    def close(self) -> None:
        """Close the bag (and its salvage copy). Idempotent."""
        cm, self._bag_cm = getattr(self, "_bag_cm", None), None
        if cm is not None:
            cm.__exit__(None, None, None)


def main(args: list[str] | None = None) -> int:
    """Replay until the bag ends or SIGINT/SIGTERM. Exit status 0 on success; 2 on a bad parameter
    (one error line naming it: a ``ConfigError`` of the node's checks, ``topics`` the bag lacks,
    ``start_s`` past its end, or a value rclpy refuses against the parameter's descriptor or
    type); 1 on a bag error (``bag`` cannot be opened or read)."""
    rclpy.init(args=args)
    node: ReplayNode | None = None
    rc = 0
    try:
        node = ReplayNode()
        rclpy.spin_until_future_complete(node, node.finished)
        if node.done:
            # let reliable subscribers drain the last messages before the publishers go away
            rclpy.spin_until_future_complete(node, Future(), timeout_sec=0.5)
            rclpy.logging.get_logger("replay.done").info(f"replayed {node.count} messages")
    except (KeyboardInterrupt, ExternalShutdownException):
        if node is not None:
            node._bar.finish()
    except (ConfigError, InvalidParameterValueException, InvalidParameterTypeException) as err:
        rclpy.logging.get_logger("replay").error(one_line(err))
        rc = EXIT_BAD_PARAMETER
    except rec.BagError as err:
        rclpy.logging.get_logger("replay").error(str(err))
        rc = EXIT_BAG_ERROR
    except Exception:  # a signal may shut the context down in the middle of a wait: that is a stop too
        if rclpy.ok():
            raise
    finally:
        if node is not None:
            node.close()
            node.destroy_node()
        rclpy.try_shutdown()
    return rc


if __name__ == "__main__":
    sys.exit(main())
