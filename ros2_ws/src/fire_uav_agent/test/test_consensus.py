"""Fire consensus (FF III-C, Eqs. 26-29)."""

import math

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


def test_predict_moves_active_fires_by_their_drift_and_leaves_extinguished_ones():
    """Constant-drift kinematics (FF III-C, drift estimation): x(t + dt) = x(t) + v dt."""
    c = FireConsensus(0)
    c.fuse(
        {
            1: _pf(
                1,
                0,
                [
                    FireEntry(7, True, 100.0, 200.0, 10.0, 0.5, -0.25, 0.1),
                    FireEntry(9, False, 500.0, 500.0, 0.0, 1.0, 1.0, 0.1),
                ],
            )
        },
        0.2,
    )
    before = {e.fire_id: (e.x_m, e.y_m) for e in c.entries()}
    c.predict(4.0)
    after = {e.fire_id: (e.x_m, e.y_m) for e in c.entries()}
    assert after[7] == pytest.approx((before[7][0] + 2.0, before[7][1] - 1.0))
    assert after[9] == before[9]


# --- no extinction from stale estimates or an own drop alone (issue 16, item 4) -------------------
def test_flying_over_a_stale_estimate_without_seeing_the_fire_does_not_put_it_out():
    """Briefed at (300, 400) at t = 0; the fire drifts at 1 m/s and the briefing was 15 m off, so at
    t = 60 s it burns 75 m from the estimate, beyond the 70 m sensor range. A UAV that circles the
    estimate 25 m out for 2 s and sees nothing has no evidence that the fire is out. (Over the
    very centre, within ``negative_range_min_m`` = 15 m, it may end it: ghost tracks must end.)"""
    fc = FireConsensus(0)
    [fid] = fc.brief(((300.0, 400.0, 20.0),), t_s=0.0, position_sigma_m=10.0)
    for k in range(20):
        fc.observe(np.zeros((0, 4)), (300.0 + 25.0 * math.cos(k), 400.0 + 25.0 * math.sin(k)), 60.0 + 0.1 * k)
    assert [e.fire_id for e in fc.active()] == [fid] and not fc.all_out()


def test_flying_over_a_fresh_estimate_without_seeing_the_fire_puts_it_out():
    """The counterpart: seen at t = 10 s; at t = 11 s the UAV is over the centre and sees nothing."""
    fc = FireConsensus(0)
    [fid] = fc.observe(np.array([[10.0, 300.0, 400.0, 1.5]]), (300.0, 380.0), 10.0)
    for k in range(5):
        fc.observe(np.zeros((0, 4)), (300.0, 395.0), 11.0 + 0.1 * k)
    assert fc.all_out()


def test_an_own_drop_never_ends_a_fire_and_on_a_stale_estimate_changes_nothing():
    fc = FireConsensus(0)
    [fid] = fc.observe(np.array([[1.0, 100.0, 100.0, 3.0]]), (100.0, 60.0), 1.0)
    # 30 s later, without a look since: the centre may be anywhere; the drop tells nothing
    assert not fc.note_drop(fid, (100.0, 100.0), 31.0, footprint_m=20.0)
    assert fc.active()[0].extent_m == pytest.approx(3.0)
    # seen just now: the hit model halves it (3 -> 1.5 m, below the 2 m threshold) but it stays
    # active until a look confirms it is gone
    fc.observe(np.array([[31.5, 100.0, 100.0, 3.0]]), (100.0, 60.0), 31.5)
    assert fc.note_drop(fid, (100.0, 100.0), 31.6, footprint_m=20.0)
    assert fc.active() and fc.active()[0].extent_m < 2.0


# --- drift: least-squares fit of the own detections -----------------------------------------------
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_drift_fit_recovers_a_known_drift_from_noisy_detections(seed):
    """A fire drifting at (-0.5, -0.2) m/s (FF Fig. 3, fire 1), centre noise sigma 2 m (FF II-C
    camera), 10 Hz for 10 s: the standard error of a least-squares slope is
    2 / sqrt(N var(t)) = 0.07 m/s; the estimate must be within 0.25 m/s (3.5 sigma) of the truth."""
    rng = np.random.default_rng(seed)
    fc = FireConsensus(0)
    v = np.array([-0.5, -0.2])
    fid = None
    for k in range(100):
        t = 0.1 * (k + 1)
        c = np.array([300.0, 400.0]) + v * t + rng.normal(0.0, 2.0, 2)
        fc.predict(0.1)
        ids = fc.observe(np.array([[t, c[0], c[1], 50.0]]), (300.0, 350.0), t)
        fid = fid or ids[0]
    (e,) = fc.active()
    assert math.hypot(e.vx_mps - v[0], e.vy_mps - v[1]) < 0.25, (e.vx_mps, e.vy_mps)
