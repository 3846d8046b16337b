"""Live bridge to Foxglove: every mission topic, raw CDR with its ros2msg schema, over Foxglove's
WebSocket protocol (the official ``foxglove-sdk`` server).

Parameters (all read once at start-up; a bad one is one error line naming it and exit status 2,
:func:`main`):
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
- ``uav_count`` (-1: the scenario's, or the bag's): the fleet whose topics get their channels at
  start-up (below), and on a landscape the NavSatFix channels made then.

Channels made before any client connects: a channel made while a client is connected can be
advertised to it a moment before the server takes subscriptions to it, and a client that
subscribes at once (as Foxglove does) is then answered "Unknown channel ID" and never gets a
message of it (foxglove-sdk 0.30.3: 14 of 300 channels made while a client subscribed to each
advertisement at once; none of 300 made before it connected; the same subscription sent again
50 ms later is taken). So before the server starts the bridge makes the channel of every wanted
fleet topic (``fire_uav_common.topics``, the per-vehicle ones for vehicles
``0 .. uav_count - 1``, the fleet the scenario or bag names when ``uav_count`` is -1;
:func:`up_front_topics`), with the spec's type: a client
connecting at any moment of a mission subscribes to ``/tf`` and ``/viz/world`` when it connects,
before their first message. Such a channel is advertised even while nobody publishes its topic
(an empty topic in Foxglove). A topic found later (a foreign name, a vehicle beyond
``uav_count``, a fleet name published with another type, or any topic when no fleet size is
known) gets its channel when discovery finds it, and a client connected at that moment may
still meet the SDK's race on it.

Discovery, the QoS rule and the schema text are the recorder's
(:mod:`fire_uav_recording.raw_topics`): a Foxglove channel is announced with
``message_encoding="cdr"`` and ``Schema(name="pkg/msg/Type", encoding="ros2msg", data=...)``,
the same text the bag's schema record holds, and receives the subscription's bytes unchanged.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Callable
from dataclasses import dataclass

import foxglove
import foxglove.channels
import foxglove.messages
import rclpy
from fire_uav_common import topics
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter

import fire_uav_recording as rec
from fire_uav_recording.errors import EXIT_BAD_PARAMETER, ConfigError, one_line
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
    fleet_topic_names,
    schema_text,
    spec_of,
    topic_wanted,
)

DEFAULT_TOPICS = topics.recorded_patterns()  # what the recorder records, /tf and /tf_static included


def up_front_topics(uav_count: int, wants: Callable[[str], bool]) -> list[tuple[str, str]]:
    """(topic, ``pkg/msg/Type``) of every fleet topic the bridge serves from start-up: each name
    of ``fire_uav_common.topics`` in a fleet of ``uav_count`` vehicles that ``wants``, with its
    spec's type, in the table's order (module docstring: why before the server starts)."""
    out = []
    for name in fleet_topic_names(uav_count):
        spec = spec_of(name)
        if spec is not None and wants(name):
            out.append((name, spec.type))
    return out


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
        self._foxglove_context = foxglove.Context()  # this node's channels and server only
        self._channels: dict[str, foxglove.Channel] = {}
        self.messages_sent = 0
        self.geo = self._geo_view()
        self._geo_channels: dict[str, foxglove.Channel] = {}
        self._area_channel: foxglove.channels.GeoJsonChannel | None = None
        # every channel known in advance is made before the server starts (module docstring)
        n = self._fleet_size()  # known whenever there is a map view
        if n is not None:
            for name, ros_type in up_front_topics(n, self.config.wants):
                self._raw_channel(name, ros_type)
            if self.geo is not None:
                for k in range(n):
                    self._fix_channel(truth_fix_topic(k))
                self._area_channel = foxglove.channels.GeoJsonChannel(
                    FIRE_AREA_TOPIC, context=self._foxglove_context
                )
        try:
            self.server = foxglove.start_server(
                name="fire_uav",
                host=self.config.host,
                port=self.config.port,
                capabilities=[foxglove.Capability.Time],
                supported_encodings=["cdr"],
                context=self._foxglove_context,
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
            raise ConfigError(f"parameter discovery_period_wall_s: must be in [0.01, 60] s, got {period}")
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

    def _fleet_size(self) -> int | None:
        """The fleet whose topics get their channels at start-up: ``uav_count``, else the
        scenario's (``scenario_file``) or the recorded one (``bag``'s metadata); None when none is
        known. ConfigError naming the parameter when the scenario cannot be read."""
        cfg = self.config
        if cfg.uav_count >= 0:
            return cfg.uav_count
        if self.geo is not None:
            return self.geo.frame.uav_count
        if cfg.bag:  # read by _geo_view already: a bad bag was named there
            text = rec.inspect_bag(cfg.bag).custom_data.get(rec.KEY_UAV_COUNT, "")
            return int(text) if text.isdigit() else None
        if cfg.scenario_file:
            from fire_uav_common.scenario import load_scenario

            try:
                return int(load_scenario(cfg.scenario_file).uavs.count)
            except Exception as err:  # the loader's errors say what is wrong in one line
                raise ConfigError(f"parameter scenario_file: {' '.join(str(err).split())}") from None
        return None

    def _raw_channel(self, name: str, ros_type: str) -> foxglove.Channel | None:
        """The raw CDR channel of topic ``name`` with type ``ros_type``: the one made before (at
        start-up) when its type is that, else a new one (replacing one of another type); None
        (logged) when the type has no definition."""
        old = self._channels.get(name)
        if old is not None and old.schema_name() == ros_type:
            return old
        try:
            text = schema_text(self._typestore, ros_type)
        except rec.BagError as err:
            self.get_logger().warning(f"not serving {name}: {err}")
            return None
        if old is not None:  # a fleet name published with another type than the spec's
            self.get_logger().warning(f"serving {name} as {ros_type}, not the fleet's {old.schema_name()}")
            old.close()
        channel = self._channels[name] = foxglove.Channel(
            name,
            message_encoding="cdr",
            schema=foxglove.Schema(name=ros_type, encoding="ros2msg", data=text.encode()),
            metadata={"topic_type_hash": self._typestore.hash_rihs01(ros_type)},
            context=self._foxglove_context,
        )
        return channel

    def _fix_channel(self, name: str) -> foxglove.Channel:
        """The NavSatFix channel ``name`` (made on first use)."""
        ch = self._geo_channels.get(name)
        if ch is None:
            ch = self._geo_channels[name] = foxglove.Channel(
                name,
                message_encoding="cdr",
                schema=foxglove.Schema(
                    name=NAVSAT_TYPE,
                    encoding="ros2msg",
                    data=schema_text(self._typestore, NAVSAT_TYPE).encode(),
                ),
                metadata={"topic_type_hash": self._typestore.hash_rihs01(NAVSAT_TYPE)},
                context=self._foxglove_context,
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
                        self._area_channel = foxglove.channels.GeoJsonChannel(
                            FIRE_AREA_TOPIC, context=self._foxglove_context
                        )
                    self._area_channel.log(foxglove.messages.GeoJson(geojson=text), log_time=now_ns)
                    self.messages_sent += 1
        except Exception as err:  # a malformed message must not stop the raw topics
            self.get_logger().warning(
                f"map view: cannot convert a {source} message: {err}", throttle_duration_sec=10.0
            )

    def _on_topic(self, topic: RawTopic) -> Callable[[bytes], None] | None:
        channel = self._raw_channel(topic.name, topic.ros_type)
        if channel is None:
            return None
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
    """Serve until SIGINT/SIGTERM. Exit status 0 on a clean stop; 2 on a bad parameter (one error
    line naming it: a ``ConfigError`` of the node's checks, its ``scenario_file`` or ``bag`` that
    cannot be read, ``host``/``port`` it cannot listen on, or a value rclpy refuses against the
    parameter's descriptor or type)."""
    rclpy.init(args=args)
    node: FoxgloveBridgeNode | None = None
    rc = 0
    try:
        node = FoxgloveBridgeNode()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except (ConfigError, InvalidParameterValueException, InvalidParameterTypeException) as err:
        rclpy.logging.get_logger("foxglove_bridge").error(one_line(err))
        rc = EXIT_BAD_PARAMETER
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
