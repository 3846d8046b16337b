"""The planner hook of the agent: what a planner sees (:class:`PlannerView`) and returns.

Objectives SEARCH and MONITOR take their target from a :class:`Planner`: the coverage-search
planner (``fire_uav_agent.search``), the perimeter monitor (``monitor_role.MonitorPlanner``) or
the default :class:`~fire_uav_agent.staleness_search.StalenessSearch`. This module depends on
nothing of the agent but the grid and the fire entries, so planners import it without a cycle.
Positions are [m; map frame].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from .coverage import Grid
from .peer_link import FireEntry

__all__ = ["Planner", "PlannerTarget", "PlannerView"]


@dataclass(frozen=True)
class PlannerView:
    t_s: float
    uav_id: int
    s: np.ndarray  # own estimate (x, y, z, yaw)
    grid: Grid
    cell_mask: np.ndarray  # (M,) own Voronoi cell
    peers_xy: dict[int, tuple[float, float]]  # alive flying peers' last known positions
    fires: tuple[FireEntry, ...]
    target_fire_id: int = -1  # MONITOR: the fire this UAV monitors
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # this step's FireCells
    cell_size_m: float = 0.0  # [m]
    peer_roles: dict[int, tuple[int, int]] = field(
        default_factory=dict
    )  # alive peer -> (objective, target fire)
    own_published_xy: tuple[float, float] | None = None  # own position as peers last received it
    own_objective: int = -1
    own_target_fire_id: int = -1


@dataclass(frozen=True)
class PlannerTarget:
    """Either a waypoint [m; map] or a density on ``grid.points`` (then the cell centroid)."""

    waypoint_xy: tuple[float, float] | None = None
    density: np.ndarray | None = None
    height_m: float | None = None  # above terrain; None: flight height
    speed_cap_mps: float | None = None


class Planner(Protocol):
    def plan(self, view: PlannerView) -> PlannerTarget | None: ...
