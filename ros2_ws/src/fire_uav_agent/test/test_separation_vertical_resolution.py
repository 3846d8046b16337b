"""A fixed-wing's vertical resolution (``separation.vertical_sense``, ``SeparationConfig.vertical_resolution``)
against the world's own ``coordinated_turn`` airframe flying what the agents' avoider commands.

The case it was made for (docs/airframes.md, "The raster scenarios on each airframe";
grass_brush_hill, small_uav on coordinated_turn, seed 3, 126.1 s): UAV 1, a monitor descending at
4 m/s at 15.6 m/s, and UAV 4, a suppressor climbing at 4.5 m/s to its layer, crossing some 100
deg apart; 50 m apart and 14 m apart in height 2 s before, they passed 5.1 m apart. The heading
filter judged the height difference now and saw the conflict at 10 m, 37 m apart, where a 16 m/s
aircraft turning at its 45 deg bank (a 26 m turn radius) cannot clear 20 m. Here two small_uav
UAVs on that crossing, each behind the agent's last stage (``PeerAvoidance.command``, the right
of way to the lower id), each seeing the other's published position every control step, each
steering at a point beyond the crossing and at a height the other's path crosses at the crossing.
"""

import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.separation import PeerAvoidance, SeparationConfig, vertical_sense
from fire_uav_agent.testing.avoider_pair import closest_approach_flown
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective
from fire_uav_common.scenario import load_scenario
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel

T = 0.1  # [s] control period
SUBSTEPS = 10  # the world's 100 Hz physics
K_Z = 1.0  # [1/s] height gain of the test's own pilots (a first-order climb toward the height)


@pytest.fixture(scope="module")
def cfg():
    """UAV 0's config of grass_brush_hill on coordinated_turn (small_uav; the avoider as the agents get it)."""
    sc = load_scenario(
        scenario_path("grass_brush_hill"), overrides={"uavs.vehicle_model": "coordinated_turn"}
    )
    return config_from_scenario(sc, 0, uav_count=5, seed=3)


def _cross(cfg, sep: SeparationConfig, angle_deg: float, vz_mps: float = 4.0, t_meet_s: float = 8.0) -> float:
    """UAV 0 (right of way) descending at ``vz_mps`` toward a height 5 m below the crossing, UAV 1
    climbing at ``vz_mps`` toward one 5 m above it; both reach the crossing's height when they
    reach the crossing point, ``t_meet_s`` after the start, ``angle_deg`` apart in course, UAV 0
    at 15.6 m/s (the monitor's speed), UAV 1 at 20 m/s. The closest 3-D approach [m] of the truth."""
    af = cfg.airframe
    lim = cfg.limits
    model = CoordinatedTurnModel(af, 0.0)
    z0 = 50.0
    speeds = (15.6, 20.0)
    courses = (0.0, math.radians(180.0 - angle_deg))  # UAV 1 comes from the far side, angle_deg apart
    start, targets, heights = [], [], []
    for i, (v, c) in enumerate(zip(speeds, courses, strict=True)):
        d = v * t_meet_s
        sign = -1.0 if i == 0 else 1.0  # UAV 0 descends, UAV 1 climbs
        x, y = -d * math.cos(c), -d * math.sin(c)
        start.append(FlightState(x, y, z0 - sign * vz_mps * t_meet_s, c))
        targets.append((3.0 * d * math.cos(c), 3.0 * d * math.sin(c)))
        heights.append(z0 + sign * 5.0)
    states = [model.launch(s, Command(v, 0.0, 0.0)) for s, v in zip(start, speeds, strict=True)]
    states = [
        FlightState(s.x_m, s.y_m, s.z_m, s.yaw_rad, s.airspeed_mps, (-1.0 if i == 0 else 1.0) * vz_mps)
        for i, s in enumerate(states)
    ]

    def rate(v_mps: float) -> float:  # as agent_core gives the avoider its airframe's turn rate
        return min(lim.omega_max_radps, af.turn_rate_max_radps(v_mps))

    avoiders = [
        PeerAvoidance(i, T, sep, lim.v_stall_mps, lim.v_max_mps, lim.omega_max_radps, rate) for i in (0, 1)
    ]

    def wanted(i: int, s: FlightState) -> tuple[float, float, float]:
        want = math.atan2(targets[i][1] - s.y_m, targets[i][0] - s.x_m)
        om = math.remainder(want - s.yaw_rad, math.tau) / T
        return speeds[i], max(-vz_mps, min(vz_mps, K_Z * (heights[i] - s.z_m))), om

    steps = int(3.0 * t_meet_s / T)
    return closest_approach_flown(
        model, states, targets, wanted, avoiders, lim.omega_max_radps, steps, Objective.MONITOR, T, SUBSTEPS
    )


@pytest.mark.parametrize("angle_deg", [80.0, 90.0, 100.0, 110.0])
def test_a_descent_crossing_a_climb_keeps_ten_metres(cfg, angle_deg):
    assert _cross(cfg, cfg.separation, angle_deg) >= 10.0


@pytest.mark.parametrize("angle_deg", [80.0, 90.0, 100.0, 110.0])
def test_with_the_heading_alone_the_same_pair_passes_within_ten_metres(cfg, angle_deg):
    """The truth behind the test above: the heading filter alone (the code before) on the same crossing."""
    old = SeparationConfig(
        vertical_rates=cfg.separation.vertical_rates,
        detect_m=cfg.separation.detect_m,
        vertical_resolution=False,
    )
    assert _cross(cfg, old, angle_deg) < 10.0


def test_the_senses_of_a_pair_are_complementary():
    """Two UAVs 60 m apart head on at 20 m/s, 8 m apart in height: the higher stops descending, the lower stops
    climbing; each judged from its own side (the same two heights)."""
    sep = SeparationConfig(vertical_resolution=True)
    hi = vertical_sense(
        (0.0, 0.0, 58.0), 20.0, 0.0, 0.0, np.array([[60.0, 0.0, 50.0, -20.0, 0.0, 0.0]]), 3.0, sep
    )
    lo = vertical_sense(
        (60.0, 0.0, 50.0), 20.0, math.pi, 0.0, np.array([[0.0, 0.0, 58.0, 20.0, 0.0, 0.0]]), 3.0, sep
    )
    assert (hi, lo) == (1, -1)


def test_a_pair_whose_courses_stay_apart_is_left_alone():
    """Parallel courses 40 m apart (beyond radius + margin, 30 m) at one height: no resolution."""
    sep = SeparationConfig(vertical_resolution=True)
    peer = np.array([[0.0, 40.0, 50.0, 20.0, 0.0, 0.0]])
    assert vertical_sense((0.0, 0.0, 50.0), 20.0, 0.0, 0.0, peer, 3.0, sep) == 0


# --- vertical_sense on hand-made geometry: own UAV at the origin, heading east at 20 m/s, level;
# radius 20 m + margin 10 m = 30 m horizontally, over a 3 s horizon
_SEP = SeparationConfig(vertical_resolution=True, radius_m=20.0, release_margin_m=10.0, vertical_m=10.0)


def _sense(*peers: tuple[float, float, float, float, float, float], cfg: SeparationConfig = _SEP) -> int:
    return vertical_sense((0.0, 0.0, 50.0), 20.0, 0.0, 0.0, np.array(peers, dtype=float), 3.0, cfg)


@pytest.mark.parametrize(
    ("peer", "sense"),
    [
        ((60.0, 0.0, 45.0, -20.0, 0.0, 0.0), 1),  # head on, 5 m below: do not descend
        ((60.0, 0.0, 55.0, -20.0, 0.0, 0.0), -1),  # head on, 5 m above: do not climb
        ((60.0, 0.0, 50.0, -20.0, 0.0, 0.0), -1),  # level with us: counted as above (dz >= 0)
        ((60.0, 0.0, 50.5, -20.0, 0.0, 0.0), -1),  # half a metre above is above
        ((60.0, 0.0, 60.0, -20.0, 0.0, 0.0), -1),  # exactly vertical_m above: still a threat
        ((60.0, 0.0, 60.5, -20.0, 0.0, 0.0), 0),  # beyond vertical_m, no vertical closure
        ((60.0, 0.0, 70.0, -20.0, 0.0, -5.0), -1),  # 20 m above, descending 5 m/s: within 10 m at 2 s
        # a parallel course (no closure): the closest approach is the lateral offset
        ((0.0, 30.0, 50.0, 20.0, 0.0, 0.0), 0),  # exactly radius + margin: clear (strictly less counts)
        ((0.0, 29.5, 50.0, 20.0, 0.0, 0.0), -1),  # inside radius + margin, not inside radius - margin
        ((0.0, 15.0, 50.0, 20.0, 0.0, 0.0), -1),
        # head on but 300 m away: the gap closes at 40 m/s, 180 m left after the 3 s horizon
        ((300.0, 0.0, 50.0, -20.0, 0.0, 0.0), 0),
    ],
)
def test_vertical_sense_on_hand_geometry(peer, sense):
    assert _sense(peer) == sense


def test_vertical_sense_reads_every_row_of_the_peers():
    clear = (300.0, 0.0, 50.0, -20.0, 0.0, 0.0)
    below = (60.0, 0.0, 45.0, -20.0, 0.0, 0.0)
    above = (60.0, 0.0, 55.0, -20.0, 0.0, 0.0)
    assert _sense(clear, below) == 1
    assert _sense(below, clear, clear) == 1
    assert _sense(below, above) == 0  # threats on both sides: none


def test_vertical_sense_judges_the_height_over_the_whole_horizon_on_a_fine_band():
    """A band of 0.2 m: a peer 0.5 m above and climbing away (1.5 m at the horizon's end) is no
    threat; one 0.5 m above and descending through our height (-1.0 m at the end) is."""
    fine = SeparationConfig(vertical_resolution=True, radius_m=20.0, release_margin_m=10.0, vertical_m=0.2)
    assert _sense((60.0, 0.0, 50.5, -20.0, 0.0, 1.0 / 3.0), cfg=fine) == 0
    assert _sense((60.0, 0.0, 50.5, -20.0, 0.0, -0.5), cfg=fine) == -1
    half = SeparationConfig(vertical_resolution=True, radius_m=20.0, release_margin_m=10.0, vertical_m=0.5)
    assert _sense((60.0, 0.0, 50.9, -20.0, 0.0, -0.6), cfg=half) == -1  # crosses our height at 1.5 s


# --- PeerAvoidance.command's vertical part: UAV 1 at (0, 0), heading east at 20 m/s; a still
# peer 0 ahead; the turn rate 0.5 rad/s gives a look-ahead of max(2 s, (pi / 2) / 0.5) = 3.14 s
def _avoider() -> PeerAvoidance:
    return PeerAvoidance(1, T, _SEP, 15.0, 30.0, 1.0, lambda v: 0.5)


def _peer(x: float, z: float, step: int = 0) -> dict:
    return {0: PeerState(0, step, step, x, 0.0, z, math.pi, int(Objective.MONITOR), -1, 0.0, -1000.0, 0.0)}


def _vz(av: PeerAvoidance, z: float, vz: float, peers: dict, step: int = 0, agl_m: float = math.inf) -> float:
    s = np.array([0.0, 0.0, z, 0.0])
    return av.command(s, (20.0, vz, 0.0), (1000.0, 0.0), peers, step, agl_m=agl_m)[1]


def test_the_command_stops_a_descent_over_a_peer_below_and_a_climb_under_one_above():
    assert _vz(_avoider(), 50.0, -3.0, _peer(40.0, 45.0)) == 0.0  # do not descend
    assert _vz(_avoider(), 50.0, 2.0, _peer(40.0, 45.0)) == 2.0  # a climb stays
    assert _vz(_avoider(), 50.0, 3.0, _peer(40.0, 55.0)) == 0.0  # do not climb
    assert _vz(_avoider(), 50.0, -2.0, _peer(40.0, 55.0)) == -2.0  # a descent stays


def test_no_threat_leaves_the_vertical_command_alone():
    far = _peer(40.0, 75.0)  # 25 m above, level: beyond the 10 m band
    assert _vz(_avoider(), 50.0, -3.0, far) == -3.0
    assert _vz(_avoider(), 50.0, 2.0, far) == 2.0


def test_near_the_ground_a_climb_is_never_stopped():
    """Within vertical_m of the terrain the lower UAV keeps its climb (module doc)."""
    assert _vz(_avoider(), 50.0, 3.0, _peer(40.0, 55.0), agl_m=8.0) == 3.0
    assert _vz(_avoider(), 50.0, 3.0, _peer(40.0, 55.0), agl_m=12.0) == 0.0


def test_the_look_ahead_is_the_quarter_turn_of_the_airframe():
    """A peer 90 m ahead is 30 m away after 3.0 s: inside the 3.14 s look-ahead, outside FF's 2 s."""
    assert _vz(_avoider(), 50.0, 3.0, _peer(90.0, 55.0)) == 0.0


def test_the_own_vertical_speed_is_measured_from_the_heights_of_successive_steps():
    """A peer 15 m below, level: beyond the band now. Descending at 5 m/s (50.0 m at step 0, 49.5
    m at step 1) we close 15.7 m over the 3.14 s look-ahead: a threat, do not descend. Asked
    twice at one step, the rate is the one measured last; a first call assumes level flight (a
    peer 12 m above is no threat then)."""
    av = _avoider()
    assert _vz(av, 50.0, -5.0, _peer(40.0, 35.0, 0), 0) == -5.0  # level assumed: 15 m, no threat
    assert _vz(av, 49.5, -5.0, _peer(40.0, 35.0, 1), 1) == 0.0  # -5 m/s measured: a threat
    assert _vz(av, 49.5, -5.0, _peer(40.0, 35.0, 1), 1) == 0.0  # the same step again: the same rate
    assert _vz(_avoider(), 50.0, 3.0, _peer(40.0, 62.0)) == 3.0  # first call: 12 m above, level


def test_the_command_resolves_where_it_is_and_counts_the_steps_it_changed():
    """Own UAV at x = 100 m, the peer 40 m ahead of it (at x = 0 the same peer is 140 m away and
    no threat); exactly vertical_m above the terrain a climb is kept (the rule is strictly
    above); climbing at 5 m/s (50.0 then 50.5 m) toward a peer 15 m above, level, we close 15.7 m
    over the look-ahead: do not climb. steps_resolved counts the steps whose v_z changed."""
    av = _avoider()
    s = np.array([100.0, 0.0, 50.0, 0.0])
    assert av.command(s, (20.0, 3.0, 0.0), (1000.0, 0.0), _peer(140.0, 55.0, 0), 0)[1] == 0.0
    assert av.steps_resolved == 1
    s = np.array([100.0, 0.0, 50.0, 0.0])
    assert av.command(s, (20.0, 3.0, 0.0), (1000.0, 0.0), _peer(140.0, 55.0, 1), 1, agl_m=10.0)[1] == 3.0
    assert av.steps_resolved == 1
    assert av.command(s, (20.0, -3.0, 0.0), (1000.0, 0.0), _peer(140.0, 45.0, 2), 2)[1] == 0.0
    assert av.steps_resolved == 2
    climb = _avoider()
    assert _vz(climb, 50.0, 5.0, _peer(40.0, 65.0, 0), 0) == 5.0  # level assumed: 15 m, no threat
    assert _vz(climb, 50.5, 5.0, _peer(40.0, 65.0, 1), 1) == 0.0  # +5 m/s measured: a threat
