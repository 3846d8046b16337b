"""StalenessSearch.plan and staleness against hand-computed answers (mutation testing).

Truths: the class doc (staleness = time since seen / horizon, saturating at 1; the waypoint is
the nearest of the points within ``stale_band`` of the stalest in the own cell; it is kept until
seen or out of the cell), on grids small enough to list the answer by hand.
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.planning import PlannerView
from fire_uav_agent.staleness_search import StalenessSearch


def view(t_s, xy, mask):
    return PlannerView(t_s, 0, np.array([xy[0], xy[1], 20.0, 0.0]), None, mask, {}, ())


def idx(grid, p):
    return int(np.flatnonzero((grid.points == p).all(axis=1))[0])


def test_staleness_is_time_since_seen_over_the_horizon_clipped_to_0_1() -> None:
    grid = make_grid(0.0, 30.0, 0.0, 10.0, 10.0)  # points (5, 5), (15, 5), (25, 5)
    s = StalenessSearch(grid, 1.0, horizon_s=40.0)
    assert np.array_equal(s.staleness(0.0), np.ones(3))  # never seen: stale from the start
    s.observe(10.0, np.array([[5.0, 5.0]]))
    s.observe(30.0, np.array([[15.0, 5.0]]))
    assert s.staleness(30.0).tolist() == [0.5, 0.0, 1.0]
    assert s.staleness(20.0).tolist() == [0.25, 0.0, 1.0]  # before a sighting: 0, not negative
    assert s.staleness(50.0).tolist() == [1.0, 0.5, 1.0]  # 40 s after: saturated exactly
    s.observe(31.0, np.zeros((0, 2)))  # no positions: nothing changes
    assert s.staleness(30.0).tolist() == [0.5, 0.0, 1.0]


def test_the_default_horizon_is_two_minutes() -> None:
    grid = make_grid(0.0, 10.0, 0.0, 10.0, 10.0)
    s = StalenessSearch(grid, 1.0)
    assert s.staleness(0.0).tolist() == [1.0]
    s.observe(0.0, np.array([[5.0, 5.0]]))
    assert s.staleness(60.0)[0] == pytest.approx(0.5) and s.staleness(120.0)[0] == 1.0


def test_the_nearest_of_the_stalest_within_the_band_is_chosen() -> None:
    """Row of points x = 5..95: the near points seen recently; with the default band 0.05 the
    nearest point at most 0.05 fresher than the stalest wins over the stalest far away."""
    grid = make_grid(0.0, 100.0, 0.0, 10.0, 10.0)
    s = StalenessSearch(grid, 1.0, horizon_s=100.0)
    for x, t in ((5.0, 100.0), (15.0, 100.0), (25.0, 4.0), (35.0, 6.0)):
        s.observe(t, np.array([[x, 5.0]]))
    # at t = 100: staleness 0, 0, 0.96, 0.94, then 1.0 (never seen) from x = 45 on
    allm = np.ones(10, dtype=bool)
    assert s.plan(view(100.0, (0.0, 5.0), allm)).waypoint_xy == (25.0, 5.0)  # 0.96 >= 1 - 0.05
    s2 = StalenessSearch(grid, 1.0, horizon_s=100.0, stale_band=0.01)
    for x, t in ((5.0, 100.0), (15.0, 100.0), (25.0, 4.0), (35.0, 6.0)):
        s2.observe(t, np.array([[x, 5.0]]))
    assert s2.plan(view(100.0, (0.0, 5.0), allm)).waypoint_xy == (45.0, 5.0)  # the stalest, nearest
    s3 = StalenessSearch(grid, 1.0, horizon_s=100.0)
    for x, t in ((5.0, 100.0), (15.0, 100.0), (25.0, 6.0)):
        s3.observe(t, np.array([[x, 5.0]]))
    # 0.94 < 1 - 0.05: outside the default band
    assert s3.plan(view(100.0, (0.0, 5.0), allm)).waypoint_xy == (35.0, 5.0)


def test_the_choice_is_inside_the_own_cell_and_any_point_without_one() -> None:
    grid = make_grid(0.0, 100.0, 0.0, 10.0, 10.0)
    cell = np.zeros(10, dtype=bool)
    cell[7:] = True  # x = 75, 85, 95
    s = StalenessSearch(grid, 1.0, horizon_s=100.0)
    assert s.plan(view(0.0, (0.0, 5.0), cell)).waypoint_xy == (75.0, 5.0)
    for mask in (None, np.zeros(10, dtype=bool)):  # no own cell (yet): the whole grid
        s = StalenessSearch(grid, 1.0, horizon_s=100.0)
        assert s.plan(view(0.0, (31.0, 5.0), mask)).waypoint_xy == (35.0, 5.0)


def test_a_waypoint_seen_at_the_instant_it_was_chosen_is_released() -> None:
    grid = make_grid(0.0, 100.0, 0.0, 10.0, 10.0)
    s = StalenessSearch(grid, 1.0, horizon_s=100.0)
    allm = np.ones(10, dtype=bool)
    assert s.plan(view(5.0, (3.0, 5.0), allm)).waypoint_xy == (5.0, 5.0)
    s.observe(5.0, np.array([[5.0, 5.0]]))  # seen in the same step, after the choice
    assert s.plan(view(5.0, (3.0, 5.0), allm)).waypoint_xy == (15.0, 5.0)


def test_without_an_own_cell_the_waypoint_is_kept_until_seen() -> None:
    grid = make_grid(0.0, 100.0, 0.0, 10.0, 10.0)
    s = StalenessSearch(grid, 1.0, horizon_s=100.0)
    assert s.plan(view(1.0, (3.0, 5.0), None)).waypoint_xy == (5.0, 5.0)
    assert s.plan(view(2.0, (94.0, 5.0), None)).waypoint_xy == (5.0, 5.0)  # kept
    empty = np.zeros(10, dtype=bool)
    assert s.plan(view(3.0, (94.0, 5.0), empty)).waypoint_xy == (5.0, 5.0)  # an empty cell: kept
    cell = np.zeros(10, dtype=bool)
    cell[9] = True
    assert s.plan(view(4.0, (94.0, 5.0), cell)).waypoint_xy == (95.0, 5.0)  # left the cell
    assert isinstance(s.plan(view(4.0, (94.0, 5.0), cell)).waypoint_xy[0], float)
    assert idx(grid, (95.0, 5.0)) == 9


def test_a_point_exactly_at_the_sensor_range_is_seen() -> None:
    grid = make_grid(0.0, 30.0, 0.0, 10.0, 10.0)  # points (5, 5), (15, 5), (25, 5)
    s = StalenessSearch(grid, 10.0, horizon_s=60.0)
    s.observe(3.0, np.array([[5.0, 5.0]]))
    assert s.last_seen.tolist() == [3.0, 3.0, -60.0]  # (15, 5) at exactly 10 m: within range


def test_a_zero_band_takes_the_nearest_of_the_stalest_only() -> None:
    grid = make_grid(0.0, 100.0, 0.0, 10.0, 10.0)
    s = StalenessSearch(grid, 1.0, horizon_s=100.0, stale_band=0.0)
    s.observe(99.0, np.array([[5.0, 5.0]]))  # (5, 5) fresh: 0.01
    s.observe(1.0, np.array([[15.0, 5.0]]))  # (15, 5) 0.99
    assert s.plan(view(100.0, (0.0, 5.0), np.ones(10, dtype=bool))).waypoint_xy == (25.0, 5.0)
