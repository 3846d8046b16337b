"""Monitors on a synthetic raster fire: circling coverage, alpha trend (PM VI-B), peers, summary."""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import Direction
from fire_perimeter_monitor.planner import CirclingMonitor, ImportanceMonitor, MonitorConfig
from fire_perimeter_monitor.synthetic_fire import fly, linear_ros, star_fire

C = 30.0
SPEED = 10.0


@pytest.fixture(scope="module")
def fire():
    """PM V-A representative scenario: ROS linear in angle, r_min east, r_max = 10 r_min west."""
    return star_fire((120, 120), C, (60, 60), linear_ros(0.02, 0.2, 0.0))


def _config(fire, rule="windows", **kw):
    cx, cy = fire.ignition_xy_m
    return MonitorConfig(
        cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy, ignition_time_s=0.0, rule=rule, **kw
    )


def _fly(fire, monitor, hours=1.0):
    return fly(
        fire,
        monitor,
        start_angle_rad=0.5,
        t_start_s=3600.0,
        t_end_s=3600.0 * (1 + hours),
        speed_mps=SPEED,
        sensor_range_m=1.5 * C,
    )


def test_config_validation():
    with pytest.raises(ValueError, match="speed_mps"):
        MonitorConfig(cell_size_m=1.0, speed_mps=0.0)
    with pytest.raises(ValueError, match="alpha"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, alpha=-1.0)
    with pytest.raises(ValueError, match="both"):
        MonitorConfig(cell_size_m=1.0, speed_mps=1.0, center_x_m=0.0)


def test_circling_visits_every_bin_and_never_turns(fire):
    m = CirclingMonitor(_config(fire))
    tr = _fly(fire, m, hours=0.5)
    assert m.initial_lap_done and m.direction_changes == 0 and set(tr.direction) == {0}
    assert m.fire_map.known.all()  # every one of the 360 bins has an outer cell
    ang = np.unwrap(
        np.arctan2(np.array(tr.y_m) - fire.ignition_xy_m[1], np.array(tr.x_m) - fire.ignition_xy_m[0])
    )
    assert ang[-1] - ang[0] > 2 * np.pi  # CCW: angle increases


@pytest.mark.slow  # ~17 s: six whole monitoring runs (the planner's unit tests are in test_planner_unit.py)
def test_direction_changes_increase_with_alpha(fire):
    """PM VI-B / Fig. 11: 0, 8, 11, 15, 20, 43 changes for these alphas; we check the trend."""
    changes = []
    for alpha in (0.0, 0.8, 1.0, 1.2, 1.5, 5.0):
        m = ImportanceMonitor(_config(fire, alpha=alpha))
        _fly(fire, m, hours=1.5)
        changes.append(m.direction_changes)
    assert changes[0] == 0
    assert changes == sorted(changes), changes
    assert changes[-1] > changes[0]


@pytest.mark.parametrize("rule", ["windows", "worst"])
def test_importance_monitor_turns_back_towards_the_active_side(fire, rule):
    m = ImportanceMonitor(_config(fire, rule=rule, alpha=1.0))
    tr = _fly(fire, m, hours=1.0)
    assert m.direction_changes > 0
    ang = np.degrees(
        np.arctan2(np.array(tr.y_m) - fire.ignition_xy_m[1], np.array(tr.x_m) - fire.ignition_xy_m[0])
    )
    turns = np.flatnonzero(np.diff(tr.direction) != 0)
    # turns happen on the fast (west, r_max at 180 deg) half, not near r_min (0 deg); the
    # worst-angle rule sweeps that half and turns at its ends, the flanks (85-95 deg)
    assert np.all(np.abs(ang[turns]) > (90 if rule == "windows" else 80)), ang[turns]


def test_summary_fields_and_merge(fire):
    a = ImportanceMonitor(_config(fire))
    _fly(fire, a, hours=0.5)
    s = a.to_summary()
    for key in ("outer_distance_m", "outer_visit_time_s", "spread_rate_mps", "importance"):
        assert s[key].dtype == np.float32 and s[key].shape == (360,)
    assert s["direction"] in (0, 1) and s["direction_changes"] == a.direction_changes
    b = ImportanceMonitor(_config(fire))
    taken = b.merge(s, peer_id=1, t_s=5400.0)
    assert taken == 360
    assert np.allclose(b.fire_map.outer_d_m, s["outer_distance_m"], atol=0.1)
    with pytest.raises(ValueError, match="PerimeterMap field"):
        b.merge({"center_x_m": 0.0})


def test_two_monitors_split_the_perimeter(fire):
    """Two monitors deployed at the same place end up flying apart (opposite directions)."""
    m1, m2 = (
        ImportanceMonitor(_config(fire, alpha=1.0, uav_id=0)),
        ImportanceMonitor(_config(fire, alpha=1.0, uav_id=1)),
    )
    cell = fire.boundary_cell_at_angle(0.5, 3600.0)
    pos = [tuple(float(v) for v in fire.grid.center(*cell))] * 2
    t = 3600.0
    while not (m1.initial_lap_done and m2.initial_lap_done):
        for k, m in enumerate((m1, m2)):
            m.update(fire.observe(*pos[k], 1.5 * C, t), pos[k], t)
            pos[k] = m.next_waypoint()
        t += C / SPEED
    opposite = []
    for _ in range(40):
        for k, (m, peer) in enumerate(((m1, m2), (m2, m1))):
            m.merge(peer.to_summary(), peer_id=1 - k, peer_pos_m=pos[1 - k], t_s=t)
            m.update(fire.observe(*pos[k], 1.5 * C, t), pos[k], t)
            pos[k] = m.next_waypoint()
        t += C / SPEED
        opposite.append(m1.direction != m2.direction)
    assert all(opposite[:10])  # they part at once; later each may turn on its own arc
    a1 = math.atan2(pos[0][1] - fire.ignition_xy_m[1], pos[0][0] - fire.ignition_xy_m[0])
    a2 = math.atan2(pos[1][1] - fire.ignition_xy_m[1], pos[1][0] - fire.ignition_xy_m[0])
    assert abs((a1 - a2 + math.pi) % (2 * math.pi) - math.pi) > math.radians(20)


def test_unknown_centre_is_estimated_after_initial_lap(fire):
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, initial_direction=Direction.CW))
    _fly(fire, m, hours=0.5)
    assert m.initial_lap_done
    # the centre of a fire spreading 10x faster west lies west of the ignition point
    assert m.fire_map.center_x_m < fire.ignition_xy_m[0]
    assert abs(m.fire_map.center_y_m - fire.ignition_xy_m[1]) < 3 * C


def test_worst_angle_rule_turns_less_at_alpha_zero(fire):
    """alpha = 0 makes every cell's ROS alike (Eq. 7): the worst-angle rule then turns only
    for a cell left staler than circling would leave it, far less often than at alpha = 1."""
    changes = []
    for alpha in (0.0, 1.0):
        m = ImportanceMonitor(_config(fire, rule="worst", alpha=alpha))
        _fly(fire, m, hours=0.5)
        assert m.initial_lap_done
        changes.append(m.direction_changes)
    assert changes[0] <= 2 < changes[1], changes


def test_unknown_centre_lap_ends_when_the_fire_grows_over_the_start():
    """The lap ends by the heading's full turn, not by a return to the start position: on a
    fast fire the start is soon inside the burned area and the UAV never gets back to it."""
    fast = star_fire((120, 120), C, (60, 60), linear_ros(0.5, 2.0, 0.0))
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED))
    fly(fast, m, start_angle_rad=0.5, t_start_s=300.0, t_end_s=900.0, speed_mps=SPEED, sensor_range_m=1.5 * C)
    assert m.initial_lap_done and m.center_known


def test_reach_is_the_sensor_footprint_radius(fire):
    """Without a configured reach the monitor takes the radius of what it sees: within one
    cell's half-diagonal of the sensor range the fly driver uses (cell centres inside it)."""
    for cells in (1.5, 4.0):
        m = ImportanceMonitor(_config(fire, rule="worst"))
        fly(fire, m, start_angle_rad=0.5, t_start_s=3600.0, t_end_s=3700.0, speed_mps=SPEED,
            sensor_range_m=cells * C)  # fmt: skip
        assert cells * C - C / math.sqrt(2) <= m.reach_m <= cells * C
    assert ImportanceMonitor(_config(fire, rule="worst", reach_m=12.0)).reach_m == 12.0


def test_a_monitor_that_sees_the_whole_fire_never_turns():
    """A footprint larger than the fire refreshes every bin at every sample, so the map is
    current whatever the UAV does and turning gains nothing (the uneven spread, 10:1, would
    otherwise pull the UAV back towards the fast side)."""
    small = star_fire((60, 60), C, (30, 30), linear_ros(0.02, 0.2, 0.0))
    m = ImportanceMonitor(_config(small, rule="worst", min_run_fraction=0.0))
    fly(small, m, start_angle_rad=0.5, t_start_s=1800.0, t_end_s=3600.0, speed_mps=SPEED,
        sensor_range_m=60 * C)  # fmt: skip
    assert m.initial_lap_done
    assert m.direction_changes == 0
