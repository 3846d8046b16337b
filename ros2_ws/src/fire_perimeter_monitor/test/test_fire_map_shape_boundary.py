"""On-board fire map (PM IV-A), scan-method construction (IV-B), hull/error (VI-E), boundary following."""

import ast
import math
from pathlib import Path

import numpy as np
import pytest
from fire_perimeter_monitor.boundary import lookup_from_grid, next_boundary_cell
from fire_perimeter_monitor.fire_map import (
    CellGrid,
    Direction,
    FireMap,
    angle_bin,
    direction_sign,
    perimeter_mask,
)
from fire_perimeter_monitor.shape import (
    construct_perimeter,
    convex_hull,
    max_distance_error,
    polygon_radial_extent,
    resample_closed,
)


def test_no_rclpy_in_library_modules():
    pkg = Path(__file__).resolve().parents[1] / "fire_perimeter_monitor"
    for f in pkg.glob("*.py"):
        if f.name == "viewer_node.py":
            continue
        for node in ast.walk(ast.parse(f.read_text())):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            assert not any(n.split(".")[0] == "rclpy" for n in names), f.name


def test_angle_bins():
    b = angle_bin([1, 0, -1, 0, 1], [0.001, 1, 0, -1, -0.001], 0.0, 0.0)
    assert b.tolist() == [0, 90, 180, 270, 359]


def test_fire_map_outer_inner_update_and_ros():
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record([100.0], [0.0], 50.0)  # Listing 2: inner = ignition point at t=0
    assert fm.outer_d_m[0] == 100.0 and fm.inner_d_m[0] == 0.0 and fm.inner_t_s[0] == 0.0
    assert fm.ros_mps()[0] == pytest.approx(2.0)
    fm.record([102.0], [0.0], 55.0)  # within the revisit gap: same visit, inner kept
    assert fm.outer_d_m[0] == 102.0 and fm.inner_t_s[0] == 0.0
    fm.record([130.0], [0.0], 100.0)  # new visit: outer -> inner
    assert fm.inner_d_m[0] == 102.0 and fm.inner_t_s[0] == 55.0 and fm.outer_t_s[0] == 100.0
    assert fm.ros_mps()[0] == pytest.approx(28.0 / 45.0)  # Eq. 1
    assert np.isnan(fm.ros_mps()[1])
    # farthest cell of a bin is the outer cell
    fm.record([50.0, 150.0], [0.1, 0.2], 200.0)
    assert fm.outer_d_m[0] == pytest.approx(math.hypot(150.0, 0.2))


def test_fire_map_unknown_ignition_time_and_merge():
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    fm.record([0.0], [100.0], 50.0)
    assert np.isnan(fm.ros_mps()[90])
    other = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    other.record([0.0], [140.0], 90.0)
    assert fm.merge_outer(other.outer_x_m, other.outer_y_m, other.outer_t_s) == 1
    assert fm.ros_mps()[90] == pytest.approx(1.0)
    assert fm.merge_outer(other.outer_x_m, other.outer_y_m, other.outer_t_s) == 0  # not newer


def test_fill_of_skipped_bins():
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    r = 3000.0  # a bin is ~52 m wide here: two neighbouring 100 m cells skip a bin
    x = r * np.cos(np.radians([10.2, 12.1]))
    y = r * np.sin(np.radians([10.2, 12.1]))
    fm.record(x, y, 1.0, link_m=150.0)
    assert fm.known[10] and fm.known[11] and fm.known[12]
    assert fm.outer_d_m[11] == pytest.approx(r, rel=1e-3)


def test_perimeter_mask():
    g = CellGrid(0.0, 0.0, 1.0)
    ii, jj = np.meshgrid(np.arange(-3, 4), np.arange(-3, 4), indexing="ij")
    x, y = g.center(ii.ravel(), jj.ravel())
    state = ((ii.ravel() ** 2 + jj.ravel() ** 2) <= 4).astype(int)
    per = perimeter_mask(x, y, state, 1.0)
    assert per.sum() > 0 and not per[(x == 0) & (y == 0)].any()
    assert per[(x == 2) & (y == 0)].all()


def _disc_mask(n=41, r=12.0):
    ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    return (ii - n // 2) ** 2 + (jj - n // 2) ** 2 <= r * r


@pytest.mark.parametrize("direction", [Direction.CCW, Direction.CW])
def test_boundary_following_closes_a_lap(direction):
    mask = _disc_mask()
    g = CellGrid(0.0, 0.0, 1.0)
    look = lookup_from_grid(mask, g)
    start = (20 + 12, 20)
    cell, prev, path = start, None, [start]
    for _ in range(500):
        nxt = next_boundary_cell(look, cell, direction, prev)
        prev, cell = cell, nxt
        path.append(cell)
        if cell == start:
            break
    assert cell == start and 40 < len(path) < 120
    ang = np.unwrap([math.atan2(j - 20, i - 20) for i, j in path])
    assert (ang[-1] - ang[0]) * direction_sign(direction) == pytest.approx(2 * np.pi, abs=0.2)
    # sensor range: a step only needs the 8 neighbours
    look_r = lookup_from_grid(mask, g, center_cell=start, range_cells=1.5)
    assert next_boundary_cell(look_r, start, direction) == path[1]


def test_scan_method_closes_perimeter_at_tangent():
    """PM IV-B / Fig. 5: old (stale) circle of radius 50 ahead, UAV outside at radius 80."""
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    th = (np.arange(360) + 0.5) * np.pi / 180
    fm.record(50 * np.cos(th), 50 * np.sin(th), 0.0)
    cp = construct_perimeter(fm, 80.0, 0.0, Direction.CCW, 1000.0, angle_tol_rad=0.0)
    tangent = math.degrees(math.acos(50 / 80))  # 51.3 degrees
    assert cp.anchor_bin == -1 and abs(cp.best_bin - tangent) <= 1.5
    assert len(cp.replaced_bins) == pytest.approx(tangent, abs=2)
    cw = construct_perimeter(fm, 80.0, 0.0, Direction.CW, 1000.0, angle_tol_rad=0.0)
    assert abs((360 - cw.best_bin) - tangent) <= 1.5
    pts, spacing = resample_closed(cp.vertices_m, 5.0)
    assert spacing == pytest.approx(5.0, rel=0.05) and np.allclose(pts[0], [80.0, 0.0])


def test_convex_hull_and_distance_error():
    pts = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1], [1, 0.5]], dtype=float)
    h = convex_hull(pts)
    assert len(h) == 4 and {tuple(p) for p in h} == {(0, 0), (2, 0), (2, 2), (0, 2)}
    r = polygon_radial_extent(h, 1.0, 1.0, 360)
    assert r.min() == pytest.approx(1.0, abs=1e-3) and r.max() == pytest.approx(math.sqrt(2), abs=0.02)
    assert max_distance_error(r, r) == 0.0
    assert max_distance_error(r + 0.5, r) == pytest.approx(0.5)
