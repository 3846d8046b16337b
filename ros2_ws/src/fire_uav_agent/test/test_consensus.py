"""Fire consensus (FF III-C, Eqs. 26-29)."""

import numpy as np
import pytest
from fire_uav_agent.consensus import FireConsensus, consensus_matrix
from fire_uav_agent.peer_link import FireEntry, PeerFires


def test_paper_example_eqs_26_to_29():
    lm = np.array([[1, 4, 8], [2, 5, 8], [1, 3, 9]], dtype=float)  # Eq. 26
    sums = (1.0 / lm).sum(axis=1)
    assert np.allclose(sums, [1.375, 0.825, 1.4444], atol=1e-3)  # Eq. 28 (paper prints 1.441)
    qc = consensus_matrix(lm)
    assert np.allclose(qc.sum(axis=1), 1.0)  # row-stochastic
    assert np.allclose(qc[0], [1 / 1.375, 0.25 / 1.375, 0.125 / 1.375])
    assert np.allclose(qc[1], [0.5 / 0.825, 0.2 / 0.825, 0.125 / 0.825])
    assert np.all(np.diff(qc, axis=1) < 0)  # fresher (smaller Lm) weighs more
    with pytest.raises(ValueError):
        consensus_matrix(np.array([[1.0, 0.0]]))


def _pf(j, step, entries):
    return PeerFires(j, step + 1, step, tuple(entries))


def test_agents_converge_to_common_estimate():
    n = 4
    agents = [FireConsensus(i) for i in range(n)]
    rng = np.random.default_rng(0)
    # every agent saw the fire (id 1) once, at different times, with different errors
    for i, a in enumerate(agents):
        t = 0.1 * (i + 1)
        a.observe(
            np.array([[t, 300 + rng.normal(0, 5), 400 + rng.normal(0, 5), 50 + rng.normal(0, 3)]]), None, t
        )
    ids = {next(iter(a.tracks)) for a in agents}
    assert len(ids) == n  # each opened its own id ...
    for k in range(5, 60):
        t = 0.1 * (k + 1)
        pics = [_pf(i, k - 1, a.entries()) for i, a in enumerate(agents)]
        for i, a in enumerate(agents):
            a.fuse({j: pics[j] for j in range(n) if j != i}, t)
    assert {tuple(a.tracks) for a in agents} == {(min(ids),)}  # ... merged into the smallest id
    xs = np.array([[e.x_m, e.y_m, e.extent_m] for a in agents for e in a.entries()])
    assert np.ptp(xs, axis=0).max() < 1e-6
    assert abs(xs[0, 0] - 300) < 10 and abs(xs[0, 2] - 50) < 6


def test_fresh_measurement_dominates_and_extinction_propagates():
    a, b = FireConsensus(0), FireConsensus(1)
    a.observe(np.array([[0.1, 100.0, 100.0, 20.0]]), None, 0.1)
    fid = next(iter(a.tracks))
    b.fuse({0: _pf(0, 0, a.entries())}, 0.2)
    assert b.entries()[0].fire_id == fid and b.entries()[0].extent_m == pytest.approx(20.0)
    # b measures a much smaller fire much later; a fuses: b's fresh data dominate
    b.tracks[fid].lm_s = 0.1
    b.observe(np.array([[5.0, 101.0, 100.0, 10.0]] * 20), None, 5.0)
    a.fuse({1: _pf(1, 49, b.entries())}, 5.1)
    w_b = 1.0 / (1 + 0.1 / 0.1)
    assert a.entries()[0].extent_m < 20.0 - 0.6 * (20.0 - b.entries()[0].extent_m) * w_b
    # b sees it out (flies over the centre, no detection for 5 steps): a adopts the status
    for k in range(5):
        b.observe(np.zeros((0, 4)), (101.0, 100.0), 6.0 + 0.1 * k)
    assert b.all_out()
    a.fuse({1: _pf(1, 65, b.entries())}, 6.6)
    assert a.all_out() and not a.entries()[0].active
    # an older active report does not revive it
    a.fuse({1: PeerFires(1, 99, 10, (FireEntry(fid, True, 100, 100, 20.0, last_measurement_s=0.1),))}, 6.7)
    assert a.all_out()


def test_new_fire_id_scheme():
    c = FireConsensus(3)
    new = c.observe(np.array([[0.1, 0.0, 0.0, 10.0], [0.1, 500.0, 0.0, 10.0]]), None, 0.1)
    assert new == [(3 << 16) | 1, (3 << 16) | 2]


# --- known effect of an own drop, briefing (known-fires mode) -----------------------------------
def test_an_own_hit_halves_the_estimated_extent_at_once_and_a_miss_does_not():
    from fire_uav_agent.consensus import FireConsensus

    fc = FireConsensus(0)
    [fid] = fc.observe(np.array([[1.0, 100.0, 100.0, 50.0]]), (100.0, 100.0), 1.0)
    assert fc.note_drop(fid, (110.0, 100.0), 2.0, footprint_m=20.0)  # FF V-B: area / 4
    (e,) = fc.active()
    assert e.extent_m == pytest.approx(25.0) and e.last_measurement_s == 2.0
    assert not fc.note_drop(fid, (100.0, 200.0), 3.0, footprint_m=20.0)  # 100 m off: no hit
    assert fc.active()[0].extent_m == pytest.approx(25.0)


def test_the_briefing_gives_every_agent_the_same_ids_and_a_detection_joins_it():
    from fire_uav_agent.consensus import PRIOR_FIRE_ID_BASE, FireConsensus

    a, b = FireConsensus(0), FireConsensus(3)
    brief = ((300.0, 400.0, 50.0), (450.0, 50.0, 20.0))
    assert a.brief(brief) == b.brief(brief) == [PRIOR_FIRE_ID_BASE, PRIOR_FIRE_ID_BASE + 1]
    assert b.observe(np.array([[1.0, 455.0, 45.0, 21.0]]), (450.0, 50.0), 1.0) == []  # no new id
    assert sorted(e.fire_id for e in b.active()) == [PRIOR_FIRE_ID_BASE, PRIOR_FIRE_ID_BASE + 1]
