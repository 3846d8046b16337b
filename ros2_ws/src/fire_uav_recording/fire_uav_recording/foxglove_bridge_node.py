"""Live bridge to Foxglove: every mission topic, raw CDR with its ros2msg schema, over Foxglove's
WebSocket protocol (the official ``foxglove-sdk`` server).

Parameters (all read once at start-up):
- ``host`` ("127.0.0.1"), ``port`` (8765; 0 = any free port, logged): where the server listens.
- ``topics`` (string[]): regular expressions; a topic is served if one matches it fully.
  Default: every recorded topic of ``fire_uav_common.topics`` (``/tf`` and ``/tf_static`` too).
- ``exclude`` (string[]): regular expressions of topics never served.
- ``discovery_period_wall_s`` (0.5): how often the graph is polled for new topics [s, wall].
- ``use_sim_time`` (true): the log time of each message is sim time (``/clock``) at receipt,
  and the server broadcasts ``/clock`` as its time (the ``time`` capability), so Foxglove's
  timeline is the mission's.
- ``scenario_file`` (""): the mission's scenario YAML; or ``bag`` (""): a mission bag, whose
  recorded scenario is taken (replay). On a landscape the bridge also serves the map view of
  :mod:`fire_uav_recording.geo` for Foxglove's Map panel: each UAV's TRUE position as
  ``sensor_msgs/NavSatFix`` on ``/uav_<k>/geo/truth_fix`` (from ``/world/truth``) and the burned
  and burning area as ``foxglove.GeoJSON`` on ``/geo/fire_area`` (from ``/viz/fire_grid``, at
  most once per ``fire_area_period_s`` (1.0) sim seconds). Both source topics must be served.
  ``uav_count`` (-1: the scenario's, or the bag's): the NavSatFix channels made at start-up, before
  any client connects (a channel made while a client is connected can be advertised to it before
  the server takes subscriptions to it: foxglove-sdk 0.30 then answers "Unknown channel ID").

Discovery, the QoS rule and the schema text are the recorder's
(:mod:`fire_uav_recording.raw_topics`): a Foxglove channel is announced with
``message_encoding="cdr"`` and ``Schema(name="pkg/msg/Type", encoding="ros2msg", data=...)``,
the same text the bag's schema record holds, and receives the subscription's bytes unchanged.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass

import foxglove
import foxglove.channels
import foxglove.messages
import rclpy
from fire_uav_common import topics
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter

import fire_uav_recording as rec
from fire_uav_recording.errors import ConfigError
from fire_uav_recording.geo import (
    FIRE_AREA_TOPIC,
    NAVSAT_TYPE,
    GeoFrame,
    GeoView,
    geo_frame_of_bag,
    geo_frame_of_scenario_file,
    truth_fix_topic,
)
from fire_uav_recording.raw_topics import (
    RawTopic,
    RawTopicFollower,
    compile_patterns,
    schema_text,
    topic_wanted,
)

DEFAULT_TOPICS = topics.recorded_patterns()  # what the recorder records, /tf and /tf_static included



@dataclass(frozen=True)
class BridgeConfig:
    host: str
    port: int
    include: tuple[re.Pattern[str], ...]
    exclude: tuple[re.Pattern[str], ...]
    discovery_period_wall_s: float
    scenario_file: str = ""
    bag: str = ""
    fire_area_period_s: float = 1.0
    uav_count: int = -1

    def wants(self, topic: str) -> bool:
        """Whether ``topic`` is served (full-match an include pattern and no exclude pattern)."""
        return topic_wanted(topic, self.include, self.exclude)


class FoxgloveBridgeNode(Node):
    """Serves every wanted topic on a Foxglove WebSocket server, raw CDR, log time = sim time."""

    def __init__(self) -> None:
        super().__init__(
            "foxglove_bridge",
            parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)],
        )
        self.config = self._read_config()
        self._typestore = rec.fleet_typestore()
        self._channels: dict[str, foxglove.Channel] = {}
        self.messages_sent = 0
        self.geo = self._geo_view()
        self._geo_channels: dict[str, foxglove.Channel] = {}
        self._area_channel: foxglove.channels.GeoJsonChannel | None = None
        if self.geo is not None:  # before the server: see uav_count in the module docstring
            n = self.config.uav_count if self.config.uav_count >= 0 else self.geo.frame.uav_count
            for k in range(n):
                self._fix_channel(truth_fix_topic(k))
            self._area_channel = foxglove.channels.GeoJsonChannel(FIRE_AREA_TOPIC)
        try:
            self.server = foxglove.start_server(
                name="fire_uav",
                host=self.config.host,
                port=self.config.port,
                capabilities=[foxglove.Capability.Time],
                supported_encodings=["cdr"],
            )
        except Exception as err:  # the SDK raises its own error type for a port in use
            raise ConfigError(
                f"parameters host/port: cannot listen on {self.config.host}:{self.config.port}: {err}"
            ) from None
        self._follower = RawTopicFollower(self, self.config.wants, self._typestore, self._on_topic)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(
            self.config.discovery_period_wall_s, self._follower.discover, clock=wall
        )
        self.get_logger().info(f"Foxglove WebSocket server on ws://{self.config.host}:{self.server.port}")
        self._follower.discover()

    def _read_config(self) -> BridgeConfig:
        ro = ParameterDescriptor(read_only=True)
        self.declare_parameter("host", "127.0.0.1", ro)
        self.declare_parameter(
            "port",
            8765,
            ParameterDescriptor(read_only=True, integer_range=[IntegerRange(from_value=0, to_value=65535)]),
        )
        self.declare_parameter("topics", list(DEFAULT_TOPICS), ro)
        self.declare_parameter("exclude", [""], ro)
        self.declare_parameter("discovery_period_wall_s", 0.5, ro)
        self.declare_parameter("scenario_file", "", ro)
        self.declare_parameter("bag", "", ro)
        self.declare_parameter("fire_area_period_s", 1.0, ro)
        self.declare_parameter(
            "uav_count", -1,
            ParameterDescriptor(read_only=True, integer_range=[IntegerRange(from_value=-1, to_value=255)]),
        )  # fmt: skip
        g = self.get_parameter
        period = float(g("discovery_period_wall_s").value)
        if not 0.01 <= period <= 60.0:
            raise ConfigError(
                f"parameter discovery_period_wall_s: must be in [0.01, 60] s, got {period}"
            )
        host = str(g("host").value)
        if not host:
            raise ConfigError("parameter host: empty (e.g. 127.0.0.1)")
        include = [t for t in g("topics").value if t]
        if not include:
            raise ConfigError("parameter topics: empty; nothing would be served")
        area_period = float(g("fire_area_period_s").value)
        if not 0.0 <= area_period <= 3600.0:
            raise ConfigError(f"parameter fire_area_period_s: must be in [0, 3600] s, got {area_period}")
        scenario_file, bag = str(g("scenario_file").value), str(g("bag").value)
        if scenario_file and bag:
            raise ConfigError("parameters scenario_file and bag: give one (the bag's scenario, or a file)")
        return BridgeConfig(
            scenario_file=scenario_file,
            bag=bag,
            fire_area_period_s=area_period,
            uav_count=int(g("uav_count").value),
            host=host,
            port=int(g("port").value),
            include=compile_patterns("topics", include, ConfigError),
            exclude=compile_patterns("exclude", [t for t in g("exclude").value if t], ConfigError),
            discovery_period_wall_s=period,
        )

    def _geo_view(self) -> GeoView | None:
        """The map view when the scenario is on a landscape (None otherwise); ConfigError naming
        the parameter when its scenario or bag cannot be read."""
        cfg = self.config
        name, path = ("scenario_file", cfg.scenario_file) if cfg.scenario_file else ("bag", cfg.bag)
        if not path:
            return None
        try:
            frame: GeoFrame | None = (
                geo_frame_of_scenario_file(path) if name == "scenario_file" else geo_frame_of_bag(path)
            )
        except Exception as err:  # a scenario, landscape or bag error: each says what is wrong in one line
            raise ConfigError(f"parameter {name}: {path}: {' '.join(str(err).split())}") from None
        if frame is None:
            return None
        self.get_logger().info(
            f"map view of landscape {frame.landscape}: true positions as NavSatFix on "
            f"/uav_<k>/geo/truth_fix, the burned area as GeoJSON on {FIRE_AREA_TOPIC}"
        )
        return GeoView(self._typestore, frame, cfg.fire_area_period_s)

    def _fix_channel(self, name: str) -> foxglove.Channel:
        """The NavSatFix channel ``name`` (made on first use)."""
        ch = self._geo_channels.get(name)
        if ch is None:
            ch = self._geo_channels[name] = foxglove.Channel(
                name,
                message_encoding="cdr",
                schema=foxglove.Schema(
                    name=NAVSAT_TYPE, encoding="ros2msg", data=schema_text(self._typestore, NAVSAT_TYPE).encode()
                ),
                metadata={"topic_type_hash": self._typestore.hash_rihs01(NAVSAT_TYPE)},
            )
        return ch

    def _log_geo(self, source: str, data: bytes, now_ns: int) -> None:
        """The map view's messages derived from one message of ``source``."""
        geo = self.geo
        assert geo is not None
        try:
            if source == topics.WORLD_TRUTH:
                for name, cdr in geo.on_truth(data):
                    self._fix_channel(name).log(cdr, log_time=now_ns)
                    self.messages_sent += 1
            else:
                text = geo.on_fire_grid(data)
                if text is not None:
                    if self._area_channel is None:
                        self._area_channel = foxglove.channels.GeoJsonChannel(FIRE_AREA_TOPIC)
                    self._area_channel.log(foxglove.messages.GeoJson(geojson=text), log_time=now_ns)
                    self.messages_sent += 1
        except Exception as err:  # a malformed message must not stop the raw topics
            self.get_logger().warning(
                f"map view: cannot convert a {source} message: {err}", throttle_duration_sec=10.0
            )

    def _on_topic(self, topic: RawTopic):
        try:
            text = schema_text(self._typestore, topic.ros_type)
        except rec.BagError as err:
            self.get_logger().warning(f"not serving {topic.name}: {err}")
            return None
        channel = foxglove.Channel(
            topic.name,
            message_encoding="cdr",
            schema=foxglove.Schema(name=topic.ros_type, encoding="ros2msg", data=text.encode()),
            metadata={"topic_type_hash": self._typestore.hash_rihs01(topic.ros_type)},
        )
        self._channels[topic.name] = channel
        is_clock = topic.name == topics.CLOCK_SPEC.name
        geo = self.geo is not None and topic.name in (topics.WORLD_TRUTH, topics.VIZ_FIRE_GRID)

        def forward(data: bytes) -> None:
            now_ns = self.get_clock().now().nanoseconds
            channel.log(bytes(data), log_time=now_ns)
            self.messages_sent += 1
            if is_clock:
                self.server.broadcast_time(now_ns)
            if geo:
                self._log_geo(topic.name, bytes(data), now_ns)

        return forward

    def close(self) -> None:
        """Stop the server (idempotent)."""
        server, self.server = getattr(self, "server", None), None
        if server is not None:
            server.stop()


def main(args: list[str] | None = None) -> int:
    """Serve until SIGINT/SIGTERM; 0 on a clean stop, 1 on a bad parameter."""
    rclpy.init(args=args)
    node: FoxgloveBridgeNode | None = None
    rc = 0
    try:
        node = FoxgloveBridgeNode()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ConfigError as err:
        rclpy.logging.get_logger("foxglove_bridge").error(str(err))
        rc = 1
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
