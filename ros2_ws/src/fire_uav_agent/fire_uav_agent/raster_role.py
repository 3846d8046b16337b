"""The agent's part over a raster fire: its front picture, the fronts it shares, and the aim point
and release of the tactic (:mod:`.fire_front`, :mod:`.front_consensus`, :mod:`.tactics`). ROS-free.

:class:`RasterSuppression` is made with the agent and stays idle until the first bundle with a
cell size (FireCells): the analytic fires of FF carry none.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping

import numpy as np
from fire_uav_common.codecs.sensor_bundle import Bundle
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective, VehicleStatus

from .agent_config import AgentConfig
from .coverage import Grid, mass_centroid
from .fire_front import FrontCells, FrontConfig, FrontPicture
from .front_consensus import FrontSharing, PeerFront, same_cell_size
from .peer_link import FireEntry
from .tactics import (
    TacticConfig,
    aim_on_front,
    aims_taken,
    choose_anchor,
    free_front,
    front_density,
    front_weights,
    raster_layers,
    release_now,
    standoff_point,
)

__all__ = ["RasterSuppression"]


class RasterSuppression:
    """One agent's front picture, front sharing and tactic over a raster fire."""

    def __init__(self, cfg: AgentConfig, grid: Grid) -> None:
        self.cfg = cfg
        self.grid = grid
        self.front: FrontPicture | None = None  # made at the first FireCells with a cell size
        self.sharing = FrontSharing()
        layers, step, top = raster_layers(  # the altitude stack over a raster fire
            cfg.vehicle.collision_radius_m,
            cfg.sensors.altimeter.max_range_m,
            cfg.guidance.refill_height_fraction * cfg.vehicle.refill_height_m,
            separation_m=cfg.separation.vertical_m,
        )
        self.tactic = TacticConfig(
            tactic=cfg.mission.tactic,
            release_radius_m=0.8 * cfg.drop_radius_m,
            layers=layers,
            layer_step_m=step,
            layer_top_m=top,
            airspace_vertical_m=cfg.separation.vertical_m,
        )
        self.peer_fronts: list[PeerFront] = []  # received since the last step
        # (sender, its cell size [m]) of the peer fronts the last fuse refused for their cell size
        self.cell_size_refused: list[tuple[int, float]] = []
        self.anchor: tuple[float, float] | None = None  # flank tactic: chosen once
        self.fronts_received = 0
        # the tactic's weights, Eq. 13' density and grid index of the last front (see _weighted)
        self._weighted_cache: tuple[tuple, tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None

    def fuse(
        self,
        bundle: Bundle,
        vehicle: VehicleStatus,
        t_s: float,
        reject: Callable[[str], object] = lambda reason: None,
    ) -> None:
        """Own FireCells (airborne) and the peers' shared fronts into this UAV's front picture.

        A peer's front of another cell size than this picture's is not merged (its cells would land
        in the wrong cells: :func:`.front_consensus.same_cell_size`): ``reject("cell size")``
        counts it, and ``cell_size_refused`` names it until the next call."""
        self.cell_size_refused = []
        if self.front is None and bundle.cell_size_m > 0:
            self.front = FrontPicture(FrontConfig(self.cfg.area_m, float(bundle.cell_size_m)))
        if self.front is None:
            self.peer_fronts.clear()
            return
        if vehicle == VehicleStatus.AIRBORNE and bundle.cells is not None:
            self.front.observe(*bundle.cells, t_s)
        for pf in self.peer_fronts:
            if not same_cell_size(pf.cell_size_m, self.front.cfg.cell_size_m):
                reject("cell size")
                self.cell_size_refused.append((pf.uav_id, pf.cell_size_m))
                continue
            try:
                self.front.merge(pf.cells)
                self.fronts_received += 1
            except ValueError:
                pass  # malformed peer message: ignored
        self.peer_fronts.clear()

    def target(
        self,
        bundle: Bundle,
        s: np.ndarray,
        aim: tuple[FireEntry, ...],
        cell: np.ndarray,
        speed_mps: float,
        peers: Mapping[int, PeerState] | None = None,
    ) -> tuple[tuple[FireEntry, ...], bool | None, tuple[float, float] | None]:
        """Aim point on the front (Eq. 13' density, Lloyd centroid in the own ``cell``, tactics), the
        release verdict at ``speed_mps`` and the aim point (None: none). The active fire nearest
        the aim point is re-centred there (extent 0).

        ``peers`` (the alive peers' last states): no aim within ``aim_clear_m`` of the published
        aim of a suppressing right-of-way peer that shares the airspace (:func:`.tactics.aims_taken`);
        with every front cell that close to one, the UAV waits at :func:`.tactics.standoff_point`
        (not re-centring a fire there)."""
        assert self.front is not None
        front = self.front.front(bundle.stamp_s)
        if len(front) == 0 or not aim:
            return aim, None if not aim else False, None
        if self.tactic.tactic == "flank" and self.anchor is None:
            self.anchor = choose_anchor(front)
        w, dens, on_grid = self._weighted(front)
        _, c = mass_centroid(self.grid.points, dens, cell, self.grid.cell_area_m2)
        in_cell = cell[on_grid]
        near = (float(s[0]), float(s[1])) if c is None else (float(c[0]), float(c[1]))
        taken = aims_taken(
            self.cfg.uav_id,
            [
                (j, p.objective == Objective.SUPPRESS, p.centroid_x_m, p.centroid_y_m)
                for j, p in (peers or {}).items()
            ],
            self.tactic,
        )
        xy = aim_on_front(near, front, w, in_cell, free_front(front, taken, self.tactic.aim_clear_m))
        if xy is None:
            if taken.shape[0] == 0:
                return aim, False, None
            wait = standoff_point((float(s[0]), float(s[1])), near, taken, self.tactic.aim_clear_m)
            return aim, self._release(bundle, s, speed_mps), wait
        k = min(range(len(aim)), key=lambda n: math.hypot(aim[n].x_m - xy[0], aim[n].y_m - xy[1]))
        aim = tuple(
            dataclasses.replace(e, x_m=xy[0], y_m=xy[1], extent_m=0.0) if n == k else e
            for n, e in enumerate(aim)
        )
        return aim, self._release(bundle, s, speed_mps), xy

    def _weighted(self, front: FrontCells) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The tactic's weights w_i, the Eq. 13' density on the grid and each front cell's flat grid
        index, for ``front``.

        These depend only on the front cells' centres and ROS (and the flank anchor), which stay
        the same over most control steps (a cell burns or goes out every few seconds; the picture's
        version changes at every observation, with the cells' observation times): they are kept
        for the last front and recomputed only when those bytes change. Read-only arrays."""
        key = (front.x_m.tobytes(), front.y_m.tobytes(), front.ros_mps.tobytes(), self.anchor)
        if self._weighted_cache is not None and self._weighted_cache[0] == key:
            return self._weighted_cache[1]
        w = front_weights(front, self.tactic, self.anchor)
        dens = front_density(self.grid, front, w, self.tactic.sigma_m)
        res = self.grid.resolution_m
        ny, nx = self.grid.shape
        gj = np.clip(np.floor((front.x_m - self.grid.xs[0]) / res + 0.5).astype(int), 0, nx - 1)
        gi = np.clip(np.floor((front.y_m - self.grid.ys[0]) / res + 0.5).astype(int), 0, ny - 1)
        out = (w, dens, gi * nx + gj)
        for a in out:
            a.setflags(write=False)
        self._weighted_cache = (key, out)
        return out

    def _release(self, bundle: Bundle, s: np.ndarray, speed_mps: float) -> bool:
        """The release rule (:func:`.tactics.release_now`) at the estimated pose ``s``."""
        return release_now(
            bundle.cells,
            (float(s[0]), float(s[1])),
            float(s[3]),
            speed_mps * self.cfg.control_period_s,
            self.tactic,
        )

    def message(self, bundle: Bundle):
        """This step's FireFront payload (every ``front_every_steps`` steps), or None."""
        if self.front is None or bundle.step % max(1, self.cfg.front_every_steps) != 0:
            return None
        return self.sharing.message(self.front, bundle.stamp_s)
