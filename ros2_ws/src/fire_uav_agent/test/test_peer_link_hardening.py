"""Peer link against hostile and corrupted messages.

Truth is the attack and properties of the protocol, not the implementation's rules: a
genuine peer sends one state per step with sequence step + 1 (docs/protocol.md), so whatever else
arrives, its message of the step being looked at must be accepted, and a peer heard every step
must never be declared crashed.
"""

import math

import pytest
from fire_uav_agent.peer_link import PeerLink, PeerState, Verdict

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
