"""The lockstep offline schedule."""

from __future__ import annotations

import math

import pytest
from fire_uav_common.lockstep import (
    OfflineWindow,
    first_step_at,
    format_schedule,
    offline_uavs,
    parse_schedule,
)
from hypothesis import given
from hypothesis import strategies as st


def test_parse_and_steps() -> None:
    w = parse_schedule("2@40;1@5:6.5")
    assert w == (OfflineWindow(1, 5.0, 6.5), OfflineWindow(2, 40.0, math.inf))
    # 0.1 s steps: step k starts at k * 0.1 s; offline from step 50 to 64 inclusive
    assert w[0].steps(0.1) == (50, 65)
    assert offline_uavs(w, 49, 0.1) == frozenset()
    assert offline_uavs(w, 50, 0.1) == {1}
    assert offline_uavs(w, 64, 0.1) == {1}
    assert offline_uavs(w, 65, 0.1) == frozenset()
    assert offline_uavs(w, 400, 0.1) == {2}
    assert offline_uavs(w, 10**6, 0.1) == {2}
    assert parse_schedule("") == () and parse_schedule(" ; ") == ()


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("x@1", "expected K@T1:T2"),
        ("1@a:2", "expected K@T1:T2"),
        ("1@3:2", "need K >= 0, 0 <= T1 < T2"),
        ("-1@3", "need K >= 0"),
        ("1@-3", "0 <= T1"),
        ("1@2@3", "expected K@T1:T2"),
    ],
)
def test_parse_errors(text: str, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        parse_schedule(text)


@given(
    st.lists(
        st.tuples(
            st.integers(0, 30),
            st.floats(0, 1e4, allow_nan=False),
            st.one_of(st.none(), st.floats(1e-3, 1e4, allow_nan=False)),
        ),
        max_size=6,
    )
)
def test_format_round_trip(items: list) -> None:
    ws = tuple(OfflineWindow(u, t, math.inf if d is None else t + d) for u, t, d in items)
    ws = tuple(w for w in ws if w.end_s > w.start_s)
    assert parse_schedule(format_schedule(ws)) == tuple(
        sorted(ws, key=lambda w: (w.start_s, w.uav_id, w.end_s))
    )


@given(st.floats(0, 1e5, allow_nan=False), st.sampled_from([0.05, 0.1, 0.2, 0.25]))
def test_first_step_is_first_start_at_or_after(t_s: float, p: float) -> None:
    k = first_step_at(t_s, p)
    assert k * p >= t_s - 1e-6 * max(1.0, t_s)
    assert k == 0 or (k - 1) * p < t_s
    with pytest.raises(ValueError, match="control period must be > 0"):
        first_step_at(t_s, 0.0)
