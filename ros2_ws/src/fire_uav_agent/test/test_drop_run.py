"""A pattern drop's run: low and slow near the aim point (fire_uav_agent.guidance.Guide._drop_run).

Truth: the world's own ground-pattern model (fire_world_sim.drop_pattern, (P1)-(P3)) and the
fire services' coverage level for grass (FBFM 1: CL 1, 0.41 L/m^2): a tanker's drop from its run
reaches it, the same drop from the layer and speed it cruises at does not (grass_running_tanker:
no cell put out from the 22 and 36 m layers, docs/airframes.md).
"""

from __future__ import annotations

import math

import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario
from fire_world_sim.drop_pattern import L_PER_M2_PER_CL, Release, coverage_level, pattern_of

GRASS_LPM2 = coverage_level(1) * L_PER_M2_PER_CL  # FBFM 1 (short grass): CL 1


def _tanker(uid: int, **over):
    sc = load_scenario(scenario_path("grass_running_tanker"), overrides=over)
    return sc, Agent(config_from_scenario(sc, uid, uav_count=5, seed=1, loss_probability=0.0))


def _peak(sc, height_m: float, speed_mps: float) -> float:
    af = sc.uavs.airframe
    r = Release(0.0, 0.0, 0.0, speed_mps, height_m, af.water_capacity_kg, af.drop_flow_lps)
    return pattern_of(r).peak_lpm2


@pytest.mark.parametrize("uid", [1, 2])  # the 22 and 36 m layers
def test_the_run_puts_grass_out_where_the_cruise_does_not(uid):
    sc, a = _tanker(uid)
    g = a.guide
    aim = (3000.0, 3000.0)
    run = g._drop_run((aim[0] + 0.5 * g.drop_run_m, aim[1]), aim)
    assert run is not None
    height, speed = run
    assert _peak(sc, height, speed) >= GRASS_LPM2
    layer = g.raster.tactic.layer_height_m(uid)
    assert height < layer
    assert _peak(sc, layer, sc.uavs.airframe.v_max_mps) < GRASS_LPM2


def test_the_run_begins_where_the_tanker_can_still_slow_and_descend():
    """From its top speed to the run's speed at its deceleration limit, (v0^2 - v1^2) / (2 a)
    (B&M Eq. 9.18), plus the release radius; the tanker's descent from 36 to 8 m is shorter."""
    sc, a = _tanker(2)
    g = a.guide
    af = sc.uavs.airframe
    v_run = g._drop_run((0.0, 0.0), (1.0, 0.0))[1]
    slow = (af.v_max_mps**2 - v_run**2) / (2.0 * af.accel_max_mps2)
    assert g.drop_run_m == pytest.approx(g.raster.tactic.release_radius_m + slow)
    assert g._drop_run((0.0, 0.0), (g.drop_run_m * 1.0001, 0.0)) is None
    assert g._drop_run((0.0, 0.0), (g.drop_run_m * 0.9999, 0.0)) is not None


def test_no_run_where_the_drop_is_a_disc():
    for name in ("grass_running", "ff_two_fires"):
        sc = load_scenario(scenario_path(name))
        a = Agent(config_from_scenario(sc, 0, uav_count=2, seed=1, loss_probability=0.0))
        assert a.guide.drop_run_m == 0.0 and a.guide._drop_run((0.0, 0.0), (1.0, 0.0)) is None
    _, a = _tanker(0, **{"fires.drop_model": "disc"})
    assert a.guide.drop_run_m == 0.0
    assert math.isfinite(_tanker(0)[1].guide.drop_run_m)
