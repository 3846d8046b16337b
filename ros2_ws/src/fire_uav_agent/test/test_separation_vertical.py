"""The avoider's vertical band over the horizon (``SeparationConfig.vertical_rates``), against
kinematic truth: unicycles flown step by step in 3-D, heights straight at their vertical speeds.

The case it was made for (grass_running, 6 UAVs, auto, seed 2 of the tactics study, 565.8 s):
one UAV climbing out of a missed landing at 15 m/s, a right-of-way peer descending to land at
15 m/s, 26.5 m apart in height 0.7 s before they passed 8.8 m apart (28.5 m at 0.9 s); the band
judged on the height difference now saw no conflict until they were 11 m apart, too late to turn.
"""

import math

import numpy as np
import pytest
from fire_uav_agent.errors import InputError
from fire_uav_agent.separation import Avoider, SeparationConfig, avoid_heading

V = 44.7  # [m/s] FF stall speed, the landing speed
T = 0.1  # [s] control period
PREDICTED = SeparationConfig(vertical_rates=True)  # mission.vertical_band: predicted (opt-in)


def _fly(cfg: SeparationConfig, dist_m: float, vz_mps: float, late_m: float, steps: int = 50) -> float:
    """UAV 0 (the right of way) and UAV 1 head-on at V, ``dist_m`` apart: UAV 0 descending and
    flying on, UAV 1 climbing and yielding to it (FF II-B's 10 rad/s, the peer's last two states
    seen one step late, as PeerAvoidance sees them). Heights: at ``vz_mps`` each, still
    ``late_m`` apart when they meet (their heights cross just after). The closest 3-D approach [m]."""
    t_meet = dist_m / (2 * V)
    p = np.array([[dist_m, 0.0], [0.0, 0.0]])
    z = np.array([2.0 + 2 * vz_mps * t_meet + late_m, 2.0])
    vz = np.array([-vz_mps, vz_mps])
    th = np.array([math.pi, 0.0])
    prev_p, prev_z = p.copy(), z.copy()
    avoider = Avoider(cfg)
    dmin = math.inf
    for _ in range(steps):
        vel, vzs = (p - prev_p) / T, (z - prev_z) / T
        lead = p[0] + vel[0] * T
        row = np.array([[lead[0], lead[1], z[0] + vzs[0] * T, vel[0, 0], vel[0, 1], vzs[0]]])
        want, _, _ = avoider.step((p[1, 0], p[1, 1], z[1]), V, 0.0, row, np.array([True]), own_vz_mps=vz[1])
        prev_p, prev_z = p.copy(), z.copy()
        th[1] += max(-1.0, min(1.0, math.remainder(want - th[1], math.tau)))
        p = p + V * T * np.column_stack([np.cos(th), np.sin(th)])
        z = z + vz * T
        dmin = min(dmin, float(math.dist((*p[0], z[0]), (*p[1], z[1]))))
    return dmin


@pytest.mark.parametrize(
    ("dist_m", "vz_mps", "late_m"), [(100.0, 15.0, 8.0), (60.0, 15.0, 8.0), (120.0, 10.0, 8.0)]
)
def test_a_climb_into_a_descending_right_of_way_peer_keeps_ten_metres(dist_m, vz_mps, late_m):
    assert _fly(PREDICTED, dist_m, vz_mps, late_m) >= 10.0


def test_judged_on_the_height_difference_now_the_same_pair_passes_within_ten_metres():
    """The default rule on the same geometry (the truth behind the test above: it fails without the
    heights predicted)."""
    assert _fly(SeparationConfig(), 100.0, 15.0, 8.0) < 10.0


def test_a_pair_that_stays_apart_in_height_is_left_alone():
    """28 m apart and closing at 2 x 2 m/s: 20 m apart at the end of the 2 s horizon (> 10 m)."""
    cfg = PREDICTED
    peer = np.array([[80.0, 0.0, 32.0, -V, 0.0, -2.0]])
    assert avoid_heading((0.0, 0.0, 4.0), V, 0.0, peer, cfg, own_vz_mps=2.0) == (0.0, False, True)


@pytest.mark.parametrize(
    ("dz_m", "closing_mps"),
    [(15.0, 2.6), (15.0, 2.4), (5.0, -20.0), (15.0, 40.0), (25.0, 7.4), (25.0, 7.6), (-15.0, -2.6)],
)
def test_the_band_holds_over_the_whole_horizon(dz_m, closing_mps):
    """A peer ``dz_m`` above, the gap closing at ``closing_mps``: a conflict iff the gap is within
    10 m at some t in [0, 2 s] (horizon_s); the truth by sampling the two vertical tracks."""
    cfg = PREDICTED
    t = np.linspace(0.0, cfg.horizon_s, 20001)
    conflict = bool(np.min(np.abs(dz_m - np.sign(dz_m) * closing_mps * t)) <= cfg.vertical_m)
    peer = np.array([[60.0, 0.0, 30.0 + dz_m, -V, 0.0, -np.sign(dz_m) * closing_mps]])
    assert avoid_heading((0.0, 0.0, 30.0), V, 0.0, peer, cfg)[1] is conflict


def test_rows_must_have_five_or_six_columns():
    with pytest.raises(InputError, match="5 or 6 columns"):
        avoid_heading((0.0, 0.0, 30.0), V, 0.0, np.zeros((1, 4)), SeparationConfig())


@pytest.mark.parametrize(
    ("model", "band", "predicted"),
    [
        ("ff_paper", None, True),  # auto: FF's unicycle flies the v_z it commands
        ("coordinated_turn", None, False),  # auto: a fixed-wing does not (module doc)
        ("jsbsim", None, False),
        ("ff_paper", "now", False),
        ("coordinated_turn", "predicted", True),
    ],
)
def test_the_scenario_chooses_the_band(model, band, predicted):
    from fire_uav_agent.agent_config import config_from_scenario
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_common.scenario import load_scenario

    over = {"uavs.vehicle_model": model, **({} if band is None else {"mission.vertical_band": band})}
    sc = load_scenario(scenario_path("ff_two_fires"), overrides=over)
    assert config_from_scenario(sc, 0, uav_count=2, seed=1).separation.vertical_rates is predicted


def test_an_unknown_band_is_refused_with_the_field_named():
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_common.scenario import ScenarioError, load_scenario

    with pytest.raises(
        ScenarioError,
        match=r"mission\.vertical_band: must be one of \['auto', 'now', 'predicted'\], got 'on'",
    ):
        load_scenario(scenario_path("ff_two_fires"), overrides={"mission.vertical_band": "on"})
