"""Peer link against hostile and corrupted messages.

Truth is the attack and properties of the protocol, not the implementation's rules: a
genuine peer sends one state per step with sequence step + 1 (docs/protocol.md), so whatever else
arrives, its message of the step being looked at must be accepted, and a peer heard every step
must never be declared crashed.
"""

import math

import pytest
from fire_uav_agent.peer_link import PeerFires, PeerLink, PeerState, Verdict
from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

U32 = 2**32 - 1


def genuine(j: int, step: int, x: float = 1.0) -> PeerState:
    return PeerState(j, step + 1, step, x, 2.0, 30.0, 0.1, 1)


def test_issue_attack_forged_max_sequence_does_not_shut_a_peer_out():
    """A replay: one UavState for UAV 1 with sequence 2**32-1 mid-mission."""
    link = PeerLink(0, 5, seed=1, loss_probability=0.0, control_period_s=0.1)
    rejected_genuine = 0
    for k in range(1, 400):
        inbox = [genuine(j, k - 1) for j in (1, 2, 3, 4)]
        if k == 50:
            inbox.insert(0, PeerState(1, U32, k - 1, 5.0, 5.0, 30.0, 0.0, 1))
        for m in inbox:
            v = link.receive_state(m, now_step=k)
            if m.sequence != U32 and v != Verdict.ACCEPTED:
                rejected_genuine += 1
        assert link.end_step(k) == []  # nobody is ever declared crashed
    assert rejected_genuine == 0
    assert link.reject_reasons == {"implausible sequence": 1}
    assert link.alive_ids() == [0, 1, 2, 3, 4]


def test_forged_far_future_step_is_rejected_and_does_not_block():
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(PeerState(1, 1000, 999, 0.0, 0.0, 0.0, 0.0, 1), now_step=5) == Verdict.REJECTED
    assert link.receive_state(genuine(1, 4), now_step=5) == Verdict.ACCEPTED
    assert link.reject_reasons == {"implausible step": 1}


def test_restarted_peer_is_accepted_and_counted():
    """A peer process restarted at step 200 starts its sequence again at 1."""
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1)
    for k in range(1, 100):
        assert link.receive_state(genuine(1, k - 1), now_step=k) == Verdict.ACCEPTED
    assert link.receive_state(PeerState(1, 1, 199, 0.0, 0.0, 0.0, 0.0, 1), now_step=200) == Verdict.ACCEPTED
    assert link.receive_state(PeerState(1, 2, 200, 0.0, 0.0, 0.0, 0.0, 1), now_step=201) == Verdict.ACCEPTED
    assert link.restarts == 1 and link.rejected == 0


def test_each_rejection_kind_counted_separately():
    link = PeerLink(0, 3, seed=1, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(genuine(1, 9), now_step=10) == Verdict.ACCEPTED
    cases = {
        "unknown id": PeerState(9, 10, 9, 0.0, 0.0, 0.0, 0.0, 1),
        "own id": genuine(0, 9),
        "negative step": PeerState(2, 1, -3, 0.0, 0.0, 0.0, 0.0, 1),
        "implausible step": genuine(2, 10),
        "implausible sequence": PeerState(2, 0, 9, 0.0, 0.0, 0.0, 0.0, 1),
        "nan/inf": genuine(2, 9, x=math.nan),
        "duplicate": genuine(1, 9),
        "unknown objective": PeerState(2, 10, 9, 0.0, 0.0, 0.0, 0.0, 200),
    }
    for m in cases.values():
        assert link.receive_state(m, now_step=10) == Verdict.REJECTED
    link.receive_state(genuine(2, 9), now_step=10)
    assert link.receive_state(genuine(2, 8), now_step=10) == Verdict.REJECTED
    assert link.reject_reasons == {k: 1 for k in [*cases, "old step"]}
    assert link.rejected == len(cases) + 1


def test_step_window_configuration():
    with pytest.raises(ValueError, match="max_step_lag"):
        PeerLink(0, 2, 0, 0.0, 0.1, max_step_lag=0)


# --- session 21's mutation survivors, each against the protocol's rule ----------------------
def test_default_crash_threshold_is_the_protocols_ten_steps():
    """docs/protocol.md "Peer link": a peer is declared crashed when ``missed`` reaches 10."""
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1)
    assert [link.end_step(k) for k in range(1, 10)] == [[]] * 9
    assert [(e.kind, e.peer_id, e.step) for e in link.end_step(10)] == [("crashed", 1, 10)]


def test_a_rejoin_event_carries_its_step():
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1, crash_threshold_steps=1)
    assert [(e.kind, e.step) for e in link.end_step(3)] == [("crashed", 3)]
    assert link.receive_state(genuine(1, 3), now_step=4) == Verdict.ACCEPTED
    assert [(e.kind, e.peer_id, e.step) for e in link.end_step(4)] == [("rejoined", 1, 4)]


def test_expected_skips_only_the_crashed_peer():
    """Peer 1 crashed: the wait still holds out for the state and fires of peers 2 and 3."""
    link = PeerLink(0, 4, seed=1, loss_probability=0.0, control_period_s=0.1, crash_threshold_steps=1)
    for j in (2, 3):
        link.receive_state(genuine(j, 0), now_step=1)
    link.end_step(1)
    assert link.crashed_ids() == [1]
    state_i, fires_i = FLEET_STATE_SPEC.loss_index, FLEET_FIRES_SPEC.loss_index
    assert link.expected(1) == {(2, state_i), (2, fires_i), (3, state_i), (3, fires_i)}


def test_a_sender_id_equal_to_the_fleet_size_is_unknown():
    """Ids are 0..N-1: id N is rejected as unknown, not looked up (no such peer)."""
    link = PeerLink(0, 3, seed=1, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(genuine(3, 4), now_step=5) == Verdict.REJECTED
    assert link.receive_fires(PeerFires(3, 5, 4, ()), now_step=5) == Verdict.REJECTED
    assert link.reject_reasons == {"unknown id": 2}


def test_every_restart_is_counted_and_an_unchanged_sequence_at_a_newer_step_is_one():
    """A running peer's sequence rises by one per step (one state per step from step 0 on), so a
    newer step with the same sequence, as with a lower one, means its process started again."""
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(PeerState(1, 3, 2, 0.0, 0.0, 0.0, 0.0, 1)) == Verdict.ACCEPTED
    assert link.receive_state(PeerState(1, 3, 7, 0.0, 0.0, 0.0, 0.0, 1)) == Verdict.ACCEPTED
    assert link.restarts == 1
    assert link.receive_state(PeerState(1, 1, 20, 0.0, 0.0, 0.0, 0.0, 1)) == Verdict.ACCEPTED
    assert link.restarts == 2 and link.rejected == 0


def test_fires_are_held_to_the_step_window_too():
    link = PeerLink(0, 2, seed=1, loss_probability=0.0, control_period_s=0.1, max_step_lag=3)
    assert link.receive_fires(PeerFires(1, 7, 6, ()), now_step=10) == Verdict.REJECTED  # oldest is 7
    assert link.receive_fires(PeerFires(1, 10, 10, ()), now_step=10) == Verdict.REJECTED  # not run yet
    assert link.receive_fires(PeerFires(1, 8, 7, ()), now_step=10) == Verdict.ACCEPTED
    assert link.reject_reasons == {"implausible step": 2}
