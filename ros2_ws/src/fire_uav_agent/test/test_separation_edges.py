"""The separation filter's geometry at its edges, against a brute-force kinematic reference
(positions sampled along the straight-line prediction), not the module's closed form."""

import math

import numpy as np
import pytest
from fire_uav_agent.separation import SeparationConfig, avoid_heading, closest_approach_m, hold_layer

SPEED = 100.0  # [m/s] FF cruise


def _brute_closest(rel, vel, horizon_s, n=20001):
    t = np.linspace(0.0, horizon_s, n)
    return float(np.min(np.hypot(rel[0] + vel[0] * t, rel[1] + vel[1] * t)))


def _approach(heading, own_xy, peer, horizon_s):
    """Brute-force closest approach to one peer row (x, y, z, vx, vy) flying ``heading``."""
    rel = (peer[0] - own_xy[0], peer[1] - own_xy[1])
    vel = (peer[3] - SPEED * math.cos(heading), peer[4] - SPEED * math.sin(heading))
    return _brute_closest(rel, vel, horizon_s)


def test_closest_approach_matches_the_sampled_trajectory():
    rng = np.random.default_rng(4)
    rel = rng.uniform(-300, 300, (200, 2))
    vel = rng.uniform(-200, 200, (200, 2))
    got = closest_approach_m(rel, vel, 2.0)
    want = [_brute_closest(r, v, 2.0) for r, v in zip(rel, vel, strict=True)]
    # the sampled minimum is at most |v| x dt / 2 above the true one (dt = 1e-4 s)
    np.testing.assert_allclose(got, want, atol=0.03)
    assert np.all(got <= np.asarray(want) + 1e-9)


def test_closest_approach_cases_in_closed_form():
    r = np.array([[100.0, 30.0], [100.0, 30.0], [100.0, 30.0], [5.0, 0.0]])
    w = np.array([[-10.0, 0.0], [-10.0, 0.0], [10.0, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(closest_approach_m(r[:1], w[:1], 20.0), [30.0])  # at t = 10 s
    np.testing.assert_allclose(
        closest_approach_m(r[1:2], w[1:2], 5.0), [math.hypot(50.0, 30.0)]
    )  # horizon first
    np.testing.assert_allclose(closest_approach_m(r[2:], w[2:], 5.0), [math.hypot(100.0, 30.0), 5.0])  # now


def _head_on(dx=150.0, dz=0.0):
    """A peer dx ahead on our track, flying at us at cruise speed."""
    return np.array([[dx, 0.0, 30.0 + dz, -SPEED, 0.0]])


def test_a_peer_at_the_detection_range_counts_and_one_beyond_does_not():
    cfg = SeparationConfig()  # detect 150 m; closing at 200 m/s: 150 m close within the 2 s horizon
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, _head_on(cfg.detect_m), cfg)[1]
    assert not avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, _head_on(cfg.detect_m + 0.01), cfg)[1]


def test_a_peer_at_the_vertical_band_edge_counts_and_one_beyond_does_not():
    cfg = SeparationConfig()
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, _head_on(100.0, cfg.vertical_m), cfg)[1]
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, _head_on(100.0, -cfg.vertical_m), cfg)[1]
    assert not avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, _head_on(100.0, cfg.vertical_m + 0.01), cfg)[1]


def test_the_heading_chosen_is_clear_and_no_nearer_candidate_is():
    cfg = SeparationConfig()
    peer = _head_on(120.0)
    peer[0, 1] = 5.0  # slightly off our track
    h, deviated, clear = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg)
    assert deviated and clear
    assert _approach(h, (0.0, 0.0), peer[0], cfg.horizon_s) >= cfg.radius_m - 0.03
    dev = abs(math.remainder(h, 2 * math.pi))
    for k in range(cfg.headings):  # every candidate nearer the desired heading is in conflict
        c = -math.pi + 2 * math.pi * k / cfg.headings
        if abs(c) < dev - 1e-9:
            assert _approach(c, (0.0, 0.0), peer[0], cfg.horizon_s) < cfg.radius_m


def test_the_margin_raises_the_clearance_the_desired_heading_needs():
    cfg = SeparationConfig()
    peer = np.array([[100.0, 25.0, 30.0, -SPEED, 0.0]])  # passes 25 m abeam: clear of 20 m, not of 30 m
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg) == (0.0, False, True)
    h, deviated, _ = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg, margin_m=10.0)
    assert deviated and _approach(h, (0.0, 0.0), peer[0], cfg.horizon_s) >= 30.0 - 0.03


def test_a_deviation_stays_nearest_the_preferred_heading():
    cfg = SeparationConfig()
    peer = _head_on(120.0)
    h_left = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg, prefer_heading_rad=1.0)[0]
    h_right = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg, prefer_heading_rad=-1.0)[0]
    assert h_left > 0 > h_right  # a symmetric conflict is left on the side the preference is


def test_a_right_of_way_peer_within_the_yield_range_is_never_closed_on():
    cfg = SeparationConfig()  # yield 60 m
    # the peer flies away from us faster than we follow: no predicted conflict, but we aim at it
    peer = np.array([[50.0, 0.0, 30.0, 2 * SPEED, 0.0]])
    h, deviated, clear = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg, yield_to=np.array([True]))
    assert deviated and clear and math.cos(h) * 50.0 <= 1e-9  # no component towards the peer
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg)[1] is False  # no right of way: fly on
    far = np.array([[cfg.yield_m + 1.0, 0.0, 30.0, 2 * SPEED, 0.0]])
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, far, cfg, yield_to=np.array([True]))[1] is False


def test_with_nothing_clear_a_uav_flies_straight_away_from_the_nearest_right_of_way_peer():
    cfg = SeparationConfig()
    # boxed in: four peers 15 m around us, all inside the 20 m radius whatever we do
    peers = np.array([[15.0, 0.0, 30.0, 0.0, 0.0], [0.0, 15.0, 30.0, 0.0, 0.0],
                      [-15.0, 0.0, 30.0, 0.0, 0.0], [0.0, -16.0, 30.0, 0.0, 0.0]])  # fmt: skip
    h, deviated, clear = avoid_heading(
        (0.0, 0.0, 30.0), SPEED, 0.3, peers, cfg, yield_to=np.array([False, True, False, False])
    )
    assert (deviated, clear) == (True, True) and h == pytest.approx(-math.pi / 2)  # away from (0, 15)
    h2, deviated2, clear2 = avoid_heading((0.0, 0.0, 30.0), SPEED, 0.3, peers, cfg)
    assert deviated2 and not clear2

    # no right of way: the candidate heading whose closest approach to any peer is largest
    def worst(h):
        return min(_approach(h, (0.0, 0.0), p, cfg.horizon_s) for p in peers)

    best = max(worst(0.3 - math.pi + 2 * math.pi * k / cfg.headings) for k in range(cfg.headings))
    assert worst(h2) >= best - 0.05


def test_yield_flags_must_match_the_peer_rows():
    with pytest.raises(ValueError, match=r"yield_to must have one entry per peer row \(1\), got 2"):
        avoid_heading(
            (0.0, 0.0, 30.0), SPEED, 0.0, _head_on(), SeparationConfig(), yield_to=np.array([True, False])
        )


def test_holding_needs_a_peer_strictly_inside_the_radius_and_strictly_below():
    cfg = SeparationConfig()
    me = (0.0, 0.0, 37.0)
    assert not hold_layer(me, [(cfg.radius_m, 0.0, 23.0)], cfg)  # exactly at the radius
    assert hold_layer(me, [(cfg.radius_m - 0.01, 0.0, 23.0)], cfg)
    assert not hold_layer(me, [(0.0, 0.0, 37.0)], cfg)  # same height
    assert hold_layer(me, [(30.0, 0.0, 20.0), (0.0, 5.0, 36.9)], cfg)  # any one peer is enough


@pytest.mark.parametrize("field", ["radius_m", "vertical_m", "horizon_s", "detect_m", "on_course_beyond_m"])
def test_every_positive_field_is_checked(field):
    with pytest.raises(ValueError, match=rf"SeparationConfig\.{field} must be > 0, got -1"):
        SeparationConfig(**{field: -1})
    with pytest.raises(ValueError, match=rf"SeparationConfig\.{field} must be > 0, got 0"):
        SeparationConfig(**{field: 0})


def test_four_headings_are_enough_three_are_not():
    assert SeparationConfig(headings=4).headings == 4
    with pytest.raises(ValueError, match=r"SeparationConfig\.headings must be >= 4, got 3"):
        SeparationConfig(headings=3)


def test_a_slow_relative_motion_is_still_followed_over_the_horizon():
    # 0.5 m/s closing over a 20 s horizon (two UAVs nearly abreast): they meet at t = 10 s
    assert closest_approach_m(np.array([[5.0, 0.0]]), np.array([[-0.5, 0.0]]), 20.0)[0] == pytest.approx(
        0.0, abs=1e-9
    )
    assert _brute_closest((5.0, 0.0), (-0.5, 0.0), 20.0) == pytest.approx(0.0, abs=1e-3)


def test_sub_metre_settings_are_valid():
    cfg = SeparationConfig(radius_m=0.5, vertical_m=0.5, horizon_s=0.5, detect_m=0.5)
    assert (cfg.radius_m, cfg.vertical_m, cfg.horizon_s, cfg.detect_m) == (0.5, 0.5, 0.5, 0.5)
