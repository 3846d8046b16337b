"""The report matches fleet fire tracks to true fires by position, not by id."""

import numpy as np
import pytest
from fire_report.matching import match_tracks_to_fires

PRIOR = 1 << 24  # a briefed fire's track id (consensus.PRIOR_FIRE_ID_BASE)


def _truth(x0, y0, vx, vy, t_out=None):
    t = np.arange(0.0, 60.0, 0.5)
    status = np.zeros(t.size, int) if t_out is None else (t >= t_out).astype(int)
    return {"t": t, "x": x0 + vx * t, "y": y0 + vy * t, "status": status}


def _track(truth, t0, t1, noise_m, seed, offset=(0.0, 0.0)):
    rng = np.random.default_rng(seed)
    t = np.arange(t0, t1, 0.1)
    x = np.interp(t, truth["t"], truth["x"]) + offset[0] + rng.normal(0, noise_m, t.size)
    y = np.interp(t, truth["t"], truth["y"]) + offset[1] + rng.normal(0, noise_m, t.size)
    return {"t": t, "x": x, "y": y, "status": np.zeros(t.size, int)}


def test_tracks_go_to_the_fire_they_follow_whatever_their_ids():
    # the FF scenario's two fires (Fig. 3); fire 1 burns out at 30 s
    truth = {0: _truth(300, 400, -0.5, -0.2), 1: _truth(450, 50, -0.25, 0.1, t_out=30.0)}
    est = {
        (0, PRIOR + 1): _track(truth[0], 1, 50, 3.0, 1),  # briefed "fire 1" is really fire 0
        (1, PRIOR + 0): _track(truth[1], 1, 29, 3.0, 2),
        (2, (2 << 16) | 1): _track(truth[0], 5, 20, 5.0, 3, offset=(20, -10)),  # a duplicate of fire 0
        (1, (2 << 16) | 1): _track(truth[0], 5, 20, 5.0, 4, offset=(20, -10)),
        (0, (0 << 16) | 7): _track(truth[1], 1, 20, 3.0, 5, offset=(0, 250)),  # a ghost, 250 m off
    }
    m = match_tracks_to_fires(est, truth)
    assert m == {PRIOR + 1: 0, PRIOR + 0: 1, (2 << 16) | 1: 0}


def test_a_track_seen_only_after_its_fire_went_out_is_not_matched_to_it():
    truth = {1: _truth(450, 50, 0.0, 0.0, t_out=10.0)}
    est = {(0, 5): _track(truth[1], 20, 40, 1.0, 1)}
    assert match_tracks_to_fires(est, truth) == {}


def test_a_few_wild_samples_do_not_move_a_track_to_the_other_fire():
    """Median, not mean: a track that jumped for 10 % of its samples (merge) stays with its fire."""
    truth = {0: _truth(100, 100, 0, 0), 1: _truth(400, 100, 0, 0)}
    tr = _track(truth[0], 1, 41, 2.0, 1)
    tr["x"][:40] += 300.0  # 40 of 400 samples at fire 1
    assert match_tracks_to_fires({(0, 9): tr}, truth) == {9: 0}


def test_bad_gate_is_refused():
    with pytest.raises(ValueError, match="gate_m must be > 0"):
        match_tracks_to_fires({}, {}, gate_m=0.0)


def _still(x, y, t0=0.0, t1=60.0, dt=0.5, status=0):
    t = np.arange(t0, t1, dt)
    return {
        "t": t,
        "x": np.full(t.size, float(x)),
        "y": np.full(t.size, float(y)),
        "status": np.full(t.size, status),
    }


def test_the_gate_is_inclusive_and_a_hundred_metres_by_default():
    truth = {3: _still(0.0, 0.0)}
    at = {(0, 1): _still(60.0, 80.0, 1, 20)}  # 100 m off (3-4-5)
    beyond = {(0, 2): _still(60.5, 80.0, 1, 20)}
    assert match_tracks_to_fires(at, truth) == {1: 3}
    assert match_tracks_to_fires(beyond, truth) == {}
    assert match_tracks_to_fires(beyond, truth, gate_m=101.0) == {2: 3}
    assert match_tracks_to_fires(at, truth, gate_m=99.0) == {}


def test_truth_is_interpolated_between_its_samples():
    # a fire moving 2 m/s east sampled every 10 s; a track on its true path at the half-steps
    t = np.arange(0.0, 100.0, 10.0)
    truth = {0: {"t": t, "x": 2.0 * t, "y": np.zeros(t.size), "status": np.zeros(t.size, int)}}
    tt = t[:-1] + 5.0
    est = {(0, 1): {"t": tt, "x": 2.0 * tt, "y": np.zeros(tt.size)}}  # no status: every sample counts
    assert match_tracks_to_fires(est, truth, gate_m=1e-6) == {1: 0}  # the nearest sample is 10 m off


def test_only_active_samples_of_a_track_and_burning_samples_of_a_fire_count():
    truth = {0: _still(0.0, 0.0), 1: _still(500.0, 0.0)}
    tr = _still(500.0, 0.0, 1, 20)  # sits on fire 1 ...
    tr["status"][:] = 1  # ... but every one of those samples is not active
    near0 = _still(10.0, 0.0, 20, 25)
    est = {(0, 4): {k: np.concatenate([tr[k], near0[k]]) for k in tr}}
    assert match_tracks_to_fires(est, truth) == {4: 0}
    # a fire that never burns (status 1 throughout) is no candidate, even right under the track
    assert match_tracks_to_fires({(0, 4): _still(500.0, 0.0, 1, 20)}, {1: _still(500.0, 0.0, status=1)}) == {}
    # without a status array every truth sample is burning
    no_status = {1: {k: v for k, v in _still(500.0, 0.0).items() if k != "status"}}
    assert match_tracks_to_fires({(0, 4): _still(500.0, 0.0, 1, 20)}, no_status) == {4: 1}
    # another code for "active" is honoured
    assert match_tracks_to_fires({(0, 4): _still(500.0, 0.0, 1, 20, status=7)}, truth, active_status=7) == {}
    both7 = {1: _still(500.0, 0.0, status=7)}
    assert match_tracks_to_fires({(0, 4): _still(500.0, 0.0, 1, 20, status=7)}, both7, active_status=7) == {
        4: 1
    }


def test_a_sample_at_the_first_or_last_burning_instant_counts():
    truth = {0: _still(0.0, 0.0, 10.0, 20.5, 0.5)}  # burns over [10, 20]
    first = {"t": np.array([10.0]), "x": np.array([1.0]), "y": np.array([0.0])}
    last = {"t": np.array([20.0]), "x": np.array([1.0]), "y": np.array([0.0])}
    before = {"t": np.array([9.9]), "x": np.array([1.0]), "y": np.array([0.0])}
    assert match_tracks_to_fires({(0, 1): first}, truth) == {1: 0}
    assert match_tracks_to_fires({(0, 1): last}, truth) == {1: 0}
    assert match_tracks_to_fires({(0, 1): before}, truth) == {}


def test_samples_of_one_track_from_several_uavs_are_pooled():
    """Three UAVs publish track 9; two of them near fire 0, one (fewer samples) near fire 1:
    the median over all of them decides, not the last UAV's samples."""
    truth = {0: _still(0.0, 0.0), 1: _still(300.0, 0.0)}
    est = {
        (0, 9): _still(5.0, 0.0, 1, 11),
        (2, 9): _still(5.0, 0.0, 11, 21),
        (5, 9): _still(305.0, 0.0, 21, 31),
        (5, 10): _still(305.0, 0.0, 21, 22),
    }
    assert match_tracks_to_fires(est, truth) == {9: 0, 10: 1}


def test_empty_tracks_and_fires_are_skipped():
    empty = {"t": np.zeros(0), "x": np.zeros(0), "y": np.zeros(0)}
    truth = {0: empty, 1: _still(0.0, 0.0)}
    est = {(0, 1): empty, (0, 2): _still(1.0, 1.0, 1, 5), (0, 3): {}}
    assert match_tracks_to_fires(est, truth) == {2: 1}
    assert match_tracks_to_fires(est, {}) == {}


def test_bad_gates_are_refused_with_their_value():
    for bad in (-5.0, float("nan")):
        with pytest.raises(ValueError, match=r"gate_m must be > 0, got (-5.0|nan)"):
            match_tracks_to_fires({}, {}, gate_m=bad)
    assert match_tracks_to_fires({}, {}, gate_m=1e-9) == {}


def test_a_fire_known_by_a_single_truth_sample_can_be_matched():
    truth = {0: {"t": np.array([10.0]), "x": np.array([0.0]), "y": np.array([0.0]), "status": np.array([0])}}
    est = {(0, 1): {"t": np.array([10.0]), "x": np.array([3.0]), "y": np.array([4.0])}}
    assert match_tracks_to_fires(est, truth) == {1: 0}


def test_fires_that_cannot_match_do_not_stop_the_search():
    """A fire that never burns, or burns only at other times, is passed over, not the end of the search."""
    never = _still(0.0, 0.0, status=1)
    later = _still(0.0, 0.0, 100.0, 160.0)
    target = _still(400.0, 0.0)
    track = {(0, 2): _still(401.0, 0.0, 1, 20)}
    assert match_tracks_to_fires(track, {0: never, 1: target}) == {2: 1}
    assert match_tracks_to_fires(track, {0: later, 1: target}) == {2: 1}


def test_truth_is_interpolated_in_time_on_both_axes():
    t = np.arange(0.0, 100.0, 10.0)
    truth = {0: {"t": t, "x": 100.0 + t, "y": 2.0 * t, "status": np.zeros(t.size, int)}}
    tt = t[:-1] + 5.0
    est = {(0, 1): {"t": tt, "x": 100.0 + tt, "y": 2.0 * tt}}
    assert match_tracks_to_fires(est, truth, gate_m=1e-6) == {1: 0}
