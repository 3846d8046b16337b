"""Peer link (docs/protocol.md): loss rate, outages, validation, crash after exactly 10 misses, rejoin."""

import math

import pytest
from fire_uav_agent.peer_link import (
    FireEntry,
    Outage,
    PeerFires,
    PeerLink,
    PeerState,
    Verdict,
)
from fire_uav_common.topics import FLEET_STATE_SPEC


def state(j: int, seq: int, step: int, x: float = 1.0) -> PeerState:
    return PeerState(j, seq, step, x, 2.0, 30.0, 0.1, 1)


def test_loss_rate_matches_probability_and_is_order_independent():
    link = PeerLink(0, 2, seed=3, loss_probability=0.05, control_period_s=0.1)
    n = 4000
    lost = sum(link.receive_state(state(1, k + 1, k)) == Verdict.LOST for k in range(n))
    # binomial(4000, 0.05): sd = 13.8; 5 sd bounds (0.05 +- 0.017: p = 0.03 or 0.07 is outside)
    assert abs(lost - 0.05 * n) < 5 * math.sqrt(n * 0.05 * 0.95)
    assert link.lost == lost and link.received == n - lost and link.rejected == 0
    other = PeerLink(0, 2, seed=3, loss_probability=0.05, control_period_s=0.1)
    assert [other.is_lost(1, k, FLEET_STATE_SPEC.loss_index) for k in reversed(range(200))] == [
        link.is_lost(1, k, FLEET_STATE_SPEC.loss_index) for k in reversed(range(200))
    ]


def test_bad_messages_rejected_and_counted():
    link = PeerLink(1, 3, seed=0, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(state(0, 1, 0)) == Verdict.ACCEPTED
    assert link.receive_state(state(0, 1, 0)) == Verdict.REJECTED  # a second state of step 0
    assert link.receive_state(state(7, 1, 1)) == Verdict.REJECTED  # unknown id
    assert link.receive_state(state(1, 1, 1)) == Verdict.REJECTED  # own id
    assert link.receive_state(state(2, 1, 1, x=math.nan)) == Verdict.REJECTED
    bad_fire = FireEntry(5, True, 1.0, math.inf, 3.0)
    assert link.receive_fires(PeerFires(2, 1, 1, (bad_fire,))) == Verdict.REJECTED
    assert link.rejected == 5 and link.received == 1
    assert link.reject_reasons == {"duplicate": 1, "unknown id": 1, "own id": 1, "nan/inf": 2}


def test_crash_declared_at_exactly_threshold_and_rejoin():
    link = PeerLink(0, 3, seed=0, loss_probability=0.0, control_period_s=0.1, crash_threshold_steps=10)
    seq = 0
    for k in range(1, 6):  # both peers heard
        for j in (1, 2):
            link.receive_state(state(j, k, k - 1))
        assert link.end_step(k) == []
    seq = 5
    events = []
    for k in range(6, 30):  # peer 2 silent from step 6 on
        seq += 1
        link.receive_state(state(1, seq, k - 1))
        ev = link.end_step(k)
        events += ev
        if k < 15:
            assert link.missed(2) == k - 5 and 2 in link.alive_ids()
        if k == 15:
            assert [(e.kind, e.peer_id, e.step) for e in ev] == [("crashed", 2, 15)]
    assert len(events) == 1 and link.alive_ids() == [0, 1] and link.crashed_ids() == [2]
    assert 2 not in link.alive_states() and 2 not in {j for j, _ in link.expected(30)}
    link.receive_state(state(2, 31, 30))
    ev = link.end_step(31)
    assert [(e.kind, e.peer_id) for e in ev] == [("rejoined", 2)]
    assert link.alive_ids() == [0, 1, 2] and link.missed(2) == 0


def test_outage_drops_link_in_window_only():
    link = PeerLink(
        1, 2, seed=0, loss_probability=0.0, control_period_s=0.1, outages=(Outage(0, 1, 10.0, 20.0),)
    )
    verdicts = [link.receive_state(state(0, k + 1, k)) for k in range(300)]
    lost_steps = [k for k, v in enumerate(verdicts) if v == Verdict.LOST]
    assert lost_steps == list(range(99, 199))  # stamps (k+1) T in [10, 20)
    # the reverse link is untouched
    assert not PeerLink(0, 2, 0, 0.0, 0.1, outages=(Outage(0, 1, 10.0, 20.0),)).in_outage(1, 150)


def test_last_known_state_reused_while_lost():
    link = PeerLink(0, 2, seed=0, loss_probability=0.0, control_period_s=0.1)
    link.receive_state(state(1, 1, 0, x=42.0))
    link.end_step(1)
    link.end_step(2)
    assert link.alive_states()[1].x_m == 42.0 and link.missed(1) == 1


def test_invalid_configuration():
    with pytest.raises(ValueError, match="uav_id"):
        PeerLink(3, 3, 0, 0.0, 0.1)
    with pytest.raises(ValueError, match="loss_probability"):
        PeerLink(0, 3, 0, 1.5, 0.1)
