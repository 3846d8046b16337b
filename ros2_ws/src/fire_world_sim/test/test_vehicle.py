"""Vehicle kinematics (FF Eq. 4), limits, life-cycle and tank."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.scenario import Vehicle as VehicleSpec
from fire_uav_common.terrain import Lake, Terrain
from fire_world_sim.vehicle import Command, Status, VehicleSim, wrap_angle

SPEC0 = VehicleSpec(process_noise_sigma=0.0)


def airborne(spec: VehicleSpec = SPEC0, pose=(0.0, 0.0, 50.0, 0.0), lakes=()) -> VehicleSim:
    v = VehicleSim(0, spec, pose, Terrain(), lakes, np.random.default_rng(0))
    out = v.accept_command(Command(50.0, 1.0, 0.0), 0.1)
    assert out.took_off and v.status == Status.AIRBORNE
    return v


def test_eq4_by_hand_without_noise() -> None:
    v = airborne(pose=(10.0, 20.0, 50.0, 0.3))
    v.accept_command(Command(60.0, 2.0, 0.5), 0.1)
    x, y, z, th = 10.0, 20.0, 50.0, 0.3
    for _ in range(10):
        v.substep(0.01)
        x += math.cos(th) * 0.01 * 60.0
        y += math.sin(th) * 0.01 * 60.0
        z += 0.01 * 2.0
        th += 0.01 * 0.5
    assert v.pose == pytest.approx((x, y, z, th), abs=1e-12)


def test_process_noise_statistics() -> None:
    spec = VehicleSpec(process_noise_sigma=1.0)
    finals = []
    for seed in range(400):
        v = VehicleSim(0, spec, (0, 0, 50, 0), Terrain(), (), np.random.default_rng(seed))
        v.accept_command(Command(50.0, 1.0, 0.0), 0.1)
        v.accept_command(Command(50.0, 0.0, 0.0), 0.1)
        for _ in range(100):
            v.substep(0.01)
        finals.append(v.z_m - 50.0)
    # z after N substeps: sum of dt * nu, std = dt * sigma * sqrt(N) = 0.1 m
    assert np.std(finals) == pytest.approx(0.1, rel=0.15)
    assert abs(np.mean(finals)) < 0.03


def test_limits_are_clamped_and_counted() -> None:
    v = airborne()
    out = v.accept_command(Command(150.0, -300.0, 20.0), 0.1)
    assert out.clamped and v.commands_clamped == 1
    assert (v.v_lin_mps, v.v_z_mps, v.omega_z_radps) == (100.0, -100.0, 10.0)
    out = v.accept_command(Command(10.0, 0.0, -20.0), 0.1)  # too slow while high: no landing, clamped
    assert out.clamped and v.commands_clamped == 2
    assert v.v_lin_mps == 44.7 and v.omega_z_radps == -10.0
    out = v.accept_command(Command(60.0, 0.0, 0.0), 0.1)
    assert not out.clamped and v.commands_clamped == 2


def test_ground_stays_put_until_takeoff() -> None:
    v = VehicleSim(0, SPEC0, (5.0, 6.0, 0.0, 1.0), Terrain(), (), np.random.default_rng(0))
    for cmd in (Command(30.0, 5.0, 0.0), Command(60.0, 0.0, 0.0), Command(60.0, -1.0, 1.0)):
        out = v.accept_command(cmd, 0.1)
        v.substep(0.01)
        assert not out.took_off and v.status == Status.ON_GROUND and v.pose == (5.0, 6.0, 0.0, 1.0)


def test_landing_needs_low_and_slow() -> None:
    v = airborne()
    v.z_m = 0.5
    out = v.accept_command(Command(30.0, 0.0, 0.0), 0.1)
    assert out.landed and v.status == Status.LANDED and v.z_m == 0.0
    v.accept_command(Command(60.0, 5.0, 0.0), 0.1)
    v.substep(0.01)
    assert v.status == Status.LANDED


def test_fall_after_command_timeout() -> None:
    v = airborne()
    v.accept_command(Command(60.0, 5.0, 0.0), 0.1)
    for k in range(29):
        out = v.accept_command(None, 0.1)
        assert out.missed and not out.crashed, k
        v.substep(0.01)
    assert v.v_lin_mps == 60.0  # keeps flying on the previous command
    assert v.accept_command(Command(math.nan, 0, 0), 0.1).crashed  # NaN counts as missed: 30th miss
    assert v.status == Status.CRASHED and not v.responsive


def test_landed_vehicle_does_not_crash_when_silent() -> None:
    v = airborne()
    v.z_m = 0.2
    v.accept_command(Command(0.0, 0.0, 0.0), 0.1)
    for _ in range(40):
        v.accept_command(None, 0.1)
    assert v.status == Status.LANDED and not v.responsive


def test_refill_conditions_and_drop() -> None:
    lake = Lake(0.0, 0.0, 90.0)
    v = airborne(lakes=(lake,))
    assert v.release_water() == 2000.0 and v.water_kg == 0.0
    v.z_m = 10.0
    v.accept_command(Command(50.0, 0.0, 0.0), 0.1)
    assert v.request_refill()
    taken = 0.0
    for _ in range(499):
        taken += v.refill_tick(0.01)
    assert taken == 0.0 and v.water_kg == pytest.approx(1996.0)
    assert v.refill_tick(0.01) == pytest.approx(2000.0)
    v.water_kg = 0.0
    v.accept_command(Command(70.0, 0.0, 0.0), 0.1)  # too fast
    assert not v.request_refill()
    v.accept_command(Command(50.0, 0.0, 0.0), 0.1)
    v.z_m = 20.0  # too high
    assert not v.request_refill()
    v.z_m, v.x_m = 10.0, 100.0  # not over the lake
    assert not v.request_refill()


def test_wrap_angle() -> None:
    assert wrap_angle(math.pi) == pytest.approx(math.pi)
    assert wrap_angle(-math.pi) == pytest.approx(math.pi)
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
