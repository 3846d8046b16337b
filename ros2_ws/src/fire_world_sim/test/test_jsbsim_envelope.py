"""The preset the ``jsbsim`` backend flies by default is the aircraft's own envelope, measured.

The agents plan, predict and land with the preset's figures; each is checked against what JSBSim's
J3Cub flies under the world's autopilot (``fire_world_sim.vehicles.jsbsim_envelope``, stepped at
fixed commands), not against the preset's own numbers. With ``small_uav`` (the default before)
the agents planned a 5 m/s climb and descent and 15.6 m/s; the J3Cub gives 1.4 m/s and 22 m/s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario
from fire_uav_common.scenario.airframes import G_MPS2
from fire_world_sim.vehicles import Command, FlightState, JsbsimModel
from fire_world_sim.vehicles.jsbsim_envelope import _unlimited, holds_level, measure_envelope


@pytest.fixture(scope="module")
def preset():
    sc = load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "jsbsim"})
    assert sc.uavs.airframe is not None
    return sc.uavs.airframe


@pytest.fixture(scope="module")
def measured(preset):
    return measure_envelope(preset, preset.water_capacity_kg, preset.v_min_mps)


def test_the_lowest_commanded_speed_is_one_the_aircraft_holds(preset, measured) -> None:
    assert preset.v_min_mps >= measured.v_hold_min_mps
    assert preset.v_stall_mps == pytest.approx(measured.v_trim_min_mps, abs=0.3)  # its 1 g minimum
    assert holds_level(preset, preset.v_min_mps, preset.water_capacity_kg)


def test_climb_and_descent_limits_are_what_it_flies_at_the_lowest_speed(preset, measured) -> None:
    # the agents' height loop and their approach's length rest on these: no more than the aircraft
    # gives, and not far below it (the climb keeps a margin of about 20 % for a full tank in a turn)
    assert 0.75 * measured.climb_max_mps <= preset.climb_max_mps <= measured.climb_max_mps
    assert 0.85 * measured.descent_max_mps <= preset.descent_max_mps <= measured.descent_max_mps


def test_the_bank_limit_holds_and_the_planned_turn_is_the_flown_one(preset, measured) -> None:
    assert measured.bank_max_deg <= preset.bank_max_deg
    planned = G_MPS2 * math.tan(preset.bank_max_rad) / preset.v_min_mps
    # the agents' tightest turn (their omega_max and turn radius) against the flown one
    assert planned == pytest.approx(measured.turn_rate_max_radps, rel=0.15)
    assert preset.roll_rate_max_degps == pytest.approx(measured.roll_rate_max_degps, rel=0.25)


def test_speed_limits_are_within_what_it_flies(preset, measured) -> None:
    assert preset.v_max_mps <= measured.v_level_max_mps
    assert preset.accel_max_mps2 <= measured.accel_max_mps2


@pytest.mark.parametrize(("v_mps", "water_kg"), [(50.0, 1000.0), (60.0, 3000.0), (70.0, 0.0), (75.0, 3000.0)])
def test_the_tankers_energy_limit_is_what_the_pc7_flies(v_mps: float, water_kg: float) -> None:
    """The tanker's ``jsbsim.excess_power`` table (the agents' and the autopilot's energy limit):
    the steepest climb JSBSim's PC-7 holds at full throttle and the commanded speed, and its P_s,
    flown again at points of the grid (at 50 m/s the pitch limit bounds the climb below P_s)."""
    from fire_uav_common.scenario.airframes import AIRFRAMES
    from fire_world_sim.vehicles.jsbsim_envelope import full_throttle_climb

    af = AIRFRAMES["tanker"]
    ep = af.jsbsim.excess_power
    assert ep is not None
    i, j = ep.water_kg.index(water_kg), ep.speeds_mps.index(v_mps)
    climb, ps = full_throttle_climb(af, v_mps, water_kg)
    assert climb == pytest.approx(ep.climb_mps[i][j], abs=0.3)
    assert ps == pytest.approx(ep.power_mps[i][j], abs=0.3)


def test_the_top_speed_is_a_level_flight_at_full_power(preset, measured) -> None:
    """The top speed of level flight is where level flight takes the whole of the engine: flown
    level at ``v_level_max_mps`` (trimmed 2 m/s faster, 30 s), the J3Cub holds its height and
    speed with the throttle at >= 95 %. At the base the figure came from a run commanded to 120 m/s
    at full throttle in which the autopilot's pitch command stood on its -15 deg stop: 40.3 m/s,
    flown climbing at 2.25 m/s; level at 40.3 m/s the J3Cub needs 78 % throttle."""
    v = measured.v_level_max_mps
    m = JsbsimModel(_unlimited(preset, v))
    s = m.launch(
        FlightState(0.0, 0.0, 200.0, 0.0, water_kg=preset.water_capacity_kg), Command(v + 2.0, 0.0, 0.0)
    )
    tail = []
    for i in range(3000):
        (s,) = m.step([s], [Command(v, 0.0, 0.0)], 0.01, [np.random.default_rng(0)])
        if i >= 2500:
            tail.append(s)
    assert max(abs(f.climb_mps) for f in tail) < 0.3
    assert max(abs(f.airspeed_mps - v) for f in tail) < 0.7
    assert m.fdm is not None
    assert m.fdm["fcs/throttle-cmd-norm"] >= 0.95
