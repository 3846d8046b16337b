"""Every topic name of the fleet, paired with its QoS, in one place (DESIGN "Processes and topics").

Per-vehicle topics are relative names under the ``uav_<k>`` namespace; :func:`uav_topic`
gives the absolute form for nodes outside that namespace (the world, the recorder).
This module imports only ``rclpy.qos`` data classes when asked for QoS profiles, so the
names can be used from ROS-free code too.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from rclpy.qos import QoSProfile

# --- names -----------------------------------------------------------------------------
CLOCK = "/clock"
# per vehicle, relative to the uav_<k> namespace
SENSORS = "sensors"  # fire_uav_msgs/SensorBundle       world -> agent k
CMD = "cmd"  # geometry_msgs/TwistStamped             agent k -> world
PAYLOAD = "payload"  # fire_uav_msgs/PayloadRequest   agent k -> world
VIZ_AGENT = "viz"  # visualization_msgs/MarkerArray   agent k -> RViz/Foxglove
# fleet (peer-to-peer), absolute
FLEET_STATE = "/fleet/state"  # fire_uav_msgs/UavState
FLEET_FIRES = "/fleet/fires"  # fire_uav_msgs/FireEstimateArray
FLEET_PERIMETER = "/fleet/perimeter"  # fire_uav_msgs/PerimeterMap
FLEET_EVENTS = "/fleet/events"  # fire_uav_msgs/MissionEvent (agents' own decisions)
COVERAGE_WEIGHTS = "/fleet/coverage/weights"  # fire_uav_msgs/CoverageWeight
COVERAGE_CANDIDATES = "/fleet/coverage/candidates"  # fire_uav_msgs/CoverageCandidate
COVERAGE_MST = "/fleet/coverage/mst"  # fire_uav_msgs/MstFragment
# world, absolute (agents never subscribe to these)
WORLD_TRUTH = "/world/truth"  # fire_uav_msgs/WorldTruth
WORLD_EVENTS = "/world/events"  # fire_uav_msgs/MissionEvent
VIZ_WORLD = "/viz/world"  # visualization_msgs/MarkerArray
VIZ_FIRE_GRID = "/viz/fire_grid"  # nav_msgs/OccupancyGrid

UAV_NAMESPACE = "uav_{k}"


def uav_namespace(uav_id: int) -> str:
    """Namespace of vehicle ``uav_id``, e.g. ``/uav_3``."""
    if uav_id < 0:
        raise ValueError(f"uav_id must be >= 0, got {uav_id}")
    return "/" + UAV_NAMESPACE.format(k=uav_id)


def uav_topic(uav_id: int, name: str) -> str:
    """Absolute name of a per-vehicle topic, e.g. ``uav_topic(3, SENSORS) == '/uav_3/sensors'``."""
    return f"{uav_namespace(uav_id)}/{name}"


# --- QoS -----------------------------------------------------------------------------
def qos(kind: str) -> QoSProfile:
    """QoS profile for a class of topic.

    - ``"lockstep"``: sensors, commands, payload: reliable, depth 20 (the world waits for them).
    - ``"fleet"``: peer-to-peer state: reliable on the wire; the injected loss is applied on
      receipt (DESIGN "Faults"), so the real transport must not lose messages on its own.
    - ``"events"``: reliable + transient local, depth 1000: a late recorder still gets them.
    - ``"truth"``: reliable, depth 50.
    - ``"viz"``: best effort, depth 5.
    """
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    table = {
        "lockstep": (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE, 20),
        "fleet": (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE, 100),
        "events": (ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL, 1000),
        "truth": (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE, 50),
        "viz": (ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE, 5),
    }
    if kind not in table:
        raise ValueError(f"unknown QoS kind {kind!r}; expected one of {sorted(table)}")
    rel, dur, depth = table[kind]
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth, reliability=rel, durability=dur)
