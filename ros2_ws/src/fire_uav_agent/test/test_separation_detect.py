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
from fire_uav_agent.separation import PeerAvoidance, SeparationConfig, detect_range_m
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.codecs.uav_state import PeerState
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
    rngs = [np.random.default_rng(0), np.random.default_rng(1)]
    start = [FlightState(0.0, 0.0, 30.0, 0.0), FlightState(gap_m, offset_m, 30.0, math.pi)]
    states = [model.launch(s, Command(v, 0.0, 0.0)) for s in start]
    targets = [(gap_m + 10_000.0, 0.0), (-10_000.0, offset_m)]

    def rate(v_mps: float) -> float:  # as agent_core gives the avoider its airframe's turn rate
        return min(lim.omega_max_radps, TANKER.turn_rate_max_radps(v_mps))

    avoiders = [
        PeerAvoidance(i, T, sep, lim.v_stall_mps, lim.v_max_mps, lim.omega_max_radps, rate) for i in (0, 1)
    ]
    dmin = math.inf
    for k in range(int(40.0 / T)):
        pub = [
            PeerState(i, k, k, s.x_m, s.y_m, s.z_m, s.yaw_rad, int(Objective.SEARCH), -1, 0.0, *targets[i])
            for i, s in enumerate(states)
        ]
        cmds = []
        for i, s in enumerate(states):
            own = np.array([s.x_m, s.y_m, s.z_m, s.yaw_rad])
            v_c, vz_c, om = avoiders[i].command(own, (v, 0.0, 0.0), targets[i], {1 - i: pub[1 - i]}, k)
            cmds.append(Command(v_c, vz_c, max(-lim.omega_max_radps, min(lim.omega_max_radps, om))))
        for _ in range(SUBSTEPS):
            states = model.step(states, cmds, T / SUBSTEPS, rngs)
            a, b = states
            dmin = min(dmin, math.dist((a.x_m, a.y_m, a.z_m), (b.x_m, b.y_m, b.z_m)))
    return dmin


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
