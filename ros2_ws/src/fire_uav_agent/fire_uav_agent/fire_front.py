"""One agent's picture of a raster fire: the cells it knows, the active front, ROS per direction.

The picture is a grid over the mission area with the raster's cell size (learnt from the first
``FireCells`` sample). Each cell holds the last known state (``CellState`` UNBURNED / BURNING /
BURNED as ``FireCells`` carries it, or ``UNKNOWN`` = never seen) and the sim time of that
observation [s]. Inputs are only this UAV's fire sensor (``observe``) and its peers' shared
fronts (``merge``, newest observation wins per cell: FF III-C's freshness weighting taken to
its limit, since a cell's state is a fact at a time, not a noisy estimate); the world's truth
is never read.

The **active front** is the set of cells last seen BURNING that have at least one of their 8
neighbours UNBURNED or UNKNOWN (fire that can still advance), seen within ``max_age_s``. An
extinguished cell shows as BURNED, so a drop removes its cells from the front.

**Rate of spread per direction** follows PM IV-A: a :class:`fire_perimeter_monitor.fire_map.FireMap`
(PM Table 1, Eq. 1) around the fire centre (centroid of the fire cells known when the map is
made; the ignition point is not known to the fleet) gets the front cells at every update (own
sightings) and peers' front cells with their observation times (``merge_outer``); Eq. 1 gives
ROS per angle bin once a bin is revisited ``revisit_gap_s`` later. Where no bin is known yet
(the first minute), the front cell's distance from the centre stands in, scaled to a nominal
rate: for a wind- or slope-driven ellipse the head is the farthest point from any interior
centre, so the ordering of the front (what head attack needs) is right. This proxy is our
choice; PM has nothing for a fire seen once. Positions [m; map frame], times [s sim].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_perimeter_monitor.fire_map import FireMap, circular_fill
from fire_uav_common.constants import CellState

from .errors import ConfigError, InputError

__all__ = ["UNKNOWN", "FrontCells", "FrontConfig", "FrontPicture"]

UNKNOWN = -1
_UNBURNED = int(CellState.UNBURNED)
# row and column offsets of the 8 neighbours in the framed state grid (FrontPicture._framed)
_NEIGHBOUR_DI = np.array([1 + di for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj])
_NEIGHBOUR_DJ = np.array([1 + dj for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj])


@dataclass(frozen=True)
class FrontCells:
    """Cells of a front picture: centres [m], ``CellState`` values, observation times [s], ROS [m/s].

    ``ros_mps`` is NaN where unknown. The payload of ``FireFront`` (one message per sender).
    """

    x_m: np.ndarray
    y_m: np.ndarray
    state: np.ndarray
    t_obs_s: np.ndarray
    ros_mps: np.ndarray

    def __post_init__(self) -> None:
        n = len(self.x_m)
        if not (len(self.y_m) == len(self.state) == len(self.t_obs_s) == len(self.ros_mps) == n):
            raise ConfigError(
                "front cells: x_m, y_m, state, t_obs_s and ros_mps must have the same length, got "
                f"{[len(a) for a in (self.x_m, self.y_m, self.state, self.t_obs_s, self.ros_mps)]}"
            )

    def __len__(self) -> int:
        return len(self.x_m)

    @staticmethod
    def empty() -> FrontCells:
        z = np.zeros(0)
        return FrontCells(z, z, np.zeros(0, dtype=np.int64), z, z)


@dataclass(frozen=True)
class FrontConfig:
    area_m: tuple[float, float, float, float]  # x_min, x_max, y_min, y_max [m]
    cell_size_m: float  # [m] raster cell side (FireCells.cell_size_m)
    max_age_s: float = 240.0  # [s] a front cell not seen for longer leaves the front
    bin_count: int = 72  # PM fire map angle bins (5 deg)
    revisit_gap_s: float = 30.0  # [s] PM fire map: sightings closer than this are one visit
    min_cells_for_centre: int = 20  # fire cells known before the PM map is centred
    nominal_ros_mps: float = 0.5  # [m/s] scale of the distance proxy before Eq. 1 knows a bin
    record_period_s: float = 1.0  # [s] own front sightings go into the PM map at most this often

    def __post_init__(self) -> None:
        x0, x1, y0, y1 = self.area_m
        if not (x1 > x0 and y1 > y0):
            raise ConfigError(f"front area must be non-empty, got {self.area_m}")
        if not self.cell_size_m > 0:
            raise ConfigError(f"front cell_size_m must be > 0, got {self.cell_size_m}")
        if not self.max_age_s > 0:
            raise ConfigError(f"front max_age_s must be > 0, got {self.max_age_s}")


class FrontPicture:
    """See the module doc. ``observe``/``merge`` cells, then ``front()``."""

    def __init__(self, cfg: FrontConfig) -> None:
        self.cfg = cfg
        x0, x1, y0, y1 = cfg.area_m
        cs = cfg.cell_size_m
        self.nx = max(1, math.ceil((x1 - x0) / cs - 1e-9))
        self.ny = max(1, math.ceil((y1 - y0) / cs - 1e-9))
        # the state grid lives inside a frame of one BURNED cell (not open): the front's neighbour
        # test reads the frame instead of padding the grid at every step
        self._framed = np.full((self.ny + 2, self.nx + 2), CellState.BURNED, dtype=np.int8)
        self.state = self._framed[1:-1, 1:-1]  # a view: writes to it are writes to the frame's inside
        self.state[...] = UNKNOWN
        self.t_obs = np.full((self.ny, self.nx), -np.inf)
        self.fire_map: FireMap | None = None
        self._t_s = -math.inf
        self._t_recorded = -math.inf
        self._version = 0  # bumped by every observe/merge (the front cache's key)
        self._front_cache: tuple[tuple[int, float], FrontCells] | None = None
        self._burning_cache: tuple[tuple[int, float], tuple[np.ndarray, np.ndarray]] | None = None
        # rows i0..i1 and columns j0..j1 (inclusive) holding every cell ever written BURNING: the
        # only block the search for burning cells has to read (empty while i1 < i0)
        self._burn_box = [self.ny, -1, self.nx, -1]

    # --- geometry ------------------------------------------------------------------------
    def index(self, x_m: np.ndarray, y_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(row, col, inside) of cell centres [m]."""
        cs = self.cfg.cell_size_m
        j = np.floor((np.asarray(x_m, dtype=float) - self.cfg.area_m[0]) / cs).astype(np.int64)
        i = np.floor((np.asarray(y_m, dtype=float) - self.cfg.area_m[2]) / cs).astype(np.int64)
        inside = (i >= 0) & (i < self.ny) & (j >= 0) & (j < self.nx)
        return np.where(inside, i, 0), np.where(inside, j, 0), inside

    def centre_xy(self, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        cs = self.cfg.cell_size_m
        return self.cfg.area_m[0] + (j + 0.5) * cs, self.cfg.area_m[2] + (i + 0.5) * cs

    # --- inputs --------------------------------------------------------------------------
    def observe(self, x_m: np.ndarray, y_m: np.ndarray, state: np.ndarray, t_s: float) -> None:
        """This UAV's FireCells sample at ``t_s`` [s] (centres [m], CellState values)."""
        i, j, ok = self.index(x_m, y_m)
        st = np.asarray(state, dtype=np.int64)
        if st.size != ok.size:
            raise InputError(f"observe: {ok.size} cell centres but {st.size} states")
        i, j, st = i[ok], j[ok], st[ok]
        self.state[i, j] = st
        self.t_obs[i, j] = t_s
        self._grow_burn_box(i, j, st)
        self._version += 1
        self._t_s = max(self._t_s, t_s)
        if self.fire_map is None:
            self._maybe_centre()
        if (
            self.fire_map is not None
            and st.size
            and t_s - self._t_recorded >= self.cfg.record_period_s - 1e-9
        ):
            self._t_recorded = t_s
            seen = np.zeros((self.ny, self.nx), dtype=bool)
            seen[i, j] = True
            fi, fj = np.nonzero(self._front_mask(t_s) & seen)
            if fi.size:
                fx, fy = self.centre_xy(fi, fj)
                self.fire_map.record(fx, fy, t_s, link_m=1.5 * self.cfg.cell_size_m)

    def merge(self, cells: FrontCells) -> int:
        """A peer's shared cells; each replaces ours where it is newer. Returns cells taken."""
        if len(cells) == 0:
            return 0
        t = np.asarray(cells.t_obs_s, dtype=float)
        st = np.asarray(cells.state, dtype=np.int64)
        good = np.isfinite(t) & np.isin(st, (CellState.UNBURNED, CellState.BURNING, CellState.BURNED))
        i, j, ok = self.index(cells.x_m, cells.y_m)
        ok &= good
        newer = ok & (t > self.t_obs[i, j])
        i, j, t, st = i[newer], j[newer], t[newer], st[newer]
        # several entries for one cell: the newest wins (sort by time, later writes last)
        order = np.argsort(t, kind="stable")
        self.state[i[order], j[order]] = st[order]
        self.t_obs[i[order], j[order]] = t[order]
        self._grow_burn_box(i, j, st)
        self._version += 1
        if self.fire_map is None:
            self._maybe_centre()
        if self.fire_map is not None:
            b = newer & (np.asarray(cells.state) == CellState.BURNING)
            if b.any():
                self.fire_map.merge_outer(
                    np.asarray(cells.x_m)[b], np.asarray(cells.y_m)[b], np.asarray(cells.t_obs_s)[b]
                )
        return int(newer.sum())

    def _grow_burn_box(self, i: np.ndarray, j: np.ndarray, st: np.ndarray) -> None:
        """Widen the block of cells ever written BURNING by the cells ``(i, j)`` written ``st``."""
        b = st == CellState.BURNING
        if not b.any():
            return
        bi, bj = i[b], j[b]
        box = self._burn_box
        box[0] = min(box[0], int(bi.min()))
        box[1] = max(box[1], int(bi.max()))
        box[2] = min(box[2], int(bj.min()))
        box[3] = max(box[3], int(bj.max()))

    def _maybe_centre(self) -> None:
        fire = (self.state == CellState.BURNING) | (self.state == CellState.BURNED)
        if int(fire.sum()) < self.cfg.min_cells_for_centre:
            return
        i, j = np.nonzero(fire)
        x, y = self.centre_xy(i, j)
        self.fire_map = FireMap(
            float(x.mean()),
            float(y.mean()),
            bin_count=self.cfg.bin_count,
            revisit_gap_s=self.cfg.revisit_gap_s,
        )

    # --- outputs -------------------------------------------------------------------------
    def _front_ij(self, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        """(row, col) of the active front cells at ``t_s`` [s], row-major order.

        Tested only at the burning cells (a few hundred of the grid's cells): a cell outside the
        grid counts as not open, as the zero padding of a whole-grid neighbour test would.
        """
        i, j = self._fresh_burning_ij(t_s)
        if i.size == 0:
            return i, j
        # the 8 neighbours of every cell at once, in the framed grid (row + 1, col + 1 is the cell)
        s = self._framed[i[:, None] + _NEIGHBOUR_DI, j[:, None] + _NEIGHBOUR_DJ]  # (n, 8)
        nb = ((s == _UNBURNED) | (s == UNKNOWN)).any(axis=1)
        return i[nb], j[nb]

    def _fresh_burning_ij(self, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        """(row, col) of the cells last seen BURNING within ``max_age_s`` of ``t_s`` [s]; cached
        until the next ``observe``/``merge`` (the front and the consensus both ask each step).
        Searched in the block of cells ever written BURNING (``_burn_box``), not the whole grid."""
        key = (self._version, t_s)
        if self._burning_cache is not None and self._burning_cache[0] == key:
            return self._burning_cache[1]
        i0, i1, j0, j1 = self._burn_box
        # a BURNING cell lies in the block: its row-major order is the whole grid's
        i, j = np.nonzero(self.state[i0 : i1 + 1, j0 : j1 + 1] == CellState.BURNING)
        i += i0
        j += j0
        with np.errstate(invalid="ignore"):
            fresh = t_s - self.t_obs[i, j] <= self.cfg.max_age_s
        out = (i[fresh], j[fresh])
        self._burning_cache = (key, out)
        return out

    def _front_mask(self, t_s: float) -> np.ndarray:
        mask = np.zeros((self.ny, self.nx), dtype=bool)
        mask[self._front_ij(t_s)] = True
        return mask

    def front(self, t_s: float | None = None) -> FrontCells:
        """The active front at ``t_s`` [s] (default: the latest observation), with ROS [m/s] per cell.

        Cached until the next ``observe``/``merge`` (an agent asks for it several times a step).
        """
        t = self._t_s if t_s is None else t_s
        key = (self._version, t)
        if self._front_cache is not None and self._front_cache[0] == key:
            return self._front_cache[1]
        i, j = self._front_ij(t)
        x, y = self.centre_xy(i, j)
        out = FrontCells(x, y, self.state[i, j].astype(np.int64), self.t_obs[i, j], self.ros_at(x, y))
        self._front_cache = (key, out)
        return out

    def ros_at(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """Rate of spread [m/s] toward the cells' directions from the centre (module doc), NaN if no map."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        fm = self.fire_map
        if fm is None or x.size == 0:
            return np.full(x.shape, np.nan)
        ros = fm.ros_mps()
        known = np.isfinite(ros) & fm.known
        if known.any():
            return circular_fill(np.where(known, ros, np.nan))[fm.bin_of(x, y)]
        d = np.hypot(x - fm.center_x_m, y - fm.center_y_m)
        return self.cfg.nominal_ros_mps * d / max(float(d.max()), self.cfg.cell_size_m)

    def burning_xy(self, t_s: float | None = None) -> np.ndarray:
        """(N, 2) centres [m] of the cells last seen BURNING within ``max_age_s`` of ``t_s`` [s]
        (default: the latest observation): what the consensus's negative evidence must respect."""
        x, y = self.centre_xy(*self._fresh_burning_ij(self._t_s if t_s is None else t_s))
        return np.column_stack([x, y])

    def known_cells(self, states: tuple[int, ...]) -> FrontCells:
        """Every known cell in ``states`` (for sharing retractions and the report)."""
        mask = np.isin(self.state, states)
        i, j = np.nonzero(mask)
        x, y = self.centre_xy(i, j)
        return FrontCells(x, y, self.state[i, j].astype(np.int64), self.t_obs[i, j], np.full(i.size, np.nan))

    def cells_at(self, x_m: np.ndarray, y_m: np.ndarray) -> FrontCells:
        """Our current knowledge of the given cells (state, time), for retractions."""
        i, j, ok = self.index(x_m, y_m)
        i, j = i[ok], j[ok]
        x, y = self.centre_xy(i, j)
        return FrontCells(x, y, self.state[i, j].astype(np.int64), self.t_obs[i, j], np.full(i.size, np.nan))
