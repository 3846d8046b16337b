"""Mission recorder: every mission topic, raw CDR, into a rosbag2 directory with MCAP storage.

Parameters (all read once at start-up):
- ``output`` (string, required): bag directory to create; an existing path is an error.
- ``scenario_file`` (string): scenario YAML, stored verbatim in the bag's metadata.
- ``seed`` (int >= 0), ``uav_count`` (int >= 0): stored in the bag's metadata.
- ``topics`` (string[]): regular expressions; a topic is recorded if one matches it fully.
  Default: every recorded topic of ``fire_uav_common.topics`` (``recorded_patterns()``).
- ``exclude`` (string[]): regular expressions of topics never recorded.
- ``discovery_period_wall_s`` (0.5): how often the graph is polled for new topics [s, wall].
- ``flush_period_wall_s`` (1.0): how often the open MCAP chunk is written out [s, wall];
  a SIGKILL loses at most this much.
- ``compress`` (true): zstd-compressed MCAP chunks.
- ``use_sim_time`` (true): bag timestamps are sim time (``/clock``) at receipt.

Messages are stamped with the node clock at receipt (sim time by default). A topic of
``fire_uav_common.topics`` is subscribed with its spec's QoS (depth at least 100, so a burst
is not dropped while the bag is flushed); any other topic with the QoS its publishers offer
(rosbag2's adaptive rule). Either way the subscription is made compatible with every offered
profile: best effort if a publisher is, volatile unless every publisher is transient local.
"""

from __future__ import annotations

import datetime as _dt
import importlib
import re
import sys
from dataclasses import dataclass
from functools import partial
from importlib import metadata as _im
from pathlib import Path

import rclpy
from fire_uav_common import topics
from fire_uav_common.stamps import NS_PER_S
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

import fire_uav_recording as rec

DEFAULT_TOPICS = topics.recorded_patterns()
MIN_DEPTH = 100  # recorder queue depth floor per topic [messages]
_INF_SEC, _INF_NSEC = 2147483647, 4294967295  # rosbag2's spelling of an infinite duration


class RecorderConfigError(ValueError):
    """A recorder parameter is invalid (message names the parameter)."""


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

    def wants(self, topic: str) -> bool:
        """Whether ``topic`` is recorded (full-match an include pattern and no exclude pattern)."""
        return any(p.fullmatch(topic) for p in self.include) and not any(
            p.fullmatch(topic) for p in self.exclude
        )


def _compile(name: str, patterns: list[str]) -> tuple[re.Pattern[str], ...]:
    out = []
    for p in patterns:
        try:
            out.append(re.compile(p))
        except re.error as err:
            raise RecorderConfigError(f"parameter {name}: bad regular expression {p!r}: {err}") from None
    return tuple(out)


def software_version() -> str:
    """``fire_uav_recording <v>; fire_world_sim <v>; rosbags <v>`` (installed distribution versions)."""
    parts = []
    for dist in ("fire_uav_recording", "fire_world_sim", "rosbags"):
        try:
            parts.append(f"{dist} {_im.version(dist)}")
        except _im.PackageNotFoundError:
            parts.append(f"{dist} unknown")
    return "; ".join(parts)


def to_bag_qos(profile: QoSProfile) -> Qos:
    """rclpy QoS profile -> rosbags Qos (the enums share rmw's numbering)."""

    def dur(d: object) -> QosTime:
        ns = int(getattr(d, "nanoseconds", 0))
        if ns <= 0 or ns >= 2**63 - 1 or ns // NS_PER_S > _INF_SEC:
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


def spec_of(topic: str) -> topics.TopicSpec | None:
    """The fleet's spec of ``topic`` (``None`` for a topic fire_uav_common does not declare)."""
    try:
        return topics.topic_by_name(topic)
    except KeyError:
        return None


def subscription_qos(offered: list[QoSProfile], spec: topics.TopicSpec | None = None) -> QoSProfile:
    """A subscription QoS that matches every offered publisher profile.

    Starts from ``spec.qos()`` (depth at least :data:`MIN_DEPTH`) when the topic has a spec, else
    from rosbag2's adaptive rule; then gives up reliability / transient local where a
    publisher does not offer it (a stricter subscription would never match that publisher).
    """
    best_effort = any(p.reliability == ReliabilityPolicy.BEST_EFFORT for p in offered)
    transient = bool(offered) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in offered)
    if spec is not None:
        want = spec.qos()
        best_effort = best_effort or want.reliability == ReliabilityPolicy.BEST_EFFORT
        transient = transient and want.durability == DurabilityPolicy.TRANSIENT_LOCAL
        depth = max(MIN_DEPTH, int(want.depth))
    else:
        depth = max([1000 if transient else MIN_DEPTH, *[int(p.depth) for p in offered]])
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE,
    )


def message_class(ros_type: str) -> type:
    """``pkg/msg/Name`` -> the generated Python class (ImportError/AttributeError if not installed).

    For types no spec of fire_uav_common.topics names (the recorder records what it finds).
    """
    pkg, kind, name = ros_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)


class RecorderNode(Node):
    """Subscribes raw to every mission topic as it appears and writes it into one MCAP bag."""

    def __init__(self) -> None:
        super().__init__(
            "recorder",
            parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)],
            allow_undeclared_parameters=False,
        )
        self.config = self._read_config()
        self._subs: dict[str, object] = {}
        self._skipped: set[str] = set()
        self._typestore = rec.fleet_typestore()
        self._writer = rec.BagWriter(
            self.config.output, custom_data=self._custom_data(), compress=self.config.compress
        )
        self._writer.open()
        self._closed = False
        self.messages_written = 0
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
        self.declare_parameter("compress", True, ro)
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
                "compress",
            )
        }
        if not p["output"]:
            raise RecorderConfigError("parameter output: required (the bag directory to create)")
        output = Path(str(p["output"])).expanduser()
        if output.exists():
            raise RecorderConfigError(
                f"parameter output: {output} exists already; refusing to overwrite a bag"
            )
        if p["scenario_file"] and not Path(str(p["scenario_file"])).is_file():
            raise RecorderConfigError(f"parameter scenario_file: {p['scenario_file']} is not a readable file")
        for name in ("discovery_period_wall_s", "flush_period_wall_s"):
            if not 0.01 <= float(p[name]) <= 60.0:
                raise RecorderConfigError(f"parameter {name}: must be in [0.01, 60] s, got {p[name]}")
        include = [t for t in p["topics"] if t]
        if not include:
            raise RecorderConfigError("parameter topics: empty; nothing would be recorded")
        return RecorderConfig(
            output=output,
            scenario_file=str(p["scenario_file"]),
            seed=int(p["seed"]),
            uav_count=int(p["uav_count"]),
            include=_compile("topics", include),
            exclude=_compile("exclude", [t for t in p["exclude"] if t]),
            discovery_period_wall_s=float(p["discovery_period_wall_s"]),
            flush_period_wall_s=float(p["flush_period_wall_s"]),
            compress=bool(p["compress"]),
        )

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
        }

    # --- discovery and recording ---------------------------------------------------------
    def _discover(self) -> None:
        """Subscribe to every wanted topic that has publishers and is not yet recorded."""
        for topic, types in self.get_topic_names_and_types():
            if topic in self._subs or topic in self._skipped or not self.config.wants(topic):
                continue
            pubs = self.get_publishers_info_by_topic(topic)
            if not pubs:
                continue  # only subscribers so far: wait for a publisher to learn its QoS
            if len(types) != 1:
                self._skip(topic, f"has {len(types)} types {types}; recording none")
                continue
            ros_type = types[0]
            spec = spec_of(topic)
            if spec is not None and spec.type != ros_type:
                spec = None  # someone publishes another type under a fleet name: record it as it is
            if not rec.ensure_type(self._typestore, ros_type):
                self._skip(topic, f"type {ros_type} has no .msg definition in AMENT_PREFIX_PATH")
                continue
            try:
                cls = spec.msg_class() if spec is not None else message_class(ros_type)
            except (ImportError, AttributeError, ValueError) as err:
                self._skip(topic, f"type {ros_type} not importable: {err}")
                continue
            offered = [p.qos_profile for p in pubs]
            conn = self._writer.add_connection(
                topic,
                ros_type,
                typestore=self._typestore,
                offered_qos_profiles=[to_bag_qos(q) for q in offered],
            )
            qos = subscription_qos(offered, spec)
            self._subs[topic] = self.create_subscription(
                cls, topic, partial(self._on_message, conn), qos, raw=True
            )
            self.get_logger().info(
                f"recording {topic} [{ros_type}] ({qos.reliability.name.lower()}, {qos.durability.name.lower()})"
            )

    def _skip(self, topic: str, why: str) -> None:
        self._skipped.add(topic)
        self.get_logger().warning(f"not recording {topic}: {why}")

    def _on_message(self, conn: object, data: bytes) -> None:
        if self._closed:
            return
        self._writer.write(conn, self.get_clock().now().nanoseconds, data)  # type: ignore[arg-type]
        self.messages_written += 1

    def _flush(self) -> None:
        if not self._closed:
            self._writer.flush()

    def close_bag(self) -> None:
        """Write the MCAP summary/footer and the final metadata.yaml. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self._writer.close()
        # not the node's logger: after a signal the context is gone and rosout would complain
        rclpy.logging.get_logger("recorder.bag").info(
            f"closed {self.config.output}: {self.messages_written} messages on {len(self._subs)} topics"
        )


def main(args: list[str] | None = None) -> int:
    """Run the recorder until SIGINT/SIGTERM; 0 on a clean stop, 1 on a configuration or bag error."""
    rclpy.init(args=args)
    node: RecorderNode | None = None
    rc = 0
    try:
        node = RecorderNode()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except (RecorderConfigError, rec.BagError) as err:
        rclpy.logging.get_logger("recorder").error(str(err))
        rc = 1
    except Exception:  # a signal may shut the context down in the middle of a wait: that is a stop too
        if rclpy.ok():
            raise
    finally:
        if node is not None:
            try:
                node.close_bag()
            except Exception as err:
                rclpy.logging.get_logger("recorder").error(f"closing the bag failed: {err}")
                rc = 1
            node.destroy_node()
        rclpy.try_shutdown()
    return rc


if __name__ == "__main__":
    sys.exit(main())
