"""Boundary following on a raster (PM III) against independent references.

References: scipy's binary erosion (a fire cell with an outside 4-neighbour is exactly a cell of
the mask minus its erosion by the 4-connected cross), a brute-force nearest search, and the
analytic Moore trace of an axis-aligned rectangle (its 2 (w + h) - 4 edge cells in CCW order).
"""

import numpy as np
import pytest
from fire_perimeter_monitor.boundary import (
    fire_lookup,
    is_boundary_cell,
    lookup_from_cells,
    lookup_from_grid,
    nearest_boundary_cell,
    next_boundary_cell,
)
from fire_perimeter_monitor.fire_map import CellGrid, CellState, Direction
from hypothesis import Phase, given, settings
from hypothesis import strategies as st
from scipy.ndimage import binary_erosion

# No shrinking: a failing example is reported as drawn (fast, also under mutation testing).
NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate)

CROSS = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], dtype=bool)
GRID = CellGrid(0.0, 0.0, 1.0)


def _erosion_boundary(mask: np.ndarray) -> np.ndarray:
    return mask & ~binary_erosion(mask, structure=CROSS, border_value=0)


def _rect_ccw(i0, i1, j0, j1):
    """The edge cells of the rectangle [i0, i1] x [j0, j1] in CCW order from (i0, j0)."""
    path = [(i, j0) for i in range(i0, i1 + 1)]  # east along the bottom (fire on the left)
    path += [(i1, j) for j in range(j0 + 1, j1 + 1)]  # north along the right side
    path += [(i, j1) for i in range(i1 - 1, i0 - 1, -1)]  # west along the top
    path += [(i0, j) for j in range(j1 - 1, j0, -1)]  # south along the left side
    return path


def _trace(look, start, direction, max_steps=1000):
    cell, prev, path = start, None, [start]
    for _ in range(max_steps):
        nxt = next_boundary_cell(look, cell, direction, prev)
        assert nxt is not None
        prev, cell = cell, nxt
        if cell == start:
            return path
        path.append(cell)
    raise AssertionError("lap did not close")


@settings(max_examples=25, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1))
def test_is_boundary_cell_equals_mask_minus_erosion(seed):
    rng = np.random.default_rng(seed)
    mask = rng.random((9, 8)) < rng.uniform(0.2, 0.9)
    look = lookup_from_grid(mask, GRID)
    got = np.array([[is_boundary_cell(look, (i, j)) for j in range(8)] for i in range(9)])
    np.testing.assert_array_equal(got, _erosion_boundary(mask))


@pytest.mark.parametrize("i0,i1,j0,j1", [(2, 7, 3, 5), (1, 4, 1, 9), (3, 4, 2, 6)])
def test_rectangle_trace_is_its_edge_cells_in_order(i0, i1, j0, j1):
    mask = np.zeros((12, 12), dtype=bool)
    mask[i0 : i1 + 1, j0 : j1 + 1] = True
    look = lookup_from_grid(mask, GRID)
    ccw = _rect_ccw(i0, i1, j0, j1)
    assert len(ccw) == 2 * ((i1 - i0 + 1) + (j1 - j0 + 1)) - 4
    for k in (0, 3, len(ccw) - 1):  # any start cell, with or without a heading
        start = ccw[k]
        path = _trace(look, start, Direction.CCW)
        assert path == ccw[k:] + ccw[:k]
        path_cw = _trace(look, start, Direction.CW)
        assert path_cw == [start] + (ccw[k:] + ccw[:k])[:0:-1]


def test_next_cell_is_none_inside_and_outside_the_fire():
    mask = np.zeros((10, 10), dtype=bool)
    mask[2:8, 2:8] = True
    look = lookup_from_grid(mask, GRID)
    assert next_boundary_cell(look, (5, 5), Direction.CCW) is None  # all 8 neighbours fire
    assert next_boundary_cell(look, (0, 9), Direction.CW) is None  # no neighbour is fire
    assert next_boundary_cell(look, (1, 5), Direction.CCW) == (2, 4)  # outside, next to the fire


def test_neck_is_crossed_both_ways_and_the_lap_covers_both_lobes():
    """Two 5x5 squares joined by a one-cell-wide, 3-cell-long neck (a dumbbell).

    The neck cells have two outside-to-fire transitions; choosing by the heading (not going
    back to ``prev``) the lap crosses the neck, goes round the far lobe and comes back: it
    visits every boundary cell of the dumbbell (mask minus erosion), the neck cells twice.
    """
    mask = np.zeros((17, 9), dtype=bool)
    mask[1:6, 2:7] = True
    mask[6:9, 4] = True
    mask[9:14, 2:7] = True
    look = lookup_from_grid(mask, GRID)
    for direction in (Direction.CCW, Direction.CW):
        path = _trace(look, (1, 2), direction)
        assert set(path) == {tuple(c) for c in np.argwhere(_erosion_boundary(mask))}
        for neck in [(6, 4), (7, 4), (8, 4)]:
            assert path.count(neck) == 2, (direction, neck)
        steps = np.diff(np.array(path + [path[0]]), axis=0)
        assert np.abs(steps).max() == 1  # always to an 8-neighbour


def test_lookup_range_and_extent():
    mask = np.ones((5, 5), dtype=bool)
    look = lookup_from_grid(mask, GRID, center_cell=(2, 2), range_cells=1.5)
    assert look(3, 3) and look(2, 1) and not look(4, 2)  # sqrt(2) <= 1.5 < 2
    assert not look(-1, 2) and not look(2, 5) and not look(5, 0) and look(0, 0) is False
    full = lookup_from_grid(mask, GRID)
    assert full(0, 0) and full(4, 4) and not full(0, -1) and not full(-1, 0)


def test_lookup_from_cells_uses_reported_states_only():
    g = CellGrid(10.0, 20.0, 5.0)
    cells = np.array(
        [
            [10.0, 20.0, CellState.BURNING],
            [15.0, 20.0, CellState.BURNED],
            [20.0, 20.0, CellState.UNBURNED],
            [10.0, 26.0, CellState.BURNING],  # rounds to cell (0, 1)
        ]
    )
    look = lookup_from_cells(cells, g)
    assert look(0, 0) and look(1, 0) and look(0, 1)
    assert not look(2, 0)  # unburned
    assert not look(5, 5)  # never reported: outside


@settings(max_examples=25, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1), st.integers(0, 4))
def test_nearest_boundary_cell_against_brute_force(seed, radius):
    rng = np.random.default_rng(seed)
    mask = np.zeros((15, 15), dtype=bool)
    mask[3:12, 3:12] = rng.random((9, 9)) < 0.6
    look = lookup_from_grid(mask, GRID)
    a, b = (int(v) for v in rng.integers(0, 15, 2))
    cands = [
        ((i - a) ** 2 + (j - b) ** 2, i, j)
        for i, j in np.argwhere(_erosion_boundary(mask))
        if abs(i - a) <= radius and abs(j - b) <= radius
    ]
    got = nearest_boundary_cell(look, (a, b), radius)
    if not cands:
        assert got is None
    else:
        _, i, j = min(cands)  # nearest, ties: lowest (i, j)
        assert got == (int(i), int(j))


def test_fire_lookup_is_membership_in_the_reported_fire_cells():
    """A cell is fire iff it was reported burning or burned (module doc); every other cell, near
    the reported block or far from it, at negative or positive indices, is outside. Checked
    against a set of the cells built by index (centre = origin + (i, j) * cell size)."""
    grid = CellGrid(-3.0, 7.0, 2.5)
    states = (CellState.UNBURNED, CellState.BURNING, CellState.BURNED)
    rng = np.random.default_rng(21)
    for n in (0, 1, 2, 5, 30):
        for _ in range(8):
            ij = rng.integers(-7, 8, size=(n, 2))
            st = rng.choice([int(s) for s in states], size=n)
            x = grid.origin_x_m + ij[:, 0] * grid.cell_size_m
            y = grid.origin_y_m + ij[:, 1] * grid.cell_size_m
            fire = {(int(a), int(b)) for (a, b), s in zip(ij, st, strict=True) if s != CellState.UNBURNED}
            look = fire_lookup(x.astype(float), y.astype(float), st.astype(np.uint8), grid)
            for a in range(-10, 11):
                for b in range(-10, 11):
                    assert look(a, b) is ((a, b) in fire), (n, a, b)
