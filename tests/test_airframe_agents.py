"""The agents plan within the envelope the world flies: their limits come from the same
``uavs.airframe`` preset as the world's coordinated-turn model (docs/airframes.md)."""

from __future__ import annotations

import math

import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import AIRFRAMES, load_scenario
from fire_uav_common.scenario.airframes import G_MPS2


@pytest.mark.parametrize("preset", sorted(AIRFRAMES))
def test_agent_limits_are_the_presets_envelope(preset: str) -> None:
    # FF's 90 m lake is too short for the tanker's 702 m scoop run (the scenario is refused): a
    # ten times faster scoop (70 m) lets the tanker's flight envelope load on FF's map
    airframe = {"preset": preset, "refill_rate_kgps": 10 * AIRFRAMES[preset].refill_rate_kgps}
    sc = load_scenario(
        scenario_path("ff_two_fires"),
        overrides={"uavs.vehicle_model": "coordinated_turn", "uavs.airframe": airframe},
    )
    af = AIRFRAMES[preset]
    lim = config_from_scenario(sc, 0).limits
    assert lim.v_stall_mps == pytest.approx(1.3 * af.v_stall_mps)
    assert lim.v_max_mps == af.v_max_mps
    assert lim.vz_max_mps == min(af.climb_max_mps, af.descent_max_mps)
    # the tightest coordinated turn at the lowest speed: radius v^2 / (g tan phi_max)
    radius = lim.v_stall_mps / lim.omega_max_radps
    assert radius == pytest.approx(lim.v_stall_mps**2 / (G_MPS2 * math.tan(math.radians(af.bank_max_deg))))


def test_ff_paper_agents_keep_ffs_limits() -> None:
    lim = config_from_scenario(load_scenario(scenario_path("ff_two_fires")), 0).limits
    assert (lim.v_stall_mps, lim.v_max_mps, lim.vz_max_mps, lim.omega_max_radps) == (44.7, 100.0, 100.0, 10.0)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 3])
def test_the_ff_mission_on_a_fixed_wing_is_safe(seed: int) -> None:
    """Issue's must-show on ``coordinated_turn`` + ``small_uav``, 5 UAVs, in process: every fire out,
    no collision, closest approach >= 10 m, every UAV landed within 5 m of its takeoff point.
    Seeds 2 and 3 each lost a pair to a collision (2.9-3.0 m) while the agents predicted with the
    commanded turn and separated as if they turned at once (docs/airframes.md)."""
    from fire_mission.inprocess import run_inprocess

    d = run_inprocess("ff_two_fires", uavs=5, seed=seed, overrides={"uavs.vehicle_model": "coordinated_turn"})
    assert d["outcome"] == "complete", d["detail"]
    assert d["fires_active_at_end"] == 0
    assert d["collisions"] == 0 and d["crashes"] == []
    assert d["min_separation_m"] >= 10.0
    assert len(d["landed"]) == 5 and max(d["landing_error_m"].values()) <= 5.0
