"""Mission recorder: every mission topic, raw CDR, into a rosbag2 directory with MCAP storage.

Parameters (all read once at start-up; a bad one is one error line naming it and exit status 2,
:func:`main`):
- ``output`` (string, required): bag directory to create; an existing path is refused (a bag
  error: exit status 1, the recorder never overwrites).
- ``scenario_file`` (string): scenario YAML, stored verbatim in the bag's metadata.
- ``seed`` (int >= 0): stored in the bag's metadata.
- ``uav_count`` (int in [0, 255]): stored in the bag's metadata; the per-vehicle topics of
  vehicles ``0 .. uav_count - 1`` are subscribed up front (below).
- ``topics`` (string[]): regular expressions; a topic is recorded if one matches it fully.
  Default: every recorded topic of ``fire_uav_common.topics`` (``recorded_patterns()``).
- ``exclude`` (string[]): regular expressions of topics never recorded.
- ``discovery_period_wall_s`` (0.5): how often the graph is polled for new topics and for the
  publishers of the up-front ones [s, wall].
- ``flush_period_wall_s`` (1.0): how often the open MCAP chunk is written out [s, wall];
  a SIGKILL loses at most this much.
- ``stop_drain_wall_s`` (2.0): at a stop, the longest the recorder goes on taking what is still
  queued [s, wall], in [0, 60] (a bound for publishers that go on publishing).
- ``compress`` (true): zstd-compressed MCAP chunks.
- ``use_sim_time`` (true): bag timestamps are sim time (``/clock``) at receipt.
- ``geo_fixes`` (true): on a scenario with a landscape, each ``/world/truth`` message written is
  followed by one ``sensor_msgs/NavSatFix`` per vehicle on ``/uav_<k>/geo/truth_fix`` (its TRUE
  position in WGS84, :func:`fire_uav_recording.geo.truth_fixes`), at the same bag time, so the
  bag opened in Foxglove shows the fleet on the Map panel. Derived in the recorder from every
  truth message it writes: none is lost that the truth has.
- ``stamp_wall_epoch`` (false): add the wall-clock epoch of the recorder's start (whole
  seconds) to every bag timestamp, so tools that show log times (Foxglove, ``ros2 bag info``)
  show the real date instead of 1970; the offset is stored as ``fire_uav.log_time_offset_ns``
  and :class:`fire_uav_recording.MissionBag` takes it off again (message header stamps stay sim
  time).

Messages are stamped with the node clock at receipt (sim time by default). A topic of
``fire_uav_common.topics`` is subscribed with its spec's QoS (depth at least 1000,
``raw_topics.MIN_DEPTH``, so a burst is not dropped while the recorder is held up: its start-up,
a flush, a busy CPU); any other topic with the QoS its publishers offer (rosbag2's adaptive
rule), made compatible with every profile offered when it was found: best effort if a
publisher is, volatile unless every publisher is transient local.

Start-up: the world starts stepping once ``/world/truth`` has ``wait_for_subscribers``
subscribers (recorder and runner) and every agent said AGENT_READY. Nothing waits for the
recorder's other subscriptions, and one made only when the graph poll finds its publisher misses
what that publisher sent before (measured: a 20-UAV mission began while the recorder was still
subscribing to ~90 topics; ~40 per-vehicle topics lost their first 1-7 steps). So before
anything else the recorder subscribes to every fleet topic it can name (:func:`up_front_topics`:
``fire_uav_common.topics.ALL_TOPICS``, the per-vehicle ones for vehicles ``0 .. uav_count - 1``,
those ``topics``/``exclude`` want) with the spec's QoS, as
:func:`~fire_uav_recording.raw_topics.subscription_qos` gives it for the fleet's own publishers, and
``/world/truth`` last: DDS announces a participant's endpoints in the order they are made, so a
world that sees the recorder on ``/world/truth`` has matched its other subscriptions too (the
agents, started after the recorder, match them while they wait for each other's AGENT_READY).
Other topics (foreign names, vehicles beyond ``uav_count``) are subscribed when the poll finds a
publisher, as before. Same 20-UAV mission, two runs: no step missing on any per-vehicle topic.

An up-front topic gets its bag connection when the poll first shows a publisher of it or its
first message comes, whichever is first; its ``offered_qos_profiles`` are those of the
publishers the graph shows then (none yet: what a fleet publisher offers,
``raw_topics.fleet_offered_qos``). So, as before, a topic nobody publishes on has no connection and
one with publishers but no message an empty one. The subscription keeps the fleet's QoS: a
publisher it cannot match (best effort on a reliable topic, volatile on a transient local one,
another type) is not recorded; the recorder names it in a warning when the topic gets its
connection, rclpy's incompatible-QoS event names later ones (the adaptive rule, too, relaxes
only for the publishers there when a topic is found). Re-subscribing with a laxer QoS would
lose or duplicate the fleet publishers' messages during the switch, and the lean executor
cannot have a subscription destroyed from a callback.

Keeping up: at 20 UAVs ``/fleet/state`` and ``/tf`` each get ~20 messages per step. The node
spins on the project's :class:`fire_uav_common.ros_io.LeanExecutor` (wait set built once, not
rebuilt in Python over ~90 subscriptions at every wake) and every subscription is drained (one
callback takes the topic's whole queue, ``topics.drain_queue``); with rclpy's executor, one
message per topic per wake, the recorder fell ever further behind (measured: 804 of 3000
``/fleet/state`` messages of a 20-UAV, 150-step mission).

Stopping: SIGINT/SIGTERM only count (rclpy's own signal handlers are not installed: they shut
the context down at once and, for SIGINT, raise ``KeyboardInterrupt`` in whatever runs, a bag
write included). The spin loop sees the signal within :data:`STOP_POLL_WALL_S`; then every
message still queued in a subscription is taken and written
(:meth:`~fire_uav_recording.raw_topics.RawTopicFollower.take_queued`), the count is logged
(``stop: took N queued messages ...``), and the bag is closed. Between its passes the drain waits
on the node's executor, which wakes when a message comes (no sleep). Once the world has
announced the end of its mission (``MISSION_COMPLETE`` on ``/world/events``, stamped with its
final step), it waits for that step's ``/world/truth`` (:mod:`fire_uav_recording.stop_drain`),
then, as without an announced end, until nothing has come for 0.1 s; at most
``stop_drain_wall_s``, and a second signal cuts it short. A final truth still missing then is
named in a warning (``stop: the bag lacks the world's final /world/truth ...``). That message
is there only if the world lived until the recorder had it: the world exits once every reader
has acknowledged its messages, and the runner lets it (docs/recording.md, "Stopping"). Over
the memory budget at a stop the chunk is flushed rather than a message dropped. A SIGKILL
loses what the last ``flush_period_wall_s`` wrote, as before.
"""

from __future__ import annotations

import datetime as _dt
import re
import signal
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from importlib import metadata as _im
from pathlib import Path
from typing import Any

import rclpy
from fire_uav_common import topics
from fire_uav_common.ros_io import make_executor
from fire_uav_common.stamps import NS_PER_S
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from rclpy.signals import SignalHandlerOptions
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

import fire_uav_recording as rec
from fire_uav_recording.errors import EXIT_BAD_PARAMETER, EXIT_BAG_ERROR, ConfigError, one_line
from fire_uav_recording.geo import NAVSAT_TYPE, GeoView, geo_frame_of_scenario_file
from fire_uav_recording.raw_topics import (  # noqa: F401  (re-exported: the recorder's QoS rule)
    MIN_DEPTH,
    RawTopic,
    RawTopicFollower,
    compile_patterns,
    fleet_topic_names,
    message_class,
    spec_of,
    subscription_qos,
    topic_wanted,
)
from fire_uav_recording.stop_drain import MissionEndWatch

DEFAULT_TOPICS = topics.recorded_patterns()
_INF_SEC, _INF_NSEC = rec.INFINITE_DURATION  # rosbag2 Jazzy's spelling of an infinite duration
STOP_POLL_WALL_S = 0.1  # [s, wall] longest wait between a stop signal and the spin loop seeing it
MAX_UAV_COUNT = 255  # vehicle ids are uint8 (the scenario's uavs.count has the same bound)


@dataclass(frozen=True)
class RecorderConfig:
    output: Path
    scenario_file: str
    seed: int
    uav_count: int
    include: tuple[re.Pattern[str], ...]
    exclude: tuple[re.Pattern[str], ...]
    discovery_period_wall_s: float
    flush_period_wall_s: float
    compress: bool
    stop_drain_wall_s: float
    stamp_wall_epoch: bool
    max_pending_bytes: int = 64 * 2**20  # [B] written since the last flush before messages are dropped
    geo_fixes: bool = True

    def wants(self, topic: str) -> bool:
        """Whether ``topic`` is recorded (full-match an include pattern and no exclude pattern)."""
        return topic_wanted(topic, self.include, self.exclude)


def software_version() -> str:
    """``fire_uav_recording <v>; fire_world_sim <v>; rosbags <v>`` (installed distribution versions)."""
    parts = []
    for dist in ("fire_uav_recording", "fire_world_sim", "rosbags"):
        try:
            parts.append(f"{dist} {_im.version(dist)}")
        except _im.PackageNotFoundError:
            parts.append(f"{dist} unknown")
    return "; ".join(parts)


def up_front_topics(uav_count: int) -> list[str]:
    """The fleet topics the recorder subscribes to before anything else, in that order: every
    name of ``fire_uav_common.topics`` in a fleet of ``uav_count`` vehicles, ``/world/truth``
    last (the world starts stepping once it sees the recorder on ``/world/truth``; DDS announces
    the recorder's subscriptions in the order they are made, so by then it has matched the others
    too)."""
    names = fleet_topic_names(uav_count)
    return [t for t in names if t != topics.WORLD_TRUTH] + [t for t in names if t == topics.WORLD_TRUTH]


def to_bag_qos(profile: QoSProfile) -> Qos:
    """rclpy QoS profile -> rosbags Qos (the enums share rmw's numbering)."""

    def dur(d: object) -> QosTime:
        ns = int(getattr(d, "nanoseconds", 0))
        if ns <= 0 or ns >= _INF_SEC * NS_PER_S + _INF_NSEC or ns // NS_PER_S > 2**31 - 1:
            return QosTime(_INF_SEC, _INF_NSEC) if ns else QosTime(0, 0)
        return QosTime(*divmod(ns, NS_PER_S))

    return Qos(
        history=QosHistory(int(profile.history)),
        depth=int(profile.depth),
        reliability=QosReliability(int(profile.reliability)),
        durability=QosDurability(int(profile.durability)),
        deadline=dur(profile.deadline),
        lifespan=dur(profile.lifespan),
        liveliness=QosLiveliness(int(profile.liveliness)),
        liveliness_lease_duration=dur(profile.liveliness_lease_duration),
        avoid_ros_namespace_conventions=bool(profile.avoid_ros_namespace_conventions),
    )


class RecorderNode(Node):
    """Subscribes raw to every mission topic (the fleet's at once, others as they appear) and
    writes it into one MCAP bag."""

    def __init__(self) -> None:
        super().__init__(
            "recorder",
            parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)],
            allow_undeclared_parameters=False,
        )
        self.config = self._read_config()
        self._typestore = rec.fleet_typestore()
        # before the bag is made (a bad scenario_file leaves no half-made bag behind) and before
        # the subscriptions (the world waits for them, not for this)
        self._geo = self._geo_view()
        self._offset_ns = (time.time_ns() // NS_PER_S) * NS_PER_S if self.config.stamp_wall_epoch else 0
        self._writer = rec.BagWriter(
            self.config.output, custom_data=self._custom_data(), compress=self.config.compress
        )
        self._writer.open()
        self._closed = False
        self._stopping = False  # taking what is queued at a stop: flush rather than drop
        self.messages_written = 0
        self.messages_dropped: dict[str, int] = {}  # per topic, over the memory budget (a flood)
        self._pending_bytes = 0  # [B] written since the last flush
        self._fix_connections: dict[str, object] = {}
        self.mission_end = MissionEndWatch()  # the world's final truth, expected at a stop
        self._follower = RawTopicFollower(self, self.config.wants, self._typestore, self._on_topic)
        # before anything else the world waits for: see up_front_topics
        n = self._follower.follow(up_front_topics(self.config.uav_count))
        self.get_logger().info(f"subscribed to {n} fleet topics up front ({self.config.uav_count} UAVs)")
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._discovery_timer = self.create_timer(
            self.config.discovery_period_wall_s, self._discover, clock=wall
        )
        self._flush_timer = self.create_timer(self.config.flush_period_wall_s, self._flush, clock=wall)
        self.get_logger().info(f"recording to {self.config.output}")
        self._discover()

    # --- configuration -------------------------------------------------------------------
    def _read_config(self) -> RecorderConfig:
        ro = ParameterDescriptor(read_only=True)
        self.declare_parameter("output", "", ParameterDescriptor(read_only=True, description="bag directory"))
        self.declare_parameter("scenario_file", "", ro)
        nonneg = ParameterDescriptor(
            read_only=True, integer_range=[IntegerRange(from_value=0, to_value=2**31 - 1)]
        )
        self.declare_parameter("seed", 0, nonneg)
        self.declare_parameter("uav_count", 0, nonneg)
        self.declare_parameter("topics", list(DEFAULT_TOPICS), ro)
        self.declare_parameter("exclude", [""], ro)
        self.declare_parameter("discovery_period_wall_s", 0.5, ro)
        self.declare_parameter("flush_period_wall_s", 1.0, ro)
        self.declare_parameter("stop_drain_wall_s", 2.0, ro)
        self.declare_parameter("compress", True, ro)
        self.declare_parameter("stamp_wall_epoch", False, ro)
        self.declare_parameter("max_pending_mib", 64, nonneg)
        self.declare_parameter("geo_fixes", True, ro)
        p = {
            name: self.get_parameter(name).value
            for name in (
                "output",
                "scenario_file",
                "seed",
                "uav_count",
                "topics",
                "exclude",
                "discovery_period_wall_s",
                "flush_period_wall_s",
                "stop_drain_wall_s",
                "compress",
                "stamp_wall_epoch",
                "max_pending_mib",
                "geo_fixes",
            )
        }
        if not p["output"]:
            raise ConfigError("parameter output: required (the bag directory to create)")
        output = Path(str(p["output"])).expanduser()
        if output.exists():  # a refusal to overwrite a bag (exit status 1), not a bad value
            raise rec.BagError(f"parameter output: {output} exists already; refusing to overwrite a bag")
        if p["scenario_file"] and not Path(str(p["scenario_file"])).is_file():
            raise ConfigError(f"parameter scenario_file: {p['scenario_file']} is not a readable file")
        if int(p["uav_count"]) > MAX_UAV_COUNT:
            raise ConfigError(
                f"parameter uav_count: must be <= {MAX_UAV_COUNT} (uint8 ids), got {p['uav_count']}"
            )
        for name in ("discovery_period_wall_s", "flush_period_wall_s"):
            if not 0.01 <= float(p[name]) <= 60.0:
                raise ConfigError(f"parameter {name}: must be in [0.01, 60] s, got {p[name]}")
        if not 0.0 <= float(p["stop_drain_wall_s"]) <= 60.0:
            raise ConfigError(
                f"parameter stop_drain_wall_s: must be in [0, 60] s, got {p['stop_drain_wall_s']}"
            )
        include = [t for t in p["topics"] if t]
        if not include:
            raise ConfigError("parameter topics: empty; nothing would be recorded")
        return RecorderConfig(
            output=output,
            scenario_file=str(p["scenario_file"]),
            seed=int(p["seed"]),
            uav_count=int(p["uav_count"]),
            include=compile_patterns("topics", include, ConfigError),
            exclude=compile_patterns("exclude", [t for t in p["exclude"] if t], ConfigError),
            discovery_period_wall_s=float(p["discovery_period_wall_s"]),
            flush_period_wall_s=float(p["flush_period_wall_s"]),
            compress=bool(p["compress"]),
            stop_drain_wall_s=float(p["stop_drain_wall_s"]),
            stamp_wall_epoch=bool(p["stamp_wall_epoch"]),
            max_pending_bytes=int(p["max_pending_mib"]) * 2**20,
            geo_fixes=bool(p["geo_fixes"]),
        )

    def _geo_view(self) -> GeoView | None:
        """The NavSatFix source of a scenario on a landscape (None otherwise or if turned off)."""
        cfg = self.config
        if not (cfg.geo_fixes and cfg.scenario_file):
            return None
        try:
            frame = geo_frame_of_scenario_file(cfg.scenario_file)
        except Exception as err:  # a scenario or landscape error names what is wrong in one line
            raise ConfigError(
                f"parameter scenario_file: {cfg.scenario_file}: {' '.join(str(err).split())}"
            ) from None
        if frame is None:
            return None
        self.get_logger().info(
            f"landscape {frame.landscape}: true positions as NavSatFix on /uav_<k>/geo/truth_fix"
        )
        return GeoView(self._typestore, frame)

    def _custom_data(self) -> dict[str, str]:
        cfg = self.config
        text = Path(cfg.scenario_file).read_text(encoding="utf8") if cfg.scenario_file else ""
        return {
            rec.KEY_SCENARIO_FILE: cfg.scenario_file,
            rec.KEY_SCENARIO_YAML: text,
            rec.KEY_SEED: str(cfg.seed),
            rec.KEY_UAV_COUNT: str(cfg.uav_count),
            rec.KEY_SOFTWARE_VERSION: software_version(),
            rec.KEY_RECORDER_STARTED: _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            rec.KEY_LOG_TIME_OFFSET_NS: str(self._offset_ns),
        }

    # --- discovery and recording ---------------------------------------------------------
    def _discover(self) -> None:
        """Subscribe to every wanted topic that has publishers and is not yet recorded; give the
        up-front ones whose publishers appeared their connection."""
        self._follower.discover()

    def _on_topic(self, topic: RawTopic):
        conn = self._writer.add_connection(
            topic.name,
            topic.ros_type,
            typestore=self._typestore,
            offered_qos_profiles=[to_bag_qos(q) for q in topic.offered],
        )
        if topic.name == topics.WORLD_TRUTH and topic.ros_type == topics.WORLD_TRUTH_SPEC.type:
            return partial(self._on_truth, conn)
        if topic.name == topics.WORLD_EVENTS and topic.ros_type == topics.WORLD_EVENTS_SPEC.type:
            return partial(self._on_event, conn)
        return partial(self._on_message, conn)

    def _on_event(self, conn: object, data: bytes) -> None:
        """Write a ``/world/events`` message; a MISSION_COMPLETE names the final truth to expect."""
        self._on_message(conn, data)
        self.mission_end.on_event(data)

    def _on_truth(self, conn: object, data: bytes) -> None:
        """Write a ``/world/truth`` message, then (on a landscape) each vehicle's NavSatFix derived
        from it."""
        self._on_message(conn, data)
        self.mission_end.on_truth(data)
        if self._closed or self._geo is None:
            return
        try:
            fixes = self._geo.on_truth(bytes(data))
        except Exception as err:  # a malformed truth must not stop the recording
            self.get_logger().warning(
                f"no NavSatFix from a /world/truth message: {err}", throttle_duration_sec=10.0
            )
            return
        for name, cdr in fixes:
            fix_conn = self._fix_connections.get(name)
            if fix_conn is None:
                fix_conn = self._fix_connections[name] = self._writer.add_connection(
                    name,
                    NAVSAT_TYPE,
                    typestore=self._typestore,
                    # written by the recorder itself: the truth's QoS, as if published beside it
                    offered_qos_profiles=[to_bag_qos(topics.WORLD_TRUTH_SPEC.qos())],
                )
            self._on_message(fix_conn, cdr)

    def _on_message(self, conn: object, data: bytes) -> None:
        if self._closed:
            return
        if self._pending_bytes + len(data) > self.config.max_pending_bytes and self._stopping:
            self._flush()  # the last messages (take_queued): write the chunk out rather than drop
        elif self._pending_bytes + len(data) > self.config.max_pending_bytes:
            # a flood: drop with a counted warning rather than let the chunk buffer grow
            topic = getattr(conn, "topic", "?")
            self.messages_dropped[topic] = self.messages_dropped.get(topic, 0) + 1
            self.get_logger().warning(
                f"over the memory budget ({self.config.max_pending_bytes} B since the last flush): "
                f"dropped so far {self.messages_dropped}",
                throttle_duration_sec=2.0,
            )
            return
        self._writer.write(conn, self.get_clock().now().nanoseconds + self._offset_ns, data)  # type: ignore[arg-type]
        self._pending_bytes += len(data)
        self.messages_written += 1

    def _flush(self) -> None:
        if not self._closed:
            self._writer.flush()
            self._pending_bytes = 0

    def take_queued(
        self, cancelled: Callable[[], bool] = lambda: False, wait: Callable[[float], bool] | None = None
    ) -> int:
        """At a stop: write every message still queued in a subscription, log how many; returns
        the count. ``wait(timeout_s)``: the node's executor (:func:`executor_wait`), which wakes
        when a message comes; with it, once the world has announced the end of its mission
        (MISSION_COMPLETE), the recorder waits for that final step's ``/world/truth`` rather than
        for a quiet gap alone (:mod:`fire_uav_recording.stop_drain`). At most
        ``stop_drain_wall_s``, until ``cancelled()``; what is still missing then is named in a
        warning."""
        if self._closed:
            return 0
        self._stopping = True
        t0 = time.monotonic()
        taken, empty = self._follower.take_queued(
            self.config.stop_drain_wall_s, cancelled, wait=wait, expecting=self.mission_end.missing
        )
        n = sum(taken.values())
        busiest = ", ".join(f"{t} {k}" for t, k in sorted(taken.items(), key=lambda tk: -tk[1])[:5])
        why = "the queues are empty" if empty else "cut short (time cap or a second signal): more may be lost"
        # not the node's logger: the context may be shut down already (an external shutdown)
        log = rclpy.logging.get_logger("recorder")
        took_s = time.monotonic() - t0
        log.info(f"stop: took {n} queued messages in {took_s:.3f} s ({busiest or 'none'}); {why}")
        missing = self.mission_end.missing()
        if missing is not None:
            log.warning(f"stop: the bag lacks {missing}")
        return n

    def close_bag(self) -> None:
        """Write the MCAP summary/footer and the final metadata.yaml. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self._writer.close()
        # not the node's logger: after a signal the context is gone and rosout would complain
        rclpy.logging.get_logger("recorder.bag").info(
            f"closed {self.config.output}: {self.messages_written} messages on {len(self._follower.announced)} topics"
            f"; dropped over the memory budget: {self.messages_dropped or 'none'}"
        )


class StopSignals:
    """SIGINT/SIGTERM as a count: the handler only counts (it runs between two Python bytecodes,
    so it must not raise in the middle of a bag write, as rclpy's handlers would)."""

    def __init__(self) -> None:
        self.count = 0

    def __call__(self, signum: int, frame: object) -> None:
        self.count += 1

    def install(self) -> None:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, self)


def executor_wait(executor: Any) -> Callable[[float], bool]:
    """``wait(timeout_s)`` for :meth:`RecorderNode.take_queued`: one turn of ``executor`` (it
    returns when a subscription has a message, which its callback writes, or after ``timeout_s``
    [s, wall]); False once the context is shut down (nothing can wait on it any more)."""

    def wait(timeout_s: float) -> bool:
        try:
            executor.spin_once(timeout_sec=max(0.0, timeout_s))
        except ExternalShutdownException:
            return False
        return True

    return wait


def main(args: list[str] | None = None) -> int:
    """Run the recorder until SIGINT/SIGTERM. Exit status 0 on a clean stop; 2 on a bad parameter
    (one error line naming it, no bag made: a ``ConfigError`` of the node's checks, or a value
    rclpy refuses against the parameter's descriptor or type); 1 on a bag error (``output``
    exists already, the bag cannot be written or closed)."""
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = StopSignals()
    stop.install()
    node: RecorderNode | None = None
    executor = None
    rc = 0
    try:
        node = RecorderNode()
        executor = make_executor()
        executor.add_node(node)
        while not stop.count:
            executor.spin_once(timeout_sec=STOP_POLL_WALL_S)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except (ConfigError, InvalidParameterValueException, InvalidParameterTypeException) as err:
        rclpy.logging.get_logger("recorder").error(one_line(err))
        rc = EXIT_BAD_PARAMETER
    except rec.BagError as err:
        rclpy.logging.get_logger("recorder").error(str(err))
        rc = EXIT_BAG_ERROR
    except Exception:  # the context shut down (not by a signal) in the middle of a wait: a stop too
        if rclpy.ok():
            raise
    finally:
        if node is not None:
            try:
                # the executor still waits on the subscriptions: the drain wakes when a message comes
                wait = executor_wait(executor) if executor is not None else None
                node.take_queued(cancelled=lambda: stop.count > 1, wait=wait)
            except Exception as err:  # the bag is closed all the same
                rclpy.logging.get_logger("recorder").error(f"taking the queued messages failed: {err}")
                rc = EXIT_BAG_ERROR
            if executor is not None:
                executor.shutdown()
            try:
                node.close_bag()
            except Exception as err:
                rclpy.logging.get_logger("recorder").error(f"closing the bag failed: {err}")
                rc = EXIT_BAG_ERROR
            node.destroy_node()
        rclpy.try_shutdown()
    return rc


if __name__ == "__main__":
    sys.exit(main())
