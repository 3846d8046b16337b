"""head_index and relay_split against plain-loop references of their documented rules, on
random closed perimeters (integer spread rates, so that every average is exact and ties are
real), NaN and negative rates mixed in."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_perimeter_monitor.errors import InputError
from fire_perimeter_monitor.split import head_index, relay_split
from hypothesis import given, settings
from hypothesis import strategies as st


def _clean(v: float) -> float:
    return 0.0 if (math.isnan(v) or v < 0) else v


def means_ref(ros: list[float], smooth: int = 2) -> list[float]:
    """Each cell's circular mean over +-k cells, k = min(smooth, (M-1)//2)."""
    m = len(ros)
    r = [_clean(v) for v in ros]
    k = min(smooth, (m - 1) // 2)
    return [sum(r[(i + j) % m] for j in range(-k, k + 1)) / (2 * k + 1) for i in range(m)]


def head_ref(ros: list[float], smooth: int = 2) -> int:
    """The first cell of largest circular mean over +-k cells."""
    means = means_ref(ros, smooth)
    return means.index(max(means))


def relay_ref(ros, spacing, peer, half, mine_on_tie, fast_fraction):
    """The arc within ``half`` of the head, widened over the contiguous cells whose own rate is
    at least ``fast_fraction`` of the head's smoothed rate (none if that is 0), capped at a
    quarter of the perimeter each side; the holder is the nearer monitor."""
    m = len(ros)
    h = head_ref(ros)
    head_rate = means_ref(ros)[h]
    dist = [min(abs(i - h), m - abs(i - h)) * spacing for i in range(m)]
    if fast_fraction > 0 and head_rate > 0:
        r = [_clean(v) for v in ros]
        for step in (1, -1):
            n = 0
            while n < m // 2 and r[(h + step * (n + 1)) % m] >= fast_fraction * head_rate:
                n += 1
            half = max(half, n * spacing)
    arc = [d <= min(half, 0.25 * m * spacing) for d in dist]
    holder = dist[0] < dist[peer] or (dist[0] == dist[peer] and mine_on_tie)
    owned = [a if holder else not a for a in arc]
    owned[0] = True
    return owned


rates = st.lists(st.sampled_from([0.0, 1.0, 2.0, 3.0, 5.0, 8.0, -1.0, math.nan]), min_size=1, max_size=40)


@settings(max_examples=300, deadline=None)
@given(rates, st.integers(0, 4))
def test_head_index_is_the_first_largest_circular_mean(ros, smooth) -> None:
    assert head_index(np.array(ros), smooth) == head_ref(ros, smooth)


@settings(max_examples=300, deadline=None)
@given(
    rates.filter(lambda r: len(r) >= 2),
    st.sampled_from([1.0, 5.0, 30.0]),
    st.data(),
    st.sampled_from([0.0, 10.0, 35.0, 157.5, 1e6]),
    st.booleans(),
    st.sampled_from([0.0, 0.3, 0.5, 1.0]),
)
def test_relay_split_is_its_rule_by_loops(ros, spacing, data, half, tie, fast) -> None:
    peer = data.draw(st.integers(1, len(ros) - 1))
    got = relay_split(np.array(ros), spacing, peer, half, tie, fast)
    assert got.tolist() == relay_ref(ros, spacing, peer, half, tie, fast)


def test_bad_input_is_named() -> None:
    with pytest.raises(InputError, match="non-empty 1-D"):
        head_index(np.array([]))
    with pytest.raises(InputError, match="non-empty 1-D"):
        head_index(np.ones((2, 2)))
    assert head_index(np.array([4.0])) == 0  # one cell: its own head
    with pytest.raises(InputError, match="1-D"):
        relay_split(np.ones((2, 2)), 5.0, 1, 10.0, True)
    with pytest.raises(InputError, match=r"1 \.\. 3"):
        relay_split(np.ones(4), 5.0, 4, 10.0, True)
    with pytest.raises(InputError, match="spacing_m"):
        relay_split(np.ones(4), 0.0, 1, 10.0, True)
    with pytest.raises(InputError, match="head_half_m"):
        relay_split(np.ones(4), 5.0, 1, -1.0, True)
    assert relay_split(np.ones(1), 5.0, 1, 10.0, True).tolist() == [True]


def test_the_arc_is_widened_only_when_asked_and_nan_or_slow_cells_are_not_fast() -> None:
    ros = np.array([0.0, 0.0, 3.0, 3.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    # peer far from the head, we are the holder (cell 0 is 3 cells from the head at cell 3)
    plain = relay_split(ros, 1.0, 7, 0.0, True)  # fast_fraction left at its default
    assert plain.tolist() == relay_ref(ros.tolist(), 1.0, 7, 0.0, True, 0.0)
    assert plain[1:].sum() == 1  # no widening: the head cell alone (and our own cell)
    # a NaN beside a 3 m/s head at fraction 0.3 (0.9 m/s) is not fast; neither is a 0 m/s cell
    # (head at cell 2, the stretch 2-4 fast, the cap a quarter of 12 cells: 3 cells)
    for tail in (math.nan, 0.0):
        ros2 = [0.0, 0.0, 3.0, 3.0, 3.0, tail, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        got = relay_split(np.array(ros2), 1.0, 9, 0.0, True, 0.3)
        assert got.tolist() == relay_ref(ros2, 1.0, 9, 0.0, True, 0.3)
        assert got[2:5].all() and not got[5]  # widened over the stretch, not over cell 5


def test_a_one_cell_perimeter_is_owned_as_a_bool_mask() -> None:
    got = relay_split(np.array([2.0]), 5.0, 1, 10.0, False)
    assert got.dtype == bool and got.tolist() == [True]


def test_a_head_cell_reading_0_does_not_widen_the_arc_to_the_cap() -> None:
    """Two fast pairs with a 0 between: the +-2-cell mean peaks on the 0 cell (4, 4, 0, 4, 4:
    3.2 m/s, against 2.4 one cell either side), so the head is cell 4 and its own rate is 0.
    Against its smoothed 3.2 m/s at fraction 0.5 (1.6 m/s) the fast stretch is cells 2-6, the
    four 4 m/s cells about it; compared with the cell's own 0, every cell is "fast" and the arc
    is the cap, 10 cells each side (the old rule's 21 cells)."""
    ros = [0.0] * 40
    ros[2:4] = ros[5:7] = [4.0, 4.0]
    assert head_index(np.array(ros)) == 4 and ros[4] == 0.0
    # we (cell 0) are 4 cells from the head, the peer at cell 20 is 16: we hold
    got = relay_split(np.array(ros), 1.0, 20, 0.0, True, 0.5)
    assert np.flatnonzero(got).tolist() == [0, 2, 3, 4, 5, 6]
    # and no spread known about the head: nothing is widened (the head cell alone)
    zero = relay_split(np.zeros(40), 1.0, 20, 0.0, True, 0.5)
    assert np.flatnonzero(zero).tolist() == [0]
