"""StalenessSearch.observe marks exactly the grid points within sensor range (property test).

The truth is the definition: a point q is seen at t when ||q - p|| <= r for some position p,
checked against every grid point for every position, independent of the windowed implementation.
"""

from __future__ import annotations

import numpy as np
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.staleness_search import StalenessSearch
from hypothesis import given, settings
from hypothesis import strategies as st

coord = st.floats(min_value=-150.0, max_value=450.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(
    positions=st.lists(st.tuples(coord, coord), min_size=0, max_size=6),
    r=st.floats(min_value=0.5, max_value=120.0),
    h=st.sampled_from([5.0, 7.5, 10.0]),
)
def test_observe_marks_exactly_the_points_in_range(positions, r, h):
    grid = make_grid(0.0, 300.0, 0.0, 240.0, h)
    s = StalenessSearch(grid, r, horizon_s=60.0)
    s.observe(12.5, np.array(positions, dtype=float).reshape(-1, 2))
    q = grid.points
    dist = [np.hypot(q[:, 0] - px, q[:, 1] - py) for px, py in positions]  # every point, every position
    expect = np.zeros(len(q), dtype=bool)
    near_edge = np.zeros(len(q), dtype=bool)
    for d in dist:
        expect |= d <= r
        near_edge |= np.abs(d - r) < 1e-9  # rounding may go either way exactly on the circle
    got = s.last_seen == 12.5
    assert np.array_equal(got[~near_edge], expect[~near_edge])
    assert np.all(s.last_seen[~got] == -60.0)  # the others keep their earlier time


def test_observe_keeps_earlier_sightings_and_updates_only_new_ones():
    grid = make_grid(0.0, 100.0, 0.0, 100.0, 10.0)
    s = StalenessSearch(grid, 15.0, horizon_s=60.0)
    s.observe(1.0, np.array([[5.0, 5.0]]))
    s.observe(2.0, np.array([[95.0, 95.0]]))
    assert s.staleness(2.0)[0] == 1.0 / 60.0  # (5, 5) seen at t = 1 s
    assert s.staleness(2.0)[-1] == 0.0  # (95, 95) seen now
    assert s.staleness(2.0)[45] == 1.0  # (55, 45) never seen: saturated


@settings(max_examples=40, deadline=None)
@given(
    tracks=st.lists(st.lists(st.tuples(coord, coord), min_size=1, max_size=4), min_size=1, max_size=8),
    r=st.floats(min_value=20.0, max_value=200.0),
)
def test_swept_since_is_the_oldest_points_last_sighting(tracks, r):
    """``swept_since_s`` (the mission's end of the post-fire sweep): every point of the area has
    been inside a sensor's range since that time, and not since any later one. The truth, per
    point, is its last step within range of a position (brute force over every point and
    step), -horizon_s if never; the answer is the oldest of those."""
    grid = make_grid(0.0, 300.0, 0.0, 240.0, 10.0)
    s = StalenessSearch(grid, r, horizon_s=60.0)
    last = np.full(len(grid.points), -60.0)
    for k, positions in enumerate(tracks):
        t = 1.0 + k
        s.observe(t, np.array(positions, dtype=float))
        for px, py in positions:
            d = np.hypot(grid.points[:, 0] - px, grid.points[:, 1] - py)
            last[d < r - 1e-9] = t  # points exactly on a circle may round either way: left out below
    on_a_circle = np.zeros(len(grid.points), dtype=bool)
    for positions in tracks:
        for px, py in positions:
            on_a_circle |= np.abs(np.hypot(grid.points[:, 0] - px, grid.points[:, 1] - py) - r) < 1e-9
    if on_a_circle.any():
        return
    assert s.swept_since_s() == last.min()


def test_swept_since_before_and_after_the_whole_area_is_covered():
    grid = make_grid(0.0, 100.0, 0.0, 100.0, 10.0)
    s = StalenessSearch(grid, 5.0, horizon_s=60.0)  # each position sees its own point only
    assert s.swept_since_s() == -60.0  # nothing seen
    for k, y in enumerate(range(5, 100, 10)):  # a sweep, one row of points per second
        s.observe(float(k), np.array([[x, float(y)] for x in range(5, 100, 10)], dtype=float))
        assert s.swept_since_s() == (-60.0 if k < 9 else 0.0)
    s.observe(20.0, np.array([[x, 5.0] for x in range(5, 100, 10)], dtype=float))  # the first row again
    assert s.swept_since_s() == 1.0  # the second row's sighting is now the oldest


def _view(t_s, xy, mask):
    from fire_uav_agent.planning import PlannerView

    return PlannerView(t_s, 0, np.array([xy[0], xy[1], 20.0, 0.0]), None, mask, {}, ())


def test_the_waypoint_is_kept_until_seen_or_out_of_the_cell():
    """A chosen waypoint is kept while unseen and in the own cell (it jumped 50-70 m per step).

    Every point is unseen, so the choice is the point nearest the UAV. The UAV then moves next
    to another point: a fresh choice would take that one, the committed waypoint stays. Seeing
    the waypoint, or the waypoint leaving the own cell, releases it.
    """
    grid = make_grid(0.0, 100.0, 0.0, 100.0, 10.0)
    s = StalenessSearch(grid, 4.0, horizon_s=60.0)
    every = np.ones(len(grid.points), dtype=bool)
    first = s.plan(_view(1.0, (6.0, 4.0), every)).waypoint_xy
    assert first == (5.0, 5.0)
    s.observe(1.1, np.array([[50.0, 50.0]]))  # someone else sees a far point: not the waypoint
    assert s.plan(_view(1.1, (94.0, 94.0), every)).waypoint_xy == (5.0, 5.0)  # kept, not (95, 95)
    s.observe(1.2, np.array([[5.0, 5.0]]))  # the waypoint is seen
    assert s.plan(_view(1.2, (94.0, 94.0), every)).waypoint_xy == (95.0, 95.0)  # chosen afresh
    out = every.copy()
    out[np.flatnonzero((grid.points == (95.0, 95.0)).all(axis=1))] = False  # cell shrinks off it
    got = s.plan(_view(1.3, (94.0, 94.0), out)).waypoint_xy
    assert got != (95.0, 95.0) and got in {(85.0, 95.0), (95.0, 85.0)}
