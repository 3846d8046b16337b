"""Spanning-tree coverage paths with turn arcs (CP III-C)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.search.errors import PathError, SearchConfigError
from fire_uav_agent.search.stc import SEG_ARC, spanning_tree, stc_path, stc_subcell_tour

CELL = 120.0


def _random_region(rng: np.random.Generator, shape=(7, 9), fill: float = 0.6) -> np.ndarray:
    """A random 4-connected region grown from one cell."""
    region = np.zeros(shape, dtype=bool)
    start = (int(rng.integers(shape[0])), int(rng.integers(shape[1])))
    region[start] = True
    frontier = [start]
    target = int(fill * region.size)
    while region.sum() < target and frontier:
        cy, cx = frontier[int(rng.integers(len(frontier)))]
        dy, dx = [(0, 1), (1, 0), (0, -1), (-1, 0)][int(rng.integers(4))]
        ny, nx = cy + dy, cx + dx
        if 0 <= ny < shape[0] and 0 <= nx < shape[1] and not region[ny, nx]:
            region[ny, nx] = True
            frontier.append((ny, nx))
    return region


def test_root_is_lowest_row_then_leftmost() -> None:
    region = np.zeros((4, 4), dtype=bool)
    region[1, 2] = region[1, 3] = region[2, 1] = region[2, 2] = True
    root, edges = spanning_tree(region)
    assert root == (1, 2)
    assert len(edges) == region.sum() - 1


@pytest.mark.parametrize("seed", range(12))
def test_tour_visits_every_subcell_once(seed: int) -> None:
    region = _random_region(np.random.default_rng(seed))
    tour = stc_subcell_tour(region)
    assert len(tour) == 4 * region.sum()
    assert len({tuple(t) for t in tour}) == len(tour)
    assert np.all(region[tour[:, 0] // 2, tour[:, 1] // 2])
    steps = np.abs(np.diff(np.vstack([tour, tour[:1]]), axis=0)).sum(axis=1)
    assert np.all(steps == 1)  # closed 4-neighbour walk


@pytest.mark.parametrize("seed", range(12))
def test_path_covers_region_with_min_radius_and_is_c1(seed: int) -> None:
    region = _random_region(np.random.default_rng(seed))
    r_min = 20.0
    path = stc_path(region, x_min_m=-300.0, y_min_m=50.0, cell_size_m=CELL, turn_radius_m=25.0)
    assert path.min_turn_radius_m >= r_min
    assert np.all(path.radius_m[path.kind == SEG_ARC] >= r_min)
    smp = path.sample(2.0)
    # every sample lies inside the region; every sub-cell of the region is entered
    half = CELL / 2
    sx = np.floor((smp.pos_m[:, 0] + 300.0) / half).astype(int)
    sy = np.floor((smp.pos_m[:, 1] - 50.0) / half).astype(int)
    assert np.all(region[sy // 2, sx // 2])
    visited = set(zip(sy.tolist(), sx.tolist(), strict=True))
    wanted = {(2 * y + a, 2 * x + b) for y, x in np.argwhere(region) for a in (0, 1) for b in (0, 1)}
    assert visited == wanted
    # C^1: position and heading continuous along the closed path
    s = np.arange(0.0, path.length_m, 0.5)
    p = path.positions_at(s)
    gaps = np.linalg.norm(np.diff(np.vstack([p, p[:1]]), axis=0), axis=1)
    assert gaps.max() <= 0.5 + 1e-6
    h = path.headings_at(s)
    dh = np.abs(np.angle(np.exp(1j * np.diff(np.append(h, h[0])))))
    assert dh.max() <= 0.5 / 25.0 + 1e-6


def test_path_length_matches_hand_count() -> None:
    region = np.zeros((3, 4), dtype=bool)
    region[0, :] = True
    region[1, 1] = True
    region[2, 1:3] = True
    r = CELL / 4
    path = stc_path(region, x_min_m=0.0, y_min_m=0.0, cell_size_m=CELL)
    # polygon through 28 sub-cell centres = 28 * 60 m; each 90 deg fillet saves 2r - pi r / 2
    expected = 28 * CELL / 2 - path.n_turns * (2 * r - math.pi * r / 2)
    assert path.length_m == pytest.approx(expected)
    assert path.turn_length_m == pytest.approx(path.n_turns * math.pi * r / 2)


def test_start_offset_moves_start_along_path() -> None:
    region = np.ones((2, 3), dtype=bool)
    path = stc_path(region, x_min_m=0.0, y_min_m=0.0, cell_size_m=CELL)
    np.testing.assert_allclose(path.positions_at(np.array([0.0])), [[CELL / 2, CELL / 4]])
    smp = path.sample(10.0, start_fraction=0.3)
    np.testing.assert_allclose(smp.pos_m[0], path.positions_at(np.array([0.3 * path.length_m]))[0])
    with pytest.raises(SearchConfigError, match="start_fraction"):
        path.sample(10.0, start_fraction=1.0)


def test_turn_radius_that_does_not_fit_is_rejected() -> None:
    with pytest.raises(PathError, match="turn_radius_m"):
        stc_path(np.ones((2, 2), dtype=bool), x_min_m=0, y_min_m=0, cell_size_m=CELL, turn_radius_m=31.0)


def test_disconnected_region_is_rejected() -> None:
    region = np.array([[True, False, True]])
    with pytest.raises(PathError, match="not 4-connected"):
        stc_subcell_tour(region)
    with pytest.raises(PathError, match="empty"):
        spanning_tree(np.zeros((2, 2), dtype=bool))


def test_loiter_is_a_ccw_circle_from_its_bottom_point() -> None:
    from fire_uav_agent.search.stc import loiter_path

    c, r = np.array([300.0, -200.0]), 80.0
    path = loiter_path(c, r)
    assert path.length_m == pytest.approx(2 * math.pi * r) and path.n_turns == 1
    assert path.turn_length_m == pytest.approx(path.length_m) and path.straight_length_m == 0.0
    assert path.min_turn_radius_m == r
    s = np.linspace(0.0, path.length_m, 37)
    p = path.positions_at(s)
    np.testing.assert_allclose(np.linalg.norm(p - c, axis=1), r)
    phase = s / r - math.pi / 2  # angle about the centre, CCW from the bottom point
    np.testing.assert_allclose(p, c + r * np.column_stack([np.cos(phase), np.sin(phase)]), atol=1e-9)
    h = path.headings_at(s)
    np.testing.assert_allclose(np.cos(h), np.cos(phase + math.pi / 2), atol=1e-9)  # tangent, CCW
    np.testing.assert_allclose(np.sin(h), np.sin(phase + math.pi / 2), atol=1e-9)
    assert path.is_turn_at(s).all()


def test_straight_and_turn_lengths_of_a_one_cell_region() -> None:
    """One coarse cell: a square of side Delta/2 through the 4 sub-cell centres, 4 quarter arcs."""
    r = 10.0
    path = stc_path(np.ones((1, 1), dtype=bool), x_min_m=0.0, y_min_m=0.0, cell_size_m=CELL, turn_radius_m=r)
    side = CELL / 2
    assert path.n_turns == 4
    assert path.straight_length_m == pytest.approx(4 * (side - 2 * r))
    assert path.turn_length_m == pytest.approx(4 * (math.pi / 2) * r)
    assert path.min_turn_radius_m == r
    smp = path.sample(1.0)
    assert smp.spacing_m == pytest.approx(path.length_m / math.ceil(path.length_m))
    assert smp.is_turn.mean() == pytest.approx(path.turn_length_m / path.length_m, abs=0.02)
    # headings on the first straight (bottom side, eastward) and the first arc (turning north)
    assert path.headings_at(np.array([1.0]))[0] == pytest.approx(0.0)
    assert not path.is_turn_at(np.array([1.0]))[0]
    mid_arc = side - 2 * r + (math.pi / 4) * r
    assert path.headings_at(np.array([mid_arc]))[0] == pytest.approx(math.pi / 4)
    assert path.is_turn_at(np.array([mid_arc]))[0]
    with pytest.raises(SearchConfigError, match="spacing_m"):
        path.sample(0.0)
    with pytest.raises(SearchConfigError, match="start_fraction"):
        path.sample(1.0, start_fraction=-0.1)
    with pytest.raises(SearchConfigError, match="cell_size_m"):
        stc_path(np.ones((1, 1), dtype=bool), x_min_m=0.0, y_min_m=0.0, cell_size_m=0.0)
    with pytest.raises(PathError, match="turn_radius_m"):
        stc_path(np.ones((1, 1), dtype=bool), x_min_m=0.0, y_min_m=0.0, cell_size_m=CELL, turn_radius_m=0.0)
