"""The coverage search's configuration and the agent's SEARCH planner (CP): the planner flies the
own STC path of the adopted plan (:class:`SearchPlanner`), the coordinator (:mod:`.coordinator`)
decides the plan. ROS-free.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..planning import PlannerTarget, PlannerView
from .errors import SearchConfigError
from .stc import CoveragePath

__all__ = ["MST_KEY_STRIDE", "SearchConfig", "SearchPlanner", "default_cell_size_m"]

MST_KEY_STRIDE = 1000  # MST sample_index = plan key * stride + instant


def default_cell_size_m(area_m: tuple[float, float, float, float], sensor_range_m: float) -> float:
    """Coarse cell edge Delta [m]: lanes Delta/2 apart, at most 1.4 sensor ranges, fitting the area.

    A point is then at most 0.35 sensor ranges from the nearest lane (margin for tracking errors).
    """
    width = max(area_m[1] - area_m[0], area_m[3] - area_m[2])
    n = max(2, math.ceil(width / (2.8 * sensor_range_m)))
    return width / n


@dataclass(frozen=True)
class SearchConfig:
    """Parameters of the in-fleet search. Steps are control steps."""

    mode: str = "bo"  # "bo" (Thompson sampling, CP III-F) | "random" (baseline, same budget and pool)
    budget: int = 18  # candidate evaluations, fleet-wide
    lambda_m_per_j: float = 1e-3  # lambda of the cost [m/J]
    cell_size_m: float | None = None  # coarse cell edge [m]; None: default_cell_size_m
    sensor_range_m: float = 70.0  # [m]
    speed_mps: float = 50.0  # search airspeed [m/s] (energy model and planner speed cap)
    pool_size: int = 256
    ts_subset: int = 128
    n_time_samples: int = 50  # sampled instants of Eq. 11 (cost and message MST)
    bo_start_step: int = 1
    consume_delay_steps: int = 2
    agree_steps: int = 6
    rebroadcast_every_steps: int = 10
    epsilon: float = 0.02
    balance_max_iterations: int = 150
    balance_timeout_steps: int = 300
    linger_steps: int = 40  # keep re-sending final weight reports this long after finishing
    mst_timeout_steps: int = 80
    lookahead_m: float = 30.0  # planner carrot distance along the path [m]
    capture_m: float = 25.0  # joined the path when this close [m]

    def __post_init__(self) -> None:
        if self.mode not in ("bo", "random"):
            raise SearchConfigError(f"mode must be 'bo' or 'random', got {self.mode!r}")
        if self.budget < 1 or self.pool_size < self.budget:
            raise SearchConfigError(f"need 1 <= budget <= pool_size, got {self.budget}, {self.pool_size}")
        if self.lambda_m_per_j < 0.0 or not math.isfinite(self.lambda_m_per_j):
            raise SearchConfigError(f"lambda_m_per_j must be >= 0, got {self.lambda_m_per_j}")
        if self.cell_size_m is not None and not self.cell_size_m > 0.0:
            raise SearchConfigError(f"cell_size_m must be > 0, got {self.cell_size_m}")
        if min(self.consume_delay_steps, self.agree_steps, self.bo_start_step) < 0:
            raise SearchConfigError("step counts must be >= 0")
        if min(self.rebroadcast_every_steps, self.balance_timeout_steps, self.mst_timeout_steps) < 1:
            raise SearchConfigError("rebroadcast, balance and MST timeouts must be >= 1 step")
        if not 0 < self.n_time_samples < MST_KEY_STRIDE:
            raise SearchConfigError(f"n_time_samples must be in 1..{MST_KEY_STRIDE - 1}")
        if self.lookahead_m <= 0.0 or self.capture_m <= 0.0 or self.speed_mps <= 0.0:
            raise SearchConfigError("lookahead_m, capture_m and speed_mps must be > 0")


# --- the path follower -----------------------------------------------------------------------------
class SearchPlanner:
    """Planner for Objective.SEARCH: a carrot ``lookahead_m`` ahead on the own STC path.

    Returns None until a plan exists (the agent then uses its default search). It first flies to
    its start point (the start offset along the path, or the nearest path point after a re-plan or
    after time away from SEARCH), then tracks its arc-length progress by projecting the vehicle onto
    a window of the path ahead, so the fixed-wing never stops: laps repeat. Speed is capped at
    ``speed_mps``.
    """

    def __init__(self, config: SearchConfig) -> None:
        self.config = config
        self.path: CoveragePath | None = None
        self.s_m: float | None = None  # arc-length progress (unwrapped) [m]
        self.start_m = 0.0
        self.joined = False
        self._last_t_s: float | None = None
        self.plans_set = 0

    @property
    def laps(self) -> float:
        """Laps flown since joining the current path [-]."""
        if self.path is None or self.s_m is None or not self.joined:
            return 0.0
        return (self.s_m - self.start_m) / self.path.length_m

    def set_path(self, path: CoveragePath, start_fraction: float | None) -> None:
        """New own path; ``start_fraction`` in [0, 1) or None for the point nearest the vehicle."""
        self.path = path
        self.s_m = None if start_fraction is None else float(start_fraction) * path.length_m
        self.start_m = self.s_m or 0.0
        self.joined = False
        self.plans_set += 1

    def _nearest_s(self, pos: np.ndarray) -> float:
        assert self.path is not None
        s = np.linspace(0.0, self.path.length_m, max(8, math.ceil(self.path.length_m / 5.0)), endpoint=False)
        d = np.linalg.norm(self.path.positions_at(s) - pos[None, :], axis=1)
        return float(s[int(np.argmin(d))])

    def plan(self, view: PlannerView) -> PlannerTarget | None:
        path = self.path
        if path is None:
            return None
        cfg = self.config
        pos = np.asarray(view.s[:2], dtype=float)
        away = self._last_t_s is not None and view.t_s - self._last_t_s > 1.0
        self._last_t_s = float(view.t_s)
        if self.s_m is None or away:
            self.s_m = self._nearest_s(pos)
            self.start_m = self.s_m
            self.joined = False
        if not self.joined:
            p = path.positions_at(np.array(self.s_m))
            if float(np.linalg.norm(p - pos)) > cfg.capture_m:
                return PlannerTarget(waypoint_xy=(float(p[0]), float(p[1])), speed_cap_mps=cfg.speed_mps)
            self.joined = True
        window = 3.0 * cfg.lookahead_m + cfg.speed_mps
        ss = self.s_m + np.linspace(-5.0, window, 64)
        d = np.linalg.norm(path.positions_at(ss) - pos[None, :], axis=1)
        k = int(np.argmin(d))
        if d[k] <= 3.0 * cfg.capture_m:
            self.s_m = max(self.s_m, float(ss[k]))
        else:  # pushed off the path: go back to where we left it
            self.joined = False
            p = path.positions_at(np.array(self.s_m))
            return PlannerTarget(waypoint_xy=(float(p[0]), float(p[1])), speed_cap_mps=cfg.speed_mps)
        wp = path.positions_at(np.array(self.s_m + cfg.lookahead_m))
        return PlannerTarget(waypoint_xy=(float(wp[0]), float(wp[1])), speed_cap_mps=cfg.speed_mps)
