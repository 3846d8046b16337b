"""The agent node's ROS side that is not the node: the declaration of its parameters (listed in
``agent_params``), the markers, the tf of the estimate, mission events, and the spin loop. The
node (``agent_node``) wires them up; the fleet messages go through the codecs (``incoming``,
``outgoing``).
"""

from __future__ import annotations

import math

import rclpy
from builtin_interfaces.msg import Time as TimeMsg
from fire_uav_common.codecs.agent_pose import write_tf_one
from fire_uav_common.constants import EventType
from fire_uav_msgs.msg import MissionEvent
from geometry_msgs.msg import Point
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.node import Node
from rclpy.parameter import Parameter
from visualization_msgs.msg import Marker, MarkerArray

from .agent_params import (
    RCLPY_PARAMETERS,
    NodeConfig,
    ParamSpec,
    declare_agent_parameters,
    node_config,
    unknown_parameters,
)
from .agent_types import AgentEvent, StepOutput
from .errors import ConfigError

__all__ = [
    "event_msg",
    "log_event",
    "read_node_config",
    "make_executor",
    "markers_msg",
    "profiled",
    "spin_through_bad_messages",
    "tf_estimate_bytes",
]


def markers_msg(out: StepOutput, stamp: TimeMsg, ns: str) -> MarkerArray:
    md = out.markers
    arr = MarkerArray()
    if md is None:
        return arr
    z = float(out.state.s[2])
    cell = Marker(ns=ns, id=0, type=Marker.POINTS, action=Marker.ADD)
    cell.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in md.cell_boundary_xy]
    cell.scale.x = cell.scale.y = 2.0
    if not cell.points:  # no cell yet (or lost): remove the old one rather than send an empty POINTS
        cell.action = Marker.DELETE
    cell.color.g, cell.color.a = 1.0, 0.8
    cen = Marker(ns=ns, id=1, type=Marker.SPHERE, action=Marker.ADD)
    cen.pose.position = Point(x=md.centroid_xy[0], y=md.centroid_xy[1], z=z)
    cen.scale.x = cen.scale.y = cen.scale.z = 6.0
    cen.color.g, cen.color.b, cen.color.a = 1.0, 1.0, 1.0
    txt = Marker(ns=ns, id=2, type=Marker.TEXT_VIEW_FACING, action=Marker.ADD, text=md.text)
    txt.pose.position = Point(x=float(out.state.s[0]), y=float(out.state.s[1]), z=z + 15.0)
    txt.scale.z = 10.0
    txt.color.r = txt.color.g = txt.color.b = txt.color.a = 1.0
    for m in (cell, cen, txt):
        m.header.stamp = stamp
        m.header.frame_id = "map"
        arr.markers.append(m)
    return arr


def tf_estimate_bytes(out: StepOutput, stamp: TimeMsg, uav_id: int) -> bytes:
    """``/tf`` as CDR bytes (``codecs.agent_pose``, published raw): ``map -> uav_<k>/estimate``, the
    agent's own pose estimate (x, y, z [m], yaw [rad])."""
    x, y, z, yaw = (float(v) for v in out.state.s[:4])
    rotation = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    return write_tf_one(stamp.sec, stamp.nanosec, "map", f"uav_{uav_id}/estimate", (x, y, z), rotation)


def event_msg(
    type_: int,
    uav_id: int,
    peer_id: int = -1,
    fire_id: int = -1,
    x_m: float = math.nan,
    y_m: float = math.nan,
    value: float = 0.0,
    detail: str = "",
    stamp: TimeMsg | None = None,
) -> MissionEvent:
    """A MissionEvent in the map frame (a fire id beyond int32, a briefed fire's, is sent as -1)."""
    m = MissionEvent(
        type=int(type_),
        uav_id=uav_id,
        peer_id=peer_id,
        fire_id=int(fire_id) if fire_id < 2**31 else -1,
        x_m=float(x_m),
        y_m=float(y_m),
        value=float(value),
        detail=detail,
    )
    if stamp is not None:
        m.header.stamp = stamp
    m.header.frame_id = "map"
    return m


def make_executor():
    """The executor an agent spins on: ``fire_uav_common.ros_io.make_executor`` (the lean
    executor, a wait set built once; ``FIRE_UAV_EXECUTOR=rclpy`` for rclpy's
    SingleThreadedExecutor), made explicit so that the profile hook below wraps exactly what
    runs. rclpy's EventsExecutor (rclpy.experimental) is not offered: with this rclpy wheel the messaging skeleton did not finish its steps and its processes ignored
    SIGINT/SIGTERM, so it is not offered (docs/profile.md)."""
    from fire_uav_common.ros_io import make_executor as _make

    return _make()


def profiled(fn, path: str) -> None:
    """Run ``fn()`` under cProfile and write the statistics to ``path`` (FIRE_UAV_PROFILE_DIR)."""
    import cProfile
    import time

    # the main thread's CPU time: on a shared, oversubscribed machine wall time would charge a
    # call for every moment the process waited for a core (Fast DDS's threads are not counted)
    prof = cProfile.Profile(time.thread_time)
    try:
        prof.runcall(fn)
    finally:
        prof.dump_stats(path)


def spin_through_bad_messages(executor, node, stopped=lambda: False) -> None:
    """``executor.spin()`` until ``stopped()`` (a signal: ``ros_io.StopSignals``), except that a
    message rclpy cannot convert to Python is dropped.

    ``node``: the agent node (its peer link counts the rejection). A malformed peer message can fail inside rclpy's ``take_message``, before any
    callback of ours runs; ``spin()`` would then end the agent. The message is counted as a
    rejection ("undecodable") and the agent spins on; any other error still ends it.
    """
    while rclpy.ok() and not stopped():
        try:
            executor.spin_once()
        except RuntimeError as err:
            if "Unable to convert" not in str(err):
                raise
            node.agent.link.count_rejection("undecodable")
            node.get_logger().warning(
                f"dropped a message rclpy could not decode: {err} "
                f"(rejections so far: {node.agent.link.reject_reasons})",
                throttle_duration_sec=5.0,
            )


# --- parameters -----------------------------------------------------------------------------------
def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    d = ParameterDescriptor(description=spec.description, read_only=spec.read_only)
    if spec.float_range is not None:
        d.floating_point_range = [
            FloatingPointRange(from_value=spec.float_range[0], to_value=spec.float_range[1])
        ]
    if spec.int_range is not None:
        d.integer_range = [IntegerRange(from_value=spec.int_range[0], to_value=spec.int_range[1], step=1)]
    return d


def read_node_config(node: Node) -> NodeConfig:
    """Declare every parameter of :func:`declare_agent_parameters` on ``node`` and read them.

    The node is built with ``automatically_declare_parameters_from_overrides``, so every name it
    was given is declared already: an unknown one is refused (:class:`ConfigError`), a known one
    declared again with its descriptor (the given value stays). ``fleet_key`` is undeclared once
    read, so the node's parameter services do not hand it to other participants; it is never logged.
    """
    decl = declare_agent_parameters()
    names = [name for name, _, _ in decl]
    unknown = unknown_parameters(node.list_parameters([], 0).names, names)
    if unknown:
        raise ConfigError(
            f"unknown parameter{'s' if len(unknown) > 1 else ''} {', '.join(unknown)} given to uav_agent "
            f"(known: {', '.join(sorted(names))})"
        )
    for name, default, spec in decl:
        if name in RCLPY_PARAMETERS:
            node.set_parameters([Parameter(name, value=default)])
            continue
        if node.has_parameter(name):
            node.undeclare_parameter(name)
        node.declare_parameter(name, default, _descriptor(spec))
    values = {name: node.get_parameter(name).value for name in names}
    node.undeclare_parameter("fleet_key")
    cfg = node_config(values, node.get_namespace())
    if cfg.authenticator is None:
        node.get_logger().warning("authentication off: any participant on the domain can speak for the fleet")
    return cfg


def log_event(log, step: int, ev: AgentEvent) -> None:
    """One log line for the events worth one (``log``: the node's logger)."""
    if ev.type == EventType.PEER_CRASHED:
        log.warning(f"step {step}: peer {ev.peer_id} declared crashed ({int(ev.value)} missed steps)")
    elif ev.type == EventType.PEER_REJOINED:
        log.info(f"step {step}: peer {ev.peer_id} rejoined")
    elif ev.type == EventType.FIRE_DETECTED:
        log.info(f"step {step}: fire {ev.fire_id} detected at ({ev.x_m:.0f}, {ev.y_m:.0f})")
    elif ev.type == EventType.OBJECTIVE:
        log.info(f"step {step}: objective {ev.detail}")
