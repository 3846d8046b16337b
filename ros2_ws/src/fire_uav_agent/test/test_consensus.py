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


# --- no extinction from stale estimates or an own drop alone --------------------
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


# --- freshness weights, gates, negative evidence, merging (mutation testing) -------------------
def _peer_reports(entries_by_peer: dict[int, FireEntry], step: int) -> dict[int, PeerFires]:
    return {j: _pf(j, step, [e]) for j, e in entries_by_peer.items()}


def test_fused_position_is_the_freshness_weighted_mean_of_the_paper_example():
    """FF Eq. 26 row 1: ages Lm = (1, 4, 8) control steps. Eq. 28 (the text's reading) weighs them
    1/Lm / 1.375 = (0.727, 0.182, 0.091): peers reporting x = 0, 100, 200 fuse to 50 / 1.375 =
    36.4 m; uniform weights would give 100 m. The extent comes from the freshest report alone
    (module doc "Extent after a hit"); the fused entry carries the newest measurement time."""
    c = FireConsensus(9)
    t = 2.0  # ages 1 + (t - lm) / 0.1 = 1, 4, 8
    reports = {
        1: FireEntry(5, True, 0.0, 50.0, 10.0, last_measurement_s=2.0),
        2: FireEntry(5, True, 100.0, 50.0, 30.0, last_measurement_s=1.7),
        3: FireEntry(5, True, 200.0, 50.0, 60.0, last_measurement_s=1.3),
    }
    assert c.fuse(_peer_reports(reports, 19), t) == [5]
    (e,) = c.entries()
    assert e.x_m == pytest.approx(50.0 / 1.375) and e.y_m == pytest.approx(50.0)
    assert e.extent_m == pytest.approx(10.0) and e.last_measurement_s == 2.0
    # two equally fresh reports (ages 1 and 1.5, within one step): the extent is their 1/age mean
    d = FireConsensus(9)
    d.fuse(
        _peer_reports(
            {
                1: FireEntry(5, True, 0.0, 0.0, 10.0, last_measurement_s=2.0),
                2: FireEntry(5, True, 0.0, 0.0, 40.0, last_measurement_s=1.95),
            },
            19,
        ),
        t,
    )
    assert d.entries()[0].extent_m == pytest.approx((10.0 / 1.0 + 40.0 / 1.5) / (1.0 + 1.0 / 1.5))


def test_one_fresh_measurement_reaches_the_whole_ring_with_freshness_weights_only():
    """Fleet-level (FF III-C): 4 agents on a ring graph all briefed at x = 0 at t = 0; at t = 30 s
    agent 0 alone sees the fire 30 m east (its estimate moves to 15 m). Over the next 4 steps the
    others hear it only through their ring neighbours. With Eq. 28's 1/age weights the fresh
    estimate (age ~2 steps) outweighs the 300-step-old copies ~150:1, so every agent ends within
    1 m of agent 0's estimate; with equal weights agent 0's own first fusion averages it with two
    stale copies (15 -> 5 m) and the fleet settles near 15/4 m."""
    n = 4
    agents = [FireConsensus(i) for i in range(n)]
    for a in agents:
        a.brief(((0.0, 0.0, 30.0),), t_s=0.0)
    agents[0].observe(np.array([[30.0, 30.0, 0.0, 30.0]]), None, 30.0)
    target = agents[0].entries()[0].x_m
    assert target == pytest.approx(15.0)
    for k in range(1, 5):
        t = 30.0 + 0.1 * k
        pics = [_pf(i, 299 + k, a.entries()) for i, a in enumerate(agents)]
        for i, a in enumerate(agents):
            a.fuse({j: pics[j] for j in ((i - 1) % n, (i + 1) % n)}, t)
    xs = [a.entries()[0].x_m for a in agents]
    assert all(abs(x - target) < 1.0 for x in xs), xs


def test_peer_reports_are_moved_by_their_drift_to_now():
    """A report made at step s (stamp (s + 1) T) with drift (1, -2) m/s, fused 3 s later: its centre
    has moved by (3, -6) m (constant-drift kinematics, FF III-C)."""
    c = FireConsensus(0)
    c.fuse({1: _pf(1, 9, [FireEntry(4, True, 10.0, 20.0, 5.0, 1.0, -2.0, 1.0)])}, 4.0)
    (e,) = c.entries()
    assert (e.x_m, e.y_m) == pytest.approx((13.0, 14.0)) and (e.vx_mps, e.vy_mps) == (1.0, -2.0)


def test_association_gate_is_the_larger_of_the_floor_and_two_extents():
    """Gate max(40 m, 2 extent): a detection 39 m from a 10 m fire joins it, 41 m opens a new id;
    next to a 30 m fire the gate is 60 m."""
    for ext, d, joins in ((10.0, 39.0, True), (10.0, 41.0, False), (30.0, 59.0, True), (30.0, 61.0, False)):
        c = FireConsensus(0)
        c.brief(((0.0, 0.0, ext),))
        new = c.observe(np.array([[0.1, d, 0.0, ext]]), None, 0.1)
        assert (new == []) == joins, (ext, d)
        assert len(c.tracks) == (1 if joins else 2)  # and far enough not to be merged either


def test_an_own_detection_moves_the_estimate_halfway_and_nearest_track_wins():
    c = FireConsensus(0)
    c.brief(((0.0, 0.0, 10.0), (100.0, 0.0, 10.0)))
    c.observe(np.array([[0.1, 70.0, 10.0, 20.0]]), None, 0.1)  # 30 m from the second, 70 from the first
    a, b = c.entries()
    assert (a.x_m, a.y_m, a.extent_m) == (0.0, 0.0, 10.0)
    assert (b.x_m, b.y_m, b.extent_m) == pytest.approx((85.0, 5.0, 15.0))  # alpha = 0.5
    assert b.last_measurement_s == 0.1


def _seen_at(t: float, extent: float = 5.0) -> FireConsensus:
    c = FireConsensus(0)
    c.observe(np.array([[t, 300.0, 400.0, extent]]), None, t)
    return c


def _looks(c: FireConsensus, d_m: float, t0: float, steps: int) -> None:
    for k in range(steps):
        c.observe(np.zeros((0, 4)), (300.0 + d_m, 400.0), t0 + 0.1 * k)


def test_negative_evidence_needs_five_looks_within_range():
    """A fresh estimate (uncertainty 10 m): range min(50, 70 - 10) = 50 m. 5 looks at 49 m end
    it, 4 do not; looks at 51 m never do; a look out of range restarts the count."""
    c = _seen_at(10.0)
    _looks(c, 49.0, 10.1, 4)
    assert not c.all_out()
    _looks(c, 49.0, 10.5, 1)
    assert c.all_out() and c.entries()[0].extent_m == 0.0 and c.entries()[0].last_measurement_s == 10.5
    c = _seen_at(10.0)
    _looks(c, 51.0, 10.1, 20)
    assert not c.all_out()
    c = _seen_at(10.0)
    _looks(c, 10.0, 10.1, 4)
    _looks(c, 80.0, 10.5, 1)
    _looks(c, 10.0, 10.6, 4)
    assert not c.all_out()
    assert not FireConsensus(0).all_out()  # no fire known: not "all out"


def test_negative_range_shrinks_with_the_age_and_the_drift_uncertainty():
    """FireConsensus.negative_range: the fire is within unc = 10 m + dv age of the estimate,
    dv = 1 m/s without an own drift fit, so 20 s after the last look the range is 70 - 30 = 40 m
    (45 m: no evidence, 38 m: evidence); 100 s after, unc is capped at 70 - 15 = 55 m: range 15 m.
    With an own fit of 100 detections over 10 s (sigma_v = 2 / sqrt(sum (t - mean)^2) ~ 0.07 m/s),
    dv = 3 sigma_v ~ 0.21 m/s and the range at 20 s is still 50 m."""
    c = _seen_at(10.0)
    _looks(c, 45.0, 30.0, 10)
    assert not c.all_out()
    _looks(c, 38.0, 31.0, 5)
    assert c.all_out()
    c = _seen_at(10.0)
    _looks(c, 16.0, 110.0, 10)
    assert not c.all_out()
    _looks(c, 14.0, 111.0, 5)
    assert c.all_out()
    f = FireConsensus(0)
    for k in range(100):
        t = 0.1 * (k + 1)
        f.observe(np.array([[t, 300.0 + 0.5 * (k % 2), 400.0, 5.0]]), None, t)
    (tr,) = f.tracks.values()
    assert math.isfinite(tr.drift_sigma_mps) and 0.05 < tr.drift_sigma_mps < 0.1
    assert f.negative_range(tr, 30.0) == pytest.approx(50.0)
    _looks(f, 45.0, 30.0, 5)
    assert f.all_out()


def test_the_briefing_uncertainty_sets_the_negative_range():
    """Briefed with sigma 10 m: the centre is within 30 m, so the range at t = 0 is 70 - 30 = 40 m."""
    c = FireConsensus(0)
    c.brief(((300.0, 400.0, 20.0),), t_s=0.0, position_sigma_m=10.0)
    _looks(c, 42.0, 0.0, 10)
    assert not c.all_out()
    _looks(c, 38.0, 0.0, 5)
    assert c.all_out()


def test_an_extinguished_fire_revives_only_on_newer_evidence():
    c = _seen_at(10.0)
    _looks(c, 0.0, 10.1, 5)  # out at 10.5 s
    assert c.all_out()
    c.observe(np.array([[10.4, 301.0, 400.0, 5.0]]), None, 10.6)  # older than the extinction
    assert c.all_out()
    c.observe(np.array([[10.7, 320.0, 410.0, 7.0]]), None, 10.7)
    (e,) = c.entries()
    assert e.active and (e.x_m, e.y_m, e.extent_m) == (320.0, 410.0, 7.0)


def test_a_peer_extinction_report_is_adopted_only_if_not_older():
    c = _seen_at(10.0)
    (fid,) = c.tracks
    c.fuse({1: _pf(1, 100, [FireEntry(fid, False, 300.0, 400.0, 0.0, last_measurement_s=9.0)])}, 10.2)
    assert not c.all_out()  # older than our 10.0 s detection
    c.fuse({1: _pf(1, 101, [FireEntry(fid, False, 300.0, 400.0, 0.0, last_measurement_s=10.0)])}, 10.3)
    assert c.all_out()
    c.fuse({1: _pf(1, 102, [FireEntry(fid, True, 300.0, 400.0, 9.0, last_measurement_s=10.3)])}, 10.4)
    assert not c.all_out() and c.entries()[0].extent_m == pytest.approx(9.0)


def test_duplicates_merge_into_the_smaller_id_with_the_fresher_numbers_and_aliases_resolve():
    c = FireConsensus(0)
    c.fuse(
        {
            1: _pf(1, 5, [FireEntry((1 << 16) | 1, True, 100.0, 100.0, 5.0, last_measurement_s=0.2)]),
            2: _pf(2, 5, [FireEntry((2 << 16) | 1, True, 120.0, 100.0, 5.0, last_measurement_s=0.5)]),
        },
        0.6,
    )
    assert list(c.tracks) == [(1 << 16) | 1] and c.alias == {(2 << 16) | 1: (1 << 16) | 1}
    # a later report of the retired id joins the kept one
    c.fuse({2: _pf(2, 6, [FireEntry((2 << 16) | 1, True, 120.0, 100.0, 5.0, last_measurement_s=0.7)])}, 0.7)
    (e,) = c.entries()
    assert e.fire_id == (1 << 16) | 1 and e.last_measurement_s == 0.7 and e.x_m == pytest.approx(120.0)
    # far apart (gate 40 m): two fires stay two
    d = FireConsensus(0)
    d.brief(((0.0, 0.0, 5.0), (41.0, 0.0, 5.0)))
    assert len(d.tracks) == 2


def test_a_drop_counts_within_the_footprint_or_the_extent_and_only_on_a_fresh_look():
    fc = FireConsensus(0)
    [fid] = fc.observe(np.array([[1.0, 100.0, 100.0, 50.0]]), None, 1.0)
    assert fc.note_drop(fid, (145.0, 100.0), 2.0, footprint_m=20.0)  # 45 m: inside the 50 m extent
    fc2 = FireConsensus(0)
    [fid2] = fc2.observe(np.array([[1.0, 100.0, 100.0, 10.0]]), None, 1.0)
    assert not fc2.note_drop(fid2, (121.0, 100.0), 1.5, footprint_m=20.0)  # beyond both
    assert fc2.note_drop(fid2, (119.0, 100.0), 2.0, footprint_m=20.0)  # seen 1.0 s ago: counts
    assert not fc2.note_drop(fid2, (100.0, 100.0), 3.1, footprint_m=20.0)  # 2.1 s: stale
    assert not fc2.note_drop(12345, (100.0, 100.0), 2.0, footprint_m=20.0)  # unknown id


def test_drift_is_fitted_only_over_enough_recent_detections():
    """Fewer than 20 detections, or spanning under 5 s: no drift yet. A fire whose drift changes:
    after the 30 s window has passed, the fit reflects the new drift only."""
    c = FireConsensus(0)
    for k in range(19):
        t = 1.0 * k
        c.observe(np.array([[t, 1.0 * t, 0.0, 5.0]]), None, t)
    (tr,) = c.tracks.values()
    assert tr.vx_mps == 0.0 and not math.isfinite(tr.drift_sigma_mps)
    c = FireConsensus(0)
    for k in range(40):  # 40 samples over 3.9 s
        t = 0.1 * k
        c.observe(np.array([[t, 0.5 * t, 0.0, 5.0]]), None, t)
    assert next(iter(c.tracks.values())).vx_mps == 0.0
    c = FireConsensus(0)
    for k in range(70):  # 1 m/s east for 40 s, then 1 m/s north for 30 s (a sample per second)
        t = float(k)
        xy = (t, 0.0) if t <= 40 else (40.0, t - 40.0)
        c.predict(1.0)
        c.observe(np.array([[t, *xy, 5.0]]), None, t)
    tr = next(iter(c.tracks.values()))
    assert abs(tr.vx_mps) < 0.1 and abs(tr.vy_mps - 1.0) < 0.1


def test_consensus_row_rejects_bad_ages():
    from fire_uav_agent.consensus import consensus_row

    for bad in (np.array([]), np.array([[1.0, 2.0]]), np.array([1.0, math.nan]), np.array([1.0, -2.0])):
        with pytest.raises(ValueError, match="ages must be a non-empty vector of positive numbers"):
            consensus_row(bad)
