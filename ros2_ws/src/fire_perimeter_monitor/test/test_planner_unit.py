"""Fast unit tests of the monitors (PM Listings 1-3) on small fires; the long flights are in test_planner.py.

References: the Dirichlet-kernel gain of a moving average on a sampled sine, the bisector split
of a circle between two monitors, a circular fire of constant ROS (Eq. 1 gives the ROS, the front
is the outer cell of the fastest bin), and the geometry of a full lap about a known centre.
"""

import math
import re

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import Direction
from fire_perimeter_monitor.planner import (
    CirclingMonitor,
    ImportanceMonitor,
    MonitorConfig,
    smooth_circular,
)
from fire_perimeter_monitor.shape import polygon_radial_extent
from fire_perimeter_monitor.synthetic_fire import fly, star_fire

C = 30.0
SPEED = 10.0


@pytest.mark.parametrize("n,k,freq", [(360, 5, 3), (72, 2, 7), (8, 1, 1)])
def test_smooth_circular_is_the_moving_average_of_a_sine(n, k, freq):
    """Averaging sin(f x) over 2k+1 samples h apart scales it by sin((2k+1) f h/2) / ((2k+1) sin(f h/2))."""
    h = 2 * np.pi / n
    x = np.arange(n) * h
    gain = math.sin((2 * k + 1) * freq * h / 2) / ((2 * k + 1) * math.sin(freq * h / 2))
    np.testing.assert_allclose(smooth_circular(np.sin(freq * x), k), gain * np.sin(freq * x), atol=1e-12)
    np.testing.assert_allclose(smooth_circular(np.full(n, 2.5), k), 2.5)


def test_smooth_circular_edge_cases():
    v = np.array([1.0, 5.0, 2.0, 8.0, 4.0])
    out = smooth_circular(v, 0)
    assert out.tolist() == v.tolist() and out is not v
    assert smooth_circular(v, -3).tolist() == v.tolist()
    assert smooth_circular(np.zeros(0), 2).size == 0
    np.testing.assert_allclose(smooth_circular(v, 50), np.full(5, v.mean()))  # capped at the whole circle
    np.testing.assert_allclose(smooth_circular(v, 1), [(4 + 1 + 5) / 3, 8 / 3, 5, 14 / 3, 13 / 3])


def test_config_validation_messages():
    with pytest.raises(ValueError, match="cell_size_m"):
        MonitorConfig(cell_size_m=0.0, speed_mps=1.0)
    with pytest.raises(ValueError, match="speed_mps"):
        MonitorConfig(cell_size_m=1.0, speed_mps=-1.0)
    with pytest.raises(ValueError, match="alpha"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, alpha=-0.5)
    with pytest.raises(ValueError, match="both"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, center_y_m=0.0)
    for kw in (
        {"min_run_cells": -1},
        {"min_run_fraction": 1.5},
        {"min_run_fraction": -0.1},
        {"turn_margin": -1.0},
    ):
        with pytest.raises(ValueError, match="min_run_cells must be >= 0"):
            MonitorConfig(cell_size_m=1.0, speed_mps=1.0, **kw)
    with pytest.raises(ValueError, match="revisit_gap_s"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, revisit_gap_s=-1.0)
    ok = MonitorConfig(cell_size_m=1.0, speed_mps=1.0, alpha=0.0, min_run_fraction=1.0, revisit_gap_s=0.0)
    assert ok.gap_s == 0.0
    # the default same-visit window: the time to fly 10 cells
    assert MonitorConfig(cell_size_m=30.0, speed_mps=10.0).gap_s == pytest.approx(30.0)


def test_config_bounds_of_the_relay_the_reach_and_the_front_are_inclusive():
    """Each bound of MonitorConfig's docs at its edge is valid (a 0 s relay period, a 0 m reach,
    no front smoothing, fractions of 0 and 1), and past it named with the message whole."""
    for kw in (
        {"relay_head_period_s": 0.0, "relay_fast_fraction": 0.0},
        {"relay_fast_fraction": 1.0},
        {"reach_m": 0.0},
        {"front_smooth_bins": 0, "front_ros_fraction": 0.0},
        {"front_ros_fraction": 1.0},
    ):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, **kw)
    relay = "relay_head_period_s must be >= 0 and relay_fast_fraction in [0, 1]; got "
    front = "front_smooth_bins must be >= 0 and front_ros_fraction in [0, 1]; got "
    for kw, message in (
        ({"relay_head_period_s": -0.5}, relay + "-0.5, 0.5"),
        ({"relay_fast_fraction": 1.5}, relay + "3.5, 1.5"),
        ({"reach_m": -1.0}, "reach_m must be >= 0 or None, got -1.0"),
        ({"front_smooth_bins": -1}, front + "-1, 0.8"),
        ({"front_ros_fraction": -0.5}, front + "5, -0.5"),
        ({"rule": "x"}, "rule must be 'worst' or 'windows', got 'x'"),
        ({"split": "x"}, "split must be 'spread', 'angle' or 'relay', got 'x'"),
    ):
        with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
            MonitorConfig(cell_size_m=1.0, speed_mps=1.0, **kw)


@pytest.fixture(scope="module")
def disc():
    """A circular fire of constant ROS 0.05 m/s from (600, 600) m at t = 0 (40 x 40 cells of 30 m)."""
    return star_fire((40, 40), C, (20, 20), lambda th: np.full_like(th, 0.05))


def _config(fire, **kw):
    cx, cy = fire.ignition_xy_m
    return MonitorConfig(
        cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy, ignition_time_s=0.0, **kw
    )


def _lap(fire, monitor, t0=6000.0, minutes=12.0):
    return fly(
        fire,
        monitor,
        start_angle_rad=0.3,
        t_start_s=t0,
        t_end_s=t0 + 60.0 * minutes,
        speed_mps=SPEED,
        sensor_range_m=1.5 * C,
    )


def test_initial_lap_about_a_known_centre_ends_after_one_turn(disc):
    m = CirclingMonitor(_config(disc, ros_baseline_s=1e6))  # Eq. 1 always from the ignition point
    with pytest.raises(RuntimeError, match="before any update"):
        m.next_waypoint()
    tr = _lap(disc, m)
    assert m.initial_lap_done
    cx, cy = disc.ignition_xy_m
    ang = np.unwrap(np.arctan2(np.array(tr.y_m) - cy, np.array(tr.x_m) - cx))
    done_at = int(np.argmax(np.abs(ang - ang[0]) >= 2 * np.pi))
    assert done_at > 0  # one full CCW turn was flown ...
    assert np.all(np.diff(ang) > -0.2)  # ... counter-clockwise
    # every bin known; Eq. 1 ROS from the ignition point: 0.05 m/s within a cell over >= 6000 s
    assert m.fire_map.known.all()
    ros = m.fire_map.ros_mps()
    assert np.nanmax(np.abs(ros - 0.05)) < C / 6000.0
    # PM VI-E: the hull of the perimeter cells' squares reaches the fire's edge (radius ~0.05 t)
    hull_r = polygon_radial_extent(m.hull_m(), cx, cy, 72)
    t_last = tr.t_s[-1]
    assert np.all(hull_r > 0.05 * 6000.0 - C) and np.all(hull_r < 0.05 * t_last + 2 * C)
    front = m.front()  # uniform spread: every bin is fast, the head is the farthest outer cell
    assert front is not None and abs(front[2] - 0.05) < C / 6000.0
    k = int(np.nanargmax(m.fire_map.outer_d_m))
    assert front[:2] == (m.fire_map.outer_x_m[k], m.fire_map.outer_y_m[k])


def test_waypoints_follow_the_perimeter_and_lookahead(disc):
    m = CirclingMonitor(_config(disc, initial_direction=Direction.CW))
    t = 6000.0
    cell = disc.boundary_cell_at_angle(1.0, t)
    x, y = (float(v) for v in disc.grid.center(*cell))
    m.update(np.zeros((0, 3)), (x, y), t)  # nothing seen yet: stay put
    assert m.next_waypoint() == (x, y) and m.lookahead_waypoint(5) == (x, y)
    m.update(disc.observe(x, y, 3 * C, t), (x, y), t)
    w1 = m.next_waypoint()
    assert math.hypot(w1[0] - x, w1[1] - y) <= math.sqrt(2) * C + 1e-9
    assert m.lookahead_waypoint(1) == w1
    w4 = m.lookahead_waypoint(4)
    d4 = math.hypot(w4[0] - x, w4[1] - y)
    assert 2 * C <= d4 <= 4 * math.sqrt(2) * C
    cx, cy = disc.ignition_xy_m
    a0, a4 = math.atan2(y - cy, x - cx), math.atan2(w4[1] - cy, w4[0] - cx)
    assert (a4 - a0 + math.pi) % (2 * math.pi) - math.pi < 0  # CW: the angle decreases
    assert m.front() is not None  # centre known: the front is known before the initial lap ends
    blind = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED))
    blind.update(disc.observe(x, y, 3 * C, t), (x, y), t)
    assert blind.front() is None  # centre unknown and the initial lap not done


def test_off_the_perimeter_the_uav_steps_back_towards_it(disc):
    t = 6000.0
    cx, cy = disc.ignition_xy_m
    burning_r = 0.05 * t  # 300 m
    for r, inside in ((burning_r - 4 * C, True), (burning_r + 5 * C, False)):
        # search radius 0: the footprint's edge (unseen = outside) is not taken for the perimeter
        m = CirclingMonitor(_config(disc, search_radius_cells=0))
        x, y = cx + r, cy
        m.update(disc.observe(x, y, 1.5 * C, t), (x, y), t)
        wx, wy = m.next_waypoint()
        assert math.hypot(wx - x, wy - y) == pytest.approx(C)
        assert (math.hypot(wx - cx, wy - cy) > r) == inside  # out of the fire, or towards it


def _summary_with_recent_arc(n=360, centre=(0.0, 0.0), arc_deg=(80, 100)):
    d = np.full(n, 500.0)
    tv = np.full(n, 100.0)
    tv[arc_deg[0] : arc_deg[1]] = 900.0  # the peer was last here
    return {"center_x_m": centre[0], "center_y_m": centre[1], "outer_distance_m": d, "outer_visit_time_s": tv}


def test_merge_locates_the_peer_and_splits_the_perimeter_at_the_bisectors():
    m = ImportanceMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    assert m.merge(_summary_with_recent_arc(), peer_id=7) == 360
    peer = m._peers[7]
    assert peer.angle_rad == pytest.approx(math.radians(90.0), abs=math.radians(1.0))
    assert peer.heard_s == 900.0  # no t_s: the newest visit time
    m.uav_xy, m.t_s = (-500.0, 0.0), 950.0  # we are at 180 degrees
    th = np.radians(np.arange(0.5, 360.0, 1.0))
    cells = 500.0 * np.column_stack([np.cos(th), np.sin(th)])
    w = m._peer_weight(cells)
    deg = np.degrees(th)
    mine = (deg > 135) & (deg < 315)  # nearer (in angle) to 180 than to 90
    assert w.tolist() == mine.astype(float).tolist()
    m.t_s = 900.0 + m.config.peer_timeout_s + 1.0  # peer silent too long: everything is ours again
    assert m._peer_weight(cells) is None
    m.t_s = 900.0 + m.config.peer_timeout_s
    assert m._peer_weight(cells) is not None


def test_merge_with_a_known_peer_position_and_time():
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=100.0, center_y_m=100.0))
    m.merge(_summary_with_recent_arc(centre=(100.0, 100.0)), peer_id=2, peer_pos_m=(100.0, -300.0), t_s=42.0)
    assert m._peers[2].angle_rad == pytest.approx(-math.pi / 2) and m._peers[2].heard_s == 42.0
    no_times = _summary_with_recent_arc()
    no_times["outer_visit_time_s"] = np.full(360, np.nan)
    n = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    assert n.merge(no_times, peer_id=3) == 0 and 3 not in n._peers  # nowhere to place the peer


def test_two_peers_at_our_angle_split_by_id():
    """Same place: the lower id keeps the arc ahead (CCW: larger angles), the higher id the arc behind."""
    th = np.radians(np.arange(0.5, 360.0, 1.0))
    cells = 500.0 * np.column_stack([np.cos(th), np.sin(th)])
    deg = np.degrees(th)
    for me, peer, ahead in ((0, 1, True), (1, 0, False)):
        m = ImportanceMonitor(
            MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0, uav_id=me)
        )
        m.merge(_summary_with_recent_arc(), peer_id=peer, peer_pos_m=(0.0, 500.0), t_s=900.0)
        m.uav_xy, m.t_s = (0.0, 500.0), 900.0
        w = m._peer_weight(cells)
        inner, outer = (deg > 92) & (deg < 268), (deg < 88) | (deg > 272)
        assert np.all(w[inner] == float(ahead)) and np.all(w[outer] == float(not ahead)), me


def test_merge_errors_are_one_line_and_named():
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    good = _summary_with_recent_arc()
    with pytest.raises(ValueError, match="lacks a PerimeterMap field"):
        m.merge({k: v for k, v in good.items() if k != "outer_visit_time_s"})
    with pytest.raises(ValueError, match="lacks a PerimeterMap field"):
        m.merge({**good, "center_x_m": None})
    with pytest.raises(ValueError, match=">= 8 bins"):
        m.merge({**good, "outer_distance_m": good["outer_distance_m"][:10]})
    with pytest.raises(ValueError, match=">= 8 bins"):
        m.merge({**good, "outer_distance_m": np.ones(7), "outer_visit_time_s": np.ones(7)})
    with pytest.raises(ValueError, match="centre is not finite"):
        m.merge({**good, "center_y_m": math.inf})
    with pytest.raises(ValueError, match="non-finite UAV position"):
        m.update(np.zeros((0, 3)), (math.nan, 0.0), 1.0)
    assert m.merge({**good, "outer_distance_m": np.ones(8), "outer_visit_time_s": np.ones(8)}) == 8


def test_summary_importance_is_the_max_per_bin(disc):
    m = ImportanceMonitor(_config(disc))
    _lap(disc, m, minutes=14.0)
    s = m.to_summary()
    assert m.last_window is not None
    b = m.fire_map.bin_of(m.last_cells_m[:, 0], m.last_cells_m[:, 1])
    imp = s["importance"]
    for k in np.unique(b):
        assert imp[k] == pytest.approx(np.float32(m.last_window.importance[b == k].max()))
    assert np.isnan(imp[np.setdiff1d(np.arange(360), b)]).all()
    assert s["center_x_m"] == disc.ignition_xy_m[0] and s["direction"] == int(m.direction)
    np.testing.assert_array_equal(s["spread_rate_mps"], m.fire_map.ros_mps().astype(np.float32))


def _head_fire_map(m, spike_bin=None):
    """Record on ``m``'s map an egg-shaped fire about the centre, spreading at ``4 m/s`` towards
    45 deg and 1 m/s backwards (``v(a) = 2.5 + 1.5 cos(a - 45 deg)``), seen whole at 10 s and at
    50 s. ``spike_bin``: at 10 s that bin's ray was seen only where it crosses a notch at 30 % of
    its extent (an inner crossing), so its Eq. 1 rate is 1.175 v(a) there."""
    fm = m.fire_map
    th = fm.bin_center_rad()
    v = 2.5 + 1.5 * np.cos(th - math.radians(45.0))
    for t in (10.0, 50.0):
        r = v * t
        if t == 10.0 and spike_bin is not None:
            r = r.copy()
            r[spike_bin] *= 0.3
        fm.record(fm.center_x_m + r * np.cos(th), fm.center_y_m + r * np.sin(th), t)
    return v


def test_front_is_the_head_not_a_flank_bin_with_a_spread_rate_spike():
    """The head of the fire is at 45 deg, 200 m out at 50 s. A flank bin at 15 deg whose earlier
    sighting was an inner crossing has an Eq. 1 rate of 4.1 m/s, above the head's true 4 m/s:
    the single fastest bin (the old rule) is that flank, 100 m from the head; the front must be
    within a cell of the head."""
    m = ImportanceMonitor(
        MonitorConfig(cell_size_m=5.0, speed_mps=50.0, center_x_m=0.0, center_y_m=0.0, ros_baseline_s=30.0)
    )
    _head_fire_map(m, spike_bin=15)
    ros = m.fire_map.ros_mps()
    assert int(np.nanargmax(ros)) == 15 and ros[15] > 4.0  # the spike outruns the head
    front = m.front()
    assert front is not None
    head = (200.0 * math.cos(math.radians(45.0)), 200.0 * math.sin(math.radians(45.0)))
    assert math.hypot(front[0] - head[0], front[1] - head[1]) <= 5.0
    assert front[2] == pytest.approx(4.0, abs=0.1)


def test_front_ignores_a_far_bin_that_stopped_spreading():
    """A head put out (its bins seen again, unchanged, 40 s later) is still the farthest part
    of the map but no longer the front: the farthest bin that still spreads is."""
    m = ImportanceMonitor(
        MonitorConfig(cell_size_m=5.0, speed_mps=50.0, center_x_m=0.0, center_y_m=0.0, ros_baseline_s=30.0)
    )
    fm = m.fire_map
    _head_fire_map(m)
    th = fm.bin_center_rad()
    head = np.abs((th - math.radians(45.0) + np.pi) % (2 * np.pi) - np.pi) < math.radians(45.0)
    r = fm.outer_d_m + np.where(head, 1e-6, 0.25 * 40.0)  # the rest creeps on at 0.25 m/s
    fm.record(r * np.cos(th), r * np.sin(th), 90.0)
    assert head[int(np.argmax(fm.outer_d_m))]  # the dead head is the farthest
    front = m.front()
    assert front is not None
    k = int(fm.bin_of(np.array([front[0]]), np.array([front[1]]))[0])
    assert not head[k] and fm.ros_mps()[k] == pytest.approx(0.25)


def test_front_config_validation():
    with pytest.raises(ValueError, match="front_ros_fraction"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, front_ros_fraction=1.5)
    with pytest.raises(ValueError, match="front_smooth_bins"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, front_smooth_bins=-1)
