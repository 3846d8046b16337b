"""The agent's model of its airframe (fire_uav_agent.airframe_model) against the world's own backend.

The world's ``coordinated_turn`` backend (Beard & McLain ch. 9) is the truth the on-board model
must reproduce: fed the same commands from the same state without process noise, the EKF input
it gives must be the mean of what the world flew over each control period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.airframe_model import FlownInput, inside_turn_circle, turn_radius_m
from fire_uav_agent.coverage import VehicleLimits
from fire_uav_common import scenario as sc
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import AIRFRAMES
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel

AIR, GROUND, LANDED = VehicleStatus.AIRBORNE, VehicleStatus.ON_GROUND, VehicleStatus.LANDED
SMALL = AIRFRAMES["small_uav"]
LIM = VehicleLimits.of(sc.airframes.envelope_vehicle(sc.Vehicle(), SMALL))


def _world_means(commands: list[tuple[float, float, float]], water_kg: float) -> list[np.ndarray]:
    """The world's flown (ground speed, climb, turn rate), averaged per control period of 10 substeps."""
    model = CoordinatedTurnModel(SMALL, 0.0)
    rng = np.random.default_rng(0)
    st = FlightState(0.0, 0.0, 30.0, 0.0, water_kg=water_kg)
    out = []
    for k, (v, vz, w) in enumerate(commands):
        c = Command(
            min(max(v, LIM.v_stall_mps), LIM.v_max_mps),
            min(max(vz, -LIM.vz_max_mps), LIM.vz_max_mps),
            min(max(w, -LIM.omega_max_radps), LIM.omega_max_radps),
        )
        if k == 0:
            st = model.launch(st, Command(v, vz, w))
        acc = np.zeros(3)
        for _ in range(10):
            (st,) = model.step([st], [c], 0.01, [rng])
            acc += (math.sqrt(st.airspeed_mps**2 - st.climb_mps**2), st.climb_mps, st.turn_rate_radps)
        out.append(acc / 10)
    return out


def test_the_ekf_input_is_the_turn_the_world_flies_not_the_command():
    cmds = [(16.0, 3.0, 0.0)] + [(30.0, 5.0, 1.0)] * 15 + [(15.0, -5.0, -0.6)] * 20 + [(22.0, 0.0, 0.2)] * 10
    truth = _world_means(cmds, water_kg=6.0)
    f = FlownInput(SMALL, LIM, 0.01, 0.1)
    prev = GROUND
    worst = 0.0
    for cmd, want in zip(cmds, truth, strict=True):
        u = f.input(np.array(cmd), prev == AIR, AIR, 6.0)
        worst = max(worst, float(np.max(np.abs(u - want))))
        prev = AIR
    assert worst < 1e-9
    # and the command itself is far from it: the first second of a turn lags by the bank response
    f2 = FlownInput(SMALL, LIM, 0.01, 0.1)
    u0 = f2.input(np.array(cmds[0]), False, AIR, 6.0)
    u1 = f2.input(np.array(cmds[1]), True, AIR, 6.0)
    assert u0[2] == 0.0 and 0.0 < u1[2] < 0.5 * LIM.omega_max_radps


def test_without_an_airframe_the_input_is_the_clamped_command_as_before():
    lim = VehicleLimits.of(sc.Vehicle())
    f = FlownInput(None, lim, 0.01, 0.1)
    assert list(f.input(np.array([150.0, 150.0, 30.0]), True, AIR, 0.0)) == [
        lim.v_max_mps, lim.vz_max_mps, lim.omega_max_radps,
    ]  # fmt: skip
    assert list(f.input(np.array([10.0, 150.0, 0.0]), False, AIR, 0.0)) == [10.0, lim.vz_max_mps, 0.0]
    assert list(f.input(np.array([50.0, -0.5, 3.0]), True, LANDED, 0.0)) == [0.0, -0.5, 0.0]


def test_a_touchdown_stops_the_prediction_and_a_new_takeoff_starts_wings_level():
    f = FlownInput(SMALL, LIM, 0.01, 0.1)
    f.input(np.array([16.0, 3.0, 0.0]), False, AIR, 0.0)
    for _ in range(10):
        f.input(np.array([25.0, 0.0, 0.5]), True, AIR, 0.0)
    assert f.state.bank_rad > 0.2
    assert list(f.input(np.array([0.0, -0.5, 0.0]), True, LANDED, 0.0)) == [0.0, -0.5, 0.0]
    u = f.input(np.array([16.0, 3.0, 0.0]), False, AIR, 0.0)
    assert u[2] == 0.0 and u[0] == pytest.approx(16.0, abs=0.1)  # at the commanded speed


def test_the_turn_radius_is_v_squared_over_g_tan_bank():
    # docs/airframes.md: small_uav at its lowest commanded speed, full bank: 24.8 m
    assert turn_radius_m(SMALL, SMALL.v_min_mps, 0.0) == pytest.approx(24.8, abs=0.05)
    assert turn_radius_m(AIRFRAMES["tanker"], 45.0, 0.0) == pytest.approx(206.4, abs=0.1)
    # just above stall with a full tank the stall limits the bank below 45 deg: a wider turn
    v = 1.05 * SMALL.v_stall_mps
    assert turn_radius_m(SMALL, v) > v * v / 9.80665 * 1.5


def test_points_inside_the_turn_circles_are_found():
    r = 25.0
    pose = (0.0, 0.0, 0.0)  # heading +x: circles centred at (0, +25) and (0, -25)
    assert inside_turn_circle(pose, (0.0, 30.0), r)
    assert inside_turn_circle(pose, (5.0, -20.0), r)
    assert not inside_turn_circle(pose, (60.0, 0.0), r)
    assert not inside_turn_circle(pose, (-30.0, 0.0), r)  # behind: reachable by a turn
