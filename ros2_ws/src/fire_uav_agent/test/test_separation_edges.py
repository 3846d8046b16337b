"""The separation filter's geometry at its edges, against a brute-force kinematic reference
(positions sampled along the straight-line prediction), not the module's closed form; and the
agent's last stage (``PeerAvoidance.command``) and the ``Avoider``'s memory against their
documented steps written out."""

import math

import numpy as np
import pytest
from fire_uav_agent.separation import (
    Avoider,
    PeerAvoidance,
    SeparationConfig,
    avoid_heading,
    closest_approach_m,
    hold_layer,
    peer_rows,
    turning_approach_m,
)
from fire_uav_common.angles import wrap_angle
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective

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


# --- PeerAvoidance.command: the peers' motion and the command, against its documented steps ----


def _reference_command(ref, s, cmd, target, peers, last_step, straight, cfg, lim, rate, uav_id):
    """PeerAvoidance.command's documented steps written out over plain floats: each flying peer's
    velocity from its last two states (``ref['motion']``: id -> step, x, y, z, vx, vy, vz; none
    across a jump faster than 1.5 v_max, the last one kept for a repeated step), its position moved
    from its step to ours plus one, :func:`peer_rows` with the right of way to lower ids, then the
    :class:`Avoider` (``ref['avoider']``) and the turn to its heading within omega_max."""
    v_stall, v_max, om_max = lim
    T = 0.1
    rows, yt = [], []
    for j in sorted(peers):
        p = peers[j]
        if p.objective in (int(Objective.GROUNDED), int(Objective.LANDED)):
            continue
        old = ref["motion"].get(j)
        vel = (0.0, 0.0, 0.0)
        if old is not None and p.step > old[0]:
            gap = (p.step - old[0]) * T
            vel = ((p.x_m - old[1]) / gap, (p.y_m - old[2]) / gap, (p.z_m - old[3]) / gap)
            if math.hypot(vel[0], vel[1]) > 1.5 * v_max:
                vel = (0.0, 0.0, 0.0)
        elif old is not None:
            vel = old[4:]
        if old is None or p.step != old[0]:
            ref["motion"][j] = (p.step, p.x_m, p.y_m, p.z_m, *vel)
        lead = (last_step + 1 - p.step) * T
        z = p.z_m + vel[2] * lead if cfg.vertical_rates else p.z_m
        state = (p.x_m + vel[0] * lead, p.y_m + vel[1] * lead, z, vel[0], vel[1])
        for row in peer_rows(state, (p.centroid_x_m, p.centroid_y_m), v_stall, cfg, (s[0], s[1]), j < uav_id):
            rows.append((*row, vel[2]))
            yt.append(j < uav_id)
    if not rows:
        return cmd, False
    v, vz, _ = cmd
    want = s[3] if straight else math.atan2(target[1] - s[1], target[0] - s[0])
    speed = max(v, v_stall)
    head, changed, clear = ref["avoider"].step(
        (s[0], s[1], s[2]), speed, want, np.array(rows), np.array(yt, bool),
        None if rate is None else rate(speed), s[3], vz,
    )  # fmt: skip
    if not changed:
        return cmd, False
    turn = math.remainder(head - s[3], 2 * math.pi)
    return (v if clear else v_stall, vz, min(om_max, max(-om_max, turn / T))), True


@pytest.mark.parametrize("case", range(6))
def test_the_commands_follow_the_documented_steps_over_random_peer_histories(case):
    """Random seeded histories of three peers around UAV 2 (ids 0, 1 with the right of way, 3
    without) over 40 steps: steps repeated and skipped, jumps, peers grounded or landed for a while,
    centroids to turn to, climbs, straight-on steps, with and without vertical rates and a turn
    rate; the command equals the reference's at every step, and so does the count of changed ones."""
    rng = np.random.default_rng(100 + case)
    cfg = SeparationConfig(vertical_rates=bool(case % 2), detect_m=150.0 + 100.0 * (case % 3 == 2))
    lim = (12.0, 30.0, 0.8)  # v_stall, v_max, omega_max

    def rate(v_mps):  # a coordinated turn's rate at 45 deg of bank (B&M Eq. 9.14)
        return 9.80665 / v_mps

    turn_rate = rate if case >= 3 else None
    pa = PeerAvoidance(2, 0.1, cfg, *lim, turn_rate)
    ref = {"motion": {}, "avoider": Avoider(cfg)}
    own = np.array(
        [float(rng.uniform(-300, 300)), float(rng.uniform(-300, 300)), 40.0, float(rng.uniform(-3, 3))]
    )
    pos = {j: own[:3] + np.array([*rng.uniform(-40, 40, 2), rng.uniform(-6, 6)]) for j in (0, 1, 3)}
    vel = {j: np.array([*rng.uniform(-25, 25, 2), rng.uniform(-3, 3)]) for j in (0, 1, 3)}
    step = {j: 0 for j in (0, 1, 3)}
    changed_steps = 0
    handed: dict[str, list] = {"module": [], "reference": []}  # what each Avoider is asked

    def spy(av, key):
        real = av.step
        av.step = lambda *a: (handed[key].append(a), real(*a))[1]

    spy(pa.avoider, "module")
    spy(ref["avoider"], "reference")
    for k in range(40):
        peers = {}
        for j in (0, 1, 3):
            if rng.random() < 0.2:  # a new velocity
                vel[j] = np.array([*rng.uniform(-25, 25, 2), rng.uniform(-3, 3)])
            r = rng.random()
            if r < 0.15:  # a state skipped: the peer's step advances by two
                step[j] += 2
                pos[j] = pos[j] + 2 * 0.1 * vel[j]
            elif r < 0.25:  # the same state again
                pass
            else:
                step[j] += 1
                pos[j] = pos[j] + 0.1 * vel[j]
            x, y, z = pos[j]
            if rng.random() < 0.05:  # a jump (GPS reset): 100 m in one step
                x += 100.0
            elif rng.random() < 0.05:  # 2 v_max for a step: a jump too
                x += 6.0
            obj = Objective.SEARCH
            if rng.random() < 0.1:
                obj = Objective.GROUNDED if rng.random() < 0.5 else Objective.LANDED
            cx, cy = (math.nan, math.nan) if rng.random() < 0.3 else (float(x - 40.0), float(y + 25.0))
            peers[j] = PeerState(
                j, step[j], step[j], float(x), float(y), float(z), 0.0, int(obj), -1, 0.0, cx, cy
            )
        cmd = (float(rng.uniform(5.0, 30.0)), float(rng.uniform(-3, 3)), float(rng.uniform(-0.5, 0.5)))
        target = (float(own[0] + rng.uniform(-200, 200)), float(own[1] + rng.uniform(-200, 200)))
        straight = bool(rng.random() < 0.2)
        last = k + int(rng.integers(0, 2))
        if straight or rng.random() < 0.5:
            got = pa.command(own.copy(), cmd, target, peers, last, straight)
        else:  # the default: steer at the target
            got = pa.command(own.copy(), cmd, target, peers, last)
        want, changed = _reference_command(
            ref, tuple(own), cmd, target, peers, last, straight, cfg, lim, turn_rate, 2
        )
        assert got[:2] == want[:2], k
        assert got[2] == pytest.approx(want[2], rel=1e-12, abs=1e-12), k  # the turn's wrap: to the ulp
        changed_steps += changed
        own[:2] += 0.1 * got[0] * np.array([math.cos(own[3]), math.sin(own[3])])
        own[3] = math.remainder(own[3] + 0.1 * got[2], 2 * math.pi)
    assert pa.steps_changed == changed_steps
    # the rows, flags, turn rate, heading and vertical speed handed over, not only the outcome
    assert len(handed["module"]) == len(handed["reference"]) > 0
    for a, b in zip(handed["module"], handed["reference"], strict=True):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            if isinstance(x, np.ndarray):
                assert x.dtype == y.dtype and np.array_equal(x, y)
            else:
                assert x == y
    assert changed_steps >= 3  # the peers are close enough that the filter acts


def test_the_avoider_keeps_its_deviation_with_the_release_margin_as_documented():
    """Avoider.step is avoid_heading with the release margin and its last deviation preferred while
    avoiding, none of either otherwise; every other argument handed through (written out here over
    a sequence of steps with a fixed-wing's turn rate, right-of-way flags and vertical rates)."""
    cfg = SeparationConfig(vertical_rates=True)
    av = Avoider(cfg)
    rng = np.random.default_rng(7)
    last = None
    deviated = 0
    for _ in range(30):
        own = (float(rng.uniform(-50, 50)), float(rng.uniform(-50, 50)), 40.0)
        peers = np.column_stack(
            [rng.uniform(-60, 60, 3) + own[0], rng.uniform(-60, 60, 3) + own[1], 40.0 + rng.uniform(-12, 12, 3),
             rng.uniform(-20, 20, 3), rng.uniform(-20, 20, 3), rng.uniform(-4, 4, 3)]
        )  # fmt: skip
        yt = rng.random(3) < 0.5
        want, head_now, vz = float(rng.uniform(-3, 3)), float(rng.uniform(-3, 3)), float(rng.uniform(-4, 4))
        margin = 0.0 if last is None else cfg.release_margin_m
        expect = avoid_heading(own, 20.0, want, peers, cfg, margin, last, yt, 0.5, head_now, vz)
        assert av.step(own, 20.0, want, peers, yt, 0.5, head_now, vz) == expect
        last = expect[0] if expect[1] else None
        assert av.heading_rad == last
        deviated += expect[1]
    assert 5 <= deviated <= 25  # both branches, several times


def test_flat_and_empty_peer_arrays_and_column_flags():
    """One row given flat is that row; no peers (an empty list) is no conflict; flags given as a
    column or as 0/1 are read one per row."""
    cfg = SeparationConfig()
    row = [100.0, 5.0, 30.0, -100.0, 0.0]
    assert avoid_heading((0.0, 0.0, 30.0), 100.0, 0.0, np.array(row), cfg) == avoid_heading(
        (0.0, 0.0, 30.0), 100.0, 0.0, np.array([row]), cfg
    )
    assert avoid_heading((0.0, 0.0, 30.0), 100.0, 0.7, [], cfg) == (0.7, False, True)
    peers = np.array([[40.0, 0.0, 30.0, 0.0, 0.0], [-40.0, 0.0, 30.0, 0.0, 0.0]])
    # the right-of-way peer ahead (40 m < yield_m): no heading that closes on it
    want = avoid_heading((0.0, 0.0, 30.0), 20.0, 0.0, peers, cfg, yield_to=np.array([True, False]))
    assert want[1] and math.cos(want[0]) <= 1e-9
    for flags in (np.array([[True], [False]]), [1, 0]):
        assert avoid_heading((0.0, 0.0, 30.0), 20.0, 0.0, peers, cfg, yield_to=flags) == want


def test_vertical_rates_with_five_column_rows_take_the_peer_level():
    """With vertical rates, a row without vz is a peer holding its height: 10.5 m below us, we
    level, it stays 10.5 m below (no conflict); with vz = +1 m/s it comes within 10 m (8.5 m at 2 s)."""
    cfg = SeparationConfig(vertical_rates=True)
    level = np.array([[60.0, 0.0, 19.5, -20.0, 0.0]])
    climbing = np.array([[60.0, 0.0, 19.5, -20.0, 0.0, 1.0]])
    assert avoid_heading((0.0, 0.0, 30.0), 20.0, 0.0, level, cfg) == (0.0, False, True)
    assert avoid_heading((0.0, 0.0, 30.0), 20.0, 0.0, climbing, cfg)[1]


@pytest.mark.parametrize(
    ("dz_m", "vz_mps", "conflict"), [(0.5, 0.25, False), (0.5, -0.5, True), (-0.5, 0.5, True)]
)
def test_a_sub_metre_band_reads_the_height_difference_over_the_horizon(dz_m, vz_mps, conflict):
    """vertical_m 0.3: a peer 0.5 m above climbing away at 0.25 m/s stays 0.5-1.0 m above (clear);
    one crossing our height within the 2 s horizon (0.5 -> -0.5 m, -0.5 -> 0.5 m) is a conflict."""
    cfg = SeparationConfig(vertical_m=0.3, vertical_rates=True)
    peer = np.array([[60.0, 0.0, 30.0 + dz_m, -20.0, 0.0, vz_mps]])
    assert avoid_heading((0.0, 0.0, 30.0), 20.0, 0.0, peer, cfg)[1] is conflict


def test_a_right_of_way_peer_due_north_does_not_hold_a_landing_uav():
    """30 m north and below: outside the 20 m radius (the y offset counts)."""
    assert not hold_layer((5.0, 7.0, 30.0), [(5.0, 37.0, 20.0)], SeparationConfig())
    assert hold_layer((5.0, 7.0, 30.0), [(5.0, 22.0, 20.0)], SeparationConfig())


def test_intent_rows_off_the_origin_and_off_the_axes():
    """The intent row: the peer at its speed straight at its centroid (the bearing by hand), for a
    peer and a UAV off the origin, within yield_m (60 m, inclusive) by the full 2-D distance, a
    centroid 0.5 m off still a target; none for a peer already flying at its centroid (course
    +y), nor for one turning by exactly intent_min_turn_rad ("more than")."""
    cfg = SeparationConfig()
    own = (100.0, 200.0)
    st = (100.0, 260.0, 30.0, 0.0, 25.0)  # 60 m north of us, flying north at 25 m/s
    rows = peer_rows(st, (130.0, 220.0), 10.0, cfg, own)
    assert len(rows) == 2
    b = math.atan2(220.0 - 260.0, 130.0 - 100.0)
    assert rows[1][:3] == st[:3]
    assert rows[1][3:] == pytest.approx((25.0 * math.cos(b), 25.0 * math.sin(b)), rel=1e-12)
    assert len(peer_rows(st, (130.0, 220.0), 10.0, cfg, (100.0, 199.99))) == 1  # 60.01 m away
    assert len(peer_rows(st, (130.0, 220.0), 10.0, cfg, (140.0, 260.0 + 45.0))) == 1  # 60.2 m off diagonally
    assert len(peer_rows(st, (100.0, 400.0), 10.0, cfg, own)) == 1  # already flying at it
    assert len(peer_rows(st, (100.0, 259.5), 10.0, cfg, own)) == 2  # right behind it, 0.5 m
    slow = (100.0, 260.0, 30.0, 0.0, 0.5)  # 0.5 m/s north, centroid ahead: no turn
    assert len(peer_rows(slow, (100.0, 300.0), 10.0, cfg, own)) == 1
    edge = SeparationConfig(intent_min_turn_rad=wrap_angle(math.atan2(0.25, 1.0)))  # the angle as it is read
    east = (100.0, 260.0, 30.0, 25.0, 0.0)
    assert len(peer_rows(east, (101.0, 260.25), 10.0, edge, own)) == 1
    assert len(peer_rows(east, (101.0, 260.5), 10.0, edge, own)) == 2


def test_the_turning_prediction_at_its_first_and_last_sample_and_straight_on():
    """A peer 5 m off now and moving away: the closest is now (t = 0); one closing until the
    horizon's end: the closest is at 3.0 s, not beyond; a candidate equal to the heading is the
    straight line (no turn), by hand."""
    away = turning_approach_m(
        np.array([[5.0, 0.0]]), np.array([[30.0, 0.0]]), 10.0, 0.0, np.array([0.0]), 0.5, 3.0
    )
    assert away[0] == pytest.approx(5.0)
    closing = turning_approach_m(
        np.array([[100.0, 0.0]]), np.array([[-10.0, 0.0]]), 10.0, 0.0, np.array([0.0]), 0.5, 3.0
    )
    assert closing[0] == pytest.approx(100.0 - 3.0 * 20.0)
    for h in (0.0, 1.1, -2.0):
        got = turning_approach_m(
            np.array([[50.0, 30.0]]), np.array([[-5.0, 2.0]]), 12.0, h, np.array([[h]]), 0.5, 3.0
        )
        t = np.arange(0.0, 3.0 + 1e-9, 0.1)
        d = np.hypot(50.0 - 5.0 * t - 12.0 * math.cos(h) * t, 30.0 + 2.0 * t - 12.0 * math.sin(h) * t)
        assert got.shape == (1,) and got[0] == pytest.approx(d.min(), rel=1e-12)


def test_the_avoiders_defaults_are_avoid_headings():
    """Called without the heading and the vertical speed, the Avoider's first step is avoid_heading's
    answer with its own defaults (a fixed-wing turning from heading 0, level): peers ahead that
    conflict only when turning from +x, and a level peer 10.5 m above, head on, which is no conflict
    for a level UAV but one for a UAV climbing at 1 m/s (6.6 m at the 3.9 s horizon)."""
    cfg = SeparationConfig(vertical_rates=True)
    ahead = np.array([[70.0, 15.0, 30.0, -10.0, 0.0, 0.0], [20.0, -60.0, 24.0, 0.0, 15.0, 3.0]])
    above = np.array([[60.0, 0.0, 40.5, -15.0, 0.0, 0.0]])
    for peers in (ahead, above):
        for want in (0.0, 0.8, -1.4):
            expect = avoid_heading((0.0, 0.0, 30.0), 15.0, want, peers, cfg, turn_rate_radps=0.4)
            assert Avoider(cfg).step((0.0, 0.0, 30.0), 15.0, want, peers, turn_rate_radps=0.4) == expect
    # the defaults matter for these peers
    turned = avoid_heading((0.0, 0.0, 30.0), 15.0, 0.8, ahead, cfg, turn_rate_radps=0.4, heading_rad=1.0)
    assert turned != avoid_heading((0.0, 0.0, 30.0), 15.0, 0.8, ahead, cfg, turn_rate_radps=0.4)
    assert avoid_heading((0.0, 0.0, 30.0), 15.0, 0.0, above, cfg, turn_rate_radps=0.4) == (0.0, False, True)
    assert avoid_heading((0.0, 0.0, 30.0), 15.0, 0.0, above, cfg, turn_rate_radps=0.4, own_vz_mps=1.0)[1]


def test_with_nothing_clear_the_nearest_right_of_way_peer_is_the_one_left():
    """Boxed in by four still peers 15-16 m around us, two with the right of way: (-15.5, 0) first
    and (0, 15) second; the nearer is the second, though the first is nearer on the y axis alone."""
    cfg = SeparationConfig()
    peers = np.array([[15.0, 1.0, 30.0, 0.0, 0.0], [-15.5, 0.0, 30.0, 0.0, 0.0],
                      [0.0, 15.0, 30.0, 0.0, 0.0], [0.0, -16.0, 30.0, 0.0, 0.0]])  # fmt: skip
    h, deviated, clear = avoid_heading(
        (0.0, 0.0, 30.0), SPEED, 0.3, peers, cfg, yield_to=np.array([False, True, True, False])
    )
    assert (deviated, clear) == (True, True) and h == pytest.approx(-math.pi / 2)  # away from (0, 15)


def test_a_right_of_way_peer_exactly_yield_m_away_is_within_it():
    """A still right-of-way peer 60 m ahead; flying at it at 10 m/s closes to 40 m (clear of 20 m),
    but within yield_m (inclusive, as detect_m) no heading may close on it; 1 cm further it may."""
    cfg = SeparationConfig()
    for dx, deviates in ((60.0, True), (60.01, False)):
        peer = np.array([[dx, 0.0, 30.0, 0.0, 0.0]])
        assert avoid_heading((0.0, 0.0, 30.0), 10.0, 0.0, peer, cfg, yield_to=np.array([True]))[1] is deviates


def test_the_unicycles_look_ahead_ends_at_the_horizon():
    """A peer 100 m ahead on our track, flying our way 20 m/s slower: 60 m apart at the 2 s horizon
    (clear), though it would be caught up with after 5 s."""
    cfg = SeparationConfig()
    peer = np.array([[100.0, 0.0, 30.0, 80.0, 0.0]])
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, peer, cfg) == (0.0, False, True)


def test_a_closest_approach_of_exactly_the_radius_is_clear():
    """Head on 20 m abeam: rel (100, 20), closing at 200 m/s, closest (0, 20) at t = 0.5 s, exactly
    radius_m (the filter acts when it 'would fall below'); 1 cm nearer it acts."""
    cfg = SeparationConfig()
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, np.array([[100.0, 20.0, 30.0, -SPEED, 0.0]]), cfg) == (
        0.0,
        False,
        True,
    )
    assert avoid_heading((0.0, 0.0, 30.0), SPEED, 0.0, np.array([[100.0, 19.99, 30.0, -SPEED, 0.0]]), cfg)[1]


def test_a_fresh_avoider_needs_the_radius_only():
    """Not avoiding, the desired heading needs radius_m (no margin): a peer passing 20.5 m abeam."""
    cfg = SeparationConfig()
    peer = np.array([[100.0, 20.5, 30.0, -SPEED, 0.0]])
    assert Avoider(cfg).step((0.0, 0.0, 30.0), SPEED, 0.0, peer) == (0.0, False, True)


def _recording(step, seen):
    """An Avoider.step that records the peer rows it is handed."""

    def rec(*a, **k):
        seen.append(a[3])
        return step(*a, **k)

    return rec


def test_a_peer_moving_exactly_one_and_a_half_v_max_is_no_jump():
    """A jump is a velocity faster than 1.5 v_max (32 m/s): 6 m in a 0.125 s step is 48 m/s exactly,
    kept; 6.01 m is a jump (no velocity). The velocity shows in the peer's row handed to the avoider."""
    for dx, vx in ((6.0, 48.0), (6.01, 0.0)):
        pa = PeerAvoidance(2, 0.125, SeparationConfig(), 10.0, 32.0, 1.0)
        seen: list = []
        pa.avoider.step = _recording(pa.avoider.step, seen)
        for k, x in ((0, 30.0), (1, 30.0 + dx)):
            p = PeerState(0, k, k, x, 5.0, 40.0, 0.0, int(Objective.SEARCH))
            pa.command(np.array([0.0, 0.0, 40.0, 0.0]), (20.0, 0.0, 0.0), (500.0, 0.0), {0: p}, k)
        assert seen[-1][0][3] == vx


def test_a_heading_square_to_a_right_of_way_peer_does_not_close_on_it():
    """cos(heading, bearing from the peer) >= 0 is allowed: a still right-of-way peer 32 m to our
    left (clear of the 20 m radius), we flying east, square to it: the desired heading is kept."""
    peer = np.array([[0.0, 32.0, 30.0, 0.0, 0.0]])
    got = avoid_heading((0.0, 0.0, 30.0), 10.0, 0.0, peer, SeparationConfig(), yield_to=np.array([True]))
    assert got == (0.0, False, True)
