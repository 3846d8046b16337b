"""Shape construction, hull and distance error (PM IV-B, VI-E) on shapes with analytic answers.

References: scipy's Qhull (convex hull), the polar equation of an ellipse and of a square
(radial extent), the Minkowski-sum area of a convex polygon and a square (hull of cell squares),
arc length of a square (resampling), and the tangent from an outside point to a circle (scan).
"""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import Direction, FireMap
from fire_perimeter_monitor.shape import (
    construct_perimeter,
    convex_hull,
    max_distance_error,
    perimeter_cells_hull,
    polygon_radial_extent,
    resample_closed,
)
from hypothesis import Phase, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

# No shrinking: a failing example is reported as drawn (fast, also under mutation testing).
NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate)


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _widths(p: np.ndarray) -> tuple[float, float]:
    return float(np.ptp(p[:, 0])), float(np.ptp(p[:, 1]))


@settings(max_examples=30, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1), st.integers(3, 40))
def test_convex_hull_matches_qhull_and_is_ccw(seed, n):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 2)) * rng.uniform(0.1, 100.0, 2)
    pts = np.vstack([pts, pts[: n // 3]])  # repeated points
    h = convex_hull(pts)
    ref = ConvexHull(pts)
    assert {tuple(p) for p in h} == {tuple(pts[k]) for k in ref.vertices}
    assert len(h) == len(ref.vertices)  # no collinear or repeated vertices
    assert _signed_area(h) == pytest.approx(ref.volume, rel=1e-9)  # CCW: positive area


def test_convex_hull_degenerate_inputs():
    assert convex_hull(np.zeros((0, 2))).shape == (0, 2)
    assert len(convex_hull([[1.0, 2.0], [1.0, 2.0]])) == 1
    assert len(convex_hull([[0.0, 0.0], [1.0, 1.0]])) == 2
    line = convex_hull([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]])
    assert {tuple(p) for p in line} == {(0.0, 0.0), (3.0, 3.0)}  # collinear points dropped
    square_with_edge_points = [[0, 0], [1, 0], [2, 0], [2, 2], [0, 2], [0, 1]]
    assert len(convex_hull(square_with_edge_points)) == 4


@pytest.mark.parametrize("a,b", [(300.0, 100.0), (120.0, 200.0)])
def test_radial_extent_of_an_ellipse(a, b):
    """Ellipse x^2/a^2 + y^2/b^2 = 1 about its centre: r(t) = a b / sqrt((b cos t)^2 + (a sin t)^2)."""
    k = 2000
    s = np.linspace(0, 2 * np.pi, k, endpoint=False)
    cx, cy = 1000.0, -400.0
    poly = np.column_stack([cx + a * np.cos(s), cy + b * np.sin(s)])
    bins = 72
    r = polygon_radial_extent(poly, cx, cy, bins)
    t = (np.arange(bins) + 0.5) * 2 * np.pi / bins
    exact = a * b / np.hypot(b * np.cos(t), a * np.sin(t))
    chord_sag = max(a, b) * (1 - math.cos(math.pi / k)) * max(a, b) / min(a, b)
    np.testing.assert_allclose(r, exact, atol=chord_sag + 1e-9)
    assert max_distance_error(exact, r) <= chord_sag + 1e-9


def test_radial_extent_of_a_square_about_an_inner_and_an_outer_point():
    sq = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    t = (np.arange(360) + 0.5) * np.pi / 180
    r = polygon_radial_extent(sq, 5.0, 5.0)
    np.testing.assert_allclose(r, 5.0 / np.maximum(np.abs(np.cos(t)), np.abs(np.sin(t))))
    r2 = polygon_radial_extent(sq, 2.0, 3.0, 4)  # rays at 45, 135, 225, 315 degrees
    np.testing.assert_allclose(r2, [7 * math.sqrt(2), 2 * math.sqrt(2), 2 * math.sqrt(2), 3 * math.sqrt(2)])
    # centre outside, left of the square: only rays pointing right hit it, at the far side
    r3 = polygon_radial_extent(sq, -10.0, 5.0, 16)  # 11.25, 33.75, ... degrees
    far = 20.0 / math.cos(math.radians(11.25))  # leaves through the right side x = 10
    assert r3[0] == pytest.approx(far) and r3[15] == pytest.approx(far)
    assert np.isnan(r3[1:15]).all()  # 33.75 degrees passes above the square; the rest point away
    assert np.isnan(polygon_radial_extent(sq[:2], 5.0, 5.0, 6)).all()  # fewer than 3 vertices


def test_max_distance_error_unknowns():
    true = np.array([10.0, 20.0, np.nan, 5.0])
    est = np.array([12.0, np.nan, 3.0, 5.5])
    assert max_distance_error(true, est) == 20.0  # unknown estimate: the whole true extent
    assert max_distance_error(true, np.array([9.0, 21.5, 100.0, 5.0])) == 1.5  # NaN true: ignored
    assert math.isnan(max_distance_error(np.full(3, np.nan), np.ones(3)))


@pytest.mark.parametrize("spacing", [7.0, 10.0, 13.0])
def test_resample_square_tiles_the_loop(spacing):
    side = 100.0
    sq = np.array([[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]]) + [5.0, 7.0]
    pts, got = resample_closed(sq, spacing)
    m = round(4 * side / spacing)
    assert len(pts) == m and got == pytest.approx(4 * side / m)
    assert np.allclose(pts[0], sq[0])
    # every point on the square's edges, and consecutive points one spacing apart along the loop
    x, y = pts[:, 0] - 5.0, pts[:, 1] - 7.0
    on_edge = np.minimum.reduce([np.abs(x), np.abs(x - side), np.abs(y), np.abs(y - side)])
    assert on_edge.max() < 1e-9
    arc = np.where(
        y < 1e-9,
        x,
        np.where(x > side - 1e-9, side + y, np.where(y > side - 1e-9, 3 * side - x, 4 * side - y)),
    )
    arc[0] = 0.0
    np.testing.assert_allclose(np.diff(arc), got, atol=1e-9)


def test_resample_degenerate_loops():
    one = np.array([[3.0, 4.0]])
    pts, s = resample_closed(one, 5.0)
    assert np.array_equal(pts, one) and s == 5.0
    same = np.array([[3.0, 4.0], [3.0, 4.0], [3.0, 4.0]])
    pts, s = resample_closed(same, 5.0)
    assert np.array_equal(pts, same[:1]) and s == 5.0
    pts, s = resample_closed(np.array([[0.0, 0.0], [1.0, 0.0]]), 10.0)  # loop of 2 m: at least 2 points
    assert len(pts) == 2 and s == pytest.approx(1.0) and np.allclose(pts[1], [1.0, 0.0])


def test_cells_hull_is_the_minkowski_sum_with_the_cell_square():
    """Hull of the cells' squares = hull(centres) (+) square: area A + c (w_x + w_y) + c^2."""
    c = 30.0
    rng = np.random.default_rng(3)
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    th = rng.uniform(0, 2 * np.pi, 200)
    rad = rng.uniform(200.0, 400.0, 200)
    fm.record(rad * np.cos(th), rad * np.sin(th), 5.0)
    k = fm.known
    centres = np.column_stack([fm.outer_x_m[k], fm.outer_y_m[k]])
    ref = ConvexHull(centres)
    wx, wy = _widths(centres)
    h = perimeter_cells_hull(fm, c)
    assert _signed_area(h) == pytest.approx(ref.volume + c * (wx + wy) + c * c, rel=1e-9)
    assert _widths(h) == pytest.approx((wx + c, wy + c))
    one = FireMap(0.0, 0.0)
    one.record([100.0], [50.0], 0.0)
    sq = perimeter_cells_hull(one, c)
    assert _signed_area(sq) == pytest.approx(c * c) and np.allclose(sq.mean(axis=0), [100.0, 50.0])
    assert perimeter_cells_hull(FireMap(0.0, 0.0), c).shape[0] == 0


def _stale_circle(radius=50.0, t=0.0):
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    th = (np.arange(360) + 0.5) * np.pi / 180
    fm.record(radius * np.cos(th), radius * np.sin(th), t)
    return fm


@pytest.mark.parametrize("uav_r", [60.0, 80.0, 150.0])
@pytest.mark.parametrize("direction", [Direction.CCW, Direction.CW])
def test_scan_closes_at_the_tangent_point(uav_r, direction):
    """From a point at distance R of a circle of radius r the tangent touches at acos(r / R)."""
    fm = _stale_circle()
    ang = 0.7
    cp = construct_perimeter(
        fm, uav_r * math.cos(ang), uav_r * math.sin(ang), direction, 1000.0, angle_tol_rad=0.0
    )
    sign = 1 if direction is Direction.CCW else -1
    tangent = math.degrees(ang + sign * math.acos(50.0 / uav_r)) % 360
    assert cp.anchor_bin == -1
    assert abs((cp.best_bin + 0.5 - tangent + 180) % 360 - 180) <= 1.0
    replaced = np.asarray(cp.replaced_bins)
    assert len(replaced) == pytest.approx(math.degrees(math.acos(50.0 / uav_r)), abs=2)
    # the closed perimeter: the UAV, then the kept cells, in the flying direction
    assert np.allclose(cp.vertices_m[0], [uav_r * math.cos(ang), uav_r * math.sin(ang)])
    assert len(cp.vertices_m) == 1 + 359 - len(replaced)
    bearings = np.unwrap(np.arctan2(cp.vertices_m[1:, 1], cp.vertices_m[1:, 0]))
    assert np.all(sign * np.diff(bearings) > 0)


def test_scan_with_fresh_cells_ahead_anchors_at_the_last_fresh_one():
    fm = _stale_circle()
    th = np.radians(np.arange(1, 11) + 0.5)  # bins 1..10 seen again just now, further out
    fm.record(55 * np.cos(th), 55 * np.sin(th), 995.0)
    cp = construct_perimeter(fm, 80.0, 0.0, Direction.CCW, 1000.0, angle_tol_rad=0.0)
    assert cp.anchor_bin == 10
    anchor = np.array([55 * math.cos(th[-1]), 55 * math.sin(th[-1])])
    expect = math.degrees(math.atan2(anchor[1], anchor[0]) + math.acos(50.0 / 55.0))
    assert abs(cp.best_bin + 0.5 - expect) <= 1.5
    assert cp.replaced_bins.min() == 11  # the fresh cells are kept


def test_scan_edge_cases():
    empty = construct_perimeter(FireMap(0.0, 0.0), 80.0, 0.0, Direction.CCW, 10.0)
    assert empty.vertices_m.shape == (1, 2) and empty.anchor_bin == -1 and empty.best_bin == -1
    fresh = _stale_circle(t=1000.0)  # everything fresh: no closing line
    cp = construct_perimeter(fresh, 80.0, 0.0, Direction.CCW, 1000.0)
    assert cp.best_bin == -1 and cp.anchor_bin == -1 and len(cp.vertices_m) == 360
    assert len(cp.replaced_bins) == 0
    # only the half-turn behind the UAV stale: no candidate within half a turn ahead
    fm = _stale_circle(t=0.0)
    th = np.radians(np.arange(0, 181) + 0.5)
    fm.record(55 * np.cos(th), 55 * np.sin(th), 1000.0)  # the fire grew: the map never moves inward
    cp = construct_perimeter(fm, 80.0, 0.0, Direction.CCW, 1000.0)
    assert cp.best_bin == -1 and cp.anchor_bin == 180 and len(cp.vertices_m) == 360
    # fresh_s overrides the map's revisit gap: with a huge one, nothing is stale
    cp = construct_perimeter(_stale_circle(t=0.0), 80.0, 0.0, Direction.CCW, 1000.0, fresh_s=5000.0)
    assert cp.best_bin == -1 and len(cp.vertices_m) == 360
