"""A raster fire does not cross a non-burnable line one cell wide (a road, a stream), in a
straight line or a diagonal staircase, but does pass through a gap in it.

Truth: a fire spreading through burnable cells cannot reach a cell whose every path from the
ignition crosses a non-burnable cell (minimum-travel-time spread, Finney 2002, sums the travel
time of every cell a path crosses; FARSITE's barriers and pyretechnics' level set stop there too).
The geometry of the paths is checked against dense sampling of each ring node's segment."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import FuelPatch, Ignition, Raster, Wind
from fire_uav_common.terrain import Terrain
from fire_world_sim.fires import RasterFireModel
from fire_world_sim.fires.ring_update import RING, blocked_nodes, crossed_cells

CS = 5.0
NX, NY = 30, 20


def fire(patches, wind_mps=0.0, compiled=True, t_end_s=400.0):
    spec = Raster(
        nx=NX,
        ny=NY,
        cell_size_m=CS,
        wind=(Wind(0.0, wind_mps, 90.0),),
        ignitions=(Ignition(22.5, 52.5, 0.0),),  # cell (row 10, col 4)
        spread_factor=20.0,
        fuel_patches=tuple(patches),
    )
    m = RasterFireModel(spec, Terrain(), compiled=compiled)
    t = 0.0
    while t < t_end_s:
        m.step(t, 1.0)
        t += 1.0
    return m.state_grid() != CellState.UNBURNED


def cell(i: int, j: int) -> FuelPatch:
    """A non-burnable patch covering cell (row i, column j) only."""
    return FuelPatch(j * CS, (j + 1) * CS, i * CS, (i + 1) * CS, 0)


ROAD = [cell(i, 12) for i in range(NY)]  # column 12, the whole height


@pytest.mark.parametrize("compiled", [True, False])
def test_a_one_cell_road_across_the_grid_stops_the_fire(compiled) -> None:
    burned = fire(ROAD, compiled=compiled)
    assert burned[:, :12].sum() > 150  # the fire filled its side (12 x 20 cells less the first)
    assert not burned[:, 12:].any()


@pytest.mark.parametrize("compiled", [True, False])
def test_a_road_with_a_gap_lets_the_fire_through_the_gap(compiled) -> None:
    burned = fire([c for c in ROAD if c.y_min_m != 10 * CS], compiled=compiled)  # row 10 open
    assert burned[10, 12] and burned[:, 13:].sum() > 100


def test_a_diagonal_staircase_touching_at_corners_stops_the_fire() -> None:
    # cells (i, 8 + i): each touches the next only at a corner
    stair = [cell(i, 8 + i) for i in range(NY)]
    burned = fire(stair, wind_mps=2.0)
    rows, cols = np.mgrid[0:NY, 0:NX]
    assert burned[cols < 8 + rows].sum() > 100
    assert not burned[cols > 8 + rows].any()


def test_the_road_holds_under_a_wind_blowing_across_it() -> None:
    burned = fire(ROAD, wind_mps=3.0)
    assert not burned[:, 12:].any()


def _sampled(di: int, dj: int) -> tuple[set, set]:
    """Cells whose interior the segment (di, dj) -> (0, 0) passes through, and the corners it
    passes through, by dense sampling (independent of :func:`crossed_cells`' arithmetic)."""
    inside, corners = set(), set()
    for t in np.linspace(0.0, 1.0, 20001)[1:-1]:
        pi, pj = di * (1 - t), dj * (1 - t)
        fi, fj = pi - math.floor(pi), pj - math.floor(pj)
        on_i, on_j = abs(fi - 0.5) < 1e-9, abs(fj - 0.5) < 1e-9
        if on_i and on_j:
            corners.add((round(pi * 2), round(pj * 2)))
        elif not on_i and not on_j:
            inside.add((round(pi), round(pj)))
    return inside - {(0, 0), (di, dj)}, corners


@pytest.mark.parametrize("off", RING)
def test_crossed_cells_are_the_cells_the_segment_passes_through(off) -> None:
    cells, corners = crossed_cells(*off)
    inside, corner_pts = _sampled(*off)
    assert set(cells) == inside
    assert len(corners) == len(corner_pts)
    for a, b in corners:  # the two side cells of a corner: diagonal neighbours, off the path
        assert abs(a[0] - b[0]) == 1 and abs(a[1] - b[1]) == 1
        assert a not in inside and b not in inside


def test_blocked_nodes_marks_only_nodes_across_a_barrier() -> None:
    nonburn = np.zeros((9, 9), dtype=bool)
    nonburn[:, 5] = True  # a column just east of the centre cell (4, 4)
    blk = blocked_nodes(nonburn)
    bits = [k for k in range(len(RING)) if (int(blk[4, 4]) >> k) & 1]
    # blocked: the nodes whose sampled path runs through column 5 (dj = +1): every node two
    # columns east, and (+-2, +1), whose paths cross cell (+-1, +1); a corner squeeze needs two
    # non-burnable cells in different columns, which one column cannot give
    expected = sorted(o for o in RING if any(c[1] == 1 for c in _sampled(*o)[0]))
    assert sorted(RING[k] for k in bits) == expected
    assert {(-2, 1), (2, 1), (0, 2)} <= set(expected) and (1, 1) not in expected
