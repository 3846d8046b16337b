"""Every topic of the fleet, paired with its type, QoS and loss-draw index, in one place.

One :class:`TopicSpec` per topic, so a topic's name, type and QoS change in one place. Every node, the runner and the
recorder take names, types and QoS from here: ``create_publisher(spec.msg_class(), spec.name,
spec.qos())``, or the helpers :func:`publisher` / :func:`subscription`. Per-vehicle topics are
relative names under the ``uav_<k>`` namespace; :meth:`TopicSpec.for_uav` gives the absolute
form for nodes outside that namespace (the world, the recorder).

``loss_index`` is the topic's index in the seeded loss draw of the peer link
(``rng.bernoulli(p, seed, "loss", sender, receiver, step, loss_index)``): every peer-to-peer topic
has one, every other topic ``None``.

This module imports rclpy only when asked for a QoS profile or a message class, so the names
can be used from ROS-free code too.
"""

from __future__ import annotations

import importlib
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .errors import TopicError, UnknownTopicError

if TYPE_CHECKING:  # pragma: no cover
    from rclpy.qos import QoSProfile

__all__ = [
    "ALL_TOPICS",
    "QOS_KINDS",
    "TopicSpec",
    "publisher",
    "qos",
    "recorded_patterns",
    "subscription",
    "topic_by_name",
    "uav_namespace",
    "uav_topic",
]

UAV_NAMESPACE = "uav_{k}"

#: QoS kind -> (reliable, transient_local, depth); see :func:`qos`
QOS_KINDS: dict[str, tuple[bool, bool, int]] = {
    "lockstep": (True, False, 100),
    "clock": (True, False, 10),
    "fleet": (True, False, 5000),
    "events": (True, True, 1000),
    "truth": (True, False, 1000),
    "viz": (False, False, 5),
    "latched": (True, True, 1),
    "tf": (True, False, 100),
}


def qos(kind: str) -> QoSProfile:
    """QoS profile for a class of topic.

    - ``"lockstep"``: sensors, commands, payload: reliable, depth 100 (the world waits for them).
    - ``"clock"``: ``/clock``: reliable, depth 10.
    - ``"fleet"``: peer-to-peer state: reliable, depth 5000. The injected loss is applied on
      receipt (per directed link, seeded, so runs repeat), and the lockstep wait counts every message a peer announced,
      so the transport must never drop one: a depth-100 history dropped the oldest samples of
      a burst (the CP MST phase sends ~100 messages in one step) and the fleet waited for them
      for ever. KEEP_ALL is no answer either: Fast DDS then blocks and fails ``publish`` once
      400 samples are unacknowledged. 5000 is far above any step's burst.
    - ``"events"``: reliable + transient local, depth 1000: a late recorder still gets them.
    - ``"truth"``: reliable, depth 1000 (nothing recorded is lost when the recorder lags).
    - ``"viz"``: best effort, depth 5.
    - ``"latched"``: reliable + transient local, depth 1 (static data such as ``/tf_static``).
    - ``"tf"``: ``/tf``: reliable, volatile, depth 100 (tf2's broadcaster default).
    """
    if kind not in QOS_KINDS:
        raise TopicError(f"unknown QoS kind {kind!r}; expected one of {sorted(QOS_KINDS)}")
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    reliable, transient, depth = QOS_KINDS[kind]
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE,
    )


def uav_namespace(uav_id: int) -> str:
    """Namespace of vehicle ``uav_id``, e.g. ``/uav_3``."""
    if uav_id < 0:
        raise TopicError(f"uav_id must be >= 0, got {uav_id}")
    return "/" + UAV_NAMESPACE.format(k=uav_id)


def uav_topic(uav_id: int, name: str) -> str:
    """Absolute name of a per-vehicle topic, e.g. ``uav_topic(3, SENSORS.name) == '/uav_3/sensors'``."""
    return f"{uav_namespace(uav_id)}/{name}"


@dataclass(frozen=True)
class TopicSpec:
    """One topic: name, ROS type (``pkg/msg/Name``), QoS kind and loss-draw index.

    ``name`` is absolute (``/fleet/state``) or, for per-vehicle topics (``per_uav``), relative to
    the ``uav_<k>`` namespace (``sensors``).
    """

    name: str
    type: str
    qos_kind: str
    per_uav: bool = False
    loss_index: int | None = None
    recorded: bool = True
    doc: str = ""

    def __post_init__(self) -> None:
        if self.qos_kind not in QOS_KINDS:
            raise TopicError(f"topic {self.name}: unknown QoS kind {self.qos_kind!r}")
        if self.per_uav == self.name.startswith("/"):
            raise TopicError(f"topic {self.name}: per-vehicle names are relative, others absolute")

    @property
    def draw_index(self) -> int:
        """The loss index of a peer topic (ValueError for a topic that has none)."""
        if self.loss_index is None:
            raise TopicError(f"topic {self.name} is not a peer topic: it has no loss index")
        return self.loss_index

    def qos(self) -> QoSProfile:
        """The topic's rclpy QoS profile."""
        return qos(self.qos_kind)

    def msg_class(self) -> Any:
        """The generated Python message class (imports the message package)."""
        pkg, kind, cls = self.type.split("/")
        return getattr(importlib.import_module(f"{pkg}.{kind}"), cls)

    def for_uav(self, uav_id: int) -> str:
        """Absolute name for vehicle ``uav_id`` (per-vehicle topics only)."""
        if not self.per_uav:
            raise TopicError(f"topic {self.name} is not a per-vehicle topic")
        return uav_topic(uav_id, self.name)

    def pattern(self) -> str:
        """Regular expression of every absolute name of this topic (for the recorder)."""
        if self.per_uav:
            return r"/uav_\d+/" + re.escape(self.name)
        return re.escape(self.name)


# --- the topics ----------------------------------------------------------------------------
CLOCK_SPEC = TopicSpec("/clock", "rosgraph_msgs/msg/Clock", "clock", doc="world -> all")
# per vehicle, relative to the uav_<k> namespace
SENSORS_SPEC = TopicSpec("sensors", "fire_uav_msgs/msg/SensorBundle", "lockstep", per_uav=True,
                         doc="world -> agent k")  # fmt: skip
CMD_SPEC = TopicSpec(
    "cmd", "geometry_msgs/msg/TwistStamped", "lockstep", per_uav=True, doc="agent k -> world"
)
PAYLOAD_SPEC = TopicSpec("payload", "fire_uav_msgs/msg/PayloadRequest", "lockstep", per_uav=True,
                         doc="agent k -> world")  # fmt: skip
VIZ_AGENT_SPEC = TopicSpec("viz", "visualization_msgs/msg/MarkerArray", "viz", per_uav=True,
                           doc="agent k -> RViz/Foxglove")  # fmt: skip
# fleet (peer-to-peer), absolute; loss_index: the topic's index in the peer link's loss draw
FLEET_STATE_SPEC = TopicSpec("/fleet/state", "fire_uav_msgs/msg/UavState", "fleet", loss_index=0)
# /fleet/fires: the fleet's fire picture rides in UavState (one peer message per step instead of
# two, which halves the messages a 20-UAV fleet exchanges); loss_index 1 is that part's own loss draw and lockstep count. Nothing of the fleet
# publishes on the topic any more; it stays for bags recorded before and for tools.
FLEET_FIRES_SPEC = TopicSpec("/fleet/fires", "fire_uav_msgs/msg/FireEstimateArray", "fleet", loss_index=1)
FLEET_PERIMETER_SPEC = TopicSpec("/fleet/perimeter", "fire_uav_msgs/msg/PerimeterMap", "fleet", loss_index=2)
FLEET_EVENTS_SPEC = TopicSpec("/fleet/events", "fire_uav_msgs/msg/MissionEvent", "events",
                              doc="agents' own decisions")  # fmt: skip
COVERAGE_WEIGHTS_SPEC = TopicSpec("/fleet/coverage/weights", "fire_uav_msgs/msg/CoverageWeight", "fleet",
                                  loss_index=3)  # fmt: skip
COVERAGE_CANDIDATES_SPEC = TopicSpec("/fleet/coverage/candidates", "fire_uav_msgs/msg/CoverageCandidate",
                                     "fleet", loss_index=4)  # fmt: skip
COVERAGE_MST_SPEC = TopicSpec("/fleet/coverage/mst", "fire_uav_msgs/msg/MstFragment", "fleet", loss_index=5)
FLEET_FRONT_SPEC = TopicSpec("/fleet/front", "fire_uav_msgs/msg/FireFront", "fleet", loss_index=6,
                             doc="raster fire front pictures")  # fmt: skip
# world, absolute (agents never subscribe to these)
WORLD_TRUTH_SPEC = TopicSpec("/world/truth", "fire_uav_msgs/msg/WorldTruth", "truth", doc="world -> recorder")
WORLD_EVENTS_SPEC = TopicSpec("/world/events", "fire_uav_msgs/msg/MissionEvent", "events")
# the fire type per cell of a fire on a landscape (a world without one never publishes it, so
# its record is as before): its own topic, as /world/truth's messages stay the same for all
WORLD_FIRE_TYPE_SPEC = TopicSpec("/world/fire_type", "nav_msgs/msg/OccupancyGrid", "truth",
                                 doc="world -> recorder: 0 not burnt, 1 surface, 2 passive crown, 3 active crown")  # fmt: skip
VIZ_WORLD_SPEC = TopicSpec("/viz/world", "visualization_msgs/msg/MarkerArray", "viz")
VIZ_FIRE_GRID_SPEC = TopicSpec("/viz/fire_grid", "nav_msgs/msg/OccupancyGrid", "viz")
VIZ_PERIMETER_SPEC = TopicSpec("/viz/perimeter", "visualization_msgs/msg/MarkerArray", "viz",
                               doc="perimeter_viewer -> RViz/Foxglove")  # fmt: skip
# transforms (REP 105 style: map -> uav_<k> from the truth, map -> uav_<k>/estimate from agent k)
TF_SPEC = TopicSpec("/tf", "tf2_msgs/msg/TFMessage", "tf", doc="world, agents -> RViz/Foxglove")
TF_STATIC_SPEC = TopicSpec("/tf_static", "tf2_msgs/msg/TFMessage", "latched", doc="world -> RViz/Foxglove")

ALL_TOPICS: tuple[TopicSpec, ...] = (
    CLOCK_SPEC, SENSORS_SPEC, CMD_SPEC, PAYLOAD_SPEC, VIZ_AGENT_SPEC,
    FLEET_STATE_SPEC, FLEET_FIRES_SPEC, FLEET_PERIMETER_SPEC, FLEET_EVENTS_SPEC,
    COVERAGE_WEIGHTS_SPEC, COVERAGE_CANDIDATES_SPEC, COVERAGE_MST_SPEC,
    WORLD_TRUTH_SPEC, WORLD_EVENTS_SPEC, WORLD_FIRE_TYPE_SPEC, VIZ_WORLD_SPEC, VIZ_FIRE_GRID_SPEC, VIZ_PERIMETER_SPEC,
    FLEET_FRONT_SPEC,
    TF_SPEC, TF_STATIC_SPEC,
)  # fmt: skip

# Plain names, kept for call sites that only need the string (the spec is the source).
CLOCK = CLOCK_SPEC.name
SENSORS = SENSORS_SPEC.name
CMD = CMD_SPEC.name
PAYLOAD = PAYLOAD_SPEC.name
VIZ_AGENT = VIZ_AGENT_SPEC.name
FLEET_STATE = FLEET_STATE_SPEC.name
FLEET_FIRES = FLEET_FIRES_SPEC.name
FLEET_PERIMETER = FLEET_PERIMETER_SPEC.name
FLEET_EVENTS = FLEET_EVENTS_SPEC.name
COVERAGE_WEIGHTS = COVERAGE_WEIGHTS_SPEC.name
COVERAGE_CANDIDATES = COVERAGE_CANDIDATES_SPEC.name
COVERAGE_MST = COVERAGE_MST_SPEC.name
WORLD_TRUTH = WORLD_TRUTH_SPEC.name
WORLD_EVENTS = WORLD_EVENTS_SPEC.name
WORLD_FIRE_TYPE = WORLD_FIRE_TYPE_SPEC.name
VIZ_WORLD = VIZ_WORLD_SPEC.name
VIZ_FIRE_GRID = VIZ_FIRE_GRID_SPEC.name
VIZ_PERIMETER = VIZ_PERIMETER_SPEC.name
FLEET_FRONT = FLEET_FRONT_SPEC.name
TF = TF_SPEC.name
TF_STATIC = TF_STATIC_SPEC.name


def topic_by_name(name: str) -> TopicSpec:
    """The spec of an absolute topic name (``/uav_3/cmd`` -> :data:`CMD_SPEC`); KeyError if unknown."""
    for spec in ALL_TOPICS:
        if re.fullmatch(spec.pattern(), name):
            return spec
    raise UnknownTopicError(f"no topic {name!r} in fire_uav_common.topics")


def recorded_patterns() -> tuple[str, ...]:
    """Regular expressions of every recorded topic (the recorder's default include list)."""
    return tuple(spec.pattern() for spec in ALL_TOPICS if spec.recorded)


# Quiet endpoints: the helpers below create their endpoints without rclpy's default QoS-event
# handlers. rclpy gives every publisher and subscription two (incompatible QoS, incompatible type), each a
# waitable that the executor adds to, and checks in, every wait set in Python: ~140 of them in a
# 20-UAV world node, for events that cannot happen between endpoints that all take their QoS and
# type from this table (docs/profile.md). A tool that subscribes with an
# incompatible QoS still gets the warning from its own subscription's default handler.


def publisher(node: Any, spec: TopicSpec, uav_id: int | None = None) -> Any:
    """``node.create_publisher`` for ``spec`` (absolute per-vehicle name when ``uav_id`` is given)."""
    from rclpy.event_handler import PublisherEventCallbacks

    name = spec.for_uav(uav_id) if uav_id is not None else spec.name
    quiet = PublisherEventCallbacks(use_default_callbacks=False)  # quiet endpoints (above)
    return node.create_publisher(spec.msg_class(), name, spec.qos(), event_callbacks=quiet)


def subscription(
    node: Any, spec: TopicSpec, callback: Any, uav_id: int | None = None, *, drain: bool = False, **kw: Any
) -> Any:
    """``node.create_subscription`` for ``spec`` (absolute per-vehicle name when ``uav_id`` is given).

    ``drain=True``: see :func:`drain_queue` (for topics many peers publish on every step).
    """
    from rclpy.event_handler import SubscriptionEventCallbacks

    name = spec.for_uav(uav_id) if uav_id is not None else spec.name
    quiet = SubscriptionEventCallbacks(use_default_callbacks=False)  # quiet endpoints (above)
    kw.setdefault("event_callbacks", quiet)
    sub = node.create_subscription(spec.msg_class(), name, callback, spec.qos(), **kw)
    return drain_queue(sub) if drain else sub


DRAIN_LIMIT = 64
"""At most this many further messages taken by one drained callback (others' turn comes after)."""


def drain_queue(sub: Any, limit: int = DRAIN_LIMIT) -> Any:
    """Make ``sub``'s callback also take and handle the messages already queued behind its own.

    rclpy's executor takes one message per ready subscription per wait, and rebuilds the wait set
    (Python bookkeeping over every entity of the node) for the next: an agent of a 20-UAV fleet
    got ~40 peer messages per step on two topics, so ~20 waits per step
    (docs/profile.md). A drained subscription handles its whole queue in the one callback, in
    arrival order, as the executor would have, through the same ``take_message``; a message rclpy
    cannot convert raises from there as it would from the executor's own take. Only for a
    callback of the message alone (no ``MessageInfo``). Returns ``sub``.
    """
    if sub._callback_type is not type(sub).CallbackType.MessageOnly:
        raise TopicError(f"drain_queue: the callback of {sub.topic_name} must take the message alone")
    inner = sub.callback

    def drained(msg: Any) -> None:
        inner(msg)
        for _ in range(limit):
            with sub.handle:
                got = sub.handle.take_message(sub.msg_type, sub.raw)
            if got is None:
                return
            inner(got[0])

    sub.callback = drained
    return sub
