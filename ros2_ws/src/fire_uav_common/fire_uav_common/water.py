"""A water body by its real outline: the water cells of a landscape (no ROS).

:class:`WaterCells` is a boolean raster in the map frame (row 0 the southern row): a point is
over the water when the cell under it is water, so the outline is the data's own, cell by cell.
:func:`longest_straight_run` finds the longest straight segment that stays over water (a
scooping aircraft needs one), :meth:`WaterCells.outline` the polygon around the cells and
:meth:`WaterCells.row_runs` the cells as row rectangles (what a filled drawing needs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["StraightRun", "WaterCells", "longest_straight_run"]


@dataclass(frozen=True)
class WaterCells:
    """``mask[i, j]`` is water for the cell whose south-west corner is ``(x0_m + j cell_m,
    y0_m + i cell_m)`` [m; map frame]."""

    x0_m: float
    y0_m: float
    cell_m: float
    mask: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        m = np.array(self.mask, dtype=bool)
        m.flags.writeable = False
        object.__setattr__(self, "mask", m)

    def contains(self, x_m: float | np.ndarray, y_m: float | np.ndarray) -> bool | np.ndarray:
        """Over water at (x_m, y_m) [m]: the cell there is water (vectorised)."""
        ny, nx = self.mask.shape
        j = np.floor((np.asarray(x_m, dtype=float) - self.x0_m) / self.cell_m).astype(int)
        i = np.floor((np.asarray(y_m, dtype=float) - self.y0_m) / self.cell_m).astype(int)
        inside = (i >= 0) & (i < ny) & (j >= 0) & (j < nx)
        out = inside & self.mask[np.clip(i, 0, ny - 1), np.clip(j, 0, nx - 1)]
        return bool(out) if np.ndim(out) == 0 else out

    def shifted(self, dx_m: float, dy_m: float) -> WaterCells:
        return WaterCells(self.x0_m + dx_m, self.y0_m + dy_m, self.cell_m, self.mask)

    @property
    def area_m2(self) -> float:
        return float(self.mask.sum()) * self.cell_m**2

    def row_runs(self) -> np.ndarray:
        """The water as rectangles, one per maximal run of water cells along a row: an (n, 4)
        array of (x_min, y_min, x_max, y_max) [m]. Together they cover exactly the water cells,
        none overlapping (a filled drawing of the real outline, islands left open)."""
        ny, nx = self.mask.shape
        padded = np.zeros((ny, nx + 2), dtype=np.int8)
        padded[:, 1:-1] = self.mask
        d = np.diff(padded, axis=1)
        rows, starts = np.nonzero(d == 1)
        _, ends = np.nonzero(d == -1)  # same row order: one end per start, exclusive
        cs = self.cell_m
        return np.column_stack(
            (
                self.x0_m + starts * cs,
                self.y0_m + rows * cs,
                self.x0_m + ends * cs,
                self.y0_m + (rows + 1) * cs,
            )
        ).astype(float)

    def outline(self) -> list[list[list[tuple[float, float]]]]:
        """The polygons around the water cells (one per 4-connected piece), each a list of rings
        of (x, y) [m]: the shore first, then the islands' (``rasterio.features.shapes``)."""
        from rasterio.features import shapes
        from rasterio.transform import Affine

        ny = self.mask.shape[0]
        # rasterio's rows run north to south: flip, and put the transform's origin at the north edge
        north = self.y0_m + ny * self.cell_m
        t = Affine(self.cell_m, 0.0, self.x0_m, 0.0, -self.cell_m, north)
        flipped = np.ascontiguousarray(self.mask[::-1]).astype(np.uint8)
        return [
            [[(float(x), float(y)) for x, y in ring] for ring in geom["coordinates"]]
            for geom, value in shapes(flipped, mask=flipped.astype(bool), transform=t)
            if value == 1
        ]


@dataclass(frozen=True)
class StraightRun:
    """The longest straight segment over water: from (x0, y0) to (x1, y1) [m], length_m."""

    x0_m: float
    y0_m: float
    x1_m: float
    y1_m: float
    length_m: float

    @property
    def heading_rad(self) -> float:
        """Direction from the start to the end [rad ccw from +x]."""
        return math.atan2(self.y1_m - self.y0_m, self.x1_m - self.x0_m)


def longest_straight_run(
    water: WaterCells, *, step_deg: float = 2.0, spacing_cells: float = 0.25
) -> StraightRun:
    """The longest straight segment whose sample points all lie over ``water``.

    Lines in every direction (every ``step_deg`` over 180 deg) cross the body ``spacing_cells``
    of a cell apart, sampled every ``spacing_cells`` along; the longest run of consecutive water
    samples is the answer, short of the true one by at most about one spacing at each end."""
    mask = water.mask
    ny, nx = mask.shape
    cs = water.cell_m
    h = spacing_cells * cs
    cx, cy = water.x0_m + 0.5 * nx * cs, water.y0_m + 0.5 * ny * cs
    half = 0.5 * math.hypot(nx, ny) * cs + h
    offs = np.arange(-half, half + h, h)  # [m] across (lines) and along (samples)
    best = StraightRun(cx, cy, cx, cy, 0.0)
    for deg in np.arange(0.0, 180.0, step_deg):
        u = (math.cos(math.radians(deg)), math.sin(math.radians(deg)))
        x = cx + offs[None, :] * u[0] - offs[:, None] * u[1]  # rows: lines, columns: along
        y = cy + offs[None, :] * u[1] + offs[:, None] * u[0]
        wet = np.asarray(water.contains(x, y))
        # runs of True along each row: starts and ends from the padded row's differences
        padded = np.zeros((wet.shape[0], wet.shape[1] + 2), dtype=np.int8)
        padded[:, 1:-1] = wet
        d = np.diff(padded, axis=1)
        rows_s, starts = np.nonzero(d == 1)
        _, ends = np.nonzero(d == -1)  # same row order: one end per start
        if starts.size == 0:
            continue
        k = int(np.argmax(ends - starts))
        n = int(ends[k] - starts[k])
        length = (n - 1) * h
        if length > best.length_m:
            r, a, b = int(rows_s[k]), int(starts[k]), int(ends[k] - 1)
            best = StraightRun(float(x[r, a]), float(y[r, a]), float(x[r, b]), float(y[r, b]), length)
    return best
