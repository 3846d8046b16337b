"""The resend protocol's bookkeeping (docs/protocol.md "Resend"), without ROS."""

import pytest
from fire_uav_agent.resend import ResendBook

S = 10**9  # ns per second


def test_the_first_copy_of_each_sender_topic_step_is_taken_and_later_ones_dropped():
    book: ResendBook[str] = ResendBook()
    assert not book.duplicate(2, 0, 7)
    assert book.duplicate(2, 0, 7) and book.duplicate(2, 0, 7)
    assert book.copies_dropped == 2
    # another sender, topic or step is another message
    assert not book.duplicate(3, 0, 7) and not book.duplicate(2, 1, 7) and not book.duplicate(2, 0, 8)
    assert book.copies_dropped == 2


T0 = 7200 * S  # a steady clock does not start at 0


def test_a_missing_peer_is_asked_once_per_interval_and_step():
    book: ResendBook[str] = ResendBook(ask_every_ns=5 * S)
    assert book.peers_to_ask([1, 4], k=10, now_ns=T0) == [1, 4]
    assert book.peers_to_ask([1, 4], k=10, now_ns=T0 + 4 * S) == []  # asked 4 s ago
    assert book.peers_to_ask([1, 4, 6], k=10, now_ns=T0 + 4 * S) == [6]  # a newly missing peer at once
    assert book.peers_to_ask([4], k=10, now_ns=T0 + 5 * S) == [4]  # 5 s later: again
    assert book.peers_to_ask([1], k=11, now_ns=T0 + 5 * S + 1) == [1]  # the next step is a new request


def test_only_the_last_steps_are_kept_and_a_request_is_served_once_per_interval():
    book: ResendBook[str] = ResendBook(keep_steps=4, resend_every_ns=2 * S)
    for step in range(1, 7):
        book.keep(step, [f"state {step}", f"fires {step}"])
    assert book.to_resend(2, now_ns=T0) is None  # older than the last 4 steps
    assert book.to_resend(3, now_ns=T0) == ["state 3", "fires 3"]
    assert book.to_resend(3, now_ns=T0 + 1 * S) is None  # one copy serves every peer asking within 2 s
    assert book.to_resend(6, now_ns=T0 + 1 * S) == ["state 6", "fires 6"]  # per step
    book.keep(7, ["state 7"])  # publishing the next step keeps the throttle of the steps still kept
    assert book.to_resend(6, now_ns=T0 + 2 * S) is None
    assert book.to_resend(3, now_ns=T0 + 2 * S) is None  # step 3 is no longer kept
    assert book.to_resend(4, now_ns=T0 + 2 * S) == ["state 4", "fires 4"]
    assert book.to_resend(9, now_ns=T0 + 9 * S) is None  # never sent
    assert book.resends_served == 3


def test_one_kept_step_and_no_throttle_are_valid_settings():
    book: ResendBook[str] = ResendBook(keep_steps=1, ask_every_ns=0, resend_every_ns=0)
    book.keep(1, ["a"])
    book.keep(2, ["b"])
    assert book.to_resend(1, now_ns=T0) is None and book.to_resend(2, now_ns=T0) == ["b"]
    assert book.to_resend(2, now_ns=T0) == ["b"]  # interval 0: every request is served
    assert book.peers_to_ask([3], k=5, now_ns=T0) == [3] and book.peers_to_ask([3], k=5, now_ns=T0) == [3]


def test_after_step_k_ran_only_steps_from_k_minus_1_are_remembered():
    book: ResendBook[str] = ResendBook()
    for step in (5, 6, 7):
        book.duplicate(1, 0, step)
    for k in (6, 7, 8):
        book.peers_to_ask([2], k=k, now_ns=T0)
    book.ran(8)
    assert book.duplicate(1, 0, 7)  # step 7 = k-1: its late copies are still dropped
    assert not book.duplicate(1, 0, 6)  # forgotten (the wait has pruned that step too)
    assert book.peers_to_ask([2], k=7, now_ns=T0 + 1) == [2]  # requests for steps 5 and 6: forgotten
    assert book.peers_to_ask([2], k=6, now_ns=T0 + 1) == [2]
    assert book.peers_to_ask([2], k=8, now_ns=T0 + 1) == []  # the current one (step 7) was not


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"keep_steps": 0}, "keep_steps must be >= 1, got 0"),
        ({"ask_every_ns": -1}, "ask_every_ns and resend_every_ns must be >= 0, got -1"),
    ],
)
def test_bad_settings_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        ResendBook(**kw)
