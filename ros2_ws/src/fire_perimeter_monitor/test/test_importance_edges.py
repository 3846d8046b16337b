"""PM Eqs. 1, 7 and the window inputs at their edges (hand-computed values)."""

import numpy as np
import pytest
from fire_perimeter_monitor.importance import (
    adjust_heterogeneity,
    rate_of_spread,
    should_turn,
    window_importance,
    worst_angle_turn,
)


def test_eq1_divides_by_the_time_between_the_two_visits():
    # outer cell 30 m out at t = 15 s, inner 10 m out at t = 5 s: 20 m in 10 s
    assert rate_of_spread(np.array([30.0]), np.array([10.0]), np.array([15.0]), np.array([5.0]))[0] == 2.0


def test_eq1_holds_for_visits_under_a_second_apart():
    # 1 m in 0.5 s is 2 m/s (a sub-second revisit is neither unknown nor a 1 s interval)
    got = rate_of_spread(np.array([11.0]), np.array([10.0]), np.array([3.5]), np.array([3.0]))
    assert got[0] == 2.0


@pytest.mark.parametrize("alpha", [1.5, 3.0])
def test_eq7_keeps_the_below_average_cells_for_any_alpha_above_one(alpha):
    ros = np.array([0.0, 1.0, 2.0, 9.0])  # mean 3
    got = adjust_heterogeneity(ros, alpha)
    np.testing.assert_array_equal(got[:3], ros[:3])
    assert got[3] == pytest.approx(alpha * 9.0)  # ROS_min + alpha (ROS - ROS_min), ROS_min = 0


def test_eq7_keeps_a_cell_exactly_at_the_average():
    got = adjust_heterogeneity(np.array([0.0, 2.0, 4.0]), 2.0)  # mean 2: "ROS <= ROS_avg" keeps it
    np.testing.assert_array_equal(got, [0.0, 2.0, 8.0])


def test_window_inputs_must_be_one_dimensional_even_when_their_shapes_agree():
    with pytest.raises(
        ValueError, match=r"ros and t_since must be equal 1-D arrays, got \(2, 2\) and \(2, 2\)"
    ):
        window_importance(np.ones((2, 2)), np.ones((2, 2)), spacing_m=10.0, speed_mps=20.0)
    with pytest.raises(ValueError, match=r"got \(4,\) and \(3,\)"):
        window_importance(np.ones(4), np.ones(3), spacing_m=10.0, speed_mps=20.0)


def test_eq3_distances_along_the_perimeter_with_an_odd_cell_count():
    # 5 cells, 10 m apart: back window cells 0, 1 reached by turning back (0, 10 m), front cells
    # 2, 3, 4 by flying on ((5 - i) x 10 m = 30, 20, 10 m); 20 m/s
    w = window_importance(np.full(5, 0.1), np.zeros(5), spacing_m=10.0, speed_mps=20.0)
    assert w.n_back == 2
    np.testing.assert_allclose(w.t_to_cell_s, [0.0, 0.5, 1.5, 1.0, 0.5])
    np.testing.assert_allclose(w.ros_adjusted, np.full(5, 0.1))
    np.testing.assert_allclose(w.importance, 0.1 * w.t_to_cell_s)  # Eq. 4 with t_since 0
    assert w.imp_back == pytest.approx(0.05) and w.imp_front == pytest.approx(0.3)


def test_a_cell_weight_scales_its_importance():
    since = np.array([10.0, 20.0, 30.0, 40.0])
    w = window_importance(
        np.full(4, 0.5), since, spacing_m=0.0, speed_mps=20.0, weight=np.array([1.0, 0.0, 0.5, 2.0])
    )
    np.testing.assert_allclose(w.importance, [5.0, 0.0, 7.5, 40.0])  # 0.5 m/s x t_since x weight
    assert (w.imp_back, w.imp_front) == (5.0, 47.5)


def test_should_turn_tie_band_is_relative_and_inclusive():
    # |front - back| = 1 = 0.25 x max(4, 3): a tie (inclusive edge) keeps the direction
    assert not should_turn(4.0, 3.0, tie_rel_tol=0.25)
    assert should_turn(4.0, 3.0, tie_rel_tol=0.25, turn_on_tie=True)
    assert not should_turn(4.0, 3.5, tie_rel_tol=0.25)  # 0.5 <= 1: tie
    assert should_turn(4.0, 2.9, tie_rel_tol=0.25)  # 1.1 > 1: the back window wins
    assert not should_turn(10.0, 10.5)  # the front is more important: fly on


def _circling_since(m, spacing, speed):
    """t_sinceVisit of a UAV circling at constant speed: cell i (behind by i cells) was seen
    i cells of flight ago."""
    return np.arange(m) * spacing / speed


def test_worst_angle_keeps_circling_a_uniform_fire():
    """Uniform spread (or alpha = 0): circling is optimal (PM VI-D), the rule never turns."""
    m, s, v = 40, 5.0, 10.0
    since = _circling_since(m, s, v)
    for ros in (np.full(m, 0.3), np.linspace(0.1, 2.0, m)):
        alpha = 1.0 if np.ptp(ros) == 0 else 0.0
        w = worst_angle_turn(ros, since, s, v, alpha)
        assert w.worst_back_m > w.worst_on_m  # turning back leaves the cells ahead stale twice as long
        # flying on, every cell's predicted error is ROS * one lap
        assert np.allclose(w.on_m, w.ros_adjusted * m * s / v)


def test_worst_angle_turns_back_to_a_fast_cell_just_passed():
    """The fast head is 2 cells behind: flying on reaches it after a lap, turning back at once."""
    m, s, v = 40, 5.0, 10.0
    since = _circling_since(m, s, v)
    ros = np.full(m, 0.05)
    ros[2] = 2.0
    w = worst_angle_turn(ros, since, s, v)
    assert w.worst_back_m < w.worst_on_m
    assert int(np.argmax(w.on_m)) == 2
    # its values are Eq. 4 with the turn's and the flight's times to the cell
    assert w.on_m[2] == pytest.approx(2.0 * (since[2] + (m - 2) * s / v))
    assert w.back_m[2] == pytest.approx(2.0 * (since[2] + 2 * s / v))
    # a peer owns the head (weight 0): no reason to turn
    weight = np.ones(m)
    weight[2] = 0.0
    w = worst_angle_turn(ros, since, s, v, weight=weight)
    assert w.worst_back_m > w.worst_on_m


def test_worst_angle_reach_and_errors():
    m, s, v = 10, 5.0, 10.0
    w0 = worst_angle_turn(np.ones(m), np.zeros(m), s, v)
    w1 = worst_angle_turn(np.ones(m), np.zeros(m), s, v, reach_m=2 * s)
    assert np.allclose(w0.on_m, (m - np.arange(m)) * s / v)
    # a circling UAV with a footprint of radius R: a cell it leaves behind stays in view until
    # it is R behind and is seen again R before the UAV is back, so every cell it now sees
    # behind it waits the lap less 2 R; a cell out of view waits until it is R ahead
    r = 2 * s
    gap = (m * s - 2 * r) / v
    i = np.arange(m)
    behind, ahead = i * s <= r, (m - i) * s <= r
    assert np.allclose(w1.on_m[behind], gap)
    assert np.allclose(w1.on_m[ahead], 0.0)
    mid = ~behind & ~ahead
    assert np.allclose(w1.on_m[mid], ((m - i[mid]) * s - r) / v)
    # turning back mirrors it: the cells now in view ahead wait the same gap
    assert np.allclose(w1.back_m[ahead], gap)
    assert np.allclose(w1.back_m[behind], 0.0)
    # without the footprint behind (a monitor with a peer turns at its arc's end): each cell
    # waits until it is R ahead, whichever way
    w2 = worst_angle_turn(np.ones(m), np.zeros(m), s, v, reach_m=r, keep_in_view=False)
    assert np.allclose(w2.on_m, np.maximum((m - i) * s - r, 0.0) / v)
    assert np.allclose(w2.back_m, np.maximum(i * s - r, 0.0) / v)
    with pytest.raises(ValueError, match="reach_m"):
        worst_angle_turn(np.ones(m), np.zeros(m), s, v, reach_m=-1.0)
    with pytest.raises(ValueError, match="equal 1-D"):
        worst_angle_turn(np.ones(m), np.zeros(m + 1), s, v)
