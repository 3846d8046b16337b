"""The Agent's stages one control step at a time (agent_core), against independent truths.

Fast on purpose (the mutation selection of ``fire_uav_agent.agent_core`` runs this file once per
mutant): no world, no mission, only a few hand-made bundles per test. Truths used: the exact
linear-Gaussian posterior of one GPS / altimeter / gyro sample, the unicycle's exact motion
under a held command, the life-cycle's documented edges (mission module doc), the peer link's
crash rule (crash_threshold_steps missed steps), Gaussian centroids that symmetry fixes, a
brute-force sampled closest approach, and the published fields against what was decided.

Pose trick (:func:`_place`): the estimate is set by hand and the previous command to zero with
the vehicle "on the ground" before the step, so the step's prediction moves nothing and the
stages see exactly that pose.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.agent_core import Agent, AgentConfig, Bundle, GuidanceConfig, PlannerTarget
from fire_uav_agent.estimation import Samples
from fire_uav_agent.peer_link import FireEntry, PeerFires, PeerState
from fire_uav_agent.separation import SeparationConfig
from fire_uav_common import scenario as sc
from fire_uav_common.constants import EventType, Objective, PayloadAction, VehicleStatus
from fire_uav_common.terrain import Lake

AIR, GROUND, LANDED, CRASHED = (
    VehicleStatus.AIRBORNE,
    VehicleStatus.ON_GROUND,
    VehicleStatus.LANDED,
    VehicleStatus.CRASHED,
)
AREA = (0.0, 300.0, 0.0, 300.0)
T = 0.1  # [s] control period (scenario default)


def _cfg(uid: int = 0, n: int = 2, **kw) -> AgentConfig:
    kw.setdefault("area_m", AREA)
    kw.setdefault("loss_probability", 0.0)
    return AgentConfig(uav_id=uid, uav_count=n, **kw)


def _bundle(k, vehicle=AIR, water=2000.0, samples=None, fires=None, cells=None, cell_size=0.0):
    det = np.zeros((0, 4)) if fires is None else np.asarray(fires, dtype=float).reshape(-1, 4)
    return Bundle(k, T * (k + 1), samples or Samples(), det, water, int(vehicle), T, cells, cell_size)


def _place(a: Agent, x: float, y: float, z: float = 30.0, yaw: float = 0.0) -> None:
    """Set the estimate; the next step predicts with zero input from there (module doc)."""
    a.ekf.s = np.array([x, y, z, yaw], dtype=float)
    a._last_vehicle = int(GROUND)
    a.last_command = np.zeros(3)


def _fly(
    a: Agent, k: int, x: float, y: float, z: float = 30.0, yaw: float = 0.0, inbox=(), markers=False, **bkw
):
    _place(a, x, y, z, yaw)
    out = a.step(_bundle(k, **bkw), inbox, want_markers=markers)
    assert out is not None
    return out


def _peer(j, k, x, y, z=30.0, yaw=0.0, obj=Objective.SEARCH, fire=-1, water=2000.0, cx=None, cy=None):
    return PeerState(j, k + 1, k, x, y, z, yaw, int(obj), fire, water, x if cx is None else cx,
                     y if cy is None else cy)  # fmt: skip


def _heading_after(out, yaw0: float) -> float:
    return yaw0 + out.command[2] * T


class _Waypoint:
    """A planner that always answers the same waypoint (PlannerTarget fields as given)."""

    def __init__(self, xy=None, density=None, height=None, cap=None):
        self.target = PlannerTarget(xy, density, height, cap)
        self.views = []

    def plan(self, view):
        self.views.append(view)
        return self.target


class _Nothing:
    def plan(self, view):
        return None


# --- stage 1: estimate ------------------------------------------------------------------------
def _gps(t, x, y, var=0.0):
    return Samples(gps=np.array([[t, x, y]]), gps_var_m2=np.array([var]))


def test_a_gps_fix_on_the_ground_gives_the_exact_kalman_posterior():
    """Prior N(x0, 3^2) per axis (EkfConfig.initial_sigma), GPS sigma 4 m: K = 9 / (9 + 16)."""
    sens = sc.Sensors(gps=sc.GpsSpec(sigma_m=4.0))
    a = Agent(_cfg(start_pose=(100.0, 50.0, 0.0, 0.0), sensors=sens, takeoff_interval_s=100.0, uid=1))
    out = a.step(_bundle(0, GROUND, samples=_gps(0.05, 110.0, 45.0)))
    k = 9.0 / 25.0
    assert out.state.s[0] == pytest.approx(100.0 + 10.0 * k, abs=1e-9)
    assert out.state.s[1] == pytest.approx(50.0 - 5.0 * k, abs=1e-9)
    assert out.state.covariance[0, 0] == pytest.approx(9.0 * 16.0 / 25.0, abs=1e-9)
    assert out.state.covariance[2, 2] == pytest.approx(1.5**2, abs=1e-12)  # no motion, no noise
    # a reported variance (> 0) replaces the configured sigma: K = 9 / (9 + 1)
    b = Agent(_cfg(start_pose=(100.0, 50.0, 0.0, 0.0), sensors=sens, takeoff_interval_s=100.0, uid=1))
    out = b.step(_bundle(0, GROUND, samples=_gps(0.05, 110.0, 50.0, var=1.0)))
    assert out.state.s[0] == pytest.approx(100.0 + 10.0 * 0.9, abs=1e-9)


def test_an_altimeter_sample_gives_the_exact_posterior_and_one_beyond_range_is_ignored():
    """Prior z ~ N(20, 1.5^2), altimeter sigma 2 m on flat ground: K = 2.25 / 6.25."""
    sens = sc.Sensors(altimeter=sc.AltimeterSpec(sigma_m=2.0, max_range_m=50.0))
    a = Agent(_cfg(start_pose=(100.0, 50.0, 20.0, 0.0), sensors=sens, takeoff_interval_s=100.0, uid=1))
    out = a.step(_bundle(0, GROUND, samples=Samples(alt=np.array([[0.05, 24.0]]))))
    assert out.state.s[2] == pytest.approx(20.0 + 4.0 * 2.25 / 6.25, abs=1e-9)
    # 45 m: inside this altimeter's 50 m range (used), outside the default 40 m range (ignored)
    far = Samples(alt=np.array([[0.05, 45.0]]))
    a = Agent(_cfg(start_pose=(100.0, 50.0, 20.0, 0.0), sensors=sens, takeoff_interval_s=100.0, uid=1))
    assert a.step(_bundle(0, GROUND, samples=far)).state.s[2] > 20.0
    d = Agent(_cfg(start_pose=(100.0, 50.0, 20.0, 0.0), takeoff_interval_s=100.0, uid=1))
    assert d.step(_bundle(0, GROUND, samples=far)).state.s[2] == 20.0


@pytest.mark.parametrize(
    ("cmd", "dx", "dz", "dyaw"),
    [
        ((60.0, 2.0, 0.0), 6.0, 0.2, 0.0),  # inside the limits: as commanded
        ((150.0, 150.0, 0.0), 10.0, 10.0, 0.0),  # clamped to v_max = vz_max = 100 m/s
        ((10.0, -150.0, 0.0), 4.47, -10.0, 0.0),  # below stall: flown at v_stall 44.7 m/s
        ((50.0, 0.0, 30.0), None, 0.0, 1.0),  # turn rate clamped to 10 rad/s: 1 rad per step
        ((50.0, 0.0, -30.0), None, 0.0, -1.0),
    ],
)
def test_the_prediction_uses_the_previous_command_as_the_world_applies_it(cmd, dx, dz, dyaw):
    a = Agent(_cfg())
    a.ekf.s = np.array([100.0, 100.0, 30.0, 0.0])
    a._last_vehicle = int(AIR)
    a.last_command = np.array(cmd)
    a.last_step = 4
    out = a.step(_bundle(5, AIR))
    if dx is not None:
        assert out.state.s[0] == pytest.approx(100.0 + dx, abs=1e-9)
        assert out.state.s[1] == pytest.approx(100.0, abs=1e-9)
    assert out.state.s[2] == pytest.approx(30.0 + dz, abs=1e-9)
    assert out.state.s[3] == pytest.approx(dyaw, abs=1e-9)


def test_a_vehicle_that_just_took_off_predicts_with_the_raw_command():
    """On the ground the world does not clamp to stall speed: the first step's input is as sent."""
    a = Agent(_cfg())
    a.ekf.s = np.array([100.0, 100.0, 0.0, 0.0])
    a.last_command = np.array([10.0, 150.0, 0.0])  # vz still clamped to vz_max
    out = a.step(_bundle(0, AIR))
    assert out.state.s[0] == pytest.approx(101.0, abs=1e-9)
    assert out.state.s[2] == pytest.approx(10.0, abs=1e-9)


def test_touching_down_during_the_step_stops_the_horizontal_prediction():
    a = Agent(_cfg())
    a.ekf.s = np.array([100.0, 100.0, 1.0, 0.0])
    a._last_vehicle = int(AIR)
    a.last_command = np.array([50.0, -0.5, 3.0])
    out = a.step(_bundle(0, LANDED))
    assert out.state.s[0] == 100.0 and out.state.s[1] == 100.0 and out.state.s[3] == 0.0
    assert out.state.s[2] == pytest.approx(1.0 - 0.05, abs=1e-9)  # the sink still applies


def test_a_vehicle_on_the_ground_is_not_predicted():
    a = Agent(_cfg(uid=1, takeoff_interval_s=100.0))
    a.last_command = np.array([50.0, 5.0, 1.0])
    p0 = a.ekf.P.copy()
    out = a.step(_bundle(0, GROUND))
    assert np.array_equal(out.state.s, np.zeros(4)) and np.array_equal(out.state.covariance, p0)


def test_process_noise_and_the_gyro_enter_with_their_configured_sigmas():
    """P_zz grows by n dt^2 sigma_nu^2 over n = T / dt substeps; a gyro sample m per substep moves the
    rate to omega + k (m - omega), k = sigma_nu^2 / (sigma_nu^2 + sigma_gyro^2) (estimation doc)."""
    veh = sc.Vehicle(process_noise_sigma=2.0)
    sens = sc.Sensors(gyro=sc.GyroSpec(sigma_radps=0.5))
    a = Agent(_cfg(vehicle=veh, sensors=sens))
    a.ekf.s = np.array([100.0, 100.0, 30.0, 0.0])
    a._last_vehicle = int(AIR)
    a.last_command = np.array([50.0, 0.0, 0.0])
    gyro = np.column_stack([0.0 + 0.01 * np.arange(1, 11) - 0.005, np.ones(10)])
    out = a.step(_bundle(0, AIR, samples=Samples(gyro=gyro)))
    k = 4.0 / (4.0 + 0.25)
    assert out.state.s[3] == pytest.approx(10 * 0.01 * k, abs=1e-9)
    assert out.state.covariance[2, 2] == pytest.approx(1.5**2 + 10 * 0.01**2 * 4.0, abs=1e-12)


# --- stage 2: link ----------------------------------------------------------------------------
def test_a_silent_peer_is_declared_crashed_after_the_threshold_and_rejoins_when_heard():
    cfg = _cfg(n=3, mission=sc.Mission(crash_threshold_steps=3), takeoff_interval_s=100.0)
    a = Agent(cfg)
    outs = {}
    for k in range(12):
        inbox = [_peer(2, k - 1, 200.0, 200.0)] if k >= 1 else []  # peer 2 always heard
        if 1 <= k <= 2 or k >= 9:
            inbox.append(_peer(1, k - 1, 150.0, 150.0))  # peer 1 heard, silent for steps 2..8
        outs[k] = a.step(_bundle(k, GROUND), inbox)
    crashed = [(k, e) for k, o in outs.items() for e in o.events if e.type == EventType.PEER_CRASHED]
    rejoined = [(k, e) for k, o in outs.items() for e in o.events if e.type == EventType.PEER_REJOINED]
    # last heard at step 2 (state of step 1); missed at steps 3, 4, 5: crashed at step 5
    assert [(k, e.peer_id, e.value, e.detail) for k, e in crashed] == [(5, 1, 3.0, "crashed")]
    assert [(k, e.peer_id, e.detail) for k, e in rejoined] == [(9, 1, "rejoined")]
    assert outs[4].state.alive_peers == (0, 1, 2) and outs[4].state.crashed_peers == ()
    assert outs[5].state.alive_peers == (0, 2) and outs[5].state.crashed_peers == (1,)
    assert outs[8].state.alive_peers == (0, 2)
    assert outs[9].state.alive_peers == (0, 1, 2) and outs[9].state.crashed_peers == ()


def test_a_peer_never_heard_crashes_at_the_threshold_counted_from_step_1():
    a = Agent(_cfg(mission=sc.Mission(crash_threshold_steps=2), takeoff_interval_s=100.0))
    first = [
        k for k in range(5) for e in a.step(_bundle(k, GROUND)).events if e.type == EventType.PEER_CRASHED
    ]
    assert first == [2]


def test_two_states_of_one_peer_in_one_inbox_are_taken_oldest_first():
    """Both are news (steps 1 and 2): in step order both are accepted; newest first, the older one
    would be refused as old."""
    a = Agent(_cfg(takeoff_interval_s=100.0))
    a.step(_bundle(0, GROUND))
    a.step(_bundle(1, GROUND))
    out = a.step(_bundle(3, GROUND), [_peer(1, 2, 10.0, 10.0), _peer(1, 1, 5.0, 5.0)])
    assert (out.state.packets_received, out.state.packets_rejected) == (2, 0)
    assert a.link.alive_states()[1].step == 2


def test_peer_states_too_old_for_the_step_window_are_ignored():
    """The window is [k - crash_threshold_steps, k - 1]: at step 20 with threshold 10 a state of step 9
    is refused, one of step 10 accepted."""
    a = Agent(_cfg(takeoff_interval_s=100.0))
    a.last_step = 19
    out = a.step(_bundle(20, GROUND), [_peer(1, 9, 10.0, 10.0)])
    assert 1 not in a.link.alive_states() and out.state.packets_rejected == 1
    out = a.step(_bundle(21, GROUND), [_peer(1, 11, 10.0, 10.0)])
    assert a.link.alive_states()[1].step == 11 and out.state.packets_received == 1


def test_perimeters_and_fronts_from_bad_ids_or_lost_are_dropped():
    from fire_uav_agent.agent_types import PeerPerimeter
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront

    a = Agent(_cfg(n=3))
    per = [PeerPerimeter(j, 1, 4, 7, {}) for j in (0, 3, -1, 2)]
    fr = [PeerFront(j, 1, 4, FrontCells.empty()) for j in (0, 3, -1, 1)]
    got = a._link(5, per + fr, [])
    assert [p.uav_id for p in got] == [2]
    assert [f.uav_id for f in a._peer_fronts] == [1]
    assert a.perimeter_lost == 0
    lossy = Agent(_cfg(n=3, loss_probability=1.0))
    assert lossy._link(5, per + fr, []) == [] and lossy._peer_fronts == []
    assert lossy.perimeter_lost == 1


def test_peer_fire_pictures_go_through_the_link():
    a = Agent(_cfg(takeoff_interval_s=100.0))
    a.last_step = 3
    fe = FireEntry((1 << 16) | 1, True, 200.0, 200.0, 10.0, last_measurement_s=0.3)
    out = a.step(_bundle(4, GROUND), [PeerFires(1, 3, 3, (fe,))])
    assert [f.fire_id for f in out.fires] == [fe.fire_id]
    assert not [e for e in out.events if e.type == EventType.FIRE_DETECTED]  # not this UAV's sighting
    assert a.link.received == 1


# --- stage 3: fuse ----------------------------------------------------------------------------
def test_an_own_detection_airborne_opens_a_fire_with_this_uavs_id_and_an_event():
    a = Agent(_cfg(uid=1, n=3))
    out = _fly(a, 0, 100.0, 100.0, fires=[(0.05, 130.0, 110.0, 8.0)])
    (ev,) = [e for e in out.events if e.type == EventType.FIRE_DETECTED]
    assert ev.fire_id >> 16 == 1 and ev.detail == "first seen"
    assert (ev.x_m, ev.y_m) == pytest.approx((130.0, 110.0), abs=1e-6)
    assert [f.fire_id for f in out.fires] == [ev.fire_id]
    out = _fly(a, 1, 100.0, 100.0, fires=[(0.15, 130.0, 110.0, 8.0)])
    assert not [e for e in out.events if e.type == EventType.FIRE_DETECTED]  # the same fire again


def test_detections_are_ignored_on_the_ground():
    a = Agent(_cfg(uid=1, takeoff_interval_s=100.0))
    _place(a, 100.0, 100.0, 0.0)
    out = a.step(_bundle(0, GROUND, fires=[(0.05, 130.0, 110.0, 8.0)]))
    assert out.fires == () and out.events == ()


# --- stage 4: decide (life-cycle edges) ---------------------------------------------------------
def _objectives(outs):
    return [Objective(o.state.objective) for o in outs]


def test_grounded_until_the_takeoff_slot_then_search_with_an_objective_event():
    a = Agent(_cfg(uid=1, takeoff_interval_s=0.5))  # slot 1 x 0.5 s
    outs = [a.step(_bundle(k, GROUND)) for k in range(6)]  # stamps 0.1 .. 0.6
    assert _objectives(outs) == [Objective.GROUNDED] * 4 + [Objective.SEARCH] * 2
    assert all(o.command == (0.0, 0.0, 0.0) for o in outs[:4])
    (ev,) = outs[4].events
    assert ev.type == EventType.OBJECTIVE and ev.detail == "GROUNDED -> SEARCH"
    assert ev.value == float(Objective.SEARCH) and ev.fire_id == -1
    assert (ev.x_m, ev.y_m) == (0.0, 0.0)
    # takeoff: at least stall speed and the capped climb rate, straight ahead
    assert outs[4].command == (44.7, 20.0, 0.0)
    b = Agent(_cfg(uid=1, takeoff_interval_s=0.5, vehicle=sc.Vehicle(vz_max_mps=12.0)))
    assert [b.step(_bundle(k, GROUND)) for k in range(5)][4].command == (44.7, 12.0, 0.0)


def _suppressor(fire=(150.0, 150.0, 10.0), uid=0, n=2, **kw):
    return Agent(_cfg(uid=uid, n=n, prior_fires=(fire,), **kw))


def test_suppress_a_known_fire_and_drop_only_over_it():
    """Release within drop_radius_fraction x drop_radius = 0.7 x 20 = 14 m of the fire's centre; the
    drop halves the fire's extent at once (FF V-B, consensus.note_drop): a UAV that released has half
    the extent of one that saw the same and did not."""
    seen = [(0.05, 150.0, 150.0, 10.0)]
    a, b = _suppressor(), _suppressor()
    for ag in (a, b):
        out = _fly(ag, 0, 150.0 - 16.0, 150.0, fires=seen)
        assert out.state.objective == Objective.SUPPRESS and out.payload_requests == ()
        assert [e.detail for e in out.events if e.type == EventType.OBJECTIVE] == ["GROUNDED -> SUPPRESS"]
    fid = out.state.target_fire_id
    assert fid == out.fires[0].fire_id
    seen = [(0.15, 150.0, 150.0, 10.0)]
    out = _fly(a, 1, 150.0 - 13.0, 150.0, fires=seen)
    kept = _fly(b, 1, 150.0 - 16.0, 150.0, fires=seen)
    assert kept.payload_requests == () and kept.state.objective == Objective.SUPPRESS
    assert out.payload_requests == ((int(PayloadAction.DROP), fid),)
    assert out.state.objective == Objective.REFILL and out.state.target_fire_id == fid
    (ev,) = [e for e in out.events if e.type == EventType.OBJECTIVE]
    assert ev.detail == "SUPPRESS -> REFILL" and ev.fire_id == fid and (ev.x_m, ev.y_m) == (137.0, 150.0)
    assert ev.value == float(Objective.REFILL)
    (f,) = [e for e in out.fires if e.fire_id == fid]
    (g,) = [e for e in kept.fires if e.fire_id == fid]
    assert f.extent_m == pytest.approx(g.extent_m / 2, rel=1e-9)


def test_the_drop_radius_follows_the_footprint():
    a = _suppressor(drop_radius_m=30.0)  # 0.7 x 30 = 21 m
    _fly(a, 0, 100.0, 100.0)
    assert _fly(a, 1, 150.0 - 20.0, 150.0).payload_requests[0][0] == PayloadAction.DROP
    b = _suppressor(guidance=GuidanceConfig(drop_radius_fraction=0.5))  # 0.5 x 20 = 10 m
    _fly(b, 0, 100.0, 100.0)
    assert _fly(b, 1, 150.0 - 11.0, 150.0).payload_requests == ()


def test_an_empty_tank_flies_to_the_lake_and_refills_over_it():
    lake = Lake(250.0, 150.0, 40.0)
    a = _suppressor(lakes=(Lake(-2000.0, -2000.0, 40.0), lake))
    out = _fly(a, 0, 50.0, 150.0, water=100.0)  # the nearer lake due east, 200 m
    assert out.state.objective == Objective.REFILL and out.payload_requests == ()
    assert abs(out.command[2]) < 1e-6 and out.state.centroid_xy[0] > 150.0  # straight east at it
    out = _fly(a, 1, 50.0, 150.0, yaw=math.pi / 2, water=100.0)  # heading north: turn right (cw)
    assert out.command[2] < -1.0
    out = _fly(a, 2, 250.0, 155.0, water=1500.0)  # over the lake, tank not full
    assert out.payload_requests == ((int(PayloadAction.REFILL), -1),)
    out = _fly(a, 3, 250.0, 155.0, water=1999.0)  # full (>= 98 %): back to the fire
    assert out.state.objective == Objective.SUPPRESS and out.payload_requests == ()


def test_the_fleet_landing_and_the_touchdown_end_the_mission():
    a = _suppressor(fire=(250.0, 250.0, 10.0), start_pose=(20.0, 20.0, 0.0, 0.0))
    _fly(a, 0, 100.0, 100.0)
    out = _fly(a, 1, 100.0, 100.0, inbox=[_peer(1, 0, 200.0, 200.0, obj=Objective.LAND)])
    assert out.state.objective == Objective.LAND
    out = _fly(a, 2, 100.0, 100.0, inbox=[_peer(1, 1, 200.0, 200.0, obj=Objective.SEARCH)])
    assert out.state.objective == Objective.LAND  # terminal
    out = _fly(a, 3, 20.0, 20.0, z=0.0, vehicle=LANDED)
    assert out.state.objective == Objective.LANDED and out.command == (0.0, 0.0, 0.0)
    assert out.events[-1].detail == "LAND -> LANDED"


def test_a_crashed_vehicle_commands_nothing():
    a = _suppressor()
    _fly(a, 0, 100.0, 100.0)
    out = _fly(a, 1, 100.0, 100.0, vehicle=CRASHED)
    assert out.command == (0.0, 0.0, 0.0) and out.payload_requests == ()


def test_the_target_is_the_fire_of_largest_mass_in_the_own_cell_else_the_nearest():
    fires = ((60.0, 150.0, 10.0), (240.0, 150.0, 10.0))
    # peer flying at (250, 150): the own cell is the west half; own UAV nearer the east fire
    a = Agent(_cfg(prior_fires=fires))
    _fly(a, 0, 140.0, 150.0)
    out = _fly(a, 1, 140.0, 150.0, inbox=[_peer(1, 0, 250.0, 150.0)])
    west, east = sorted(out.fires, key=lambda f: f.x_m)
    assert out.state.target_fire_id == west.fire_id
    # the same peer grounded: no split, both fires in the cell, the larger mass wins
    b = Agent(_cfg(prior_fires=((60.0, 150.0, 5.0), (240.0, 150.0, 20.0))))
    _fly(b, 0, 140.0, 150.0)
    out = _fly(b, 1, 140.0, 150.0, inbox=[_peer(1, 0, 250.0, 150.0, obj=Objective.GROUNDED)])
    assert out.state.target_fire_id == max(out.fires, key=lambda f: f.extent_m).fire_id
    # both fires far outside the cell (no mass on it): the nearest
    c = Agent(_cfg(prior_fires=((-900.0, 150.0, 1.0), (1300.0, 150.0, 1.0))))
    _fly(c, 0, 250.0, 150.0)
    out = _fly(c, 1, 250.0, 150.0)
    assert out.state.target_fire_id == max(out.fires, key=lambda f: f.x_m).fire_id


def test_the_own_cell_splits_at_the_bisector_minus_the_safety_band():
    """Eq. 7: peer 200 m away, band Delta = 2 x 10 m: the cell ends at d - ... = bisector (d/2 > 20)."""
    a = Agent(_cfg())
    _fly(a, 0, 50.0, 150.0)
    out = _fly(a, 1, 50.0, 150.0, inbox=[_peer(1, 0, 250.0, 150.0)], markers=True)
    assert out.markers is not None
    assert np.all(out.markers.cell_boundary_xy[:, 0] == 147.5)  # the last column west of x = 150
    # peer 30 m away: d / 2 = 15 < Delta = 20, the boundary moves to d - Delta = 10 m from the UAV
    out = _fly(a, 2, 50.0, 150.0, inbox=[_peer(1, 1, 80.0, 150.0)], markers=True)
    assert np.all(out.markers.cell_boundary_xy[:, 0] == 57.5)
    assert out.markers.text == "uav 0: SEARCH" and out.markers.objective == int(Objective.SEARCH)
    # without the band (Eq. 6): the bisector at 65 m
    b = Agent(_cfg(mission=sc.Mission(use_safety_band=False)))
    _fly(b, 0, 50.0, 150.0)
    out = _fly(b, 1, 50.0, 150.0, inbox=[_peer(1, 0, 80.0, 150.0)], markers=True)
    assert np.all(out.markers.cell_boundary_xy[:, 0] == 62.5)


# --- stage 5: guide ---------------------------------------------------------------------------
def test_the_ff_altitude_layers_separate_even_and_odd_uavs():
    """GuidanceConfig: two layers 14 m apart around the 30 m flight height (23 and 37 m); a UAV at
    30 m climbs or sinks toward its own layer. One layer: everyone holds 30 m."""
    vz = {}
    for uid in (0, 1):
        a = Agent(_cfg(uid=uid, n=2, takeoff_interval_s=0.0))
        vz[uid] = _fly(a, 0, 100.0, 150.0, z=30.0).command[1]
    assert vz[0] * vz[1] < 0 and vz[0] == pytest.approx(-vz[1])
    a = Agent(_cfg(uid=0, guidance=GuidanceConfig(ff_layers=1)))
    assert _fly(a, 0, 100.0, 150.0, z=30.0).command[1] == pytest.approx(0.0, abs=1e-9)
    a = Agent(_cfg(uid=0, guidance=GuidanceConfig(ff_layers=1)))
    assert _fly(a, 0, 100.0, 150.0, z=25.0).command[1] > 0
    a = Agent(_cfg(uid=0, guidance=GuidanceConfig(ff_layers=2, ff_layer_step_m=4.0)))
    sink = _fly(a, 0, 100.0, 150.0, z=30.0).command[1]  # layer 28 m
    assert sink < 0 and abs(sink) < abs(vz[0])


def test_suppress_steers_at_the_centroid_of_the_fire_density():
    """Eq. 13 on a grid symmetric about the fire: the centroid is the fire's centre."""
    a = _suppressor(fire=(150.0, 150.0, 20.0))
    out = _fly(a, 0, 50.0, 150.0)
    assert out.state.centroid_xy == pytest.approx((150.0, 150.0), abs=1e-6)
    assert out.command[2] == pytest.approx(0.0, abs=1e-9)
    assert out.command[0] == 100.0  # K_p x 100 m, clamped to v_max
    out = _fly(a, 1, 150.0, 50.0, yaw=0.0)  # fire due north: turn left (ccw)
    assert out.command[2] > 1.0


def test_an_attack_run_flies_at_the_fire_itself():
    a = _suppressor(fire=(150.0, 150.0, 20.0))
    _fly(a, 0, 50.0, 150.0)
    a.mission._attack_since_s = 0.1  # a stalled UAV's attack run (mission doc)
    out = _fly(a, 1, 50.0, 100.0)
    assert out.direct and out.state.centroid_xy == (150.0, 150.0)


def test_refill_near_the_lake_is_low_and_slow_and_far_from_it_at_cruise():
    """Within lake radius + 150 m: height 0.5 x refill_height (7.5 m), speed <= v_stall + 0.3 x 10."""
    lake = Lake(250.0, 150.0, 40.0)
    a = _suppressor(lakes=(lake,))
    near = _fly(a, 0, 90.0, 150.0, z=7.5, water=0.0)  # 160 m from the centre: 20 + 150 = 170 m
    assert near.state.objective == Objective.REFILL
    assert near.command[0] == pytest.approx(44.7 + 3.0) and near.command[1] == pytest.approx(0.0, abs=1e-9)
    b = _suppressor(lakes=(lake,))
    far = _fly(b, 0, 10.0, 150.0, z=23.0, water=0.0)  # 240 m out: full speed at uav 0's 23 m layer
    assert far.command[0] == 100.0 and far.command[1] == pytest.approx(0.0, abs=1e-9)
    c = _suppressor(lakes=(lake,))
    assert _fly(c, 0, 90.0, 150.0, z=23.0, water=0.0).command[1] < 0  # near: down to 7.5 m


def test_landing_descends_near_home_and_touches_down_only_on_it():
    home = (100.0, 100.0, 0.0, 0.0)
    a = Agent(_cfg(start_pose=home))
    a.mission.objective = Objective.LAND
    far = _fly(a, 0, 250.0, 100.0, yaw=math.pi)  # 150 m out (> 120 m): the Eq. 15 density, at cruise
    assert far.state.centroid_xy == pytest.approx((100.0, 100.0), abs=1e-6)
    assert far.command[0] > 44.7
    near = _fly(a, 1, 180.0, 100.0, z=30.0, yaw=math.pi)  # 80 m: v_stall, descending
    assert near.command[0] == 44.7 and near.command[1] < 0
    # height profile: 0.5 m inside 0.3 x 120 = 36 m, cruise at 120 m; at 78 m: halfway
    lo = _fly(a, 2, 130.0, 100.0, z=0.5, yaw=math.pi).command[1]
    assert lo == pytest.approx(0.0, abs=1e-9)
    mid_h = 0.5 + (23.0 - 0.5) * (78.0 - 36.0) / 84.0
    mid = _fly(a, 3, 178.0, 100.0, z=mid_h, yaw=math.pi).command[1]
    assert mid == pytest.approx(0.0, abs=1e-9)
    # touch-down: below 0.8 m AGL within 2.5 m of home: no speed, sink 0.5 m/s
    assert _fly(a, 4, 102.0, 100.0, z=0.5, yaw=math.pi).command == (0.0, -0.5, 0.0)
    assert _fly(a, 5, 103.0, 100.0, z=0.5, yaw=math.pi).command != (0.0, -0.5, 0.0)
    assert _fly(a, 6, 102.0, 100.0, z=0.9, yaw=math.pi).command != (0.0, -0.5, 0.0)


def test_a_landing_uav_not_lined_up_close_to_home_flies_straight_out():
    """Within 25 m and more than 0.5 rad off the bearing to home: omega 0 (go around)."""
    a = Agent(_cfg(start_pose=(100.0, 100.0, 0.0, 0.0)))
    a.mission.objective = Objective.LAND
    out = _fly(a, 0, 120.0, 100.0, z=5.0, yaw=0.0)  # home behind it
    assert out.command[2] == 0.0 and out.command[0] == 44.7
    assert out.state.centroid_xy == (100.0, 100.0)
    out = _fly(a, 1, 120.0, 100.0, z=5.0, yaw=math.pi - 0.4)  # lined up within 0.5 rad: steer in (ccw)
    assert out.command[2] > 0
    out = _fly(a, 2, 130.0, 100.0, z=5.0, yaw=0.0)  # 30 m out: turns back instead
    assert out.command[2] != 0.0


def test_a_landing_uav_keeps_its_layer_over_a_landing_right_of_way_peer():
    a = Agent(_cfg(uid=1, start_pose=(100.0, 100.0, 0.0, 0.0)))
    a.mission.objective = Objective.LAND
    _fly(a, 0, 130.0, 100.0, z=5.0, yaw=math.pi)
    peer = _peer(0, 0, 125.0, 100.0, z=2.0, obj=Objective.LAND)
    held = _fly(a, 1, 130.0, 100.0, z=5.0, yaw=math.pi, inbox=[peer]).command[1]
    b = Agent(_cfg(uid=1, start_pose=(100.0, 100.0, 0.0, 0.0)))
    b.mission.objective = Objective.LAND
    _fly(b, 0, 130.0, 100.0, z=5.0, yaw=math.pi)
    free = _fly(
        b, 1, 130.0, 100.0, z=5.0, yaw=math.pi, inbox=[_peer(0, 0, 125.0, 100.0, z=2.0, obj=Objective.LANDED)]
    ).command[1]
    assert held > 0 > free  # climbs back to its layer / keeps descending


def test_home_outside_the_area_is_flown_at_directly():
    a = Agent(_cfg(start_pose=(-50.0, 150.0, 0.0, 0.0)))
    a.mission.objective = Objective.LAND
    out = _fly(a, 0, 250.0, 150.0, yaw=math.pi)
    assert out.state.centroid_xy == (-50.0, 150.0) and out.command[2] == pytest.approx(0.0, abs=1e-9)


def test_search_flies_the_planners_waypoint_height_and_speed_cap():
    p = _Waypoint((250.0, 150.0), height=10.0, cap=50.0)
    a = Agent(_cfg(), planners={int(Objective.SEARCH): p})
    out = _fly(a, 0, 50.0, 150.0, z=10.0)
    assert out.state.objective == Objective.SEARCH
    assert out.state.centroid_xy == (250.0, 150.0)
    assert out.command == pytest.approx((50.0, 0.0, 0.0), abs=1e-9)
    (v,) = p.views
    assert v.uav_id == 0 and v.s[0] == 50.0 and v.target_fire_id == -1 and v.t_s == pytest.approx(0.1)


def test_a_density_plan_is_flown_to_its_centroid_and_no_plan_falls_back_to_the_staleness_search():
    a = Agent(_cfg())
    dens = np.exp(-(np.hypot(a.grid.points[:, 0] - 150.0, a.grid.points[:, 1] - 200.0) ** 2) / 800.0)
    a.planners[int(Objective.SEARCH)] = _Waypoint(density=dens)
    out = _fly(a, 0, 150.0, 50.0, yaw=math.pi / 2)
    assert out.state.centroid_xy == pytest.approx((150.0, 200.0), abs=1e-3)
    b = Agent(_cfg(), planners={int(Objective.SEARCH): _Nothing()})
    c = Agent(_cfg())  # the default planner is the staleness search
    assert _fly(b, 0, 150.0, 50.0).state.centroid_xy == _fly(c, 0, 150.0, 50.0).state.centroid_xy


# --- separation -------------------------------------------------------------------------------
def _miss(own_xy, heading, speed, peer_xy, peer_v, horizon=2.0, n=2001):
    """Brute force: closest sampled distance of two straight-line motions over the horizon."""
    t = np.linspace(0.0, horizon, n)
    ox = own_xy[0] + speed * math.cos(heading) * t
    oy = own_xy[1] + speed * math.sin(heading) * t
    px, py = peer_xy[0] + peer_v[0] * t, peer_xy[1] + peer_v[1] * t
    return float(np.hypot(ox - px, oy - py).min())


def _head_on(avoidance=True, peer_obj=Objective.SEARCH, jump=0.0):
    """UAV 1 flies east at (100, 150) to a waypoint far east; peer 0 flies west at 60 m/s toward it."""
    a = Agent(_cfg(uid=1, avoidance=avoidance), planners={int(Objective.SEARCH): _Waypoint((290.0, 150.0))})
    a.avoider.cfg = SeparationConfig()
    _fly(a, 0, 100.0, 150.0)
    _fly(a, 1, 100.0, 150.0, inbox=[_peer(0, 0, 206.0 + jump, 150.0, yaw=math.pi, obj=peer_obj, cx=0.0)])
    before = a.avoidance_steps
    out = _fly(a, 2, 100.0, 150.0, inbox=[_peer(0, 1, 200.0, 150.0, yaw=math.pi, obj=peer_obj, cx=0.0)])
    a.avoidance_steps -= before  # count step 2 only
    return a, out


def test_separation_turns_away_from_a_peer_on_a_collision_course():
    r = SeparationConfig().radius_m
    a, out = _head_on()
    # peer predicted one period on: (194, 150), velocity (-60, 0)
    straight = _miss((100.0, 150.0), 0.0, out.command[0], (194.0, 150.0), (-60.0, 0.0))
    assert straight < 1.0  # the law alone flies into it
    new = _heading_after(out, 0.0)
    assert abs(new) > 0.1 and a.avoidance_steps == 1
    assert _miss((100.0, 150.0), new, max(out.command[0], 44.7), (194.0, 150.0), (-60.0, 0.0)) >= r - 0.5
    off, out_off = _head_on(avoidance=False)
    assert out_off.command[2] == pytest.approx(0.0, abs=1e-9) and off.avoidance_steps == 0


def test_separation_ignores_grounded_peers_and_a_jumping_peer_has_no_velocity():
    a, out = _head_on(peer_obj=Objective.GROUNDED)
    assert out.command[2] == pytest.approx(0.0, abs=1e-9) and a.avoidance_steps == 0
    # a peer that "moved" 2000 m in a step (GPS reset, rejoin): no velocity, a standing peer 100 m
    # ahead on the line, 2 s x 100 m/s reach it: still avoided, but from a standing prediction
    a, out = _head_on(jump=-2000.0)
    new = _heading_after(out, 0.0)
    assert _miss((100.0, 150.0), new, max(out.command[0], 44.7), (200.0, 150.0), (0.0, 0.0)) >= 19.5


# --- stage 6: publish -------------------------------------------------------------------------
def test_the_published_state_matches_the_estimate_and_the_decision():
    a = _suppressor(uid=1, n=3, takeoff_interval_s=0.0)
    outs = [_fly(a, k, 60.0 + k, 150.0, water=1500.0 - k) for k in range(3)]
    for k, o in enumerate(outs):
        st = o.state
        assert (o.step, st.step, st.sequence, o.fires_sequence) == (k, k, k + 1, k + 1)
        assert st.stamp_s == o.stamp_s == pytest.approx(T * (k + 1))
        assert st.uav_id == 1 and st.water_kg == 1500.0 - k
        assert st.s[0] == 60.0 + k and st.s[1] == 150.0
        assert st.objective == int(Objective.SUPPRESS) and st.target_fire_id == o.fires[0].fire_id
        assert st.alive_peers == (0, 1, 2) and st.crashed_peers == ()
    assert np.array_equal(outs[-1].state.covariance, a.ekf.P) and outs[-1].state.covariance is not a.ekf.P
    assert np.array_equal(a.last_command, np.array(outs[-1].command)) and a.last_step == 2
    assert a._pub_xy == (62.0, 150.0)
    assert a.step(_bundle(2)) is None and a.step(_bundle(1)) is None  # not newer: nothing
    ps = outs[-1].state.as_peer_state()
    assert (ps.centroid_x_m, ps.centroid_y_m) == outs[-1].state.centroid_xy


def test_markers_only_when_asked():
    a = _suppressor()
    assert _fly(a, 0, 60.0, 150.0).markers is None
    m = _fly(a, 1, 60.0, 150.0, markers=True).markers
    fid = a.mission.target_fire_id
    assert m.text == f"uav 0: SUPPRESS fire {fid}" and m.centroid_xy == a._centroid
    assert m.cell_boundary_xy.shape == (0, 2)  # alone: the whole area, no inner border


def test_fronts_known_from_peers_feed_the_published_fires_and_the_aim():
    """The fastest-spreading front among the peers' reports for an active fire (PM)."""
    a = _suppressor(fire=(150.0, 150.0, 20.0), n=3)
    fid = _fly(a, 0, 50.0, 150.0).state.target_fire_id
    slow = FireEntry(fid, True, 150.0, 150.0, 20.0, front_x_m=120.0, front_y_m=150.0, max_spread_rate_mps=0.5)
    fast = FireEntry(fid, True, 150.0, 150.0, 20.0, front_x_m=160.0, front_y_m=180.0, max_spread_rate_mps=1.5)
    other = FireEntry(99, True, 10.0, 10.0, 5.0, front_x_m=1.0, front_y_m=1.0, max_spread_rate_mps=9.0)
    nan = FireEntry(fid, True, 150.0, 150.0, 20.0, front_y_m=100.0, max_spread_rate_mps=5.0)
    inbox = [PeerFires(1, 1, 0, (slow, other)), PeerFires(2, 1, 0, (fast, nan))]
    out = _fly(a, 1, 50.0, 150.0, inbox=inbox)
    (f,) = [e for e in out.fires if e.fire_id == fid]
    assert (f.front_x_m, f.front_y_m, f.max_spread_rate_mps) == (160.0, 180.0, 1.5)
    assert a._fronts[fid] == (160.0, 180.0, 1.5)  # the NaN front (rate 5) is not a front
    (aim,) = [e for e in a._aim(tuple(a.fires.active())) if e.fire_id == fid]
    assert (aim.x_m, aim.y_m) == (160.0, 180.0)


# --- lockstep helper --------------------------------------------------------------------------
def test_the_lockstep_wait_expects_the_previous_steps_messages_of_the_alive_peers():
    from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

    st, fi = int(FLEET_STATE_SPEC.loss_index), int(FLEET_FIRES_SPEC.loss_index)
    a = Agent(_cfg(n=3, mission=sc.Mission(crash_threshold_steps=2), takeoff_interval_s=100.0))
    assert a.expected_peer_messages(0) == set()  # nothing was sent before step 0
    assert a.expected_peer_messages(1) == {(1, st), (1, fi), (2, st), (2, fi)}
    for k in range(3):
        a.step(_bundle(k, GROUND), [_peer(2, k - 1, 10.0, 10.0)] if k else [])
    assert a.link.crashed_ids() == [1]
    assert a.expected_peer_messages(3) == {(2, st), (2, fi)}
    lossy = Agent(_cfg(n=3, loss_probability=1.0))
    assert lossy.expected_peer_messages(5) == set()  # every message of step 4 is lost on receipt


# --- raster fires (FireCells) -----------------------------------------------------------------
def _block(cx=145.0, cy=145.0, cs=10.0, burning=1, ring=2):
    """FireCells: a 3 x 3 BURNING block centred on (cx, cy) inside rings of UNBURNED cells."""
    xs, ys, st = [], [], []
    for di in range(-ring, ring + 1):
        for dj in range(-ring, ring + 1):
            xs.append(cx + dj * cs)
            ys.append(cy + di * cs)
            st.append(1 if max(abs(di), abs(dj)) <= burning else 0)
    return (np.array(xs), np.array(ys), np.array(st, dtype=np.int64))


def _ring_cells(cx=145.0, cy=145.0, cs=10.0):
    """The active front of :func:`_block`: its 8 outer burning cells (the centre has no unburned
    neighbour)."""
    return {(cx + dj * cs, cy + di * cs) for di in (-1, 0, 1) for dj in (-1, 0, 1) if (di, dj) != (0, 0)}


def test_a_raster_fire_makes_the_front_picture_and_the_uavs_fly_their_tactic_layers():
    """raster_layers for the defaults: 4 layers 36, 28, 20, 12 m (tactics); uav 0 holds 12 m."""
    a = Agent(_cfg())
    out = _fly(a, 0, 50.0, 50.0, z=12.0, cells=_block(), cell_size=10.0)
    assert a.front is not None and a.front.cfg.cell_size_m == 10.0
    assert out.command[1] == pytest.approx(0.0, abs=1e-9)  # at its layer
    assert {(float(x), float(y)) for x, y in zip(out.front.x_m, out.front.y_m, strict=True)} == _ring_cells()
    b = Agent(_cfg(uid=1))
    assert _fly(b, 0, 50.0, 50.0, z=20.0, cells=_block(), cell_size=10.0).command[1] == pytest.approx(
        0.0, abs=1e-9
    )
    c = Agent(_cfg())  # no raster: the FF layer (23 m), so 12 m climbs
    assert _fly(c, 0, 50.0, 50.0, z=12.0).command[1] > 0 and c.front is None


def test_own_cells_are_observed_only_airborne_and_the_front_is_published_every_n_steps():
    a = Agent(_cfg(front_every_steps=3, takeoff_interval_s=100.0, uid=1))
    _place(a, 50.0, 50.0, 0.0)
    out = a.step(_bundle(0, GROUND, cells=_block(), cell_size=10.0))
    assert a.front is not None and len(a.front.front(0.1)) == 0  # on the ground: nothing seen
    assert len(out.front) == 0  # step 0: published (empty)
    a = Agent(_cfg(front_every_steps=3))
    outs = [_fly(a, k, 50.0, 50.0, cells=_block(), cell_size=10.0) for k in range(7)]
    assert [k for k, o in enumerate(outs) if o.front is not None] == [0, 3, 6]
    z = Agent(_cfg(front_every_steps=0))  # 0 counts as every step
    assert all(_fly(z, k, 50.0, 50.0, cells=_block(), cell_size=10.0).front is not None for k in range(2))


def test_peer_fronts_are_merged_and_malformed_ones_ignored():
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront

    a = Agent(_cfg(n=3))
    _fly(a, 0, 50.0, 50.0, cells=_block(), cell_size=10.0)
    good = FrontCells(np.array([255.0]), np.array([255.0]), np.array([1]), np.array([0.05]), np.array([0.3]))
    bad = FrontCells(np.array([25.0]), np.array([25.0]), np.array([1]), np.array(["noon"]), np.array([0.3]))
    out = _fly(a, 1, 50.0, 50.0, cells=_block(), cell_size=10.0,
               inbox=[PeerFront(1, 1, 0, good), PeerFront(2, 1, 0, bad)])  # fmt: skip
    assert a.fronts_received == 1 and a._peer_fronts == []
    fr = a.front.front(out.stamp_s)
    assert (255.0, 255.0) in {(float(x), float(y)) for x, y in zip(fr.x_m, fr.y_m, strict=True)}
    # no picture yet (no raster): peer fronts are dropped, not kept for later
    b = Agent(_cfg(n=3))
    _fly(b, 0, 50.0, 50.0)
    b._peer_fronts.append(PeerFront(1, 1, 0, good))
    b._fuse_front(_bundle(1), AIR, 0.2)
    assert b._peer_fronts == [] and b.front is None and b.fronts_received == 0


def test_over_a_raster_fire_the_uav_aims_at_a_front_cell_and_releases_only_at_the_peak():
    """Release rule (tactics): >= 3 burning cells within 0.8 x 20 = 16 m, and no more one step ahead."""
    fire = (145.0, 145.0, 15.0)
    a = _suppressor(fire=fire)
    out = _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    assert out.state.objective == Objective.SUPPRESS and out.payload_requests == ()
    assert out.state.centroid_xy in _ring_cells()  # the aim point is on the active front
    # at (125, 145) heading east: 3 burning cells in reach, 4 one step (4.47 m) ahead: not yet
    out = _fly(a, 1, 125.0, 145.0, cells=_block(), cell_size=10.0)
    assert out.payload_requests == ()
    # over the block's centre: 9 in reach, 7 ahead: release
    out = _fly(a, 2, 145.0, 145.0, cells=_block(), cell_size=10.0)
    assert out.payload_requests == ((int(PayloadAction.DROP), out.state.target_fire_id),)


def test_the_aim_point_lies_in_the_own_cell():
    a = _suppressor(fire=(145.0, 145.0, 15.0))
    _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    out = _fly(a, 1, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[_peer(1, 0, 230.0, 145.0)])
    x, y = out.state.centroid_xy
    assert (x, y) in _ring_cells() and x < (60.0 + 230.0) / 2  # west of the bisector at 145 m
    assert a._front_aim == (x, y)


def test_a_direct_run_over_a_raster_fire_without_front_goes_to_the_own_point_of_the_circle():
    """tactics.direct_run_point: 25 m around the track centre, 6 points, uav id modulo 6."""
    for uid, ang in ((1, math.pi / 3), (6, 0.0)):
        a = _suppressor(fire=(145.0, 145.0, 15.0), uid=uid, n=7)
        burnt = _block()
        burnt = (burnt[0], burnt[1], np.where(burnt[2] == 1, 2, 0))  # all burnt out: no front
        _fly(a, 0, 60.0, 145.0, cells=burnt, cell_size=10.0)
        a.mission._attack_since_s = 0.1
        out = _fly(a, 1, 60.0, 145.0, cells=burnt, cell_size=10.0)
        assert out.direct
        assert out.state.centroid_xy == pytest.approx(
            (145.0 + 25 * math.cos(ang), 145.0 + 25 * math.sin(ang))
        )


def test_the_flank_anchor_is_chosen_once():
    a = _suppressor(fire=(145.0, 145.0, 15.0), mission=sc.Mission(tactic="flank"))
    _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    first = a._anchor
    assert first in _ring_cells()
    _fly(a, 1, 60.0, 145.0, cells=_block(cx=175.0), cell_size=10.0)  # the front moved east
    assert a._anchor == first


# --- perimeter monitoring (PM) ----------------------------------------------------------------
def test_the_nearest_uav_monitors_the_fire_and_publishes_its_perimeter_every_n_steps():
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.Mission(monitors_per_fire=1),
                   perimeter_every_steps=4))  # fmt: skip
    outs = [_fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0) for k in range(9)]
    # step 0: no published position yet, so no role; then MONITOR (mission: monitor before suppress)
    assert _objectives(outs) == [Objective.SUPPRESS] + [Objective.MONITOR] * 8
    fid = outs[1].state.target_fire_id
    assert fid == outs[1].fires[0].fire_id
    assert [k for k, o in enumerate(outs) if o.perimeter is not None] == [4, 8]
    assert outs[4].perimeter[0] == fid


def test_loss_and_outages_follow_the_seeded_rule_of_the_peer_link():
    """peer_link doc: lost if rng.bernoulli(p, seed, "loss", j, i, s, topic) or (j -> i) is in an outage
    at (s + 1) T."""
    from fire_uav_agent.peer_link import Outage
    from fire_uav_common import rng
    from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

    tis = (int(FLEET_STATE_SPEC.loss_index), int(FLEET_FIRES_SPEC.loss_index))
    for seed in (3, 4):
        a = Agent(_cfg(uid=2, n=4, seed=seed, loss_probability=0.5))
        for s in range(6):
            want = {
                (j, ti) for j in (0, 1, 3) for ti in tis if not rng.bernoulli(0.5, seed, "loss", j, 2, s, ti)
            }
            assert a.expected_peer_messages(s + 1) == want
    down = Agent(_cfg(uid=0, n=2, outages=(Outage(1, 0, 0.0, 0.45),)))  # steps 0..3 stamped 0.1 .. 0.4
    assert [bool(down.expected_peer_messages(s + 1)) for s in range(6)] == [False] * 4 + [True] * 2
    slow = Agent(_cfg(uid=0, n=2, outages=(Outage(1, 0, 0.0, 0.45),), timing=sc.Timing(control_period_s=0.2)))
    assert [bool(slow.expected_peer_messages(s + 1)) for s in range(3)] == [False, False, True]


def _ending(dist_m, known=False, cells=None, steps=6):
    """Detect a fire at (150, 150) at step 0, then fly ``dist_m`` west of it without seeing it."""
    m = sc.Mission(prior_fires="known" if known else "unknown")
    a = Agent(_cfg(mission=m))
    outs = [
        _fly(
            a,
            0,
            110.0,
            150.0,
            fires=[(0.05, 150.0, 150.0, 5.0)],
            cells=cells,
            cell_size=10.0 if cells else 0.0,
        )
    ]
    for k in range(1, steps + 1):
        outs.append(_fly(a, k, 150.0 - dist_m, 150.0, cells=cells, cell_size=10.0 if cells else 0.0))
    return outs


def test_a_fire_is_ended_by_not_seeing_it_from_within_the_negative_range():
    """'No fire here' range = min(50 m, 0.7 x 70 m sensor range) = 49 m (GuidanceConfig), 5 steps."""
    outs = _ending(48.5)
    assert [o.fires[0].active for o in outs] == [True] * 5 + [False] * 2
    assert _objectives(outs)[-1] == Objective.SEARCH  # unknown fires: sweep before landing
    assert all(o.fires[0].active for o in _ending(49.5))
    # known-fires mode: no sweep, land as soon as the fires are out
    assert _objectives(_ending(48.5, known=True))[4:] == [Objective.SUPPRESS, Objective.LAND, Objective.LAND]


def test_burning_cells_near_a_fire_keep_it_alive():
    """Raster fires (consensus doc): no negative evidence while a known burning cell is in its gate."""
    outs = _ending(20.0, cells=_block(cx=165.0, cy=165.0))
    assert all(o.fires[0].active for o in outs)
    assert not _ending(20.0)[-1].fires[0].active


def test_a_malformed_peer_perimeter_counts_nothing():
    from fire_uav_agent.agent_types import PeerPerimeter

    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.Mission(monitors_per_fire=1)))
    for k in range(3):
        _fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0)
    fid = a.mission.target_fire_id
    assert fid in a.monitor.monitors
    bad = PeerPerimeter(1, 1, 2, fid, {"center_x_m": 1.0})
    other = PeerPerimeter(1, 2, 2, fid + 1, {"center_x_m": 1.0})  # a fire this UAV does not monitor
    try:
        _fly(a, 3, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[bad, other])
    except (KeyError, TypeError) as e:  # pragma: no cover - a malformed map must not crash the agent
        pytest.fail(f"malformed perimeter crashed the agent: {e!r}")
    assert (a.perimeter_received, a.perimeter_lost) == (0, 0)
    good = PeerPerimeter(1, 3, 3, fid, a.monitor.active.to_summary())
    _fly(a, 4, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[good])
    assert (a.perimeter_received, a.perimeter_lost) == (1, 0)
