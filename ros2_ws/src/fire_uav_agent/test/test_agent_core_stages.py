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

import dataclasses
import math

import numpy as np
import pytest
from fire_uav_agent.agent_core import Agent, AgentConfig, Bundle, GuidanceConfig, PlannerTarget
from fire_uav_agent.estimation import Samples
from fire_uav_agent.peer_link import FireEntry, PeerFires, PeerState
from fire_uav_agent.separation import SeparationConfig
from fire_uav_common import scenario as sc
from fire_uav_common.constants import EventType, Objective, PayloadAction, VehicleStatus
from fire_uav_common.terrain import Lake, Terrain

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
    cfg = _cfg(n=3, mission=sc.MissionSettings(crash_threshold_steps=3), takeoff_interval_s=100.0)
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
    a = Agent(_cfg(mission=sc.MissionSettings(crash_threshold_steps=2), takeoff_interval_s=100.0))
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


def test_only_the_gates_sorted_inbox_skips_the_sort():
    """The gate's SortedInbox (already in inbox_order) is taken as it is; any other sequence, a
    plain tuple included, is sorted first: the same step either way."""
    from fire_uav_agent.peer_gate import SortedInbox, inbox_order

    msgs = [_peer(2, 2, 20.0, 20.0), _peer(1, 2, 10.0, 10.0), _peer(1, 1, 5.0, 5.0), _peer(2, 1, 4.0, 4.0)]
    outs = []
    for inbox in (tuple(msgs), list(reversed(msgs)), SortedInbox(sorted(msgs, key=inbox_order))):
        a = Agent(_cfg(n=3, takeoff_interval_s=100.0))
        a.step(_bundle(0, GROUND))
        a.step(_bundle(1, GROUND))
        out = a.step(_bundle(3, GROUND), inbox)
        outs.append((out.state.packets_received, out.state.packets_rejected, a.link.alive_states()))
    assert outs[0] == outs[1] == outs[2]
    assert outs[0][:2] == (4, 0) and {j: s.step for j, s in outs[0][2].items()} == {1: 2, 2: 2}


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
    fr = [PeerFront(j, 1, 4, FrontCells.empty(), 10.0) for j in (0, 3, -1, 1)]
    got = a._link(5, per + fr, [])
    assert [p.uav_id for p in got] == [2]
    assert [f.uav_id for f in a.raster.peer_fronts] == [1]
    assert a.perimeter_lost == 0
    lossy = Agent(_cfg(n=3, loss_probability=1.0))
    assert lossy._link(5, per + fr, []) == [] and lossy.raster.peer_fronts == []
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
    b = Agent(_cfg(mission=sc.MissionSettings(use_safety_band=False)))
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


def test_the_centroid_steered_to_feeds_the_deadlock_rule():
    """Mission doc (FF IV-D deadlock): a UAV in SUPPRESS with water whose centroid moved less than
    deadlock_centroid_move_m (10 m) for deadlock_timeout_s attacks directly. Hovering 100 m from
    the fire (no drop), its Eq. 9 centroid stays on the fire: with a 0.5 s timeout, the attack run
    starts at the first step 0.5 s after SUPPRESS began (t 0.1 s), at t 0.6 s, not before."""
    a = _suppressor(fire=(150.0, 150.0, 20.0))
    a.mission.cfg = dataclasses.replace(a.mission.cfg, deadlock_timeout_s=0.5)
    outs = [_fly(a, k, 50.0, 150.0) for k in range(8)]
    assert all(o.state.objective == Objective.SUPPRESS for o in outs)
    assert [o.direct for o in outs] == [False] * 5 + [True] * 3


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
def _miss(own_xy, heading, speed, peer_xy, peer_v, horizon=2.0, n=4001):
    """Brute force: closest sampled distance of two straight-line motions over the horizon."""
    t = np.linspace(0.0, horizon, n)
    ox = own_xy[0] + speed * math.cos(heading) * t
    oy = own_xy[1] + speed * math.sin(heading) * t
    px, py = peer_xy[0] + peer_v[0] * t, peer_xy[1] + peer_v[1] * t
    return float(np.hypot(ox - px, oy - py).min())


def _wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def _nearest_clear(own_xy, want, speed, peer_xy, peer_v, yield_m=None, r=20.0):
    """The separation rule by brute force: the desired heading if its sampled miss distance is at
    least ``r``, else the nearest of the 72 candidate headings around it that is; with ``yield_m``
    (the peer has the right of way and is that close) also no heading that closes on the peer."""
    away = (own_xy[0] - peer_xy[0], own_xy[1] - peer_xy[1])

    def ok(h):
        opening = yield_m is None or math.cos(h) * away[0] + math.sin(h) * away[1] >= 0
        return opening and _miss(own_xy, h, speed, peer_xy, peer_v) >= r

    if ok(want):
        return want
    cands = [want - math.pi + k * 2 * math.pi / 72 for k in range(72)]
    return min((c for c in cands if ok(c)), key=lambda c: abs(_wrap(c - want)))


OWN = (60.0, 100.0)


def _crossing(uid, pid, p0, v, yaw=0.0, n=2, avoidance=True, extra=(), z=30.0, steps=6, wp=(290.0, OWN[1]),
              p2=None, cxy=(math.nan, math.nan)):  # fmt: skip
    """UAV ``uid`` at OWN heading ``yaw``, its waypoint ``wp``; peer ``pid`` (published target ``cxy``)
    reports p0 for step 1 (received at our step 2) and p0 + 2 T v for step 3 (received at step 4).
    Our step 4 then predicts it one period on, at t_5: p0 + 3 T v, moving at v."""
    a = Agent(_cfg(uid=uid, n=n, avoidance=avoidance), planners={int(Objective.SEARCH): _Waypoint(wp)})
    yaw_p = math.atan2(v[1], v[0])
    p2 = p2 or (p0[0] + 2 * T * v[0], p0[1] + 2 * T * v[1])
    outs = []
    for k in range(steps):
        inbox = list(extra) if k == 2 else []
        if k == 2:
            inbox.append(_peer(pid, 1, *p0, z=z, yaw=yaw_p, cx=cxy[0], cy=cxy[1]))
        if k == 4:
            inbox.append(_peer(pid, 3, *p2, z=z, yaw=yaw_p, cx=cxy[0], cy=cxy[1]))
        outs.append(_fly(a, k, *OWN, yaw=yaw, inbox=inbox))
    return a, outs


@pytest.mark.parametrize(
    ("p0", "v"),
    [((170.0, 10.0), (-30.0, 90.0)), ((150.0, 190.0), (-20.0, -80.0)), ((200.0, 40.0), (-10.0, 50.0))],
)
def test_separation_turns_to_the_nearest_heading_that_clears_the_peer(p0, v):
    """The peer's motion from its last two states (2 steps apart), moved to our t_{k+1}; the heading
    flown after the step is the nearest clear one, by brute force (lower ids have the right of way,
    so uav 0 has no peer to yield to)."""
    q = (p0[0] + 3 * T * v[0], p0[1] + 3 * T * v[1])
    a, outs = _crossing(0, 1, p0, v)
    assert all(o.command[2] == 0.0 for o in outs[:4])  # the first report alone (no velocity): clear
    assert _miss(OWN, 0.0, 100.0, q, v) < 20.0  # the law's heading would pass too close
    want = _nearest_clear(OWN, 0.0, 100.0, q, v)
    assert _heading_after(outs[4], 0.0) == pytest.approx(want, abs=1e-9)
    assert outs[4].command[0] == 100.0  # clear: at the law's speed
    assert a.avoidance_steps == 2  # steps 4 and 5 (it keeps to its deviation)
    off, outs_off = _crossing(0, 1, p0, v, avoidance=False)
    assert outs_off[4].command[2] == 0.0 and off.avoidance_steps == 0


def test_the_avoider_gets_the_height_above_the_terrain_below_and_resolves_vertically_except_landing():
    """The vertical resolution's wiring (``Guide._separate``, session 26): every avoider call gets
    the UAV's height above the terrain under it (z minus E(x, y) on a ground sloping both ways,
    so that x and y are told apart) and resolves vertically in any objective but LAND."""
    terrain = Terrain(base_m=5.0, slope_x=0.05, slope_y=0.02)
    a = Agent(
        _cfg(avoidance=True, terrain=terrain), planners={int(Objective.SEARCH): _Waypoint((290.0, 100.0))}
    )
    calls = []
    command = a.avoidance.command

    def spy(s, cmd, target, peers, last_step, straight=False, agl_m=math.inf, resolve_vertical=True):
        calls.append((a.mission.objective, np.array(s, dtype=float), agl_m, resolve_vertical))
        return command(s, cmd, target, peers, last_step, straight, agl_m, resolve_vertical)

    a.avoidance.command = spy
    _fly(a, 0, 60.0, 100.0, z=40.0)
    a.mission.objective = Objective.LAND
    _fly(a, 1, 150.0, 100.0, z=40.0)  # 50 m from home (100, 50): the approach
    assert [c[0] for c in calls] == [Objective.SEARCH, Objective.LAND]
    for obj, s, agl, vertical in calls:
        assert agl == pytest.approx(s[2] - (5.0 + 0.05 * s[0] + 0.02 * s[1]), abs=1e-12)
        assert 25.0 < agl < 31.0  # 40 - (5 + 3 + 2) = 30 at (60, 100); 40 - 14.5 at (150, 100)
        assert vertical is (obj != Objective.LAND)


def test_separation_wants_the_targets_bearing_not_the_current_heading():
    p0, v = (150.0, 190.0), (-20.0, -80.0)
    q = (p0[0] + 3 * T * v[0], p0[1] + 3 * T * v[1])
    a, outs = _crossing(0, 1, p0, v, yaw=0.3)
    want = _nearest_clear(OWN, 0.0, 100.0, q, v)  # the waypoint is due east, whatever the heading
    assert 0.3 + _wrap(want - 0.3) == pytest.approx(_heading_after(outs[4], 0.3), abs=1e-9)


def test_a_peer_with_the_right_of_way_close_by_is_never_closed_on():
    """Within yield_m = 60 m of a lower id: only headings that do not close on it (separation doc)."""
    p0, v = (110.0, 60.0), (-20.0, 40.0)
    q = (p0[0] + 3 * T * v[0], p0[1] + 3 * T * v[1])
    a, outs = _crossing(1, 0, p0, v)
    want = _nearest_clear(OWN, 0.0, 100.0, q, v, yield_m=60.0)
    turn = max(-1.0, min(1.0, want))  # at most omega_max T = 1 rad in one step
    assert _heading_after(outs[4], 0.0) == pytest.approx(turn, abs=1e-9)
    b, outs_b = _crossing(0, 1, p0, v)  # the same peer without the right of way
    assert _heading_after(outs_b[4], 0.0) == pytest.approx(_nearest_clear(OWN, 0.0, 100.0, q, v), abs=1e-9)


def test_the_peers_velocity_is_kept_while_it_is_not_heard_again():
    """Step 5 reuses the step-3 report: the peer is predicted 2 T on (p0 + 4 T v), same velocity.
    (The avoider's commitment to its step-4 deviation is cleared first, so the rule is the plain one.)"""
    p0, v = (150.0, 190.0), (-20.0, -80.0)
    a, outs = _crossing(0, 1, p0, v, steps=5)
    a.avoidance.avoider.heading_rad = None
    out = _fly(a, 5, *OWN)
    q = (p0[0] + 4 * T * v[0], p0[1] + 4 * T * v[1])
    assert _heading_after(out, 0.0) == pytest.approx(_nearest_clear(OWN, 0.0, 100.0, q, v), abs=1e-9)


def test_separation_ignores_grounded_peers_and_a_jumping_peer_has_no_velocity():
    p0, v = (150.0, 190.0), (-20.0, -80.0)
    grounded = PeerState(1, 1, 0, 65.0, 100.0, 30.0, 0.0, int(Objective.GROUNDED), -1, 2000.0, 65.0, 100.0)
    a, outs = _crossing(0, 2, p0, v, n=3, extra=[grounded])  # uav 1 grounded 5 m away: no conflict
    assert all(o.command[2] == 0.0 for o in outs[:4]) and outs[4].command[2] != 0.0
    # a peer that "moved" 2000 m between its reports (rejoin, GPS reset): no velocity; standing at
    # its last report p2, 2 s x 100 m/s reach it
    a, outs = _crossing(0, 1, (150.0 - 2000.0, 190.0), v)
    p2 = (150.0 + 2 * T * v[0], 190.0 + 2 * T * v[1])
    assert _heading_after(outs[4], 0.0) == pytest.approx(
        _nearest_clear(OWN, 0.0, 100.0, p2, (0.0, 0.0)), abs=1e-9
    )


def test_peers_far_above_are_no_conflict_and_with_no_clear_heading_it_slows_to_stall():
    p0, v = (150.0, 190.0), (-20.0, -80.0)
    a, outs = _crossing(0, 1, p0, v, z=45.0)  # 15 m above (> vertical_m = 10 m)
    assert outs[4].command[2] == 0.0 and a.avoidance_steps == 0
    # a standing peer 5 m away: every heading passes within 20 m; speed down to stall
    a = Agent(_cfg(uid=0), planners={int(Objective.SEARCH): _Waypoint((290.0, OWN[1]))})
    _fly(a, 0, *OWN)
    out = _fly(a, 1, *OWN, inbox=[_peer(1, 0, OWN[0] - 5.0, OWN[1])])
    assert out.command[0] == 44.7 and a.avoidance_steps == 1
    assert Agent(_cfg()).avoidance_steps == 0


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


def test_the_marked_cell_boundary_is_every_cell_point_with_a_grid_neighbour_outside_it():
    """The markers' boundary, by brute force over the grid: a point of the own cell with one of
    its 4 grid neighbours (inside the grid) not in the cell. Peers below, above, left and right
    of uav 1 give a cell with an inner edge on each side."""
    for peer_xy in ((150.0, 50.0), (150.0, 250.0), (50.0, 150.0), (250.0, 150.0)):
        a = Agent(_cfg(uid=1))
        _fly(a, 0, 150.0, 150.0)
        m = _fly(
            a, 1, 300.0 - peer_xy[0], 300.0 - peer_xy[1], inbox=[_peer(0, 0, *peer_xy)], markers=True
        ).markers
        ny, nx = a.grid.shape
        c = a._cell.reshape(ny, nx)
        want = set()
        for i in range(ny):
            for j in range(nx):
                nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))]
                if c[i, j] and any(0 <= p < ny and 0 <= q < nx and not c[p, q] for p, q in nbrs):
                    want.add((float(a.grid.xs[j]), float(a.grid.ys[i])))
        got = {(float(x), float(y)) for x, y in m.cell_boundary_xy}
        assert got == want and len(want) >= nx - 2, peer_xy


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


def test_an_own_monitors_front_comes_before_the_peers_reports():
    """_collect_fronts: a fire this UAV monitors takes its own monitor's head (PerimeterMonitor
    .front) over a peer's reported front. The monitor's map is given a spreading fire by hand
    (every bin 1 m/s by Eq. 1, its outer cells 400 m out, beyond the footprint)."""
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1), n=3))
    for k in range(3):
        _fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0)
    fid = a.mission.target_fire_id
    fm = a.monitor.monitors[fid].fire_map
    th = fm.bin_center_rad()
    r = np.where(np.abs(np.sin(th)) < 0.5, 400.0, 390.0)  # farthest east and west
    fm.outer_x_m[:], fm.outer_y_m[:] = fm.center_x_m + r * np.cos(th), fm.center_y_m + r * np.sin(th)
    fm.outer_d_m[:], fm.outer_t_s[:] = r, 0.25
    fm.inner_d_m[:], fm.inner_t_s[:] = r - 0.2, 0.05
    peer = FireEntry(fid, True, 145.0, 145.0, 15.0, front_x_m=10.0, front_y_m=20.0, max_spread_rate_mps=9.0)
    out = _fly(a, 3, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[PeerFires(1, 3, 2, (peer,))])
    own = a.monitor.front(fid)
    assert own is not None and own[2] == pytest.approx(1.0)
    (f,) = [e for e in out.fires if e.fire_id == fid]
    assert (f.front_x_m, f.front_y_m, f.max_spread_rate_mps) == own


# --- lockstep helper --------------------------------------------------------------------------
def test_the_lockstep_wait_expects_the_previous_steps_messages_of_the_alive_peers():
    from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

    st, fi = int(FLEET_STATE_SPEC.loss_index), int(FLEET_FIRES_SPEC.loss_index)
    a = Agent(_cfg(n=3, mission=sc.MissionSettings(crash_threshold_steps=2), takeoff_interval_s=100.0))
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
    """raster_layers for the defaults: 3 layers 36, 22, 8 m (tactics); uav 0 holds 8 m."""
    a = Agent(_cfg())
    out = _fly(a, 0, 50.0, 50.0, z=8.0, cells=_block(), cell_size=10.0)
    assert a.front is not None and a.front.cfg.cell_size_m == 10.0
    assert out.command[1] == pytest.approx(0.0, abs=1e-9)  # at its layer
    f = a.front.front()
    assert {(float(x), float(y)) for x, y in zip(f.x_m, f.y_m, strict=True)} == _ring_cells()
    # the published FireFront: the front plus the burning cells just seen off it (the centre;
    # front_consensus' recent cells)
    sent = {(float(x), float(y)) for x, y in zip(out.front.x_m, out.front.y_m, strict=True)}
    assert sent == _ring_cells() | {(145.0, 145.0)}
    b = Agent(_cfg(uid=1))
    assert _fly(b, 0, 50.0, 50.0, z=22.0, cells=_block(), cell_size=10.0).command[1] == pytest.approx(
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
               inbox=[PeerFront(1, 1, 0, good, 10.0), PeerFront(2, 1, 0, bad, 10.0)])  # fmt: skip
    assert a.fronts_received == 1 and a.raster.peer_fronts == []
    fr = a.front.front(out.stamp_s)
    assert (255.0, 255.0) in {(float(x), float(y)) for x, y in zip(fr.x_m, fr.y_m, strict=True)}
    # no picture yet (no raster): peer fronts are dropped, not kept for later
    b = Agent(_cfg(n=3))
    _fly(b, 0, 50.0, 50.0)
    b.raster.peer_fronts.append(PeerFront(1, 1, 0, good, 10.0))
    b.raster.fuse(_bundle(1), AIR, 0.2)
    assert b.raster.peer_fronts == [] and b.front is None and b.fronts_received == 0


def test_a_peer_front_of_another_cell_size_is_a_counted_rejection_not_a_merge():
    """The picture is of 10 m cells; a 30 m sender's cell centred at (255, 255) would be taken as the
    10 m cell there (its centre too). Rejected, counted in the link as "cell size" (so in the
    published ``packets_rejected``) and named for the node's log; a 10 m sender's same cell merges."""
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront

    a = Agent(_cfg(n=3))
    _fly(a, 0, 50.0, 50.0, cells=_block(), cell_size=10.0)
    cell = FrontCells(np.array([255.0]), np.array([255.0]), np.array([1]), np.array([0.05]), np.array([0.3]))
    out = _fly(a, 1, 50.0, 50.0, cells=_block(), cell_size=10.0, inbox=[PeerFront(2, 1, 0, cell, 30.0)])
    assert a.link.reject_reasons == {"cell size": 1} and out.state.packets_rejected == 1
    assert a.raster.cell_size_refused == [(2, 30.0)] and a.fronts_received == 0
    assert a.front.state[a.front.index(np.array([255.0]), np.array([255.0]))[:2]].tolist() == [-1]  # unknown
    # float32 on the wire: a 10 m side within float32 rounding is the same raster's
    near = float(np.float32(10.0 * (1 + 3e-8)))
    out = _fly(a, 2, 50.0, 50.0, cells=_block(), cell_size=10.0, inbox=[PeerFront(1, 1, 1, cell, near)])
    assert a.fronts_received == 1 and a.raster.cell_size_refused == [] and out.state.packets_rejected == 1
    assert a.front.state[a.front.index(np.array([255.0]), np.array([255.0]))[:2]].tolist() == [1]


def test_a_refused_peer_front_does_not_stop_the_next_ones_merging():
    """Peer 1's front (30 m cells, handed over first: inbox order is by sender) is refused; peer 2's
    of the same step (10 m, the picture's) still merges."""
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront

    a = Agent(_cfg(n=3))
    _fly(a, 0, 50.0, 50.0, cells=_block(), cell_size=10.0)
    cell = FrontCells(np.array([255.0]), np.array([255.0]), np.array([1]), np.array([0.05]), np.array([0.3]))
    inbox = [PeerFront(1, 1, 0, cell, 30.0), PeerFront(2, 1, 0, cell, 10.0)]
    _fly(a, 1, 50.0, 50.0, cells=_block(), cell_size=10.0, inbox=inbox)
    assert a.raster.cell_size_refused == [(1, 30.0)] and a.fronts_received == 1
    assert a.front.state[a.front.index(np.array([255.0]), np.array([255.0]))[:2]].tolist() == [1]


def test_the_raster_aim_keeps_clear_of_a_suppressing_right_of_way_peers_aim():
    """_decide hands the alive peers' states to the raster aim (tactics module doc): uav 3 shares
    uav 0's 8 m layer; peer 0, suppressing, published the block's centre (145, 145) as its aim, so
    every front cell (the ring, within 14.2 m of it) is within aim_clear_m = 60 m and uav 3 waits
    60 m from (145, 145) on its own side: (85, 145) by hand. Without the peer it aims at the ring."""
    fire = (145.0, 145.0, 15.0)
    aims = []
    for inbox in ([], [_peer(0, 0, 145.0, 100.0, z=8.0, obj=Objective.SUPPRESS, cx=145.0, cy=145.0)]):
        a = _suppressor(fire=fire, uid=3, n=4)
        _fly(a, 0, 60.0, 145.0, z=8.0, cells=_block(), cell_size=10.0)
        out = _fly(a, 1, 60.0, 145.0, z=8.0, cells=_block(), cell_size=10.0, inbox=inbox)
        assert out.state.objective == Objective.SUPPRESS
        aims.append(out.state.centroid_xy)
    assert aims[0] in _ring_cells()
    assert aims[1] == pytest.approx((85.0, 145.0))


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
    a = _suppressor(fire=(145.0, 145.0, 15.0), mission=sc.MissionSettings(tactic="flank"))
    _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    first = a.raster.anchor
    assert first in _ring_cells()
    _fly(a, 1, 60.0, 145.0, cells=_block(cx=175.0), cell_size=10.0)  # the front moved east
    assert a.raster.anchor == first


# --- perimeter monitoring (PM) ----------------------------------------------------------------
def test_the_nearest_uav_monitors_the_fire_and_publishes_its_perimeter_every_n_steps():
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1),
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
    from fire_uav_common import rng
    from fire_uav_common.scenario import LinkOutage
    from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

    tis = (int(FLEET_STATE_SPEC.loss_index), int(FLEET_FIRES_SPEC.loss_index))
    for seed in (3, 4):
        a = Agent(_cfg(uid=2, n=4, seed=seed, loss_probability=0.5))
        for s in range(6):
            want = {
                (j, ti) for j in (0, 1, 3) for ti in tis if not rng.bernoulli(0.5, seed, "loss", j, 2, s, ti)
            }
            assert a.expected_peer_messages(s + 1) == want
    down = Agent(_cfg(uid=0, n=2, outages=(LinkOutage(1, 0, 0.0, 0.45),)))  # steps 0..3 stamped 0.1 .. 0.4
    assert [bool(down.expected_peer_messages(s + 1)) for s in range(6)] == [False] * 4 + [True] * 2
    slow = Agent(
        _cfg(uid=0, n=2, outages=(LinkOutage(1, 0, 0.0, 0.45),), timing=sc.Timing(control_period_s=0.2))
    )
    assert [bool(slow.expected_peer_messages(s + 1)) for s in range(3)] == [False, False, True]


def _ending(dist_m, known=False, cells=None, steps=6):
    """Detect a fire at (150, 150) at step 0, then fly ``dist_m`` west of it without seeing it."""
    m = sc.MissionSettings(prior_fires="known" if known else "unknown")
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

    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1)))
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


def test_a_peer_perimeter_is_merged_with_the_peers_id_position_and_the_step_time():
    """The monitor of the fire gets the peer's map with the peer's id, its published position
    (which places it for the split: the angle about the map's centre) and the step's time t_{k+1}
    (its heard time); a map of a fire this UAV does not monitor, first in the inbox, is skipped
    and the next one still merged."""
    from fire_uav_agent.agent_types import PeerPerimeter

    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1)))
    for k in range(3):
        _fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0)
    fid = a.mission.target_fire_id
    mon = a.monitor.monitors[fid]
    summary = a.monitor.active.to_summary()
    other = PeerPerimeter(1, 1, 2, fid + 1, summary)
    good = PeerPerimeter(1, 2, 2, fid, summary)
    peer = _peer(1, 2, 230.0, 200.0)
    _fly(a, 3, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[peer, other, good])
    assert a.perimeter_received == 1
    p = mon._peers[1]
    cx, cy = mon.fire_map.center_x_m, mon.fire_map.center_y_m
    assert p.angle_rad == pytest.approx(math.atan2(200.0 - cy, 230.0 - cx), abs=1e-12)
    assert p.heard_s == pytest.approx(T * 4)


def test_a_fixed_wing_agent_is_built_on_its_airframe():
    """A fixed-wing fleet (ff_two_fires on coordinated_turn: small_uav): the EKF with two wind
    states (wind_estimation), starting at the start pose with no wind, over the configured
    terrain, with no floor under its height, the input noise of the airframe (airframe_model's
    input_noise_sigma over the physics period), the flown input on the airframe, the lakes long
    enough for its scoop run, and the separation's turn rate the airframe's at each speed (B&M
    Eq. 9.14, under the vehicle limit); FF's unicycle otherwise."""
    from fire_uav_agent.agent_config import config_from_scenario
    from fire_uav_agent.airframe_model import input_noise_sigma, usable_lakes
    from fire_uav_agent.estimation import StateEkf
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_agent.wind_estimation import WindStateEkf
    from fire_uav_common.scenario import load_scenario

    s = load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "coordinated_turn"})
    base = config_from_scenario(s, 1)
    assert base.airframe is not None
    # a model error (raises the speed and climb noise) and a pond too short for the scoop run
    af = dataclasses.replace(base.airframe, model_error_mps=0.5)
    cfg = dataclasses.replace(
        base, airframe=af, terrain=Terrain(base_m=5.0), lakes=(*base.lakes, Lake(60.0, 60.0, 2.0))
    )
    a = Agent(cfg)
    assert isinstance(a.ekf, WindStateEkf)
    np.testing.assert_array_equal(a.ekf.x, [*cfg.start_pose, 0.0, 0.0])
    assert a.ekf.terrain is cfg.terrain and a.ekf.cfg.alt_min_m == -math.inf
    want = input_noise_sigma(af, cfg.vehicle.process_noise_sigma, cfg.physics_period_s)
    assert tuple(a.ekf.cfg.sigma_nu) == tuple(want) and want[0] > cfg.vehicle.process_noise_sigma
    assert a.flown.af is af and a.guide.flown is a.flown
    assert a.lakes == usable_lakes(cfg.lakes, af)[0] and len(a.lakes) == len(cfg.lakes) - 1
    lim = cfg.limits
    for v in (lim.v_stall_mps, 0.5 * (lim.v_stall_mps + lim.v_max_mps), lim.v_max_mps):
        assert a.avoidance.turn_rate_at(v) == min(lim.omega_max_radps, af.turn_rate_max_radps(v))
    rotor = Agent(dataclasses.replace(cfg, airframe=None))
    assert isinstance(rotor.ekf, StateEkf) and rotor.ekf.cfg.alt_min_m == 0.0
    assert rotor.avoidance.turn_rate_at is None and rotor.flown.af is None


def test_the_flown_input_banks_with_the_water_aboard():
    """The EKF's flown input (airframe_model.FlownInput) is given the bundle's water: the stall
    bank limit acos((V_S(m) / v)^2) (lift = weight / cos(phi), B&M Eq. 9.14's coordinated turn)
    falls with the mass. small_uav (V_S 12 m/s full, 15 kg empty + 10 kg water) at 1.05 V_S,
    banked 20 deg and commanded a hard turn: full, its stall limit (24.9 deg at the start) holds
    the bank back; empty (V_S 12 sqrt(15 / 25) = 9.3 m/s, limit 45 deg) it banks farther."""
    from fire_uav_agent.agent_config import config_from_scenario
    from fire_uav_agent.airframe_model import OnboardState
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_common.scenario import load_scenario

    s = load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "coordinated_turn"})
    cfg = config_from_scenario(s, 1)
    af = cfg.airframe
    assert af is not None and (af.v_stall_mps, af.empty_mass_kg, af.water_capacity_kg) == (12.0, 15.0, 10.0)
    end = {}
    for water in (0.0, 10.0):
        a = Agent(cfg)
        a._last_vehicle = int(AIR)
        a.flown.state = OnboardState(1.05 * 12.0, 0.0, math.radians(20.0))
        a.last_command = np.array([af.v_min_mps, 0.0, 2.0])
        a.step(_bundle(0, water=water))
        end[water] = a.flown.state
    full = end[10.0]
    assert full.bank_rad <= math.acos((12.0 / full.airspeed_mps) ** 2)  # within its stall limit
    assert end[0.0].airspeed_mps == full.airspeed_mps and end[0.0].bank_rad > full.bank_rad + math.radians(
        2.0
    )


def test_the_fire_consensus_gets_the_control_period_and_the_sensors_position_noise():
    """FF III-C's fusion predicts over one control period T and weighs detections with the fire
    sensor's centre noise (scenario sensors.fire.position_sigma_m): both from the scenario, here
    off their defaults (T = 0.2 s, 3.5 m)."""
    sens = sc.Sensors(fire=sc.FireSensorSpec(position_sigma_m=3.5))
    a = Agent(_cfg(sensors=sens, timing=sc.Timing(control_period_s=0.2)))
    assert (a.fires.cfg.control_period_s, a.fires.cfg.position_sigma_m) == (0.2, 3.5)


def test_the_search_map_is_refreshed_only_by_an_airborne_sensor():
    """FF's staleness search counts a grid point seen when it lies within the fire sensor's range
    (70 m) of a flying UAV: a UAV on the ground sees nothing, one in the air at (150, 150) marks
    the points within 70 m of it at t_{k+1}. Before any step the own cell is the whole grid."""
    ground = Agent(_cfg())
    assert ground._cell.all() and ground._cell.size == ground.grid.points.shape[0]  # before any step
    _fly(ground, 0, 150.0, 150.0, vehicle=GROUND)
    assert np.all(ground.search.last_seen == -ground.search.horizon_s)
    air = Agent(_cfg())
    _fly(air, 0, 150.0, 150.0)
    d = np.hypot(air.grid.points[:, 0] - 150.0, air.grid.points[:, 1] - 150.0)
    assert np.all(air.search.last_seen[d < 69.0] == T) and np.all(air.search.last_seen[d > 71.0] < 0)


# --- wiring of the configuration into the stages ------------------------------------------------
def test_the_altimeter_measures_height_above_the_a_priori_terrain():
    """h(s) = z - E(x, y) (estimation doc): on ground 5 m above datum, a 24 m reading at prior z = 20
    (15 m above ground) moves z by K x 9."""
    a = Agent(
        _cfg(
            start_pose=(100.0, 50.0, 20.0, 0.0), terrain=Terrain(base_m=5.0), uid=1, takeoff_interval_s=100.0
        )
    )
    out = a.step(_bundle(0, GROUND, samples=Samples(alt=np.array([[0.05, 24.0]]))))
    assert out.state.s[2] == pytest.approx(20.0 + 9.0 * 2.25 / (2.25 + 2.25), abs=1e-9)


def test_the_prediction_runs_at_the_physics_period():
    """5 substeps of 0.02 s: P_zz grows by 5 x 0.02^2 x sigma_nu^2 (not 10 x 0.01^2)."""
    a = Agent(_cfg(timing=sc.Timing(physics_period_s=0.02)))
    a.ekf.s = np.array([100.0, 100.0, 30.0, 0.0])
    a._last_vehicle = int(AIR)
    out = a.step(_bundle(0, AIR))
    assert out.state.covariance[2, 2] == pytest.approx(1.5**2 + 5 * 0.02**2, abs=1e-12)


def test_the_tank_capacity_and_the_briefing_sigma_come_from_the_scenario():
    small = sc.Vehicle(water_capacity_kg=1000.0)
    a = _suppressor(vehicle=small)
    assert _fly(a, 0, 60.0, 150.0, water=600.0).state.objective == Objective.SUPPRESS  # > 50 % of 1000
    b = _suppressor()
    assert _fly(b, 0, 60.0, 150.0, water=600.0).state.objective == Objective.REFILL  # < 50 % of 2000
    # briefed centre sigma 5 m: 3 sigma = 15 m of uncertainty, negative range min(49, 70 - 15) = 49 m;
    # with the default 10 m it is 70 - 30 = 40 m, so 45 m away the fire is not ended
    for sigma, ended in ((5.0, True), (10.0, False)):
        c = _suppressor(mission=sc.MissionSettings(prior_position_sigma_m=sigma))
        outs = [_fly(c, k, 105.0, 150.0) for k in range(6)]
        assert (not outs[-1].fires[0].active) is ended


def test_the_sweep_before_landing_comes_from_the_scenario():
    """mission.post_search_s (ff_two_fires_tanker: 150 s) sets the agent's sweep; unset, the 45 s."""
    assert Agent(_cfg()).mission.cfg.post_search_s == 45.0
    assert Agent(_cfg(mission=sc.MissionSettings(post_search_s=150.0))).mission.cfg.post_search_s == 150.0


def test_the_sweeps_bound_comes_from_the_scenario_and_its_end_from_the_staleness_map(monkeypatch):
    """mission.post_search_max_s sets the agent's bound (unset: 300 s); the mission sees the
    staleness map's oldest sighting once the fires are out (``swept_since_s``), and none (inf:
    not read) while one burns."""
    assert Agent(_cfg()).mission.cfg.post_search_max_s == 300.0
    a = Agent(_cfg(mission=sc.MissionSettings(post_search_max_s=500.0)))
    assert a.mission.cfg.post_search_max_s == 500.0
    seen = []
    step = a.mission.step
    monkeypatch.setattr(a.mission, "step", lambda v: (seen.append(v), step(v))[1])
    _fly(a, 0, 110.0, 150.0)
    a.search.last_seen[:] = 12.5  # covered all over at 12.5 s
    a.search.last_seen[7] = 11.0  # but one point last at 11 s
    monkeypatch.setattr(a.fires, "all_out", lambda: True)
    _fly(a, 1, 400.0, 400.0)  # far from point 7: it keeps its 11 s
    monkeypatch.setattr(a.fires, "all_out", lambda: False)
    _fly(a, 2, 400.0, 400.0)
    assert [(v.all_out, v.swept_since_s) for v in seen[1:]] == [(True, 11.0), (False, math.inf)]


def test_the_negative_range_follows_the_sensor_range():
    """Fire sensor range 60 m: 'no fire here' range = min(50, 0.7 x 60) = 42 m."""
    sens = sc.Sensors(fire=sc.FireSensorSpec(range_m=60.0))
    for dist, ended in ((41.0, True), (43.0, False)):
        a = Agent(_cfg(sensors=sens))
        _fly(a, 0, 110.0, 150.0, fires=[(0.05, 150.0, 150.0, 5.0)])
        outs = [_fly(a, k, 150.0 - dist, 150.0) for k in range(1, 7)]
        assert (not outs[-1].fires[0].active) is ended


def test_the_monitor_planner_takes_the_configured_speed_alpha_and_kind():
    from fire_perimeter_monitor.planner import CirclingMonitor, ImportanceMonitor

    a = Agent(_cfg(mission=sc.MissionSettings(monitors_per_fire=1), monitor_alpha=0.4, monitor_circling=True))
    assert a.monitor.cfg.speed_mps == pytest.approx(44.7 + 5.0)  # v_stall + monitor_speed_margin
    assert a.monitor.cfg.alpha == 0.4 and a.monitor.cfg.circling
    assert a.monitor.uav_id == 0 and a.planners[int(Objective.MONITOR)] is a.monitor
    assert isinstance(a.monitor.monitor_for(7, (1.0, 1.0), 10.0), CirclingMonitor)
    b = Agent(_cfg(mission=sc.MissionSettings(monitors_per_fire=1)))
    assert isinstance(b.monitor.monitor_for(7, (1.0, 1.0), 10.0), ImportanceMonitor)
    assert Agent(_cfg()).monitor is None and Agent(_cfg()).monitor_assigner is None  # no PM


def test_a_given_monitor_assigner_and_planner_are_used():
    views = []

    def assigner(view):
        views.append(view)
        return view.fires[0].fire_id

    p = _Waypoint((200.0, 250.0))
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1)),
              planners={int(Objective.MONITOR): p}, monitor_assigner=assigner)  # fmt: skip
    assert a.monitor is None and a.monitor_assigner is assigner
    out = _fly(a, 0, 60.0, 145.0)
    assert out.state.objective == Objective.MONITOR and out.state.centroid_xy == (200.0, 250.0)
    assert p.views[0].target_fire_id == out.state.target_fire_id == views[0].fires[0].fire_id
    b = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),)), monitor_assigner=assigner)  # without PM too
    assert _fly(b, 0, 60.0, 145.0).state.objective == Objective.MONITOR


def test_raster_layers_follow_the_altimeter_range_and_the_release_radius_the_footprint():
    """Altimeter range 60 m: top 60 - 2 x 2 = 56 m, 14 m apart, 4 layers (56 - 3 x 14 = 14 m above the
    7.5 m floor): uav 0 at 14 m."""
    a = Agent(_cfg(sensors=sc.Sensors(altimeter=sc.AltimeterSpec(max_range_m=60.0))))
    assert _fly(a, 0, 50.0, 50.0, z=14.0, cells=_block(), cell_size=10.0).command[1] == pytest.approx(
        0.0, abs=1e-9
    )
    # footprint 10 m: release within 8 m, where only the centre cell burns (< 3 cells): no drop
    b = _suppressor(fire=(145.0, 145.0, 15.0), drop_radius_m=10.0)
    _fly(b, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    assert _fly(b, 1, 145.0, 145.0, cells=_block(), cell_size=10.0).payload_requests == ()


def test_over_a_raster_fire_the_release_rule_replaces_the_distance_rule():
    """At (137, 145) heading east the aim point is within 14 m, but one step ahead more cells burn
    within the release radius (7 > 6): wait for the peak (a head attack: its aim is the front)."""
    a = _suppressor(fire=(145.0, 145.0, 15.0), mission=sc.MissionSettings(tactic="head"))
    _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    out = _fly(a, 1, 137.0, 145.0, cells=_block(), cell_size=10.0)
    assert math.hypot(out.state.centroid_xy[0] - 137.0, out.state.centroid_xy[1] - 145.0) <= 14.0
    assert out.payload_requests == ()


def test_the_grounded_uav_publishes_its_start_point_as_its_centroid():
    a = Agent(_cfg(uid=1, start_pose=(12.0, 34.0, 0.0, 0.0), takeoff_interval_s=100.0))
    out = a.step(_bundle(0, GROUND))
    assert out.state.centroid_xy == (12.0, 34.0) and a.fronts_received == 0 and a.perimeter_received == 0


def test_known_fires_mode_without_a_fire_suppresses_nothing_and_searches():
    """Search disabled (known fires): the objective is SUPPRESS with no target; the search planner flies."""
    p = _Waypoint((250.0, 150.0))
    a = Agent(_cfg(mission=sc.MissionSettings(prior_fires="known")), planners={int(Objective.SEARCH): p})
    out = _fly(a, 0, 60.0, 150.0)
    assert out.state.objective == Objective.SUPPRESS and out.state.target_fire_id == -1
    assert p.views == []  # SUPPRESS without a fire flies the staleness search, not the SEARCH planner
    assert out.state.centroid_xy == _fly(Agent(_cfg()), 0, 60.0, 150.0).state.centroid_xy


def test_tiny_masses_still_pick_the_largest_and_the_nearest_uses_both_coordinates():
    # both fires outside the area, their tails in the cell with masses far below 1: the larger wins
    a = Agent(_cfg(prior_fires=((-40.0, 150.0, 8.0), (420.0, 150.0, 30.0))))
    out = _fly(a, 0, 100.0, 150.0)
    assert out.state.target_fire_id == max(out.fires, key=lambda f: f.x_m).fire_id
    # no mass at all: the nearest in the plane (1150 m vs 1185 m; by x alone the other one)
    b = Agent(_cfg(prior_fires=((-900.0, 150.0, 1.0), (1300.0, 700.0, 1.0))))
    out = _fly(b, 0, 250.0, 150.0, z=700.0)
    assert out.state.target_fire_id == min(out.fires, key=lambda f: f.x_m).fire_id
    c = Agent(_cfg(prior_fires=((-900.0, -150.0, 1.0), (1300.0, 400.0, 1.0))))  # 1188 m vs 1079 m
    out = _fly(c, 0, 250.0, 150.0)
    assert out.state.target_fire_id == max(out.fires, key=lambda f: f.x_m).fire_id


def test_the_planner_sees_the_fleet_as_the_agent_does():
    p = _Waypoint((250.0, 150.0))
    a = Agent(_cfg(n=3), planners={int(Objective.SEARCH): p})
    _fly(a, 0, 60.0, 150.0)
    peers = [
        _peer(1, 0, 200.0, 150.0, obj=Objective.SUPPRESS, fire=7),
        _peer(2, 0, 10.0, 10.0, obj=Objective.GROUNDED),
    ]
    _fly(a, 1, 61.0, 150.0, inbox=peers, cells=_block(), cell_size=10.0)
    v = p.views[-1]
    assert v.grid is a.grid and np.array_equal(v.cell_mask, a._cell) and not v.cell_mask.all()
    assert v.peers_xy == {1: (200.0, 150.0)}  # the grounded peer does not fly
    assert v.peer_roles == {1: (int(Objective.SUPPRESS), 7), 2: (int(Objective.GROUNDED), -1)}
    assert v.own_published_xy == (60.0, 150.0) and v.own_objective == int(Objective.SEARCH)
    assert v.own_target_fire_id == -1 and v.fires == ()
    assert v.cell_size_m == 10.0 and v.cells is not None and np.array_equal(v.cells[0], _block()[0])
    assert v.s[0] == 61.0 and v.t_s == pytest.approx(0.2)
    _place(a, 61.0, 150.0, 0.0)
    a.step(_bundle(2, GROUND, cells=_block(), cell_size=10.0))
    assert len(p.views) == 2  # on the ground the planner is not asked (takeoff first)


def test_two_steps_in_flight_then_a_touchdown_without_help():
    """The step-(k-1) command is predicted as applied in flight, and not after touching down."""
    a = Agent(_cfg(), planners={int(Objective.SEARCH): _Waypoint((290.0, 100.0))})
    a.ekf.s = np.array([60.0, 100.0, 30.0, 0.0])
    o0 = a.step(_bundle(0, AIR))
    o1 = a.step(_bundle(1, AIR))
    assert o1.state.s[0] == pytest.approx(o0.state.s[0] + o0.command[0] * T, abs=1e-6)
    o2 = a.step(_bundle(2, LANDED))
    assert o2.state.s[0] == o1.state.s[0]


def test_lost_peer_messages_are_counted_in_the_published_state():
    a = Agent(_cfg(loss_probability=1.0, takeoff_interval_s=100.0))
    a.last_step = 3
    out = a.step(_bundle(4, GROUND), [_peer(1, 3, 10.0, 10.0), PeerFires(1, 4, 3, ())])
    assert (out.state.packets_lost, out.state.packets_received) == (2, 0)


# --- landing details --------------------------------------------------------------------------
def _lander(home=(100.0, 100.0), **kw):
    a = Agent(_cfg(start_pose=(*home, 0.0, 0.0), **kw))
    a.mission.objective = Objective.LAND
    return a


def test_homes_on_the_area_border_are_in_the_area():
    """Home on the border: inside (<=), so beyond 120 m the Eq. 15 density is flown; its centroid
    lies inside the area, off the home point (the density is cut at the border)."""
    for home in ((0.0, 0.0), (300.0, 300.0)):
        a = _lander(home)
        out = _fly(a, 0, 150.0, 150.0)
        c = out.state.centroid_xy
        assert c != home and 0.0 < c[0] < 300.0 and 0.0 < c[1] < 300.0


def test_the_approach_starts_strictly_inside_the_radius():
    """At exactly 120 m: still the density target and no slow-down; home near the border (cut density)."""
    a = _lander((100.0, 5.0))
    out = _fly(a, 0, 220.0, 5.0, yaw=math.pi)
    assert out.command[0] > 44.7 and out.state.centroid_xy != (100.0, 5.0)


def test_the_landing_profile_and_touchdown_scale_with_the_landing_height():
    """landing_height 2 m: lowest approach 0.5 x 2 = 1 m, touch down below 0.8 x 2 = 1.6 m."""
    a = _lander(vehicle=sc.Vehicle(landing_height_m=2.0))
    assert _fly(a, 0, 130.0, 100.0, z=1.0, yaw=math.pi).command[1] == pytest.approx(0.0, abs=1e-9)
    assert _fly(a, 1, 101.0, 100.0, z=1.5, yaw=math.pi).command == (0.0, -0.5, 0.0)


def test_touchdown_boundaries_and_height_above_sloped_ground():
    a = _lander()
    assert _fly(a, 0, 100.0, 102.5, z=0.5, yaw=-math.pi / 2).command == (0.0, -0.5, 0.0)  # 2.5 m: in
    assert _fly(a, 1, 101.0, 100.0, z=0.8, yaw=math.pi).command != (0.0, -0.5, 0.0)  # 0.8 m AGL: not below
    # ground E = 10 + 0.5 x: 61 m at x = 102, so z = 61.5 is 0.5 m above it
    b = _lander(terrain=Terrain(base_m=10.0, slope_x=0.5))
    assert _fly(b, 0, 102.0, 100.0, z=61.5, yaw=math.pi).command == (0.0, -0.5, 0.0)


def test_the_go_around_uses_the_true_bearing_to_home():
    home = (100.0, 60.0)
    a = _lander(home)
    bearing = math.atan2(60.0 - 70.0, 100.0 - 110.0)  # from (110, 70): -3 pi / 4
    out = _fly(a, 0, 110.0, 70.0, z=5.0, yaw=bearing + 0.3)  # lined up: steer in
    assert out.command[2] != 0.0
    out = _fly(a, 1, 110.0, 70.0, z=5.0, yaw=bearing + 0.7)  # not lined up, 14 m out: straight on
    assert out.command[2] == 0.0 and out.state.centroid_xy == home
    out = _fly(a, 2, 125.0, 60.0, z=5.0, yaw=0.0)  # exactly 25 m out: not "within"
    assert out.command[2] != 0.0


def test_a_going_around_uav_avoids_on_its_own_heading():
    """The go-around flies straight on; a peer ahead on that line is avoided around the current
    heading (not the bearing to home behind it, which is clear)."""
    a = _lander()
    _fly(a, 0, 120.0, 100.0, z=5.0)
    out = _fly(a, 1, 120.0, 100.0, z=5.0, inbox=[_peer(1, 0, 160.0, 108.0, z=5.0, cx=math.nan, cy=math.nan)])
    want = _nearest_clear((120.0, 100.0), 0.0, 44.7, (160.0, 108.0), (0.0, 0.0))
    assert out.command[2] != 0.0 and _heading_after(out, 0.0) == pytest.approx(max(-1.0, min(1.0, want)))


def test_a_home_outside_the_own_cell_is_flown_at_directly():
    """No density mass in the cell (a flying peer between): the fallback is the home point itself."""
    a = _lander((20.0, 150.0), area_m=(0.0, 1000.0, 0.0, 300.0))  # 480 m = 48 sigma: exactly 0
    _fly(a, 0, 900.0, 150.0, yaw=math.pi)
    out = _fly(a, 1, 900.0, 150.0, yaw=math.pi, inbox=[_peer(1, 0, 500.0, 150.0)])
    assert out.state.centroid_xy == (20.0, 150.0)


def test_a_zero_density_plan_holds_the_own_position():
    a = Agent(_cfg())
    a.planners[int(Objective.SEARCH)] = _Waypoint(density=np.zeros(a.grid.points.shape[0]))
    assert _fly(a, 0, 80.0, 120.0).state.centroid_xy == (80.0, 120.0)


# --- helpers of the stages --------------------------------------------------------------------
def test_the_markers_border_is_every_cell_point_with_a_neighbour_outside_the_cell():
    """Brute force over the grid: a cell point is on the border if one of its 4 neighbours inside
    the grid is not in the cell (the cell in the lower left, in the upper right, below a horizontal
    boundary)."""
    for own, peer in (
        ((20.0, 15.0), (75.0, 50.0)),
        ((75.0, 50.0), (20.0, 15.0)),
        ((50.0, 10.0), (50.0, 50.0)),
    ):
        a = Agent(_cfg(area_m=(0.0, 100.0, 0.0, 60.0)))
        _fly(a, 0, *own)
        out = _fly(a, 1, *own, inbox=[_peer(1, 0, *peer)], markers=True)
        ny, nx = a.grid.shape
        m = a._cell.reshape(ny, nx)
        want = set()
        for i in range(ny):
            for j in range(nx):
                if not m[i, j]:
                    continue
                nbs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))]
                if any(0 <= p < ny and 0 <= q < nx and not m[p, q] for p, q in nbs):
                    want.add((float(a.grid.xs[j]), float(a.grid.ys[i])))
        got = {(float(x), float(y)) for x, y in out.markers.cell_boundary_xy}
        assert got == want and len(want) > 5


def test_refill_goes_to_the_nearest_lake_in_the_plane():
    for lakes, uav, nearest in (
        ((Lake(250.0, 150.0, 20.0), Lake(60.0, 280.0, 20.0)), (50.0, 150.0), 1),  # 200 m vs 130 m
        ((Lake(150.0, 160.0, 20.0), Lake(60.0, 40.0, 20.0)), (50.0, 150.0), 0),  # 100.5 m vs 110.5 m
    ):
        a = _suppressor(lakes=lakes)
        c = _fly(a, 0, *uav, water=0.0).state.centroid_xy
        d = [math.hypot(c[0] - lk.x_m, c[1] - lk.y_m) for lk in lakes]
        assert d[nearest] < d[1 - nearest], (lakes, c)


def test_peer_perimeters_and_fronts_from_uav_0_count_and_one_lost_one_does_not_stop_the_rest():
    from fire_uav_agent.agent_types import PeerPerimeter
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront
    from fire_uav_common.scenario import LinkOutage

    a = Agent(_cfg(uid=2, n=4, outages=(LinkOutage(1, 2, 0.0, 100.0),)))
    msgs = [PeerPerimeter(1, 1, 4, 7, {}), PeerPerimeter(1, 2, 4, 8, {}), PeerPerimeter(0, 1, 4, 7, {}),
            PeerFront(0, 1, 4, FrontCells.empty(), 10.0), _peer(3, 4, 10.0, 10.0)]  # fmt: skip
    a.last_step = 4
    got = a._link(5, msgs, [])
    assert [p.uav_id for p in got] == [0] and [f.uav_id for f in a.raster.peer_fronts] == [0]
    assert a.perimeter_lost == 2 and 3 in a.link.alive_states()


def test_peer_fire_pictures_outside_the_step_window_are_refused():
    a = Agent(_cfg(takeoff_interval_s=100.0))
    a.last_step = 19
    fe = FireEntry((1 << 16) | 1, True, 200.0, 200.0, 10.0, last_measurement_s=0.3)
    out = a.step(_bundle(20, GROUND), [PeerFires(1, 5, 9, (fe,))])
    assert out.fires == () and out.state.packets_rejected == 1


def test_assign_monitor_returns_minus_one_unless_this_uav_is_the_nearest_eligible():
    from fire_uav_agent.coverage import make_grid
    from fire_uav_agent.planning import PlannerView

    grid = make_grid(*AREA, 5.0)
    fire = (FireEntry(5, True, 300.0, 300.0, 30.0),)

    def view(own_xy, peers_xy, roles):
        return PlannerView(0.0, 0, np.array([*own_xy, 30.0, 0.0]), grid, np.ones(grid.points.shape[0], bool),
                           peers_xy, fire, peer_roles=roles, own_published_xy=own_xy,
                           own_objective=int(Objective.SEARCH))  # fmt: skip

    a = Agent(_cfg(n=3, mission=sc.MissionSettings(monitors_per_fire=1)))
    # own 70.7 m from the fire, peer 1 at (150, 300) 150 m: this UAV monitors it
    assert a.assign_monitor(view((250.0, 250.0), {1: (150.0, 300.0)}, {1: (int(Objective.SEARCH), -1)})) == 5
    # peer 1 nearer (10 m): it monitors, this UAV does not
    assert a.assign_monitor(view((250.0, 250.0), {1: (290.0, 300.0)}, {1: (int(Objective.SEARCH), -1)})) == -1
    # the nearer peer is grounded (not eligible): this UAV; a peer without a known role counts as SEARCH
    assert (
        a.assign_monitor(view((250.0, 250.0), {1: (290.0, 300.0)}, {1: (int(Objective.GROUNDED), -1)})) == 5
    )
    assert a.assign_monitor(view((250.0, 250.0), {1: (290.0, 300.0)}, {})) == -1
    assert a.roles == {5: (1,)}


def test_the_fastest_front_wins_whichever_peer_reports_it_and_own_monitors_come_first():
    a = _suppressor(fire=(150.0, 150.0, 20.0), n=3)
    fid = _fly(a, 0, 50.0, 150.0).state.target_fire_id
    fast = FireEntry(fid, True, 150.0, 150.0, 20.0, front_x_m=160.0, front_y_m=180.0, max_spread_rate_mps=1.5)
    slow = FireEntry(fid, True, 150.0, 150.0, 20.0, front_x_m=120.0, front_y_m=150.0, max_spread_rate_mps=0.5)
    _fly(a, 1, 50.0, 150.0, inbox=[PeerFires(1, 1, 0, (fast,)), PeerFires(2, 1, 0, (slow,))])
    assert a._fronts[fid] == (160.0, 180.0, 1.5)


def test_a_monitor_without_a_front_of_its_own_takes_the_peers():
    a = Agent(_cfg(n=3, prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1)))
    outs = [_fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0) for k in range(4)]
    fid = outs[-1].state.target_fire_id
    assert outs[-1].state.objective == Objective.MONITOR and a.monitor.front(fid) is None  # no Eq. 1 yet
    peer = FireEntry(fid, True, 145.0, 145.0, 15.0, front_x_m=1.0, front_y_m=2.0, max_spread_rate_mps=0.7)
    _fly(a, 4, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[PeerFires(1, 1, 3, (peer,))])
    assert a._fronts == {fid: (1.0, 2.0, 0.7)}


def test_a_monitor_flies_at_its_fire():
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1)))
    outs = [_fly(a, k, 60.0, 145.0) for k in range(3)]
    assert outs[-1].state.objective == Objective.MONITOR
    assert outs[-1].state.centroid_xy == (145.0, 145.0)  # no cells yet: "go and see" the fire


def test_without_a_search_planner_the_staleness_search_is_the_search_planner():
    from fire_uav_agent.agent_core import StalenessSearch

    a = Agent(_cfg())
    assert a.planners == {int(Objective.SEARCH): a.search} and isinstance(a.search, StalenessSearch)
    p = _Waypoint((1.0, 2.0))
    assert Agent(_cfg(), planners={int(Objective.SEARCH): p}).planners[int(Objective.SEARCH)] is p


def test_a_one_cell_front_is_still_a_front_to_aim_at():
    """A lone burning cell in unburned ground is the whole active front: aim at it, not at the track."""
    a = _suppressor(fire=(150.0, 150.0, 15.0))
    out = _fly(a, 0, 60.0, 145.0, cells=_block(cx=125.0, cy=125.0, burning=0, ring=1), cell_size=10.0)
    assert out.state.centroid_xy == (125.0, 125.0)


def test_without_a_front_the_distance_rule_does_not_release_over_a_raster_fire():
    """Raster fire with every cell burnt out: the release verdict is 'no' (tactics), even right over
    the track's centre, where the FF distance rule would drop."""
    burnt = _block()
    burnt = (burnt[0], burnt[1], np.where(burnt[2] == 1, 2, 0))
    a = _suppressor(fire=(145.0, 145.0, 15.0))
    _fly(a, 0, 60.0, 145.0, cells=burnt, cell_size=10.0)
    assert _fly(a, 1, 145.0, 145.0, cells=burnt, cell_size=10.0).payload_requests == ()


def test_with_no_front_in_the_own_cell_the_aim_is_the_front_cell_nearest_the_uav():
    """The peer at (140, 145) owns the whole fire (bisector at x = 100, the Eq. 13' kernel reaches 30 m
    from the ring at x >= 135): no mass in the own cell, so the aim is the front cell nearest this UAV
    (a head attack; ``auto`` flanks a fire whose head has no rate yet)."""
    head = sc.MissionSettings(tactic="head")
    a = _suppressor(fire=(145.0, 145.0, 15.0), mission=head)
    _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
    out = _fly(a, 1, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[_peer(1, 0, 140.0, 145.0)])
    assert out.state.centroid_xy == (135.0, 145.0)
    b = _suppressor(fire=(145.0, 145.0, 15.0), mission=head)
    _fly(b, 0, 60.0, 170.0, cells=_block(), cell_size=10.0)
    out = _fly(b, 1, 60.0, 170.0, cells=_block(), cell_size=10.0, inbox=[_peer(1, 0, 140.0, 170.0)])
    assert out.state.centroid_xy == (135.0, 155.0)


def test_a_uav_still_on_the_ground_when_the_fleet_lands_stays_there():
    """Its takeoff slot (0.3 s) comes after the fleet agreed to land: it never climbs out (was: a
    takeoff command, v_stall and a climb, just to land again) and reports LANDED."""
    a = Agent(_cfg(uid=1, takeoff_interval_s=0.3))
    outs = [
        a.step(_bundle(k, GROUND), [_peer(0, k - 1, 50.0, 50.0, obj=Objective.LAND)] if k else [])
        for k in range(4)
    ]
    assert all(o.command == (0.0, 0.0, 0.0) for o in outs)
    objectives = [Objective(o.state.objective) for o in outs]
    assert objectives[0] == Objective.GROUNDED and objectives[-1] == Objective.LANDED
    assert set(objectives) == {Objective.GROUNDED, Objective.LANDED}


def test_the_release_rule_looks_one_step_ahead_at_the_speed_flown():
    """At (141, 145) heading east: 7 burning cells within 16 m. One step ahead at 100 m/s (10 m) only
    6-7 are: release; at stall speed (4.47 m ahead) 9 are: wait."""
    for speed, drop in ((100.0, True), (44.7, False)):
        a = _suppressor(fire=(145.0, 145.0, 15.0))
        _fly(a, 0, 60.0, 145.0, cells=_block(), cell_size=10.0)
        a.ekf.s = np.array([141.0 - speed * T, 145.0, 30.0, 0.0])
        a._last_vehicle = int(AIR)
        a.last_command = np.array([speed, 0.0, 0.0])
        out = a.step(_bundle(1, cells=_block(), cell_size=10.0))
        assert out.state.s[0] == pytest.approx(141.0, abs=1e-9)
        assert bool(out.payload_requests) is drop


def test_a_uav_on_the_ground_observes_nothing_for_the_search():
    """The staleness search counts only what airborne UAVs saw: two agents that spent step 0 on the
    ground at different places then plan the same search target."""
    outs = []
    for xy in ((50.0, 150.0), (150.0, 40.0)):
        a = Agent(_cfg())
        _place(a, *xy, 0.0)
        a.step(_bundle(0, GROUND))
        outs.append(_fly(a, 1, 250.0, 150.0))
    assert outs[0].state.centroid_xy == outs[1].state.centroid_xy


# --- more edges -------------------------------------------------------------------------------
def test_separation_wants_the_bearing_of_an_off_axis_waypoint():
    p0, v = (150.0, 190.0), (-20.0, -80.0)
    q = (p0[0] + 3 * T * v[0], p0[1] + 3 * T * v[1])
    wp = (290.0, 160.0)
    a, outs = _crossing(0, 1, p0, v, wp=wp)
    want = math.atan2(wp[1] - OWN[1], wp[0] - OWN[0])
    head = _nearest_clear(OWN, want, 100.0, q, v)
    assert head != want and _heading_after(outs[4], 0.0) == pytest.approx(max(-1.0, min(1.0, head)), abs=1e-9)


@pytest.mark.parametrize("jump", [(0.0, -2000.0), (40.0, 0.0)])
def test_a_report_implying_more_than_one_and_a_half_v_max_is_a_jump(jump):
    """2000 m north, or 40 m more in 2 steps (an apparent 200 m/s > 150 m/s): no velocity."""
    p0, v = (150.0 + jump[0], 190.0 + jump[1]), (-20.0, -80.0)
    p2 = (150.0 + 2 * T * v[0], 190.0 + 2 * T * v[1])
    a, outs = _crossing(0, 1, p0, v, p2=p2)
    want = _nearest_clear(OWN, 0.0, 100.0, p2, (0.0, 0.0))
    assert _heading_after(outs[4], 0.0) == pytest.approx(want, abs=1e-9)


def test_a_touchdown_command_still_in_the_air_is_flown_at_stall_speed():
    """The world clamps an airborne vehicle's speed to v_stall: the EKF predicts that, not a stop."""
    a = _lander()
    assert _fly(a, 0, 101.0, 100.0, z=0.5, yaw=0.0).command == (0.0, -0.5, 0.0)
    out = a.step(_bundle(1, AIR))  # not yet down
    assert out.state.s[0] == pytest.approx(101.0 + 4.47, abs=1e-9)


def test_peer_fronts_and_perimeters_count_one_each():
    from fire_uav_agent.agent_types import PeerPerimeter
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.front_consensus import PeerFront
    from fire_uav_common.scenario import LinkOutage

    a = Agent(_cfg(n=3))
    _fly(a, 0, 50.0, 50.0, cells=_block(), cell_size=10.0)
    f1 = FrontCells(np.array([255.0]), np.array([255.0]), np.array([1]), np.array([0.05]), np.array([0.3]))
    f2 = FrontCells(np.array([265.0]), np.array([255.0]), np.array([1]), np.array([0.05]), np.array([0.3]))
    _fly(
        a,
        1,
        50.0,
        50.0,
        cells=_block(),
        cell_size=10.0,
        inbox=[PeerFront(1, 1, 0, f1, 10.0), PeerFront(2, 1, 0, f2, 10.0)],
    )
    assert a.fronts_received == 2
    m = Agent(_cfg(n=4, prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1),
                   outages=(LinkOutage(3, 0, 0.0, 9.0),)))  # fmt: skip
    for k in range(3):
        _fly(m, k, 60.0, 145.0, cells=_block(), cell_size=10.0)
    fid = m.mission.target_fire_id
    summ = m.monitor.active.to_summary()
    _fly(m, 3, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=[PeerPerimeter(3, 1, 2, fid, summ)])
    assert m.perimeter_lost == 1  # in an outage
    inbox = [
        PeerPerimeter(1, 1, 3, fid, summ),
        PeerPerimeter(2, 1, 3, fid, summ),
        PeerPerimeter(2, 2, 3, fid, {}),
    ]
    _fly(m, 4, 60.0, 145.0, cells=_block(), cell_size=10.0, inbox=inbox)
    assert (m.perimeter_received, m.perimeter_lost) == (2, 1)  # the malformed one counts nowhere


def test_a_briefed_fire_is_ended_only_within_the_sensor_range_minus_its_uncertainty():
    """Briefing sigma 10 m: 30 m of uncertainty; fire sensor 60 m: negative range 60 - 30 = 30 m."""
    sens = sc.Sensors(fire=sc.FireSensorSpec(range_m=60.0))
    for dist, ended in ((28.0, True), (33.0, False)):
        a = _suppressor(sensors=sens)
        outs = [_fly(a, k, 150.0 - dist, 150.0) for k in range(6)]
        assert (not outs[-1].fires[0].active) is ended


def test_layers_follow_the_collision_radius_and_the_avoiders_band():
    """Step max(R, separation.vertical_m) + 2 x 2 m below 36 m, above 7.5 m. Collision radius 12 m:
    16 m apart, 36 and 20 m; avoider's band 6 m (R 3 m): 10 m apart, 36, 26, 16 m."""
    a = Agent(_cfg(vehicle=sc.Vehicle(collision_radius_m=12.0)))
    assert _fly(a, 0, 50.0, 50.0, z=20.0, cells=_block(), cell_size=10.0).command[1] == pytest.approx(
        0.0, abs=1e-9
    )
    b = Agent(_cfg(separation=SeparationConfig(vertical_m=6.0)))
    assert _fly(b, 0, 50.0, 50.0, z=16.0, cells=_block(), cell_size=10.0).command[1] == pytest.approx(
        0.0, abs=1e-9
    )
    assert Agent(_cfg()).roles == {}


def test_step_publishes_no_markers_by_default():
    a = Agent(_cfg(takeoff_interval_s=100.0, uid=1))
    assert a.step(_bundle(0, GROUND)).markers is None


def test_a_direct_run_goes_to_the_target_fire_and_eq13_sums_every_fire():
    fires = ((100.0, 150.0, 20.0), (200.0, 150.0, 20.0))
    a = Agent(_cfg(prior_fires=fires))
    out = _fly(a, 0, 150.0, 60.0, yaw=math.pi / 2)
    assert out.state.centroid_xy == pytest.approx((150.0, 150.0), abs=1e-6)  # between the two
    tgt = next(f for f in out.fires if f.fire_id == out.state.target_fire_id)
    a.mission._attack_since_s = 0.1
    out = _fly(a, 1, 150.0, 60.0, yaw=math.pi / 2)
    assert out.direct and out.state.centroid_xy == (tgt.x_m, tgt.y_m)


def test_the_refill_approach_radius_is_lake_radius_plus_150_m():
    lake = Lake(250.0, 150.0, 40.0)  # 20 + 150 = 170 m
    for xy, slow in (
        ((85.0, 150.0), True),
        ((80.0, 150.0), False),
        ((50.0, 150.0), False),
        ((100.0, 270.0), False),
    ):
        a = _suppressor(lakes=(lake,))
        out = _fly(a, 0, *xy, z=7.5, water=0.0)
        assert (out.command[0] == pytest.approx(47.7)) is slow, xy
    assert out.state.centroid_xy[0] < 250.0  # the Eq. 14 density cut at the area's edge pulls it in


def test_touchdown_needs_both_coordinates_near_home_and_the_layer_hold_compares_heights():
    a = _lander()
    assert _fly(a, 0, 100.0, 110.0, z=0.5, yaw=-math.pi / 2).command != (0.0, -0.5, 0.0)  # 10 m north
    b = Agent(_cfg(uid=1, start_pose=(100.0, 100.0, 0.0, 0.0)))
    b.mission.objective = Objective.LAND
    _fly(b, 0, 130.0, 100.0, z=5.0, yaw=math.pi)
    held = _fly(
        b, 1, 130.0, 100.0, z=5.0, yaw=math.pi, inbox=[_peer(0, 0, 125.0, 100.0, z=4.0, obj=Objective.LAND)]
    )
    assert held.command[1] > 0  # 4 m < 5 m: the peer is below, hold the layer


def test_a_going_around_uav_without_avoidance_just_flies_straight():
    a = _lander(avoidance=False)
    _fly(a, 0, 120.0, 100.0, z=5.0)
    out = _fly(a, 1, 120.0, 100.0, z=5.0, inbox=[_peer(1, 0, 160.0, 108.0, z=5.0, cx=math.nan, cy=math.nan)])
    assert out.command[2] == 0.0


def test_the_note_of_a_drop_uses_the_release_position():
    """Fire at (150, 60): released at (137, 60), 13 m away, the extent halves (see the drop test)."""
    seen = [(0.05, 150.0, 60.0, 10.0)]
    a, b = _suppressor(fire=(150.0, 60.0, 10.0)), _suppressor(fire=(150.0, 60.0, 10.0))
    for ag in (a, b):
        _fly(ag, 0, 134.0, 60.0, fires=seen)
    seen = [(0.15, 150.0, 60.0, 10.0)]
    out, kept = _fly(a, 1, 137.0, 60.0, fires=seen), _fly(b, 1, 134.0, 60.0, fires=seen)
    assert out.payload_requests and not kept.payload_requests
    assert out.fires[0].extent_m == pytest.approx(kept.fires[0].extent_m / 2, rel=1e-9)


def test_perimeters_every_step_when_asked():
    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),), mission=sc.MissionSettings(monitors_per_fire=1),
                   perimeter_every_steps=1))  # fmt: skip
    outs = [_fly(a, k, 60.0, 145.0, cells=_block(), cell_size=10.0) for k in range(6)]
    assert outs[4].perimeter is not None and outs[5].perimeter is not None


def test_a_given_assigner_sees_no_cells_on_the_ground_and_the_own_target_of_the_last_step():
    views = []

    def assigner(view):
        views.append(view)
        return view.fires[0].fire_id

    a = Agent(_cfg(prior_fires=((145.0, 145.0, 15.0),)), monitor_assigner=assigner)
    _place(a, 60.0, 145.0, 0.0)
    a.step(_bundle(0, GROUND, cells=_block(), cell_size=10.0))
    out = _fly(a, 1, 60.0, 145.0, cells=_block(), cell_size=10.0)
    assert views[0].cells is None and views[1].cells is not None
    assert views[1].own_target_fire_id == out.state.target_fire_id and views[0].own_target_fire_id == -1


def test_tiny_raster_cells_still_make_a_front_picture():
    a = Agent(_cfg(area_m=(0.0, 40.0, 0.0, 40.0)))
    _fly(a, 0, 20.0, 20.0, cells=_block(cx=20.25, cy=20.25, cs=0.5), cell_size=0.5)
    assert a.front is not None and a.front.cfg.cell_size_m == 0.5
