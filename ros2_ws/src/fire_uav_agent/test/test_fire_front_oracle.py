"""FrontPicture against independent truth (mutation testing of fire_front).

Truths: a brute-force loop over hand-drawn and random rasters for the active front (module doc:
burning cells seen within ``max_age_s`` with an UNBURNED or UNKNOWN 8-neighbour inside the grid),
the per-cell rule "newest observation wins" for merges, the centroid of the fire cells for the PM
map centre, and a circular fire of known radius growth rate (analytic) for PM Eq. 1's ROS.
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_agent.fire_front import UNKNOWN, FrontCells, FrontConfig, FrontPicture
from fire_uav_common.constants import CellState
from hypothesis import given, settings
from hypothesis import strategies as st

B, N, U = int(CellState.BURNING), int(CellState.BURNED), int(CellState.UNBURNED)


def oracle_front(state: np.ndarray, t_obs: np.ndarray, t_s: float, max_age_s: float) -> set[tuple[int, int]]:
    """The module doc's definition by a plain loop: (row, col) of the active front."""
    ny, nx = state.shape
    out = set()
    for i in range(ny):
        for j in range(nx):
            if state[i, j] != B or not t_s - t_obs[i, j] <= max_age_s:
                continue
            open_nb = False
            for di in (-1, 0, 1):
                for dj in (-1, 0, 1):
                    a, b = i + di, j + dj
                    if (di or dj) and 0 <= a < ny and 0 <= b < nx and state[a, b] in (U, UNKNOWN):
                        open_nb = True
            if open_nb:
                out.add((i, j))
    return out


def ij_of(p: FrontPicture, c: FrontCells) -> set[tuple[int, int]]:
    i, j, ok = p.index(c.x_m, c.y_m)
    assert ok.all()
    return {(int(a), int(b)) for a, b in zip(i, j, strict=True)}


@st.composite
def rasters(draw):
    ny = draw(st.integers(1, 6))
    nx = draw(st.integers(1, 6))
    codes = draw(st.lists(st.sampled_from([UNKNOWN, U, B, N]), min_size=nx * ny, max_size=nx * ny))
    times = draw(st.lists(st.integers(0, 6), min_size=nx * ny, max_size=nx * ny))
    return np.array(codes).reshape(ny, nx), np.array(times, dtype=float).reshape(ny, nx)


@settings(max_examples=15, deadline=None)
@given(
    raster=rasters(),
    origin=st.sampled_from([(0.0, 0.0), (-37.0, 12.5), (400.0, -250.0)]),
    cs=st.sampled_from([2.0, 5.0]),
    t_query=st.integers(0, 10),
)
def test_front_and_burning_cells_match_a_brute_force_loop(raster, origin, cs, t_query) -> None:
    """Random rasters (unseen cells, all states, cells seen at different times, some exactly
    ``max_age_s`` old, area not at the origin): the front and the fresh burning cells are the
    loop's, each with its state and observation time; points outside the area are dropped."""
    codes, times = raster
    ny, nx = codes.shape
    x0, y0 = origin
    max_age = 3.0
    p = FrontPicture(
        FrontConfig((x0, x0 + nx * cs, y0, y0 + ny * cs), cs, max_age_s=max_age, min_cells_for_centre=10**6)
    )
    ii, jj = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    for t in np.unique(times):
        sel = (times == t) & (codes != UNKNOWN)
        xs = x0 + (jj[sel] + 0.5) * cs
        ys = y0 + (ii[sel] + 0.5) * cs
        # burning points just outside every side of the area: not part of the picture
        out_x = np.array([x0 - 0.5 * cs, x0 + nx * cs + 0.5 * cs, x0 + 0.5 * cs, x0 + 0.5 * cs])
        out_y = np.array([y0 + 0.5 * cs, y0 + 0.5 * cs, y0 - 0.5 * cs, y0 + ny * cs + 0.5 * cs])
        p.observe(np.r_[xs, out_x], np.r_[ys, out_y], np.r_[codes[sel], np.full(4, B)], float(t))
    t_obs = np.where(codes == UNKNOWN, -np.inf, times)
    expect = oracle_front(codes, t_obs, float(t_query), max_age)
    f = p.front(float(t_query))
    assert ij_of(p, f) == expect
    assert np.all(f.state == B)
    for x, y, t in zip(f.x_m, f.y_m, f.t_obs_s, strict=True):
        i, j = int((y - y0) // cs), int((x - x0) // cs)
        assert t == times[i, j]
        assert x == pytest.approx(x0 + (j + 0.5) * cs) and y == pytest.approx(y0 + (i + 0.5) * cs)
    fresh = {
        (i, j) for i in range(ny) for j in range(nx) if codes[i, j] == B and t_query - times[i, j] <= max_age
    }
    bxy = p.burning_xy(float(t_query))
    assert bxy.shape == (len(fresh), 2)
    assert {(int((y - y0) // cs), int((x - x0) // cs)) for x, y in bxy} == fresh
    # the default time is the latest observation (any sample, even one with no cell inside)
    t_last = float(times.max())
    assert ij_of(p, p.front()) == oracle_front(codes, t_obs, t_last, max_age)
    assert len(p.burning_xy()) == int(((codes == B) & (t_last - times <= max_age)).sum())


def test_a_cell_leaves_the_front_after_exactly_max_age() -> None:
    """Documented edge: seen ``max_age_s`` ago it is still on the front, a moment later it is not."""
    p = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), 10.0, max_age_s=100.0))
    p.observe(np.array([5.0, 15.0]), np.array([5.0, 5.0]), np.array([N, B]), 50.0)
    assert len(p.front(150.0)) == 1 and len(p.burning_xy(150.0)) == 1
    assert len(p.front(150.001)) == 0 and len(p.burning_xy(150.001)) == 0
    # asking again at the earlier time after a later one: not a stale cached answer
    assert len(p.front(150.0)) == 1 and len(p.burning_xy(150.0)) == 1


def test_the_grid_covers_the_area_and_nothing_beyond_it() -> None:
    """22 m wide at 5 m cells: a last, partial column (20-22 m) exists; 20 m tall: exactly 4 rows,
    so a point at y = 20.5 m is outside and ignored."""
    p = FrontPicture(FrontConfig((0.0, 22.0, 0.0, 20.0), 5.0))
    p.observe(np.array([21.0, 2.5]), np.array([2.5, 20.5]), np.array([B, B]), 1.0)
    assert ij_of(p, p.front()) == {(0, 4)}
    assert p.cells_at(np.array([21.0, 2.5]), np.array([2.5, 20.5])).state.tolist() == [B]


def test_observe_rejects_a_state_count_that_differs_from_the_centres() -> None:
    p = FrontPicture(FrontConfig((0.0, 10.0, 0.0, 10.0), 5.0))
    with pytest.raises(ValueError, match="observe: 2 cell centres but 1 states"):
        p.observe(np.array([2.5, 7.5]), np.array([2.5, 2.5]), np.array([B]), 1.0)


def test_config_errors_name_the_bad_field() -> None:
    with pytest.raises(ValueError, match="front area must be non-empty"):
        FrontConfig((0.0, 0.0, 0.0, 10.0), 5.0)
    with pytest.raises(ValueError, match="front area must be non-empty"):
        FrontConfig((0.0, 10.0, 5.0, 5.0), 5.0)
    with pytest.raises(ValueError, match="front max_age_s must be > 0"):
        FrontConfig((0.0, 10.0, 0.0, 10.0), 5.0, max_age_s=0.0)
    with pytest.raises(
        ValueError,
        match=r"x_m, y_m, state, t_obs_s and ros_mps must have the same length, got \[1, 1, 1, 1, 2\]",
    ):
        FrontCells(np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(2))
    with pytest.raises(ValueError, match="same length"):
        FrontCells(np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(2), np.zeros(1))
    with pytest.raises(ValueError, match="same length"):
        FrontCells(np.zeros(1), np.zeros(1), np.zeros(2), np.zeros(1), np.zeros(1))


def test_empty_front_cells_are_empty_and_merge_nothing() -> None:
    e = FrontCells.empty()
    assert len(e) == 0 and e.state.dtype == np.int64
    p = FrontPicture(FrontConfig((0.0, 10.0, 0.0, 10.0), 5.0))
    assert p.merge(e) == 0
    assert len(p.front(0.0)) == 0 and p.burning_xy(0.0).shape == (0, 2)


def _cells(xy: list[tuple[float, float]], states: list[int], times: list[float]) -> FrontCells:
    a = np.array(xy, dtype=float).reshape(-1, 2)
    return FrontCells(
        a[:, 0], a[:, 1], np.array(states), np.array(times, dtype=float), np.full(len(a), np.nan)
    )


def test_merge_takes_only_strictly_newer_valid_cells_inside_the_area() -> None:
    """Newest observation wins per cell (module doc): an older or equally old peer cell, one with
    no finite time, one with a state that is not a CellState, or one outside the area is not taken;
    the count returned is the cells taken."""
    p = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), 10.0))
    p.observe(np.array([5.0, 15.0, 25.0]), np.array([5.0, 5.0, 5.0]), np.array([U, B, U]), 10.0)
    assert p.merge(_cells([(5.0, 5.0)], [B], [9.0])) == 0  # older
    assert p.merge(_cells([(5.0, 5.0)], [B], [10.0])) == 0  # as old
    assert p.merge(_cells([(5.0, 5.0)], [B], [np.inf])) == 0
    assert p.merge(_cells([(5.0, 5.0)], [B], [np.nan])) == 0
    assert p.merge(_cells([(5.0, 5.0), (25.0, 5.0)], [UNKNOWN, 3], [11.0, 11.0])) == 0
    assert p.merge(_cells([(35.0, 5.0), (5.0, -5.0)], [B, B], [11.0, 11.0])) == 0
    assert p.cells_at(np.array([5.0, 15.0, 25.0]), np.full(3, 5.0)).state.tolist() == [U, B, U]
    assert ij_of(p, p.front()) == {(0, 1)}
    # newer: taken, whatever order the entries come in; the newest of several for one cell wins
    got = p.merge(
        _cells([(5.0, 5.0), (15.0, 5.0), (5.0, 5.0), (25.0, 5.0)], [N, U, B, U], [12.0, 11.0, 13.0, 9.0])
    )
    assert got == 3
    now = p.cells_at(np.array([5.0, 15.0, 25.0]), np.full(3, 5.0))
    assert now.state.tolist() == [B, U, U] and now.t_obs_s.tolist() == [13.0, 11.0, 10.0]
    assert ij_of(p, p.front(13.0)) == {(0, 0)}


@settings(max_examples=20, deadline=None)
@given(
    entries=st.lists(
        st.tuples(st.integers(0, 2), st.integers(0, 3), st.sampled_from([U, B, N]), st.integers(0, 50)),
        min_size=1,
        max_size=25,
        unique_by=lambda e: (e[0], e[1], e[3]),
    ),
    split=st.integers(0, 25),
)
def test_merge_keeps_the_newest_observation_of_every_cell(entries, split) -> None:
    """Entries merged in two messages: every cell ends with the state of its newest entry (ties
    in time within one cell are excluded: no newest)."""
    newest: dict[tuple[int, int], tuple[int, int]] = {}
    for i, j, s, t in entries:
        if (i, j) not in newest or t > newest[(i, j)][1]:
            newest[(i, j)] = (s, t)
    p = FrontPicture(FrontConfig((-20.0, 0.0, 100.0, 115.0), 5.0))
    xy = [(-20.0 + (j + 0.5) * 5.0, 100.0 + (i + 0.5) * 5.0) for i, j, _, _ in entries]
    sts = [e[2] for e in entries]
    ts = [float(e[3]) for e in entries]
    k = min(split, len(entries))
    for part in (slice(0, k), slice(k, None)):
        if not xy[part]:
            continue
        # cells taken: the entries newer than what the picture held before this message
        before = {(e[0], e[1]): p.t_obs[e[0], e[1]] for e in entries[part]}
        expect = sum(1 for e in entries[part] if e[3] > before[(e[0], e[1])])
        assert p.merge(_cells(xy[part], sts[part], ts[part])) == expect
    for (i, j), (s, t) in newest.items():
        assert p.state[i, j] == s and p.t_obs[i, j] == t
    unseen = np.ones(p.state.shape, dtype=bool)
    for i, j in newest:
        unseen[i, j] = False
    assert np.all(p.state[unseen] == UNKNOWN)


def test_known_cells_and_cells_at_report_state_and_time() -> None:
    p = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), 10.0))
    p.observe(np.array([5.0, 15.0]), np.array([5.0, 5.0]), np.array([N, B]), 4.0)
    k = p.known_cells((N,))
    assert (k.x_m.tolist(), k.y_m.tolist(), k.state.tolist(), k.t_obs_s.tolist()) == (
        [5.0],
        [5.0],
        [N],
        [4.0],
    )
    assert np.all(np.isnan(k.ros_mps)) and k.state.dtype == np.int64
    both = p.known_cells((N, B, U))
    assert sorted(both.x_m.tolist()) == [5.0, 15.0]
    c = p.cells_at(np.array([17.0, 29.0, 31.0]), np.array([1.0, 9.0, 5.0]))  # the third is outside
    assert c.x_m.tolist() == [15.0, 25.0] and c.y_m.tolist() == [5.0, 5.0]
    assert c.state.tolist() == [B, UNKNOWN] and c.t_obs_s.tolist() == [4.0, -np.inf]
    assert np.all(np.isnan(c.ros_mps)) and c.state.dtype == np.int64


# --- the PM fire map: centre, distance proxy, Eq. 1 -----------------------------------------
def _disc(cs: float, cx: float, cy: float, r_burning: float, r_burnt: float, size: float):
    """A whole-area sighting of a circular fire: burnt inside ``r_burnt``, a burning ring out to
    ``r_burning``, unburned beyond."""
    g = np.arange(cs / 2, size, cs)
    xx, yy = np.meshgrid(g, g)
    r = np.hypot(xx - cx, yy - cy)
    s = np.full(xx.shape, U)
    s[r <= r_burning] = B
    s[r <= r_burnt] = N
    return xx.ravel(), yy.ravel(), s.ravel()


def test_the_pm_map_is_centred_on_the_fire_cells_once_enough_are_known() -> None:
    """Below ``min_cells_for_centre`` fire cells (burning or burnt) no map and no ROS; at the count
    the map is centred on their centroid (unburned cells do not count)."""
    cfg = FrontConfig((0.0, 100.0, 0.0, 100.0), 10.0, min_cells_for_centre=4)
    p = FrontPicture(cfg)
    p.observe(
        np.array([5.0, 15.0, 95.0, 85.0]), np.array([5.0, 5.0, 95.0, 95.0]), np.array([B, N, U, U]), 1.0
    )
    assert p.fire_map is None and np.all(np.isnan(p.front().ros_mps)) and len(p.front()) == 1
    p.observe(np.array([5.0]), np.array([25.0]), np.array([B]), 2.0)
    assert p.fire_map is None
    p.observe(np.array([35.0]), np.array([25.0]), np.array([N]), 3.0)
    assert p.fire_map is not None
    assert (p.fire_map.center_x_m, p.fire_map.center_y_m) == pytest.approx((15.0, 15.0))
    assert p.fire_map.bin_count == cfg.bin_count and p.fire_map.revisit_gap_s == cfg.revisit_gap_s
    # a peer's cells can complete the count as well
    q = FrontPicture(cfg)
    q.merge(_cells([(5.0, 5.0), (15.0, 5.0), (5.0, 25.0)], [B, N, B], [1.0, 1.0, 1.0]))
    assert q.fire_map is None
    q.merge(_cells([(35.0, 25.0)], [N], [3.0]))
    assert q.fire_map is not None and (q.fire_map.center_x_m, q.fire_map.center_y_m) == pytest.approx(
        (15.0, 15.0)
    )


def test_before_eq1_knows_a_bin_ros_grows_with_distance_and_the_farthest_cell_gets_the_nominal_rate() -> None:
    """The proxy (module doc): ordered by distance from the centre, the farthest front cell at
    ``nominal_ros_mps``; a fire within one cell of its centre is not given the full nominal rate."""
    cfg = FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, min_cells_for_centre=20, nominal_ros_mps=0.7)
    p = FrontPicture(cfg)
    x, y, s = _disc(5.0, 100.0, 100.0, 30.0, 25.0, 200.0)
    p.observe(x, y, s, 1.0)
    f = p.front()
    assert len(f) > 20
    d = np.hypot(f.x_m - p.fire_map.center_x_m, f.y_m - p.fire_map.center_y_m)
    assert np.nanmax(f.ros_mps) == pytest.approx(0.7)
    assert f.ros_mps[int(np.argmax(d))] == pytest.approx(0.7)
    order = np.argsort(d)
    assert np.all(np.diff(f.ros_mps[order]) >= -1e-12) and f.ros_mps.min() < 0.7
    c = (p.fire_map.center_x_m, p.fire_map.center_y_m)
    near = p.ros_at(np.array([c[0], c[0] + 2.0]), np.array([c[1], c[1]]))
    assert near[0] == pytest.approx(0.0) and 0.0 < near[1] < 0.7
    assert p.ros_at(np.zeros(0), np.zeros(0)).shape == (0,)
    one = p.ros_at(np.array([f.x_m[int(np.argmax(d))]]), np.array([f.y_m[int(np.argmax(d))]]))
    assert one.shape == (1,) and np.isfinite(one[0])  # a single query point too


def test_eq1_ros_of_a_circle_growing_at_a_known_rate() -> None:
    """A circular fire whose edge advances 0.5 m/s, seen whole at t = 0 and t = 60 s (a revisit,
    ``revisit_gap_s`` 30 s): PM Eq. 1 gives 0.5 m/s in every direction, within a cell per minute."""
    cfg = FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, nominal_ros_mps=2.0)
    p = FrontPicture(cfg)
    p.observe(*_disc(5.0, 100.0, 100.0, 30.0, 25.0, 200.0), 0.0)
    p.observe(*_disc(5.0, 100.0, 100.0, 60.0, 55.0, 200.0), 60.0)
    ros = p.front().ros_mps
    assert np.all(np.isfinite(ros))
    assert np.median(ros) == pytest.approx(0.5, abs=0.05)
    assert np.all(np.abs(ros - 0.5) <= 2 * 5.0 / 60.0)


def test_a_peer_learns_the_same_eq1_ros_from_shared_fronts_alone() -> None:
    """Agent b sees nothing itself; merging a's published fronts (with their observation times)
    at both sightings gives it the ROS a measured."""
    cfg = FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, nominal_ros_mps=2.0)
    a, b = FrontPicture(cfg), FrontPicture(cfg)
    for r, t in ((30.0, 0.0), (60.0, 60.0)):
        a.observe(*_disc(5.0, 100.0, 100.0, r, r - 5.0, 200.0), t)
        b.merge(a.known_cells((N,)))
        b.merge(a.front(t))
    rb = b.ros_at(a.front().x_m, a.front().y_m)
    assert np.all(np.isfinite(rb))
    assert np.median(rb) == pytest.approx(0.5, abs=0.05)


def test_own_sightings_reach_the_pm_map_at_most_once_per_record_period() -> None:
    """A sighting 0.5 s after a recorded one (``record_period_s`` 1 s) does not reach the map, one
    a full period after does. Constructed so it shows in Eq. 1: the ring is drawn 10 m larger in
    the intermediate sighting; only if recorded does it become the baseline of the revisit."""
    for t_mid, recorded in ((0.5, False), (1.0, True)):
        p = FrontPicture(FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, nominal_ros_mps=2.0))
        p.observe(*_disc(5.0, 100.0, 100.0, 30.0, 25.0, 200.0), 0.0)
        p.observe(*_disc(5.0, 100.0, 100.0, 40.0, 35.0, 200.0), t_mid)
        p.observe(*_disc(5.0, 100.0, 100.0, 60.0, 55.0, 200.0), 60.0)
        expect = (60.0 - 40.0) / (60.0 - t_mid) if recorded else (60.0 - 30.0) / 60.0
        assert np.median(p.front().ros_mps) == pytest.approx(expect, abs=0.05), t_mid


def test_an_empty_sighting_does_not_delay_the_next_record() -> None:
    """An empty FireCells sample (nothing in the footprint) records nothing, so the next real
    sighting 0.7 s later (but 1.2 s after the last record) still goes in."""
    p = FrontPicture(FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, nominal_ros_mps=2.0))
    p.observe(*_disc(5.0, 100.0, 100.0, 30.0, 25.0, 200.0), 0.0)
    p.observe(np.zeros(0), np.zeros(0), np.zeros(0), 0.5)
    p.observe(*_disc(5.0, 100.0, 100.0, 40.0, 35.0, 200.0), 1.2)
    p.observe(*_disc(5.0, 100.0, 100.0, 60.0, 55.0, 200.0), 60.0)
    assert np.median(p.front().ros_mps) == pytest.approx(20.0 / 58.8, abs=0.05)


def test_the_smallest_positive_sizes_are_accepted() -> None:
    p = FrontPicture(FrontConfig((0.0, 1.0, 0.0, 1.0), 0.5, max_age_s=0.5))
    p.observe(np.array([0.25, 0.75]), np.array([0.25, 0.25]), np.array([B, U]), 1.0)
    assert len(p.front(1.5)) == 1 and len(p.front(1.6)) == 0


def test_a_point_outside_a_one_column_grid_is_ignored_by_merge() -> None:
    p = FrontPicture(FrontConfig((0.0, 5.0, 0.0, 10.0), 5.0))  # one column, two rows
    assert p.merge(_cells([(7.5, 2.5), (2.5, -1.0)], [B, B], [1.0, 1.0])) == 0
    assert p.merge(_cells([(2.5, 2.5), (12.5, 7.5)], [B, B], [1.0, 1.0])) == 1


def test_an_enclosed_lone_burning_cell_is_not_front() -> None:
    p = FrontPicture(FrontConfig((0.0, 15.0, 0.0, 15.0), 5.0))
    g = np.array([2.5, 7.5, 12.5])
    xx, yy = np.meshgrid(g, g)
    s = np.full(9, N)
    s[4] = B
    p.observe(xx.ravel(), yy.ravel(), s, 1.0)
    assert len(p.front()) == 0 and len(p.burning_xy()) == 1


def test_every_new_sample_shows_in_the_front_even_at_one_instant() -> None:
    """front(t) is cached; samples that arrive at the same sim time (own sighting and a peer's
    cells in one step, in either order) must still show in it."""
    p = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), 10.0))
    assert len(p.front(5.0)) == 0
    p.merge(_cells([(25.0, 5.0)], [U], [5.0]))
    p.observe(np.array([5.0, 15.0]), np.array([5.0, 5.0]), np.array([U, B]), 5.0)
    f = p.front(5.0)
    assert ij_of(p, f) == {(0, 1)} and f.state.dtype == np.int64
    p.observe(np.array([15.0]), np.array([5.0]), np.array([N]), 5.0)  # put out in the same step
    assert len(p.front(5.0)) == 0
    q = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), 10.0))
    assert len(q.front(5.0)) == 0
    q.observe(np.array([5.0]), np.array([5.0]), np.array([U]), 5.0)
    q.merge(_cells([(15.0, 5.0)], [B], [5.0]))
    assert ij_of(q, q.front(5.0)) == {(0, 1)}
    assert len(q.burning_xy(5.0)) == 1


def test_neighbouring_front_cells_are_linked_in_the_pm_map_and_a_gap_is_not() -> None:
    """PM map record's deviation: bins between two neighbouring front cells (diagonal 1.41 cells)
    are filled, so one sighting of a ring r = 30 m (fewer cells than the 72 bins) knows every bin;
    two front cells two cells apart with a burnt cell between are not neighbours: the bins
    between them stay unknown."""
    p = FrontPicture(FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0))
    p.observe(*_disc(5.0, 100.0, 100.0, 30.0, 25.0, 200.0), 0.0)
    assert p.fire_map is not None and p.fire_map.known.all()
    q = FrontPicture(FrontConfig((0.0, 200.0, 0.0, 200.0), 5.0, min_cells_for_centre=9))
    g = np.array([97.5, 102.5, 107.5])
    xx, yy = np.meshgrid(g, g)  # a burnt 3 x 3 block: the map centre (102.5, 102.5)
    q.observe(xx.ravel(), yy.ravel(), np.full(9, N), 0.0)
    q.observe(np.array([97.5, 102.5, 107.5]), np.full(3, 132.5), np.array([B, N, B]), 2.0)
    fm = q.fire_map
    assert fm is not None and (fm.center_x_m, fm.center_y_m) == (102.5, 102.5)
    b_right, b_left = int(fm.bin_of(107.5, 132.5)), int(fm.bin_of(97.5, 132.5))
    assert b_left - b_right == 3  # two bins between the cells
    assert fm.known[b_right] and fm.known[b_left]
    assert not fm.known[b_right + 1] and not fm.known[b_right + 2]


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), t_query=st.integers(3, 12))
def test_front_and_burning_cells_in_row_major_order_on_a_larger_grid(seed: int, t_query: int) -> None:
    """A 30 x 40 picture written by a random run of own samples and peers' merges, burning cells
    in patches anywhere (edges included), later rewritten unburned or burned: the front and the
    fresh burning cells are the brute-force loop's, listed in the grid's row-major order (the
    order the tactics' sums see), whichever of ``observe`` and ``merge`` wrote them."""
    rng = np.random.default_rng(seed)
    ny, nx, cs, x0, y0, max_age = 30, 40, 5.0, -100.0, 20.0, 4.0
    p = FrontPicture(FrontConfig((x0, x0 + nx * cs, y0, y0 + ny * cs), cs, max_age_s=max_age))
    codes = np.full((ny, nx), UNKNOWN)
    times = np.full((ny, nx), -np.inf)
    for t in range(1, 11):
        ci, cj = int(rng.integers(0, ny)), int(rng.integers(0, nx))
        h, w = int(rng.integers(1, 6)), int(rng.integers(1, 6))
        ii, jj = np.meshgrid(np.arange(ci, min(ci + h, ny)), np.arange(cj, min(cj + w, nx)), indexing="ij")
        ii, jj = ii.ravel(), jj.ravel()
        st_ = rng.choice([U, B, B, N], size=ii.size)
        xs, ys = x0 + (jj + 0.5) * cs, y0 + (ii + 0.5) * cs
        if rng.random() < 0.5:
            p.observe(xs, ys, st_, float(t))
        else:
            p.merge(_cells(list(zip(xs, ys, strict=True)), list(st_), [float(t)] * ii.size))
        codes[ii, jj] = st_
        times[ii, jj] = t
    order = sorted(oracle_front(codes, times, float(t_query), max_age))
    f = p.front(float(t_query))
    assert [(int((y - y0) // cs), int((x - x0) // cs)) for x, y in zip(f.x_m, f.y_m, strict=True)] == order
    fresh = [
        (i, j) for i in range(ny) for j in range(nx) if codes[i, j] == B and t_query - times[i, j] <= max_age
    ]
    bxy = p.burning_xy(float(t_query))
    assert [(int((y - y0) // cs), int((x - x0) // cs)) for x, y in bxy] == fresh
