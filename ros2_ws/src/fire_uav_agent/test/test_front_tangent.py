"""``tactics.front_tangent`` (the pattern drop's leg direction) against brute force: the front cells
within the radius counted with ``math.hypot``, and the total-least-squares line as the direction
minimising the cells' mean squared distance across it, scanned over a fine grid of angles (for a
2 x 2 covariance the smallest and largest spreads over all directions are its eigenvalues)."""

import math

import numpy as np
import pytest
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.tactics import front_tangent

ANGLES = np.linspace(0.0, math.pi, 7201)  # every 0.025 deg


def _cells(x, y):
    z = np.zeros(len(x))
    return FrontCells(np.asarray(x, float), np.asarray(y, float), z.astype(np.int64), z, z)


def _brute(x, y, aim, radius):
    """(n, spreads across the direction for each angle of ANGLES) of the cells within the radius."""
    keep = [i for i in range(len(x)) if math.hypot(x[i] - aim[0], y[i] - aim[1]) <= radius]
    px, py = np.asarray(x)[keep], np.asarray(y)[keep]
    px, py = px - px.mean(), py - py.mean()
    across = np.mean((-np.outer(np.sin(ANGLES), px) + np.outer(np.cos(ANGLES), py)) ** 2, axis=1)
    return len(keep), across


@pytest.mark.parametrize("seed", range(4))
def test_the_direction_is_the_least_squares_line_of_the_cells_within_the_radius(seed):
    """Seeded elongated clouds at random orientations off the origin, the aim off their centre, with
    cells beyond the radius on both axes that must not count: the direction returned is a unit
    vector whose across-spread is the brute-force minimum (to 1e-9 relative) and whose along-spread
    is the maximum; clouds whose spread ratio is above max_aspect (with a margin) give None."""
    rng = np.random.default_rng(seed)
    lines = blobs = 0
    for _ in range(25):
        th = float(rng.uniform(0.0, math.pi))
        n = int(rng.integers(6, 40))
        along, across = rng.normal(0.0, 60.0, n), rng.normal(0.0, float(rng.uniform(3.0, 50.0)), n)
        cx, cy = float(rng.uniform(-800, 800)), float(rng.uniform(-800, 800))
        x = cx + along * math.cos(th) - across * math.sin(th)
        y = cy + along * math.sin(th) + across * math.cos(th)
        aim = (cx + float(rng.normal(0, 20)), cy + float(rng.normal(0, 20)))
        far = [(aim[0] + 400.0, aim[1]), (aim[0], aim[1] - 400.0), (aim[0] - 300.0, aim[1] + 300.0)]
        x = np.concatenate([x, [f[0] for f in far]])
        y = np.concatenate([y, [f[1] for f in far]])
        radius = 250.0
        k, spread = _brute(x, y, aim, radius)
        lam2, lam1 = float(spread.min()), float(spread.max())
        ratio = math.sqrt(lam2 / lam1)
        got = front_tangent(_cells(x, y), aim, radius)
        if k < 5:
            assert got is None
            continue
        if abs(ratio - 0.5) < 0.01:
            continue  # the grid's minimum is not the exact eigenvalue: too close to the bound to tell
        if ratio > 0.5:
            assert got is None
            blobs += 1
            continue
        lines += 1
        assert got is not None and math.hypot(*got) == pytest.approx(1.0, abs=1e-12)
        ux, uy = got
        near = [i for i in range(len(x)) if math.hypot(x[i] - aim[0], y[i] - aim[1]) <= radius]
        px, py = x[near] - x[near].mean(), y[near] - y[near].mean()
        assert np.mean((-uy * px + ux * py) ** 2) <= lam2 * (1 + 1e-9) + 1e-12
        assert np.mean((ux * px + uy * py) ** 2) >= lam1 * (1 - 1e-9) - 1e-12
    assert lines >= 5 and blobs >= 2


def test_min_cells_counts_the_cells_within_the_radius_inclusive():
    """Cells on the x axis 10 m apart, the aim at the first, the radius 40 m: the cell at exactly 40 m
    counts (five cells: a line), without it four are too few; min_cells 3 takes three; below 2 cells
    there is no line whatever min_cells says."""
    x = np.array([0.0, 10.0, 20.0, 30.0, 40.0, 50.0]) + 300.0
    y = np.full(6, -200.0)
    got = front_tangent(_cells(x, y), (300.0, -200.0), 40.0)
    assert got is not None and abs(got[0]) == pytest.approx(1.0) and got[1] == pytest.approx(0.0, abs=1e-12)
    assert front_tangent(_cells(x, y), (300.0, -200.0), 39.99) is None
    assert front_tangent(_cells(x[:3], y[:3]), (300.0, -200.0), 40.0, min_cells=3) is not None
    assert front_tangent(_cells(x[:2], y[:2]), (300.0, -200.0), 40.0, min_cells=3) is None
    assert front_tangent(_cells(x[:1], y[:1]), (300.0, -200.0), 40.0, min_cells=1) is None
    two = front_tangent(_cells(x[:2], y[:2] + np.array([0.0, 10.0])), (300.0, -200.0), 40.0, min_cells=1)
    assert two is not None and abs(two[0]) == pytest.approx(math.sqrt(0.5)) and two[0] * two[1] > 0


def test_the_aspect_bound_and_the_degenerate_inputs():
    """A rectangle of cells 4 x 2 (spreads 5/4 and 1/4 x 10^2: ratio sqrt(0.2) = 0.447) is a line for
    max_aspect 0.45 and 0.5, not for 0.44; a square block and cells all at one point are no line; an
    empty front and a radius that is not positive give None."""
    gx, gy = np.meshgrid([0.0, 10.0, 20.0, 30.0], [0.0, 10.0])
    rect = _cells(gx.ravel() + 50.0, gy.ravel() - 70.0)
    aim = (65.0, -65.0)
    for aspect, line in ((0.5, True), (0.45, True), (0.44, False)):
        assert (front_tangent(rect, aim, 100.0, max_aspect=aspect) is not None) is line
    got = front_tangent(rect, aim, 100.0)
    assert abs(got[0]) == pytest.approx(1.0) and got[1] == pytest.approx(0.0, abs=1e-12)
    sx, sy = np.meshgrid([0.0, 10.0, 20.0], [0.0, 10.0, 20.0])
    assert front_tangent(_cells(sx.ravel(), sy.ravel()), (10.0, 10.0), 100.0) is None
    assert front_tangent(_cells(np.full(6, 5.0), np.full(6, 7.0)), (5.0, 7.0), 10.0) is None
    assert front_tangent(_cells([], []), (0.0, 0.0), 100.0) is None
    assert front_tangent(rect, aim, 0.0) is None
    assert front_tangent(rect, aim, -5.0) is None
    assert front_tangent(rect, aim, -100.0) is None  # not read as a 100 m radius (its square)


def test_a_sub_metre_line_within_a_sub_metre_radius():
    """Nothing in the rule is in metres: five cells 0.2 m apart on a diagonal (spread 0.04 m^2)
    within a 0.9 m radius are a line along the diagonal."""
    d = np.array([-0.4, -0.2, 0.0, 0.2, 0.4])
    got = front_tangent(_cells(10.0 + d, 20.0 + d), (10.0, 20.0), 0.9)
    assert got is not None and abs(got[0]) == pytest.approx(math.sqrt(0.5)) and got[0] * got[1] > 0


def test_a_spread_ratio_of_exactly_max_aspect_is_still_a_line():
    """None only for a ratio *above* max_aspect: four cells at (+-10, +-5) m have spreads 100 and 25
    m^2 along the axes (no cross term), a ratio of exactly 0.5."""
    cells = _cells([90.0, 110.0, 90.0, 110.0], [45.0, 45.0, 55.0, 55.0])
    got = front_tangent(cells, (100.0, 50.0), 50.0, min_cells=4, max_aspect=0.5)
    assert got is not None and abs(got[0]) == pytest.approx(1.0)
    assert front_tangent(cells, (100.0, 50.0), 50.0, min_cells=4, max_aspect=0.4999) is None
