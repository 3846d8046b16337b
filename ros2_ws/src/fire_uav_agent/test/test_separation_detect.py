"""The avoider's detection range on a fixed-wing (``separation.detect_range_m``), against the
world's own ``coordinated_turn`` airframe flying what the agents' avoider commands.

The case it was made for (docs/airframes.md, grass_running_tanker seed 2, 763.8 s): two tankers
on one 8 m layer crossing 150 deg apart at 70 and 74 m/s closed from 68 m to 7.6 m in 0.5 s; the
avoider ignored peers beyond FF's 150 m, one second at that closing speed, for an aircraft that
needs 12 s for a quarter turn. Here two tanker-preset UAVs meet head on at the preset's top speed
on one layer, each behind the agent's last stage (``PeerAvoidance.command``, the right of way to
the lower id), each seeing the other's published position every control step.
"""

import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.separation import PeerAvoidance, SeparationConfig, avoid_heading, detect_range_m
from fire_uav_agent.testing.avoider_pair import closest_approach_flown
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.constants import Objective
from fire_uav_common.scenario import AIRFRAMES, load_scenario
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel

TANKER = AIRFRAMES["tanker"]
T = 0.1  # [s] control period
SUBSTEPS = 10  # the world's 100 Hz physics


@pytest.fixture(scope="module")
def tanker_cfg():
    """UAV 0's config of the tanker scenario (the separation config as the agents get it)."""
    sc = load_scenario(scenario_path("ff_two_fires_tanker"))
    return config_from_scenario(sc, 0, uav_count=2, seed=1)


def _head_on(sep: SeparationConfig, lim, gap_m: float = 3000.0, offset_m: float = 0.0) -> float:
    """Two tankers ``gap_m`` apart head on at the preset's top speed, one layer, ``offset_m`` off
    each other's track; each steers at a point far beyond the other. The closest approach [m] of
    the world's truth over 40 s (they meet after ~20 s)."""
    v = TANKER.v_max_mps
    model = CoordinatedTurnModel(TANKER, 0.0)
    start = [FlightState(0.0, 0.0, 30.0, 0.0), FlightState(gap_m, offset_m, 30.0, math.pi)]
    states = [model.launch(s, Command(v, 0.0, 0.0)) for s in start]
    targets = [(gap_m + 10_000.0, 0.0), (-10_000.0, offset_m)]

    def rate(v_mps: float) -> float:  # as agent_core gives the avoider its airframe's turn rate
        return min(lim.omega_max_radps, TANKER.turn_rate_max_radps(v_mps))

    avoiders = [
        PeerAvoidance(i, T, sep, lim.v_stall_mps, lim.v_max_mps, lim.omega_max_radps, rate) for i in (0, 1)
    ]
    return closest_approach_flown(
        model,
        states,
        targets,
        lambda i, s: (v, 0.0, 0.0),
        avoiders,
        lim.omega_max_radps,
        int(40.0 / T),
        Objective.SEARCH,
        T,
        SUBSTEPS,
    )


def test_the_tankers_range_covers_its_turning_horizon_at_top_speed(tanker_cfg):
    """2 v_max H + radius, H the quarter turn at v_max: pi / 2 x 75 / (g tan 45 deg) = 12.01 s."""
    h = 0.5 * math.pi * 75.0 / (9.80665 * math.tan(math.radians(45.0)))
    assert tanker_cfg.separation.detect_m == pytest.approx(2 * 75.0 * h + 20.0, rel=1e-9)
    assert tanker_cfg.separation.detect_m == pytest.approx(1822.0, abs=0.5)


def test_ff_paper_keeps_the_150_m_range():
    sc = load_scenario(scenario_path("ff_two_fires"))
    assert config_from_scenario(sc, 0, uav_count=2, seed=1).separation.detect_m == 150.0


@pytest.mark.parametrize("offset_m", [0.0, 6.0, -6.0])
def test_two_tankers_head_on_at_top_speed_keep_ten_metres(tanker_cfg, offset_m):
    assert _head_on(tanker_cfg.separation, tanker_cfg.limits, offset_m=offset_m) >= 10.0


@pytest.mark.parametrize("offset_m", [0.0, 6.0, -6.0])
def test_seen_only_within_150_m_the_same_pair_passes_within_ten_metres(tanker_cfg, offset_m):
    """The truth behind the test above: with FF's 150 m range (a second of warning at 150 m/s)
    the tankers cannot turn away in time (1.9 / 7.8 / 7.8 m)."""
    old = SeparationConfig(vertical_rates=tanker_cfg.separation.vertical_rates)
    assert old.detect_m == 150.0
    assert _head_on(old, tanker_cfg.limits, offset_m=offset_m) < 10.0


def test_the_range_is_never_below_the_configured_one():
    """A slow airframe whose horizon is the straight 2 s keeps the 150 m (2 x 20 x 2 + 20 = 100 m)."""
    assert detect_range_m(SeparationConfig(), 20.0, 2.0) == 150.0
    assert detect_range_m(SeparationConfig(), 50.0, 2.0) == pytest.approx(2 * 50.0 * 2.0 + 20.0)


# --- the on-course rule beyond on_course_beyond_m (module doc, "Detection range") ---------------


def _course_meets_m(own_xy, speed_mps, heading_rad, peer, horizon_s, n=8001):
    """Brute force: the closest distance [m] between our present course (straight at ``speed_mps``
    on ``heading_rad`` from ``own_xy``) and a peer row's straight line, sampled over the horizon."""
    t = np.linspace(0.0, horizon_s, n)
    ox = own_xy[0] + speed_mps * math.cos(heading_rad) * t
    oy = own_xy[1] + speed_mps * math.sin(heading_rad) * t
    return float(np.min(np.hypot(peer[0] + peer[3] * t - ox, peer[1] + peer[4] * t - oy)))


def test_beyond_150_m_a_peer_counts_only_when_the_present_course_meets_it():
    """Random peers 150-400 m away (seeded), half of them flying at us, and half the time we want
    to fly at them: each is ignored (the answer
    is the one with no peer) exactly when our present course, sampled, keeps it 30 m (radius +
    release margin) or more away over the horizon; otherwise it counts (the answer is the one with
    the rule off)."""
    cfg = SeparationConfig(detect_m=400.0)
    off = SeparationConfig(detect_m=400.0, on_course_beyond_m=400.0)
    rng = np.random.default_rng(24)
    rate, speed = 0.3, 30.0
    horizon = max(cfg.horizon_s, 0.5 * math.pi / rate)  # the quarter turn: 5.24 s
    ignored_mattered = counted_mattered = 0
    for _ in range(400):
        own = (float(rng.uniform(-500, 500)), float(rng.uniform(-500, 500)), 40.0)
        heading = float(rng.uniform(-math.pi, math.pi))
        dist, bearing = float(rng.uniform(151.0, 300.0)), float(rng.uniform(-math.pi, math.pi))
        # wanting to fly at the peer, or near our course
        desired = (bearing if rng.random() < 0.5 else heading) + float(rng.normal(0.0, 0.3))
        px, py = own[0] + dist * math.cos(bearing), own[1] + dist * math.sin(bearing)
        if rng.random() < 0.5:  # at us, give or take
            course = bearing + math.pi + float(rng.normal(0.0, 0.15))
        else:
            course = float(rng.uniform(-math.pi, math.pi))
        pv = float(rng.uniform(10.0, 35.0))
        peer = np.array([[px, py, 40.0, pv * math.cos(course), pv * math.sin(course)]])
        meets = _course_meets_m(own, speed, heading, peer[0], horizon)
        if abs(meets - 30.0) < 0.05:
            continue  # too close to the line to decide by sampling
        args = (own, speed, desired)
        kw = {"turn_rate_radps": rate, "heading_rad": heading}
        got = avoid_heading(*args, peer, cfg, **kw)
        alone = avoid_heading(*args, np.zeros((0, 5)), cfg, **kw)
        full = avoid_heading(*args, peer, off, **kw)
        if meets >= 30.0:
            assert got == alone
            ignored_mattered += full != alone
        else:
            assert got == full
            counted_mattered += full != alone
    # the cases tell the two sides apart: counting an ignored peer would have changed the answer
    assert ignored_mattered >= 10 and counted_mattered >= 5  # 21 and 9


def test_the_on_course_rule_is_for_fixed_wings_only():
    """A peer 200 m north coming south at 100 m/s, we heading east and wanting north: our course
    keeps it 141 m off (relative velocity (-100, -100) from (0, 200)), so a fixed-wing ignores it;
    FF's unicycle (no turn rate) takes the heading at once and sees it 200 m ahead closing at
    200 m/s within its 2 s horizon."""
    cfg = SeparationConfig(detect_m=400.0)
    peer = np.array([[0.0, 200.0, 30.0, 0.0, -100.0]])
    up = 0.5 * math.pi
    assert avoid_heading((0.0, 0.0, 30.0), 100.0, up, peer, cfg, heading_rad=0.0)[1]
    fixed = avoid_heading((0.0, 0.0, 30.0), 100.0, up, peer, cfg, turn_rate_radps=10.0, heading_rad=0.0)
    assert fixed == (up, False, True)


def test_a_peer_at_on_course_beyond_m_counts_whatever_the_course():
    """A still peer due east, we heading north (course 150 m off it) and wanting east (straight at
    it, 200 m in the 2 s horizon): at exactly 150 m it counts, 1 cm further it is ignored."""
    cfg = SeparationConfig(detect_m=400.0)
    for dx, counts in ((150.0, True), (150.01, False)):
        peer = np.array([[dx, 0.0, 30.0, 0.0, 0.0]])
        got = avoid_heading(
            (0.0, 0.0, 30.0), 100.0, 0.0, peer, cfg, turn_rate_radps=10.0, heading_rad=0.5 * math.pi
        )
        assert got[1] is counts


def test_a_course_passing_exactly_radius_plus_margin_off_clears_the_peer():
    """We fly east at 10 m/s; a still peer at (200, y) is passed y off at t = 20 s (inside the
    31.4 s quarter turn at 0.05 rad/s). Wanting to fly at it, a counted peer deviates us. At y =
    radius + release margin (30 m) the course clears it, as the Avoider's release clears a heading
    (>=); 10 cm nearer it counts."""
    cfg = SeparationConfig(detect_m=400.0)
    for y, counts in ((30.0, False), (29.9, True), (10.0, True)):
        peer = np.array([[200.0, y, 30.0, 0.0, 0.0]])
        want = math.atan2(y, 200.0)
        got = avoid_heading((0.0, 0.0, 30.0), 10.0, want, peer, cfg, turn_rate_radps=0.05, heading_rad=0.0)
        assert got[1] is counts, y
