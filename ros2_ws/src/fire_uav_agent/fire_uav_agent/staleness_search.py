"""The default SEARCH planner: a greedy frontier over the fleet's staleness map."""

from __future__ import annotations

from bisect import bisect_left

import numpy as np

from .coverage import Grid
from .planning import PlannerTarget, PlannerView

__all__ = ["StalenessSearch"]


class StalenessSearch:
    """Default SEARCH planner: a greedy frontier over the fleet's staleness map.

    Staleness = time since any UAV's fire sensor covered a grid point (saturating after
    ``horizon_s``). Every agent updates the map from the same information (own estimate +
    peers' states). The UAV flies to the *nearest of the stalest points of its own Voronoi
    cell* (within ``stale_band`` of the cell's maximum staleness), so the fleet partitions the
    search like the Lloyd controller partitions suppression.

    Why not a staleness density and the Lloyd centroid: that was the first version, and in
    system runs two UAVs circled fixed centroids for four minutes, 73 m from an undetected
    fire: the fresh disc around a circling UAV balances the rest of its cell, an equilibrium
    that stops exploring. A waypoint on the stale frontier is seen as the UAV reaches it, so
    the target always moves on.

    The UAV keeps its waypoint until that point has been seen (by anyone) or has left its
    cell; only then does it choose again. Choosing afresh every step made the waypoint jump
    50-70 m from one 0.1 s step to the next as the stalest set changed under the fleet's
    sensors, so the UAV turned 50-90 deg per step and the waypoint it had published (which
    its peers use to predict a turning UAV, :func:`.separation.peer_rows`) was stale the
    step after: two searching UAVs closed from 34 m to 6 m in 0.2 s in FF unknown-fires,
    14 UAVs, seed 1 (docs/benchmarks.md, acceptance matrix).
    """

    def __init__(
        self, grid: Grid, sensor_range_m: float, horizon_s: float = 120.0, stale_band: float = 0.05
    ) -> None:
        self.grid = grid
        self.r2 = sensor_range_m**2
        self.horizon_s = horizon_s
        self.stale_band = stale_band
        self.last_seen = np.full(grid.points.shape[0], -horizon_s)
        self._xs_list, self._ys_list = grid.xs.tolist(), grid.ys.tolist()  # for observe's bisection
        self._target: int | None = None  # index into grid.points of the committed waypoint
        self._chosen_s = 0.0  # when it was chosen [s]

    def observe(self, t_s: float, positions_xy: np.ndarray) -> None:
        """Mark every grid point within the sensor range of a position as seen at ``t_s``.

        Only the block of grid cells around each position's sensor disc is tested (one cell of
        margin against rounding), not all M points against every position: the same points,
        at O(n r^2 / h^2) instead of O(M n) per step (docs/profile.md).
        """
        p = np.asarray(positions_xy, dtype=float).reshape(-1, 2)
        if p.shape[0] == 0:
            return
        xs, ys, h = self.grid.xs, self.grid.ys, self.grid.resolution_m
        r = float(np.sqrt(self.r2))
        seen = self.last_seen.reshape(ys.size, xs.size)  # a view: row-major (y, x) like Grid.points
        xl, yl = self._xs_list, self._ys_list
        for px, py in p.tolist():
            # bisect_left on the sorted centres is np.searchsorted's default side, one value at a time
            i0, i1 = bisect_left(xl, px - r - h), bisect_left(xl, px + r + h)
            j0, j1 = bisect_left(yl, py - r - h), bisect_left(yl, py + r + h)
            if i0 >= i1 or j0 >= j1:
                continue
            dx = xs[i0:i1] - px
            dy = ys[j0:j1] - py
            block = seen[j0:j1, i0:i1]
            block[(dy[:, None] * dy[:, None] + dx[None, :] * dx[None, :]) <= self.r2] = t_s

    def swept_since_s(self) -> float:
        """[s] Every point of the area has been inside a sensor's range since this time (the
        oldest point's last sighting; ``-horizon_s`` while a point has never been seen). The
        mission's end of the post-fire sweep (:class:`.mission.Mission`)."""
        return float(self.last_seen.min())

    def staleness(self, t_s: float) -> np.ndarray:
        """Per grid point, in [0, 1]: 1 = not seen for ``horizon_s`` (or never)."""
        return np.clip((t_s - self.last_seen) / self.horizon_s, 0.0, 1.0)

    def plan(self, view: PlannerView) -> PlannerTarget | None:
        mask = view.cell_mask
        own = mask is not None and bool(np.any(mask))
        k = self._target
        if k is not None and self.last_seen[k] < self._chosen_s and (not own or bool(mask[k])):
            x, y = self.grid.points[k]  # committed: not seen since chosen, still in the own cell
            return PlannerTarget(waypoint_xy=(float(x), float(y)))
        age = self.staleness(view.t_s)
        cand = np.flatnonzero(mask) if own else np.arange(age.size)
        a = age[cand]
        sel = cand[a >= a.max() - self.stale_band]
        pts = self.grid.points[sel]
        d2 = (pts[:, 0] - view.s[0]) ** 2 + (pts[:, 1] - view.s[1]) ** 2
        k = int(sel[int(np.argmin(d2))])
        self._target, self._chosen_s = k, float(view.t_s)
        x, y = self.grid.points[k]
        return PlannerTarget(waypoint_xy=(float(x), float(y)))
