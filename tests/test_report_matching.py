"""The report matches fleet fire tracks to true fires by position, not by id (issue 16)."""

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
