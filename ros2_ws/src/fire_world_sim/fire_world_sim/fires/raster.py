"""Raster fire (PM section VI, after DEVS-FIRE): a cell space with Rothermel spread.

Each cell of ``nx x ny`` squares of ``cell_size_m`` has a fuel model (scenario default plus
rectangular patches; lake cells have no fuel), the dead fuel moisture of the scenario, and the
terrain slope under its centre. Wind is piecewise constant in time. For every cell, Rothermel
(1972) gives the head rate of spread and direction (wind and slope added as vectors); the
spread rate toward each of 16 neighbours follows the ellipse of Anderson (1983) with the fire
at its rear focus: ``R(theta) = R_head (1 - e) / (1 - e cos(theta - theta_head))``.

Propagation is by arrival time: a burning cell ignites neighbour k at
``t_ign + d_k / R_k`` (minimum over all burning neighbours), computed with numpy over the
bounding box of the burning cells; several hops per update are resolved by iterating.
A cell burns from ``t_ign`` until ``t_ign + max(residence + crossing time, time to reach its
still-unburned neighbours)``, then it is burnt out. A drop wets the cells within its radius:
burning cells are extinguished (they spread no more) and unburned cells cannot ignite for
``wet_duration_s``. Fire ids are the ignition indices; each cell carries the id of the
ignition that reached it first. Time unit: seconds of sim time; lengths in metres.
"""

from __future__ import annotations

import math

import numpy as np
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import Raster
from fire_uav_common.terrain import Terrain

from ..sensors import CellsSample
from .base import STATUS_ACTIVE, STATUS_EXTINGUISHED, FireTruthRecord
from .fuel_models import fuel_model
from .rothermel import ellipse_eccentricity, head_spread, length_to_breadth, spread_params

__all__ = ["CELL_BURNED", "CELL_BURNING", "CELL_UNBURNED", "NEIGHBOURS", "RasterFireModel"]

# aliases of the one definition (fire_uav_common.constants.CellState)
CELL_UNBURNED, CELL_BURNING, CELL_BURNED = CellState.UNBURNED, CellState.BURNING, CellState.BURNED

#: 16-neighbourhood offsets (di rows = north, dj cols = east)
NEIGHBOURS = (
    (0, 1), (1, 0), (0, -1), (-1, 0),
    (1, 1), (1, -1), (-1, 1), (-1, -1),
    (1, 2), (2, 1), (2, -1), (1, -2), (-1, -2), (-2, -1), (-2, 1), (-1, 2),
)  # fmt: skip
PAD = 2
MAX_BURN_S = 3600.0
DEFAULT_DROP_RADIUS_M = 20.0


class RasterFireModel:
    """Raster fire over ``spec``'s grid; ``update_period_s`` batches propagation updates."""

    def __init__(
        self,
        spec: Raster,
        terrain: Terrain,
        *,
        lakes: tuple = (),
        drop_radius_m: float | None = None,
        update_period_s: float = 0.5,
    ) -> None:
        self.spec = spec
        self.cs = spec.cell_size_m
        self.nx, self.ny = spec.nx, spec.ny
        self.drop_radius_m = drop_radius_m if drop_radius_m is not None else DEFAULT_DROP_RADIUS_M
        self.update_period_s = update_period_s
        shape = (self.ny + 2 * PAD, self.nx + 2 * PAD)
        self.xc = spec.origin.x_m + (np.arange(self.nx) + 0.5) * self.cs  # [m] cell centres east
        self.yc = spec.origin.y_m + (np.arange(self.ny) + 0.5) * self.cs  # [m] cell centres north
        xx, yy = np.meshgrid(self.xc, self.yc)
        # fuel per cell
        fuel = np.full((self.ny, self.nx), spec.fuel_model, dtype=np.int16)
        for p in spec.fuel_patches:
            fuel[(xx >= p.x_min_m) & (xx < p.x_max_m) & (yy >= p.y_min_m) & (yy < p.y_max_m)] = p.fuel_model
        for lake in lakes:
            fuel[(xx - lake.x_m) ** 2 + (yy - lake.y_m) ** 2 <= (lake.diameter_m / 2) ** 2] = 0
        self.fuel = fuel
        self._params = {
            int(m): spread_params(fuel_model(int(m)), spec.moisture) for m in np.unique(fuel) if m > 0
        }
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
        for m, p in self._params.items():
            r0[fuel == m] = p.r0_mps
        self.burnable[inner] = r0 > 0
        # dynamic state (padded)
        self.t_ign = np.full(shape, np.inf)
        self.t_out = np.full(shape, np.inf)
        self.label = np.full(shape, -1, dtype=np.int32)
        self.extinguished = np.zeros(shape, dtype=bool)
        self.wet_until = np.full(shape, -np.inf)
        self._offsets = np.array(NEIGHBOURS)
        self._dist = self.cs * np.hypot(self._offsets[:, 0], self._offsets[:, 1])
        self._theta = np.arctan2(self._offsets[:, 0], self._offsets[:, 1])  # direction of each neighbour
        self._travel = np.full((len(NEIGHBOURS), *shape), np.inf)  # [s] d_k / R_k per source cell
        self._head = np.zeros(shape)  # [m/s] head rate of spread
        self._res = np.zeros(shape)  # [s] residence + crossing time
        self._wind_index = -1
        self.t_s = 0.0
        self._t_updated = 0.0
        self._drops = [0] * len(spec.ignitions)
        self._ignited = [False] * len(spec.ignitions)
        self._truth_cache: list[FireTruthRecord] | None = None
        self._set_wind(0.0)

    # --- spread rates ------------------------------------------------------------------------
    def wind_at(self, t_s: float) -> tuple[float, float]:
        """(speed [m/s], direction the wind blows toward [rad ccw from +x]) at t_s."""
        w = self.spec.wind[0]
        for seg in self.spec.wind:
            if seg.start_s <= t_s + 1e-9:
                w = seg
        return w.speed_mps, math.radians(w.direction_deg)

    def _set_wind(self, t_s: float) -> bool:
        idx = 0
        for i, seg in enumerate(self.spec.wind):
            if seg.start_s <= t_s + 1e-9:
                idx = i
        if idx == self._wind_index:
            return False
        self._wind_index = idx
        speed, direction = self.wind_at(t_s)
        inner = self._inner
        head = np.zeros((self.ny, self.nx))
        hdir = np.zeros((self.ny, self.nx))
        ueff = np.zeros((self.ny, self.nx))
        res = np.zeros((self.ny, self.nx))
        for m, p in self._params.items():
            mask = self.fuel == m
            r, d, u = head_spread(p, speed, direction, self.slope_tan[mask], self.upslope_dir[mask])
            head[mask] = np.asarray(r) * self.spec.spread_factor
            hdir[mask] = d
            ueff[mask] = u
            res[mask] = p.residence_time_s
        ecc = ellipse_eccentricity(length_to_breadth(ueff))
        self._head[inner] = head
        self._res[inner] = res + np.where(head > 0, self.cs / np.maximum(head, 1e-9), 0.0)
        for k in range(len(NEIGHBOURS)):
            rk = head * (1.0 - ecc) / (1.0 - ecc * np.cos(self._theta[k] - hdir))
            with np.errstate(divide="ignore"):
                self._travel[k][inner] = np.where(rk > 1e-9, self._dist[k] / np.maximum(rk, 1e-12), np.inf)
        return True

    # --- state -------------------------------------------------------------------------------
    def _burning(self, t_s: float) -> np.ndarray:
        return (self.t_ign <= t_s) & (t_s < self.t_out) & ~self.extinguished

    def _ignite(self, idx: tuple[np.ndarray, np.ndarray], t: np.ndarray, labels: np.ndarray) -> None:
        """Ignite padded cells ``idx`` at times ``t`` with fire ids ``labels``; set their burn-out time."""
        self.t_ign[idx] = t
        self.label[idx] = labels
        ii, jj = idx
        longest = self._res[idx].copy()
        for k, (di, dj) in enumerate(NEIGHBOURS):
            ni, nj = ii + di, jj + dj
            pending = self.burnable[ni, nj] & (self.t_ign[ni, nj] > t) & ~self.extinguished[ni, nj]
            tk = self._travel[k][idx]
            longest = np.where(pending & np.isfinite(tk), np.maximum(longest, tk), longest)
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
        return new

    def _propagate(self, t0: float, t1: float) -> None:
        """Ignite every cell whose arrival time is <= t1 (iterating for multi-hop spread)."""
        for _ in range(64):
            src = (self.t_ign <= t1) & (self.t_out > t0) & ~self.extinguished
            rows = np.flatnonzero(src.any(axis=1))
            if rows.size == 0:
                return
            cols = np.flatnonzero(src.any(axis=0))
            r0, r1 = max(rows[0] - PAD, PAD), min(rows[-1] + PAD + 1, self.ny + PAD)
            c0, c1 = max(cols[0] - PAD, PAD), min(cols[-1] + PAD + 1, self.nx + PAD)
            t_src = np.where(src, self.t_ign, np.inf)
            best = np.full((r1 - r0, c1 - c0), np.inf)
            best_lab = np.full((r1 - r0, c1 - c0), -1, dtype=np.int32)
            for k, (di, dj) in enumerate(NEIGHBOURS):
                ss = (slice(r0 - di, r1 - di), slice(c0 - dj, c1 - dj))
                cand = t_src[ss] + self._travel[k][ss]
                better = cand < best
                best = np.where(better, cand, best)
                best_lab = np.where(better, self.label[ss], best_lab)
            box = (slice(r0, r1), slice(c0, c1))
            t_arr = np.maximum(best, self.wet_until[box])
            new = self.burnable[box] & ~np.isfinite(self.t_ign[box]) & ~self.extinguished[box] & (t_arr <= t1)
            if not new.any():
                return
            ii, jj = np.nonzero(new)
            self._ignite((ii + r0, jj + c0), np.maximum(t_arr[new], t0), best_lab[new])

    # --- FireModel interface ---------------------------------------------------------------
    def step(self, t_s: float, dt_s: float) -> list[tuple[int, str]]:
        t1 = t_s + dt_s
        self.t_s = t1
        events = [(n, "ignition") for n in self._start_ignitions(t1)]
        if t1 - self._t_updated >= self.update_period_s - 1e-9 or events:
            was_active = self._active_ids()
            if self._set_wind(t1):
                # burning cells re-derive their pending spread under the new wind
                burning = np.nonzero(self._burning(t1))
                if burning[0].size:
                    self._ignite(burning, self.t_ign[burning], self.label[burning])
            self._propagate(self._t_updated, t1)
            self._t_updated = t1
            self._truth_cache = None
            now_active = self._active_ids()
            events += [(n, "extinguished") for n in sorted(was_active - now_active) if self._ignited[n]]
        return events

    def _active_ids(self) -> set[int]:
        b = self._burning(self.t_s)
        return set(np.unique(self.label[b]).tolist()) - {-1}

    def apply_drop(self, x_m: float, y_m: float, radius_m: float | None = None) -> list[int]:
        r = self.drop_radius_m if radius_m is None else radius_m
        win = self._window(x_m, y_m, r)
        if win is None:
            return []
        box, xs, ys = win
        inside = (xs - x_m) ** 2 + (ys - y_m) ** 2 <= r * r
        burning = self._burning(self.t_s)[box] & inside
        hit = sorted(set(np.unique(self.label[box][burning]).tolist()) - {-1})
        ext = self.extinguished[box]
        ext |= burning
        wet = self.wet_until[box]
        unburned = inside & ~np.isfinite(self.t_ign[box])
        wet[unburned] = np.maximum(wet[unburned], self.t_s + self.spec.wet_duration_s)
        for n in hit:
            self._drops[n] += 1
        self._truth_cache = None
        return hit

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
        xs, ys = np.meshgrid(self.xc[j0:j1], self.yc[i0:i1])
        return box, xs, ys

    def state_grid(self) -> np.ndarray:
        """(ny, nx) uint8 of CELL_*; row 0 is the southern row."""
        inner = self._inner
        t = self.t_s
        ign = self.t_ign[inner] <= t
        burning = self._burning(t)[inner]
        out = np.full((self.ny, self.nx), CELL_UNBURNED, dtype=np.uint8)
        out[ign] = CELL_BURNED
        out[burning] = CELL_BURNING
        return out

    def wet_grid(self) -> np.ndarray:
        """(ny, nx) bool: unburned cells currently wet."""
        return self.wet_until[self._inner] > self.t_s

    def truth(self) -> list[FireTruthRecord]:
        if self._truth_cache is not None:
            return self._truth_cache
        n = len(self.spec.ignitions)
        inner = self._inner
        lab = self.label[inner]
        ign = (self.t_ign[inner] <= self.t_s) & (lab >= 0)
        xs, ys = np.meshgrid(self.xc, self.yc)
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
                    status=STATUS_ACTIVE if (on or not started) else STATUS_EXTINGUISHED,
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
        seen = self._burning(self.t_s)[box] & ((xs - x_m) ** 2 + (ys - y_m) ** 2 <= range_m**2)
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
        state = np.full(xs.shape, CELL_UNBURNED, dtype=np.uint8)
        state[self.t_ign[box] <= t] = CELL_BURNED
        state[self._burning(t)[box]] = CELL_BURNING
        return CellsSample(
            stamp_ns,
            self.cs,
            xs[inside].astype(np.float32),
            ys[inside].astype(np.float32),
            state[inside],
        )

    @property
    def all_out(self) -> bool:
        return all(self._ignited) and not self._burning(self.t_s).any()
