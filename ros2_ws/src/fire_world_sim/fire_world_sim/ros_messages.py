"""The world's records as the ROS messages it publishes (one place per message type).

ROS adapter module (it builds rclpy message objects): ``/world/truth`` (:func:`truth_msg`; the
node publishes :func:`truth_bytes`, the same message as CDR bytes),
``/world/events`` (:func:`event_msg`, :func:`agent_lost_msg`), ``/viz/world``
(:func:`marker_array`), ``/tf`` (:func:`tf_msg`) and ``/viz/fire_grid`` (:func:`grid_msg`). The
SensorBundle is written as bytes by ``fire_uav_common.codecs.sensor_bundle``.
"""

from __future__ import annotations

import math
import struct

import numpy as np
from builtin_interfaces.msg import Time
from fire_uav_common.cdr import ENCAPSULATION, U32, pad
from fire_uav_common.constants import CellState, EventType
from fire_uav_common.stamps import to_time_msg
from fire_uav_msgs.msg import FireTruth, MissionEvent, VehicleTruth, WorldTruth
from geometry_msgs.msg import Point, TransformStamped
from nav_msgs.msg import OccupancyGrid
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

from . import viz
from .fires import FireGrid
from .world import MissionEventRecord, StepResult

__all__ = [
    "FRAME",
    "agent_lost_msg",
    "event_msg",
    "grid_msg",
    "header",
    "marker_array",
    "stamp",
    "tf_msg",
    "truth_bytes",
    "truth_msg",
]

FRAME = "map"
_MARKER_TYPES = {
    "arrow": Marker.ARROW,
    "cylinder": Marker.CYLINDER,
    "sphere": Marker.SPHERE,
    "text": Marker.TEXT_VIEW_FACING,
    "triangle_list": Marker.TRIANGLE_LIST,
}


def stamp(ns: int) -> Time:
    """Integer nanoseconds of sim time -> ``builtin_interfaces/Time``."""
    return to_time_msg(ns, Time)


def header(ns: int) -> Header:
    return Header(stamp=stamp(ns), frame_id=FRAME)


def truth_msg(r: StepResult) -> WorldTruth:
    m = WorldTruth(
        header=header(r.stamp_ns),
        step=r.step,
        min_separation_m=float(r.min_separation_m),
        collisions=int(r.collisions),
    )
    for v in r.vehicles:
        m.vehicles.append(
            VehicleTruth(
                uav_id=v.uav_id,
                status=v.status,
                x_m=float(v.x_m),
                y_m=float(v.y_m),
                z_m=float(v.z_m),
                yaw_rad=float(v.yaw_rad),
                v_lin_mps=float(v.v_lin_mps),
                v_z_mps=float(v.v_z_mps),
                omega_z_radps=float(v.omega_z_radps),
                water_kg=float(v.water_kg),
                commands_clamped=int(v.commands_clamped),
                commands_missed=int(v.commands_missed),
            )
        )
    for f in r.fires:
        m.fires.append(
            FireTruth(
                fire_id=int(f.fire_id),
                status=int(f.status),
                x_m=float(f.x_m),
                y_m=float(f.y_m),
                extent_m=float(f.extent_m),
                area_m2=float(f.area_m2),
                drops_received=int(f.drops_received),
            )
        )
    return m


_TRUTH_HEAD = struct.Struct("<iII")  # Header: stamp sec, nanosec; the length of frame_id "map" with NUL
_MAP = b"map\x00"
_F64 = struct.Struct("<d")
# VehicleTruth after its two uint8 ids and the padding to 8: 7 float64, float32 water, 2 uint32
_VEHICLE = struct.Struct("<7dfII")
# FireTruth after its two uint8 ids and the padding to 8: 4 float64, uint32 drops_received
_FIRE = struct.Struct("<4dI")


def truth_bytes(r: StepResult) -> bytes:
    """:func:`truth_msg` as the CDR bytes rclpy serialises it to (XCDR1 little-endian, the rules
    of ``fire_uav_common.cdr``), published raw: at 20 UAVs building and converting the message
    objects was a sizeable part of the world's serial step (docs/profile.md). Pinned byte for
    byte to ``serialize_message(truth_msg(r))`` in test_truth_bytes.py; out-of-range values
    raise (struct.error), as rclpy's setters do."""
    buf = bytearray(ENCAPSULATION)
    buf += _TRUTH_HEAD.pack(*divmod(r.stamp_ns, 1_000_000_000), len(_MAP))
    buf += _MAP
    buf += U32.pack(r.step)  # at index 20: 4-aligned
    pad(buf, 8)
    buf += _F64.pack(float(r.min_separation_m))
    buf += U32.pack(int(r.collisions))
    buf += U32.pack(len(r.vehicles))
    for v in r.vehicles:
        buf.append(int(v.uav_id))
        buf.append(int(v.status))
        pad(buf, 8)
        buf += _VEHICLE.pack(
            float(v.x_m),
            float(v.y_m),
            float(v.z_m),
            float(v.yaw_rad),
            float(v.v_lin_mps),
            float(v.v_z_mps),
            float(v.omega_z_radps),
            float(v.water_kg),
            int(v.commands_clamped),
            int(v.commands_missed),
        )
    pad(buf, 4)
    buf += U32.pack(len(r.fires))
    for f in r.fires:
        buf.append(int(f.fire_id))
        buf.append(int(f.status))
        pad(buf, 8)
        buf += _FIRE.pack(
            float(f.x_m), float(f.y_m), float(f.extent_m), float(f.area_m2), int(f.drops_received)
        )
    return bytes(buf)


def event_msg(e: MissionEventRecord) -> MissionEvent:
    return MissionEvent(
        header=header(e.stamp_ns),
        type=int(e.type),
        uav_id=int(e.uav_id),
        peer_id=-1,
        fire_id=int(e.fire_id),
        x_m=float(e.x_m),
        y_m=float(e.y_m),
        value=float(e.value),
        detail=e.detail,
    )


def agent_lost_msg(uav_id: int, stamp_ns: int) -> MissionEvent:
    """``AGENT_LOST``: the world stopped waiting for ``uav_id``, whose process left the graph."""
    return MissionEvent(
        header=header(stamp_ns),
        type=int(EventType.AGENT_LOST),
        uav_id=uav_id,
        peer_id=-1,
        fire_id=-1,
        x_m=math.nan,
        y_m=math.nan,
        value=0.0,
        detail="process gone from the DDS graph",
    )


def marker_array(specs: list[viz.MarkerSpec], stamp_ns: int) -> MarkerArray:
    """``/viz/world`` from the frame's marker specs (:meth:`viz.MarkerBook.frame`: stable ids per
    UAV, fire and lake, DELETE for what is gone)."""
    hdr = header(stamp_ns)
    arr = MarkerArray()
    for spec in specs:
        mk = Marker(header=hdr, ns=spec.ns, id=spec.id)
        if spec.action == "delete":
            mk.action = Marker.DELETE
            arr.markers.append(mk)
            continue
        mk.type, mk.action, mk.text = _MARKER_TYPES[spec.kind], Marker.ADD, spec.text
        mk.pose.position = Point(x=spec.x_m, y=spec.y_m, z=spec.z_m)
        _, _, mk.pose.orientation.z, mk.pose.orientation.w = viz.yaw_quaternion(spec.yaw_rad)
        mk.scale.x, mk.scale.y, mk.scale.z = spec.scale_m
        mk.color.r, mk.color.g, mk.color.b, mk.color.a = spec.rgba
        if spec.points:
            mk.points = [Point(x=px, y=py, z=pz) for px, py, pz in spec.points]
        arr.markers.append(mk)
    return arr


def tf_msg(r: StepResult) -> TFMessage:
    """``/tf``: ``map -> uav_<k>`` from the truth (the frame of vehicle k's sensor headers)."""
    msg = TFMessage()
    for v in r.vehicles:
        t = TransformStamped()
        t.header = header(r.stamp_ns)
        t.child_frame_id = f"uav_{v.uav_id}"
        t.transform.translation.x, t.transform.translation.y = float(v.x_m), float(v.y_m)
        t.transform.translation.z = float(v.z_m)
        _, _, t.transform.rotation.z, t.transform.rotation.w = viz.yaw_quaternion(float(v.yaw_rad))
        msg.transforms.append(t)
    return msg


def fire_type_msg(grid: FireGrid, fire_type: np.ndarray, ns: int) -> OccupancyGrid:
    """``/world/fire_type``: per cell of ``grid``'s frame, the fire type it burned with (0 not
    burnt, 1 surface, 2 passive crown, 3 active crown; row 0 the southern row)."""
    g = OccupancyGrid(header=header(ns))
    g.info.map_load_time = stamp(ns)
    g.info.resolution = grid.cell_size_m
    g.info.width, g.info.height = grid.nx, grid.ny
    g.info.origin.position.x = grid.origin_x_m
    g.info.origin.position.y = grid.origin_y_m
    g.info.origin.orientation.w = 1.0
    g.data = fire_type.astype(np.int8).ravel().tolist()
    return g


def grid_msg(grid: FireGrid, ns: int) -> OccupancyGrid:
    """``/viz/fire_grid``: unburned 0, wet 20, burnt 60, burning 100."""
    g = OccupancyGrid(header=header(ns))
    g.info.map_load_time = stamp(ns)
    g.info.resolution = grid.cell_size_m
    g.info.width, g.info.height = grid.nx, grid.ny
    g.info.origin.position.x = grid.origin_x_m
    g.info.origin.position.y = grid.origin_y_m
    g.info.origin.orientation.w = 1.0
    state = grid.state
    occ = np.zeros(state.shape, dtype=np.int8)
    occ[grid.wet] = 20
    occ[state == CellState.BURNED] = 60
    occ[state == CellState.BURNING] = 100
    g.data = occ.ravel().tolist()
    return g
