"""On-board fire map (PM IV-A, Table 1, Listing 2, Eq. 1) against analytic fires.

References: a circle / ellipse growing self-similarly from the ignition point at t = 0 has the
radial rate of spread r(theta, t) / t at every angle; bin geometry from the angle itself; a
brute-force 4-neighbour scan for perimeter cells; linear interpolation on a circle.
"""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import (
    CellGrid,
    CellState,
    Direction,
    FireMap,
    angle_bin,
    as_cell_arrays,
    circular_fill,
    direction_sign,
    perimeter_mask,
    reversed_direction,
)
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

# No shrinking: a failing example is reported as drawn (fast, also under mutation testing).
NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate)


def _ellipse(va, vb, t, n=4000):
    s = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return va * t * np.cos(s), vb * t * np.sin(s)


def _radial_ros(va, vb, theta):
    return va * vb / np.hypot(vb * np.cos(theta), va * np.sin(theta))


@settings(max_examples=30, deadline=None, phases=NO_SHRINK)
@given(st.floats(0.0, 2 * math.pi - 1e-6), st.sampled_from([8, 36, 360, 720]), st.floats(0.5, 5000.0))
def test_angle_bin_is_the_angle_interval(theta, bins, r):
    cx, cy = 123.0, -45.0
    b = int(angle_bin(cx + r * math.cos(theta), cy + r * math.sin(theta), cx, cy, bins))
    width = 2 * math.pi / bins
    assert b * width - 1e-9 <= theta < (b + 1) * width + 1e-9
    fm = FireMap(cx, cy, bin_count=bins)
    assert int(fm.bin_of(cx + r * math.cos(theta), cy + r * math.sin(theta))) == b
    centre = fm.bin_center_rad()[b]
    assert abs(centre - theta) <= width / 2 + 1e-9


def test_cell_grid_round_trip_and_errors():
    g = CellGrid(-5.0, 10.0, 4.0)
    i, j = np.meshgrid(np.arange(-3, 4), np.arange(-2, 5), indexing="ij")
    x, y = g.center(i, j)
    assert np.allclose(x, -5.0 + 4.0 * i) and np.allclose(y, 10.0 + 4.0 * j)
    for dx, dy in [(0.0, 0.0), (1.9, -1.9), (-1.9, 1.9)]:  # within half a cell of the centre
        ii, jj = g.index(x + dx, y + dy)
        assert np.array_equal(ii, i) and np.array_equal(jj, j)
    with pytest.raises(ValueError, match="cell_size_m"):
        CellGrid(0.0, 0.0, 0.0)


def test_as_cell_arrays_forms_and_errors():
    x, y, s = as_cell_arrays([[1.0, 2.0, 1], [3.0, 4.0, 2]])
    assert x.tolist() == [1.0, 3.0] and y.tolist() == [2.0, 4.0] and s.tolist() == [1, 2]
    x2, y2, s2 = as_cell_arrays(([1.0, 3.0], [2.0, 4.0], [1, 2]))
    assert np.array_equal(x, x2) and np.array_equal(y, y2) and np.array_equal(s, s2)
    assert as_cell_arrays(np.zeros((0, 3)))[0].size == 0
    assert as_cell_arrays(([0.0], [0.0], [0]))[2].tolist() == [0]
    with pytest.raises(ValueError, match="lengths differ"):
        as_cell_arrays(([1.0, 2.0], [1.0], [0, 0]))
    with pytest.raises(ValueError, match="non-finite"):
        as_cell_arrays([[np.nan, 0.0, 1]])
    with pytest.raises(ValueError, match="non-finite"):
        as_cell_arrays([[0.0, np.inf, 1]])
    with pytest.raises(ValueError, match="state must be 0, 1 or 2"):
        as_cell_arrays([[0.0, 0.0, 3]])
    with pytest.raises(ValueError, match="state must be 0, 1 or 2"):
        as_cell_arrays([[0.0, 0.0, -1]])


def test_direction_helpers():
    assert direction_sign(Direction.CCW) == 1 and direction_sign(Direction.CW) == -1
    assert reversed_direction(Direction.CCW) == Direction.CW
    assert reversed_direction(Direction.CW) == Direction.CCW


@settings(max_examples=25, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1))
def test_perimeter_mask_against_brute_force(seed):
    """A fire cell with an observed unburned 4-neighbour; unseen neighbours do not count."""
    rng = np.random.default_rng(seed)
    n = 8
    state = rng.integers(0, 3, size=(n, n))
    seen = rng.random((n, n)) < 0.8
    seen[0, 0] = True
    c = 5.0
    ii, jj = np.nonzero(seen)
    x, y = 100.0 + c * ii, -50.0 + c * jj
    got = perimeter_mask(x, y, state[ii, jj], c)
    expect = []
    for a, b in zip(ii, jj, strict=True):
        nbrs = [(a + 1, b), (a - 1, b), (a, b + 1), (a, b - 1)]
        expect.append(
            state[a, b] != CellState.UNBURNED
            and any(0 <= p < n and 0 <= q < n and seen[p, q] and state[p, q] == 0 for p, q in nbrs)
        )
    assert got.tolist() == expect
    assert perimeter_mask([], [], [], c).size == 0


@pytest.mark.parametrize("va,vb", [(0.5, 0.5), (0.9, 0.3)])
def test_eq1_ros_of_a_self_similar_ellipse(va, vb):
    """Ignition at the map centre at t = 0 (Listing 2): ROS = radial growth rate at every angle."""
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=100.0)
    for t in (1000.0, 1600.0, 2500.0):
        fm.record(*_ellipse(va, vb, t), t)
        assert fm.known.all()
        # the bin's farthest cell lies at one of the bin's edges: ROS between the edge values
        edges = np.arange(361) * np.pi / 180
        lo = np.minimum(_radial_ros(va, vb, edges[:-1]), _radial_ros(va, vb, edges[1:]))
        hi = np.maximum(_radial_ros(va, vb, edges[:-1]), _radial_ros(va, vb, edges[1:]))
        ros = fm.ros_mps()
        assert np.all(ros >= lo * (1 - 1e-3)) and np.all(ros <= hi * (1 + 1e-3))
        assert np.all(fm.outer_t_s == t)
    assert np.all(fm.inner_t_s == 1600.0)  # the previous visit became the inner cell (PM IV-A)


def test_revisit_gap_and_ros_baseline():
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0, ros_baseline_s=100.0)
    fm.record([100.0], [0.0], 100.0)
    assert fm.ros_mps()[0] == pytest.approx(1.0)
    fm.record([104.0], [0.0], 109.0)  # same visit (< gap): outer replaced, inner kept
    assert fm.inner_t_s[0] == 0.0 and fm.outer_d_m[0] == 104.0
    fm.record([110.0], [0.0], 150.0)  # new visit, but only 41 s after the last: baseline keeps inner
    assert fm.inner_t_s[0] == 0.0 and fm.ros_mps()[0] == pytest.approx(110.0 / 150.0)
    fm.record([160.0], [0.0], 250.0)  # 100 s later: the outer cell becomes the inner one
    assert fm.inner_t_s[0] == 150.0 and fm.ros_mps()[0] == pytest.approx(0.5)
    fm.record([170.0], [0.0], 200.0)  # an older sighting (t < outer_t): ignored
    assert fm.outer_t_s[0] == 250.0 and fm.outer_d_m[0] == 160.0
    gap0 = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=0.0)
    gap0.record([10.0], [0.0], 10.0)
    gap0.record([12.0], [0.0], 10.5)  # gap 0: every later sighting is a new visit
    assert gap0.inner_t_s[0] == 10.0 and gap0.ros_mps()[0] == pytest.approx(4.0)
    assert fm.record([], [], 300.0).size == 0


def test_constructor_errors():
    with pytest.raises(ValueError, match="bin_count"):
        FireMap(0.0, 0.0, bin_count=7)
    assert FireMap(0.0, 0.0, bin_count=8).bin_count == 8
    with pytest.raises(ValueError, match="revisit_gap_s"):
        FireMap(0.0, 0.0, revisit_gap_s=-1.0)
    with pytest.raises(ValueError, match="ros_baseline_s"):
        FireMap(0.0, 0.0, ros_baseline_s=-1.0)
    with pytest.raises(ValueError, match="centre"):
        FireMap(math.nan, 0.0)
    with pytest.raises(ValueError, match="centre"):
        FireMap(0.0, math.inf)
    FireMap(0.0, 0.0, revisit_gap_s=0.0, ros_baseline_s=0.0)  # 0 is allowed for both


def test_skipped_bins_are_filled_on_the_circle():
    """A circle of 3 km seen as cells 100 m apart (2 degrees): every bin between is filled."""
    r = 3000.0
    th = np.radians(np.arange(0.25, 360.0, 100.0 / r * 180 / np.pi))
    fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    fm.record(r * np.cos(th), r * np.sin(th), 1.0, link_m=150.0)
    assert fm.known.all()
    assert np.allclose(fm.outer_d_m, r, rtol=2e-4)  # the chord sags by r (1 - cos 1 deg)
    fm2 = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    fm2.record(r * np.cos(th), r * np.sin(th), 1.0, link_m=50.0)  # cells farther apart: no fill
    assert 0 < fm2.known.sum() < 360
    fm3 = FireMap(0.0, 0.0, revisit_gap_s=10.0)
    fm3.record(r * np.cos(th), r * np.sin(th), 1.0)  # link 0: no fill
    assert fm3.known.sum() == fm2.known.sum()


def test_merge_outer_takes_newer_valid_cells():
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record([100.0, 0.0], [0.0, 100.0], 100.0)  # bins 0 and 90
    x = np.array([150.0, 0.0, np.nan, -80.0, 0.0])
    y = np.array([0.0, 120.0, 5.0, 0.0, -70.0])
    t = np.array([200.0, 50.0, 300.0, np.nan, 300.0])
    assert fm.merge_outer(x, y, t) == 2  # bin 0 newer; bin 90 older; NaNs skipped; bin 270 new
    assert fm.outer_d_m[0] == 150.0 and fm.inner_d_m[0] == 100.0 and fm.ros_mps()[0] == pytest.approx(0.5)
    assert fm.outer_d_m[90] == 100.0
    assert fm.outer_d_m[270] == 70.0 and fm.inner_t_s[270] == 0.0
    assert not fm.known[180]
    assert fm.merge_outer([np.nan], [0.0], [1.0]) == 0


def test_set_center_equals_recording_with_that_centre():
    rng = np.random.default_rng(5)
    cells = []
    for t in (10.0, 400.0, 900.0):
        th = rng.uniform(0, 2 * np.pi, 300)
        r = 0.2 * t + 20.0 + rng.uniform(0.0, 5.0, th.size)  # no ties for the farthest cell
        cells += [(30.0 + q * math.cos(a), -20.0 + q * math.sin(a), t) for a, q in zip(th, r, strict=True)]
    direct = FireMap(30.0, -20.0, ignition_time_s=0.0, revisit_gap_s=50.0, ros_baseline_s=5.0)
    for t in (10.0, 400.0, 900.0):
        sel = [c for c in cells if c[2] == t]
        direct.record([c[0] for c in sel], [c[1] for c in sel], t)
    moved = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=50.0, ros_baseline_s=5.0)
    moved.record([500.0], [500.0], 1.0)
    moved.set_center(30.0, -20.0, cells[::-1])  # any order: replayed in time order
    assert moved.center_x_m == 30.0 and moved.center_y_m == -20.0
    for name in ("outer_x_m", "outer_y_m", "outer_d_m", "outer_t_s", "inner_d_m", "inner_t_s"):
        np.testing.assert_array_equal(getattr(moved, name), getattr(direct, name), err_msg=name)
    assert moved.revisit_gap_s == 50.0 and moved.ros_baseline_s == 5.0 and moved.ignition_time_s == 0.0
    moved.set_center(1.0, 2.0, [])
    assert not moved.known.any() and moved.center_x_m == 1.0


def test_circular_fill_interpolates_across_the_wrap():
    v = np.full(8, np.nan)
    v[1], v[5] = 2.0, 10.0
    out = circular_fill(v, default=-1.0)
    assert out.tolist() == [4.0, 2.0, 4.0, 6.0, 8.0, 10.0, 8.0, 6.0]
    assert FireMap(0.0, 0.0, bin_count=8).filled(v).tolist() == out.tolist()
    assert circular_fill(np.full(4, np.nan), default=7.0).tolist() == [7.0] * 4
    full = np.arange(5.0)
    got = circular_fill(full)
    assert got.tolist() == full.tolist() and got is not full
    one = np.full(6, np.nan)
    one[4] = 3.0
    assert circular_fill(one).tolist() == [3.0] * 6


def test_angle_just_below_zero_is_in_the_last_bin():
    """atan2 of (1, -1e-300) is -1e-300, whose mod 2 pi rounds to 2 pi itself: still the last bin."""
    for bins in (8, 360):
        assert angle_bin(1.0, -1e-300, 0.0, 0.0, bins).tolist() == bins - 1
    assert FireMap(0.0, 0.0, bin_count=8).filled(np.full(8, np.nan)).tolist() == [0.0] * 8


def test_skipped_bins_are_not_filled_across_more_than_a_quarter_turn():
    """Near the centre two linked cells can span a wide angle: bins are filled up to 90 degrees."""
    r = 60.0
    for span_deg, filled in ((80, True), (100, False)):
        th = np.radians([0.5, span_deg + 0.5])
        fm = FireMap(0.0, 0.0, revisit_gap_s=10.0)
        fm.record(r * np.cos(th), r * np.sin(th), 1.0, link_m=150.0)
        assert fm.known.sum() == (span_deg + 1 if filled else 2), span_deg
        if filled:  # the chord between the two cells, seen along each bin's centre ray
            mid = np.radians(np.arange(1, span_deg) + 0.5) - np.radians(span_deg / 2 + 0.5)
            chord = r * math.cos(math.radians(span_deg / 2)) / np.cos(mid)
            np.testing.assert_allclose(fm.outer_d_m[1:span_deg], chord)


def test_the_map_never_moves_a_bin_inward_without_evidence():
    """Burned area never shrinks: a nearer perimeter cell in a bin is another crossing of the
    ray (a notched fire), not the bin's outer cell, and is no visit of it."""
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record([100.0], [0.0], 100.0)
    fm.record([60.0], [0.0], 105.0)  # same visit, nearer crossing
    assert fm.outer_d_m[0] == 100.0 and fm.outer_t_s[0] == 100.0
    fm.record([70.0], [0.0], 200.0)  # new visit, nearer crossing only
    assert fm.outer_d_m[0] == 100.0 and fm.outer_t_s[0] == 100.0 and fm.inner_t_s[0] == 0.0
    assert fm.ros_mps()[0] == pytest.approx(1.0)  # no spread-rate spike from the dent
    fm.record([130.0], [0.0], 230.0)  # the outer crossing seen again, grown
    assert fm.outer_d_m[0] == 130.0 and fm.ros_mps()[0] == pytest.approx(30.0 / 130.0)
    # the same through a peer's map
    fm.merge_outer(np.array([50.0]), np.array([0.0]), np.array([300.0]))
    assert fm.outer_d_m[0] == 130.0 and fm.outer_t_s[0] == 230.0


def test_the_map_moves_inward_where_the_outer_cell_is_seen_unburned():
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    fm.record([100.0], [0.0], 100.0)
    fm.record([70.0], [0.0], 200.0, seen_unburned=lambda x, y: np.abs(np.asarray(x) - 100.0) < 1.0)
    assert fm.outer_d_m[0] == 70.0 and fm.outer_t_s[0] == 200.0
    assert np.isnan(fm.ros_mps()[0])  # its Eq. 1 history is void
    keep = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=10.0)
    keep.record([100.0], [0.0], 100.0)
    keep.record([70.0], [0.0], 200.0, seen_unburned=lambda x, y: np.zeros(np.shape(x), dtype=bool))
    assert keep.outer_d_m[0] == 100.0


@settings(max_examples=40, deadline=None, phases=NO_SHRINK)
@given(
    st.lists(
        st.tuples(st.floats(1.0, 500.0), st.floats(0.0, 2 * math.pi), st.floats(0.5, 50.0)),
        min_size=1,
        max_size=40,
    )
)
def test_outer_distances_never_decrease(sightings):
    """Property: whatever the sightings (any distances, any order of sizes), no bin's outer
    distance ever decreases."""
    fm = FireMap(0.0, 0.0, bin_count=36, ignition_time_s=0.0, revisit_gap_s=5.0, ros_baseline_s=3.0)
    t = 0.0
    prev = fm.outer_d_m.copy()
    for r, a, dt in sightings:
        t += dt
        fm.record([r * math.cos(a)], [r * math.sin(a)], t)
        both = np.isfinite(prev)
        assert np.all(fm.outer_d_m[both] >= prev[both])
        prev = fm.outer_d_m.copy()


def test_ros_baseline_scales_with_the_spread_rate():
    """Eq. 1 is taken over at least the time the fire needs to spread ros_baseline_cells cells."""
    fm = FireMap(
        0.0,
        0.0,
        ignition_time_s=0.0,
        revisit_gap_s=1.0,
        ros_baseline_s=0.0,
        ros_baseline_cells=2.0,
        cell_size_m=10.0,
    )
    fm.record([100.0], [0.0], 1000.0)  # ROS 0.1 m/s: 2 cells take 200 s
    fm.record([110.0], [0.0], 1100.0)  # 100 s later: too soon, the inner cell stays the ignition
    assert fm.inner_t_s[0] == 0.0 and fm.ros_mps()[0] == pytest.approx(0.1)
    fm.record([130.0], [0.0], 1300.0)  # 200 s after the 1100 s sighting: it becomes the inner cell
    assert fm.inner_t_s[0] == 1100.0 and fm.ros_mps()[0] == pytest.approx(0.1)
    fast = FireMap(
        0.0,
        0.0,
        ignition_time_s=0.0,
        revisit_gap_s=1.0,
        ros_baseline_s=0.0,
        ros_baseline_cells=2.0,
        cell_size_m=10.0,
    )
    fast.record([100.0], [0.0], 10.0)  # ROS 10 m/s: 2 cells take 2 s
    fast.record([130.0], [0.0], 13.0)
    assert fast.inner_t_s[0] == 10.0 and fast.ros_mps()[0] == pytest.approx(10.0)
    with pytest.raises(ValueError, match="ros_baseline_cells"):
        FireMap(0.0, 0.0, ros_baseline_cells=-1.0)
    with pytest.raises(ValueError, match="cell_size_m"):
        FireMap(0.0, 0.0, cell_size_m=0.0)
