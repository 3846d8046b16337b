"""Turn-rate-limited avoidance (fire_uav_agent.separation) against kinematic truth."""

import math

import numpy as np
import pytest
from fire_uav_agent.separation import (
    Avoider,
    SeparationConfig,
    avoid_heading,
    closest_approach_m,
    hold_layer,
    peer_rows,
)
from hypothesis import given, settings
from hypothesis import strategies as st

V = 44.7  # [m/s] FF stall speed: the slowest a UAV can fly
T = 0.1  # [s] control period


def test_closest_approach_of_a_head_on_pair_with_an_offset_is_the_offset():
    # 100 m apart along x, 7 m apart along y, closing at 2 V: they pass 7 m apart at t = 100 / (2 V)
    d = closest_approach_m(np.array([[100.0, 7.0]]), np.array([[-2 * V, 0.0]]), horizon_s=5.0)
    assert d[0] == pytest.approx(7.0)
    # within a horizon that ends before the pass, the closest is at the horizon
    d = closest_approach_m(np.array([[100.0, 0.0]]), np.array([[-2 * V, 0.0]]), horizon_s=0.5)
    assert d[0] == pytest.approx(100.0 - 2 * V * 0.5)
    # separating: the closest is now
    assert closest_approach_m(np.array([[30.0, 40.0]]), np.array([[1.0, 1.0]]), 3.0)[0] == pytest.approx(50.0)


def test_the_desired_heading_is_kept_when_no_peer_is_in_the_way():
    cfg = SeparationConfig()
    peers = np.array([[0.0, 100.0, 30.0, V, 0.0], [500.0, 0.0, 30.0, 0.0, V]])
    assert avoid_heading((0.0, 0.0, 30.0), V, 0.0, peers, cfg) == (0.0, False, True)
    # a peer straight ahead but 20 m higher is no conflict
    above = np.array([[40.0, 0.0, 50.0, -V, 0.0]])
    assert avoid_heading((0.0, 0.0, 30.0), V, 0.0, above, cfg) == (0.0, False, True)


def test_a_peer_straight_ahead_makes_the_uav_turn_to_a_clear_heading():
    cfg = SeparationConfig()
    peers = np.array([[60.0, 0.0, 30.0, -V, 0.0]])
    head, changed, clear = avoid_heading((0.0, 0.0, 30.0), V, 0.0, peers, cfg)
    assert changed and clear
    u = V * np.array([math.cos(head), math.sin(head)])
    assert closest_approach_m(peers[:, :2], peers[:, 3:5] - u, cfg.horizon_s)[0] >= cfg.radius_m


CFG = SeparationConfig()


def _fly(starts, goals, steps=400, avoid=True, cfg=CFG):
    """Unicycles at V turning at up to 10 rad/s toward their goals, seeing peers one step late."""
    p = np.array(starts, dtype=float)
    th = np.array([math.atan2(g[1] - s[1], g[0] - s[0]) for s, g in zip(starts, goals, strict=True)])
    prev = p.copy()
    dmin = math.inf
    avoiders = [Avoider(cfg) for _ in starts]
    for _ in range(steps):
        vel = (p - prev) / T  # what the peers' last two states tell
        seen = p.copy()  # step k-1 states ...
        new_th = th.copy()
        for i in range(len(p)):
            want = math.atan2(goals[i][1] - p[i, 1], goals[i][0] - p[i, 0])
            if avoid:
                others = [j for j in range(len(p)) if j != i]
                lead = seen[others] + vel[others] * T  # ... moved to t_{k+1}
                rows = np.column_stack([lead, np.full(len(others), 30.0), vel[others]])
                want, _, _ = avoiders[i].step((p[i, 0], p[i, 1], 30.0), V, want, rows)
            err = math.remainder(want - th[i], math.tau)
            new_th[i] = th[i] + max(-1.0, min(1.0, err))  # 10 rad/s for 0.1 s
        prev, th = p.copy(), new_th
        p = p + V * T * np.column_stack([np.cos(th), np.sin(th)])
        for i in range(len(p)):
            for j in range(i + 1, len(p)):
                dmin = min(dmin, float(np.hypot(*(p[i] - p[j]))))
    return dmin


def test_a_head_on_encounter_keeps_ten_metres_with_avoidance_and_not_without():
    starts, goals = [(0.0, 0.0), (400.0, 1.0)], [(400.0, 0.0), (0.0, 1.0)]
    assert _fly(starts, goals, steps=120, avoid=False) < 3.0  # the same geometry collides without it
    assert _fly(starts, goals, steps=120) >= 10.0


@settings(max_examples=15, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(0, 2 * math.pi), st.floats(-30, 30)),
        min_size=2,
        max_size=4,
        unique_by=lambda t: t[0],
    )
)
def test_crossing_flights_through_one_point_keep_ten_metres(paths):
    """2-4 UAVs from a 250 m circle through (near) its centre: the worst case of a lake queue."""
    starts = [(250 * math.cos(a), 250 * math.sin(a)) for a, _ in paths]
    goals = [
        (-250 * math.cos(a) + off * math.sin(a), -250 * math.sin(a) + off * math.cos(a)) for a, off in paths
    ]
    if min(math.dist(a, b) for i, a in enumerate(starts) for b in starts[i + 1 :]) < 40:
        return  # starts closer than the band: not an encounter this test is about
    assert _fly(starts, goals, steps=120) >= 10.0


def test_a_peer_about_to_reverse_gets_a_second_prediction_towards_its_centroid():
    cfg = SeparationConfig()
    east = (0.0, 0.0, 30.0, 100.0, 0.0)
    rows = peer_rows(east, (-300.0, 0.0), 44.7, cfg, own_xy=(-40.0, 0.0))
    assert rows[0] == east and len(rows) == 2
    assert rows[1][3] == pytest.approx(-100.0) and rows[1][4] == pytest.approx(0.0, abs=1e-9)
    assert peer_rows(east, (300.0, 10.0), 44.7, cfg) == [east]  # flying at it already: one row
    assert peer_rows(east, (-300.0, 0.0), 44.7, cfg, right_of_way=False) == [east]  # it yields to us
    assert peer_rows(east, (-300.0, 0.0), 44.7, cfg, own_xy=(-100.0, 0.0)) == [east]  # beyond yield_m
    assert peer_rows(east, (math.nan, 0.0), 44.7, cfg) == [east]
    assert peer_rows(east, (-300.0, 0.0), 44.7, SeparationConfig(intent=False)) == [east]
    slow = peer_rows((0.0, 0.0, 30.0, 0.0, 0.0), (0.0, 50.0), 44.7, cfg)[1]  # no velocity yet: v_stall
    assert slow[3:] == pytest.approx((0.0, 44.7))


def test_a_uav_avoids_where_a_reversing_peer_will_fly_not_only_its_straight_line():
    """Issue 16's drop-point crossing: a peer with the right of way, 40 m south, flies east at
    100 m/s; it has dropped and published a centroid (-100, 40) behind it, across our path west.
    Its straight line diverges from ours (clear); the turn it is about to make (10 rad/s, about
    0.3 s) puts it within 8 m of us in under a second. Only the second prediction sees it."""
    cfg = SeparationConfig()
    me, peer = (0.0, 40.0, 30.0), (0.0, 0.0, 30.0, 100.0, 0.0)
    straight = np.array([peer])
    head, changed, _ = avoid_heading(me, 100.0, math.pi, straight, cfg, yield_to=np.ones(1, bool))
    assert not changed and head == math.pi  # the straight line alone sees no conflict
    rows = np.array(peer_rows(peer, (-100.0, 40.0), 44.7, cfg, own_xy=me[:2]))
    turned = rows[1]
    u = -100.0 * np.array([1.0, 0.0]) - turned[3:5]  # our relative velocity on the desired heading
    assert closest_approach_m(np.array(me[:2]) - turned[:2], u, cfg.horizon_s)[0] < 10.0
    head, changed, clear = avoid_heading(me, 100.0, math.pi, rows, cfg, yield_to=np.ones(2, bool))
    assert changed and clear
    u = 100.0 * np.array([math.cos(head), math.sin(head)]) - turned[3:5]
    assert closest_approach_m(np.array(me[:2]) - turned[:2], u, cfg.horizon_s)[0] >= cfg.radius_m


def test_a_landing_uav_holds_its_layer_only_over_a_right_of_way_peer_near_and_below():
    cfg = SeparationConfig()
    me = (100.0, 240.0, 37.0)  # known fires, 14 UAVs, seed 2 at t = 26 s: UAV 1 over UAV 0
    assert hold_layer(me, [(107.0, 236.0, 23.0)], cfg)  # 8 m off, 14 m below: descending meets it
    assert not hold_layer(me, [(107.0, 236.0, 40.0)], cfg)  # above us: our descent opens the gap
    assert not hold_layer(me, [(130.0, 240.0, 23.0)], cfg)  # 30 m off (the start-point spacing)
    assert not hold_layer(me, [], cfg)


def test_bad_config_is_refused_with_the_field_named():
    with pytest.raises(ValueError, match="radius_m must be > 0"):
        SeparationConfig(radius_m=0.0)
    with pytest.raises(ValueError, match="headings must be >= 4"):
        SeparationConfig(headings=2)


# --- a fixed-wing's own prediction turns at its achievable rate ----------------------------------
def _flown_min_distance(rel, vel, speed, heading, cand, rate, horizon, dt=0.001):
    """Brute force: integrate the turn-then-straight own motion finely, peers straight."""
    import math as m

    x = y = 0.0
    th = heading
    best = min(m.hypot(r[0], r[1]) for r in rel)
    for k in range(1, int(round(horizon / dt)) + 1):
        err = m.remainder(cand - th, m.tau)
        step = max(-rate * dt, min(rate * dt, err))
        x += speed * dt * m.cos(th + 0.5 * step)
        y += speed * dt * m.sin(th + 0.5 * step)
        th += step
        t = k * dt
        if k % 100 == 0:
            best = min(
                best,
                min(m.hypot(r[0] + v[0] * t - x, r[1] + v[1] * t - y) for r, v in zip(rel, vel, strict=True)),
            )
    return best


def test_the_turning_prediction_matches_a_flown_turn_and_reduces_to_the_straight_one():
    from fire_uav_agent.separation import turning_approach_m

    rel = np.array([[60.0, 10.0], [-20.0, 40.0]])
    vel = np.array([[-15.0, 0.0], [5.0, -10.0]])
    cands = np.array([0.0, 1.2, -2.5, 3.0])
    got = turning_approach_m(rel, vel, 16.0, 0.3, cands, 0.6, 3.0)
    want = [_flown_min_distance(rel, vel, 16.0, 0.3, c, 0.6, 3.0) for c in cands]
    assert got == pytest.approx(want, abs=0.05)
    # an instant turn (FF's unicycle): the straight-line closest approach at the same samples
    fast = turning_approach_m(rel, vel, 16.0, 0.3, cands, 1e6, 3.0)
    for c, f in zip(cands, fast, strict=True):
        u = 16.0 * np.array([np.cos(c), np.sin(c)])
        straight = closest_approach_m(rel, vel - u, 3.0).min()
        assert f == pytest.approx(straight, abs=0.5)


def test_a_fixed_wing_does_not_count_on_a_turn_it_cannot_fly():
    """Head-on at 80 m, closing at 32 m/s. Taking a heading at once, 20 deg off looks clear; turned
    at 0.6 rad/s it passes at 12 m. With the turn rate the filter picks a heading that is clear as
    flown (over the quarter-turn horizon, 2.6 s)."""
    from fire_uav_agent.separation import turning_approach_m

    cfg = SeparationConfig()
    peer = np.array([[80.0, 0.0, 30.0, -16.0, 0.0]])
    head_fast, changed_fast, _ = avoid_heading((0.0, 0.0, 30.0), 16.0, 0.0, peer, cfg)
    head, changed, clear = avoid_heading(
        (0.0, 0.0, 30.0), 16.0, 0.0, peer, cfg, turn_rate_radps=0.6, heading_rad=0.0
    )
    flown = turning_approach_m(
        peer[:, :2], peer[:, 3:5], 16.0, 0.0, np.array([head_fast, head]), 0.6, 0.5 * math.pi / 0.6
    )
    assert changed_fast and changed and clear
    assert flown[0] < cfg.radius_m <= flown[1]
