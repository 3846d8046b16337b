"""Boundary following on a raster (PM III: the UAV flies cell to cell on top of the perimeter).

Cells are integer indices ``(i, j)`` of a :class:`~fire_perimeter_monitor.fire_map.CellGrid`
(i east, j north). A *fire* cell is burning or burned; everything else, including a cell the
sensor cannot see, counts as outside. The step is Moore-neighbour tracing: around the current
cell, sweep the 8 neighbours in the flying sense (CCW for ``Direction.CCW``) and take the first
fire cell that follows an outside cell; the fire then stays on the UAV's left for CCW.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .fire_map import CellGrid, CellState, Direction, as_cell_arrays

__all__ = [
    "FireLookup",
    "fire_lookup",
    "lookup_from_cells",
    "lookup_from_grid",
    "next_boundary_cell",
    "nearest_boundary_cell",
    "is_boundary_cell",
]

Cell = tuple[int, int]
FireLookup = Callable[[int, int], bool]  # True: fire cell; False: unburned or unseen

_UNBURNED = int(CellState.UNBURNED)

# The 8 neighbours in CCW order starting east.
RING: tuple[Cell, ...] = ((1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1))


def lookup_from_cells(observed_cells, grid: CellGrid) -> FireLookup:
    """Fire lookup over the cells a sensor reported (FireCells); unseen cells are outside."""
    return fire_lookup(*as_cell_arrays(observed_cells), grid)


def fire_lookup(x_m: np.ndarray, y_m: np.ndarray, state: np.ndarray, grid: CellGrid) -> FireLookup:
    """:func:`lookup_from_cells` of arrays already checked by ``as_cell_arrays``."""
    if x_m.size == 0:
        return lambda a, b: False
    i, j = grid.index(x_m, y_m)
    i0, j0 = int(i.min()), int(j.min())
    ni, nj = int(i.max()) - i0 + 1, int(j.max()) - j0 + 1
    fire = np.zeros((ni, nj), dtype=bool)
    f = state != _UNBURNED
    fire[i[f] - i0, j[f] - j0] = True

    def is_fire(a: int, b: int) -> bool:
        a -= i0
        b -= j0
        return 0 <= a < ni and 0 <= b < nj and bool(fire[a, b])

    return is_fire


def lookup_from_grid(
    fire_mask: np.ndarray, grid: CellGrid, center_cell: Cell | None = None, range_cells: float = np.inf
) -> FireLookup:
    """Fire lookup over a full boolean raster ``fire_mask[i, j]`` seen within ``range_cells``."""
    ni, nj = fire_mask.shape

    def is_fire(a: int, b: int) -> bool:
        if not (0 <= a < ni and 0 <= b < nj):
            return False
        if center_cell is not None and np.hypot(a - center_cell[0], b - center_cell[1]) > range_cells:
            return False
        return bool(fire_mask[a, b])

    return is_fire


def is_boundary_cell(is_fire: FireLookup, cell: Cell) -> bool:
    """A fire cell with an outside 4-neighbour."""
    a, b = cell
    if not is_fire(a, b):
        return False
    return not (is_fire(a + 1, b) and is_fire(a - 1, b) and is_fire(a, b + 1) and is_fire(a, b - 1))


def next_boundary_cell(
    is_fire: FireLookup, cell: Cell, direction: Direction, prev: Cell | None = None
) -> Cell | None:
    """Next perimeter cell from ``cell`` in ``direction``; None if ``cell`` is not on a boundary.

    Where the sweep finds several outside-to-fire transitions (a one-cell-wide neck), the one
    not going back to ``prev`` and best aligned with the heading ``cell - prev`` is taken.
    """
    a, b = cell
    ring = RING if direction is Direction.CCW else RING[::-1]
    fire = [is_fire(a + di, b + dj) for di, dj in ring]
    if all(fire) or not any(fire):
        return None
    cands = [ring[(k + 1) % 8] for k in range(8) if not fire[k] and fire[(k + 1) % 8]]
    if len(cands) == 1 or prev is None:
        d = cands[0]
        return (a + d[0], b + d[1])
    hx, hy = a - prev[0], b - prev[1]
    back = (prev[0] - a, prev[1] - b)

    def score(d: Cell) -> float:
        return (-10.0 if d == back else 0.0) + (d[0] * hx + d[1] * hy) / (
            np.hypot(*d) * max(np.hypot(hx, hy), 1e-9)
        )

    d = max(cands, key=score)
    return (a + d[0], b + d[1])


def nearest_boundary_cell(is_fire: FireLookup, cell: Cell, radius_cells: int) -> Cell | None:
    """Nearest boundary cell within a square of ``radius_cells`` (ties: lowest index order)."""
    best: Cell | None = None
    best_d = np.inf
    a, b = cell
    for di in range(-radius_cells, radius_cells + 1):
        for dj in range(-radius_cells, radius_cells + 1):
            c = (a + di, b + dj)
            d = di * di + dj * dj
            if d < best_d and is_boundary_cell(is_fire, c):
                best, best_d = c, d
    return best
