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


# --- merge, look-ahead and radial step edges (session 25: the mutation survivors) ---------------


def _bins(n=360):
    """Bin centres [rad] of a PerimeterMap of ``n`` bins (the message doc: bin k about (k + 0.5) 2 pi / n)."""
    return (np.arange(n) + 0.5) * (2 * np.pi / n)


def _mean_angle(deg_lo, deg_hi, n=360):
    """Angle [rad] of the mean of the unit vectors of bins deg_lo .. deg_hi - 1 (a circle about the centre)."""
    th = _bins(n)[deg_lo:deg_hi]
    return math.atan2(float(np.mean(np.sin(th))), float(np.mean(np.cos(th))))


def test_the_peer_is_placed_at_its_recent_arc_about_an_off_origin_centre():
    """Without a position the peer sits at the mean of its bins seen within one cell of flight
    (cell / speed = 3 s) of its newest visit: a bin exactly 3 s older counts, one 100 s older does
    not, nor a recent bin without a distance. The centre is off the origin on both axes and the
    arc off both axes (10-30 deg: a mirrored x or y would move it)."""
    centre = (100.0, -50.0)
    m = ImportanceMonitor(
        MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=centre[0], center_y_m=centre[1])
    )
    s = _summary_with_recent_arc(centre=centre, arc_deg=(10, 20))
    s["outer_visit_time_s"][20:30] = 900.0 - C / SPEED  # exactly one cell of flight older: recent
    s["outer_visit_time_s"][200:220] = 800.0  # within 300 s (cell x speed) but not 3 s: old
    s["outer_distance_m"][120] = np.nan
    s["outer_visit_time_s"][120] = 900.0  # the newest visit, but no distance: not placed
    m.merge(s, peer_id=4)
    assert m._peers[4].angle_rad == pytest.approx(_mean_angle(10, 30), abs=1e-12)
    assert m._peers[4].heard_s == 900.0


def test_a_float32_summary_places_the_peer_as_its_values_do():
    """PerimeterMap carries float32: the recent window is judged on the times' values. With a
    7 m cell at 10 m/s (0.7 s of flight) a bin at float32(999.3) = 999.29999 s is 0.70001 s older
    than the newest (1000 s): not recent, as in float64."""
    m = ImportanceMonitor(MonitorConfig(cell_size_m=7.0, speed_mps=10.0, center_x_m=0.0, center_y_m=0.0))
    s = _summary_with_recent_arc(arc_deg=(10, 20))
    s["outer_visit_time_s"][:] = 100.0
    s["outer_visit_time_s"][10:20] = 1000.0
    s["outer_visit_time_s"][60:70] = 999.3
    s32 = {**s, "outer_distance_m": s["outer_distance_m"].astype(np.float32)}
    s32["outer_visit_time_s"] = s["outer_visit_time_s"].astype(np.float32)
    assert float(s32["outer_visit_time_s"][60]) < 1000.0 - 0.7
    m.merge(s32, peer_id=1)
    assert m._peers[1].angle_rad == pytest.approx(_mean_angle(10, 20), abs=1e-12)


def test_a_peer_position_off_the_axes_of_an_off_origin_centre():
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=100.0, center_y_m=100.0))
    m.merge(_summary_with_recent_arc(centre=(100.0, 100.0)), peer_id=2, peer_pos_m=(400.0, 400.0), t_s=42.0)
    assert m._peers[2].angle_rad == pytest.approx(math.pi / 4, abs=1e-12)


def test_a_peer_without_visit_times_or_time_owns_no_arc():
    """A summary whose visit times are all unknown, merged without a time: the peer is placed by
    its position but never heard (heard at minus infinity), so it owns no arc, however late."""
    m = ImportanceMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    s = _summary_with_recent_arc()
    s["outer_visit_time_s"] = np.full(360, np.nan)
    assert m.merge(s, peer_id=5, peer_pos_m=(0.0, 500.0)) == 0
    assert 5 in m._peers
    m.uav_xy, m.t_s = (-500.0, 0.0), 1e9
    th = _bins()
    assert m._peer_weight(500.0 * np.column_stack([np.cos(th), np.sin(th)])) is None


def test_before_the_lap_without_a_centre_a_peer_map_waits_for_the_lap():
    """Centre unknown and the initial lap not done: nothing is merged into the map yet (0 bins
    taken); the peer's cells with a distance and a visit time wait, at their positions about the
    peer's centre (x = cx + d cos, y = cy + d sin of the bin centre), for the lap's centre and map."""
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED))
    s = _summary_with_recent_arc(centre=(100.0, -50.0))
    s["outer_distance_m"][3] = np.nan
    s["outer_visit_time_s"][7] = np.nan
    assert m.merge(s, peer_id=1) == 0
    assert not m.fire_map.known.any()
    keep = np.ones(360, dtype=bool)
    keep[[3, 7]] = False
    th = _bins()[keep]
    want = np.column_stack(
        [100.0 + 500.0 * np.cos(th), -50.0 + 500.0 * np.sin(th), s["outer_visit_time_s"][keep]]
    )
    np.testing.assert_allclose(m._lap.raw_cells(), want, rtol=0, atol=1e-9)


def test_the_lap_of_no_sighting_is_an_empty_n_by_3():
    from fire_perimeter_monitor.planner import _Lap

    raw = _Lap().raw_cells()
    assert raw.shape == (0, 3)


def test_merge_error_messages_are_whole():
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    with pytest.raises(ValueError, match=r"^peer summary centre is not finite$"):
        m.merge({**_summary_with_recent_arc(), "center_x_m": math.nan})


def _line_fire(n=7, origin=(100.0, 200.0)):
    """Observed cells: a one-cell-wide line of n burning cells i = 0 .. n-1 at j = 0 (cells of C
    from ``origin``), the cells above and below it unburned."""
    rows = []
    for i in range(n):
        rows.append((origin[0] + i * C, origin[1], 1))
    for i in range(n):
        for dj in (-1, 1):
            rows.append((origin[0] + i * C, origin[1] + dj * C, 0))
    return np.array(rows, dtype=float)


def test_lookahead_along_a_one_cell_wide_line_goes_round_its_end_and_stops_before_our_cell():
    """Moore tracing (boundary.py) round a line of cells 0..6, CCW, from cell 3 (first sample: no
    previous cell, so the first step is the sweep's first fire cell after an outside one, west):
    2, 1, 0, round the end to 1, 2, then our own cell 3 stops the walk. At each cell of the line
    both neighbours follow an outside cell; the one not back where we came from is taken."""
    cells = _line_fire()
    x0, y0 = 100.0, 200.0
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    m.update(cells, (x0 + 3 * C, y0), 10.0)
    got = [m.lookahead_waypoint(n) for n in range(1, 9)]
    want_i = [2, 1, 0, 1, 2, 2, 2, 2]
    assert got == [(x0 + i * C, y0) for i in want_i]


def test_the_radial_step_off_a_cell_off_the_grids_diagonal():
    """The grid is anchored at the first cell seen; a UAV 4 cells east and 1 north of it, inside
    a burning block with the centre to its south-west, steps one cell outwards (north-east: the
    rounded unit vector from the centre, (0.8, 0.6) -> (1, 1))."""
    x0, y0 = 0.0, 0.0
    block = [(x0, y0, 1)] + [(x0 + i * C, y0 + j * C, 1) for i in range(-3, 9) for j in range(-4, 6)]
    m = CirclingMonitor(
        MonitorConfig(
            cell_size_m=C,
            speed_mps=SPEED,
            center_x_m=4 * C - 80.0,
            center_y_m=C - 60.0,
            search_radius_cells=0,
        )
    )
    m.update(np.array(block, dtype=float), (4 * C, C), 10.0)
    assert m.cell == (4, 1)
    assert m.next_waypoint() == (5 * C, 2 * C)


# --- one planning step against Eqs. 3-7 written out (session 25) -------------------------------
#
# A map of 8 bins whose outer cells are the vertices of a regular octagon of radius 200 m about
# an off-origin centre (the bin centres), every one fresh (so the constructed perimeter is the
# octagon itself, PM IV-B with nothing to close), and the UAV on bin 0's vertex. With a cell of a
# third of the octagon's side the resampled perimeter is 24 cells: each vertex and the points a
# third and two thirds of the way to the next one, in the order of Eqs. 5-6 (index 0 the UAV,
# growing against the flying direction). A cell a third of the way from a vertex lies in that
# vertex's bin, two thirds in the next one's. Bin 4's Eq. 1 rate is unknown: interpolated
# halfway between its neighbours.

_NB, _R, _CENTRE = 8, 200.0, (100.0, -50.0)
_SIDE = 2 * _R * math.sin(math.pi / _NB)
_T = 1000.0


def _octagon_vertex(k):
    a = (k % _NB + 0.5) * 2 * math.pi / _NB
    return np.array([_CENTRE[0] + _R * math.cos(a), _CENTRE[1] + _R * math.sin(a)])


def _octagon_monitor(ros, t_outer, **kw):
    """An importance monitor whose map holds the octagon; bin k's Eq. 1 rate ``ros[k]`` (NaN:
    unknown) from an inner cell 100 s before its outer visit ``t_outer[k]``."""
    cfg = {
        "cell_size_m": _SIDE / 3,
        "speed_mps": 10.0,
        "center_x_m": _CENTRE[0],
        "center_y_m": _CENTRE[1],
        "bin_count": _NB,
        "revisit_gap_s": 1e4,  # every cell fresh
        "alpha": 2.0,
        "min_run_fraction": 0.0,
    }
    m = ImportanceMonitor(MonitorConfig(**(cfg | kw)))
    fm = m.fire_map
    for k in range(_NB):
        fm.outer_x_m[k], fm.outer_y_m[k] = _octagon_vertex(k)
        fm.outer_d_m[k], fm.outer_t_s[k] = _R, t_outer[k]
        if np.isfinite(ros[k]):
            fm.inner_t_s[k], fm.inner_d_m[k] = t_outer[k] - 100.0, _R - 100.0 * ros[k]
    m.uav_xy, m.t_s = tuple(_octagon_vertex(0)), _T
    return m


def _octagon_by_hand(ros, t_outer, ccw=True, alpha=2.0):
    """The 24 cells, their Eq. 7 rates (alpha) and times since the visit (Eq. 2, never < 0)."""
    back = -1 if ccw else 1  # against the flying direction
    cells, bins = [], []
    for k in range(_NB):
        a, b = _octagon_vertex(back * k), _octagon_vertex(back * (k + 1))
        cells += [a, a + (b - a) / 3, a + 2 * (b - a) / 3]
        bins += [(back * k) % _NB, (back * k) % _NB, (back * (k + 1)) % _NB]
    filled = np.array(ros, dtype=float)
    filled[4] = 0.5 * (filled[3] + filled[5])
    r = filled[bins]
    adj = (
        np.where(r <= r.mean(), r, r.min() + alpha * (r - r.min()))
        if alpha >= 1
        else r.min() + alpha * (r - r.min())
    )
    since = np.maximum(_T - np.asarray(t_outer)[bins], 0.0)
    return np.array(cells), adj, since


def _windows_by_hand(adj, since, weight=None, speed=10.0):
    """Eqs. 3-6: back cell i reached after i cells, front cell i after 24 - i; Eq. 4 per cell."""
    i = np.arange(24)
    t_to = np.where(i < 12, i, 24 - i) * (_SIDE / 3) / speed
    imp = adj * (since + t_to) * (1.0 if weight is None else weight)
    return imp


def _worst_turns_by_hand(adj, since, reach, keep_in_view=True, weight=None, speed=10.0, margin=0.0):
    """importance.worst_angle_turn's rule as its docstring writes it: flying on reaches cell i
    after (M - i) cells, turning back after i, each less the reach, and (keeping the footprint
    in view) less the time a cell behind stays in it; turn when the largest back value, times
    1 + margin, is under the largest on value."""
    sp = _SIDE / 3
    i = np.arange(24)
    d_on, d_back = (24 - i) * sp, i * sp
    keep = reach if keep_in_view else 0.0
    t_on = np.maximum(np.maximum(d_on - reach, 0) - np.maximum(keep - d_back, 0), 0) / speed
    t_back = np.maximum(np.maximum(d_back - reach, 0) - np.maximum(keep - d_on, 0), 0) / speed
    w = 1.0 if weight is None else weight
    return bool((1 + margin) * np.max(adj * (since + t_back) * w) < np.max(adj * (since + t_on) * w))


_ROS = [0.5, 1.0, 3.0, 0.2, np.nan, 0.8, 2.0, 0.4]
_T_OUTER = [1000.0, 990.0, 900.0, 950.0, 800.0, 999.5, 700.0, 980.0]


@pytest.mark.parametrize("direction", [Direction.CCW, Direction.CW])
def test_a_planning_step_weighs_the_windows_of_eqs_3_to_7(direction):
    """The cells, the per-cell importance (Eq. 4 with Eq. 7's alpha = 2 rates, the Eq. 2 time
    since the visit clamped at 0 for the UAV's own bin seen now, the Eq. 3 time to reach) and the
    Listing 3 decision, both flying directions."""
    m = _octagon_monitor(_ROS, _T_OUTER, rule="windows", initial_direction=direction)
    m._plan()
    cells, adj, since = _octagon_by_hand(_ROS, _T_OUTER, ccw=direction == Direction.CCW)
    np.testing.assert_allclose(m.last_cells_m, cells, rtol=0, atol=1e-9)
    imp = _windows_by_hand(adj, since)
    np.testing.assert_allclose(m.last_window.importance, imp, rtol=1e-12)
    assert m.last_window.imp_back == pytest.approx(imp[:12].sum(), rel=1e-12)
    turned = m.direction != direction
    assert turned == (imp[:12].sum() > imp[12:].sum()) and m.direction_changes == int(turned)


def test_no_known_rate_anywhere_weighs_nothing_and_keeps_the_direction():
    """Every bin seen once, with no ignition time: no Eq. 1 rate is known, so every cell's rate
    is 0 (nothing is known to spread) and the UAV flies on."""
    m = _octagon_monitor([np.nan] * _NB, _T_OUTER, rule="windows")
    m._plan()
    assert m.last_window is not None and np.all(m.last_window.importance == 0.0)
    assert m.direction == Direction.CCW and m.direction_changes == 0


def test_the_worst_angle_rule_decides_with_its_reach_kept_in_view():
    """Rates and visit times chosen (by search, once) so that the rules disagree: the worst-angle
    rule with an 80 m reach kept in view flies on, while Listing 3's windows, the worst-angle rule
    without the footprint kept in view, and its values over a wrong spacing would turn."""
    ros = [3.0, 0.4, 0.8, 0.5, np.nan, 0.2, 1.0, 2.0]
    t_outer = [999.5, 980.0, 1000.0, 950.0, 800.0, 700.0, 900.0, 990.0]
    cells, adj, since = _octagon_by_hand(ros, t_outer)
    imp = _windows_by_hand(adj, since)
    assert imp[:12].sum() > imp[12:].sum()  # the windows would turn
    assert _worst_turns_by_hand(adj, since, 80.0, keep_in_view=False)
    assert not _worst_turns_by_hand(adj, since, 80.0)
    m = _octagon_monitor(ros, t_outer, rule="worst", reach_m=80.0)
    m._plan()
    assert m.direction == Direction.CCW and m.direction_changes == 0
    w = _octagon_monitor(ros, t_outer, rule="windows", reach_m=80.0)
    w._plan()
    assert w.direction == Direction.CW


def test_after_a_turn_the_next_decision_waits_a_quarter_of_the_perimeter():
    """Hysteresis: min_run_fraction 0.25 of the 24 cells is 6; with a turn behind it the monitor
    keeps its direction at 5 cells flown and decides again at 6; before any turn it decides at
    once (the windows turn here)."""
    for changes, run, turns in ((1, 5, False), (1, 6, True), (0, 0, True)):
        m = _octagon_monitor(_ROS, _T_OUTER, rule="windows", min_run_fraction=0.25)
        m.direction_changes, m.run_cells = changes, run
        m._plan()
        assert (m.direction == Direction.CW) == turns, (changes, run)


def test_a_perimeter_of_three_vertices_is_planned_on_two_is_not():
    """The UAV and two known bins close a triangle, enough to weigh windows; one known bin is not."""
    for known, planned in ((2, True), (1, False)):
        ros = [0.5] * _NB
        t_outer = [_T - 10.0] * _NB
        m = _octagon_monitor(ros, t_outer, rule="windows")
        fm = m.fire_map
        for arr in (fm.outer_x_m, fm.outer_y_m, fm.outer_d_m, fm.outer_t_s, fm.inner_d_m, fm.inner_t_s):
            arr[1 + known :] = np.nan
            arr[0] = np.nan
        m._plan()
        assert (m.last_window is not None) == planned, known
        assert (m.last_cells_m is not None) == planned, known


def _angle_owned(cells, mine_deg, *peer_degs):
    """Cells nearer in angle about the octagon's centre to us than to every peer (the bisectors)."""
    ang = np.arctan2(cells[:, 1] - _CENTRE[1], cells[:, 0] - _CENTRE[0])

    def adist(a, b):
        return np.abs((a - b + np.pi) % (2 * np.pi) - np.pi)

    owned = np.ones(len(cells), dtype=bool)
    for p in peer_degs:
        owned &= adist(ang, math.radians(mine_deg)) < adist(ang, math.radians(p))
    return owned.astype(float)


def _with_peer_at(m, deg, peer_id=1):
    x, y = _CENTRE[0] + 300.0 * math.cos(math.radians(deg)), _CENTRE[1] + 300.0 * math.sin(math.radians(deg))
    s = _summary_with_recent_arc(n=_NB, centre=_CENTRE)
    m.merge(s, peer_id=peer_id, peer_pos_m=(x, y), t_s=_T - 1.0)


_ROS_1 = [3.0, 0.4, 0.8, 0.5, np.nan, 0.2, 1.0, 2.0]
_T_OUTER_1 = [999.5, 980.0, 1000.0, 950.0, 800.0, 700.0, 900.0, 990.0]


@pytest.mark.parametrize(
    "ros,t_outer,peer_deg,reach,turns",
    [
        # the peer's cells hold the worst value: counted, the UAV would turn
        (_ROS, _T_OUTER, 252.0, 0.0, False),
        # with a peer only the footprint ahead counts (keep_in_view off); kept in view it would fly on
        (_ROS_1, _T_OUTER_1, 190.0, 80.0, True),
    ],
)
def test_a_live_peers_arc_weighs_nothing_in_the_step(ros, t_outer, peer_deg, reach, turns):
    """The angle split: cells nearer in angle (about the off-origin centre) to the peer than to
    us weigh 0 in the windows and in the worst-angle rule, which then counts the reach ahead only.
    A peer at 190 deg is more than half a turn below us (22.5 deg) in atan2's range."""
    cells, adj, since = _octagon_by_hand(ros, t_outer)
    owned = _angle_owned(cells, 22.5, peer_deg)
    assert 0 < owned.sum() < 24
    weighted = _worst_turns_by_hand(adj, since, reach, keep_in_view=False, weight=owned)
    assert weighted == turns
    assert _worst_turns_by_hand(adj, since, reach, keep_in_view=False) != turns or (
        _worst_turns_by_hand(adj, since, reach, keep_in_view=True, weight=owned) != turns
    )
    m = _octagon_monitor(ros, t_outer, rule="worst", reach_m=reach)
    _with_peer_at(m, peer_deg)
    m._plan()
    np.testing.assert_allclose(m.last_window.importance, _windows_by_hand(adj, since, owned), rtol=1e-12)
    assert (m.direction == Direction.CW) == turns


def test_two_live_peers_each_take_their_side():
    cells, adj, since = _octagon_by_hand(_ROS, _T_OUTER)
    owned = _angle_owned(cells, 22.5, 140.0, 280.0)
    assert (
        owned.sum() < _angle_owned(cells, 22.5, 140.0).sum()
        and owned.sum() < _angle_owned(cells, 22.5, 280.0).sum()
    )
    m = _octagon_monitor(_ROS, _T_OUTER, rule="windows")
    _with_peer_at(m, 140.0, peer_id=1)
    _with_peer_at(m, 280.0, peer_id=2)
    m._plan()
    np.testing.assert_allclose(m.last_window.importance, _windows_by_hand(adj, since, owned), rtol=1e-12)


def test_the_worst_angle_rule_turns_by_its_margin():
    """Largest on value / largest back value = 1.0877 (a 20 m reach): the UAV turns with no
    margin, not with a margin of 0.5; and nothing known ties at 0, where it flies on."""
    ros = [0.8, 1.0, 3.0, 0.5, np.nan, 2.0, 0.2, 0.4]
    t_outer = [900.0, 950.0, 980.0, 1000.0, 800.0, 700.0, 990.0, 999.5]
    cells, adj, since = _octagon_by_hand(ros, t_outer)
    assert _worst_turns_by_hand(adj, since, 20.0) and not _worst_turns_by_hand(adj, since, 20.0, margin=0.5)
    for margin, turns in ((0.0, True), (0.5, False)):
        m = _octagon_monitor(ros, t_outer, rule="worst", reach_m=20.0, turn_margin=margin)
        m.prev_cell = (3, 4)
        m._plan()
        assert (m.direction == Direction.CW) == turns, margin
        # after a turn going back the way we came is intended: no previous cell to avoid
        assert (m.prev_cell is None) == turns
    m = _octagon_monitor([np.nan] * _NB, t_outer, rule="worst", reach_m=20.0)
    m._plan()
    assert m.direction == Direction.CCW


def test_a_window_tie_turns_only_when_asked():
    """Uniform spread; bin 7 (back cells 2-4) seen 4 cells of flight earlier than the rest, which
    makes up the front window's longer times to reach (Eq. 3: sum 78 against 66 cells): a tie,
    kept by default and turned with turn_on_tie (PM V-A's reading)."""
    sp = _SIDE / 3
    t_outer = [900.0] * _NB
    t_outer[7] = 900.0 - 4 * sp / 10.0
    cells, adj, since = _octagon_by_hand([1.0] * _NB, t_outer)
    imp = _windows_by_hand(adj, since)
    assert imp[:12].sum() == pytest.approx(imp[12:].sum(), rel=1e-12)
    for on_tie in (False, True):
        m = _octagon_monitor([1.0] * _NB, t_outer, rule="windows", turn_on_tie=on_tie)
        m._plan()
        assert (m.direction == Direction.CW) == on_tie


def test_the_summary_keeps_the_largest_importance_of_each_bin():
    """Bin 4 holds cells 11 (back, 11 cells away), 12 and 13 (front, 12 and 11 away): the
    largest, cell 12's, is the bin's, not the last one's."""
    m = _octagon_monitor(_ROS, _T_OUTER, rule="windows")
    m._plan()
    cells, adj, since = _octagon_by_hand(_ROS, _T_OUTER)
    imp = _windows_by_hand(adj, since)
    assert imp[12] > imp[13]
    got = m.to_summary()["importance"]
    assert got[4] == np.float32(imp[12])
    assert got[7] == np.float32(max(imp[2], imp[3], imp[4]))


def _front_map(ros, dist, **kw):
    """A monitor of 8 bins about (0, 0) whose bin k has its outer cell ``dist[k]`` m out on the
    bin's centre ray (NaN: bin unknown) and the Eq. 1 rate ``ros[k]`` (NaN: unknown)."""
    m = ImportanceMonitor(
        MonitorConfig(cell_size_m=5.0, speed_mps=10.0, center_x_m=0.0, center_y_m=0.0, bin_count=8, **kw)
    )
    fm = m.fire_map
    th = fm.bin_center_rad()
    for k in range(8):
        if np.isfinite(dist[k]):
            fm.outer_x_m[k], fm.outer_y_m[k] = dist[k] * math.cos(th[k]), dist[k] * math.sin(th[k])
            fm.outer_d_m[k], fm.outer_t_s[k] = dist[k], 500.0
            if np.isfinite(ros[k]):
                fm.inner_d_m[k], fm.inner_t_s[k] = dist[k] - 100.0 * ros[k], 400.0
    return m, th


_DIST = [100.0, 120.0, 150.0, 90.0, np.nan, 200.0, 110.0, 105.0]


def test_the_front_is_the_fastest_bin_when_the_fraction_is_one():
    """front_ros_fraction 1, no smoothing: only the fastest bin (2, 3 m/s) is fast, whatever the
    farther slower ones (bin 5, 200 m) and a known bin without a rate (3) or an unknown bin (4)."""
    m, th = _front_map(
        [1.0, 2.0, 3.0, np.nan, np.nan, 0.5, 1.0, 1.0], _DIST, front_smooth_bins=0, front_ros_fraction=1.0
    )
    x, y, top = m.front()
    assert (x, y) == pytest.approx((150.0 * math.cos(th[2]), 150.0 * math.sin(th[2])), abs=1e-9)
    assert top == pytest.approx(3.0)


def test_the_front_averages_unknown_rates_as_zero():
    """+-1 bin smoothing, fraction 0.9: bin 1's average is (1 + 1 + 3) / 3 = 5/3, the top;
    bin 2's is (1 + 3 + 0) / 3 = 4/3 (bin 3's unknown rate counts 0), under 0.9 x 5/3 = 1.5, so
    the front is bin 1's outer cell (120 m) and not the farther bin 2's."""
    m, th = _front_map(
        [1.0, 1.0, 3.0, np.nan, np.nan, 0.5, 1.0, 1.0], _DIST, front_smooth_bins=1, front_ros_fraction=0.9
    )
    x, y, top = m.front()
    assert (x, y) == pytest.approx((120.0 * math.cos(th[1]), 120.0 * math.sin(th[1])), abs=1e-9)
    assert top == pytest.approx(5.0 / 3.0)


def test_no_front_where_nothing_spreads():
    m, _ = _front_map([0.0] * 8, _DIST, front_smooth_bins=1)
    assert m.front() is None


def test_smooth_circular_averages_in_float64():
    """float32 rates (a PerimeterMap's) are averaged as their float64 values."""
    v = (np.sin(np.arange(50) * 0.37) * 3.7 + 5.0).astype(np.float32)
    ref = np.array(
        [np.mean(np.take(v.astype(float), np.arange(i - 3, i + 4), mode="wrap")) for i in range(50)]
    )
    np.testing.assert_allclose(smooth_circular(v, 3), ref, rtol=1e-13)
    assert smooth_circular(v, 0).dtype == np.float64


def test_next_waypoint_on_a_line_goes_on_away_from_where_it_came_from():
    """On a one-cell-wide line both neighbours follow an outside cell in the sweep; having come
    from cell 2 to cell 3 the UAV goes on to 4 (Moore tracing's neck rule, boundary.py)."""
    cells = _line_fire()
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    m.update(cells, (100.0 + 2 * C, 200.0), 10.0)
    m.update(cells, (100.0 + 3 * C, 200.0), 11.0)
    assert m.next_waypoint() == (100.0 + 4 * C, 200.0)


def test_off_the_perimeter_the_nearest_boundary_cell_within_the_search_radius():
    """Two cells north of the line's cell 3, nothing burns around the UAV: the nearest
    perimeter cell within 3 cells is cell 3 (two cells south), not a radial step."""
    cells = _line_fire()
    m = CirclingMonitor(
        MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=100.0 + 3 * C, center_y_m=900.0)
    )
    m.update(cells, (100.0 + 3 * C, 200.0 + 2 * C), 10.0)
    assert m.next_waypoint() == (100.0 + 3 * C, 200.0)


def test_the_lap_without_a_centre_ends_when_the_heading_has_turned_once():
    """Without a centre the lap ends when the heading, cell to cell, has turned by 2 pi: round a
    square of cells (east, north, west, south) it has turned 3 pi / 2 back at the start corner
    and 2 pi one cell east of it. The square lies away from the grid's anchor (the first cell
    seen), off its diagonal."""
    seen = np.array([[0.0, 0.0, 1.0], [C, 0.0, 0.0]])
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED))
    path = (
        [(i, 2) for i in range(10, 15)]
        + [(14, j) for j in range(3, 7)]
        + [(i, 6) for i in range(13, 9, -1)]
        + [(10, j) for j in range(5, 1, -1)]
    )
    for k, (i, j) in enumerate(path):
        m.update(seen, (i * C, j * C), float(k))
        assert not m.initial_lap_done, (i, j)
    m.update(seen, (11 * C, 2 * C), float(len(path)))
    assert m.initial_lap_done and m.center_known
    # the lap's sightings (the burning cell at the anchor, its unburned neighbour east) are
    # replayed into the map with their times
    t = m.fire_map.outer_t_s[m.fire_map.known]
    assert t.size and np.all(np.isin(t, np.arange(len(path) + 1.0)))


# --- the relay and spread splits through the monitor (session 25) ------------------------------
# The expected masks come from split.py's functions (tested by hand in test_split.py /
# test_relay_reference.py) fed with what the monitor's docs say it hands them: the peer's cell
# (the nearest to its angle; on our own cell: cell 1 for the lower id, M - 1 for the higher),
# the mean cell spacing (the closed perimeter's length / M), the head's half arc
# (reach + speed x relay_head_period_s / 2) and the tie going to the lower id.


def _ring_cells(m, first_step_deg=20.0, radius=300.0):
    """``m`` cells on a circle about the octagon's centre, cell 0 at angle 0, the first step
    ``first_step_deg`` and the others equal: an uneven spacing (one long chord)."""
    rest = (360.0 - first_step_deg) / (m - 1)
    ang = np.radians(np.concatenate([[0.0], first_step_deg + rest * np.arange(m - 1)]))
    # the index grows against the flying direction (CCW): angles decrease
    return np.column_stack([_CENTRE[0] + radius * np.cos(-ang), _CENTRE[1] + radius * np.sin(-ang)])


def _mean_spacing(cells):
    return float(np.mean(np.hypot(*(np.roll(cells, -1, axis=0) - cells).T)))


@pytest.mark.parametrize("me,peer,m,head", [(0, 1, 47, 24), (1, 0, 48, 23)])
def test_the_relay_with_a_peer_on_our_cell(me, peer, m, head):
    """A peer on our own cell stands on cell 1 (we are the lower id) or M - 1. With the head at
    24 of 47 cells the lower id ties with the peer on cell 1 (23 cells each way) and holds it;
    with the head at 23 of 48 the higher id is 23 cells from it, the peer on cell 47 is 24. The
    half arc is 2 spacings and 1 cm: cells 2 spacings from the head are in it."""
    from fire_perimeter_monitor.split import relay_split

    cells = _ring_cells(m)
    sp = _mean_spacing(cells)
    reach = 2 * sp + 0.01 - 10.0 * 3.5 / 2
    ros = np.full(m, 0.5)
    ros[head - 2 : head + 3] = [1.0, 2.0, 3.0, 2.0, 1.0]  # its +-2 cell average peaks at the head alone
    mon = ImportanceMonitor(
        MonitorConfig(
            cell_size_m=5.0,
            speed_mps=10.0,
            center_x_m=_CENTRE[0],
            center_y_m=_CENTRE[1],
            split="relay",
            relay_fast_fraction=0.0,
            reach_m=reach,
            uav_id=me,
        )
    )
    mon.merge(_summary_with_recent_arc(centre=_CENTRE), peer_id=peer, peer_pos_m=tuple(cells[0]), t_s=_T)
    mon.uav_xy, mon.t_s = tuple(cells[0]), _T
    got = mon._peer_weight(cells, ros)
    k = 1 if me < peer else m - 1
    want = relay_split(ros, sp, k, 2 * sp + 0.01, me < peer, 0.0).astype(float)
    np.testing.assert_array_equal(got, want)
    assert got[head] == 1.0 and got[head + 2] == 1.0 and got[head + 3] == 0.0  # we hold the head


@pytest.mark.parametrize("me,peer", [(0, 1), (1, 0)])
def test_the_spread_split_with_a_peer_on_our_cell(me, peer):
    from fire_perimeter_monitor.split import arc_work, work_bisector_split

    m = 40
    cells = _ring_cells(m)
    ros = np.linspace(0.2, 3.0, m)
    mon = ImportanceMonitor(
        MonitorConfig(
            cell_size_m=5.0,
            speed_mps=10.0,
            center_x_m=_CENTRE[0],
            center_y_m=_CENTRE[1],
            split="spread",
            uav_id=me,
        )
    )
    mon.merge(_summary_with_recent_arc(centre=_CENTRE), peer_id=peer, peer_pos_m=tuple(cells[0]), t_s=_T)
    mon.uav_xy, mon.t_s = tuple(cells[0]), _T
    k = 1 if me < peer else m - 1
    want = work_bisector_split(arc_work(ros, _mean_spacing(cells)), np.array([k])).astype(float)
    np.testing.assert_array_equal(mon._peer_weight(cells, ros), want)


@pytest.mark.parametrize("split", ["relay", "spread"])
def test_a_three_cell_perimeter_is_split_by_work(split):
    """Three cells (0, -60 and -210 deg about the centre, the peer by the last) are enough for
    the relay and the spread split, whose answers here differ from the angle split's."""
    from fire_perimeter_monitor.split import arc_work, relay_split, work_bisector_split

    ang = np.radians([0.0, -60.0, -210.0])
    cells = np.column_stack([_CENTRE[0] + 300.0 * np.cos(ang), _CENTRE[1] + 300.0 * np.sin(ang)])
    ros = np.array([5.0, 0.1, 0.1])
    mon = ImportanceMonitor(
        MonitorConfig(
            cell_size_m=5.0,
            speed_mps=10.0,
            center_x_m=_CENTRE[0],
            center_y_m=_CENTRE[1],
            split=split,
            relay_fast_fraction=0.0,
            reach_m=0.0,
            relay_head_period_s=0.0,
        )
    )
    a = math.radians(-205.0)
    peer_xy = (_CENTRE[0] + 300.0 * math.cos(a), _CENTRE[1] + 300.0 * math.sin(a))  # nearest cell 2
    mon.merge(_summary_with_recent_arc(centre=_CENTRE), peer_id=1, peer_pos_m=peer_xy, t_s=_T)
    mon.uav_xy, mon.t_s = tuple(cells[0]), _T
    sp = _mean_spacing(cells)
    if split == "relay":
        want = relay_split(ros, sp, 2, 0.0, True, 0.0)
    else:
        want = work_bisector_split(arc_work(ros, sp), np.array([2]))
    got = mon._peer_weight(cells, ros)
    np.testing.assert_array_equal(got, want.astype(float))
    angle = ImportanceMonitor(
        MonitorConfig(cell_size_m=5.0, speed_mps=10.0, center_x_m=_CENTRE[0], center_y_m=_CENTRE[1])
    )
    angle.merge(_summary_with_recent_arc(centre=_CENTRE), peer_id=1, peer_pos_m=peer_xy, t_s=_T)
    angle.uav_xy, angle.t_s = tuple(cells[0]), _T
    assert not np.array_equal(angle._peer_weight(cells, ros), got)


# --- the map the monitor keeps (session 25) -----------------------------------------------------


def test_the_maps_settings_come_from_the_config():
    """MonitorConfig's docs: Eq. 1 over at least ros_baseline_s (default 20 cells of flight) and
    ros_baseline_cells of spread; the map's cells of cell_size_m."""
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, ros_baseline_cells=3.5))
    assert (m.fire_map.ros_baseline_s, m.fire_map.ros_baseline_cells, m.fire_map.cell_size_m) == (
        20 * C / SPEED,
        3.5,
        C,
    )
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, ros_baseline_s=7.0))
    assert m.fire_map.ros_baseline_s == 7.0


def test_the_footprint_is_the_farthest_cell_seen_from_the_uav():
    """Off the origin on both axes: the farthest cell 3 east and 4 north of the UAV is 5 cells
    away; a UAV that sees only its own cell has a footprint of 0 m."""
    ux, uy = 400.0, -250.0
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    m.update(np.array([[ux, uy, 1.0], [ux + 3 * C, uy + 4 * C, 0.0], [ux - C, uy, 0.0]]), (ux, uy), 1.0)
    assert m.footprint_m == pytest.approx(5 * C) and m.reach_m == pytest.approx(5 * C)
    own = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    own.update(np.array([[ux, uy, 1.0]]), (ux, uy), 1.0)
    assert own.footprint_m == 0.0


@pytest.mark.parametrize("step,linked", [((1, 1), True), ((1, 2), False)])
def test_only_neighbouring_perimeter_cells_fill_the_bins_between_them(step, linked):
    """Far from the centre (3 km, 0.1 deg bins) two perimeter cells of one sighting skip bins;
    FireMap.record fills those between neighbouring cells (8-neighbours, sqrt 2 cells apart),
    not between cells a knight's move (sqrt 5 cells) apart."""
    m = CirclingMonitor(
        MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0, bin_count=3600)
    )
    a = (3000.0, 0.0)
    b = (a[0] + step[0] * C, a[1] + step[1] * C)
    seen = np.array(
        [[*a, 1.0], [a[0] + C, a[1] - C, 0.0], [a[0], a[1] - C, 0.0], [*b, 1.0], [b[0] + C, b[1], 0.0]]
    )
    m.update(seen, a, 5.0)
    ba, bb = (int(m.fire_map.bin_of(*p)) for p in (a, b))
    assert bb - ba >= 2
    known = np.flatnonzero(m.fire_map.known)
    assert known.tolist() == (list(range(ba, bb + 1)) if linked else [ba, bb])


def test_a_nearer_perimeter_is_taken_where_the_old_outer_cell_is_seen_unburned():
    """PM IV-A keeps the farthest cell; FireMap.record moves a bin's outer cell inwards only on
    evidence, the same sighting's unburned cell where the outer cell was: the monitor hands it."""
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=0.0, center_y_m=0.0))
    m.update(np.array([[3000.0, 0.0, 1.0], [3030.0, 0.0, 0.0]]), (3000.0, 0.0), 10.0)
    assert m.fire_map.outer_d_m[0] == 3000.0
    m.update(np.array([[2970.0, 0.0, 1.0], [3000.0, 0.0, 0.0], [3030.0, 0.0, 0.0]]), (2970.0, 0.0), 200.0)
    assert m.fire_map.outer_d_m[0] == 2970.0


def test_a_known_centre_lap_ends_on_the_heading_only_after_a_turn_and_a_quarter():
    """A known centre outside the loop (angles about it never go round): the square of the
    heading test ends its lap only when the heading has turned 5 pi / 2, at the fifth corner."""
    seen = np.array([[0.0, 0.0, 1.0], [C, 0.0, 0.0]])
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=-5000.0, center_y_m=-5000.0))
    path = (
        [(i, 2) for i in range(10, 15)]
        + [(14, j) for j in range(3, 7)]
        + [(i, 6) for i in range(13, 9, -1)]
        + [(10, j) for j in range(5, 1, -1)]
        + [(i, 2) for i in range(11, 15)]
    )
    for k, (i, j) in enumerate(path):
        m.update(seen, (i * C, j * C), float(k))
        assert not m.initial_lap_done, (i, j)
    m.update(seen, (14 * C, 3 * C), float(len(path)))
    assert m.initial_lap_done


def test_a_lap_without_a_centre_or_any_perimeter_centres_on_the_uav():
    """Nothing but burning cells seen (no perimeter cell): at the lap's end the map's centre is
    the UAV's position."""
    seen = np.array([[0.0, 0.0, 1.0]])
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED))
    path = (
        [(i, 2) for i in range(10, 15)]
        + [(14, j) for j in range(3, 7)]
        + [(i, 6) for i in range(13, 9, -1)]
        + [(10, j) for j in range(5, 1, -1)]
        + [(11, 2)]
    )
    for k, (i, j) in enumerate(path):
        m.update(seen, (i * C, j * C), float(k))
    assert m.initial_lap_done
    assert (m.fire_map.center_x_m, m.fire_map.center_y_m) == (11 * C, 2 * C)


@pytest.mark.parametrize("split", ["spread", "relay"])
def test_a_planning_step_splits_by_eq_7_work_with_the_spread_and_relay_splits(split):
    """Through a whole step: the spread and relay splits get Eq. 7's rates of the cells (alpha
    2), the peer's cell is the one nearest its angle, the spacing the mean chord (a third of the
    octagon's side) and the relay's half arc reach + speed x period / 2; their masks weigh the
    windows (and differ from the angle split's here)."""
    from fire_perimeter_monitor.split import arc_work, relay_split, work_bisector_split

    cells, adj, since = _octagon_by_hand(_ROS, _T_OUTER)
    ang = np.arctan2(cells[:, 1] - _CENTRE[1], cells[:, 0] - _CENTRE[0])
    k = int(np.argmin(np.abs((ang - math.radians(160.0) + np.pi) % (2 * np.pi) - np.pi)))
    sp = _SIDE / 3
    if split == "spread":
        owned = work_bisector_split(arc_work(adj, sp), np.array([k]))
    else:
        owned = relay_split(adj, sp, k, 30.0 + 10.0 * 3.5 / 2, True, 0.5)
    owned = owned.astype(float)
    assert not np.array_equal(owned, _angle_owned(cells, 22.5, 160.0))
    m = _octagon_monitor(_ROS, _T_OUTER, rule="windows", split=split, reach_m=30.0)
    _with_peer_at(m, 160.0)
    m._plan()
    np.testing.assert_allclose(m.last_window.importance, _windows_by_hand(adj, since, owned), rtol=1e-12)


def test_the_worst_angle_rule_weighs_eq_7s_alpha():
    """With alpha 2 the fast cells weigh more (Eq. 7) and the UAV flies on; with alpha 1 it
    would turn (a 40 m reach)."""
    ros = [0.8, 3.0, 1.0, 0.4, np.nan, 2.0, 0.2, 0.5]
    t_outer = [700.0, 1000.0, 900.0, 999.5, 980.0, 990.0, 800.0, 950.0]
    _, adj2, since = _octagon_by_hand(ros, t_outer, alpha=2.0)
    _, adj1, _ = _octagon_by_hand(ros, t_outer, alpha=1.0)
    assert not _worst_turns_by_hand(adj2, since, 40.0) and _worst_turns_by_hand(adj1, since, 40.0)
    m = _octagon_monitor(ros, t_outer, rule="worst", reach_m=40.0)
    m._plan()
    assert m.direction == Direction.CCW


def test_the_angle_split_about_a_centre_far_off_the_y_axis():
    """Centre (1000, 0), we at 180 deg (x = 500), the peer at 90 deg: ours are the cells nearer
    in angle to 180 than to 90 deg."""
    m = ImportanceMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=1000.0, center_y_m=0.0))
    m.merge(_summary_with_recent_arc(centre=(1000.0, 0.0)), peer_id=7, peer_pos_m=(1000.0, 500.0), t_s=900.0)
    m.uav_xy, m.t_s = (500.0, 0.0), 950.0
    th = np.radians(np.arange(0.5, 360.0, 1.0))
    cells = np.column_stack([1000.0 + 500.0 * np.cos(th), 500.0 * np.sin(th)])
    deg = np.degrees(th)
    assert m._peer_weight(cells).tolist() == ((deg > 135) & (deg < 315)).astype(float).tolist()
