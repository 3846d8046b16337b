"""``final_acks``: the wait before a node exits, on a fake clock (no ROS, no timing)."""

from __future__ import annotations

import math

import pytest
from fire_uav_common.errors import ArgumentError
from fire_uav_common.final_acks import (
    FINAL_ACK_CAP_WALL_S,
    FINAL_ACK_POLL_WALL_S,
    AckOutcome,
    FinalAckWait,
    published_line,
    wait_for_final_acks,
)


class _Clock:
    """A wall clock that moves only when slept on; records the sleeps."""

    def __init__(self, t0_s: float = 100.0) -> None:
        self.t_s = t0_s
        self.sleeps: list[float] = []

    def __call__(self) -> float:
        return self.t_s

    def sleep(self, s: float) -> None:
        assert s >= 0.0
        self.sleeps.append(s)
        self.t_s += s


def _wait(pending, clock: _Clock, **kw) -> AckOutcome:
    return wait_for_final_acks(pending, clock=clock, sleep=clock.sleep, **kw)


def test_nothing_pending_ends_at_once_without_a_sleep() -> None:
    clock = _Clock()
    calls = []
    done = _wait(lambda: calls.append(1) or [], clock)
    assert done == AckOutcome((), 0.0) and done.acked
    assert calls == [1] and clock.sleeps == []
    assert done.line() == "exiting: every reader has acknowledged every message (0.00 s)"


def test_it_ends_at_the_first_poll_that_finds_everything_acknowledged() -> None:
    clock = _Clock()
    acked_at = clock.t_s + 0.5  # [s wall] the readers' last acknowledgement
    done = _wait(lambda: ["/fleet/state"] if clock.t_s < acked_at else [], clock, poll_wall_s=0.02)
    assert done.acked and not done.cut_short
    assert 0.5 <= done.waited_wall_s < 0.5 + 0.02 + 1e-9  # no later than one poll after it
    assert all(s == pytest.approx(0.02) for s in clock.sleeps)


def test_at_the_cap_it_gives_up_naming_each_pending_topic_once_and_never_sleeps_past_it() -> None:
    clock = _Clock()
    done = _wait(
        lambda: ["/uav_0/payload", "/fleet/state", "/uav_0/payload"], clock, cap_wall_s=1.0, poll_wall_s=0.3
    )
    assert done.pending == ("/fleet/state", "/uav_0/payload") and not done.acked and not done.cut_short
    assert done.waited_wall_s == pytest.approx(1.0)  # 0.3 + 0.3 + 0.3 + the 0.1 left, not a fourth 0.3
    assert clock.sleeps == pytest.approx([0.3, 0.3, 0.3, 0.1])
    line = done.line()
    assert line.startswith(
        "exiting with messages not acknowledged after 1.0 s on ['/fleet/state', '/uav_0/payload']: "
    )


def test_the_default_cap_is_the_worlds_20_s() -> None:
    clock = _Clock()
    done = _wait(lambda: ["/fleet/state"], clock)
    assert done.waited_wall_s == pytest.approx(FINAL_ACK_CAP_WALL_S) == pytest.approx(20.0)
    assert sum(clock.sleeps) == pytest.approx(20.0) and max(clock.sleeps) <= FINAL_ACK_POLL_WALL_S


def test_a_second_signal_cuts_the_wait_short() -> None:
    clock = _Clock()
    signals = iter([False, False, True])
    done = _wait(lambda: ["/tf"], clock, cancelled=lambda: next(signals), poll_wall_s=0.1)
    assert done.cut_short and done.pending == ("/tf",)
    assert done.waited_wall_s == pytest.approx(0.2)
    assert "exiting at a second signal with messages not acknowledged after 0.2 s on ['/tf']" in done.line()


def test_a_signal_when_everything_is_acknowledged_is_no_cut() -> None:
    done = _wait(lambda: [], _Clock(), cancelled=lambda: True)
    assert done.acked and not done.cut_short


def test_the_rule_asked_from_a_timer() -> None:
    rule = FinalAckWait(start_wall_s=10.0, cap_wall_s=2.0)
    assert rule.check(["/a"], 11.9) is None  # wait on
    assert rule.check([], 11.0) == AckOutcome((), 1.0)
    assert rule.check(["/a"], 12.0) == AckOutcome(("/a",), 2.0)  # the cap itself ends it
    assert rule.check(["/a"], 9.0) is None  # a clock read before the start counts as no wait
    assert FinalAckWait(0.0, 0.0).check(["/a"], 0.0) == AckOutcome(("/a",), 0.0)  # cap 0: one look


@pytest.mark.parametrize("cap", [-1.0, math.nan])
def test_a_bad_cap_is_refused(cap: float) -> None:
    with pytest.raises(ArgumentError, match="cap_wall_s must be >= 0"):
        FinalAckWait(0.0, cap)


@pytest.mark.parametrize("poll", [0.0, -0.1, math.nan])
def test_a_bad_poll_period_is_refused(poll: float) -> None:
    with pytest.raises(ArgumentError, match="poll_wall_s must be > 0"):
        wait_for_final_acks(lambda: [], poll_wall_s=poll)


def test_the_published_line() -> None:
    assert published_line({"/uav_1/cmd": 31, "/fleet/state": 31, "/parameter_events": 0}) == (
        "published: /fleet/state 31, /parameter_events 0, /uav_1/cmd 31"
    )
    assert published_line({}) == "published: nothing"


def test_a_second_signal_exactly_at_the_cap_is_the_cap_not_a_cut() -> None:
    """At the cap the wait has ended by the cap, whatever else happened in that instant: the line
    must not blame a second signal."""
    out = FinalAckWait(10.0, cap_wall_s=5.0).check(["/fleet/state"], 15.0, cut_short=True)
    assert out is not None and not out.cut_short and out.pending == ("/fleet/state",)


def test_the_warning_says_what_a_reader_may_lack() -> None:
    out = AckOutcome(("/a", "/b"), 20.0)
    assert out.line() == (
        "exiting with messages not acknowledged after 20.0 s on ['/a', '/b']: a reader of those "
        "topics (a frozen or killed process?) may lack the last of them"
    )
