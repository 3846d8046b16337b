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
