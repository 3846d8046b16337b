"""The agent's model of its airframe (fire_uav_agent.airframe_model) against the world's own backend.

The world's ``coordinated_turn`` backend (Beard & McLain ch. 9) is the truth the on-board model
must reproduce: fed the same commands from the same state without process noise, the EKF input
it gives must be the mean of what the world flew over each control period.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from fire_uav_agent.airframe_model import (
    LINE_DAMPING,
    FinalApproach,
    FlownInput,
    descent_m,
    final_approach_course,
    inside_turn_circle,
    line_gain_per_m,
    slowdown_m,
    turn_radius_m,
)
from fire_uav_agent.coverage import VehicleLimits
from fire_uav_common import scenario as sc
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import AIRFRAMES
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel

AIR, GROUND, LANDED = VehicleStatus.AIRBORNE, VehicleStatus.ON_GROUND, VehicleStatus.LANDED
SMALL = AIRFRAMES["small_uav"]
LIM = VehicleLimits.of(sc.airframes.envelope_vehicle(sc.Vehicle(), SMALL))


def _world_means(commands: list[tuple[float, float, float]], water_kg: float) -> list[np.ndarray]:
    """The world's flown (ground speed, climb, turn rate), averaged per control period of 10 substeps."""
    model = CoordinatedTurnModel(SMALL, 0.0)
    rng = np.random.default_rng(0)
    st = FlightState(0.0, 0.0, 30.0, 0.0, water_kg=water_kg)
    out = []
    for k, (v, vz, w) in enumerate(commands):
        c = Command(
            min(max(v, LIM.v_stall_mps), LIM.v_max_mps),
            min(max(vz, -LIM.vz_max_mps), LIM.vz_max_mps),
            min(max(w, -LIM.omega_max_radps), LIM.omega_max_radps),
        )
        if k == 0:
            st = model.launch(st, Command(v, vz, w))
        acc = np.zeros(3)
        for _ in range(10):
            (st,) = model.step([st], [c], 0.01, [rng])
            acc += (math.sqrt(st.airspeed_mps**2 - st.climb_mps**2), st.climb_mps, st.turn_rate_radps)
        out.append(acc / 10)
    return out


def test_the_ekf_input_is_the_turn_the_world_flies_not_the_command():
    cmds = [(16.0, 3.0, 0.0)] + [(30.0, 5.0, 1.0)] * 15 + [(15.0, -5.0, -0.6)] * 20 + [(22.0, 0.0, 0.2)] * 10
    truth = _world_means(cmds, water_kg=6.0)
    f = FlownInput(SMALL, LIM, 0.01, 0.1)
    prev = GROUND
    worst = 0.0
    for cmd, want in zip(cmds, truth, strict=True):
        u = f.input(np.array(cmd), prev == AIR, AIR, 6.0)
        worst = max(worst, float(np.max(np.abs(u - want))))
        prev = AIR
    assert worst < 1e-9
    # and the command itself is far from it: the first second of a turn lags by the bank response
    f2 = FlownInput(SMALL, LIM, 0.01, 0.1)
    u0 = f2.input(np.array(cmds[0]), False, AIR, 6.0)
    u1 = f2.input(np.array(cmds[1]), True, AIR, 6.0)
    assert u0[2] == 0.0 and 0.0 < u1[2] < 0.5 * LIM.omega_max_radps


def test_without_an_airframe_the_input_is_the_clamped_command_as_before():
    lim = VehicleLimits.of(sc.Vehicle())
    f = FlownInput(None, lim, 0.01, 0.1)
    assert list(f.input(np.array([150.0, 150.0, 30.0]), True, AIR, 0.0)) == [
        lim.v_max_mps, lim.vz_max_mps, lim.omega_max_radps,
    ]  # fmt: skip
    assert list(f.input(np.array([10.0, 150.0, 0.0]), False, AIR, 0.0)) == [10.0, lim.vz_max_mps, 0.0]
    assert list(f.input(np.array([50.0, -0.5, 3.0]), True, LANDED, 0.0)) == [0.0, -0.5, 0.0]


def test_a_touchdown_stops_the_prediction_and_a_new_takeoff_starts_wings_level():
    f = FlownInput(SMALL, LIM, 0.01, 0.1)
    f.input(np.array([16.0, 3.0, 0.0]), False, AIR, 0.0)
    for _ in range(10):
        f.input(np.array([25.0, 0.0, 0.5]), True, AIR, 0.0)
    assert f.state.bank_rad > 0.2
    assert list(f.input(np.array([0.0, -0.5, 0.0]), True, LANDED, 0.0)) == [0.0, -0.5, 0.0]
    u = f.input(np.array([16.0, 3.0, 0.0]), False, AIR, 0.0)
    assert u[2] == 0.0 and u[0] == pytest.approx(16.0, abs=0.1)  # at the commanded speed


def test_the_turn_radius_is_v_squared_over_g_tan_bank():
    # docs/airframes.md: small_uav at its lowest commanded speed, full bank: 24.8 m
    assert turn_radius_m(SMALL, SMALL.v_min_mps, 0.0) == pytest.approx(24.8, abs=0.05)
    assert turn_radius_m(AIRFRAMES["tanker"], 45.0, 0.0) == pytest.approx(206.4, abs=0.1)
    # just above stall with a full tank the stall limits the bank below 45 deg: a wider turn
    v = 1.05 * SMALL.v_stall_mps
    assert turn_radius_m(SMALL, v) > v * v / 9.80665 * 1.5


def test_points_inside_the_turn_circles_are_found():
    r = 25.0
    pose = (0.0, 0.0, 0.0)  # heading +x: circles centred at (0, +25) and (0, -25)
    assert inside_turn_circle(pose, (0.0, 30.0), r)
    assert inside_turn_circle(pose, (5.0, -20.0), r)
    assert not inside_turn_circle(pose, (60.0, 0.0), r)
    assert not inside_turn_circle(pose, (-30.0, 0.0), r)  # behind: reachable by a turn
    north = (0.0, 0.0, math.pi / 2)  # circles centred at (-25, 0) and (25, 0)
    assert inside_turn_circle(north, (20.0, 5.0), r) and inside_turn_circle(north, (-40.0, -3.0), r)
    assert not inside_turn_circle(north, (0.0, 40.0), r)


def test_the_final_leg_points_from_the_area_centre_to_the_takeoff_point_in_90_degree_steps():
    area = (0.0, 600.0, 0.0, 600.0)
    # FF's takeoff column at x = 50: every UAV gets the same westward final, so the finals are parallel
    west = [
        math.remainder(final_approach_course((50.0, y), area, -1.0) - math.pi, math.tau)
        for y in (250.0, 370.0)
    ]
    assert west == [pytest.approx(0.0, abs=1e-12)] * 2
    assert final_approach_course((300.0, 590.0), area, -1.0) == pytest.approx(math.pi / 2)
    assert final_approach_course((300.0, 300.0), area, -1.0) == -1.0  # at the centre: the takeoff heading


def test_the_approach_captures_from_behind_and_steers_onto_the_line():
    ap = FinalApproach((50.0, 250.0), math.pi, 200.0, 25.0)  # final westward to (50, 250)
    assert ap.entry_xy == pytest.approx((275.0, 250.0))
    assert ap.frame((150.0, 260.0)) == pytest.approx((-100.0, -10.0))  # 100 m before, 10 m to the right
    assert ap.captured((150.0, 260.0, math.pi))
    assert not ap.captured((150.0, 260.0, 0.0))  # heading away from the threshold
    assert not ap.captured((10.0, 250.0, math.pi))  # past the threshold (more than half a radius)
    # right of the line: the commanded course turns left toward it, at most 60 deg off, less when close
    far = math.remainder(ap.line_course((150.0, 300.0)) - math.pi, math.tau)
    near = math.remainder(ap.line_course((150.0, 252.0)) - math.pi, math.tau)
    assert 0.0 < near < far <= math.radians(60.0)
    on = ap.line_course((150.0, 250.0))
    assert math.remainder(on - math.pi, math.tau) == pytest.approx(0.0)


def test_a_vehicle_flying_the_approach_lands_lined_up_at_the_threshold():
    """Fly the world's own coordinated-turn model from the wrong side of the field, steered by the
    approach (turn-rate command as the guidance's Eq. 11 law): it reaches the threshold on the line."""
    af = SMALL
    r = turn_radius_m(af, af.v_min_mps)
    ap = FinalApproach((50.0, 250.0), math.pi, 200.0, r)
    model = CoordinatedTurnModel(af, 0.0)
    rng = np.random.default_rng(0)
    st = model.launch(FlightState(-40.0, 150.0, 30.0, 0.0, water_kg=0.0), Command(af.v_min_mps, 0.0, 0.0))
    best = math.inf
    for _ in range(1200):  # 120 s
        pose = (st.x_m, st.y_m, st.yaw_rad)
        if ap.captured(pose):
            want = ap.line_course((st.x_m, st.y_m))
        else:
            e = ap.entry_xy
            to_e = math.hypot(e[0] - st.x_m, e[1] - st.y_m)
            if to_e < 2 * r and abs(math.remainder(st.yaw_rad - ap.course_rad, math.tau)) > math.pi / 2:
                want = st.yaw_rad + ap.turn_side(pose)
            else:
                want = math.atan2(e[1] - st.y_m, e[0] - st.x_m)
        w = max(
            -LIM.omega_max_radps, min(LIM.omega_max_radps, 5.0 * math.remainder(want - st.yaw_rad, math.tau))
        )
        for _ in range(10):
            (st,) = model.step([st], [Command(af.v_min_mps, 0.0, w)], 0.01, [rng])
        along, cross = ap.frame((st.x_m, st.y_m))
        if -2.0 <= along <= 2.0 and ap.captured((st.x_m, st.y_m, st.yaw_rad)):
            best = min(best, abs(cross))
            head_err = abs(math.remainder(st.yaw_rad - ap.course_rad, math.tau))
            break
    assert best < 2.0 and head_err < math.radians(10.0)


def test_a_lake_shorter_than_the_scoop_run_is_not_used_and_said_so():
    from fire_uav_agent.airframe_model import scoop_run_m, usable_lakes
    from fire_uav_common.terrain import Lake

    # small_uav: 10 kg at 2 kg/s = 5 s at 15.6 m/s = 78 m; tanker: 15 s at 46.8 m/s = 702 m
    assert scoop_run_m(SMALL) == pytest.approx(78.0)
    assert scoop_run_m(AIRFRAMES["tanker"]) == pytest.approx(702.0)
    ff_lake, pond = Lake(300.0, 400.0, 90.0), Lake(100.0, 100.0, 60.0)
    ok, refused = usable_lakes((ff_lake, pond), SMALL)
    assert ok == (ff_lake,) and len(refused) == 1 and "(100, 100)" in refused[0] and "60 m" in refused[0]
    assert usable_lakes((ff_lake,), AIRFRAMES["tanker"])[0] == ()
    assert usable_lakes((ff_lake, pond), None) == ((ff_lake, pond), ())
    # a long narrow water body: its inside disc (60 m) is short, its straight run (120 m) is not
    from fire_uav_common.water import StraightRun

    narrow = Lake(500.0, 500.0, 60.0, run=StraightRun(440.0, 500.0, 560.0, 500.0, 120.0))
    assert usable_lakes((narrow,), SMALL) == ((narrow,), ())


def test_the_agent_refills_only_at_a_lake_long_enough():
    from fire_uav_agent.agent_core import Agent, AgentConfig
    from fire_uav_common.terrain import Lake

    lakes = (Lake(300.0, 400.0, 60.0), Lake(500.0, 100.0, 90.0))
    a = Agent(AgentConfig(uav_id=0, uav_count=1, lakes=lakes, airframe=SMALL))
    assert a._nearest_lake(np.array([300.0, 400.0])) == lakes[1] and len(a.lakes_refused) == 1
    b = Agent(AgentConfig(uav_id=0, uav_count=1, lakes=lakes))
    assert b._nearest_lake(np.array([300.0, 400.0])) == lakes[0] and b.lakes_refused == ()


def test_a_fixed_wing_on_the_ground_is_estimated_on_the_ground():
    """The altimeter adds its noise to the true height (fire_world_sim.sensors), so at touch-down
    height half its readings are below 0. A fixed-wing agent's EKF keeps them: flying level at
    0.2 m over flat ground for 20 s, its height estimate is unbiased (it was 0.6-0.9 m up when it
    dropped them, above the touch-down height of 0.8 m, and the J3Cub never touched down)."""
    from fire_uav_agent.agent_core import Agent, AgentConfig
    from fire_uav_common.codecs.sensor_bundle import Samples

    a = Agent(AgentConfig(uav_id=0, uav_count=1, airframe=SMALL, start_pose=(0.0, 0.0, 0.2, 0.0)))
    ekf = a.ekf
    rng = np.random.default_rng(3)
    errs = []
    for k in range(200):  # 20 s, altimeter at 25 Hz, sigma 1.5 m
        t0 = 0.1 * k
        alt = np.array([[t0 + 0.04 * (j + 1), 0.2 + rng.normal(0.0, 1.5)] for j in range(2)])
        smp = Samples(np.zeros((0, 3)), np.zeros(0), alt, np.zeros((0, 2)))
        ekf.process(smp, np.array([0.0, 0.0, 0.0]), t0, t0 + 0.1)
        errs.append(float(ekf.s[2]) - 0.2)
    assert abs(float(np.mean(errs[50:]))) < 0.25


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def test_a_turn_at_the_radius_flies_at_the_stall_margin_of_the_load_aboard():
    """B&M: a banked turn at load factor n = 1 / cos(phi) stalls below V_S(m) sqrt(n). Just above the
    full tank's stall speed the radius is the one whose bank puts the turn exactly at that margin,
    for the full tank; the empty aircraft stalls lower and banks to bank_max."""
    v = 12.6  # 1.05 x small_uav's full-tank stall speed (12 m/s)
    for water_kg in (None, SMALL.water_capacity_kg):
        phi = math.atan(v * v / (9.80665 * turn_radius_m(SMALL, v, water_kg)))
        assert SMALL.stall_speed_mps(SMALL.water_capacity_kg) / math.sqrt(math.cos(phi)) == pytest.approx(v)
    phi_empty = math.atan(v * v / (9.80665 * turn_radius_m(SMALL, v, 0.0)))
    assert phi_empty == pytest.approx(SMALL.bank_max_rad)
    assert SMALL.stall_speed_mps(0.0) / math.sqrt(math.cos(phi_empty)) < v


def test_below_the_stall_speed_there_is_no_turn():
    """Below V_S even level flight stalls: no bank, so the radius is effectively unbounded."""
    assert turn_radius_m(SMALL, 0.9 * SMALL.stall_speed_mps(SMALL.water_capacity_kg)) > 1e9
    assert turn_radius_m(SMALL, 0.9 * SMALL.stall_speed_mps(0.0), 0.0) > 1e9


def test_a_lake_exactly_as_long_as_the_scoop_run_is_used():
    from fire_uav_agent.airframe_model import scoop_run_m, usable_lakes
    from fire_uav_common.terrain import Lake

    exact = Lake(0.0, 0.0, scoop_run_m(SMALL))  # a disc whose diameter is the run
    assert exact.longest_run.length_m == scoop_run_m(SMALL)
    assert usable_lakes((exact,), SMALL) == ((exact,), ())


def _circle_centres(pose, r):
    """The centres of the two turn circles: r to the left and to the right, normal to the heading."""
    x, y, th = pose
    return [(x - r * math.sin(th), y + r * math.cos(th)), (x + r * math.sin(th), y - r * math.cos(th))]


def test_turn_circles_off_the_axes_contain_what_lies_within_them():
    """Poses at any place and heading: a point 0.5 m inside either circle is inside, 0.5 m outside
    both is not; the vehicle's own position, on both circles, is not inside (it can turn either way)."""
    r = 25.0
    rng = np.random.default_rng(3)
    for _ in range(200):
        pose = (float(rng.uniform(-500, 500)), float(rng.uniform(-500, 500)), float(rng.uniform(-4, 4)))
        assert not inside_turn_circle(pose, (pose[0], pose[1]), r)
        centres = _circle_centres(pose, r)
        for cx, cy in centres:
            a = float(rng.uniform(0, 2 * math.pi))
            for d, want in ((r - 0.5, True), (r + 0.5, None)):
                p = (cx + d * math.cos(a), cy + d * math.sin(a))
                if want is None:  # outside this circle: inside only if within the other one
                    want = any(math.hypot(p[0] - ox, p[1] - oy) < r for ox, oy in centres)
                assert inside_turn_circle(pose, p, r) == want, (pose, p)
        assert inside_turn_circle(pose, centres[0], r) and inside_turn_circle(pose, centres[1], r)


def _flown_against_world(af, cmds, water_kg, substeps, physics_s):
    """(model's EKF inputs, world's per-period means, model's and world's final bank) for ``cmds``."""
    lim = VehicleLimits.of(sc.airframes.envelope_vehicle(sc.Vehicle(), af))
    model = CoordinatedTurnModel(af, 0.0)
    rng = np.random.default_rng(0)
    st = FlightState(0.0, 0.0, 30.0, 0.0, water_kg=water_kg)
    f = FlownInput(af, lim, physics_s, substeps * physics_s)
    got, want = [], []
    for k, (v, vz, w) in enumerate(cmds):
        c = Command(
            min(max(v, lim.v_stall_mps), lim.v_max_mps),
            min(max(vz, -lim.vz_max_mps), lim.vz_max_mps),
            min(max(w, -lim.omega_max_radps), lim.omega_max_radps),
        )
        if k == 0:
            st = model.launch(st, Command(v, vz, w))
        acc = np.zeros(3)
        for _ in range(substeps):
            (st,) = model.step([st], [c], physics_s, [rng])
            acc += (math.sqrt(st.airspeed_mps**2 - st.climb_mps**2), st.climb_mps, st.turn_rate_radps)
        want.append(acc / substeps)
        got.append(f.input(np.array((v, vz, w)), k > 0, AIR, water_kg))
    return np.array(got), np.array(want), f.state.bank_rad, st.bank_rad


def test_with_one_substep_per_period_the_input_is_the_worlds_one_step():
    """Physics period = control period: one substep, as the world flies it."""
    cmds = [(16.0, 3.0, 0.0)] + [(30.0, 5.0, 1.0)] * 5
    got, want, _, _ = _flown_against_world(SMALL, cmds, 6.0, 1, 0.1)
    assert np.max(np.abs(got - want)) < 1e-9


def test_near_stall_the_flown_turn_is_limited_by_the_load_aboard():
    """An airframe whose lowest speed is just above its full-tank stall: the world banks less with a
    full tank than empty, and the on-board model follows the load it is handed."""
    import dataclasses

    af = dataclasses.replace(SMALL, min_speed_factor=1.05)
    cmds = [(af.v_min_mps, 0.0, 0.0)] + [(af.v_min_mps, 0.0, 1.0)] * 20
    banks = []
    for water_kg in (0.0, af.water_capacity_kg):
        got, want, bank, world_bank = _flown_against_world(af, cmds, water_kg, 10, 0.01)
        assert np.max(np.abs(got - want)) < 1e-9 and bank == pytest.approx(world_bank, abs=1e-9)
        banks.append(bank)
    assert banks[1] < banks[0] - 0.1  # the full tank's stall margin holds the bank well below the empty one's


def test_on_the_ground_the_modelled_flight_state_is_at_rest():
    """Before the first takeoff and after a touchdown: no airspeed, no climb, no bank (guidance
    reads the modelled airspeed for its turn circles)."""
    f = FlownInput(SMALL, LIM, 0.01, 0.1)
    assert (f.state.airspeed_mps, f.state.climb_mps, f.state.bank_rad) == (0.0, 0.0, 0.0)
    f.input(np.array([16.0, 3.0, 0.0]), False, AIR, 0.0)
    for _ in range(10):
        f.input(np.array([25.0, 0.0, 0.5]), True, AIR, 0.0)
    f.input(np.array([0.0, -0.5, 0.0]), True, LANDED, 0.0)
    assert (f.state.airspeed_mps, f.state.climb_mps, f.state.bank_rad) == (0.0, 0.0, 0.0)
    f.input(np.array([0.0, 0.0, 0.0]), False, GROUND, 0.0)
    assert f.state.airspeed_mps == 0.0


def test_without_an_airframe_low_and_negative_commands_are_clamped_too():
    """FF Eq. 5: airborne, v to [v_stall, v_max], v_z and omega to +-their maxima."""
    lim = VehicleLimits.of(sc.Vehicle())
    f = FlownInput(None, lim, 0.01, 0.1)
    assert list(f.input(np.array([0.1, -150.0, -30.0]), True, AIR, 0.0)) == [
        lim.v_stall_mps, -lim.vz_max_mps, -lim.omega_max_radps,
    ]  # fmt: skip


def test_a_takeoff_point_level_with_the_centre_gets_the_axis_course():
    area = (0.0, 600.0, 0.0, 600.0)
    assert final_approach_course((50.0, 300.0), area, -1.0) == pytest.approx(math.pi)  # due west
    assert final_approach_course((300.0, 40.0), area, -1.0) == pytest.approx(-math.pi / 2)  # due south


def test_the_approach_frame_and_capture_region_on_an_oblique_course():
    """Course 30 deg, threshold off the origin: a point built from (along, cross) reads back as
    them; the capture region is the module doc's (within L + 3 r behind, 0.5 r past, 3 r across,
    heading within 90 deg)."""
    course, r, length = math.radians(30.0), 25.0, 200.0
    ap = FinalApproach((120.0, -40.0), course, length, r)
    c, s = math.cos(course), math.sin(course)

    def at(along, cross, heading=course):
        return (120.0 + along * c - cross * s, -40.0 + along * s + cross * c, heading)

    assert ap.frame(at(-100.0, 10.0)[:2]) == pytest.approx((-100.0, 10.0))
    assert ap.frame(at(37.0, -55.0)[:2]) == pytest.approx((37.0, -55.0))
    assert ap.captured(at(-(length + 2.9 * r), 0.0))
    assert not ap.captured(at(-(length + 3.5 * r), 0.0))
    assert ap.captured(at(0.3 * r, 0.0)) and not ap.captured(at(r, 0.0))
    assert ap.captured(at(-100.0, 2.9 * r)) and not ap.captured(at(-100.0, -3.5 * r))
    assert ap.captured(at(-100.0, 0.0, course + 1.4)) and not ap.captured(at(-100.0, 0.0, course + 1.7))
    # B&M Eq. 10.8 with k = 1 / r: one radius off the line the course is chi_inf / 2 = 30 deg off
    off = math.remainder(ap.line_course(at(-100.0, r)[:2]) - course, math.tau)
    assert off == pytest.approx(-math.radians(30.0))


def test_the_turn_side_is_the_one_toward_the_line():
    """Left of the line and heading along the course, the vehicle turns right (-1) toward it;
    right of it, left (+1); heading against the course, the other way. At any place and heading
    off a tie the side is the one whose circle centre is nearer the line."""
    ap = FinalApproach((120.0, -40.0), math.radians(30.0), 200.0, 25.0)
    rng = np.random.default_rng(5)
    for _ in range(300):
        pose = (float(rng.uniform(-300, 300)), float(rng.uniform(-300, 300)), float(rng.uniform(-4, 4)))
        _, cross = ap.frame(pose[:2])
        along_course = math.cos(pose[2] - ap.course_rad)
        if abs(cross * along_course) < 1e-3:
            continue
        want = -1.0 if cross * along_course > 0 else 1.0
        assert ap.turn_side(pose) == want, pose


# --- the tanker: reaching the lake slow enough, a final it settles on, a touch-down it cannot step over
TANKER = AIRFRAMES["tanker"]


def _tanker_agent(uav_id: int = 0):
    from fire_uav_agent.agent_config import config_from_scenario
    from fire_uav_agent.agent_core import Agent
    from fire_uav_agent.testing.harness import scenario_path

    scen = sc.load_scenario(scenario_path("ff_two_fires_tanker"))
    return Agent(config_from_scenario(scen, uav_id)), scen


def test_a_tanker_entering_the_lake_approach_at_top_speed_reaches_the_shore_slow_enough_to_scoop():
    """The world's coordinated-turn tanker, commanded the refill speed where the agent's low-and-slow
    zone begins, at its top speed: at the shore it flies within the world's refill speed
    (v_stall + refill_speed_margin_mps; world.vehicle.refill_conditions). With FF's 150 m margin it
    reached the shore at 73 m/s (the mission never refilled)."""
    a, scen = _tanker_agent()
    margin = a.guide.lake_margin_m
    v_refill_world = a.cfg.limits.v_stall_mps + scen.vehicle.refill_speed_margin_mps
    gd = a.cfg.guidance
    v_cmd = a.cfg.limits.v_stall_mps + gd.refill_speed_fraction * scen.vehicle.refill_speed_margin_mps
    model = CoordinatedTurnModel(TANKER, 0.0)
    rng = np.random.default_rng(0)

    def speed_after(distance_m: float) -> float:
        st = model.launch(FlightState(0.0, 0.0, 30.0, 0.0, water_kg=0.0), Command(TANKER.v_max_mps, 0.0, 0.0))
        while st.x_m < distance_m:
            (st,) = model.step([st], [Command(v_cmd, 0.0, 0.0)], 0.01, [rng])
        return st.airspeed_mps

    assert speed_after(margin) <= v_refill_world
    assert speed_after(gd.lake_approach_margin_m) > v_refill_world  # FF's margin is too short for it


def _final_height_at_threshold(
    af, length_m: float, kz: float, v_mps: float, top_m: float, entry_mps: float | None = None
) -> float:
    """Fly the world's coordinated-turn model down the lined-up final's height profile (guidance's
    ``land_*``: linear from ``top_m`` to 0.5 m over 70 % of the leg, then flat) at ``v_mps``,
    entering it at ``entry_mps`` (default ``v_mps``), the height loop FF Eq. 12 at ``kz``; its true
    height at the threshold."""
    model = CoordinatedTurnModel(af, 0.0)
    rng = np.random.default_rng(0)
    v0 = v_mps if entry_mps is None else entry_mps
    st = model.launch(FlightState(-length_m, 0.0, top_m, 0.0, water_kg=0.0), Command(v0, 0.0, 0.0))
    low, flat = 0.5, 0.3
    vz_max = min(af.climb_max_mps, af.descent_max_mps)
    while st.x_m < 0.0:
        dist = -st.x_m
        h = low + (top_m - low) * min(1.0, max(0.0, (dist - flat * length_m) / ((1.0 - flat) * length_m)))
        vz = max(-vz_max, min(vz_max, kz * (h - st.z_m)))
        for _ in range(10):
            (st,) = model.step([st], [Command(v_mps, vz, 0.0)], 0.01, [rng])
    return st.z_m


@pytest.mark.parametrize("entry_mps", [46.8, 60.0, 75.0])
def test_the_tankers_final_is_long_enough_to_arrive_below_the_touchdown_height(entry_mps: float):
    """On the agent's final leg the world's tanker is below the 0.8 m touch-down height at the
    threshold, however fast it enters the leg (it slows at 1 m/s^2: it captured the line at 60-72
    m/s in the mission). On the final it flew before (4 turn radii, 893 m) it arrived 1-4 m high
    when it entered at 60-75 m/s and went round (ff_two_fires_tanker seed 2: one UAV landed 990 s
    after the fleet agreed to land)."""
    a, _ = _tanker_agent(3)  # UAV 3 flies the upper layer (37 m)
    ap = a.guide.approach
    kz, v = a.guide.land_gains.kz, a.cfg.limits.v_stall_mps
    top = 37.0
    assert _final_height_at_threshold(TANKER, ap.length_m, kz, v, top, entry_mps) < 0.8
    if entry_mps >= 60.0:
        assert _final_height_at_threshold(TANKER, 4.0 * ap.turn_radius_m, kz, v, top, entry_mps) > 0.8


@pytest.mark.parametrize("cross_m", [0.0, 1.5, 2.4])
def test_a_tanker_pass_along_the_line_cannot_step_over_the_touchdown_point(cross_m: float):
    """At 46.8 m/s a control step is 4.7 m, wider than the 2.5 m touch-down disc: for every phase of
    the steps against the threshold, a pass within 2.5 m of the line has a step that touches down,
    and that step is within 2.5 m along and across of the threshold. The disc alone is missed for
    some phases once the pass is more than about 1 m off the line (the tanker went round)."""
    ap = FinalApproach((0.0, 0.0), math.pi, 1800.0, 223.0)
    step = TANKER.v_min_mps * 0.1
    missed_by_disc = 0
    for k in range(50):
        phase = step * k / 50
        xs = [20.0 - phase - step * i for i in range(12)]  # flying west (course pi) past x = 0
        hits = [x for x in xs if ap.at_threshold((x, -cross_m), step, 2.5)]
        assert hits, f"phase {phase:.2f} m"
        assert abs(hits[0]) <= 0.5 * step + 1e-9 or math.hypot(hits[0], cross_m) <= 2.5
        missed_by_disc += not any(math.hypot(x, cross_m) <= 2.5 for x in xs)
    assert missed_by_disc > 0 or cross_m < 1.0  # the disc's chord, 2 sqrt(2.5^2 - cross^2), < 4.7 m
    # an airframe whose step is shorter than the disc keeps the disc alone
    assert not ap.at_threshold((0.7, 2.4), 1.56, 2.5) or math.hypot(0.7, 2.4) <= 2.5
    assert not ap.at_threshold((1.0, 2.4), 1.56, 2.5)


def test_slowdown_is_the_distance_the_world_flies_while_decelerating():
    """slowdown_m(tanker, 75, 49.8) against the world's model: commanded 49.8 m/s from 75 m/s, the
    tanker is within accel_max tau_airspeed (4 m/s) of it after that distance, not at 75 % of it."""
    d = slowdown_m(TANKER, 75.0, 49.8)
    model = CoordinatedTurnModel(TANKER, 0.0)
    rng = np.random.default_rng(0)
    st = model.launch(FlightState(0.0, 0.0, 30.0, 0.0, water_kg=0.0), Command(75.0, 0.0, 0.0))
    at_75 = None
    while st.x_m < d:
        (st,) = model.step([st], [Command(49.8, 0.0, 0.0)], 0.01, [rng])
        if at_75 is None and st.x_m >= 0.75 * d:
            at_75 = st.airspeed_mps
    assert st.airspeed_mps <= 49.8 + TANKER.accel_max_mps2 * TANKER.tau_airspeed_s + 1e-6
    assert at_75 is not None and at_75 > 49.8 + TANKER.accel_max_mps2 * TANKER.tau_airspeed_s
    assert slowdown_m(TANKER, 40.0, 49.8) == 0.0


# --- the J3Cub (jsbsim): reaching the lake low enough to scoop
def test_a_j3cub_entering_the_lake_approach_on_the_top_layer_reaches_the_shore_low_enough_to_scoop():
    """The world's JSBSim J3Cub under its autopilot, on the FF scenario's top layer (37 m, UAV 1),
    commanded the scoop height (FF Eq. 12's height loop at the agent's K_z, within the agent's
    climb-rate limit) and the refill speed where the agent's low-and-slow zone begins: at the shore
    it is within the world's refill height (``vehicle.refill_height_m``; world.vehicle.refill_conditions).
    With FF's 150 m margin it reached the shore at about 27 m and flew over the lake without
    scooping (ff_two_fires on jsbsim, 5 UAVs, seed 1: 5 refills in 700 s)."""
    from fire_uav_agent.agent_config import config_from_scenario
    from fire_uav_agent.agent_core import Agent
    from fire_uav_agent.testing.harness import scenario_path
    from fire_world_sim.vehicles.jsbsim_backend import JsbsimModel

    scen = sc.load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "jsbsim"})
    a = Agent(config_from_scenario(scen, 1))
    cfg, gd = a.cfg, a.cfg.guidance
    top = scen.vehicle.flight_height_m + 0.5 * gd.ff_layer_step_m  # UAV 1's layer: 37 m
    scoop_h = gd.refill_height_fraction * scen.vehicle.refill_height_m
    v_cmd = cfg.limits.v_stall_mps + gd.refill_speed_fraction * scen.vehicle.refill_speed_margin_mps

    def height_after(distance_m: float) -> float:
        m = JsbsimModel(scen.uavs.airframe)
        st = m.launch(FlightState(0.0, 0.0, top, 0.0, water_kg=0.0), Command(v_cmd, 0.0, 0.0))
        rng = [np.random.default_rng(0)]
        k = 0
        while st.x_m < distance_m:
            if k % 10 == 0:  # the agent's control period, 0.1 s
                vz = float(
                    np.clip(cfg.gains.kz * (scoop_h - st.z_m), -cfg.limits.vz_max_mps, cfg.limits.vz_max_mps)
                )
            (st,) = m.step([st], [Command(v_cmd, vz, 0.0)], 0.01, rng)
            k += 1
        return st.z_m

    assert a.guide.lake_margin_m > gd.lake_approach_margin_m
    assert height_after(a.guide.lake_margin_m) <= scen.vehicle.refill_height_m
    assert height_after(gd.lake_approach_margin_m) > scen.vehicle.refill_height_m  # FF's margin is too short


# --- session 25: the final's line gain, its band, the model's energy split, the distances by hand
@pytest.mark.parametrize(("k_a", "v"), [(1.67, 15.6), (0.5, 46.8)])
def test_the_finals_line_gain_gives_the_lateral_loop_its_damping(k_a: float, v: float):
    """B&M Eq. 10.8's field flown under the heading loop omega = K_a (chi_c - psi) (FF Eq. 11):
    de/dt = v sin(psi - chi_q). Linearised, e'' + K_a e' + K_a v K e = 0; released 0.2 m beside the
    line on course (e' = 0) its first swing past the line is e0 exp(-zeta pi / sqrt(1 - zeta^2))
    (the second-order response), from which the damping is read back: 0.7 (LINE_DAMPING)."""
    ap = FinalApproach(
        (5000.0, 0.0), 0.0, 4000.0, 200.0, line_gain_per_m=line_gain_per_m(k_a, v, math.radians(60.0))
    )

    def rate(st: np.ndarray) -> np.ndarray:
        x, y, psi = st
        return np.array([v * math.cos(psi), v * math.sin(psi), k_a * (ap.line_course((x, y)) - psi)])

    st, dt, e0, lowest = np.array([0.0, 0.2, 0.0]), 0.005, 0.2, 0.0
    for _ in range(int(4.0 * math.pi / math.sqrt(k_a * v * 2.0 / 3.0 * ap.line_gain_per_m) / dt)):
        k1 = rate(st)
        k2 = rate(st + 0.5 * dt * k1)
        k3 = rate(st + 0.5 * dt * k2)
        k4 = rate(st + dt * k3)
        st = st + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        lowest = min(lowest, float(st[1]))
    assert lowest < 0.0  # underdamped: it swings past the line
    ln_os = math.log(-lowest / e0)
    zeta = -ln_os / math.sqrt(math.pi**2 + ln_os**2)
    assert zeta == pytest.approx(LINE_DAMPING, abs=0.01)


def test_within_its_band_the_line_gain_holds_and_beyond_it_the_slope_is_one_over_r():
    """FinalApproach's doc: k within ``line_band_m`` of the line, beyond it the argument of B&M's atan
    grows as e / r (continuous at the band's edge); either side of the line alike; no band: k everywhere,
    no gain: 1 / r."""
    r, k, b, chi = 25.0, 0.1, 3.0, math.radians(60.0)

    def arg(ap: FinalApproach, cross: float) -> float:  # atan's argument, read back from the course
        return math.tan((ap.course_rad - ap.line_course((-100.0, cross))) / (chi * 2.0 / math.pi))

    banded = FinalApproach((0.0, 0.0), 0.0, 500.0, r, line_gain_per_m=k, line_band_m=b)
    for sign in (1.0, -1.0):
        for e in (0.5, 1.0, 2.9):
            assert arg(banded, sign * e) == pytest.approx(sign * k * e)
        for e in (3.5, 10.0, 60.0):
            assert arg(banded, sign * e) == pytest.approx(sign * (k * b + (e - b) / r))
    thin = FinalApproach((0.0, 0.0), 0.0, 500.0, r, line_gain_per_m=k, line_band_m=0.5)
    assert arg(thin, 2.0) == pytest.approx(k * 0.5 + 1.5 / r)
    plain = FinalApproach((0.0, 0.0), 0.0, 500.0, r, line_gain_per_m=k)
    assert arg(plain, 10.0) == pytest.approx(k * 10.0)
    weak = FinalApproach((0.0, 0.0), 0.0, 500.0, r, line_gain_per_m=0.5 / r)
    assert arg(weak, 10.0) == pytest.approx(0.5 * 10.0 / r)
    assert arg(FinalApproach((0.0, 0.0), 0.0, 500.0, r), 10.0) == pytest.approx(10.0 / r)


def _pc7_model(substeps_dt: float = 0.01) -> tuple[FlownInput, object]:
    af = dataclasses.replace(TANKER, excess_power=TANKER.jsbsim.excess_power)
    lim = VehicleLimits.of(sc.airframes.envelope_vehicle(sc.Vehicle(), af))
    return FlownInput(af, lim, 0.01, substeps_dt), af


def test_the_models_energy_split_spends_no_more_than_the_excess_power_of_the_turn():
    """Energy conservation (Lambregts 1983): climb + (v / g) dv/dt <= P_s(v, m, n) at each substep,
    n = 1 / cos(bank) (B&M Eq. 9.14's coordinated turn) and P_s the PC-7's measured table; where the
    speed gets less than its first-order command (B&M Eq. 9.18) the power is spent whole."""
    f, af = _pc7_model()
    e, w, g = af.excess_power, 1000.0, 9.80665
    cmd = np.array([65.0, 5.0, 1.0])  # faster, climbing, turning at the bank limit
    f.input(cmd, False, AIR, w)
    spent_whole = 0
    for _ in range(2000):
        v0, c0, phi0 = f.state.airspeed_mps, f.state.climb_mps, f.state.bank_rad
        f.input(cmd, True, AIR, w)
        dv = (f.state.airspeed_mps - v0) / 0.01
        rate = c0 + v0 * dv / g
        p_s = e.power_at(v0, w, 1.0 / math.cos(phi0))
        assert rate <= p_s + 1e-9
        asked = min(max((65.0 - v0) / af.tau_airspeed_s, -af.accel_max_mps2), af.accel_max_mps2)
        if dv < asked - 1e-9:
            assert rate == pytest.approx(p_s, abs=1e-9)
            spent_whole += 1
    assert f.state.bank_rad > math.radians(40.0) and spent_whole > 1000


def test_at_its_lowest_speed_full_of_water_in_a_hard_turn_the_model_holds_the_speed_and_sinks():
    """P_s < 0 at 46.8 m/s full of water in a 45 deg turn (-1 m/s): at its lowest speed the aircraft
    gives up height, not speed (ExcessPower.split's floor, the autopilot's rule the agents model)."""
    f, af = _pc7_model(0.1)
    cmd = np.array([af.v_min_mps, 0.0, 1.0])
    f.input(cmd, False, AIR, 3000.0)
    for _ in range(100):
        u = f.input(cmd, True, AIR, 3000.0)
        assert f.state.airspeed_mps >= af.v_min_mps - 1e-9
    assert f.state.bank_rad > math.radians(40.0) and u[1] < -0.5


def test_the_distances_to_slow_down_and_to_descend_by_hand():
    """Constant deceleration a from v0 to v1 takes (v0 - v1) / a at the mean speed (small_uav, a = 3
    m/s^2: 30 -> 18.6 m/s in 3.8 s at 24.3 m/s, 92.34 m, the docstring's 92 m); a descent of h at the
    descent limit takes h / descent_max at the speed flown (tanker 8 m/s: 30 m in 3.75 s at 46.8 m/s,
    175.5 m; small_uav 5 m/s: 1 m at 20 m/s, 4 m); no descent, no distance."""
    assert slowdown_m(SMALL, 30.0, 18.6) == pytest.approx(3.8 * 24.3)
    assert slowdown_m(SMALL, 20.0, 20.0) == 0.0
    assert descent_m(TANKER, 46.8, 30.0) == pytest.approx(175.5)
    assert descent_m(SMALL, 20.0, 1.0) == pytest.approx(4.0)
    assert descent_m(SMALL, 20.0, 0.0) == 0.0
    assert descent_m(SMALL, 20.0, -5.0) == 0.0


def test_the_touchdown_step_rule_at_its_edges():
    """at_threshold's doc: the step rule is for an airframe that flies *more than* the radius in a
    step, at the step with |along| <= step / 2 (the one at -step / 2 included: the pass's next step
    is a whole step on), not a step further past the threshold."""
    ap = FinalApproach((0.0, 0.0), 0.0, 1800.0, 223.0)  # course 0: along = x
    assert not ap.at_threshold((1.0, 2.4), 2.5, 2.5)  # a step of exactly the radius: the disc alone
    assert ap.at_threshold((1.0, 2.4), 2.6, 2.5)
    assert ap.at_threshold((-2.34, 2.4), 4.68, 2.5)
    assert not ap.at_threshold((0.6 * 4.68, 2.4), 4.68, 2.5)
