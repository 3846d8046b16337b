"""Paired arms: within one seed every arm of a study starts from the same fire.

The fire models draw no random numbers (fire_study.variation's module doc), the seed's fire
variation depends on the scenario and the seed only (test_study_spec), and every random stream
of the world is keyed by (seed, purpose, UAV id): so up to the fleet's first action, a world
with 3 UAVs and head attack and one with 10 UAVs and flank attack hold the same fire cell for
cell, and UAV k's sensors draw the same noise in both. Checked here on the worlds themselves.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from fire_study.spec import load_study, mission_overrides
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario
from fire_world_sim.world import World

STUDY = {
    "name": "pairing",
    "scenarios": ["grass_running"],
    "tactics": ["head", "flank", "auto"],
    "uavs": [3, 10],
    "seeds": [4],
    "fire_variation": {"wind_speed_sd_mps": 0.3, "wind_direction_sd_deg": 10, "ignition_sd_m": 20},
}


def _world(study, uavs: int, tactic: str, seed: int) -> World:
    ov = mission_overrides(study, "grass_running", "default", uavs, tactic, seed)
    return World(load_scenario(scenario_path("grass_running"), overrides=ov), seed, uavs)


def _fire_after(w: World, steps: int) -> np.ndarray:
    for _ in range(steps):
        w.step({})  # no commands: the fleet stays on the ground, as before dispatch
    return np.asarray(w.fires.t_ign).copy()


@pytest.mark.slow  # three pre-burnt raster worlds: ~35 s on a loaded machine
def test_every_arm_of_a_seed_holds_the_same_fire_and_noise_until_the_fleet_acts(tmp_path) -> None:
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(STUDY))
    study = load_study(p)
    a, b = _world(study, 3, "head", 4), _world(study, 10, "flank", 4)
    c = _world(study, 3, "auto", 5)  # another seed: another fire
    fa, fb, fc = _fire_after(a, 20), _fire_after(b, 20), _fire_after(c, 20)
    assert np.isfinite(fa).sum() > 100  # the pre-burnt fire is there
    np.testing.assert_array_equal(fa, fb)
    assert not np.array_equal(np.isfinite(fa), np.isfinite(fc))
    for k in range(3):  # UAV k's sensor and process-noise streams do not depend on the fleet size
        assert a.sensors[k].rng_gps.normal() == b.sensors[k].rng_gps.normal()
        assert a.sensors[k].rng_fire.random() == b.sensors[k].rng_fire.random()
        assert a.vehicles[k].rng.normal() == b.vehicles[k].rng.normal()
