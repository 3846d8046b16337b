"""Water bodies by their cells (fire_uav_common.water): over-water test and longest straight run
against shapes whose answers are known."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.terrain import Lake
from fire_uav_common.water import WaterCells, longest_straight_run


def test_contains_reads_the_cell_under_the_point() -> None:
    mask = np.array([[1, 0], [0, 1]], dtype=bool)  # row 0 south
    w = WaterCells(100.0, 200.0, 10.0, mask)
    assert w.contains(105.0, 205.0) and w.contains(115.0, 215.0)
    assert not w.contains(115.0, 205.0) and not w.contains(105.0, 215.0)
    assert not w.contains(99.0, 205.0) and not w.contains(105.0, 221.0)  # outside the raster
    assert list(w.contains(np.array([105.0, 115.0]), np.array([205.0, 205.0]))) == [True, False]


def test_longest_run_of_a_rectangle_is_its_diagonal() -> None:
    w = WaterCells(0.0, 0.0, 30.0, np.ones((4, 10), dtype=bool))  # 300 x 120 m
    run = longest_straight_run(w, step_deg=1.0)
    assert run.length_m == pytest.approx(math.hypot(300.0, 120.0), abs=2 * 0.25 * 30.0 * math.sqrt(2))
    assert run.length_m <= math.hypot(300.0, 120.0)


def test_longest_run_of_an_l_shape_stays_in_one_arm() -> None:
    mask = np.zeros((10, 10), dtype=bool)
    mask[0, :] = True  # a 300 m arm along the south edge, one cell wide
    mask[:, 0] = True  # and one up the west edge
    run = longest_straight_run(WaterCells(0.0, 0.0, 30.0, mask))
    assert 280.0 <= run.length_m <= 300.0
    assert abs(math.sin(run.heading_rad)) < 0.1 or abs(math.cos(run.heading_rad)) < 0.1  # along an arm


def test_a_disc_lake_keeps_its_disc_and_its_diameter_as_run() -> None:
    lake = Lake(50.0, 60.0, 40.0)
    assert lake.contains(69.0, 60.0) and not lake.contains(71.0, 60.0)
    assert lake.longest_run.length_m == 40.0


def test_a_lake_with_water_cells_reads_them_not_its_disc() -> None:
    mask = np.zeros((3, 6), dtype=bool)
    mask[1, :] = True  # a 180 m x 30 m channel
    w = WaterCells(0.0, 0.0, 30.0, mask)
    lake = Lake(15.0, 45.0, 30.0, water=w, run=longest_straight_run(w))
    assert lake.contains(170.0, 45.0)  # far outside the disc, over the channel
    assert not lake.contains(15.0, 25.0)  # inside no water cell
    moved = lake.shifted(-10.0, 5.0)
    assert moved.contains(160.0, 50.0) and moved.longest_run.x0_m == pytest.approx(
        lake.longest_run.x0_m - 10.0
    )


def test_row_runs_cover_exactly_the_water_cells() -> None:
    rng = np.random.default_rng(7)
    mask = rng.random((9, 13)) < 0.55  # islands, bays and single cells
    w = WaterCells(-40.0, 1000.0, 30.0, mask)
    rects = w.row_runs()
    assert rects.shape[1] == 4
    # every cell centre lies in exactly one rectangle if it is water, in none if it is not
    ys, xs = np.mgrid[0:9, 0:13]
    cx, cy = -40.0 + (xs + 0.5) * 30.0, 1000.0 + (ys + 0.5) * 30.0
    inside = sum(((cx > x0) & (cx < x1) & (cy > y0) & (cy < y1)).astype(int) for x0, y0, x1, y1 in rects)
    assert np.array_equal(inside, mask.astype(int))
    # one cell high, on cell edges, and together the body's area
    assert np.allclose(rects[:, 3] - rects[:, 1], 30.0)
    assert np.allclose(((rects[:, [0, 2]] + 40.0) / 30.0) % 1.0, 0.0)
    assert float(np.sum((rects[:, 2] - rects[:, 0]) * (rects[:, 3] - rects[:, 1]))) == pytest.approx(
        w.area_m2
    )
