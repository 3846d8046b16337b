"""The coverage levels the agents read from the fuel map (fire_uav_common.drop_coverage.
coverage_levels_of, which decides whether a drop run is flown) against the world's own: the raster
fire's fuel grid, as it lays it (a landscape's fuel layer north-up, or the fuel model and its
patches), and the coverage it needs to put each cell out (the world's required_coverage_lpm2, the
drop guides' Table 1). Every cell of the grid, at its centre; lakes left out (the world burns no
fuel there; the agents know the lakes as lakes)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from fire_uav_common.drop_coverage import L_PER_M2_PER_CL, coverage_levels_of, required_coverage_lpm2
from fire_uav_common.scenario import load_scenario
from fire_world_sim.fires import make_fire_model

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


@pytest.mark.parametrize("name", ["worcester_vt", "grass_brush_hill", "grass_running"])
def test_the_agents_levels_are_the_worlds_at_every_cell(name):
    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    fire = make_fire_model(sc.fires, sc.terrain, sc.lakes)
    levels = coverage_levels_of(sc.fires.raster)
    assert levels is not None
    xx, yy = np.meshgrid(fire.xc, fire.yc)
    lake = np.zeros(xx.shape, dtype=bool)
    for lk in sc.lakes:
        lake |= (xx - lk.x_m) ** 2 + (yy - lk.y_m) ** 2 <= (lk.diameter_m / 2 + fire.cs) ** 2
    world_lpm2 = required_coverage_lpm2(fire.fuel)
    assert (~lake).sum() > 0.9 * lake.size
    # at each cell's centre, and just inside its south-west corner (the cell's edges as the world's)
    for dx in (0.0, 0.01 - fire.cs / 2):
        agent_lpm2 = (
            np.array([[levels.at(x + dx, y + dx) for x in fire.xc] for y in fire.yc]) * L_PER_M2_PER_CL
        )
        np.testing.assert_array_equal(agent_lpm2[~lake], world_lpm2[~lake])
    if name == "worcester_vt":  # a real landscape: more than one fuel, and unburnable cells
        assert len(np.unique(world_lpm2[~lake])) >= 3 and np.isinf(world_lpm2[~lake]).any()
        assert levels.at(-1.0, -1.0) == np.inf  # off the landscape: no fuel known, no run flown
        assert levels.grid is not None and not levels.grid.flags.writeable  # shared by every agent
