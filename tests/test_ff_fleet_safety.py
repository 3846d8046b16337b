"""The FF fleet in process (real World, real Agents, lockstep harness): the safety figures of the
issue on the FF scenario, measured by the world (collisions, separation) and the summary."""

import pytest
from fire_mission.inprocess import run_inprocess


@pytest.mark.slow
@pytest.mark.parametrize("uavs, seed", [(8, 3), (14, 2)])
def test_known_fires_fleet_keeps_apart_lands_at_home_and_hits(uavs, seed):
    d = run_inprocess("ff_two_fires", uavs=uavs, seed=seed, overrides={"mission.prior_fires": "known"})
    assert d["outcome"] == "complete", d["detail"]
    assert d["collisions"] == 0 and d["crashes"] == []
    assert d["min_separation_m"] >= 10.0
    assert len(d["landing_error_m"]) == uavs and max(d["landing_error_m"].values()) <= 5.0
    assert d["hit_rate"] >= 0.9
    assert d["drops_per_fire"] == {"0": 5, "1": 4}  # sigma 50 -> 1.56 m: 5 hits; 20 -> 1.25 m: 4
