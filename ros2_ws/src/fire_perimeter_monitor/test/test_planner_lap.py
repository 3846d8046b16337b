"""Fast tests of the monitors' initial lap (PM Listing 2), waypoints and summary, on a small disc fire.

References: the geometry of a circle (a lap is one full turn about the centre; the mean of a
circle's perimeter cells is its centre; a radial step from a point at a known angle), the
PerimeterMap message (field names, float32 arrays, bin count), and the consistency of the
look-ahead aim point with flying the next waypoints one by one.
"""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import Direction, as_cell_arrays
from fire_perimeter_monitor.planner import CirclingMonitor, ImportanceMonitor, MonitorConfig
from fire_perimeter_monitor.synthetic_fire import elliptical_ros, fly, star_fire

C = 30.0
SPEED = 10.0
T0 = 6000.0  # disc radius 0.05 m/s x 6000 s = 300 m


@pytest.fixture(scope="module")
def disc():
    """A circular fire of constant ROS 0.05 m/s from (600, 600) m at t = 0 (40 x 40 cells of 30 m)."""
    return star_fire((40, 40), C, (20, 20), lambda th: np.full_like(th, 0.05))


class _Recording(CirclingMonitor):
    """A circling monitor that notes, per update, whether the initial lap is done."""

    def __init__(self, config):
        super().__init__(config)
        self.done_per_update: list[bool] = []

    def update(self, observed_cells, uav_pos_m, t_s):
        d = super().update(observed_cells, uav_pos_m, t_s)
        self.done_per_update.append(self.initial_lap_done)
        return d


def _fly(fire, monitor, minutes, start=0.3):
    return fly(
        fire,
        monitor,
        start_angle_rad=start,
        t_start_s=T0,
        t_end_s=T0 + 60.0 * minutes,
        speed_mps=SPEED,
        sensor_range_m=1.5 * C,
    )


def _turns(fire, tr, upto):
    """Angle [rad] flown about the true centre over the first ``upto`` samples of a trace."""
    cx, cy = fire.ignition_xy_m
    a = np.unwrap(np.arctan2(np.array(tr.y_m[:upto]) - cy, np.array(tr.x_m[:upto]) - cx))
    return a[-1] - a[0]


def test_lap_about_a_known_centre_ends_at_one_full_turn(disc):
    """Listing 2 with the centre known: the lap is done at the first sample 2 pi from the start."""
    cx, cy = disc.ignition_xy_m
    m = _Recording(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy))
    tr = _fly(disc, m, 8.0)
    k = m.done_per_update.index(True)
    assert _turns(disc, tr, k + 1) >= 2 * math.pi  # CCW: positive
    assert _turns(disc, tr, k) < 2 * math.pi


def test_lap_without_a_centre_returns_to_the_start_and_finds_the_centre(disc):
    """Listing 2, centre unknown: back near the start after leaving it, the lap ends; the centre is
    the mean of the perimeter cells seen (a circle's centre, within a cell), and the map is then
    filled from the lap and kept up to date."""
    cx, cy = disc.ignition_xy_m
    m = _Recording(MonitorConfig(cell_size_m=C, speed_mps=SPEED, ignition_time_s=0.0))
    assert m.to_summary()["direction_changes"] == 0
    tr = _fly(disc, m, 7.0)
    assert m.initial_lap_done and m.center_known
    k = m.done_per_update.index(True)
    turned = _turns(disc, tr, k + 1)
    assert 2 * math.pi - 0.5 < turned < 2 * math.pi + 0.5  # one lap, ended near the start
    start = np.array([tr.x_m[0], tr.y_m[0]])
    end = np.array([tr.x_m[k], tr.y_m[k]])
    assert np.hypot(*(end - start)) <= 1.5 * C + 1e-9
    assert math.hypot(m.fire_map.center_x_m - cx, m.fire_map.center_y_m - cy) < C
    fm = m.fire_map
    assert fm.known.mean() > 0.9
    r = fm.outer_d_m[fm.known]
    assert np.all(np.abs(r - 0.05 * T0) < 0.05 * 60 * 7 + 2 * C)  # the disc's radius during the flight
    t_lap = tr.t_s[k]
    assert np.nanmax(fm.outer_t_s) > t_lap  # cells seen after the lap are recorded
    # one step per cell entered; a circling monitor never turns
    pts = np.column_stack([tr.x_m, tr.y_m])
    stays = int(np.all(pts[1:] == pts[:-1], axis=1).sum())
    assert m.steps == len(tr.t_s) - stays
    assert m.run_cells == m.steps
    s = m.to_summary()
    assert s["direction_changes"] == 0 and s["direction"] == int(Direction.CCW)


def test_a_lap_is_not_done_before_the_uav_left_the_start(disc):
    """Within a few cells of the deployment point nothing ends the lap (Listing 2 needs a return)."""
    m = _Recording(MonitorConfig(cell_size_m=C, speed_mps=SPEED, ignition_time_s=0.0))
    _fly(disc, m, 0.5)  # 300 m of flight: a sixth of the circumference
    assert not m.initial_lap_done and not m.center_known


def test_the_first_footprint_may_be_a_single_cell(disc):
    cx, cy = disc.ignition_xy_m
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy))
    cell = disc.boundary_cell_at_angle(1.0, T0)
    x, y = (float(v) for v in disc.grid.center(*cell))
    xs, ys, ss = as_cell_arrays(disc.observe(x, y, 3 * C, T0))
    m.update((xs[:1], ys[:1], ss[:1]), (x, y), T0)
    assert m.cell is not None and m.steps == 1
    m.update(disc.observe(x, y, 3 * C, T0), (x, y), T0)
    assert m.steps == 1  # same cell: no new step


def test_lookahead_is_where_the_next_waypoints_lead(disc):
    """The aim point n cells ahead (on the latest footprint) is the cell that n next_waypoint()
    steps reach when the footprint stays the same."""
    cx, cy = disc.ignition_xy_m
    for direction in (Direction.CCW, Direction.CW):
        cfg = MonitorConfig(
            cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy, initial_direction=direction
        )
        cell = disc.boundary_cell_at_angle(2.0, T0)
        x, y = (float(v) for v in disc.grid.center(*cell))
        seen = disc.observe(x, y, 8 * C, T0)
        aim = CirclingMonitor(cfg)
        aim.update(seen, (x, y), T0)
        ahead = {n: aim.lookahead_waypoint(n) for n in range(1, 6)}
        assert ahead[1] == aim.next_waypoint() and aim.lookahead_waypoint(0) == ahead[1]
        walker = CirclingMonitor(cfg)
        px, py = x, y
        for n in range(1, 6):
            walker.update(seen, (px, py), T0)
            px, py = walker.next_waypoint()
            assert (px, py) == ahead[n], (direction, n)
        a0, a5 = math.atan2(y - cy, x - cx), math.atan2(ahead[5][1] - cy, ahead[5][0] - cx)
        turn = (a5 - a0 + math.pi) % (2 * math.pi) - math.pi
        assert (turn > 0) == (direction == Direction.CCW)


@pytest.mark.parametrize("deg", [120.0, 210.0, 300.0])
def test_off_the_perimeter_the_step_is_radial(disc, deg):
    """Inside the fire the UAV steps one cell outwards along the ray from the centre, outside
    inwards: the cell offset is the rounded unit radial vector at that angle."""
    cx, cy = disc.ignition_xy_m
    ux, uy = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    for r, sign in ((0.05 * T0 - 4 * C, 1), (0.05 * T0 + 5 * C, -1)):
        m = CirclingMonitor(
            MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy, search_radius_cells=0)
        )
        i, j = disc.grid.index(cx + r * ux, cy + r * uy)
        x, y = (float(v) for v in disc.grid.center(int(i), int(j)))
        m.update(disc.observe(x, y, 1.5 * C, T0), (x, y), T0)
        wx, wy = m.next_waypoint()
        dx, dy = x - cx, y - cy
        n = math.hypot(dx, dy)
        want = (round(sign * dx / n) * C, round(sign * dy / n) * C)
        assert (wx - x, wy - y) == pytest.approx(want), (deg, sign)


def test_summary_is_a_perimeter_map_a_peer_can_merge(disc):
    """Field names and float32 arrays of PerimeterMap.msg, one entry per bin; a peer merges it."""
    cx, cy = disc.ignition_xy_m
    cfg = MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=cx, center_y_m=cy, bin_count=72)
    m = CirclingMonitor(cfg)
    _fly(disc, m, 4.0)
    s = m.to_summary()
    for key in ("outer_distance_m", "outer_visit_time_s", "spread_rate_mps", "importance"):
        assert s[key].dtype == np.float32 and s[key].shape == (72,), key
    assert np.isnan(s["importance"]).all()  # a circling monitor weighs no windows
    assert (s["center_x_m"], s["center_y_m"]) == (cx, cy)
    peer = ImportanceMonitor(cfg)
    assert peer.merge(s, peer_id=1) == int(np.isfinite(s["outer_visit_time_s"]).sum()) > 0


class _Deciding(ImportanceMonitor):
    """An importance monitor that notes each planning step's windows and decision."""

    def __init__(self, config):
        super().__init__(config)
        self.decisions: list[tuple[float, float, int, bool]] = []  # back, front, run_cells, turned

    def _plan(self):
        before, run, changes = self.direction, self.run_cells, self.direction_changes
        self.last_window = None
        super()._plan()
        if self.last_window is not None:
            w = self.last_window
            turned = self.direction != before
            assert self.direction_changes == changes + int(turned)
            self.decisions.append((w.imp_back, w.imp_front, run, turned))


T_E = 700.0  # the ellipse's flights start here: a small fire, a short initial lap


@pytest.fixture(scope="module")
def ellipse():
    """Elliptical fire (head 0.2 m/s to +x, e = 0.8): the head is far more important than the rear."""
    return star_fire((40, 40), C, (20, 20), elliptical_ros(0.2, 0.8, 0.0))


def _fly_deciding(fire, **config):
    """An importance monitor that knows the ignition point, flown 8 min on ``fire`` from t = 1000 s."""
    cx, cy = fire.ignition_xy_m
    cfg = MonitorConfig(
        cell_size_m=C,
        speed_mps=SPEED,
        center_x_m=cx,
        center_y_m=cy,
        ignition_time_s=0.0,
        min_run_fraction=0.0,
        rule="windows",
        **config,
    )
    m = _Deciding(cfg)
    tr = fly(
        fire,
        m,
        start_angle_rad=0.3,
        t_start_s=1000.0,
        t_end_s=1480.0,
        speed_mps=SPEED,
        sensor_range_m=1.5 * C,
    )
    return m, tr


@pytest.mark.parametrize("margin", [0.0, 0.5])
def test_turns_follow_listing_3_with_the_margin(ellipse, margin):
    """PM Listing 3 (with our margin): at each planning step the UAV turns exactly when
    IMP_BACK > (1 + margin) IMP_FRONT; every turn reverses the direction and is counted."""
    m, tr = _fly_deciding(ellipse, turn_margin=margin)
    assert m.direction_changes > 0
    for back, front, _, turned in m.decisions:
        if abs(back - (1 + margin) * front) > 1e-9 * max(back, front, 1e-30):
            assert turned == (back > (1 + margin) * front), (back, front, margin)
    flips = int(np.sum(np.diff(np.array(tr.direction)) != 0))
    assert m.to_summary()["direction_changes"] == m.direction_changes == flips


def test_after_a_turn_the_uav_flies_min_run_cells_first(ellipse):
    """Hysteresis: no decision within min_run_cells cells of a turn, and one as soon as allowed."""
    m, tr = _fly_deciding(ellipse, min_run_cells=6)
    flips = np.flatnonzero(np.diff(np.array(tr.direction)) != 0)
    assert len(flips) >= 2
    assert np.diff(flips).min() == 6  # cells flown between turns: never fewer, and 6 when it pays


def test_config_edges_and_whole_messages():
    with pytest.raises(ValueError, match=r"^speed_mps must be > 0, got 0.0$"):
        MonitorConfig(cell_size_m=C, speed_mps=0.0)
    with pytest.raises(ValueError, match=r"^give both center_x_m and center_y_m, or neither$"):
        MonitorConfig(cell_size_m=C, speed_mps=SPEED, center_x_m=1.0)
    with pytest.raises(
        ValueError, match=r"^min_run_cells must be >= 0, min_run_fraction in \[0, 1\], turn_margin"
    ):
        MonitorConfig(cell_size_m=C, speed_mps=SPEED, turn_margin=-0.1)
    MonitorConfig(cell_size_m=C, speed_mps=SPEED, min_run_fraction=0.0, min_run_cells=0, turn_margin=0.0)
    with pytest.raises(RuntimeError, match=r"^next_waypoint\(\) before any update\(\)$"):
        CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED)).next_waypoint()


def test_a_peer_merged_before_the_centre_is_found_is_placed_about_the_centre_the_lap_finds(disc):
    """A peer heard during the initial lap (centre unknown) was placed by its angle about the
    map's placeholder centre and kept it after the lap, until its next summary: a peer due east of
    the fire (angle 0 about the true centre) sat at atan2(600, 800) = 0.64 rad about (0, 0).
    After the lap its angle is the one about the centre found (geometry: east of the centre is 0)."""
    cx, cy = disc.ignition_xy_m
    m = CirclingMonitor(MonitorConfig(cell_size_m=C, speed_mps=SPEED, ignition_time_s=0.0))
    summary = {
        "center_x_m": cx,
        "center_y_m": cy,
        "outer_distance_m": np.full(16, 0.05 * T0),
        "outer_visit_time_s": np.full(16, T0),
    }
    m.merge(summary, peer_id=7, peer_pos_m=(cx + 300.0, cy), t_s=T0)
    assert not m.center_known
    _fly(disc, m, 7.0)
    assert m.initial_lap_done and m.center_known
    fm = m.fire_map
    expected = math.atan2(cy - fm.center_y_m, cx + 300.0 - fm.center_x_m)  # the centre found is within a cell
    assert abs(expected) < math.atan2(C, 300.0 - C)
    assert m._peers[7].angle_rad == pytest.approx(expected, abs=1e-12)
