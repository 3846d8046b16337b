"""Edges of the on-board fire map (fire_perimeter_monitor.fire_map), found by mutation testing.

Truth: a sighting's unburned cells as a set of cells built by index (any query point, inside the
footprint's box, on its edge or far outside it), the perimeter cells by a brute-force 4-neighbour
scan; and ``merge_outer``'s documented rule (its docstring: a peer cell is a visit of its bin in
time order, taken if newer than the bin's outer cell at that moment, with :meth:`FireMap.record`'s
inner-cell rules): the same map as recording each such cell alone, one at a time. Seeded numpy
draws, no hypothesis: the same cases on every run (fast: well under a second).
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import FireMap, as_cell_arrays, circular_fill, sighting, unburned_lookup

C = 5.0  # cell size [m]
ARRAYS = ("outer_x_m", "outer_y_m", "outer_d_m", "outer_t_s", "inner_d_m", "inner_t_s")


def _footprint(rng: np.random.Generator):
    """Lattice cells of a holed square footprint about a random corner, random states."""
    n = int(rng.integers(1, 9))
    ox = C * float(rng.integers(-30, 30)) + 1.25
    oy = C * float(rng.integers(-30, 30)) - 2.5
    ii, jj = np.meshgrid(np.arange(n), np.arange(int(rng.integers(1, 9))), indexing="ij")
    keep = rng.random(ii.shape) < 0.8
    ii, jj = ii[keep], jj[keep]
    state = rng.integers(0, 3, ii.size)
    p = rng.permutation(ii.size)  # the first cell (the grid's anchor) anywhere in the footprint
    return ox + C * ii[p], oy + C * jj[p], state[p], ox, oy


def _brute(x, y, s, ox, oy):
    ij = [(round((a - ox) / C), round((b - oy) / C)) for a, b in zip(x, y, strict=True)]
    cells = {k: int(c) for k, c in zip(ij, s, strict=True)}
    nbrs = ((1, 0), (-1, 0), (0, 1), (0, -1))
    per = [cells[(i, j)] != 0 and any(cells.get((i + di, j + dj)) == 0 for di, dj in nbrs) for i, j in ij]
    return cells, per


def test_sighting_against_a_set_of_cells_by_index():
    rng = np.random.default_rng(22)
    for _ in range(120):
        x, y, s, ox, oy = _footprint(rng)
        if rng.random() < 0.2:
            s = np.where(s == 0, 1, s)  # footprints with no unburned cell
        cells, per_want = _brute(x, y, s, ox, oy)
        for checked in (False, True):
            per, look = sighting(x, y, s, C, checked=checked)
            assert per.dtype == bool and per.tolist() == per_want
            # queries: every cell of the footprint's box and a ring of two cells around it,
            # anywhere within a cell (not on its edge), and far away
            qi, qj = np.meshgrid(np.arange(-2, 11), np.arange(-2, 11), indexing="ij")
            qi = np.concatenate([qi.ravel(), [400, -400, 3]])
            qj = np.concatenate([qj.ravel(), [3, 5, -400]])
            jx = rng.uniform(-0.45, 0.45, qi.size) * C
            jy = rng.uniform(-0.45, 0.45, qi.size) * C
            got = look(ox + C * qi + jx, oy + C * qj + jy)
            assert got.dtype == bool and got.shape == qi.shape
            assert got.tolist() == [cells.get((int(a), int(b))) == 0 for a, b in zip(qi, qj, strict=True)]
            got2 = unburned_lookup(x, y, s, C)(ox + C * qi + jx, oy + C * qj + jy)
            assert got2.tolist() == got.tolist()
            # a 2-D query keeps its shape
            assert look(np.full((2, 3), ox), np.full((2, 3), oy)).shape == (2, 3)


def test_an_empty_sighting_has_no_perimeter_and_nothing_unburned():
    per, look = sighting(np.zeros(0), np.zeros(0), np.zeros(0, dtype=np.int64), C)
    assert per.dtype == bool and per.shape == (0,)
    assert look(np.array([0.0, 5.0]), np.array([0.0, 5.0])).tolist() == [False, False]
    assert unburned_lookup([], [], [], C)(np.array([1.0]), np.array([2.0])).tolist() == [False]


def test_cell_arrays_are_float_coordinates_and_int_states_from_any_form():
    # int coordinates and float states, as rows or as a 3-tuple
    for cells in ([[1, 2, 1.0], [3, 4, 2.0]], np.array([[1, 2, 1], [3, 4, 2]]), ([1, 3], [2, 4], [1.0, 2.0])):
        x, y, s = as_cell_arrays(cells)
        assert x.dtype == np.float64 and y.dtype == np.float64 and s.dtype == np.int64
        assert x.tolist() == [1.0, 3.0] and y.tolist() == [2.0, 4.0] and s.tolist() == [1, 2]
    # a list of three rows is rows, not a 3-tuple of columns
    x, y, s = as_cell_arrays([[1.0, 2.0, 0], [3.0, 4.0, 1], [5.0, 6.0, 2]])
    assert x.tolist() == [1.0, 3.0, 5.0] and s.tolist() == [0, 1, 2]
    with pytest.raises(ValueError, match=r"^observed cells: non-finite cell coordinates$"):
        as_cell_arrays([[np.nan, 0.0, 1]])


def _one_at_a_time(fm: FireMap, x, y, t) -> int:
    """merge_outer's rule written with record(): cells by bin then time (ties in the order
    given), each taken if newer than its bin's outer cell at that moment, and recorded alone."""
    x, y, t = (np.asarray(a, dtype=float) for a in (x, y, t))
    ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(t)
    x, y, t = x[ok], y[ok], t[ok]
    taken = 0
    for k in np.lexsort((t, fm.bin_of(x, y))):
        b = int(fm.bin_of(x[k], y[k]))
        if np.isnan(fm.outer_t_s[b]) or t[k] > fm.outer_t_s[b]:
            taken += 1
            fm.record([x[k]], [y[k]], float(t[k]))
    return taken


def _maps(rng):
    kw = dict(
        bin_count=int(rng.choice([8, 36, 360])),
        ignition_time_s=None if rng.random() < 0.4 else float(rng.choice([0.0, 2.0])),
        revisit_gap_s=float(rng.choice([0.0, 1.5, 10.0])),
        ros_baseline_s=float(rng.choice([0.0, 3.0])),
        ros_baseline_cells=float(rng.choice([0.0, 0.5, 2.0])),
        cell_size_m=C,
    )
    return FireMap(2.5, -7.5, **kw), FireMap(2.5, -7.5, **kw)


def test_merge_outer_is_each_newer_cell_recorded_alone_in_time_order():
    rng = np.random.default_rng(2026)
    for _ in range(60):
        fast, ref = _maps(rng)
        t_now = 0.0
        for _step in range(int(rng.integers(1, 6))):
            t_now += float(rng.choice([0.5, 1.5, 5.0, 12.0]))
            n = int(rng.integers(1, 40))
            th = rng.uniform(0.0, 2 * np.pi, n)
            r = rng.uniform(5.0, 20.0 + 3.0 * t_now, n)  # farther and nearer cells in one bin
            x = 2.5 + C * np.rint(r * np.cos(th) / C)
            y = -7.5 + C * np.rint(r * np.sin(th) / C)
            t = 0.5 * np.rint(rng.uniform(max(t_now - 20.0, 0.0), t_now, n) / 0.5)  # ties, exact gaps
            for a in (x, y, t):
                a[rng.random(n) < 0.05] = np.nan
            assert fast.merge_outer(x, y, t) == _one_at_a_time(ref, x, y, t)
            for name in ARRAYS:
                assert np.array_equal(getattr(fast, name), getattr(ref, name), equal_nan=True), name


def test_record_returns_each_touched_bin_once_as_ints():
    fm = FireMap(0.0, 0.0, bin_count=8)
    # three cells in bin 0, two in bin 2, one in bin 5 (45-degree bins), in no order
    ang = np.radians([10.0, 100.0, 20.0, 230.0, 30.0, 95.0])
    r = np.array([10.0, 12.0, 30.0, 9.0, 20.0, 40.0])
    got = fm.record(r * np.cos(ang), r * np.sin(ang), 1.0)
    assert got.dtype == np.int64 and sorted(got.tolist()) == [0, 2, 5]
    assert fm.outer_d_m[0] == 30.0 and fm.outer_d_m[2] == 40.0  # the farthest of each bin
    empty = fm.record([], [], 2.0)
    assert empty.dtype == np.int64 and empty.size == 0


def test_a_farther_cell_seen_at_the_same_time_is_the_same_visit():
    # module doc: a bin seen again within revisit_gap_s is the same visit, the outer cell replaced
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record([100.0], [0.0], 50.0)
    fm.record([120.0], [0.0], 50.0)
    assert (fm.outer_d_m[0], fm.outer_t_s[0], fm.inner_d_m[0], fm.inner_t_s[0]) == (120.0, 50.0, 0.0, 0.0)
    # with no revisit gap (the paper), a second sighting at the same time is no new visit: an
    # Eq. 1 over 0 s would have no rate
    fm0 = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=0.0)
    fm0.record([100.0], [0.0], 50.0)
    fm0.record([120.0], [0.0], 50.0)
    assert (fm0.outer_d_m[0], fm0.inner_d_m[0], fm0.inner_t_s[0]) == (100.0, 0.0, 0.0)
    assert fm0.ros_mps()[0] == 2.0


def test_a_bin_moved_inward_restarts_its_own_history_only():
    cells = ([100.0, 0.0], [0.0, 100.0])  # bins 0 and 90
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record(*cells, 50.0)
    # bin 0's outer cell (100, 0) is seen unburned, as a real sighting's lookup says
    look = unburned_lookup([100.0, 70.0], [0.0, 0.0], [0, 2], C)
    fm.record([70.0], [0.0], 80.0, seen_unburned=look)
    assert fm.outer_d_m[0] == 70.0 and fm.inner_d_m[0] == 70.0 and np.isnan(fm.inner_t_s[0])
    assert (fm.inner_d_m[90], fm.inner_t_s[90]) == (0.0, 0.0) and fm.ros_mps()[90] == 2.0
    # a lookup whose unburned cell is elsewhere on the same x (another y) is no evidence
    other = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    other.record(*cells, 50.0)
    other.record([70.0], [0.0], 80.0, seen_unburned=unburned_lookup([100.0], [30.0], [0], C))
    assert other.outer_d_m[0] == 100.0


def test_skipped_bins_are_filled_off_the_origin_on_the_segment():
    # bins between two linked cells take the point where the bin's centre ray (about the map's
    # centre, here not the origin) crosses the segment between the cells
    cx, cy = 30.0, -20.0
    fm = FireMap(cx, cy, bin_count=36)
    a0, a1 = np.radians(5.0), np.radians(45.0)  # bins 0 and 4: bins 1, 2, 3 skipped
    p0 = np.array([cx + 100.0 * np.cos(a0), cy + 100.0 * np.sin(a0)])
    p1 = np.array([cx + 80.0 * np.cos(a1), cy + 80.0 * np.sin(a1)])
    fm.record([p0[0], p1[0]], [p0[1], p1[1]], 1.0, link_m=float(np.hypot(*(p1 - p0))))  # "at most"
    assert fm.known[[0, 1, 2, 3, 4]].all() and fm.known.sum() == 5
    for k in (1, 2, 3):
        q = np.array([fm.outer_x_m[k], fm.outer_y_m[k]])
        th = np.radians(10.0 * k + 5.0)
        assert np.allclose(np.arctan2(q[1] - cy, q[0] - cx), th)  # on the bin's centre ray
        cross = (p1 - p0)[0] * (q - p0)[1] - (p1 - p0)[1] * (q - p0)[0]
        assert abs(cross) < 1e-9 * 100.0**2  # on the segment's line, between its ends
        assert 0.0 < np.dot(q - p0, p1 - p0) < np.dot(p1 - p0, p1 - p0)
        assert fm.outer_d_m[k] == pytest.approx(np.hypot(*(q - np.array([cx, cy]))))


def test_fill_across_the_wrap_and_up_to_a_quarter_turn():
    # cells in bins 357, 0 and 20 (1-degree bins); only 357 and 0 are linked: 358 and 359 filled
    fm = FireMap(0.0, 0.0)
    ang = np.radians([357.5, 0.5, 20.5])
    fm.record(100.0 * np.cos(ang), 100.0 * np.sin(ang), 1.0, link_m=10.0)
    assert np.flatnonzero(fm.known).tolist() == [0, 20, 357, 358, 359]
    # exactly a quarter turn between two linked cells is filled (not more: test_fire_map.py)
    q = FireMap(0.0, 0.0)
    ang = np.radians([0.5, 90.5])
    q.record(10.0 * np.cos(ang), 10.0 * np.sin(ang), 1.0, link_m=15.0)
    assert q.known[:91].all() and not q.known[91:].any()


def test_fill_near_the_centre_with_a_short_link():
    # two cells 0.5 m from the centre, 10 degrees apart (0.087 m): a link of 0.5 m fills the
    # bins between (a crossing within 1 m of the centre too); the default link (0) fills none
    ang = np.radians([0.5, 10.5])
    x, y = 0.5 * np.cos(ang), 0.5 * np.sin(ang)
    fm = FireMap(0.0, 0.0)
    fm.record(x, y, 1.0, link_m=0.5)
    assert np.flatnonzero(fm.known).tolist() == list(range(11))
    assert np.allclose(fm.outer_d_m[1:10], 0.5, rtol=0.01)
    none = FireMap(0.0, 0.0)
    none.record(x, y, 1.0)
    assert np.flatnonzero(none.known).tolist() == [0, 10]


def test_set_center_keeps_the_maps_configuration_and_a_single_sighting():
    fm = FireMap(
        0.0,
        0.0,
        bin_count=36,
        ignition_time_s=0.0,
        revisit_gap_s=5.0,
        ros_baseline_s=3.0,
        ros_baseline_cells=2.0,
        cell_size_m=5.0,
    )
    fm.set_center(10.0, -10.0, [[110.0, -10.0, 40.0]])  # one sighting
    assert (fm.bin_count, fm.revisit_gap_s, fm.ros_baseline_s, fm.ros_baseline_cells, fm.cell_size_m) == (
        36,
        5.0,
        3.0,
        2.0,
        5.0,
    )
    assert fm.outer_d_m.size == 36 and fm.known.sum() == 1 and fm.outer_d_m[0] == 100.0


def test_an_unknown_rate_everywhere_fills_as_zero():
    # fire_front reads circular_fill with its default: no known bin is no spread anywhere
    assert circular_fill(np.full(8, np.nan)).tolist() == [0.0] * 8
    assert FireMap(0.0, 0.0, bin_count=8).filled(np.full(8, np.nan)).tolist() == [0.0] * 8
