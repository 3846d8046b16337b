"""Peer link (docs/protocol.md): loss rate, outages, validation, crash after exactly 10 misses, rejoin."""

import math

import pytest
from fire_uav_agent.peer_link import (
    FireEntry,
    PeerFires,
    PeerLink,
    PeerState,
    Verdict,
)
from fire_uav_common.scenario import LinkOutage
from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC


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


def test_kept_draws_are_the_draws_whatever_the_order_and_eviction():
    """is_lost computes and keeps blocks of draws: every answer is still rng.bernoulli of its arguments.

    Asked in a shuffled order over 140 steps (so tables of 64 steps are evicted and asked
    again), for every sender, topic index and step, with an outage in the middle that no kept
    draw hides, and across the blocks' edges (63/64, 127/128).
    """
    import random

    from fire_uav_agent import peer_link as pl
    from fire_uav_common import rng

    link = PeerLink(
        2, 5, seed=9, loss_probability=0.4, control_period_s=0.1, outages=(LinkOutage(3, 2, 1.0, 2.0),)
    )
    asks = [(j, k, t) for j in (0, 1, 3, 4) for k in range(140) for t in (0, 1, 2, 6)] * 2
    random.Random(4).shuffle(asks)
    for j, k, t in asks:
        outage = j == 3 and 1.0 <= (k + 1) * 0.1 < 2.0
        want = outage or rng.bernoulli(0.4, 9, "loss", j, 2, k, t)
        assert link.is_lost(j, k, t) == want, (j, k, t)
    assert len(link._blocks) <= pl._BLOCKS_KEPT


def test_a_block_of_draws_is_computed_once(monkeypatch):
    """The lockstep wait and the receipt ask for the same draws: a block is computed once per topic."""
    import fire_uav_agent.peer_link as pl

    calls = []
    real = pl.rng.uniform_table
    monkeypatch.setattr(pl.rng, "uniform_table", lambda *a: calls.append(a) or real(*a))
    link = PeerLink(0, 3, seed=2, loss_probability=0.5, control_period_s=0.1)
    first = link.expected(7)
    assert len(calls) == 2  # 2 topic indices, one block each
    assert link.expected(7) == first and [link.is_lost(j, 7, t) for j in (1, 2) for t in (0, 1)]
    assert link.expected(8) is not None and len(calls) == 2  # step 8: the same block
    link.is_lost(1, pl._BLOCK_STEPS, 0)
    assert calls[-1] == (2, "loss", range(3), 0, range(pl._BLOCK_STEPS, 2 * pl._BLOCK_STEPS), 0)
    assert len(calls) == 3


def test_is_lost_is_rng_bernoulli_outside_the_tables_too():
    """Arguments no table covers (an id outside the fleet, a negative or 33-bit step or topic,
    a seed above 32 bits) are the single draw: the same answer or the same error."""
    from fire_uav_common import rng
    from fire_uav_common.errors import ArgumentError

    link = PeerLink(1, 4, seed=5, loss_probability=0.5, control_period_s=0.1)
    for j, k, t in [(0, 2**32 - 1, 0), (0, 2**32 - 70, 1), (7, 3, 0), (2, 10, 2**32 - 1)]:
        assert link.is_lost(j, k, t) == rng.bernoulli(0.5, 5, "loss", j, 1, k, t), (j, k, t)
    big = PeerLink(1, 4, seed=2**33 + 1, loss_probability=0.5, control_period_s=0.1)
    for k in range(100):
        assert big.is_lost(0, k, 0) == rng.bernoulli(0.5, 2**33 + 1, "loss", 0, 1, k, 0)
    for j, k, t in [(0, -1, 0), (-1, 3, 0), (0, 3, -1)]:
        with pytest.raises(ArgumentError):
            link.is_lost(j, k, t)
    assert not PeerLink(1, 4, seed=5, loss_probability=0.0, control_period_s=0.1).is_lost(0, -1, 0)
    assert PeerLink(1, 4, seed=5, loss_probability=1.0, control_period_s=0.1).is_lost(0, 3, 0)


def test_a_numpy_integer_step_draws_what_the_same_int_draws():
    """A numpy integer step (np.int64: what a step read from an array is) is the same message as
    the int: the single draw, as numpy's own generator gives it, whichever tables are kept."""
    import numpy as np

    link = PeerLink(1, 4, seed=5, loss_probability=0.5, control_period_s=0.1)
    for k in range(64, 128):  # block 1's tables for both topics
        link.is_lost(0, k, 0), link.is_lost(0, k, 1)
    for t in (0, 1):
        for j in (0, 2, 3):
            for k in range(64):
                want = (
                    np.random.default_rng(np.random.SeedSequence([5, _loss_key(), j, 1, k, t])).random() < 0.5
                )
                assert link.is_lost(j, np.int64(k), t) == want, (j, k, t)
                assert link.is_lost(j, k, t) == want, (j, k, t)


def _loss_key() -> int:
    from fire_uav_common.rng import _key

    return _key("loss")


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
        1, 2, seed=0, loss_probability=0.0, control_period_s=0.1, outages=(LinkOutage(0, 1, 10.0, 20.0),)
    )
    verdicts = [link.receive_state(state(0, k + 1, k)) for k in range(300)]
    lost_steps = [k for k, v in enumerate(verdicts) if v == Verdict.LOST]
    assert lost_steps == list(range(99, 199))  # stamps (k+1) T in [10, 20)
    # the reverse link is untouched
    assert not PeerLink(0, 2, 0, 0.0, 0.1, outages=(LinkOutage(0, 1, 10.0, 20.0),)).in_outage(1, 150)


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


# --- boundaries of each rule (docs/protocol.md "Peer link"; mutation testing) ----------------
def fires(j: int, seq: int, step: int, *entries: FireEntry) -> PeerFires:
    return PeerFires(j, seq, step, tuple(entries))


def test_step_window_and_sequence_bounds_are_inclusive():
    """Run step k accepts steps in [k - max_step_lag, k - 1] and sequences in [1, step + 1]."""
    link = PeerLink(0, 2, seed=0, loss_probability=0.0, control_period_s=0.1, max_step_lag=3)
    assert link.receive_state(state(1, 1, 6), now_step=10) == Verdict.REJECTED  # 10 - 3 = 7 is the oldest
    assert link.receive_state(state(1, 8, 7), now_step=10) == Verdict.ACCEPTED
    assert link.receive_state(state(1, 10, 9), now_step=10) == Verdict.ACCEPTED  # seq = step + 1
    assert link.receive_state(state(1, 12, 10), now_step=11) == Verdict.REJECTED  # seq = step + 2
    assert link.receive_state(state(1, 1, 10), now_step=11) == Verdict.ACCEPTED  # seq 1: a restart
    assert link.reject_reasons == {"implausible step": 1, "implausible sequence": 1} and link.restarts == 1
    # the default window is the crash threshold: a message 10 steps old is still news
    default = PeerLink(0, 2, seed=0, loss_probability=0.0, control_period_s=0.1, crash_threshold_steps=10)
    assert default.receive_state(state(1, 1, 0), now_step=10) == Verdict.ACCEPTED
    assert default.receive_state(state(1, 2, 1), now_step=12) == Verdict.REJECTED
    # without now_step there is no window, only the other checks
    assert default.receive_state(state(1, 3, 500)) == Verdict.ACCEPTED


def test_every_field_is_checked_for_nan_and_inf():
    link = PeerLink(0, 2, seed=0, loss_probability=0.0, control_period_s=0.1)
    base = dict(
        uav_id=1, sequence=1, step=0, x_m=1.0, y_m=2.0, z_m=3.0, yaw_rad=0.1, objective=1, water_kg=5.0
    )
    for k, name in enumerate(("x_m", "y_m", "z_m", "yaw_rad", "water_kg")):
        bad = PeerState(**{**base, "step": k, "sequence": k + 1, name: math.inf})
        assert link.receive_state(bad) == Verdict.REJECTED, name
    good = FireEntry(1, True, 1.0, 2.0, 3.0, 0.1, 0.2, 0.3)
    fields = ("x_m", "y_m", "extent_m", "vx_mps", "vy_mps", "last_measurement_s")
    for k, name in enumerate(fields):
        bad = FireEntry(**{**good.__dict__, name: math.nan})
        assert link.receive_fires(fires(1, k + 1, k, good, bad)) == Verdict.REJECTED, name
    assert link.reject_reasons == {"nan/inf": 5 + len(fields)} and link.received == 0
    assert link.receive_fires(fires(1, 1, 0, good)) == Verdict.ACCEPTED  # NaN front: not exchanged
    assert link.alive_fires()[1].fires == (good,)


def test_finite_is_kept_per_message_and_is_every_receivers_answer():
    """finite() is kept on the message once asked (the harness hands one object to every
    receiver): each receiver gets the answer of the fields, a copy with a NaN is judged on its
    own, and a state's cached answer is not its fire picture's (or another state's)."""
    import dataclasses

    good = PeerState(1, 1, 0, 1.0, 2.0, 3.0, 0.1, 1, water_kg=5.0)
    assert good.finite() and good.finite()
    for name in ("x_m", "y_m", "z_m", "yaw_rad", "water_kg"):
        bad = dataclasses.replace(good, **{name: math.nan})
        assert not bad.finite() and not bad.finite() and good.finite(), name
    assert good == PeerState(1, 1, 0, 1.0, 2.0, 3.0, 0.1, 1, water_kg=5.0)  # the cache is not a field
    ok = FireEntry(1, True, 1.0, 2.0, 3.0)
    pic = PeerFires(1, 1, 0, (ok,))
    assert pic.finite()
    nan_pic = PeerFires(1, 1, 0, (ok, dataclasses.replace(ok, vy_mps=math.inf)))
    assert not nan_pic.finite() and pic.finite() and PeerFires(1, 1, 0).finite()
    links = [PeerLink(i, 3, seed=0, loss_probability=0.0, control_period_s=0.1) for i in (0, 2)]
    for link in links:  # the same objects to both receivers
        assert link.receive_state(dataclasses.replace(good, x_m=math.inf)) == Verdict.REJECTED
        assert link.receive_fires(nan_pic) == Verdict.REJECTED
        assert link.receive_state(good) == Verdict.ACCEPTED and link.receive_fires(pic) == Verdict.ACCEPTED


def test_a_lost_message_is_never_also_rejected_but_a_bad_id_is_rejected_before_the_draw():
    link = PeerLink(0, 3, seed=0, loss_probability=1.0, control_period_s=0.1)
    assert link.receive_state(state(1, 1, 0, x=math.nan)) == Verdict.LOST
    assert link.receive_fires(fires(2, 1, 0)) == Verdict.LOST
    assert link.receive_state(state(5, 1, 0)) == Verdict.REJECTED
    assert (link.lost, link.rejected, link.received) == (2, 1, 0)
    assert link.expected(3) == set()
    clear = PeerLink(0, 3, seed=0, loss_probability=0.0, control_period_s=0.1)
    st_i, fi_i = FLEET_STATE_SPEC.loss_index, FLEET_FIRES_SPEC.loss_index
    assert clear.expected(3) == {(1, st_i), (1, fi_i), (2, st_i), (2, fi_i)}


def test_loss_draws_differ_per_topic_and_per_receiver():
    """Independent draws per (sender, receiver, step, topic): at p = 0.5 the state and fires
    messages of a step, or the same message at two receivers, agree about half the time."""
    a = PeerLink(0, 3, seed=5, loss_probability=0.5, control_period_s=0.1)
    b = PeerLink(1, 3, seed=5, loss_probability=0.5, control_period_s=0.1)
    st_i, fi_i = FLEET_STATE_SPEC.loss_index, FLEET_FIRES_SPEC.loss_index
    n = 400  # binomial(400, 0.5): sd 10; 5 sd
    same_topic = sum(a.is_lost(2, k, st_i) == a.is_lost(2, k, fi_i) for k in range(n))
    same_rx = sum(a.is_lost(2, k, st_i) == b.is_lost(2, k, st_i) for k in range(n))
    seed = sum(a.is_lost(2, k, st_i) == PeerLink(0, 3, 6, 0.5, 0.1).is_lost(2, k, st_i) for k in range(n))
    assert all(abs(c - n / 2) < 50 for c in (same_topic, same_rx, seed)), (same_topic, same_rx, seed)


def test_state_and_fires_are_ordered_per_topic():
    link = PeerLink(0, 2, seed=0, loss_probability=0.0, control_period_s=0.1)
    assert link.receive_state(state(1, 5, 4)) == Verdict.ACCEPTED
    assert link.receive_fires(fires(1, 5, 4)) == Verdict.ACCEPTED  # same step, other topic
    assert link.receive_fires(fires(1, 5, 4)) == Verdict.REJECTED
    assert link.receive_fires(fires(1, 4, 3)) == Verdict.REJECTED
    assert link.reject_reasons == {"duplicate": 1, "old step": 1}
    assert link.received == 2 and link.alive_fires()[1].step == 4 and link.alive_states()[1].step == 4


def test_only_states_keep_a_peer_alive_and_a_threshold_of_one_crashes_at_once():
    link = PeerLink(0, 3, seed=0, loss_probability=0.0, control_period_s=0.1, crash_threshold_steps=1)
    link.receive_state(state(1, 1, 0))
    link.receive_fires(fires(2, 1, 0))  # fires alone do not count as heard
    ev = link.end_step(1)
    assert [(e.kind, e.peer_id, e.step) for e in ev] == [("crashed", 2, 1)]
    assert link.crashed_ids() == [2] and link.alive_fires() == {} and link.missed(2) == 1
    assert link.end_step(2)[0].peer_id == 1  # 1 silent now
    assert link.end_step(3) == [] and link.missed(1) == 2  # crashed once, not again


def test_invalid_link_configuration_names_the_field():
    with pytest.raises(ValueError, match="uav_id -1 outside 0..2"):
        PeerLink(-1, 3, 0, 0.0, 0.1)
    with pytest.raises(ValueError, match="loss_probability must be in"):
        PeerLink(0, 3, 0, -0.1, 0.1)
    PeerLink(0, 3, 0, 1.0, 0.1)  # both ends of [0, 1] are fine
    with pytest.raises(ValueError, match="crash_threshold_steps must be >= 1"):
        PeerLink(0, 3, 0, 0.0, 0.1, crash_threshold_steps=0)
    with pytest.raises(ValueError, match="seed must be >= 0"):
        PeerLink(0, 3, -1, 0.0, 0.1)
    with pytest.raises(ValueError, match="outage ids must be >= 0"):
        LinkOutage(-1, 0, 0.0, 1.0)
    with pytest.raises(ValueError, match="outage ids must be >= 0"):
        LinkOutage(0, -1, 0.0, 1.0)
    with pytest.raises(ValueError, match="outage end_s 1.0 before start_s 2.0"):
        LinkOutage(0, 1, 2.0, 1.0)
    assert LinkOutage(0, 1, 1.0, 1.0).end_s == 1.0  # an empty window is allowed


def _numpy_loss(p: float, seed: int, sender: int, receiver: int, step: int, topic: int) -> bool:
    """docs/protocol.md's loss draw written with numpy alone: the first random() of the
    SeedSequence (seed, crc32("loss"), sender, receiver, step, topic) below p."""
    import zlib

    import numpy as np

    words = [seed, zlib.crc32(b"loss"), sender, receiver, step, topic]
    return bool(np.random.default_rng(np.random.SeedSequence(words)).random() < p)


def test_senders_outside_the_fleet_and_33_bit_steps_are_the_single_draw_beside_a_table():
    """Once a table of the block exists, a sender outside the fleet (uav_count, above it) still
    gets its own draw (numpy's), a negative sender is refused, and steps of 2**32 and more
    (numpy splits them into two words) are drawn singly, not tabled."""
    from fire_uav_common.errors import ArgumentError

    link = PeerLink(1, 4, seed=5, loss_probability=0.37, control_period_s=0.1)
    # sender uav_count on a block with no table yet: the single draw, no table built for it
    assert [link.is_lost(4, k, 0) for k in range(128, 192)] == [
        _numpy_loss(0.37, 5, 4, 1, k, 0) for k in range(128, 192)
    ]
    assert not link._blocks
    for t in (0, 1):
        assert link.is_lost(0, 0, t) == _numpy_loss(0.37, 5, 0, 1, 0, t)  # the block's table
        got = [link.is_lost(j, k, t) for j in (4, 5, 9) for k in range(64)]
        assert got == [_numpy_loss(0.37, 5, j, 1, k, t) for j in (4, 5, 9) for k in range(64)]
        with pytest.raises(ArgumentError):
            link.is_lost(-1, 3, t)
    for k in (2**32, 2**32 + 5, 2**33):
        assert [link.is_lost(j, k, 0) for j in (0, 2, 3)] == [
            _numpy_loss(0.37, 5, j, 1, k, 0) for j in (0, 2, 3)
        ]


def test_every_draw_in_the_fleet_and_the_32_bit_range_comes_from_one_table(monkeypatch):
    """The edges of the tabled range: senders 0 and uav_count - 1, topic 2**32 - 1, a seed of
    2**32 - 1 and the last block of 32-bit steps (2**32 - 64 .. 2**32 - 1) are each one
    uniform_table pass per (block, topic) and no single draw, asked again no pass at all; every
    answer is numpy's draw."""
    import fire_uav_agent.peer_link as pl

    tables, singles = [], []
    real_table, real_single = pl.rng.uniform_table, pl.rng.bernoulli
    monkeypatch.setattr(pl.rng, "uniform_table", lambda *a: tables.append(a) or real_table(*a))
    monkeypatch.setattr(pl.rng, "bernoulli", lambda *a: singles.append(a) or real_single(*a))
    top = 2**32 - 1
    link = PeerLink(2, 3, seed=top, loss_probability=0.5, control_period_s=0.1)
    asks = [(j, k, t) for k in (0, 63, top - 63, top - 1, top) for t in (0, top) for j in (0, 1)]
    for n in range(2):
        for j, k, t in asks:
            assert link.is_lost(j, k, t) == _numpy_loss(0.5, top, j, 2, k, t), (j, k, t)
        assert len(tables) == 4 and not singles, n  # 2 blocks x 2 topics, the first time only


def test_no_outage_scheduled_is_never_an_outage_and_a_draw_equal_to_p_is_kept():
    """in_outage with no schedule is False for every sender and step (docs/protocol.md: only the
    scheduled windows cut a link); a loss draw exactly equal to the loss probability is not a
    loss (P(u < p) = p for u uniform on [0, 1)), one just above it is."""
    import math

    from fire_uav_common import rng

    link = PeerLink(0, 3, seed=4, loss_probability=0.5, control_period_s=0.1)
    assert not any(link.in_outage(j, k) for j in (1, 2) for k in range(-5, 200))
    u = rng.uniform(4, "loss", 2, 0, 10, 1)
    assert not PeerLink(0, 3, seed=4, loss_probability=u, control_period_s=0.1).is_lost(2, 10, 1)
    assert PeerLink(0, 3, seed=4, loss_probability=math.nextafter(u, 1.0), control_period_s=0.1).is_lost(
        2, 10, 1
    )


def test_at_most_the_kept_tables_and_the_oldest_block_goes_first():
    """The kept tables are bounded (_BLOCKS_KEPT (block, topic) pairs): after 40 blocks of one
    topic the newest _BLOCKS_KEPT remain, and a block asked again is still numpy's draw."""
    import fire_uav_agent.peer_link as pl

    link = PeerLink(0, 3, seed=8, loss_probability=0.5, control_period_s=0.1)
    for b in range(40):
        link.is_lost(1, b * pl._BLOCK_STEPS, 0)
        assert len(link._blocks) == min(b + 1, pl._BLOCKS_KEPT)
    assert sorted(link._blocks) == [(b, 0) for b in range(40 - pl._BLOCKS_KEPT, 40)]
    assert [link.is_lost(2, k, 0) for k in range(64)] == [_numpy_loss(0.5, 8, 2, 0, k, 0) for k in range(64)]
