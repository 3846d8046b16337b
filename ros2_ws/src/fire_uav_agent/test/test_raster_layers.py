"""Raster altitude layers (tactics.TacticConfig.layer_height_m): two layers cannot collide, nor
come within FF's 10 m.

Issue [suppression]: adjacent layers were 3.5 m apart against a 3 m collision radius, so a
height error of 0.25 m each put two crossing UAVs in collision. Until session 18 layers 8 m
apart passed at 8.7-9.5 m over worcester_vt's fire, against FF's reported >= 10 m. Truth: the
world's collision model (two airborne vehicles closer than ``collision_radius_m`` in 3-D both
crash), FF's closest approach (>= 10 m), the avoider's vertical band (peers farther apart in
height are not its business) and the altimeter's range (no reading above ``max_range_m``).
"""

import itertools

import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.tactics import TRACKING_ERROR_M, TacticConfig, raster_layers
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario


def _agents(n: int):
    sc = load_scenario(scenario_path("grass_brush_hill"))
    return sc, [Agent(config_from_scenario(sc, i, uav_count=n, seed=1)) for i in range(n)]


@pytest.mark.parametrize("n", [3, 6, 10])
def test_uavs_on_different_layers_cannot_come_within_the_collision_radius_nor_10_m(n):
    """Each UAV holding its layer within the tracking error e: the worst vertical gap of two UAVs on
    different layers (step - 2 e) still exceeds the collision radius and FF's 10 m, and the
    avoider's vertical band, whatever their tracks."""
    sc, agents = _agents(n)
    r = sc.vehicle.collision_radius_m
    h = [a.tactic.layer_height_m(a.cfg.uav_id) for a in agents]
    for i, j in itertools.combinations(range(n), 2):
        if h[i] != h[j]:
            gap = abs(h[i] - h[j]) - 2 * TRACKING_ERROR_M
            assert gap > r and gap >= 10.0, (i, j, h[i], h[j])
            assert gap >= agents[0].cfg.separation.vertical_m
    assert len(set(h)) == min(n, agents[0].tactic.layers)  # every layer used once the fleet has them


def test_layers_stay_inside_the_altimeter_range_and_above_the_refill_height():
    sc, agents = _agents(6)
    top = sc.sensors.altimeter.max_range_m
    floor = 0.5 * sc.vehicle.refill_height_m  # the fleet's refill approach height (guidance)
    for a in agents:
        z = a.tactic.layer_height_m(a.cfg.uav_id)
        assert floor <= z <= top - 2 * TRACKING_ERROR_M, z  # the altimeter sees the whole band


def test_as_many_layers_as_fit():
    """The defaults: R 3 m, separation 10 m, e 2 m -> 14 m apart; top 40 - 2 x 2 = 36 m; floor 7.5 m
    -> 3 layers at 36, 22, 8 m (a fourth at -6 m would be below the floor). For collisions alone
    (R + 2 e = 7 m): 5 layers, 36 down to 8 m."""
    n, step, top = raster_layers(3.0, 40.0, 7.5, 2.0, 10.0)
    assert (n, step, top) == (3, 14.0, 36.0)
    assert top - (n - 1) * step >= 7.5 > top - n * step
    assert raster_layers(3.0, 40.0, 7.5, 2.0) == (5, 7.0, 36.0)
    assert raster_layers(0.0, 40.0, 7.5, 1.0)[0] == 6  # collisions off: the cap of 6
    with pytest.raises(ValueError, match="raster layers: the altimeter range minus twice the tracking error"):
        raster_layers(3.0, 8.0, 7.5, 2.0)


def test_layers_that_do_not_fit_above_the_ground_are_refused():
    with pytest.raises(ValueError, match="tactic layers do not fit above the ground"):
        TacticConfig(layers=6, layer_step_m=8.0, layer_top_m=38.0)
    with pytest.raises(ValueError, match="layer_step_m must be >= 0"):
        TacticConfig(layer_step_m=-1.0)
