"""The lockstep wait: exactly the messages the live peers sent at step k-1, decided by steps only."""

from __future__ import annotations

import pytest
from fire_uav_agent.lockstep_wait import STATE_INDEX as STATE
from fire_uav_agent.lockstep_wait import PeerWait
from fire_uav_common.lockstep import parse_schedule
from fire_uav_common.topics import COVERAGE_MST_SPEC, FLEET_FIRES_SPEC, FLEET_PERIMETER_SPEC

FIRES, PERIM, MST = FLEET_FIRES_SPEC.loss_index, FLEET_PERIMETER_SPEC.loss_index, COVERAGE_MST_SPEC.loss_index


def sent(perimeter: int = 0, mst: int = 0) -> tuple[int, ...]:
    c = [1, 1, perimeter, 0, 0, mst]
    return tuple(c)


def deliver(w: PeerWait, j: int, step: int, perimeter: int = 0, mst: int = 0, final: bool = False) -> None:
    w.on_state(j, step, sent(perimeter, mst), final)
    w.on_message(j, step, FIRES)
    for _ in range(perimeter):
        w.on_message(j, step, PERIM)
    for _ in range(mst):
        w.on_message(j, step, MST)


def test_waits_for_every_live_peer_state_and_what_it_announces() -> None:
    w = PeerWait(0, 3, 0.1)
    assert w.ready(0)  # step 0 answers no peer
    assert w.missing(5) == [1, 2]
    w.on_state(1, 4, sent(perimeter=1, mst=2), False)
    w.on_message(1, 4, FIRES)
    assert w.missing(5) == [1, 2]  # 1 announced a perimeter map and two MST messages
    w.on_message(1, 4, PERIM)
    w.on_message(1, 4, MST)
    assert w.missing(5) == [1, 2]
    w.on_message(1, 4, MST)
    assert w.missing(5) == [2]
    deliver(w, 2, 4)
    assert w.ready(5)
    # messages of other steps do not count for step 5
    w2 = PeerWait(0, 2, 0.1)
    deliver(w2, 1, 3)
    deliver(w2, 1, 5)
    assert not w2.ready(5)


def test_fires_before_state_is_counted_too() -> None:
    w = PeerWait(1, 2, 0.1)
    w.on_message(0, 7, FIRES)  # DDS delivers topics in any order
    assert not w.ready(8)
    w.on_state(0, 7, sent(), False)
    assert w.ready(8)


def test_scheduled_offline_peer_is_not_waited_for_in_its_window_only() -> None:
    # peer 2 frozen from 1.0 s to 1.5 s: offline during steps 10..14 (0.1 s steps)
    w = PeerWait(0, 3, 0.1, parse_schedule("2@1.0:1.5"))
    for step in range(8, 17):
        deliver(w, 1, step)
    assert w.missing(10) == [2]  # step 9 messages: peer 2 still live at 9
    for k in range(11, 16):
        assert w.ready(k), k  # steps 10..14: only peer 1 sends
    assert w.missing(16) == [2]  # step 15: back


def test_killed_peer_is_never_waited_for_again() -> None:
    w = PeerWait(0, 2, 0.25, parse_schedule("1@2.0"))  # offline from step 8
    assert w.live_peers(7) == [1] and w.live_peers(8) == [] and w.live_peers(10**6) == []


def test_final_state_ends_the_wait_for_that_peer() -> None:
    w = PeerWait(0, 2, 0.1)
    deliver(w, 1, 20, final=True)  # its vehicle crashed during step 20
    assert w.ready(21)
    assert w.live_peers(20) == [1] and w.live_peers(21) == []
    assert w.ready(30)


def test_gone_peer_and_pruning() -> None:
    w = PeerWait(0, 3, 0.1)
    deliver(w, 1, 4)
    assert w.missing(5) == [2]
    w.mark_gone(2)
    assert w.ready(5)
    w.prune(5)
    assert w.ready(5)  # step 4 kept
    w.prune(7)
    assert not w.ready(5)  # step 4 forgotten


def test_invalid_inputs() -> None:
    with pytest.raises(ValueError, match="uav_id 3 outside 0..2"):
        PeerWait(3, 3, 0.1)
    with pytest.raises(ValueError, match="control period must be > 0"):
        PeerWait(0, 3, 0.0)
    w = PeerWait(0, 2, 0.1)
    w.on_state(7, 1, sent(), False)  # unknown sender: ignored, not a crash
    w.on_state(0, 1, sent(), False)  # itself: ignored
    assert w.missing(2) == [1]


def test_describe_names_each_missing_peer_and_what_it_still_owes() -> None:
    w = PeerWait(0, 4, 0.1)
    assert w.describe(5) == "uav 1: state of step 4; uav 2: state of step 4; uav 3: state of step 4"
    w.on_state(1, 4, sent(perimeter=2, mst=1), False)
    w.on_message(1, 4, PERIM)  # 1/2 perimeter maps, no MST message, fires not in yet
    deliver(w, 3, 4)
    assert w.describe(5) == (
        f"uav 1: 0/1 on topic {FIRES}, 1/2 on topic {PERIM}, 0/1 on topic {MST}; uav 2: state of step 4"
    )
    w.on_message(1, 4, FIRES)
    w.on_message(1, 4, PERIM)
    w.on_message(1, 4, MST)
    deliver(w, 2, 4)
    assert w.describe(5) == "" and w.ready(5)


def _missing_by_recount(w: PeerWait, arrived: dict, sent: dict, step: int) -> list[int]:
    """The rule of ``missing`` recounted from the inputs as given (an independent reference of the
    running count ``PeerWait`` keeps): a live peer is missing while its state is not in, or any
    topic has fewer arrivals than its state announced."""
    prev = step - 1
    out = []
    for j in w._live_peers(prev):
        s = sent.get((prev, j))
        got = arrived.get((prev, j), {})
        if s is None or any(got.get(t, 0) < n for t, n in enumerate(s)):
            out.append(j)
    return out


@pytest.mark.parametrize("seed", range(40))
def test_missing_equals_a_recount_over_any_arrival_order(seed: int) -> None:
    """Messages in any order: before or after their state, duplicates, topics beyond what the
    state lists, negative and unknown indexes, states announcing no topic or negative counts and
    carrying parts (any index, counted with the state), a second state replacing the first's counts, final
    states, peers gone and pruning; ``missing`` and ``ready`` must agree with a recount from scratch
    after every input (the live peers recomputed by the reference: ``_live_peers``, uncached), with
    the steps asked in any order (``ready`` keeps, per step, how far it got)."""
    import random

    rng = random.Random(seed)
    n = rng.randint(2, 6)
    w = PeerWait(uav_id=0, uav_count=n, period_s=0.1)
    arrived: dict = {}
    sent: dict = {}
    for _ in range(300):
        step, j = rng.randint(0, 3), rng.randint(1, n - 1)
        if rng.random() < 0.01:
            w.mark_gone(j)
        elif rng.random() < 0.25:
            counts = tuple(rng.randint(-1 if rng.random() < 0.2 else 0, 3) for _ in range(rng.randint(0, 5)))
            carried = tuple(rng.randint(-1, 6) for _ in range(rng.choice((0, 1, 1, 2))))
            w.on_state(j, step, counts, final=rng.random() < 0.03, carried=carried)
            sent[(step, j)] = counts
            got = arrived.setdefault((step, j), {})
            for t in (STATE, *carried):  # the state, then each part it carries
                got[t] = got.get(t, 0) + 1
        else:
            t = rng.randint(-1, 6)
            w.on_message(j, step, t)
            got = arrived.setdefault((step, j), {})
            got[t] = got.get(t, 0) + 1
        if rng.random() < 0.02:
            k = rng.randint(0, 4)
            w.prune(k)
            for d in (arrived, sent):
                for key in [key for key in d if key[0] < k - 1]:
                    del d[key]
        for s in rng.sample(range(1, 5), 4):  # ``ready`` resumes where its last call stopped
            recount = _missing_by_recount(w, arrived, sent, s)
            assert w.ready(s) == (not recount), (seed, s)
            assert w.missing(s) == recount, (seed, s)


def test_a_peers_first_final_state_stands_when_a_later_one_arrives() -> None:
    """Its vehicle crashed at step 5: a final state of step 6 arriving later (the state of the
    dead vehicle resent) does not bring it back for step 6, whose messages it never sends."""
    w = PeerWait(0, 2, 0.1)
    deliver(w, 1, 5, final=True)
    deliver(w, 1, 6, final=True)
    assert w.live_peers(5) == [1] and w.live_peers(6) == [] and w.ready(7)


def test_a_final_state_of_a_negative_step_is_ignored() -> None:
    """Steps start at 0: a (corrupt) final state stamped step -1 names no step the peer missed,
    so the peer stays live at step 0 and its step-0 messages are still waited for."""
    w = PeerWait(0, 2, 0.1)
    w.on_state(1, -1, sent(), True)
    assert w.live_peers(0) == [1]
    assert w.missing(1) == [1]
