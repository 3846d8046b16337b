"""The split of a perimeter between two monitors by spread rate (split.py, MonitorConfig.split).

References: a circular perimeter of 360 cells with one fast arc, where the boundary that halves
the work (spread rate x length) is found by hand below; with uniform spread it is the length
bisector, which on a circle is the split by angle.
"""

import math

import numpy as np
import pytest
from fire_perimeter_monitor.importance import adjust_heterogeneity
from fire_perimeter_monitor.planner import ImportanceMonitor, MonitorConfig
from fire_perimeter_monitor.split import arc_work, work_bisector_split

M = 360  # cells, one per degree
SLOW, FAST = 0.5, 4.0  # [m/s]
FAST_CELLS = range(30, 90)  # behind the UAV (index grows against the flying direction)


def _ros():
    r = np.full(M, SLOW)
    r[list(FAST_CELLS)] = FAST
    return r


def test_split_halves_the_work_and_moves_toward_the_fast_arc():
    """Me at cell 0, the peer at 180. By hand (5 % of the mean rate added to every cell): the mean
    is (60 x 4 + 300 x 0.5) / 360 = 1.0833, so a slow cell weighs 0.5542 and a fast one 4.0542;
    cells 0..179 weigh 30 x 0.5542 + 60 x 4.0542 + 90 x 0.5542 = 309.75, half of it 154.875 is
    reached in the 35th fast cell after the 30 slow ones (16.625 + 34.1 x 4.0542): cells 0..64
    are ours and 65 is the peer's, 25 cells from the length bisector (90) toward the fast arc.
    Ahead (cells 180..359, uniform) the boundary stays at the length bisector, cell 270."""
    ros = _ros()
    w = arc_work(ros, 1.0)
    np.testing.assert_allclose(w[0], 0.5 + 0.05 * (60 * 4 + 300 * 0.5) / 360)
    owned = work_bisector_split(w, np.array([180]))
    first_not_owned = int(np.argmin(owned))
    assert first_not_owned == 65 and owned[:65].all()
    assert abs(int(np.argmax(owned[180:])) + 180 - 270) <= 1 and not owned[180:269].any()
    # each owns half the work, to within one cell's work at each of the two boundaries
    assert abs(w[owned].sum() - w[~owned].sum()) <= 2 * w.max()
    # and the monitor with the fast arc on its side owns less perimeter
    assert owned.sum() < M / 2 - 20


def test_uniform_spread_splits_by_length():
    # halfway to the peer each way: 0..59 and 240..359 (a cell either way: rounding of the sums)
    for ros in (np.full(M, 2.0), np.full(M, np.nan), np.zeros(M)):  # unknown or no spread: by length too
        owned = work_bisector_split(arc_work(ros, 1.0), np.array([120]))
        assert abs(int(owned.sum()) - 180) <= 1
        assert owned[:59].all() and not owned[61:239].any() and owned[241:].all()


def test_no_peer_owns_all_and_bad_input_is_named():
    assert work_bisector_split(np.ones(10), np.array([], dtype=int)).all()
    with pytest.raises(ValueError, match="peer cells must lie in 1 .. 9"):
        work_bisector_split(np.ones(10), np.array([0]))
    with pytest.raises(ValueError, match="peer cells must lie in 1 .. 9"):
        work_bisector_split(np.ones(10), np.array([10]))
    with pytest.raises(ValueError, match="work must be 1-D"):
        work_bisector_split(np.ones((2, 5)), np.array([1]))
    with pytest.raises(ValueError, match="ros_mps must be 1-D"):
        arc_work(np.ones((2, 5)), 1.0)


def test_an_unknown_spread_rate_counts_as_no_spread():
    """NaN (a cell not yet timed) weighs as a cell spreading at 0 m/s, not at 1 m/s."""
    assert np.array_equal(arc_work([math.nan, 2.0, 0.5], 5.0), arc_work([0.0, 2.0, 0.5], 5.0))
    assert not np.array_equal(arc_work([1.0, 2.0, 0.5], 5.0), arc_work([0.0, 2.0, 0.5], 5.0))


def test_two_cells_and_a_peer_on_the_other_each_own_one():
    """The smallest perimeter a split is defined on: our cell and the peer's."""
    assert work_bisector_split(arc_work([1.0, 1.0], 5.0), [1]).tolist() == [True, False]


def test_two_peers_the_nearest_each_way_bound_the_arc():
    w = arc_work(np.full(M, 1.0), 1.0)
    owned = work_bisector_split(w, np.array([100, 200, 300]))
    assert owned[:50].all() and not owned[50:330].any() and owned[330:].all()


def _monitor(split, alpha=1.0, uav_id=0):
    return ImportanceMonitor(
        MonitorConfig(
            cell_size_m=5.0,
            speed_mps=50.0,
            alpha=alpha,
            center_x_m=0.0,
            center_y_m=0.0,
            uav_id=uav_id,
            split=split,
        )
    )


def _circle_cells():
    """Cells of a 500 m circle in the planner's order: index 0 at 0 deg (the UAV, flying CCW),
    the index growing clockwise (against the flying direction)."""
    th = -np.radians(np.arange(M))
    return 500.0 * np.column_stack([np.cos(th), np.sin(th)])


def _with_peer_opposite(m, peer_id=1, peer_pos_m=(-500.0, 0.0)):
    m.merge(
        {"center_x_m": 0.0, "center_y_m": 0.0, "outer_distance_m": np.full(M, 500.0),
         "outer_visit_time_s": np.full(M, 10.0)},
        peer_id=peer_id, peer_pos_m=peer_pos_m, t_s=10.0,
    )  # fmt: skip
    m.uav_xy, m.t_s = (500.0, 0.0), 10.0
    return m


def test_monitor_spread_split_weighs_the_fast_arc():
    """The monitor's own weights (1: ours), the peer opposite: the two arcs carry equal work and
    the fast side's boundary moves into the fast arc (the split by angle, the old one, leaves it
    at the bisector, cell 90, with 2.2 times the work on our side)."""
    m = _with_peer_opposite(_monitor("spread"))
    ros = _ros()
    owned = m._peer_weight(_circle_cells(), ros) > 0
    w = arc_work(ros, 1.0)
    assert abs(w[owned].sum() - w[~owned].sum()) <= 2 * w.max()
    assert abs(int(np.argmin(owned)) - 65) <= 1  # by hand: 65 (see the test above)
    assert owned.sum() < M / 2 - 20


def test_angle_split_ignores_the_spread_rate():
    """The contrast: by angle, the boundaries are the bisectors (90 and 270) whatever the rates."""
    m = _with_peer_opposite(_monitor("angle"))
    ros = _ros()
    owned = m._peer_weight(_circle_cells(), ros) > 0
    w = arc_work(ros, 1.0)
    assert int(np.argmin(owned)) == 90 and abs(int(owned.sum()) - 180) <= 1
    assert w[owned].sum() > 2 * w[~owned].sum()


def test_monitor_spread_split_with_alpha_zero_is_by_length():
    """Eq. 7 at alpha = 0 makes every rate alike, so the split is by length (the knob stays PM's)."""
    m = _with_peer_opposite(_monitor("spread", alpha=0.0))
    owned = m._peer_weight(_circle_cells(), adjust_heterogeneity(_ros(), 0.0)) > 0
    assert abs(int(owned.sum()) - 180) <= 1 and int(np.argmin(owned)) == 90


@pytest.mark.parametrize("me,peer,ahead", [(0, 1, True), (1, 0, False)])
def test_spread_split_on_the_same_cell_by_id(me, peer, ahead):
    """Co-located: the lower id keeps the arc ahead (large indices), the other the arc behind."""
    m = _with_peer_opposite(_monitor("spread", uav_id=me), peer_id=peer, peer_pos_m=(500.0, 0.0))
    owned = m._peer_weight(_circle_cells(), np.full(M, 1.0)) > 0
    assert owned[0]
    assert owned[M // 2 + 10 :].all() == ahead and owned[1 : M // 2 - 10].any() == (not ahead)
    assert math.isclose(owned.sum(), M / 2, abs_tol=2)


def test_split_setting_is_checked():
    with pytest.raises(ValueError, match="split must be 'spread', 'angle' or 'relay'"):
        MonitorConfig(cell_size_m=5.0, speed_mps=50.0, split="work")
