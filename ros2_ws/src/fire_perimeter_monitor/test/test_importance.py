"""PM Eqs. 1-8 and the V-A / Appendix A analysis on the representative scenario."""

import numpy as np
import pytest
from fire_perimeter_monitor.importance import (
    adjust_heterogeneity,
    cell_importance,
    rate_of_spread,
    should_turn,
    time_since_visit,
    time_to_cell,
    window_importance,
)

LOCATION_POS = {1: 0.0, 2: 0.5, 3: 1.0, 4: 1.5}  # x N cells clockwise from the r_min direction


def representative(n: int, a: float, loc: int, r_min=1.0, c=1.0, s=1.0):
    """PM V-A: 2N cells, ROS linear from r_min to r_max = a r_min, UAV circling CW at `loc`.

    In steady circling the cell i cells behind the UAV was visited i c/s ago.
    """
    m = 2 * n
    delta = (a - 1) * r_min / n
    p0 = LOCATION_POS[loc] * n
    i = np.arange(m)
    p = (p0 - i) % m
    ros = r_min + delta * np.minimum(p, m - p)
    return window_importance(ros, i * c / s, c, s)


def test_eq1_to_eq4_basic():
    assert rate_of_spread(10.0, 4.0, 30.0, 0.0) == pytest.approx(0.2)
    assert np.isnan(rate_of_spread(10.0, 4.0, 0.0, 0.0))
    assert rate_of_spread(3.0, 4.0, 10.0, 0.0) == 0.0  # a shrinking fire is noise: clipped
    assert time_since_visit(100.0, 40.0) == 60.0
    assert time_to_cell(50.0, 5.0) == 10.0
    with pytest.raises(ValueError, match="speed"):
        time_to_cell(1.0, 0.0)
    assert cell_importance(0.5, 10.0, 4.0) == pytest.approx(7.0)


def test_importance_monotone_in_time_since_visit_and_ros():
    rng = np.random.default_rng(1)
    ros = rng.uniform(0.0, 1.0, 50)
    since = rng.uniform(0.0, 100.0, 50)
    to = rng.uniform(0.0, 100.0, 50)
    base = cell_importance(ros, since, to)
    assert np.all(cell_importance(ros, since + 1.0, to) >= base)
    assert np.all(cell_importance(ros + 0.1, since, to) >= base)
    assert np.all(cell_importance(ros, since, to + 1.0) >= base)
    assert np.all(cell_importance(0.0, since, to) == 0.0)


def test_eq7_alpha():
    ros = np.array([0.1, 0.2, 0.3, 0.9])
    assert np.allclose(adjust_heterogeneity(ros, 0.0), 0.1)  # no heterogeneity
    assert np.allclose(adjust_heterogeneity(ros, 1.0), ros)  # identity
    adj = adjust_heterogeneity(ros, 2.0)  # only above-average cells are magnified
    assert np.allclose(adj[:3], ros[:3]) and adj[3] == pytest.approx(0.1 + 2 * 0.8)
    assert np.allclose(adjust_heterogeneity(ros, 0.5), 0.1 + 0.5 * (ros - 0.1))
    spread = [np.ptp(adjust_heterogeneity(ros, a)) for a in (0, 0.8, 1.0, 1.2, 1.5, 5.0)]
    assert spread == sorted(spread)
    with pytest.raises(ValueError, match="alpha"):
        adjust_heterogeneity(ros, -0.1)


def test_should_turn_rule():
    assert should_turn(2.0, 1.0) and not should_turn(1.0, 2.0)
    assert not should_turn(1.0, 1.0)  # Listing 3: strict >
    assert should_turn(1.0, 1.0, turn_on_tie=True)  # V-A's "a >= 5" reading
    assert not should_turn(0.0, 0.0, turn_on_tie=True)  # nothing known: keep flying


@pytest.mark.parametrize("n", [10, 40])
@pytest.mark.parametrize("a", [2.0, 5.0, 7.0])
def test_appendix_exact_terms(n, a):
    """Where our discretisation meets the paper's Appendix A, it does so exactly."""
    r, d = 1.0, (a - 1) / n
    w1 = representative(n, a, 1)
    assert w1.imp_front == pytest.approx(2 * n * n * r + d * n**3 + d * n * n)  # location 1 front
    i = np.arange(1, n + 1)
    w3 = representative(n, a, 3)
    back3 = np.sum(2 * n * r + 2 * i * d * n - 2 * r * i - 2 * d * i**2)
    assert w3.imp_back == pytest.approx(back3)  # location 3 back


@pytest.mark.parametrize("a", [1.5, 2.0, 3.0, 5.0, 8.0])
def test_imp_diff_locations_1_to_4_leading_order(a):
    """IMP_DIFF / (N^2 r_min c/s) at locations 1-4 for large N (PM V-A, Eq. 8).

    Locations 3 and 4 match the paper. Location 1: the paper's IMP_BACK drops a factor 2 on
    its delta terms (sum of 2 i (r_min + i delta) is r_min N(N+1) + delta N(N+1)(2N+1)/3);
    the correct coefficient is 1 + (a-1)/3 (paper: 1 + 2(a-1)/3). Location 2: the paper's
    Appendix IMP_FRONT equals its IMP_BACK term for term and its IMP_DIFF (a-1)/2 vanishes at
    a = 1, where all locations must agree (~N^2 r_min); the model gives 1 + 5(a-1)/4. All
    four keep the paper's conclusion: positive (fly on) at 1-3, sign of (5 - a) at 4.
    """
    n = 400
    expected = {1: 1 + (a - 1) / 3, 2: 1 + 5 * (a - 1) / 4, 3: 1 + 2 * (a - 1) / 3, 4: (5 - a) / 4}
    for loc, coef in expected.items():
        w = representative(n, a, loc)
        assert (w.imp_front - w.imp_back) / n**2 == pytest.approx(coef, abs=3 * a / n), loc
        if loc < 4:
            assert not should_turn(w.imp_back, w.imp_front)


def test_location_4_turns_back_iff_a_at_least_5():
    """PM V-A: at location 4 IMP_DIFF = N^2 r_min (5 - a) / 4: turn back iff a >= 5.

    Discrete cells add an O(N) term, so the switch is at a*(N) = 5 + O(1/N).
    """
    for a in (1.5, 2.0, 3.0, 4.0, 4.9):
        w = representative(1000, a, 4)
        assert not should_turn(w.imp_back, w.imp_front), a
    for a in (5.1, 6.0, 8.0, 20.0):
        w = representative(1000, a, 4)
        assert should_turn(w.imp_back, w.imp_front), a
    for n in (50, 200, 1000):
        lo, hi = 1.0, 20.0
        for _ in range(60):
            mid = (lo + hi) / 2
            w = representative(n, mid, 4)
            lo, hi = (lo, mid) if should_turn(w.imp_back, w.imp_front) else (mid, hi)
        assert abs(hi - 5.0) <= 15.0 / n, (n, hi)
