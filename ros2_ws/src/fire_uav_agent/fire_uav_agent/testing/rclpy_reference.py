"""The reference conversions of rclpy messages, for the codec tests: what the agent node did with
``deserialize_message`` before the codecs (``fire_uav_common.codecs``), and how it built its
UavState, PerimeterMap and FireFront messages. The codecs must read and write exactly these values and bytes.
"""

from __future__ import annotations

import math

import numpy as np
from builtin_interfaces.msg import Time as TimeMsg
from fire_uav_common.constants import FireStatus
from fire_uav_common.stamps import s_to_ns, stamp_to_ns, stamp_to_s, stamp_to_step, to_time_msg
from fire_uav_msgs.msg import FireEstimate, FireFront, PerimeterMap, SensorBundle, UavState

from fire_uav_agent.agent_types import Bundle, PeerPerimeter, StepOutput
from fire_uav_agent.estimation import Samples
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.front_consensus import PeerFront
from fire_uav_agent.peer_link import FireEntry, PeerFires, PeerState

__all__ = [
    "add_fires",
    "front_msg",
    "from_state",
    "perimeter_msg",
    "to_bundle",
    "to_peer_fires",
    "to_peer_front",
    "to_peer_perimeter",
    "to_peer_state",
]


def to_bundle(msg: SensorBundle) -> Bundle:
    gps = np.array([(stamp_to_s(g.header.stamp), g.x_m, g.y_m) for g in msg.gps], dtype=float).reshape(-1, 3)
    gps_var = np.array([g.variance_m2 for g in msg.gps], dtype=float)
    alt = np.array([(stamp_to_s(r.header.stamp), r.range) for r in msg.altimeter], dtype=float).reshape(-1, 2)
    gyro = np.array(
        [(stamp_to_s(m.header.stamp), m.angular_velocity.z) for m in msg.gyro], dtype=float
    ).reshape(-1, 2)
    fires = np.array(
        [(stamp_to_s(f.header.stamp), f.x_m, f.y_m, f.extent_m) for f in msg.fires], dtype=float
    ).reshape(-1, 4)
    c = msg.cells
    cells = None
    if len(c.x_m) > 0 and len(c.x_m) == len(c.y_m) == len(c.state):
        cells = (
            np.asarray(c.x_m, dtype=float),
            np.asarray(c.y_m, dtype=float),
            np.frombuffer(bytes(c.state), dtype=np.uint8).astype(np.int64)
            if isinstance(c.state, (bytes, bytearray))
            else np.asarray(c.state, dtype=np.int64),
        )
    return Bundle(
        step=int(msg.step),
        stamp_s=stamp_to_s(msg.header.stamp),
        samples=Samples(gps, gps_var, alt, gyro),
        fires=fires,
        water_kg=float(msg.water_kg),
        vehicle=int(msg.vehicle_status),
        control_period_s=float(msg.control_period_s),
        cells=cells,
        cell_size_m=float(c.cell_size_m),
    )


def to_peer_state(m: UavState) -> PeerState:
    return PeerState(
        int(m.uav_id), int(m.sequence), int(m.step), m.x_m, m.y_m, m.z_m, m.yaw_rad, int(m.objective),
        int(m.target_fire_id), float(m.water_kg), m.centroid_x_m, m.centroid_y_m,
    )  # fmt: skip


def to_peer_fires(m: UavState) -> PeerFires:
    """The fire picture a peer's UavState carries (``fires``, ``fires_sequence``)."""
    entries = tuple(
        FireEntry(
            int(f.fire_id),
            f.status == FireStatus.ACTIVE,
            f.x_m,
            f.y_m,
            f.extent_m,
            f.vx_mps,
            f.vy_mps,
            stamp_to_s(f.last_measurement),
            f.front_x_m,
            f.front_y_m,
            f.max_spread_rate_mps,
        )  # fmt: skip
        for f in m.fires
    )
    return PeerFires(int(m.uav_id), int(m.fires_sequence), int(m.step), entries)


def from_state(out: StepOutput, stamp: TimeMsg) -> UavState:
    st = out.state
    m = UavState()
    m.header.stamp = stamp
    m.header.frame_id = "map"
    m.uav_id, m.sequence, m.step = st.uav_id, st.sequence, st.step
    m.x_m, m.y_m, m.z_m, m.yaw_rad = (float(v) for v in st.s)
    m.covariance = [float(v) for v in st.covariance.ravel()]
    m.objective = st.objective
    m.target_fire_id = st.target_fire_id
    m.water_kg = st.water_kg
    m.centroid_x_m, m.centroid_y_m = st.centroid_xy
    m.alive_peers = list(st.alive_peers)
    m.crashed_peers = list(st.crashed_peers)
    m.packets_received, m.packets_lost, m.packets_rejected = (
        st.packets_received, st.packets_lost, st.packets_rejected,
    )  # fmt: skip
    return m


def add_fires(m: UavState, out: StepOutput) -> UavState:
    """Put this step's fire picture into the state message (one peer message per step)."""
    m.fires_sequence = out.fires_sequence
    for e in out.fires:
        f = FireEstimate()
        f.fire_id = e.fire_id
        f.status = int(FireStatus.ACTIVE if e.active else FireStatus.EXTINGUISHED)
        f.x_m, f.y_m, f.extent_m, f.vx_mps, f.vy_mps = e.x_m, e.y_m, e.extent_m, e.vx_mps, e.vy_mps
        f.last_measurement = to_time_msg(
            s_to_ns(max(0.0, e.last_measurement_s) if math.isfinite(e.last_measurement_s) else 0.0), TimeMsg
        )
        f.front_x_m, f.front_y_m, f.max_spread_rate_mps = e.front_x_m, e.front_y_m, e.max_spread_rate_mps
        m.fires.append(f)
    return m


def to_peer_perimeter(m: PerimeterMap, control_period_s: float) -> PeerPerimeter:
    """A peer's PerimeterMap; its stamp is the bundle stamp (k + 1) T of the step k it answers."""
    summary = {
        "center_x_m": float(m.center_x_m),
        "center_y_m": float(m.center_y_m),
        "outer_distance_m": np.asarray(m.outer_distance_m, dtype=float),
        "outer_visit_time_s": np.asarray(m.outer_visit_time_s, dtype=float),
    }
    step = stamp_to_step(stamp_to_ns(m.header.stamp), s_to_ns(control_period_s))
    return PeerPerimeter(int(m.uav_id), int(m.sequence), step, int(m.fire_id), summary)


def perimeter_msg(out: StepOutput, stamp: TimeMsg, seq: int) -> PerimeterMap | None:
    if out.perimeter is None:
        return None
    fire_id, s = out.perimeter
    m = PerimeterMap()
    m.header.stamp = stamp
    m.header.frame_id = "map"
    m.uav_id, m.sequence, m.fire_id = out.state.uav_id, seq, int(fire_id) if fire_id < 2**31 else -1
    m.center_x_m, m.center_y_m = s["center_x_m"], s["center_y_m"]
    m.outer_distance_m = s["outer_distance_m"].astype(np.float32).tolist()
    m.outer_visit_time_s = s["outer_visit_time_s"].astype(np.float32).tolist()
    m.spread_rate_mps = s["spread_rate_mps"].astype(np.float32).tolist()
    m.importance = s["importance"].astype(np.float32).tolist()
    m.direction, m.direction_changes = int(s["direction"]), int(s["direction_changes"])
    return m


def to_peer_front(m: FireFront, control_period_s: float) -> PeerFront:
    """A peer's FireFront; its stamp is the bundle stamp (k + 1) T of the step k it answers."""
    state = (
        np.frombuffer(bytes(m.state), dtype=np.uint8)
        if isinstance(m.state, (bytes, bytearray))
        else np.asarray(m.state, dtype=np.uint8)
    )
    cells = FrontCells(
        np.asarray(m.x_m, dtype=float),
        np.asarray(m.y_m, dtype=float),
        state.astype(np.int64),
        np.asarray(m.observed_s, dtype=float),
        np.asarray(m.spread_rate_mps, dtype=float),
    )
    step = stamp_to_step(stamp_to_ns(m.header.stamp), s_to_ns(control_period_s))
    return PeerFront(int(m.uav_id), int(m.sequence), step, cells, float(m.cell_size_m))


def front_msg(out: StepOutput, stamp: TimeMsg, seq: int, cell_size_m: float) -> FireFront | None:
    c = out.front
    if not isinstance(c, FrontCells):
        return None
    m = FireFront()
    m.header.stamp = stamp
    m.header.frame_id = "map"
    m.uav_id, m.sequence, m.cell_size_m = out.state.uav_id, seq, float(cell_size_m)
    m.x_m = np.asarray(c.x_m, dtype=np.float32).tolist()
    m.y_m = np.asarray(c.y_m, dtype=np.float32).tolist()
    m.state = np.asarray(c.state, dtype=np.uint8).tobytes()
    m.observed_s = np.asarray(c.t_obs_s, dtype=float).tolist()
    m.spread_rate_mps = np.asarray(c.ros_mps, dtype=np.float32).tolist()
    return m
