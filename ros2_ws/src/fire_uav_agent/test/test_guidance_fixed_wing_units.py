"""Unit checks of the fixed-wing guidance (``fire_uav_agent.guidance.Guide``): the lined-up final's
glide path, the landing entry, the lake approach and the drop run's leg, each against geometry
worked by hand or Beard & McLain ch. 10 (the straight-line and orbit fields), never the code's own
formula. Fast (module-scope agents), so that the mutation run can select this file.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.guidance import _glide_height
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective
from fire_uav_common.scenario import load_scenario
from fire_world_sim.drop_pattern import Release, pattern_of


@pytest.mark.parametrize(
    "dist, want",
    [
        # layer 30 m, low 2 m, flat 0.2 of a 1000 m leg: level at 2 m for the last 200 m, then a
        # straight line up to 30 m at 1000 m (28 m over 800 m), and 30 m beyond the leg
        (0.0, 2.0),
        (200.0, 2.0),
        (600.0, 2.0 + 28.0 * 0.5),
        (1000.0, 30.0),
        (5000.0, 30.0),
    ],
)
def test_the_glide_path_is_flat_then_a_straight_line_up_to_the_layer(dist, want):
    assert _glide_height(dist, 30.0, 2.0, 0.2, 1000.0) == pytest.approx(want, abs=1e-9)


# --- the agents (one scenario load per module; an Agent is made in about a millisecond) ----------

G = 9.80665  # [m/s^2]


def _turn_radius(v_mps: float, bank_deg: float) -> float:
    """B&M Eq. 9.14 for a level coordinated turn: v^2 / (g tan(phi))."""
    return v_mps * v_mps / (G * math.tan(math.radians(bank_deg)))


@pytest.fixture(scope="module")
def scenarios():
    return {
        "small": load_scenario(
            scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "coordinated_turn"}
        ),
        "j3cub": load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "jsbsim"}),
        "tanker": load_scenario(scenario_path("grass_running_tanker")),
        "ff": load_scenario(scenario_path("ff_two_fires")),
        "ff_pattern": load_scenario(
            scenario_path("grass_running"), overrides={"fires.drop_model": "pattern"}
        ),
    }


def _agent(sc, uid: int, **kw) -> Agent:
    return Agent(config_from_scenario(sc, uid, uav_count=5, seed=1, loss_probability=0.0, **kw))


def test_the_low_and_slow_speed_and_the_lake_margin_of_each_airframe(scenarios):
    """Low and slow (FF IV-D b): the lowest commanded speed plus 0.3 of the world's 10 m/s refill
    margin. The lake zone's margin beyond the shore is FF's 150 m, or farther where the airframe
    cannot slow from its top speed to that speed at its deceleration limit ((v0^2 - v1^2) / 2a, the
    tanker) or descend from its FF layer to the 7.5 m scoop height at its descent limit (v h /
    descent_max, the J3Cub: 1.4 m/s)."""
    small = _agent(scenarios["small"], 0).guide
    assert small.v_slow_mps == pytest.approx(12.0 * 1.3 + 3.0)
    assert small.lake_margin_m == 150.0  # slows in 92 m and descends 23 -> 7.5 m in 58 m
    j0, j1 = _agent(scenarios["j3cub"], 0).guide, _agent(scenarios["j3cub"], 1).guide
    v = 16.5 * 4.0 / 3.0 + 3.0  # 25 m/s
    assert j0.v_slow_mps == pytest.approx(v)
    assert j0.lake_margin_m == pytest.approx(v * (23.0 - 7.5) / 1.4)  # the 23 m layer
    assert j1.lake_margin_m == pytest.approx(v * (37.0 - 7.5) / 1.4)  # the 37 m layer
    t = _agent(scenarios["tanker"], 0).guide
    vt = 36.0 * 1.3 + 3.0
    assert t.lake_margin_m == pytest.approx((75.0**2 - vt**2) / (2.0 * 1.0))
    ff = _agent(scenarios["ff"], 0).guide
    assert ff.lake_margin_m == 150.0 and ff.lake_clear_m == 0.0


def test_a_low_uav_leaving_the_lake_holds_it_two_stall_turn_radii_beyond_the_shore(scenarios):
    assert _agent(scenarios["small"], 0).guide.lake_clear_m == pytest.approx(2.0 * _turn_radius(15.6, 45.0))
    assert _agent(scenarios["j3cub"], 3).guide.lake_clear_m == pytest.approx(2.0 * _turn_radius(22.0, 40.0))


def test_the_lake_sequence_is_for_fixed_wings_with_the_stack_only():
    for model, seq, want in [
        ("coordinated_turn", "stack", True),
        ("coordinated_turn", "none", False),
        ("ff_paper", "stack", False),
    ]:
        sc = load_scenario(
            scenario_path("ff_two_fires"),
            overrides={"uavs.vehicle_model": model, "mission.lake_sequence": seq},
        )
        assert _agent(sc, 0).guide.lake_sequenced is want


def test_the_final_leg_of_each_airframe(scenarios):
    """The lined-up final: through the takeoff point, on the course from the area's centre snapped
    to 90 deg, on the turn radius at the lowest speed (B&M Eq. 9.14), as long as the longest of FF's
    120 m approach radius, four turn radii, the descent from the highest layer to the 0.5 m approach
    height at half the climb-rate limit at the lowest speed, and the slowdown from the top speed to
    the lowest; B&M Eq. 10.8's chi_inf 60 deg, the line's band the 2.5 m touch-down radius."""
    a0, a1 = _agent(scenarios["j3cub"], 0), _agent(scenarios["j3cub"], 1)
    ap0, ap1 = a0.guide.approach, a1.guide.approach
    assert ap0 is not None and ap1 is not None
    assert ap0.threshold_xy == (50.0, 250.0) and ap1.threshold_xy == (50.0, 280.0)
    # area (0, 600)^2, centre (300, 300): the takeoff points lie west of it, the final flies west
    assert abs(math.remainder(ap0.course_rad - math.pi, math.tau)) < 1e-9
    r = _turn_radius(22.0, 40.0)
    assert ap0.turn_radius_m == pytest.approx(r)
    # J3Cub: descent at 0.7 m/s at 22 m/s from the 30 m flight height (layer 23) or layer 37
    assert ap0.length_m == pytest.approx(2.0 * 22.0 * (30.0 - 0.5) / 1.4)
    assert ap1.length_m == pytest.approx(2.0 * 22.0 * (37.0 - 0.5) / 1.4)
    assert ap0.approach_angle_rad == pytest.approx(math.radians(60.0))
    assert ap0.line_band_m == 2.5
    s = _agent(scenarios["small"], 2).guide.approach  # small_uav: the descent 184 m
    assert s is not None and s.length_m == pytest.approx(2.0 * 15.6 * 29.5 / 5.0)
    t = _agent(scenarios["tanker"], 0).guide.approach  # tanker: slowing from 75 m/s, 1,717 m
    assert t is not None and t.length_m == pytest.approx((75.0**2 - 46.8**2) / 2.0)
    assert abs(math.remainder(t.course_rad - 0.5 * math.pi, math.tau)) < 1e-9
    assert t.turn_radius_m == pytest.approx(_turn_radius(46.8, 45.0))
    assert _agent(scenarios["ff"], 0).guide.approach is None


def test_the_finals_loops_are_damped_as_second_order_loops(scenarios):
    """Around the lagging flight-path angle (tau_gamma) and bank (tau_bank), K = 1 / (2 tau) damps
    the loop s^2 + s / tau + K / tau at zeta = sqrt(1 / (4 K tau)) = 0.7071; and the line's gain k
    (B&M Eq. 10.8 linearised: e'' + K_a e' + K_a v K e = 0, K = chi_inf (2 / pi) k) damps the final
    at zeta = sqrt(K_a / (4 v K)) = 0.7 at the lowest speed. FF's gains elsewhere."""
    for key, tau_g, tau_b, v in [
        ("small", 0.8, 0.3, 15.6),
        ("j3cub", 1.5, 0.9, 22.0),
        ("tanker", 2.0, 1.0, 46.8),
    ]:
        g = _agent(scenarios[key], 0).guide
        lg = g.land_gains
        assert math.sqrt(1.0 / (4.0 * lg.kz * tau_g)) == pytest.approx(math.sqrt(0.5))
        assert math.sqrt(1.0 / (4.0 * lg.ka * tau_b)) == pytest.approx(math.sqrt(0.5))
        assert (lg.kp, lg.vz_cmd_max_mps) == (g.cfg.gains.kp, g.cfg.gains.vz_cmd_max_mps)
        assert g.cfg.gains.kz == 5.0 and g.cfg.gains.ka == 5.0  # FF's
        ap = g.approach
        assert ap is not None
        big_k = ap.approach_angle_rad * (2.0 / math.pi) * ap.line_gain_per_m
        assert math.sqrt(lg.ka / (4.0 * v * big_k)) == pytest.approx(0.7)


def test_the_height_and_pose_memories_hold_a_second(scenarios):
    g = _agent(scenarios["small"], 0).guide
    assert g._final_agl.maxlen == 10  # 1 s at 10 Hz
    assert g._poses.maxlen == 11  # 1 s of motion between the first and the last
    assert (g.on_final, g.leg, g.run_skips, g.skip_note) == (False, None, 0, None)
    assert g.leg_counts == {"leg": 0, "few_cells": 0, "no_room": 0}


def test_the_drop_runs_pattern_turn_and_lead_in(scenarios):
    """The tanker's run at 49.8 m/s lays its 3,000 L at 757 L/s over v V / Q = 197 m (drop_pattern
    (P1)), turns on v^2 / (g tan 45 deg) = 253 m, and its leg begins three turn radii plus the 16 m
    release radius before the aim (775 m, inside its 1,588 m run). Its peak coverage from the 8 m
    layer is the world's pattern's (fire_world_sim.drop_pattern). FF's unicycle with pattern drops
    (no airframe): its tank and flow, its turn rate limit, and a run of twice the release radius."""
    t = _agent(scenarios["tanker"], 0).guide
    v = 36.0 * 1.3 + 3.0
    assert t.pattern_m == pytest.approx(v * 3000.0 / 757.0)
    assert t.run_turn_m == pytest.approx(_turn_radius(v, 45.0))
    assert t.lead_in_m == pytest.approx(3.0 * _turn_radius(v, 45.0) + 16.0)
    assert t.drop_run_m == pytest.approx(16.0 + (75.0**2 - v**2) / 2.0)
    world = pattern_of(Release(0.0, 0.0, 0.0, v, 8.0, 3000.0, 757.0)).peak_lpm2
    assert t.run_peak_lpm2 == pytest.approx(world, rel=1e-9)
    u = _agent(scenarios["ff_pattern"], 1).guide
    lim, veh = u.cfg.limits, u.cfg.vehicle
    assert u.drop_run_m == pytest.approx(2.0 * 16.0)
    assert u.lead_in_m == pytest.approx(min(32.0, 3.0 * u.v_slow_mps / lim.omega_max_radps + 16.0))
    assert u.run_turn_m == pytest.approx(u.v_slow_mps / lim.omega_max_radps)
    assert u.pattern_m == pytest.approx(u.v_slow_mps * veh.water_capacity_kg / veh.drop_flow_lps)
    world = pattern_of(
        Release(0.0, 0.0, 0.0, u.v_slow_mps, 8.0, veh.water_capacity_kg, veh.drop_flow_lps)
    ).peak_lpm2
    assert u.run_peak_lpm2 == pytest.approx(world, rel=1e-9)


# --- the crab angle: course over the ground less heading, over the last second -------------------


def _track(g, course: float, yaws: list[float], step_m: float = 1.5) -> None:
    g._poses.clear()
    for k, yaw in enumerate(yaws):
        g._poses.append((100.0 + k * step_m * math.cos(course), 200.0 + k * step_m * math.sin(course), yaw))


@pytest.mark.parametrize(
    "course, yaws, want_deg",
    [
        (0.30, [0.25] * 11, math.degrees(0.05)),  # drifted left of the heading by 0.05 rad
        (0.20, [0.25] * 11, math.degrees(-0.05)),
        (
            math.pi - 0.1,
            [math.pi - 0.05, -math.pi + 0.05] * 5 + [math.pi],
            -math.degrees(0.1),
        ),  # across the wrap
        (-math.pi + 0.05, [math.pi - 0.05] * 11, math.degrees(0.1)),
        (0.8, [0.0] * 11, 30.0),  # clipped to +-30 deg
        (-0.8, [0.0] * 11, -30.0),
    ],
)
def test_the_crab_angle_is_the_course_less_the_mean_heading(scenarios, course, yaws, want_deg):
    g = _agent(scenarios["small"], 0).guide
    _track(g, course, yaws)
    assert math.degrees(g._crab_rad()) == pytest.approx(want_deg, abs=1e-9)


def test_no_crab_angle_before_a_second_of_poses_or_without_a_metre_of_motion(scenarios):
    g = _agent(scenarios["small"], 0).guide
    _track(g, 0.3, [0.25] * 10)  # ten poses: less than a second
    assert g._crab_rad() == 0.0
    _track(g, 0.3, [0.25] * 11, step_m=0.099)  # 0.99 m in the second
    assert g._crab_rad() == 0.0
    _track(g, 0.3, [0.25] * 11, step_m=0.101)  # 1.01 m
    assert g._crab_rad() == pytest.approx(0.05)


# --- the drop run's leg: its sense ---------------------------------------------------------------


def test_a_new_leg_runs_through_the_aim_in_the_sense_of_the_smaller_turn(scenarios):
    """The tanker (run turn radius r = 253 m, lead-in 775 m): the leg along the front through the aim
    point in either sense; without a previous leg, the sense whose entry point (lead-in + r before
    the aim) it reaches with the smaller turn: heading to the entry, then onto the course (within r of
    the entry: onto the course straight away)."""
    g = _agent(scenarios["tanker"], 0).guide
    aim = (3000.0, 3000.0)
    r = g.run_turn_m
    back = g.lead_in_m + r  # the entry of course 0 is at x = 3000 - back, of course pi at 3000 + back

    def course(pose, t=(1.0, 0.0), prev=None):
        leg = g._new_leg(aim, t, pose, prev)
        assert leg.threshold_xy == aim and leg.length_m == g.lead_in_m and leg.turn_radius_m == r
        return math.degrees(math.remainder(leg.course_rad, math.tau))

    assert course((1000.0, 3000.0, 0.0)) == pytest.approx(0.0)  # from the west heading east: east
    assert course((1000.0, 3000.0, 0.0), t=(-1.0, 0.0)) == pytest.approx(0.0)  # the front's sign: no matter
    assert abs(course((5000.0, 3000.0, math.pi))) == pytest.approx(180.0)  # from the east heading west
    # from the west heading west: the east leg turns pi to its entry then not at all (pi); the west
    # leg's entry lies beyond the aim, east: pi, then pi onto its course (2 pi)
    assert course((1000.0, 3000.0, math.pi)) == pytest.approx(0.0)
    # 200 m past the east leg's entry (inside r), heading 81 deg: onto course 0 is a 0.45 pi turn;
    # the west leg's entry is 1,830 m east: 0.45 pi to it, then pi onto its course
    assert course((3000.0 - back + 200.0, 3000.0, 0.45 * math.pi)) == pytest.approx(0.0)
    # ... and from 200 m south of the east leg's entry heading south, 0.55 pi back to it
    # (bearing north) and 0.5 pi onto course 0, against 0.5 pi to the far entry and pi onto pi
    # (tie-free: (0.55 + 0.5) pi < 1.5 pi)
    assert course((3000.0 - back, 2800.0, -0.45 * math.pi)) == pytest.approx(0.0)
    # with a previous leg: its sense, whatever the pose
    assert course((1000.0, 3000.0, 0.0), prev=math.pi - 0.3) == pytest.approx(180.0)
    assert course((5000.0, 3000.0, math.pi), prev=0.3) == pytest.approx(0.0)
    assert course((5000.0, 3000.0, math.pi), prev=-1.4) == pytest.approx(0.0)
    assert abs(course((1000.0, 3000.0, 0.0), prev=1.7)) == pytest.approx(180.0)


# --- a landing entry taken by a lower id of the same layer (lake_sequence: stack) ----------------


def _peer(uid: int, xy: tuple[float, float], z_m: float, objective: Objective, step: int = 99) -> PeerState:
    return PeerState(uid, 1, step, xy[0], xy[1], z_m, 0.0, int(objective), -1, 0.0)


def test_a_landing_entry_is_taken_by_a_lower_id_of_the_layer_landing_within_reach(scenarios):
    """UAV 2 (the 23 m layer with 0 and 4): its entry area reaches four turn radii plus the
    separation radius from the entry; only a landing peer of its own layer with a lower id counts."""
    a = _agent(scenarios["small"], 2)
    ap = a.guide.approach
    assert ap is not None
    r = ap.turn_radius_m
    reach = 4.0 * r + a.cfg.separation.radius_m
    ex, ey = ap.entry_xy

    def taken(*peers: PeerState) -> bool:
        b = _agent(scenarios["small"], 2)
        for p in peers:
            b.link.receive_state(p, now_step=100)
        return b.guide._entry_taken((ex, ey), r)

    assert not taken()
    assert taken(_peer(0, (ex + reach - 0.5, ey), 23.0, Objective.LAND))
    assert taken(_peer(0, (ex, ey - reach + 0.5), 23.0, Objective.LAND))
    assert not taken(_peer(0, (ex + reach + 0.5, ey), 23.0, Objective.LAND))
    assert not taken(_peer(0, (ex, ey + reach + 0.5), 23.0, Objective.LAND))
    assert not taken(_peer(0, (ex, ey), 23.0, Objective.SUPPRESS))
    assert not taken(_peer(1, (ex, ey), 37.0, Objective.LAND))  # the other layer
    assert not taken(_peer(4, (ex, ey), 23.0, Objective.LAND))  # a higher id
    assert taken(_peer(4, (ex, ey), 23.0, Objective.LAND), _peer(0, (ex, ey), 23.0, Objective.LAND))
    assert taken(_peer(0, (ex, ey), 23.0, Objective.LAND), _peer(1, (ex, ey), 37.0, Objective.LAND))


# --- no turn toward a point inside the turn circles ----------------------------------------------


def test_a_fixed_wing_flies_straight_while_the_point_is_inside_its_turn_circles(scenarios):
    """small_uav at (100, 50) heading east: its left turn circle at the lowest speed 15.6 m/s is
    centred 24.8 m north (B&M Eq. 9.14, 45 deg), at 30 m/s 91.8 m north. The turn rate is zeroed
    for a point inside either circle at the faster of the commanded and the modelled airspeed
    (without a modelled airspeed, the commanded)."""
    a = _agent(scenarios["small"], 0)
    g = a.guide
    s = np.array([100.0, 50.0, 30.0, 0.0])
    cmd = (15.6, 0.5, 0.4)
    assert g._within_turn(s, cmd, (100.0, 70.0)) == (15.6, 0.5, 0.0)  # left circle
    assert g._within_turn(s, cmd, (100.0, 30.0)) == (15.6, 0.5, 0.0)  # right circle
    assert g._within_turn(s, cmd, (100.0, 110.0)) == cmd
    assert g._within_turn(s, (30.0, 0.5, 0.4), (100.0, 150.0)) == (30.0, 0.5, 0.0)
    assert g.flown is not None
    g.flown.state.airspeed_mps = 30.0  # flying fast, commanded slow: the turn of 30 m/s
    assert g._within_turn(s, cmd, (100.0, 150.0)) == (15.6, 0.5, 0.0)
    assert g._within_turn(s, cmd, (100.0, 250.0)) == cmd
    g.flown.state.airspeed_mps = 10.0  # slower than commanded: the commanded speed's
    assert g._within_turn(s, (30.0, 0.5, 0.4), (100.0, 150.0)) == (30.0, 0.5, 0.0)
    g.flown = None
    assert g._within_turn(s, cmd, (100.0, 70.0)) == (15.6, 0.5, 0.0)
    assert g._within_turn(s, cmd, (100.0, 110.0)) == cmd
    ff = _agent(scenarios["ff"], 0).guide
    assert ff._within_turn(s, cmd, (100.0, 51.0)) == cmd  # FF's unicycle turns on the spot


# --- the lined-up final (LAND on a fixed-wing) ---------------------------------------------------
# small_uav UAV 2 of ff_two_fires (coordinated_turn): threshold (50, 310), final flown west, 184.08 m
# long (the descent from 30 m), turn radius r = 24.8 m, layer 23 m; flat ground (elevation 0). Its
# final's gains are K_a = 1 / (2 tau_bank) = 5 / 3 1/s and K_z = 1 / (2 tau_gamma) = 0.625 1/s, so
# below the limits the command gives back the height and the heading it steers to (FF Eqs. 11-12):
# height = agl + v_z / K_z, heading = yaw + omega / K_a.

LOW, FLAT, CRUISE = 0.5, 0.3, 23.0


def _land(a: Agent, x: float, y: float, z: float, yaw: float, step: int = 100):
    from fire_uav_agent.guidance import Situation
    from fire_uav_agent.mission import Decision
    from fire_uav_common.constants import VehicleStatus

    sit = Situation(Decision(Objective.LAND, -1, None, False, False), (), None, None, None)  # type: ignore[arg-type]
    return a.guide.run(sit, VehicleStatus.AIRBORNE, np.array([x, y, z, yaw]), step)


def _glide(dist: float, length: float) -> float:
    """By hand: 0.5 m over the last 0.3 of the leg, up to 23 m at its back, linearly."""
    frac = (dist - FLAT * length) / ((1.0 - FLAT) * length)
    return LOW + (CRUISE - LOW) * min(1.0, max(0.0, frac))


def test_on_the_final_it_follows_the_glide_path_and_b_and_m_line_field(scenarios):
    """150 m before the threshold, 2 m left of the line (south: the final flies west), on the glide
    path and on course: it commands the glide path's height and B&M Eq. 10.8's course, chi_q -
    chi_inf (2 / pi) atan(k e), k for damping 0.7 (K = K_a / (4 zeta^2 v), k = K / (chi_inf 2 / pi))."""
    a = _agent(scenarios["small"], 2)
    ap = a.guide.approach
    assert ap is not None
    ka, kz = 0.5 / 0.3, 0.5 / 0.8
    k = ka / (4.0 * 0.49 * 15.6) / (math.radians(60.0) * 2.0 / math.pi)
    h = _glide(150.0, ap.length_m)
    for dz in (-1.0, 1.5):  # below the path, or above it by less than 2 m
        g = _land(a, 200.0, 308.0, h + dz, math.pi)
        v, vz, om = g.command
        assert g.target_xy == (50.0, 310.0)
        assert v == pytest.approx(15.6)
        assert (h + dz) + vz / kz == pytest.approx(h)
        chi = math.pi - math.radians(60.0) * (2.0 / math.pi) * math.atan(k * 2.0)
        assert math.pi + om / ka == pytest.approx(chi)
        assert a.guide.on_final


def test_a_fixed_wing_captured_high_above_the_glide_path_flies_to_the_entry(scenarios):
    a = _agent(scenarios["small"], 2)
    ap = a.guide.approach
    assert ap is not None
    h = _glide(150.0, ap.length_m)
    g = _land(a, 200.0, 310.0, h + 2.5, math.pi)
    assert not a.guide.on_final and g.target_xy == pytest.approx(ap.entry_xy)


def test_the_tanker_is_established_above_the_path_by_no_more_than_its_spare_descent(scenarios):
    """The tanker (final 1,717 m, north; descending at most 2.5 m/s at 46.8 m/s, the path 22.5 m over
    0.7 of the leg): 1,500 m out, above the path by up to the spare descent rate times the distance
    to the flat part, (2.5 / 46.8 - 22.5 / (0.7 * 1717.38)) (1500 - 0.3 * 1717.38) = 34.2 m, it is
    established on the final; 0.3 m above that, not."""
    length = (75.0**2 - 46.8**2) / 2.0
    spare = (2.5 / 46.8 - 22.5 / (0.7 * length)) * (1500.0 - 0.3 * length)
    h = _glide(1500.0, length)
    for dz, want in [(spare - 0.3, True), (spare + 0.3, False)]:
        a = _agent(scenarios["tanker"], 0)
        ap = a.guide.approach
        assert ap is not None
        _land(a, 2600.0, 4300.0 - 1500.0, h + dz, 0.5 * math.pi)
        assert a.guide.on_final is want, dz


def test_a_landing_uav_keeps_its_layer_over_a_lower_id_below_it_on_the_final(scenarios):
    """hold_layer: a lower-id peer (not grounded or landed) below it within the separation radius
    keeps it on its layer (23 m) on the glide path; a higher id or a landed peer does not."""
    h = _glide(150.0, 184.08)
    for peer, want in [
        (_peer(0, (205.0, 310.0), 5.0, Objective.LAND), CRUISE),
        (_peer(4, (205.0, 310.0), 5.0, Objective.LAND), h),
        (_peer(0, (205.0, 310.0), 5.0, Objective.LANDED), h),
        (_peer(0, (205.0, 310.0), 5.0, Objective.GROUNDED), h),
        (_peer(0, (205.0, 310.0 + 60.0), 5.0, Objective.LAND), h),
    ]:
        a = _agent(scenarios["small"], 2)
        a.link.receive_state(peer, now_step=100)
        g = _land(a, 200.0, 310.0, h - 1.0, math.pi)
        assert (h - 1.0) + g.command[1] / (0.5 / 0.8) == pytest.approx(want), peer


@pytest.mark.parametrize(
    "dx, dy, agl, before, touch",
    [
        (-1.0, 0.0, 0.5, [], True),  # below 0.8 m within 2.5 m of the point
        (-2.4, 0.0, 0.5, [], True),
        (-2.6, 0.0, 0.5, [], False),  # outside the disc (small_uav flies 1.56 m a step)
        (-1.0, 0.0, 0.85, [], False),  # too high ...
        (-1.0, 0.0, 0.85, [0.7] * 9, True),  # ... unless the last second's mean is below 0.8 m
        (-1.0, 0.0, 0.85, [0.7] * 8, False),  # (a full second of it)
        (-1.0, 0.0, 0.85, [0.8] * 9, False),
    ],
)
def test_it_touches_down_at_the_point_low_enough(scenarios, dx, dy, agl, before, touch):
    a = _agent(scenarios["small"], 2)
    g = a.guide
    g.on_final = True
    g._final_agl.extend(before)
    # dx metres before the threshold (x = 50 - dx: the final flies west)
    out = _land(a, 50.0 - dx, 310.0 + dy, agl, math.pi)
    assert (out.command == (0.0, -0.5, 0.0)) is touch


def test_to_the_entry_at_the_layer_slowing_within_four_turn_radii(scenarios):
    """Not captured (east of the final's back, heading west): to the entry point (258.9, 310) at the
    layer with FF's gains (K_z = 5 1/s), at the top speed, at the lowest within 4 r of the entry."""
    a = _agent(scenarios["small"], 2)
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    assert (ex, ey) == pytest.approx((50.0 + 184.08 + ap.turn_radius_m, 310.0))
    g = _land(a, ex + 250.0, ey, CRUISE - 0.5, math.pi)
    assert g.target_xy == pytest.approx((ex, ey))
    assert g.command == pytest.approx((30.0, 2.5, 0.0))
    g = _land(_agent(scenarios["small"], 2), ex + 3.9 * ap.turn_radius_m, ey, CRUISE - 0.5, math.pi)
    assert g.command[0] == pytest.approx(15.6)
    g = _land(_agent(scenarios["small"], 2), ex + 4.1 * ap.turn_radius_m, ey, CRUISE - 0.5, math.pi)
    assert g.command[0] == pytest.approx(30.0)


@pytest.mark.parametrize("dy, side", [(5.0, -1.0), (-5.0, 1.0)])
def test_at_the_entry_heading_the_wrong_way_it_turns_at_its_limit_toward_the_line(scenarios, dy, side):
    """At the entry heading east (away from the final's west course), 5 m north of the line: a
    full-rate right turn (its right circle's centre is nearer the line), 5 m south: left."""
    a = _agent(scenarios["small"], 2)
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    g = _land(a, ex + 10.0, ey + dy, CRUISE, 0.0)
    assert g.target_xy == pytest.approx((ex, ey))
    assert g.command[2] == pytest.approx(side * a.cfg.limits.omega_max_radps)
    # 5 m north heading 17 deg left of east: within 2 r the right turn toward the line; at 2.1 r the
    # control law's turn toward the entry behind it (left, the shorter way round)
    om = a.cfg.limits.omega_max_radps
    r = ap.turn_radius_m
    assert _land(_agent(scenarios["small"], 2), ex + 1.9 * r, ey + 5.0, CRUISE, 0.3).command[
        2
    ] == pytest.approx(-om)
    assert _land(_agent(scenarios["small"], 2), ex + 2.1 * r, ey + 5.0, CRUISE, 0.3).command[
        2
    ] == pytest.approx(om)


def _agent_with(sc, uid: int, guidance=None, **fields) -> Agent:
    """An Agent whose config differs from the scenario's in ``fields`` (and GuidanceConfig ``guidance``)."""
    cfg = config_from_scenario(sc, uid, uav_count=5, seed=1, loss_probability=0.0)
    if guidance:
        fields["guidance"] = dataclasses.replace(cfg.guidance, **guidance)
    return Agent(dataclasses.replace(cfg, **fields))


def test_with_one_ff_layer_every_lower_id_landing_is_of_the_layer(scenarios):
    sc = load_scenario(
        scenario_path("ff_two_fires"),
        overrides={"uavs.vehicle_model": "coordinated_turn", "mission.lake_sequence": "stack"},
    )
    for layers, want in [(1, True), (2, False)]:
        a = _agent_with(sc, 2, guidance={"ff_layers": layers})
        ap = a.guide.approach
        assert ap is not None
        a.link.receive_state(_peer(1, ap.entry_xy, 30.0, Objective.LAND), now_step=100)
        assert a.guide._entry_taken(ap.entry_xy, ap.turn_radius_m) is want


@pytest.mark.parametrize(
    "xy, inside",
    [
        ((50.0, 310.0), True),
        ((0.0, 310.0), True),  # on the area's edges: inside, as FF's LAND branch counts them
        ((600.0, 310.0), True),
        ((50.0, 0.0), True),
        ((50.0, 600.0), True),
        ((-1.0, 310.0), False),
        ((601.0, 310.0), False),
        ((50.0, -1.0), False),
        ((50.0, 601.0), False),
        ((700.0, 300.0), False),  # x out, y in
        ((300.0, 700.0), False),
    ],
)
def test_the_home_is_in_the_area_on_both_axes(scenarios, xy, inside):
    g = _agent(scenarios["small"], 0).guide
    g.start_xy = np.array(xy)
    assert g._home_in_area() is inside


def test_a_refilling_uav_holds_above_a_low_peer_on_sloped_ground(scenarios):
    """grass_running (raster; layers 8 / 22 / 36 m, step 14 m, the scoop height 7.5 m) on a plane
    E = 5 + 0.1 x + 0.05 y: a UAV is low below 7.5 + 7 = 14.5 m above the ground under it. UAV 1 at
    (300, 200) (E = 45 m), 22 m up, holds over a peer 8 m above its own ground 5 m away, whatever
    the peer does but landed or grounded; not over a peer above 14.5 m, nor far off; and a UAV low
    already (10 m up) does not hold (on its scoop run)."""
    from fire_uav_common.terrain import Terrain

    plane = Terrain(base_m=5.0, slope_x=0.1, slope_y=0.05)
    a = _agent_with(scenarios["ff_pattern"], 1, terrain=plane)
    g = a.guide

    def holds(own_agl: float, *peers: tuple[tuple[float, float], float, Objective]) -> bool:
        b = _agent_with(scenarios["ff_pattern"], 1, terrain=plane)
        for k, (xy, agl, obj) in enumerate(peers):
            b.link.receive_state(_peer(2 + k, xy, plane.elevation(*xy) + agl, obj), now_step=100)
        return b.guide._onto_low_peer(np.array([300.0, 200.0, 45.0 + own_agl, 0.0]))

    assert g.raster.tactic.layer_step_m == 14.0
    beside = (304.0, 197.0)
    assert holds(22.0, (beside, 8.0, Objective.REFILL))
    assert holds(22.0, (beside, 8.0, Objective.SUPPRESS))
    assert holds(22.0, (beside, 8.0, Objective.LAND))
    assert not holds(22.0, (beside, 8.0, Objective.LANDED))
    assert not holds(22.0, (beside, 8.0, Objective.GROUNDED))
    assert not holds(22.0, (beside, 15.0, Objective.REFILL))  # not low
    assert not holds(22.0, (beside, 18.0, Objective.SUPPRESS))
    assert holds(22.0, (beside, 14.0, Objective.REFILL))
    assert not holds(22.0, ((340.0, 200.0), 8.0, Objective.REFILL))  # 40 m off
    assert not holds(22.0)
    assert not holds(10.0, (beside, 8.0, Objective.REFILL))  # low already
    assert holds(15.0, (beside, 8.0, Objective.REFILL))


# --- the stack above the lake (mission.lake_sequence: stack) -------------------------------------


@pytest.fixture(scope="module")
def stacked():
    return load_scenario(
        scenario_path("ff_two_fires"),
        overrides={"uavs.vehicle_model": "coordinated_turn", "mission.lake_sequence": "stack"},
    )


def _rung(sc, own_xy, own_agl, peers, layers: int = 3):
    """UAV 3's rung [m] (None: it holds the lake) on the plane E = 5 + 0.1 x + 0.05 y, FF's 90 m lake
    at (50, 50), ``layers`` FF layers 14 m apart about 30 m; ``peers``: (id, xy, agl, objective)."""
    from fire_uav_common.terrain import Terrain

    plane = Terrain(base_m=5.0, slope_x=0.1, slope_y=0.05)
    a = _agent_with(sc, 3, terrain=plane, guidance={"ff_layers": layers})
    for uid, xy, agl, obj in peers:
        a.link.receive_state(_peer(uid, xy, plane.elevation(*xy) + agl, obj), now_step=100)
    s = np.array([own_xy[0], own_xy[1], plane.elevation(*own_xy) + own_agl, 0.0])
    return a.guide._lake_rung(s, a.lakes[0])


def test_the_rungs_of_the_stack_are_the_lowest_ff_layer_up_in_layer_steps(stacked):
    """Three FF layers 14 m apart about 30 m: the lowest at 16 m, a UAV low below 16 - 3.5 = 12.5 m;
    the lake zone 45 + 150 m from the centre. UAV 3 waiting 100 m out (30 m up): with UAV 0 low on
    the lake it holds rung 0 (16 m); with UAV 1 waiting too, rung 1 (30 m). One layer: the lowest is
    the flight height, 30 m, and rung 1 at 44 m."""
    at = (150.0, 50.0)
    low0 = (0, (50.0, 50.0), 8.0, Objective.REFILL)
    wait1 = (1, (50.0, 150.0), 30.0, Objective.REFILL)
    assert _rung(stacked, at, 30.0, []) is None  # alone: it holds the lake
    assert _rung(stacked, at, 30.0, [low0]) == pytest.approx(16.0)
    assert _rung(stacked, at, 30.0, [low0, wait1]) == pytest.approx(30.0)
    assert _rung(stacked, at, 30.0, [wait1]) == pytest.approx(30.0)
    assert _rung(stacked, at, 30.0, [low0], layers=1) == pytest.approx(30.0)
    assert _rung(stacked, at, 30.0, [low0, wait1], layers=1) == pytest.approx(44.0)
    assert _rung(stacked, at, 30.0, [low0, wait1], layers=2) == pytest.approx(23.0 + 14.0)


def test_who_waits_is_decided_on_the_lakes_radius_and_the_low_band(stacked):
    """Waiting: refilling within 195 m (the lake's 45 m plus the 150 m margin) of its centre and not
    low (below 12.5 m above its own ground); UAV 3 waiting 100 m out takes the rung behind a waiting
    lower id only."""
    at = (150.0, 50.0)
    assert _rung(stacked, at, 30.0, [(1, (50.0, 50.0 + 190.0), 30.0, Objective.REFILL)]) == pytest.approx(
        30.0
    )
    assert _rung(stacked, at, 30.0, [(1, (50.0, 50.0 + 200.0), 30.0, Objective.REFILL)]) is None
    assert _rung(stacked, at, 30.0, [(1, (50.0, 50.0 + 250.0), 30.0, Objective.REFILL)]) is None
    # UAV 0 refilling over the lake 14 m up: not low, waiting, the holder; UAV 3 behind it on rung 1
    assert _rung(stacked, at, 30.0, [(0, (50.0, 50.0), 14.0, Objective.REFILL)]) == pytest.approx(30.0)
    assert _rung(stacked, at, 30.0, [(0, (50.0, 50.0), 12.0, Objective.REFILL)]) == pytest.approx(16.0)


def test_a_uav_low_on_the_lake_holds_it_by_its_own_height_above_its_own_ground(stacked):
    """UAV 3 low (8 m above the sloped ground) 150 m north of the lake's centre holds it against UAV 1
    waiting; 20 m up it waits behind UAV 1 (rung 1)."""
    wait1 = (1, (150.0, 50.0), 30.0, Objective.REFILL)
    assert _rung(stacked, (50.0, 200.0), 8.0, [wait1]) is None
    assert _rung(stacked, (50.0, 200.0), 20.0, [wait1]) == pytest.approx(30.0)
    assert _rung(stacked, (200.0, 50.0), 8.0, [wait1]) is None


def test_each_lake_has_its_own_zone(stacked):
    """Two lakes: the zone of each is its own radius plus the margin (made once per lake)."""
    from fire_uav_common.terrain import Lake

    a = _agent_with(stacked, 3)
    big = Lake(400.0, 400.0, 300.0)  # zone 150 + 150 m
    a.link.receive_state(_peer(1, (400.0, 400.0 + 280.0), 30.0, Objective.REFILL), now_step=100)
    g = a.guide
    s = np.array([400.0, 500.0, 30.0, 0.0])
    assert g._lake_rung(np.array([150.0, 50.0, 30.0, 0.0]), a.lakes[0]) is None
    assert g._lake_rung(s, big) == pytest.approx(23.0 + 14.0)  # UAV 1 waits 280 m out: 3 behind it


# --- the drop run's leg along the front (AgentConfig.drop_leg) -----------------------------------
# The tanker of grass_running_tanker, a line of burning cells along x through the aim (3000, 3000):
# run turn radius r = v^2 / (g tan 45 deg) = 252.9 m at 49.8 m/s, lead-in 3 r + 16 m = 774.7 m, the
# pattern 197.4 m long; the leg's entry lies lead-in + r before the aim; captured within 3 r of the
# line from lead-in + 3 r before the aim to r / 2 past it, heading within 90 deg of the course.

AIM = (3000.0, 3000.0)


def _leg_agent(sc, cells: int = 241, y0: float = AIM[1]) -> Agent:
    from fire_uav_agent.fire_front import FrontConfig, FrontPicture
    from fire_uav_common.constants import CellState

    a = _agent(sc, 0, drop_leg=True)
    pic = FrontPicture(FrontConfig(a.cfg.area_m, 10.0))
    d = np.arange(cells, dtype=float) * 5.0
    d -= d.mean()
    x, y = AIM[0] + d, np.full(d.shape, y0)
    pic.observe(x, y, np.full(x.shape, int(CellState.BURNING)), 1.0)
    a.raster.front = pic
    return a


def _steer(a: Agent, x: float, y: float, yaw: float, aim=AIM, t_s: float = 1.0):
    return a.guide._drop_leg(np.array([x, y, 8.0, yaw]), aim, t_s)


def test_far_behind_the_leg_it_flies_to_the_entry(scenarios):
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    back = g.lead_in_m + g.run_turn_m
    assert _steer(a, 1000.0, 3000.0, 0.0) == pytest.approx((3000.0 - back, 3000.0))
    assert g.leg is not None and g.leg.threshold_xy == AIM
    assert g.leg_counts == {"leg": 1, "few_cells": 0, "no_room": 0}
    _steer(a, 1010.0, 3000.0, 0.0)  # the same leg: counted once
    assert g.leg_counts["leg"] == 1


@pytest.mark.parametrize("cross", [0.0, 20.0, -60.0])
def test_captured_it_steers_by_b_and_m_line_field(scenarios, cross):
    """500 m before the aim, ``cross`` metres left of the line (north), heading east: B&M Eq. 10.8
    with k = 1 / r, chi_inf = 60 deg; the point it steers to is 4 r along that course."""
    a = _leg_agent(scenarios["tanker"])
    r = a.guide.run_turn_m
    _steer(a, 1000.0, 3000.0, 0.0)  # the east leg (from here the west one is the smaller turn)
    chi = -math.radians(60.0) * (2.0 / math.pi) * math.atan(cross / r)
    want = (2500.0 + 4.0 * r * math.cos(chi), 3000.0 + cross + 4.0 * r * math.sin(chi))
    assert _steer(a, 2500.0, 3000.0 + cross, 0.0) == pytest.approx(want)


def test_captured_the_crab_angle_is_taken_off_the_course(scenarios):
    """Drifting north at 0.05 rad over the last second while heading along the line: the heading
    it steers is the field's course less the crab angle."""
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    r = g.run_turn_m
    _steer(a, 1000.0, 3000.0, 0.0)  # the east leg
    _track(g, 0.05, [0.0] * 11)
    assert _steer(a, 2500.0, 3000.0, 0.0) == pytest.approx(
        (2500.0 + 4.0 * r * math.cos(-0.05), 3000.0 + 4.0 * r * math.sin(-0.05))
    )


def test_too_close_to_turn_onto_a_new_leg_it_runs_straight_at_the_aim(scenarios):
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    assert _steer(a, 2800.0, 3000.0, 0.6 * math.pi) == AIM  # 200 m from the aim, heading off the leg
    assert g.leg is None and g.leg_counts == {"leg": 0, "few_cells": 0, "no_room": 1}
    # 800 m out (beyond the lead-in), heading the same way: a leg (not captured: to its entry area)
    assert _steer(a, 2200.0, 3000.0, 0.6 * math.pi) != AIM
    assert g.leg is not None and g.leg_counts["leg"] == 1


def test_at_the_entry_heading_the_wrong_way_it_turns_toward_the_line(scenarios):
    """50 m past the entry of the east leg and 30 m north of the line, heading west: the east leg
    (onto it is a half turn from here, against a half turn to the far entry plus another); a
    full turn toward the line's side: the point r to the left of the heading (south)."""
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    x = 3000.0 - (g.lead_in_m + g.run_turn_m) + 50.0
    got = _steer(a, x, 3030.0, math.pi)
    assert g.leg is not None and abs(math.remainder(g.leg.course_rad, math.tau)) < 1e-9
    assert got == pytest.approx((x, 3030.0 - g.run_turn_m))
    b = _leg_agent(scenarios["tanker"])
    assert _steer(b, x, 2970.0, math.pi) == pytest.approx((x, 2970.0 + g.run_turn_m))


def test_an_aim_that_moved_more_than_half_a_pattern_gets_a_new_leg_in_the_same_sense(scenarios):
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    back = g.lead_in_m + g.run_turn_m
    _steer(a, 1000.0, 3000.0, 0.0)  # the east leg to (3000, 3000)
    # the aim 90 m on (under half the 197 m pattern): the same leg
    assert _steer(a, 1000.0, 3000.0, 0.0, aim=(3090.0, 3000.0)) == pytest.approx((3000.0 - back, 3000.0))
    # 110 m on: a new leg through it, still eastward, though from 60 m before it heading east a
    # fresh leg would be the west one (a half turn to its entry ahead against a full one); captured
    r = g.run_turn_m
    assert _steer(a, 3050.0, 3000.0, 0.0, aim=(3110.0, 3000.0)) == pytest.approx((3050.0 + 4.0 * r, 3000.0))
    assert g.leg is not None and g.leg.threshold_xy == (3110.0, 3000.0)
    b = _leg_agent(scenarios["tanker"])
    assert _steer(b, 3050.0, 3000.0, 0.0, aim=(3110.0, 3000.0)) == (3110.0, 3000.0)  # fresh: no room
    assert g.leg_counts["leg"] == 1  # not fresh


def test_half_a_pattern_past_the_aim_without_a_release_the_leg_is_dropped(scenarios):
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    _steer(a, 1000.0, 3000.0, 0.0)
    assert g.leg is not None
    assert _steer(a, 3000.0 + 0.5 * g.pattern_m - 1.0, 3000.0, 0.0) != AIM  # still on it
    assert _steer(a, 3000.0 + 0.5 * g.pattern_m + 1.0, 3000.0, 0.0) == AIM
    assert g.leg is None


def test_without_a_line_of_front_cells_it_runs_straight_at_the_aim(scenarios):
    a = _leg_agent(scenarios["tanker"], cells=3)
    g = a.guide
    assert _steer(a, 1000.0, 3000.0, 0.0) == AIM
    assert g.leg is None and g.leg_counts == {"leg": 0, "few_cells": 1, "no_room": 0}
    b = _agent(scenarios["tanker"], 0, drop_leg=True)  # no front picture at all
    assert b.raster.front is None and _steer(b, 1000.0, 3000.0, 0.0) == AIM


def test_the_j3cubs_run_begins_where_it_can_still_descend_to_the_lowest_layer(scenarios):
    """J3Cubs with pattern drops over grass_running (raster layers 8 / 22 / 36 m): the run is the
    16 m release radius plus the longer of the slowdown from 30 to 25 m/s at 1.7 m/s^2 (80.9 m) and
    the descent from the own layer to 8 m at 1.4 m/s flown at 25 m/s (0, 250 and 500 m)."""
    sc = load_scenario(
        scenario_path("grass_running"),
        overrides={"uavs.vehicle_model": "jsbsim", "fires.drop_model": "pattern"},
    )
    slow = (30.0**2 - 25.0**2) / (2.0 * 1.7)
    for uid, drop_h in [(0, 0.0), (1, 14.0), (2, 28.0)]:
        g = _agent(sc, uid).guide
        assert g.drop_run_m == pytest.approx(16.0 + max(slow, 25.0 * drop_h / 1.4)), uid


# --- REFILL near the lake through Guide.run --------------------------------------------------------


def _refill(a: Agent, xy, z: float, yaw: float, step: int = 100):
    from fire_uav_agent.testing.harness import refill_situation
    from fire_uav_common.constants import VehicleStatus

    return a.guide.run(refill_situation(a), VehicleStatus.AIRBORNE, np.array([xy[0], xy[1], z, yaw]), step)


def _raster_agent(sc, uid: int) -> Agent:
    """An agent of ``sc`` over a raster fire (one burning cell seen: the tactic has a front)."""
    from fire_uav_common.codecs.sensor_bundle import Bundle, Samples
    from fire_uav_common.constants import CellState, VehicleStatus

    a = _agent(sc, uid)
    cells = (np.array([500.0]), np.array([500.0]), np.array([int(CellState.BURNING)]))
    b = Bundle(100, 10.0, Samples(), np.zeros((0, 4)), 0.0, int(VehicleStatus.AIRBORNE), 0.1, cells, 5.0)
    a.raster.fuse(b, VehicleStatus.AIRBORNE, b.stamp_s)
    return a


def test_over_a_low_peer_at_the_lake_it_holds_a_layer_step_above_the_scoop_height_at_speed(scenarios):
    """grass_running (lake (100, 100), 90 m; raster layers 8 / 22 / 36 m): UAV 0 refilling 190 m
    from the lake's centre, 20 m up, over UAV 2 low (8 m) 5 m away: it holds 7.5 + 14 = 21.5 m
    (K_z = 5 1/s: v_z = 7.5 m/s) at its top speed (no low-and-slow cap); UAV 1 (22 m layer) keeps
    its layer. Alone, UAV 0 descends to the scoop height at the low-and-slow speed."""
    at = (100.0 + 190.0 / math.sqrt(2), 100.0 + 190.0 / math.sqrt(2))
    low = (2, (at[0] + 4.0, at[1] - 3.0), 8.0, Objective.REFILL)
    yaw = -0.75 * math.pi
    a = _raster_agent(scenarios["ff_pattern"], 0)
    a.link.receive_state(_peer(low[0], low[1], low[2], low[3]), now_step=100)
    v, vz, _ = _refill(a, at, 20.0, yaw).command
    assert (v, vz) == pytest.approx((100.0, 7.5))
    b = _raster_agent(scenarios["ff_pattern"], 1)
    b.link.receive_state(_peer(low[0], low[1], low[2], low[3]), now_step=100)
    assert _refill(b, at, 22.0, yaw).command[1] == pytest.approx(0.0)
    v, vz, _ = _refill(_raster_agent(scenarios["ff_pattern"], 0), at, 20.0, yaw).command
    assert v == pytest.approx(44.7 + 0.3 * 10.0) and vz == pytest.approx(-20.0)


def test_in_the_stack_it_holds_its_rung_low_and_slow_and_the_holder_dives_at_the_centre(stacked):
    """small_uav, lake_sequence stack, FF's lake (50, 50): UAV 3 120 m out, 22.5 m up, with UAV 0
    low on the lake: rung 0 = the lowest FF layer, 23 m (K_z = 5 1/s: v_z = 2.5 m/s), at the
    low-and-slow 18.6 m/s; alone it holds the lake and flies at its centre down to 7.5 m."""
    at = (50.0 + 120.0 / math.sqrt(2), 50.0 + 120.0 / math.sqrt(2))
    a = _agent(stacked, 3)
    a.link.receive_state(_peer(0, (50.0, 50.0), 7.5, Objective.REFILL), now_step=100)
    g = _refill(a, at, 22.5, -0.75 * math.pi)
    assert g.command[:2] == pytest.approx((18.6, 2.5))
    g = _refill(_agent(stacked, 3), at, 22.5, -0.75 * math.pi)
    assert g.target_xy == (50.0, 50.0) and g.command[:2] == pytest.approx((18.6, -5.0))


def test_two_layers_half_a_metre_apart_are_two_layers(stacked):
    a = _agent_with(stacked, 2, guidance={"ff_layer_step_m": 0.5})
    ap = a.guide.approach
    assert ap is not None
    a.link.receive_state(_peer(1, ap.entry_xy, 30.0, Objective.LAND), now_step=100)
    assert not a.guide._entry_taken(ap.entry_xy, ap.turn_radius_m)


def _crabbed_final(a: Agent, cross: float, established: bool, yaw: float = math.pi):
    """UAV 2's final: 150 m before the threshold, ``cross`` m left of the line (south), heading
    ``yaw``, having tracked 0.05 rad left of its heading over the last second: the course it steers
    (the heading plus the heading error the command gives back)."""
    g = a.guide
    g.on_final = established
    x, y = 200.0, 310.0 - cross
    course = yaw + 0.05
    for k in range(10):
        d = (10 - k) * 1.5
        g._poses.append((x - d * math.cos(course), y - d * math.sin(course), yaw))
    h = _glide(150.0, 184.08)
    return yaw - math.pi + _land(a, x, y, h, yaw).command[2] / (0.5 / 0.3)


def test_on_the_final_near_the_line_the_crab_angle_is_taken_off_the_fields_course(scenarios):
    k = (0.5 / 0.3) / (4.0 * 0.49 * 15.6) / (math.radians(60.0) * 2.0 / math.pi)
    field = -math.radians(60.0) * (2.0 / math.pi) * math.atan(k * 2.0)
    assert _crabbed_final(_agent(scenarios["small"], 2), 2.0, True) == pytest.approx(field - 0.05)
    # just established: the crab angle of the final is measured on the final (none yet)
    assert _crabbed_final(_agent(scenarios["small"], 2), 2.0, False) == pytest.approx(field)
    # 30 m off, beyond a turn radius (24.8 m): the capture turn, no correction; the field there is
    # B&M's k = 1 / r beyond the 2.5 m band, shifted by (k - 1 / r) 2.5 m
    r = _turn_radius(15.6, 45.0)
    u = 30.0 / r + (k - 1.0 / r) * 2.5
    far = -math.radians(60.0) * (2.0 / math.pi) * math.atan(u)
    got = _crabbed_final(_agent(scenarios["small"], 2), 30.0, True, yaw=math.pi - 0.6)
    assert got == pytest.approx(far)


def test_off_the_final_the_last_seconds_heights_are_forgotten(scenarios):
    a = _agent(scenarios["small"], 2)
    g = a.guide
    g.on_final = True
    g._final_agl.extend([0.7] * 9)
    _land(a, 500.0, 310.0, CRUISE, math.pi)  # behind the capture zone
    assert g.on_final is False and len(g._final_agl) == 0


def test_a_skipped_run_is_noted_once_whole_with_the_worlds_peak():
    """small_uav over grass_running's grass (CL 1) with pattern drops: its run's pattern from the
    8 m layer at 18.6 m/s peaks (the world's pattern) under the level; the first skip's note names
    the layer, the speed, the peak, its level, the fuel's level and the aim; later skips count."""
    from fire_world_sim.drop_pattern import L_PER_M2_PER_CL

    sc = load_scenario(
        scenario_path("grass_running"),
        overrides={"uavs.vehicle_model": "coordinated_turn", "fires.drop_model": "pattern"},
    )
    g = Agent(config_from_scenario(sc, 1, uav_count=6, seed=1, loss_probability=0.0)).guide
    peak = pattern_of(Release(0.0, 0.0, 0.0, 18.6, 8.0, 10.0, 5.0)).peak_lpm2
    assert g._drop_run((510.0, 300.0), (500.0, 300.0)) is None
    assert g._drop_run((1290.0, 1310.0), (1300.0, 1300.0)) is None
    assert g.run_skips == 2
    assert g.skip_note == (
        "drop run skipped (kept the own layer and speed): the own pattern from the 8 m layer at "
        f"18.6 m/s peaks at {peak:.3f} L/m2 (coverage level {peak / L_PER_M2_PER_CL:.2f}), under the "
        "level 1 the fuel at (500, 300) m needs"
    )


@pytest.mark.parametrize(
    "pose, want_deg",
    [
        # the turns (heading -> bearing to the entry, then bearing -> course) worked out by hand
        # from the docstring's rule for a front at 30 deg through (3000, 3000); entries of the two
        # legs lead-in + r = 1,027.6 m before the aim: (2110.1, 2486.2) and (3889.9, 3513.8)
        ((3886.16, 1915.05, 2.8), 30.0),  # 2.34 rad against 3.33
        ((3270.49, 4169.87, -1.58), 210.0),  # 3.29 against 2.57
        ((2960.63, 3419.63, -0.86), 210.0),  # 4.28 against 3.68
        ((2040.11, 3643.33, 1.73), 210.0),  # 5.08 against 4.35
        ((1849.27, 4362.83, 0.75), 210.0),  # 4.14 against 3.37
    ],
)
def test_a_new_leg_on_an_oblique_front_takes_the_smaller_turn(scenarios, pose, want_deg):
    g = _agent(scenarios["tanker"], 0).guide
    t = (math.cos(math.radians(30.0)), math.sin(math.radians(30.0)))
    leg = g._new_leg(AIM, t, pose, None)
    assert math.degrees(leg.course_rad) % 360.0 == pytest.approx(want_deg)


@pytest.mark.parametrize("prev_deg, want_deg", [(100.0, 30.0), (-40.0, 30.0), (130.0, 210.0), (250.0, 210.0)])
def test_a_new_leg_on_an_oblique_front_keeps_the_previous_legs_sense(scenarios, prev_deg, want_deg):
    """The front at 30 deg: the sense within a quarter turn of the previous leg's course."""
    g = _agent(scenarios["tanker"], 0).guide
    t = (math.cos(math.radians(30.0)), math.sin(math.radians(30.0)))
    leg = g._new_leg(AIM, t, (1000.0, 1000.0, 0.0), math.radians(prev_deg))
    assert math.degrees(leg.course_rad) % 360.0 == pytest.approx(want_deg)


def test_the_leg_counts_add_up(scenarios):
    a = _leg_agent(scenarios["tanker"])
    g = a.guide
    _steer(a, 2800.0, 3000.0, 0.6 * math.pi)
    _steer(a, 2810.0, 3000.0, 0.6 * math.pi)
    assert g.leg_counts["no_room"] == 2
    _steer(a, 1000.0, 3000.0, 0.0)
    _steer(a, 3200.0, 3000.0, 0.0)  # half a pattern past the aim: dropped
    _steer(a, 1000.0, 3000.0, 0.0)  # a fresh leg again
    assert g.leg_counts["leg"] == 2
    b = _leg_agent(scenarios["tanker"], cells=3)
    _steer(b, 1000.0, 3000.0, 0.0)
    _steer(b, 1010.0, 3000.0, 0.0)
    assert b.guide.leg_counts["few_cells"] == 2


def test_off_the_diagonal_the_aim_and_the_room_are_measured_on_both_axes(scenarios):
    """The line along x through (3000, 2600): an aim moved 90 m along it keeps the leg, one moved
    110 m across it (along y) makes a new one; 800 m west of the aim, beyond the lead-in (775 m),
    a fresh leg is made, 700 m west there is no room."""
    aim = (3000.0, 2600.0)
    a = _leg_agent(scenarios["tanker"], y0=2600.0)
    g = a.guide
    _steer(a, 1000.0, 2600.0, 0.0, aim=aim)
    _steer(a, 1000.0, 2600.0, 0.0, aim=(3090.0, 2600.0))
    assert g.leg is not None and g.leg.threshold_xy == aim
    _steer(a, 1000.0, 2600.0, 0.0, aim=(3000.0, 2710.0))
    assert g.leg is not None and g.leg.threshold_xy == (3000.0, 2710.0)
    b = _leg_agent(scenarios["tanker"], y0=2600.0)
    assert _steer(b, 2200.0, 2600.0, 0.6 * math.pi, aim=aim) != aim
    assert b.guide.leg is not None
    c = _leg_agent(scenarios["tanker"], y0=2600.0)
    assert _steer(c, 2300.0, 2600.0, 0.6 * math.pi, aim=aim) == aim
    assert c.guide.leg is None


def test_the_legs_direction_is_read_from_the_front_at_the_steps_time(scenarios):
    """The picture's burning cells seen at 1 s are stale a day later: no line, no leg (the front
    at the latest observation would still have one)."""
    a = _leg_agent(scenarios["tanker"])
    assert _steer(a, 1000.0, 3000.0, 0.0, t_s=86400.0) == AIM
    assert a.guide.leg_counts["few_cells"] == 1


def test_a_run_of_any_length_is_flown_within_it(scenarios):
    """``drop_run_m`` 0 means no run; any positive length is a run within that distance."""
    g = _agent(scenarios["tanker"], 0).guide
    g.drop_run_m = 0.8
    assert g._drop_run((3000.5, 3000.0), AIM) == (8.0, pytest.approx(49.8))
    assert g._drop_run((3000.9, 3000.0), AIM) is None
    assert g._drop_run((3000.0, 3000.5), AIM) is not None
    assert g._drop_run((3000.0, 3000.9), AIM) is None
    g.drop_run_m = 0.0
    assert g._drop_run(AIM, AIM) is None


def test_the_final_is_at_least_four_turn_radii_and_the_approach_radius(scenarios):
    """The J3Cub's final with a climb-rate limit of 100 m/s (descent 2 x 22 x 36.5 / 100 = 16 m,
    slowing 30 -> 22 m/s at 1.7 m/s^2 122 m): four turn radii at 22 m/s and 40 deg (235 m); with
    FF's approach radius set to 5 km, 5 km."""
    sc = scenarios["j3cub"]
    cfg = config_from_scenario(sc, 1, uav_count=5, seed=1, loss_probability=0.0)
    fast = dataclasses.replace(cfg, vehicle=dataclasses.replace(cfg.vehicle, vz_max_mps=100.0))
    ap = Agent(fast).guide.approach
    assert ap is not None and ap.length_m == pytest.approx(4.0 * _turn_radius(22.0, 40.0))
    ap = _agent_with(sc, 1, guidance={"land_approach_radius_m": 5000.0}).guide.approach
    assert ap is not None and ap.length_m == pytest.approx(5000.0)


def test_the_fuels_level_is_read_at_the_aim_point():
    """grass_running_tanker with brush (FBFM 5, CL 3, beyond the tanker's 1.01 L/m^2 = CL 2.5) in a
    band 2.5-3.5 km east: no run at an aim in it, a run at an aim on grass north-west of it."""
    patch = {"x_min_m": 2500.0, "x_max_m": 3500.0, "y_min_m": 0.0, "y_max_m": 6000.0, "fuel_model": 5}
    sc = load_scenario(
        scenario_path("grass_running_tanker"), overrides={"fires.raster.fuel_patches": [patch]}
    )
    g = _agent(sc, 1).guide
    assert g._drop_run((3000.0, 1010.0), (3000.0, 1000.0)) is None
    assert g._drop_run((1000.0, 3010.0), (1000.0, 3000.0)) is not None


def test_the_final_on_sloped_ground_and_a_higher_landing_height(scenarios):
    """UAV 2's final over the plane E = 5 + 0.1 x + 0.05 y, the vehicle's landing height 2 m (FF's
    1 m): the approach height is 0.5 x 2 = 1 m above the ground under it, touch-down below 0.8 x 2
    = 1.6 m: at the threshold (E = 25.5 m) 1.5 m up it touches down, 1.7 m up it holds 1 m (K_z =
    0.625 1/s: v_z = -0.4375 m/s)."""
    from fire_uav_common.terrain import Terrain

    plane = Terrain(base_m=5.0, slope_x=0.1, slope_y=0.05)
    sc = scenarios["small"]
    cfg = config_from_scenario(sc, 2, uav_count=5, seed=1, loss_probability=0.0)
    cfg = dataclasses.replace(
        cfg, terrain=plane, vehicle=dataclasses.replace(cfg.vehicle, landing_height_m=2.0)
    )
    e = plane.elevation(50.0, 310.0)
    a = Agent(cfg)
    a.guide.on_final = True
    assert _land(a, 50.5, 310.0, e + 1.5, math.pi).command == (0.0, -0.5, 0.0)
    a = Agent(cfg)
    a.guide.on_final = True
    a.guide._final_agl.extend([1.5] * 9)  # ... unless the last second's mean is below 1.6 m
    assert _land(a, 50.5, 310.0, e + 1.7, math.pi).command == (0.0, -0.5, 0.0)
    a = Agent(cfg)
    a.guide.on_final = True
    v, vz, _ = _land(a, 50.5, 310.0, e + 1.7, math.pi).command
    assert v == pytest.approx(15.6) and vz == pytest.approx(0.625 * (1.0 - 1.7) - 15.6 * 0.1, abs=0.05)


def test_on_the_final_the_avoidance_acts_only_when_on(scenarios):
    """A peer (UAV 0, right of way) 40 m ahead on UAV 2's final at its height, flying at it: with
    the avoidance on, the command turns off the one without the peer; with it off, it does not."""
    h = _glide(150.0, 184.08)
    head_on = _peer(0, (160.0, 310.0), h, Objective.SUPPRESS)
    head_on = dataclasses.replace(head_on, yaw_rad=0.0)
    for avoid in (True, False):
        alone = _agent_with(scenarios["small"], 2, avoidance=avoid)
        alone.guide.on_final = True
        want = _land(alone, 200.0, 310.0, h, math.pi).command
        a = _agent_with(scenarios["small"], 2, avoidance=avoid)
        a.guide.on_final = True
        a.link.receive_state(head_on, now_step=100)
        got = _land(a, 200.0, 310.0, h, math.pi).command
        assert (got != pytest.approx(want)) is avoid


def test_to_the_entry_the_distance_is_measured_on_both_axes(scenarios):
    """4.1 turn radii south of the entry (outside the capture box: 3 r across), heading north at
    it: the top speed; at 3.9 r the lowest."""
    ap = _agent(scenarios["small"], 2).guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    r = ap.turn_radius_m
    assert _land(_agent(scenarios["small"], 2), ex, ey - 4.1 * r, CRUISE, 0.5 * math.pi).command[0] == 30.0
    assert _land(_agent(scenarios["small"], 2), ex, ey - 3.9 * r, CRUISE, 0.5 * math.pi).command[
        0
    ] == pytest.approx(15.6)


def test_off_the_final_over_a_lower_id_below_it_keeps_its_layer(scenarios):
    """Not captured, UAV 0 below it 5 m away: it holds its layer (23 m; K_z = 5 1/s, 22.5 m up:
    v_z 2.5 m/s)."""
    ap = _agent(scenarios["small"], 2).guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    a = _agent(scenarios["small"], 2)
    a.link.receive_state(_peer(0, (ex + 255.0, ey), 10.0, Objective.LAND), now_step=100)
    assert _land(a, ex + 250.0, ey, CRUISE - 0.5, math.pi).command[1] == pytest.approx(2.5)


def _entry_turn(sc, avoid: bool, peer_dxy: tuple[float, float] | None):
    """UAV 2 at its entry + (10, 5) heading east (the wrong way): the command, UAV 0 (right of way)
    hovering at ``peer_dxy`` from it on its height, the avoidance on or off."""
    a = _agent_with(sc, 2, avoidance=avoid)
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    if peer_dxy is not None:
        xy = (ex + 10.0 + peer_dxy[0], ey + 5.0 + peer_dxy[1])
        a.link.receive_state(_peer(0, xy, CRUISE, Objective.SUPPRESS, step=99), now_step=100)
    return _land(a, ex + 10.0, ey + 5.0, CRUISE, 0.0).command


def test_the_turn_at_the_entry_goes_through_the_avoidance_holding_its_heading(scenarios):
    """The full-rate turn at the entry (right, toward the line) is a straight command for the
    avoidance (it holds the present heading, not the bearing to the entry behind it): UAV 0 40 m
    behind-left of that bearing leaves it as it is (turning to the entry would turn left, toward
    it); UAV 0 15 m behind, on the turn's way, stops the turn; with the avoidance off it does not."""
    sc = scenarios["small"]
    om = _agent(scenarios["small"], 2).cfg.limits.omega_max_radps
    assert _entry_turn(sc, True, None)[2] == pytest.approx(-om)
    assert _entry_turn(sc, True, (-40.0, -40.0))[2] == pytest.approx(-om)
    assert _entry_turn(sc, True, (-15.0, 0.0))[2] == pytest.approx(0.0)
    assert _entry_turn(sc, False, (-15.0, 0.0))[2] == pytest.approx(-om)


@pytest.mark.parametrize(
    "layers, dx_r, z, vz", [(2, 5.5, 50.5, 2.5), (2, 6.5, 22.5, 2.5), (1, 5.5, 43.5, 2.5)]
)
def test_a_fixed_wing_yields_its_entry_above_every_layer_within_six_turn_radii(stacked, layers, dx_r, z, vz):
    """With the stack, UAV 2 ``dx_r`` turn radii east of its entry while UAV 0 (of its layer) lands
    there: within 6 r it climbs above every FF layer, its layer plus a layer step per layer (two
    layers: 23 + 28 = 51 m; one: 30 + 14 = 44 m); beyond, it keeps its layer (K_z = 5 1/s)."""
    a = _agent_with(stacked, 2, guidance={"ff_layers": layers})
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    a.link.receive_state(_peer(0, (ex, ey), 20.0, Objective.LAND), now_step=100)
    assert _land(a, ex + dx_r * ap.turn_radius_m, ey, z, math.pi).command[1] == pytest.approx(vz)


def test_the_tanker_turns_at_its_entry_when_heading_more_than_a_quarter_turn_off_its_course(scenarios):
    """The tanker's final flies north (course pi / 2); 10 m east of its entry heading 11 deg south of
    east (more than a quarter turn off): the full-rate turn toward the line (right: its right
    circle's centre lies nearer it), not a straight run (the entry is inside its turn circle)."""
    a = _agent(scenarios["tanker"], 0)
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    om = a.cfg.limits.omega_max_radps
    assert _land(a, ex + 10.0, ey, CRUISE, -0.2).command[2] == pytest.approx(-om)


def test_to_the_entry_the_avoidance_acts_only_when_on(scenarios):
    """UAV 2 flying west to its entry 250 m off, UAV 0 hovering 15 m ahead on its height: with the
    avoidance on, the command turns off the one without the peer; with it off, it does not."""
    ap = _agent(scenarios["small"], 2).guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    for avoid in (True, False):
        want = _land(
            _agent_with(scenarios["small"], 2, avoidance=avoid), ex + 250.0, ey, CRUISE, math.pi
        ).command
        a = _agent_with(scenarios["small"], 2, avoidance=avoid)
        a.link.receive_state(_peer(0, (ex + 235.0, ey), CRUISE, Objective.SUPPRESS, step=99), now_step=100)
        got = _land(a, ex + 250.0, ey, CRUISE, math.pi).command
        assert (got != pytest.approx(want)) is avoid


def _suppress(a: Agent, xy, yaw: float, t_s: float, step: int = 100):
    """One guidance step of ``a`` in SUPPRESS toward the aim point AIM on its raster front."""
    from fire_uav_agent.guidance import Situation
    from fire_uav_agent.mission import Decision
    from fire_uav_agent.planning import PlannerView
    from fire_uav_common.codecs.uav_state import FireEntry
    from fire_uav_common.constants import VehicleStatus

    cell = np.ones(a.grid.points.shape[0], dtype=bool)
    fire = FireEntry(0, True, AIM[0], AIM[1], 0.0)
    s = np.array([xy[0], xy[1], 30.0, yaw])
    view = PlannerView(t_s, a.cfg.uav_id, s, a.grid, cell, {}, (fire,))
    sit = Situation(Decision(Objective.SUPPRESS, 0, None, False, False), (fire,), None, view, cell, AIM)
    return a.guide.run(sit, VehicleStatus.AIRBORNE, s, step)


def test_the_run_reads_the_leg_at_the_steps_time_and_drops_it_off_the_run(scenarios):
    """The tanker with the leg on, 1,200 m west of the aim heading east (inside its 1,588 m run):
    a leg from the front seen at 1 s; with the step a day later (the cells stale) none. Beyond the
    run, the leg is dropped."""
    a = _leg_agent(scenarios["tanker"])
    _suppress(a, (1800.0, 3000.0), 0.0, 1.0)
    assert a.guide.leg is not None
    _suppress(a, (0.0, 3000.0), 0.0, 1.0)  # 3 km out: no run, no leg
    assert a.guide.leg is None
    b = _leg_agent(scenarios["tanker"])
    _suppress(b, (1800.0, 3000.0), 0.0, 86400.0)
    assert b.guide.leg is None and b.guide.leg_counts["few_cells"] == 1


def test_refill_flies_at_the_lake_on_a_direct_run_or_with_no_lake_density_in_its_cell(scenarios):
    """REFILL 400 m from FF's lake (50, 50): a direct run (attack run) flies at its centre; so does
    Eq. 14's centroid in a cell that holds none of the lake's density (an empty cell)."""
    from fire_uav_agent.guidance import Situation
    from fire_uav_agent.mission import Decision
    from fire_uav_common.constants import VehicleStatus

    s = np.array([450.0, 50.0, 30.0, math.pi])
    for direct, cell_on in [(True, True), (False, False)]:
        a = _agent(scenarios["small"], 0)
        cell = np.full(a.grid.points.shape[0], cell_on)
        sit = Situation(Decision(Objective.REFILL, -1, None, direct, False), (), a.lakes[0], None, cell)  # type: ignore[arg-type]
        assert a.guide.run(sit, VehicleStatus.AIRBORNE, s, 100).target_xy == (50.0, 50.0)


def test_ffs_go_around_flies_straight_out_steering_for_the_takeoff_point(scenarios):
    """FF's unicycle (no airframe) landing 10 m east of its takeoff point (50, 250), 30 m up,
    heading east (away): not lined up within the 25 m go-around radius, it flies straight on (omega
    0), its target the takeoff point."""
    a = _agent(scenarios["ff"], 0)
    g = _land(a, 60.0, 250.0, 30.0, 0.0)
    assert g.target_xy == (50.0, 250.0) and g.command[2] == 0.0


def test_the_pattern_is_the_airframes_tank_and_flow_and_none_without_a_flow(scenarios):
    """A fixed-wing's pattern is v V / Q of its airframe's tank and flow, whatever the vehicle
    section says; no flow rate, no pattern (0 m), a flow of 0.5 L/s a long one. FF's unicycle turns
    its run on v / omega_max at any turn-rate limit (here 0.5 rad/s)."""
    cfg = config_from_scenario(scenarios["tanker"], 0, uav_count=5, seed=1, loss_probability=0.0)
    odd = dataclasses.replace(
        cfg, vehicle=dataclasses.replace(cfg.vehicle, water_capacity_kg=1.0, drop_flow_lps=1.0)
    )
    assert Agent(odd).guide.pattern_m == pytest.approx(49.8 * 3000.0 / 757.0)
    af = cfg.airframe
    assert af is not None
    for flow, want in [(0.0, 0.0), (0.5, 49.8 * 3000.0 / 0.5)]:
        c = dataclasses.replace(cfg, airframe=dataclasses.replace(af, drop_flow_lps=flow))
        assert Agent(c).guide.pattern_m == pytest.approx(want)
    ff = config_from_scenario(scenarios["ff_pattern"], 0, uav_count=5, seed=1, loss_probability=0.0)
    slow = dataclasses.replace(ff, vehicle=dataclasses.replace(ff.vehicle, omega_max_radps=0.5))
    g = Agent(slow).guide
    assert g.run_turn_m == pytest.approx(g.v_slow_mps / 0.5)


def test_one_ff_layer_a_takeoff_at_the_centre_and_a_2_m_landing_height_shape_the_final(scenarios):
    """J3Cub UAV 1 with one FF layer (30 m): its lake margin is the descent 30 -> 7.5 m at 25 m/s
    and 1.4 m/s (402 m), its final the descent from 30 m (927 m); a takeoff point at the area's
    centre keeps its takeoff heading as the final's course; a landing height of 2 m brings the
    approach height to 1 m (small_uav UAV 2's final: 2 x 15.6 x (30 - 1) / 5 m)."""
    sc = scenarios["j3cub"]
    g = _agent_with(sc, 1, guidance={"ff_layers": 1}).guide
    assert g.lake_margin_m == pytest.approx(25.0 * (30.0 - 7.5) / 1.4)
    assert g.approach is not None and g.approach.length_m == pytest.approx(2.0 * 22.0 * 29.5 / 1.4)
    g = _agent_with(sc, 1, start_pose=(300.0, 300.0, 0.0, 0.7)).guide
    assert g.approach is not None and g.approach.course_rad == pytest.approx(0.7)
    cfg = config_from_scenario(scenarios["small"], 2, uav_count=5, seed=1, loss_probability=0.0)
    cfg = dataclasses.replace(cfg, vehicle=dataclasses.replace(cfg.vehicle, landing_height_m=2.0))
    ap = Agent(cfg).guide.approach
    assert ap is not None and ap.length_m == pytest.approx(2.0 * 15.6 * (30.0 - 1.0) / 5.0)


@pytest.mark.parametrize("period_s, heights, poses", [(1.0, 1, 2), (0.5, 2, 3), (0.1, 10, 11)])
def test_the_memories_hold_a_second_at_any_control_period(scenarios, period_s, heights, poses):
    """A second of heights is 1 / T samples; a second of motion is 1 / T + 1 poses."""
    cfg = config_from_scenario(scenarios["small"], 0, uav_count=5, seed=1, loss_probability=0.0)
    cfg = dataclasses.replace(cfg, timing=dataclasses.replace(cfg.timing, control_period_s=period_s))
    g = Agent(cfg).guide
    assert (g._final_agl.maxlen, g._poses.maxlen) == (heights, poses)
