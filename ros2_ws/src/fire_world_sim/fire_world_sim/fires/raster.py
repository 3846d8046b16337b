"""Raster fire (PM section VI, after DEVS-FIRE): a cell space with Rothermel spread.

Each cell of ``nx x ny`` squares of ``cell_size_m`` has a fuel model (scenario default plus
rectangular patches; lake cells have no fuel), the dead fuel moisture of the scenario, and the
terrain slope under its centre. Wind (midflame) is piecewise constant in time. For every cell,
Rothermel (1972) gives the head rate of spread R_h and its direction (wind and slope added as
vectors, :func:`~.rothermel.head_spread`), and Behave's length-to-width ratio L/W gives the
spread ellipse with the ignition at its rear focus (Anderson 1983; Behave's
``R(theta) = R_h (1 - e) / (1 - e cos theta)``).

PM VI only says that "burning cells ignite their unburned neighboring cells" with Rothermel's
rate and direction; a neighbour-to-neighbour scheme like that is exact only along neighbour
directions (a 16-neighbour stencil made a grass fire 17-79 % too slow and locked its head to a
grid axis). We keep the cell space and compute ARRIVAL TIMES of a front that moves with the
elliptical wavelet in every direction (Huygens' principle, as FARSITE; the level-set form with
the wavelet's normal speed is Richards 1990, used by WRF-SFIRE). The travel time of the
wavelet of a cell over a displacement v [m] is the gauge of its ellipse

    tau(v) = (a |v| - c (v . h)) / b^2                                            (1)

with a = (R_h + R_b)/2, c = (R_h - R_b)/2, b^2 = R_h R_b, R_b = R_h (1 - e)/(1 + e) the backing
rate and h the unit head direction: (1) is exact for a homogeneous ellipse (tau(R(theta) t u) =
t). A cell's arrival time is the minimum over the segments [s1, s2] between two consecutive
nodes of its 8- and 16-neighbour rings (24 segments, nodes already ignited, at least one of
them burning) of

    T(x) = min_{0 <= l <= 1}  (1 - l) T(s1) + l T(s2) + tau(x - s1 - l (s2 - s1))        (2)

i.e. the front crossing the segment is interpolated linearly and the wavelet runs straight
from the crossing point to x: a semi-Lagrangian (ordered-upwind, Sethian & Vladimirsky 2003)
update whose minimiser has a closed form because (1) is a norm plus a linear term. With the
segment end points (single-node Huygens updates) included, directions are no longer tied to
the grid. tau is that of the TARGET cell (the fuel being burnt into), which also makes a
non-burnable cell unreachable. A node whose straight path to the target crosses a non-burnable
cell (or squeezes between two at a corner) is not used for that target
(:func:`.ring_update.blocked_nodes`): the 16-neighbour ring would otherwise carry the fire over a
one-cell road or stream, which minimum-travel-time spread (Finney 2002), FARSITE's barriers and
pyretechnics' level set do not cross. Cells within 3 cells of an ignition point get the exact (1)
from the point itself, so the first cell hops do not bias the fire (not across a non-burnable
cell either).

Propagation is batched every ``update_period_s``: the update runs over the narrow band of
unburned cells within two cells of a burning one (numpy, gathered by flat index, memory O(band)),
accepts every cell whose arrival time is <= t1 and iterates until nothing new ignites. The
compiled path (:mod:`.ring_kernel`) keeps the band's arrival times and the burning cells'
burn-out times in heaps and skips an update due before both the next arrival and the next
burn-out (it would change nothing): the same bits, fewer reads.
A cell burns from ``t_ign`` until ``t_ign + max(residence + crossing time, tau to reach its
still-unburned ring neighbours)``, then it is burnt out. A drop wets the cells within its
radius: burning cells are extinguished (they spread no more) and unburned cells cannot ignite
for ``wet_duration_s``; with ``fires.drop_model: pattern`` a drop is a ground pattern with a
coverage per cell instead (:meth:`RasterFireModel.apply_pattern`, :mod:`..drop_pattern`).
Fire ids are the ignition indices; each cell carries the id of the ignition that reached it first. Ignitions may start before t = 0: the model pre-burns from
the earliest one to t = 0 at construction. Time unit: seconds of sim time; lengths in metres.

On a landscape (``spec.landscape``, :mod:`fire_uav_common.scenario.ground`) each cell has its
own fuel model (the 53 standard models; 91-99 and cells outside the data never burn), slope and
aspect from the layers, and its canopy; the wind entries are the 20-ft wind, and head rate,
direction, effective wind, residence time and fire type per cell come from
:meth:`.landscape_cells.LandscapeCells.behavior` (FlamMap's basic run: the five moisture classes, the per-cell
wind adjustment factor, crown fire by Finney's method). The spread ellipse of a crowning cell
keeps its surface fire's length-to-breadth ratio, with the crown fire's head rate.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from fire_uav_common.constants import CellState, FireStatus
from fire_uav_common.scenario import Raster
from fire_uav_common.terrain import Terrain

from ..drop_pattern import (
    L_PER_M2_PER_CL,
    MIN_FOOTPRINT_CL,
    DropPattern,
    coverage_lpm2,
    required_coverage_lpm2,
)
from ..sensors import CellsSample
from .base import FireGrid, FireTruthRecord
from .crown import FireType
from .fuel_models import fuel_model
from .landscape_cells import LandscapeCells
from .ring_update import RING, RingGeometry, _unique, arrival, blocked_nodes
from .rothermel import ellipse_eccentricity, head_spread, length_to_breadth, spread_params

__all__ = ["RING", "RasterFireModel"]


PAD = 2
MAX_BURN_S = 3600.0
DEFAULT_DROP_RADIUS_M = 20.0
SEED_RADIUS_CELLS = 3  # cells within this of an ignition point get the exact wavelet time (1)
MAX_SWEEPS = 64  # acceptance passes per update (each pass ignites every cell due by t1)


class RasterFireModel:
    """Raster fire over ``spec``'s grid; ``update_period_s`` batches propagation updates.

    ``compiled`` (default) runs the update in the compiled kernels of :mod:`.ring_kernel`;
    ``compiled=False`` runs the numpy reference path, which gives bit-identical arrival times
    (kept for the tests that show it)."""

    def __init__(
        self,
        spec: Raster,
        terrain: Terrain,
        *,
        lakes: tuple = (),
        drop_radius_m: float | None = None,
        update_period_s: float = 0.5,
        compiled: bool = True,
    ) -> None:
        self.spec = spec
        self.compiled = compiled
        self.cs = spec.cell_size_m
        self.nx, self.ny = spec.nx, spec.ny
        self.drop_radius_m = drop_radius_m if drop_radius_m is not None else DEFAULT_DROP_RADIUS_M
        self.update_period_s = update_period_s
        self.wind_limit = getattr(spec, "wind_limit", "behave")
        shape = (self.ny + 2 * PAD, self.nx + 2 * PAD)
        self._shape = shape
        self.xc = spec.origin.x_m + (np.arange(self.nx) + 0.5) * self.cs  # [m] cell centres east
        self.yc = spec.origin.y_m + (np.arange(self.ny) + 0.5) * self.cs  # [m] cell centres north
        xx, yy = np.meshgrid(self.xc, self.yc)
        self._xx, self._yy = xx, yy  # [m] cell centres (ny, nx), read-only
        xx.flags.writeable = False
        yy.flags.writeable = False
        # fuel per cell
        self._land: LandscapeCells | None = None
        self.fire_type = np.zeros((self.ny, self.nx), dtype=np.uint8)  # FireType per cell (landscape)
        if spec.landscape is not None:
            self._land = LandscapeCells.read(spec.landscape, self.ny, self.nx)
            fuel = self._land.fuel.copy()
        else:
            fuel = np.full((self.ny, self.nx), spec.fuel_model, dtype=np.int16)
            for p in spec.fuel_patches:
                fuel[(xx >= p.x_min_m) & (xx < p.x_max_m) & (yy >= p.y_min_m) & (yy < p.y_max_m)] = (
                    p.fuel_model
                )
        for lake in lakes:
            fuel[(xx - lake.x_m) ** 2 + (yy - lake.y_m) ** 2 <= (lake.diameter_m / 2) ** 2] = 0
        self.fuel = fuel
        self._required_lpm2: np.ndarray | None = None  # coverage that puts a cell out (patterns)
        self._params = (
            {}
            if self._land is not None
            else {int(m): spread_params(fuel_model(int(m)), spec.moisture) for m in np.unique(fuel) if m > 0}
        )
        # slope from the terrain (central differences on the cell centres)
        elev = np.asarray(terrain.elevation(xx, yy), dtype=float)
        if self.nx > 1 and self.ny > 1:
            gy, gx = np.gradient(elev, self.cs)
        else:  # pragma: no cover - grids are >= 3x3
            gx = gy = np.zeros_like(elev)
        self.slope_tan = np.hypot(gx, gy)
        self.upslope_dir = np.arctan2(gy, gx)
        self.burnable = np.zeros(shape, dtype=bool)
        inner = (slice(PAD, PAD + self.ny), slice(PAD, PAD + self.nx))
        self._inner = inner
        r0 = np.zeros((self.ny, self.nx))
        for m, sp in self._params.items():
            r0[fuel == m] = sp.r0_mps
        if self._land is not None:  # no wind, the cells' own slope: > 0 wherever the fuel can burn
            r0 = self._land.behavior(fuel, 0.0, 0.0, self.wind_limit).surface_ros_mps
        self.burnable[inner] = r0 > 0
        # per cell, the ring nodes whose path to it crosses a non-burnable cell (static: fuel, water)
        self._blocked = blocked_nodes(~self.burnable).ravel()
        # dynamic state (padded)
        self.t_ign = np.full(shape, np.inf)
        self.t_out = np.full(shape, np.inf)
        self.label = np.full(shape, -1, dtype=np.int32)
        self._burn_type = np.zeros(shape, dtype=np.uint8)  # FireType a cell burned with (landscape)
        self.extinguished = np.zeros(shape, dtype=bool)
        self.wet_until = np.full(shape, -np.inf)
        self._t_seed = np.full(shape, np.inf)  # exact wavelet times (1) near ignition points
        self._seed_label = np.full(shape, -1, dtype=np.int32)
        # the update's sources kept up to date cell by cell, so that no pass scans the whole grid:
        # flat indices of ignited, not extinguished cells not yet burnt out at the last update,
        # and the same as a mask; cells holding a seed time (1)
        self._live = np.zeros(0, dtype=np.intp)
        self._live_mask = np.zeros(shape[0] * shape[1], dtype=bool)
        self._seeded = np.zeros(0, dtype=np.intp)
        self._band: np.ndarray | None = None  # cells near a source or seeded (None: to compute)
        self._mark = np.zeros(shape[0] * shape[1], dtype=bool)  # scratch for _unique, kept all False
        # arrival time (2) and fire id per target cell from its ring nodes, kept until a node or
        # the cell's wavelet changes (NaN: to compute); the seed times (1) apply on top
        self._arr_t = np.full(shape[0] * shape[1], np.nan)
        self._arr_lab = np.full(shape[0] * shape[1], -1, dtype=np.int32)
        # update geometry: flat offsets of the ring nodes, vectors node -> target [m]
        w = shape[1]
        self._geom = RingGeometry.of(w, self.cs)
        self._ring_flat, self._vx, self._vy = self._geom.ring_flat, self._geom.vx, self._geom.vy
        # the compiled path's bookkeeping (ring_kernel): live cells (a min-heap by burn-out time),
        # narrow band and the queue of cells whose arrival time was invalidated, as buffers with
        # _meta = [n_live, n_band, n_queued, rebuild the live heap, ...], band and queue membership as
        # masks, live cells per fire id (+1), and _tnext = [a lower bound of the band's next
        # arrival time, the earliest burn-out time]: an update due before both changes nothing
        n_cells = shape[0] * shape[1]
        self._k: Any = None  # the kernels' module, imported here (numba costs ~0.3 s to import)
        if compiled:
            from . import ring_kernel

            self._k = ring_kernel
            self._gi, self._gf = ring_kernel.pack_geometry(self._geom)
        self._live_buf = np.zeros(n_cells if compiled else 0, dtype=np.int64)
        self._band_buf = np.zeros(n_cells if compiled else 0, dtype=np.int64)
        self._in_band = np.zeros(n_cells if compiled else 0, dtype=bool)
        self._dirty_buf = np.zeros(n_cells if compiled else 0, dtype=np.int64)
        self._is_dirty = np.zeros(n_cells if compiled else 0, dtype=bool)
        self._live_count = np.zeros(len(spec.ignitions) + 1, dtype=np.int64)
        # the band's arrival times as a min-heap of (time [s], cell, cell version, fire id), an
        # entry stale once its cell's version moved on; its size in _meta[4]
        n_heap = n_cells + 1 if compiled else 0
        self._ver = np.zeros(n_cells if compiled else 0, dtype=np.int64)
        self._heap = (
            np.empty(n_heap),
            np.empty(n_heap, dtype=np.int64),
            np.empty(n_heap, dtype=np.int64),
            np.empty(n_heap, dtype=np.int32),
        )
        self._meta = np.array([0, 0, 0, 0, 0, 1], dtype=np.int64)  # _meta[5]: rebuild the band heap
        self._tnext = np.full(2, -np.inf)  # [s]
        self._kst: tuple | None = None  # the kernels' arguments (_kernel_state)
        self._kst_src: np.ndarray | None = None  # the fire-type grid they were made with
        self._active_flags = np.zeros(len(spec.ignitions) + 1, dtype=bool)  # ids burning (+1), last asked
        self._active_set: set[int] = set()  # the same as a set
        self._kst_prop: tuple = ()
        self._kst_act: tuple = ()
        self._kst_gone: tuple = ()
        self._wind_next_s = -math.inf  # [s] the wind segment cannot change before this
        # per-cell wavelet (1): tau(v) = A |v| - Cx vx - Cy vy  [s/m]; A = inf where nothing burns
        self._A = np.full(shape, np.inf)
        self._Cx = np.zeros(shape)
        self._Cy = np.zeros(shape)
        self._head = np.zeros(shape)  # [m/s] head rate of spread
        self._head_dir = np.zeros(shape)  # [rad] head direction, ccw from +x
        self._res = np.zeros(shape)  # [s] residence + crossing time
        self._wind_index = -1
        starts = [ig.start_s for ig in spec.ignitions]
        self.t_start_s = min([0.0, *starts])  # [s] the model's own clock starts here
        self.t_s = self.t_start_s
        self._t_updated = self.t_start_s
        self._active_at_update: set[int] | None = None  # fire ids burning at the last update
        self._drops = [0] * len(spec.ignitions)
        self._ignited = [False] * len(spec.ignitions)
        self._truth_cache: list[FireTruthRecord] | None = None
        self._pending_events: list[tuple[int, str]] = []
        self.last_ignition_s = -math.inf  # [s] latest ignition time of any cell (containment)
        self.last_drop_cells = (0, 0)  # (burning cells wet, cells in the footprint) of the last drop
        self.last_drop_out_cells = 0  # burning cells the last pattern drop put out
        self._set_wind(self.t_start_s)
        if self.t_start_s < 0.0:
            self._preburn()

    # --- spread rates ------------------------------------------------------------------------
    def _segment_index(self, t_s: float) -> int:
        idx = 0
        for i, seg in enumerate(self.spec.wind):
            if seg.start_s <= t_s + 1e-9:
                idx = i
        return idx

    def wind_at(self, t_s: float) -> tuple[float, float]:
        """(midflame speed [m/s], direction the wind blows toward [rad ccw from +x]) at t_s; on a
        landscape the 20-ft wind, and for a gridded entry its domain (mean) wind: the cells'
        own winds are the grid's (:meth:`.landscape_cells.LandscapeCells.behavior`)."""
        w = self.spec.wind[self._segment_index(t_s)]
        return w.speed_mps, math.radians(w.direction_deg)

    def _set_wind(self, t_s: float) -> bool:
        if t_s + 1e-9 < self._wind_next_s:  # no segment starts before t_s
            return False
        idx = self._segment_index(t_s)
        later = [w.start_s for w in self.spec.wind if w.start_s > t_s + 1e-9]
        self._wind_next_s = min(later, default=math.inf)  # time runs forward from here
        if idx == self._wind_index:
            return False
        self._wind_index = idx
        speed, direction = self.wind_at(t_s)
        inner = self._inner
        head = np.zeros((self.ny, self.nx))
        hdir = np.zeros((self.ny, self.nx))
        ueff = np.zeros((self.ny, self.nx))
        res = np.zeros((self.ny, self.nx))
        if self._land is not None:
            w = self.spec.wind[self._wind_index]
            b = self._land.behavior(self.fuel, w.speed_mps, w.direction_deg, self.wind_limit, grid=w.grid)
            head = b.ros_mps * self.spec.spread_factor
            hdir = np.radians(90.0 - b.spread_dir_deg)
            ueff = b.effective_wind_mps
            res = b.residence_s
            self.fire_type = np.where(self.burnable[inner], b.fire_type, FireType.UNBURNABLE).astype(np.uint8)
        for m, p in self._params.items():
            mask = self.fuel == m
            r, d, u = head_spread(
                p, speed, direction, self.slope_tan[mask], self.upslope_dir[mask], wind_limit=self.wind_limit
            )
            head[mask] = np.asarray(r) * self.spec.spread_factor
            hdir[mask] = d
            ueff[mask] = u
            res[mask] = p.residence_time_s
        ecc = np.asarray(ellipse_eccentricity(length_to_breadth(ueff)))
        ok = head > 0
        rh = np.where(ok, head, 1.0)
        rb = rh * (1.0 - ecc) / (1.0 + ecc)  # backing rate
        a = 0.5 * (rh + rb)
        c = 0.5 * (rh - rb)
        b2 = rh * rb
        self._A[inner] = np.where(ok, a / b2, np.inf)
        self._Cx[inner] = np.where(ok, c / b2 * np.cos(hdir), 0.0)
        self._Cy[inner] = np.where(ok, c / b2 * np.sin(hdir), 0.0)
        self._head[inner] = head
        self._head_dir[inner] = hdir
        self._res[inner] = res + np.where(ok, self.cs / rh, 0.0)
        self._arr_t[:] = np.nan  # every wavelet changed
        self._meta[5] = 1  # the compiled path reads its whole band again
        return True

    def _tau(self, idx: np.ndarray, vx: np.ndarray, vy: np.ndarray) -> np.ndarray:
        """Travel time (1) [s] of the wavelet of flat cells ``idx`` over (vx, vy) [m] (broadcast)."""
        a = self._A.ravel()[idx]
        return a * np.hypot(vx, vy) - self._Cx.ravel()[idx] * vx - self._Cy.ravel()[idx] * vy

    # --- state -------------------------------------------------------------------------------
    def _burning(self, t_s: float, box: tuple[slice, slice] | None = None) -> np.ndarray:
        """Burning cells at ``t_s`` [s], over the padded grid or only its window ``box``."""
        if box is None:
            return (self.t_ign <= t_s) & (t_s < self.t_out) & ~self.extinguished
        return (self.t_ign[box] <= t_s) & (t_s < self.t_out[box]) & ~self.extinguished[box]

    def _ignite(self, idx: tuple[np.ndarray, np.ndarray], t: np.ndarray, labels: np.ndarray) -> None:
        """Ignite padded cells ``idx`` at times ``t`` with fire ids ``labels``; set their burn-out time."""
        if not self.compiled:
            self._ignite_numpy(idx, t, labels)
            return
        flat = np.ravel_multi_index(idx, self._shape).astype(np.int64)
        times = np.asarray(t, dtype=float).ravel()
        latest = self._k.ignite(
            flat, times, np.asarray(labels, dtype=np.int32).ravel(), *self._kernel_state()
        )
        self.last_ignition_s = max(self.last_ignition_s, latest)
        self._truth_cache = None

    def _kernel_state(self) -> tuple:
        """The flat grids and bookkeeping :func:`.ring_kernel.ignite` takes after its batch (flat
        views of the model's grids, made once; again when the fire types are a new array)."""
        st = self._kst
        if st is not None and self.fire_type is self._kst_src:
            return st
        self._kst_src = self.fire_type
        st = self._kst = (
            self.t_ign.ravel(),
            self.t_out.ravel(),
            self.label.ravel(),
            self._burn_type.ravel(),
            self.fire_type.ravel(),
            self._land is not None,
            self._shape[1],
            PAD,
            self.nx,
            self._t_seed.ravel(),
            self.burnable.ravel(),
            self.extinguished.ravel(),
            self._A.ravel(),
            self._Cx.ravel(),
            self._Cy.ravel(),
            self._res.ravel(),
            MAX_BURN_S,
            self._live_buf,
            self._live_mask,
            self._band_buf,
            self._in_band,
            self._arr_t,
            self._dirty_buf,
            self._is_dirty,
            self._live_count,
            self._gi,
            self._gf,
            self._meta,
            self._tnext,
            self._blocked,
        )
        # the arguments of propagate before the seeded cells and after them
        self._kst_prop = (
            (*st[:10], self._seed_label.ravel()),
            (*st[10:12], self.wet_until.ravel(), *st[12:21], self._arr_t, self._arr_lab, *st[22:25])
            + (self._ver, *self._heap, *st[25:]),
        )
        # of remove_gone after t0, and of active_fires after (t_s, t0, ign_ok)
        live = (self._live_buf, self._live_mask, self._arr_t, self._dirty_buf, self._is_dirty)
        self._kst_gone = (st[1], st[11], st[2], *live, self._live_count, self._gi, self._meta, self._tnext)
        self._kst_act = (st[0], *self._kst_gone, self._active_flags)
        return st

    def _ignite_numpy(self, idx: tuple[np.ndarray, np.ndarray], t: np.ndarray, labels: np.ndarray) -> None:
        """The numpy reference of :meth:`_ignite`."""
        self.t_ign[idx] = t
        if np.size(t):
            self.last_ignition_s = max(self.last_ignition_s, float(np.max(t)))
        self.label[idx] = labels
        if self._land is not None:  # the highest type under the winds it burned in
            now = self.fire_type[idx[0] - PAD, idx[1] - PAD]
            self._burn_type[idx] = np.maximum(self._burn_type[idx], now)
        self._t_seed[idx] = np.inf
        flat = np.ravel_multi_index(idx, self._shape)
        add = flat[~self._live_mask[flat]]
        self._live_mask[add] = True
        self._live = np.concatenate([self._live, add])
        self._changed(flat)
        self._band = None
        nb = flat[:, None] - self._ring_flat[None, :]  # the cells this one is a node for
        pending = (
            self.burnable.ravel()[nb]
            & (self.t_ign.ravel()[nb] > t[:, None])
            & ~self.extinguished.ravel()[nb]
            & (((self._blocked[nb] >> np.arange(len(self._ring_flat), dtype=np.uint32)[None, :]) & 1) == 0)
        )
        tau = self._tau(nb, self._vx[None, :], self._vy[None, :])
        longest = np.max(np.where(pending, tau, 0.0), axis=1, initial=0.0)
        longest = np.maximum(longest, self._res[idx])
        self.t_out[idx] = t + np.minimum(longest, MAX_BURN_S)
        self._truth_cache = None

    def _cell_index(self, x_m: float, y_m: float) -> tuple[int, int] | None:
        j = math.floor((x_m - self.spec.origin.x_m) / self.cs)
        i = math.floor((y_m - self.spec.origin.y_m) / self.cs)
        if 0 <= i < self.ny and 0 <= j < self.nx:
            return i + PAD, j + PAD
        return None

    def _start_ignitions(self, t1: float) -> list[int]:
        new = []
        for n, ig in enumerate(self.spec.ignitions):
            if self._ignited[n] or ig.start_s > t1 + 1e-9:
                continue
            self._ignited[n] = True
            new.append(n)
            cell = self._cell_index(ig.x_m, ig.y_m)
            if cell is None or not self.burnable[cell] or np.isfinite(self.t_ign[cell]):
                continue
            self._ignite(
                (np.array([cell[0]]), np.array([cell[1]])),
                np.array([ig.start_s]),
                np.array([n], dtype=np.int32),
            )
            self._seed(n, cell)
        return new

    def _seed(self, n: int, cell: tuple[int, int]) -> None:
        """Exact wavelet times (1) from ignition point ``n`` to the cells around ``cell``."""
        ig = self.spec.ignitions[n]
        k = SEED_RADIUS_CELLS
        i0, i1 = max(cell[0] - k, PAD), min(cell[0] + k + 1, self.ny + PAD)
        j0, j1 = max(cell[1] - k, PAD), min(cell[1] + k + 1, self.nx + PAD)
        gi, gj = np.meshgrid(np.arange(i0, i1), np.arange(j0, j1), indexing="ij")
        ii, jj = gi.ravel(), gj.ravel()
        vx = self.xc[jj - PAD] - ig.x_m
        vy = self.yc[ii - PAD] - ig.y_m
        keep = np.hypot(vx, vy) <= k * self.cs
        ii, jj, vx, vy = ii[keep], jj[keep], vx[keep], vy[keep]
        flat = np.ravel_multi_index((ii, jj), self._shape)
        t = ig.start_s + self._tau(flat, vx, vy)
        sel = self.burnable[ii, jj] & ~np.isfinite(self.t_ign[ii, jj]) & (t < self._t_seed[ii, jj])
        sel &= self._clear_path(ig.x_m, ig.y_m, ii, jj)
        self._t_seed[ii[sel], jj[sel]] = t[sel]
        self._seed_label[ii[sel], jj[sel]] = n
        self._seeded = np.concatenate([self._seeded, flat[sel]])
        self._band = None

    def _clear_path(self, x_m: float, y_m: float, ii: np.ndarray, jj: np.ndarray) -> np.ndarray:
        """Whether the straight path from (x_m, y_m) to the centre of each padded cell (ii, jj)
        stays on burnable cells (sampled every 1/8 of a cell: at most 3 cells here)."""
        f = np.linspace(0.0, 1.0, 8 * SEED_RADIUS_CELLS + 1)[None, :]
        px = x_m + (self.xc[jj - PAD][:, None] - x_m) * f
        py = y_m + (self.yc[ii - PAD][:, None] - y_m) * f
        pj = np.clip(np.floor((px - self.spec.origin.x_m) / self.cs).astype(np.intp), 0, self.nx - 1) + PAD
        pi = np.clip(np.floor((py - self.spec.origin.y_m) / self.cs).astype(np.intp), 0, self.ny - 1) + PAD
        return self.burnable[pi, pj].all(axis=1)

    def _propagate(self, t0: float, t1: float) -> None:
        """Ignite every cell whose arrival time (2) is <= t1 (repeated passes for multi-hop spread)."""
        if not self.compiled:
            self._propagate_numpy(t0, t1)
            return
        if self._seeded.size:
            self._seeded = self._seeded[np.isfinite(self._t_seed.ravel()[self._seeded])]
        self._kernel_state()
        a, b = self._kst_prop
        latest = self._k.propagate(t0, t1, MAX_SWEEPS, *a, self._seeded, *b)
        if latest > self.last_ignition_s:
            self.last_ignition_s = latest
            self._truth_cache = None

    def _propagate_numpy(self, t0: float, t1: float) -> None:
        """The numpy reference of :meth:`_propagate`."""
        t_ign = self.t_ign.ravel()
        ext = self.extinguished.ravel()
        burnable = self.burnable.ravel()
        for _ in range(MAX_SWEEPS):
            # sources: ignited (all at or before t1), not yet burnt out at t0, not extinguished
            sidx = self._sources(t0)
            band = self._band
            if band is None:
                seeded = self._seeded = _unique(self._seeded[np.isfinite(self._t_seed.ravel()[self._seeded])])
                if sidx.size == 0 and seeded.size == 0:
                    return
                band = _unique(
                    np.concatenate([(sidx[:, None] + self._ring_flat[None, :]).ravel(), seeded]), self._mark
                )
                self._band = band
            tgt = band[burnable[band] & ~np.isfinite(t_ign[band]) & ~ext[band]]
            if tgt.size == 0:
                return
            need = tgt[np.isnan(self._arr_t[tgt])]
            if need.size:
                self._arr_t[need], self._arr_lab[need] = self._arrival(need, self._live_mask, t1)
            best, lab = self._arr_t[tgt], self._arr_lab[tgt]
            # exact times from the ignition points, while their fire still burns: a wavelet (1)
            # from a fire that drops have put out whole has no front left to carry it
            seed = self._t_seed.ravel()[tgt]
            seed_fire = self._seed_label.ravel()[tgt]
            burning_fires = np.zeros(len(self.spec.ignitions) + 1, dtype=bool)
            burning_fires[self.label.ravel()[sidx] + 1] = True  # ids shifted by one: -1 is none
            use_seed = (seed < best) & burning_fires[seed_fire + 1]
            best = np.where(use_seed, seed, best)
            lab = np.where(use_seed, self._seed_label.ravel()[tgt], lab)
            t_arr = np.maximum(best, self.wet_until.ravel()[tgt])
            new = t_arr <= t1
            if not new.any():
                return
            idx = np.unravel_index(tgt[new], self._shape)
            self._ignite(idx, t_arr[new], lab[new])

    def _sources(self, t0: float) -> np.ndarray:
        """Flat indices of the cells burning at some time after ``t0`` (up to the update's end):
        the live cells less those burnt out by ``t0`` or extinguished since (both for good)."""
        if self.compiled:
            self._kernel_state()
            self._k.remove_gone(t0, *self._kst_gone)
            return self._live_buf[: self._meta[0]]
        live = self._live
        keep = (self.t_out.ravel()[live] > t0) & ~self.extinguished.ravel()[live]
        gone = live[~keep]
        if gone.size:
            self._live_mask[gone] = False
            self._changed(gone)
            self._band = None
        self._live = live[keep]
        return self._live

    def _changed(self, flat: np.ndarray) -> None:
        """Nodes ``flat`` changed (ignited, burnt out, extinguished): their targets' arrival
        times (2) are to be computed again."""
        self._arr_t[(flat[:, None] - self._ring_flat[None, :]).ravel()] = np.nan

    def _arrival(self, tgt: np.ndarray, src: np.ndarray, t1: float) -> tuple[np.ndarray, np.ndarray]:
        """Arrival time (2) [s] and fire id of the flat target cells ``tgt`` (:func:`.ring_update.arrival`)."""
        flat = (self.t_ign.ravel(), self.extinguished.ravel(), self.label.ravel())
        cells = (self._A.ravel(), self._Cx.ravel(), self._Cy.ravel(), self._blocked)
        return arrival(self._geom, tgt, src, t1, *flat, *cells)

    def _preburn(self) -> None:
        """Burn from the earliest ignition (start_s < 0) to t = 0; their ignitions are reported
        by the first step."""
        t = self.t_start_s
        while t < -1e-9:
            dt = min(self.update_period_s, -t)
            self._pending_events += self._advance(t + dt)
            t += dt
        self.t_s = 0.0
        self._t_updated = 0.0

    # --- FireModel interface ---------------------------------------------------------------
    def step(self, t_s: float, dt_s: float) -> list[tuple[int, str]]:
        events, self._pending_events = self._pending_events, []
        return [*events, *self._advance(t_s + dt_s)]

    def _advance(self, t1: float) -> list[tuple[int, str]]:
        self.t_s = t1
        events = [(n, "ignition") for n in self._start_ignitions(t1)]
        if t1 - self._t_updated >= self.update_period_s - 1e-9 or events:
            tn = self._tnext  # compiled: before the next arrival and burn-out nothing changes
            if not events and t1 < tn[0] and t1 < tn[1] and t1 + 1e-9 < self._wind_next_s:
                self._t_updated = t1  # the update would ignite nothing and burn nothing out
                self._truth_cache = None
                return events
            # burning at the previous update, as it was then: recomputed now, a drop since then
            # would already have removed a fire it put out, and its event would be lost
            was_active = self._active_at_update
            if was_active is None:
                was_active = self._active_ids(self._t_updated)
            if self._set_wind(t1):
                # burning cells re-derive their burn-out time under the new wind
                bi, bj = np.nonzero(self._burning(t1))
                burning = (bi, bj)
                if bi.size:
                    self._ignite(burning, self.t_ign[burning], self.label[burning])
            self._propagate(self._t_updated, t1)
            self._t_updated = t1
            self._truth_cache = None
            now_active = self._active_ids()
            self._active_at_update = now_active
            events += [(n, "extinguished") for n in sorted(was_active - now_active) if self._ignited[n]]
        return events

    def _active_ids(self, t_s: float | None = None) -> set[int]:
        t = self.t_s if t_s is None else t_s
        if t >= self._t_updated and self.compiled:
            self._kernel_state()
            ign_ok = self.last_ignition_s <= t
            if self._k.active_fires(t, self._t_updated, ign_ok, *self._kst_act):  # the ids changed
                self._active_set = set(np.flatnonzero(self._active_flags[1:]).tolist())
            return self._active_set
        if t >= self._t_updated:  # every cell burning at t is live (burnt out after the last update)
            live = self._sources(self._t_updated)
            on = (self.t_ign.ravel()[live] <= t) & (t < self.t_out.ravel()[live])
            ids = np.flatnonzero(np.bincount(self.label.ravel()[live[on]] + 1)) - 1  # labels >= -1
            return set(ids.tolist()) - {-1}
        b = self._burning(t)
        return set(np.unique(self.label[b]).tolist()) - {-1}

    def apply_drop(self, x_m: float, y_m: float, radius_m: float | None = None) -> list[int]:
        r = self.drop_radius_m if radius_m is None else radius_m
        win = self._window(x_m, y_m, r)
        if win is None:
            self.last_drop_cells = (0, 0)
            return []
        box, xs, ys = win
        inside = (xs - x_m) ** 2 + (ys - y_m) ** 2 <= r * r
        burning = self._burning(self.t_s, box) & inside
        self.last_drop_cells = (int(burning.sum()), int(inside.sum()))
        hit = sorted(set(np.unique(self.label[box][burning]).tolist()) - {-1})
        ext = self.extinguished[box]
        ext |= burning
        wet = self.wet_until[box]
        unburned = inside & ~np.isfinite(self.t_ign[box])
        wet[unburned] = np.maximum(wet[unburned], self.t_s + self.spec.wet_duration_s)
        for n in hit:
            self._drops[n] += 1
        self._wetted()
        return hit

    def apply_pattern(self, pattern: DropPattern) -> list[int]:
        """A drop as a ground pattern (:mod:`fire_world_sim.drop_pattern`): the coverage (P2) at each
        cell centre [L/m^2]. The footprint is the cells with at least ``MIN_FOOTPRINT_CL``
        (0.5 gal/100 ft^2, the drop guides' lowest contour). A burning cell goes out where the
        coverage reaches the level its fuel model needs (``required_coverage_lpm2``); a weaker
        wetting leaves it burning. An unburned cell in the footprint cannot ignite for
        ``wet_duration_s`` x coverage / needed coverage: the water dries at a constant rate, so
        that the needed coverage lasts ``wet_duration_s`` (a choice, see docs/suppression.md).
        Returns the fires with a burning cell in the footprint, as :meth:`apply_drop`."""
        if self._required_lpm2 is None:
            self._required_lpm2 = required_coverage_lpm2(self.fuel)
        x0, x1, y0, y1 = pattern.bounds_m()
        win = self._box(x0, x1, y0, y1)
        if win is None:
            self.last_drop_cells = (0, 0)
            return []
        box, xs, ys = win
        cov = coverage_lpm2(pattern, xs, ys)
        inside = cov >= MIN_FOOTPRINT_CL * L_PER_M2_PER_CL
        need = self._required_lpm2[
            box[0].start - PAD : box[0].stop - PAD, box[1].start - PAD : box[1].stop - PAD
        ]
        burning = self._burning(self.t_s, box)
        wet_burning = burning & inside
        self.last_drop_cells = (int(wet_burning.sum()), int(inside.sum()))
        hit = sorted(set(np.unique(self.label[box][wet_burning]).tolist()) - {-1})
        ext = self.extinguished[box]
        out = burning & (cov >= need)
        ext |= out
        self.last_drop_out_cells = int(out.sum())
        wet = self.wet_until[box]
        unburned = inside & ~np.isfinite(self.t_ign[box])
        wet_s = self.spec.wet_duration_s * cov[unburned] / need[unburned]
        wet[unburned] = np.maximum(wet[unburned], self.t_s + wet_s)
        for n in hit:
            self._drops[n] += 1
        self._wetted()
        return hit

    def _wetted(self) -> None:
        """A drop changed extinguished cells and wet ones: the compiled path filters its live
        cells again and assumes no idle update until its next one."""
        self._meta[3] = 1
        self._meta[5] = 1
        self._tnext[:] = -np.inf
        self._truth_cache = None

    def _box(self, x0_m: float, x1_m: float, y0_m: float, y1_m: float):
        """Padded-array slice covering the rectangle [x0, x1] x [y0, y1] [m], plus the cell-centre
        coordinates there; None when it misses the grid."""
        ox, oy = self.spec.origin.x_m, self.spec.origin.y_m
        j0 = max(math.floor((x0_m - ox) / self.cs), 0)
        j1 = min(math.floor((x1_m - ox) / self.cs) + 1, self.nx)
        i0 = max(math.floor((y0_m - oy) / self.cs), 0)
        i1 = min(math.floor((y1_m - oy) / self.cs) + 1, self.ny)
        if j0 >= j1 or i0 >= i1:
            return None
        box = (slice(i0 + PAD, i1 + PAD), slice(j0 + PAD, j1 + PAD))
        return box, self._xx[i0:i1, j0:j1], self._yy[i0:i1, j0:j1]

    def _window(self, x_m: float, y_m: float, r_m: float):
        """Padded-array slice covering the disc, plus the cell-centre coordinates there."""
        ox, oy = self.spec.origin.x_m, self.spec.origin.y_m
        j0 = max(math.floor((x_m - r_m - ox) / self.cs), 0)
        j1 = min(math.floor((x_m + r_m - ox) / self.cs) + 1, self.nx)
        i0 = max(math.floor((y_m - r_m - oy) / self.cs), 0)
        i1 = min(math.floor((y_m + r_m - oy) / self.cs) + 1, self.ny)
        if j0 >= j1 or i0 >= i1:
            return None
        box = (slice(i0 + PAD, i1 + PAD), slice(j0 + PAD, j1 + PAD))
        return box, self._xx[i0:i1, j0:j1], self._yy[i0:i1, j0:j1]

    def state_grid(self) -> np.ndarray:
        """(ny, nx) uint8 of CELL_*; row 0 is the southern row."""
        inner = self._inner
        t = self.t_s
        ign = self.t_ign[inner] <= t
        burning = self._burning(t)[inner]
        out = np.full((self.ny, self.nx), CellState.UNBURNED, dtype=np.uint8)
        out[ign] = CellState.BURNED
        out[burning] = CellState.BURNING
        return out

    def wet_grid(self) -> np.ndarray:
        """(ny, nx) bool: unburned cells currently wet."""
        return self.wet_until[self._inner] > self.t_s

    def drop_extinctions(self, hit: list[int]) -> list[int]:
        """A drop wets burning cells; a fire goes out in :meth:`step` once none of its cells burn,
        and is reported there."""
        return []

    @property
    def has_cells(self) -> bool:
        return True

    def cell_grid(self) -> FireGrid:
        return FireGrid(
            self.spec.origin.x_m, self.spec.origin.y_m, float(self.cs), self.state_grid(), self.wet_grid()
        )

    def fire_type_grid(self) -> np.ndarray | None:
        if self._land is None:
            return None
        inner = self._inner
        return np.where(self.t_ign[inner] <= self.t_s, self._burn_type[inner], FireType.UNBURNABLE).astype(
            np.uint8
        )

    def truth(self) -> list[FireTruthRecord]:
        if self._truth_cache is not None:
            return self._truth_cache
        n = len(self.spec.ignitions)
        inner = self._inner
        lab = self.label[inner]
        ign = (self.t_ign[inner] <= self.t_s) & (lab >= 0)
        xs, ys = self._xx, self._yy
        cnt = np.bincount(lab[ign], minlength=n).astype(float)
        sx = np.bincount(lab[ign], weights=xs[ign], minlength=n)
        sy = np.bincount(lab[ign], weights=ys[ign], minlength=n)
        active = self._active_ids()
        out = []
        for i, ig in enumerate(self.spec.ignitions):
            area = cnt[i] * self.cs**2
            started = self._ignited[i]
            on = started and i in active
            cx = sx[i] / cnt[i] if cnt[i] > 0 else ig.x_m
            cy = sy[i] / cnt[i] if cnt[i] > 0 else ig.y_m
            out.append(
                FireTruthRecord(
                    fire_id=i,
                    status=FireStatus.ACTIVE if (on or not started) else FireStatus.EXTINGUISHED,
                    x_m=float(cx),
                    y_m=float(cy),
                    extent_m=math.sqrt(area / math.pi),
                    area_m2=area,
                    drops_received=self._drops[i],
                    started=started,
                )
            )
        self._truth_cache = out
        return out

    def detections_near(
        self, x_m: float, y_m: float, range_m: float
    ) -> list[tuple[int, float, float, float]]:
        win = self._window(x_m, y_m, range_m)
        if win is None:
            return []
        box, xs, ys = win
        seen = self._burning(self.t_s, box) & ((xs - x_m) ** 2 + (ys - y_m) ** 2 <= range_m**2)
        ids = sorted(set(np.unique(self.label[box][seen]).tolist()) - {-1})
        truth = self.truth()
        return [(i, truth[i].x_m, truth[i].y_m, truth[i].extent_m) for i in ids]

    def cells_near(self, x_m: float, y_m: float, range_m: float, stamp_ns: int) -> CellsSample | None:
        win = self._window(x_m, y_m, range_m)
        if win is None:
            return CellsSample(stamp_ns, self.cs)
        box, xs, ys = win
        inside = (xs - x_m) ** 2 + (ys - y_m) ** 2 <= range_m**2
        t = self.t_s
        state = np.full(xs.shape, CellState.UNBURNED, dtype=np.uint8)
        state[self.t_ign[box] <= t] = CellState.BURNED
        state[self._burning(t, box)] = CellState.BURNING
        return CellsSample(
            stamp_ns,
            self.cs,
            xs[inside].astype(np.float32),
            ys[inside].astype(np.float32),
            state[inside],
        )

    @property
    def all_out(self) -> bool:
        if not all(self._ignited):
            return False
        live = self._sources(self._t_updated)  # every cell burning now is live
        t = self.t_s
        return not ((self.t_ign.ravel()[live] <= t) & (t < self.t_out.ravel()[live])).any()
