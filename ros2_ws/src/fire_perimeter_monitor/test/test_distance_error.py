"""PM VI-E distance error against geometry worked by hand: squares, discs, a notched fire."""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.distance_error import (
    distance_error,
    hull_extent,
    max_error,
    perfect_map_cells,
    running_average,
    true_extent,
)

C = 5.0


def _disc(radius_cells: int, c: float = C) -> np.ndarray:
    k = np.arange(-radius_cells, radius_cells + 1)
    i, j = np.meshgrid(k, k, indexing="ij")
    inside = i**2 + j**2 <= radius_cells**2
    return np.column_stack([i[inside] * c, j[inside] * c]).astype(float)


def test_true_extent_of_one_square_is_exact():
    """From the centre of one cell the ray at angle a leaves it at (C/2) / max(|cos a|, |sin a|)."""
    ext = true_extent(np.array([[0.0, 0.0]]), C, (0.0, 0.0), 360)
    a = (np.arange(360) + 0.5) * np.pi / 180
    assert np.allclose(ext, (C / 2) / np.maximum(np.abs(np.cos(a)), np.abs(np.sin(a))))
    # from outside: the ray at 0.5 deg leaves the square 10 m east through its side x = 12.5
    ext = true_extent(np.array([[10.0, 0.0]]), C, (0.0, 0.0), 360)
    assert ext[0] == pytest.approx(12.5 / math.cos(np.radians(0.5)))
    assert np.isnan(ext[180]) and np.isnan(ext[30])  # west, and north-east above the square: nothing


def test_a_complete_current_map_of_a_convex_fire_scores_zero():
    k = np.arange(-6, 7) * C
    block = np.column_stack([a.ravel() for a in np.meshgrid(k, k)])  # a square fire, convex
    e = distance_error(block, perfect_map_cells(block, C, (0.0, 0.0)), C, (0.0, 0.0))
    assert e.max_m == pytest.approx(0.0, abs=1e-9) and e.floor_m == pytest.approx(0.0, abs=1e-9)
    # a raster disc is a staircase: the hull bridges its steps, up to about a cell
    disc = _disc(12)
    e = distance_error(disc, perfect_map_cells(disc, C, (0.0, 0.0)), C, (0.0, 0.0))
    assert 0.0 < e.floor_m <= 1.1 * C and e.max_m == e.floor_m
    assert e.max_cells == pytest.approx(e.max_m / C) and e.floor_cells == pytest.approx(e.floor_m / C)


def test_a_stale_map_scores_the_growth_it_missed():
    """A map of the fire 3 cells ago, all round: the error is about 3 cells at every angle."""
    old, now = _disc(9), _disc(12)
    e = distance_error(now, perfect_map_cells(old, C, (0.0, 0.0)), C, (0.0, 0.0))
    assert 2.5 * C <= e.max_m <= 3.6 * C
    assert e.floor_m <= 1.1 * C


def test_a_notched_fire_has_a_floor_no_map_can_beat():
    """A square notch 4 cells deep cut into the east side: the hull bridges it, so even the
    perfect map scores about the notch's depth there."""
    fire = _disc(12)
    notch = (fire[:, 0] > 8 * C) & (np.abs(fire[:, 1]) <= 2 * C)
    fire = fire[~notch]
    e = distance_error(fire, perfect_map_cells(fire, C, (0.0, 0.0)), C, (0.0, 0.0))
    assert 3.0 * C <= e.floor_m <= 4.5 * C
    assert e.max_m == pytest.approx(e.floor_m)


def test_rays_the_map_misses_count_their_whole_extent():
    fire = _disc(10)
    half = fire[fire[:, 0] > 3 * C]  # a map of the east part only: the centre lies outside its hull
    est = hull_extent(half, C, (0.0, 0.0))
    assert np.isnan(est[180])
    tru = true_extent(fire, C, (0.0, 0.0))
    assert max_error(tru, est) == pytest.approx(np.nanmax(tru[np.isnan(est)]))
    assert math.isnan(max_error(np.full(4, np.nan), np.zeros(4)))


def test_errors_and_running_average():
    with pytest.raises(ValueError, match="cell_size_m"):
        distance_error(_disc(2), _disc(2), 0.0, (0.0, 0.0))
    with pytest.raises(ValueError, match="centre"):
        distance_error(_disc(2), _disc(2), C, (math.nan, 0.0))
    assert np.allclose(running_average(np.array([2.0, 4.0, 0.0])), [2.0, 3.0, 2.0])
    assert running_average(np.zeros(0)).size == 0
    assert np.isnan(distance_error(np.zeros((0, 2)), _disc(2), C, (0.0, 0.0)).max_m)
