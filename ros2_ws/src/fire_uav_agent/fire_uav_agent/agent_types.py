"""The agent's ROS-free inputs and outputs: one control step's bundle, and what it publishes.

Positions are [m; map frame], yaw [rad], speeds [m/s], times [s of sim time]. The node
(``agent_node``) and the test harness (``testing.harness``) convert to and from these types.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.codecs.sensor_bundle import Bundle  # re-exported: the agent's input

from .peer_link import FireEntry, PeerState

__all__ = ["AgentEvent", "Bundle", "MarkersData", "OwnState", "PeerPerimeter", "StepOutput"]


@dataclass(frozen=True)
class PeerPerimeter:
    """A peer monitor's PerimeterMap, ROS-free (``summary``: PerimeterMonitor.to_summary() fields)."""

    uav_id: int
    sequence: int
    step: int
    fire_id: int
    summary: dict


@dataclass(frozen=True)
class OwnState:
    """Fields of this agent's UavState."""

    uav_id: int
    sequence: int
    step: int
    stamp_s: float
    s: np.ndarray  # (x, y, z, yaw)
    covariance: np.ndarray  # 4x4
    objective: int
    target_fire_id: int
    water_kg: float
    centroid_xy: tuple[float, float]
    alive_peers: tuple[int, ...]
    crashed_peers: tuple[int, ...]
    packets_received: int
    packets_lost: int
    packets_rejected: int

    def as_peer_state(self) -> PeerState:
        x, y, z, yaw = (float(v) for v in self.s)
        cx, cy = self.centroid_xy
        return PeerState(
            self.uav_id, self.sequence, self.step, x, y, z, yaw,
            self.objective, self.target_fire_id, self.water_kg, cx, cy,
        )  # fmt: skip


@dataclass(frozen=True)
class AgentEvent:
    type: int  # EventType (MissionEvent.TYPE_*)
    peer_id: int = -1
    fire_id: int = -1
    x_m: float = math.nan
    y_m: float = math.nan
    value: float = 0.0
    detail: str = ""


@dataclass(frozen=True)
class MarkersData:
    cell_boundary_xy: np.ndarray  # (K, 2) grid points on this agent's cell border
    centroid_xy: tuple[float, float]
    objective: int
    text: str


@dataclass(frozen=True)
class StepOutput:
    step: int
    stamp_s: float
    command: tuple[float, float, float]  # v_lin [m/s], v_z [m/s], omega_z [rad/s]
    payload_requests: tuple[tuple[int, int], ...]  # (PayloadAction, target_fire_id)
    state: OwnState
    fires: tuple[FireEntry, ...]
    fires_sequence: int
    events: tuple[AgentEvent, ...]
    markers: MarkersData | None
    direct: bool  # attack run / stalled-refill mode in effect
    perimeter: tuple[int, dict] | None = None  # (fire_id, PerimeterMap fields) to publish this step
    front: object | None = None  # fire_front.FrontCells to publish on /fleet/front this step
