"""Perimeter-monitor roles (PM) without a coordinator, and the MONITOR planner.

Role rule (:func:`assign_monitors`), computed by every agent from the same information (the
fleet's step k-1 states it fused, its own step k-1 published position, the consensus fires):
for each active fire in ascending fleet fire id, the ``monitors_per_fire`` eligible UAVs
(alive, airborne, objective SEARCH / SUPPRESS / MONITOR) nearest to the fire's centre are its
monitors, ties broken by the lower uav id; a UAV already monitoring that fire (its published
objective MONITOR with that target fire) counts ``hysteresis_m`` nearer, so roles do not flap
as UAVs move. A UAV monitors at most one fire. A crashed peer is no longer alive, so its role
passes on at the next step. Positions [m; map frame].

:class:`MonitorPlanner` wraps a :class:`fire_perimeter_monitor.planner.ImportanceMonitor`
(or the circling baseline) per monitored fire: it takes the bundle's FireCells each step and
returns a waypoint a few cells ahead along the perimeter at flight height.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
from fire_perimeter_monitor.planner import CirclingMonitor, ImportanceMonitor, MonitorConfig, PerimeterMonitor
from fire_uav_common.constants import Objective

from .errors import ConfigError
from .planning import PlannerTarget, PlannerView

__all__ = ["MonitorPlanner", "MonitorPlannerConfig", "RoleConfig", "assign_monitors", "eligible"]

ELIGIBLE = (int(Objective.SEARCH), int(Objective.SUPPRESS), int(Objective.MONITOR))


@dataclass(frozen=True)
class RoleConfig:
    monitors_per_fire: int = 1  # [-] scenario mission.monitors_per_fire
    hysteresis_m: float = 150.0  # [m] head start of the incumbent monitor

    def __post_init__(self) -> None:
        if self.monitors_per_fire < 0:
            raise ConfigError(f"monitors_per_fire must be >= 0, got {self.monitors_per_fire}")
        if not self.hysteresis_m >= 0:
            raise ConfigError(f"hysteresis_m must be >= 0, got {self.hysteresis_m}")


def eligible(objective: int) -> bool:
    return int(objective) in ELIGIBLE


def assign_monitors(
    fires: Iterable[tuple[int, float, float]],
    uavs: Mapping[int, tuple[float, float, int, int]],
    cfg: RoleConfig,
) -> dict[int, tuple[int, ...]]:
    """Monitors per fire: ``{fire_id: (uav ids)}``.

    ``fires``: active fires ``(fire_id, x_m, y_m)``; ``uavs``: every alive UAV (own included)
    ``uav_id -> (x_m, y_m, objective, target_fire_id)``. Pure and deterministic: the result
    depends only on the arguments, not on their order.
    """
    out: dict[int, tuple[int, ...]] = {}
    if cfg.monitors_per_fire <= 0:
        return out
    taken: set[int] = set()
    for fid, fx, fy in sorted(fires, key=lambda f: f[0]):
        scored = []
        for uid, (x, y, obj, tgt) in uavs.items():
            if uid in taken or not eligible(obj):
                continue
            d = math.hypot(x - fx, y - fy)
            if int(obj) == Objective.MONITOR and int(tgt) == int(fid):
                d -= cfg.hysteresis_m
            scored.append((d, uid))
        chosen = tuple(uid for _, uid in sorted(scored)[: cfg.monitors_per_fire])
        if chosen:
            out[int(fid)] = chosen
            taken.update(chosen)
    return out


@dataclass(frozen=True)
class MonitorPlannerConfig:
    speed_mps: float = 50.0  # [m/s] ground speed along the perimeter (Eq. 3)
    alpha: float = 1.0  # Eq. 7
    circling: bool = False  # the PM VI-E baseline instead of importance-based monitoring
    lookahead_cells: int = 6  # waypoint this many perimeter cells ahead (the UAV is fast)
    ros_baseline_s: float = 30.0  # [s] FireMap Eq. 1 baseline
    height_m: float | None = None  # above terrain; None: flight height


class MonitorPlanner:
    """Objective.MONITOR planner: one perimeter monitor per fire this UAV monitors."""

    def __init__(self, uav_id: int, cfg: MonitorPlannerConfig | None = None) -> None:
        self.uav_id = uav_id
        self.cfg = cfg or MonitorPlannerConfig()
        self.monitors: dict[int, PerimeterMonitor] = {}
        self.fire_id = -1

    def monitor_for(
        self, fire_id: int, center_xy: tuple[float, float], cell_size_m: float
    ) -> PerimeterMonitor:
        m = self.monitors.get(fire_id)
        if m is None or m.config.cell_size_m != cell_size_m:
            c = self.cfg
            mc = MonitorConfig(
                cell_size_m=cell_size_m,
                speed_mps=c.speed_mps,
                alpha=c.alpha,
                center_x_m=float(center_xy[0]),
                center_y_m=float(center_xy[1]),
                ros_baseline_s=c.ros_baseline_s,
                uav_id=self.uav_id,
            )
            m = (CirclingMonitor if c.circling else ImportanceMonitor)(mc)
            self.monitors[fire_id] = m
        return m

    @property
    def active(self) -> PerimeterMonitor | None:
        return self.monitors.get(self.fire_id)

    def plan(self, view: PlannerView) -> PlannerTarget | None:
        fid = int(getattr(view, "target_fire_id", -1))
        fire = next((f for f in view.fires if f.fire_id == fid), None)
        cells = getattr(view, "cells", None)
        if fire is None:
            return None
        self.fire_id = fid
        xy = (float(view.s[0]), float(view.s[1]))
        if cells is None or cells[0].size == 0 or not getattr(view, "cell_size_m", 0.0) > 0:
            return PlannerTarget(waypoint_xy=(fire.x_m, fire.y_m), height_m=self.cfg.height_m)  # go and see
        m = self.monitor_for(fid, (fire.x_m, fire.y_m), float(view.cell_size_m))
        m.update(cells, xy, float(view.t_s))
        wx, wy = m.lookahead_waypoint(self.cfg.lookahead_cells)
        return PlannerTarget(waypoint_xy=(wx, wy), height_m=self.cfg.height_m, speed_cap_mps=None)

    def front(self, fire_id: int) -> tuple[float, float, float] | None:
        """Fastest-spreading perimeter point ``(x_m, y_m, ros_mps)`` of a monitored fire, if known."""
        m = self.monitors.get(fire_id)
        return None if m is None else m.front()


def cells_tuple(x_m, y_m, state) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return (np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float), np.asarray(state, dtype=np.int64))
