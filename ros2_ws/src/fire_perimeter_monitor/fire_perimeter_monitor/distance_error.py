"""The distance error of PM Sec. VI-E, one definition for the benchmark, the report and metrics.

PM Sec. VI-E and Fig. 15-16: at each of 360 angles around the fire's centre, the difference
between the extent of the true fire shape and the extent of the shape constructed from the
monitor's data, the filled convex hull of its on-board perimeter cells. The paper takes the
maximum over the angles each time the UAV reaches a new cell and reports the running average
of that maximum (7.3 and 12.2 against 8.5 and 15.8 for circling). It never states the unit
(a cell-based hull is its natural unit); we give metres and cells.

Choices where the paper is silent (ours):

- cells are squares of side ``cell_size_m`` centred on their points, the true shape is the
  union of the burning and burned cells' squares and the constructed one the convex hull of
  the on-board cells' squares, so that a complete, current map of a convex fire scores 0;
  the extent along a ray is the farthest point of the shape on it, computed exactly;
- a ray that meets the true fire but not the constructed shape counts its whole true extent;
  rays that miss the true fire are ignored;
- the **perfect-map floor** is the error of the map a monitor would hold if it saw the whole
  fire at that instant: per angle bin the farthest true perimeter cell (the on-board map's
  structure, PM Table 1). It is 0 on a convex fire; a fire with notches (suppression drops,
  fuel breaks) has a floor the hull cannot go below, whatever the monitor does.

Frame: map frame, metres; angles CCW from +x about ``center``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .errors import ConfigError
from .shape import convex_hull, polygon_radial_extent

__all__ = [
    "DistanceError",
    "N_ANGLES",
    "bin_points",
    "grid_cells",
    "distance_error",
    "hull_extent",
    "max_error",
    "perfect_map_cells",
    "running_average",
    "true_extent",
]

N_ANGLES = 360  # PM VI-E


def _angles(n: int) -> np.ndarray:
    return (np.arange(n) + 0.5) * (2 * np.pi / n)


def _outline_cells(cells_xy_m: np.ndarray, cell_size_m: float) -> np.ndarray:
    """The cells of a set that have a 4-neighbour outside it (the farthest point of a union of
    squares along any ray from outside or inside lies on such a cell)."""
    p = np.asarray(cells_xy_m, dtype=float).reshape(-1, 2)
    if p.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    i = np.rint((p[:, 0] - p[0, 0]) / cell_size_m).astype(np.int64)
    j = np.rint((p[:, 1] - p[0, 1]) / cell_size_m).astype(np.int64)
    i = i - i.min() + 1
    j = j - j.min() + 1
    occ = np.zeros((int(i.max()) + 2, int(j.max()) + 2), dtype=bool)
    occ[i, j] = True
    inner = occ[i + 1, j] & occ[i - 1, j] & occ[i, j + 1] & occ[i, j - 1]
    return ~inner


def true_extent(
    fire_xy_m: np.ndarray, cell_size_m: float, center_xy_m: tuple[float, float], n_angles: int = N_ANGLES
) -> np.ndarray:
    """Farthest distance [m] of the union of the fire cells' squares along each ray; NaN where a
    ray meets no fire cell. ``fire_xy_m``: (n, 2) centres of the burning and burned cells."""
    p = np.asarray(fire_xy_m, dtype=float).reshape(-1, 2)
    if p.shape[0] == 0:
        return np.full(n_angles, np.nan)
    p = p[_outline_cells(p, cell_size_m)] - np.asarray(center_xy_m, dtype=float)
    h = cell_size_m / 2
    th = _angles(n_angles)
    ux, uy = np.cos(th)[:, None], np.sin(th)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        tx1, tx2 = (p[None, :, 0] - h) / ux, (p[None, :, 0] + h) / ux
        ty1, ty2 = (p[None, :, 1] - h) / uy, (p[None, :, 1] + h) / uy
    # a ray parallel to a slab: inside it for all t, or never
    in_x = np.abs(p[None, :, 0]) <= h
    in_y = np.abs(p[None, :, 1]) <= h
    par_x = ux == 0
    par_y = uy == 0
    t_lo_x = np.where(par_x, np.where(in_x, -np.inf, np.inf), np.minimum(tx1, tx2))
    t_hi_x = np.where(par_x, np.where(in_x, np.inf, -np.inf), np.maximum(tx1, tx2))
    t_lo_y = np.where(par_y, np.where(in_y, -np.inf, np.inf), np.minimum(ty1, ty2))
    t_hi_y = np.where(par_y, np.where(in_y, np.inf, -np.inf), np.maximum(ty1, ty2))
    t_in = np.maximum(t_lo_x, t_lo_y)
    t_out = np.minimum(t_hi_x, t_hi_y)
    hit = (t_out >= np.maximum(t_in, 0.0)) & (t_out > 0)
    far = np.where(hit, t_out, -np.inf).max(axis=1)
    return np.where(np.isfinite(far), far, np.nan)


def hull_extent(
    cells_xy_m: np.ndarray, cell_size_m: float, center_xy_m: tuple[float, float], n_angles: int = N_ANGLES
) -> np.ndarray:
    """Extent [m] along each ray of the convex hull of the cells' squares (the constructed
    shape, PM VI-E); NaN where a ray misses it (fewer than 1 cell, or the centre outside)."""
    p = np.asarray(cells_xy_m, dtype=float).reshape(-1, 2)
    p = p[np.all(np.isfinite(p), axis=1)]
    if p.shape[0] == 0:
        return np.full(n_angles, np.nan)
    c = convex_hull(p)  # the hull of the squares is the hull of the centres' hull's squares
    h = cell_size_m / 2
    corners = np.concatenate([c + [dx, dy] for dx in (-h, h) for dy in (-h, h)], axis=0)
    return polygon_radial_extent(convex_hull(corners), center_xy_m[0], center_xy_m[1], n_angles)


def perfect_map_cells(
    fire_xy_m: np.ndarray, cell_size_m: float, center_xy_m: tuple[float, float], bin_count: int = 360
) -> np.ndarray:
    """The map a monitor seeing the whole fire would hold: per angle bin the farthest fire cell
    with an unburned (or absent) 4-neighbour, (k, 2) [m]."""
    p = np.asarray(fire_xy_m, dtype=float).reshape(-1, 2)
    if p.shape[0] == 0:
        return p
    p = p[_outline_cells(p, cell_size_m)]
    dx, dy = p[:, 0] - center_xy_m[0], p[:, 1] - center_xy_m[1]
    b = np.minimum(
        np.floor(np.mod(np.arctan2(dy, dx), 2 * np.pi) / (2 * np.pi) * bin_count).astype(np.int64),
        bin_count - 1,
    )
    d = np.hypot(dx, dy)
    order = np.lexsort((d, b))
    last = np.r_[b[order][1:] != b[order][:-1], True]
    return p[order[last]]


def max_error(true_extent_m: np.ndarray, constructed_extent_m: np.ndarray) -> float:
    """Maximum over the angles of |true - constructed| extent [m]; a ray the constructed shape
    misses counts the whole true extent; NaN when no ray meets the true fire."""
    t = np.asarray(true_extent_m, dtype=float)
    e = np.asarray(constructed_extent_m, dtype=float)
    ok = np.isfinite(t)
    if not ok.any():
        return float("nan")
    e = np.where(np.isfinite(e), e, 0.0)
    return float(np.max(np.abs(t[ok] - e[ok])))


class DistanceError(NamedTuple):
    """One sample of the PM VI-E distance error, with its perfect-map floor."""

    max_m: float  # [m] max over the angles, the monitor's map
    floor_m: float  # [m] the same for the perfect, instantaneous map
    cell_size_m: float  # [m]

    @property
    def max_cells(self) -> float:
        return self.max_m / self.cell_size_m

    @property
    def floor_cells(self) -> float:
        return self.floor_m / self.cell_size_m


def distance_error(
    fire_xy_m: np.ndarray,
    map_xy_m: np.ndarray,
    cell_size_m: float,
    center_xy_m: tuple[float, float],
    n_angles: int = N_ANGLES,
) -> DistanceError:
    """PM VI-E maximum distance error of a monitor's map and of the perfect map, at one instant.

    ``fire_xy_m``: (n, 2) centres of the true burning and burned cells; ``map_xy_m``: (k, 2)
    the on-board outer cells (NaN rows ignored); ``center_xy_m``: the rays' origin (the
    monitor's map centre).
    """
    if not cell_size_m > 0:
        raise ConfigError(f"cell_size_m must be > 0, got {cell_size_m}")
    if not all(math.isfinite(v) for v in center_xy_m):
        raise ConfigError(f"distance error centre must be finite, got {center_xy_m}")
    truth = true_extent(fire_xy_m, cell_size_m, center_xy_m, n_angles)
    est = hull_extent(map_xy_m, cell_size_m, center_xy_m, n_angles)
    perfect = hull_extent(
        perfect_map_cells(fire_xy_m, cell_size_m, center_xy_m), cell_size_m, center_xy_m, n_angles
    )
    return DistanceError(max_error(truth, est), max_error(truth, perfect), float(cell_size_m))


def bin_points(center_xy_m: tuple[float, float], outer_distance_m: np.ndarray) -> np.ndarray:
    """The on-board outer cells of a PerimeterMap, (k, 2) [m]: per known bin the point at the
    bin's centre angle and its outer distance (the map carries no more)."""
    d = np.asarray(outer_distance_m, dtype=float)
    k = np.flatnonzero(np.isfinite(d))
    a = (k + 0.5) * (2 * np.pi / d.size) if d.size else np.zeros(0)
    return np.column_stack([center_xy_m[0] + d[k] * np.cos(a), center_xy_m[1] + d[k] * np.sin(a)])


def grid_cells(mask: np.ndarray, x0_m: float, y0_m: float, res_m: float) -> np.ndarray:
    """Centres (k, 2) [m] of the true cells of a raster ``mask[row, col]`` whose cell (i, j)
    spans ``[x0 + j res, x0 + (j + 1) res] x [y0 + i res, y0 + (i + 1) res]``."""
    i, j = np.nonzero(np.asarray(mask, dtype=bool))
    return np.column_stack([x0_m + (j + 0.5) * res_m, y0_m + (i + 0.5) * res_m])


def running_average(values: np.ndarray) -> np.ndarray:
    """Running mean of a series (PM Fig. 16 plots the running average of the maximum)."""
    v = np.asarray(values, dtype=float)
    return np.cumsum(v) / np.arange(1, v.size + 1) if v.size else v.copy()
