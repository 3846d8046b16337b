"""Vehicle edges: the life-cycle boundaries of docs/protocol.md "Commands", the terrain floor on
sloped ground, the tank's mass balance, and FF Eq. 4's noise nu ~ N(0, sigma^2 I) having
independent components. Each test states the documented rule it checks (module docstring of
fire_world_sim.vehicle), not the implementation's arithmetic."""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_common.scenario import Vehicle as VehicleSpec
from fire_uav_common.terrain import Lake, Terrain
from fire_world_sim.vehicle import Command, Status, VehicleSim

SPEC0 = VehicleSpec(process_noise_sigma=0.0)  # v_stall 44.7, margin 10, refill 15 m, 400 kg/s
LAKE = Lake(0.0, 0.0, 90.0)
DT = 0.1
FLAT = Terrain()


def make(pose=(0.0, 0.0, 50.0, 0.0), terrain=FLAT, lakes=(), spec=SPEC0, uav_id=0) -> VehicleSim:
    return VehicleSim(uav_id, spec, pose, terrain, lakes, np.random.default_rng(0))


def fly(v: VehicleSim) -> VehicleSim:
    assert v.accept_command(Command(50.0, 1.0, 0.0), DT).took_off
    return v


def refilling_at(z_m: float, water_kg: float, terrain=FLAT) -> VehicleSim:
    """Airborne over LAKE at z_m with water_kg aboard, slow enough, refill requested."""
    v = fly(make(pose=(0.0, 0.0, z_m, 0.0), terrain=terrain, lakes=(LAKE,)))
    v.accept_command(Command(50.0, 0.0, 0.0), DT)
    v.z_m, v.water_kg = z_m, water_kg
    assert v.request_refill()
    return v


def test_a_new_vehicle_is_parked_responsive_and_uncrashed() -> None:
    v = make(uav_id=7)
    assert v.uav_id == 7 and v.status == Status.ON_GROUND and v.responsive
    assert (v.v_lin_mps, v.v_z_mps, v.omega_z_radps, v.yaw_rate_radps) == (0.0, 0.0, 0.0, 0.0)
    assert v.crash_reason == "" and not v.refilling


def test_start_below_sloped_ground_is_raised_to_the_ground_there() -> None:
    # E(x, y) = 0.1 x + 0.2 y: at (100, 50) the ground is 20 m
    v = make(pose=(100.0, 50.0, 5.0, 0.0), terrain=Terrain(slope_x=0.1, slope_y=0.2))
    assert v.z_m == pytest.approx(20.0)


def test_silence_from_construction_crashes_after_exactly_the_timeout() -> None:
    v = make()  # command_timeout_s 3.0 at 0.1 s per step: the 30th miss
    for k in range(29):
        assert not v.accept_command(None, DT).crashed, k
    assert v.accept_command(None, DT).crashed and v.status == Status.CRASHED
    assert "no valid command for 3.0 s" in v.crash_reason


def test_a_valid_command_makes_a_silent_landed_vehicle_responsive_again() -> None:
    v = fly(make())
    v.z_m = 0.2
    v.accept_command(Command(0.0, 0.0, 0.0), DT)
    for _ in range(30):
        v.accept_command(None, DT)
    assert v.status == Status.LANDED and not v.responsive
    v.accept_command(Command(0.0, 0.0, 0.0), DT)
    assert v.responsive is True


def test_takeoff_at_exactly_stall_speed() -> None:
    v = make()
    assert v.accept_command(Command(44.7, 1.0, 0.0), DT).took_off


def test_ground_commands_are_never_counted_as_clamped_and_apply_nothing() -> None:
    v = make()
    out = v.accept_command(Command(500.0, 0.0, 50.0), DT)  # no climb: no takeoff, huge inputs
    assert not out.clamped and v.commands_clamped == 0
    assert (v.v_lin_mps, v.v_z_mps, v.omega_z_radps) == (0.0, 0.0, 0.0)
    v.substep(0.01)
    assert v.yaw_rate_radps == 0.0


def test_stall_speed_is_flying_speed_not_a_landing_command() -> None:
    v = fly(make())
    v.z_m = 0.5  # low enough to land
    out = v.accept_command(Command(44.7, 0.0, 0.0), DT)
    assert not out.landed and v.status == Status.AIRBORNE


def test_landing_height_is_a_strict_bound() -> None:
    v = fly(make())
    v.z_m = 1.0  # landing_height_m exactly: "below" it is required
    assert not v.accept_command(Command(30.0, 0.0, 0.0), DT).landed


def test_landing_counts_height_above_elevated_terrain() -> None:
    v = fly(make(pose=(0.0, 0.0, 150.0, 0.0), terrain=Terrain(base_m=100.0)))
    v.z_m = 100.5  # 0.5 m above the 100 m ground
    out = v.accept_command(Command(30.0, 0.0, 0.0), DT)
    assert out.landed and v.z_m == 100.0
    assert (v.v_lin_mps, v.v_z_mps, v.omega_z_radps, v.yaw_rate_radps) == (0.0, 0.0, 0.0, 0.0)


def test_crash_drops_to_the_sloped_ground_below_and_stops() -> None:
    terrain = Terrain(slope_x=0.1)
    v = fly(make(pose=(200.0, 0.0, 300.0, 0.0), terrain=terrain))
    v.accept_command(Command(60.0, 5.0, 1.0), DT)
    v.substep(0.1)
    x = v.x_m
    v.crash("test")
    assert v.status == Status.CRASHED and v.crash_reason == "test"
    assert v.z_m == pytest.approx(0.1 * x)
    assert (v.v_lin_mps, v.v_z_mps, v.omega_z_radps, v.yaw_rate_radps) == (0.0, 0.0, 0.0, 0.0)


def test_terrain_is_a_floor_on_a_slope() -> None:
    terrain = Terrain(slope_x=0.5)  # climbing ground to the east
    v = fly(make(pose=(0.0, 0.0, 2.0, 0.0), terrain=terrain))
    v.accept_command(Command(60.0, -100.0, 0.0), DT)  # 1 m down per substep, ground 0.3 m up
    for _ in range(10):
        v.substep(0.01)
        assert v.z_m >= terrain.elevation(v.x_m, v.y_m) - 1e-12
    assert v.z_m == pytest.approx(terrain.elevation(v.x_m, v.y_m))  # pressed onto the ground
    assert v.status == Status.AIRBORNE  # not a landing: that needs a slow command


def test_process_noise_components_are_independent() -> None:
    """FF Eq. 4: nu ~ N(0, sigma^2 I): along-track, vertical and yaw noise are uncorrelated."""
    spec = VehicleSpec(process_noise_sigma=1.0)
    dx, dz, dyaw = [], [], []
    for seed in range(300):
        v = VehicleSim(0, spec, (0.0, 0.0, 50.0, 0.0), Terrain(), (), np.random.default_rng(seed))
        v.accept_command(Command(50.0, 1.0, 0.0), DT)
        v.accept_command(Command(50.0, 0.0, 0.0), DT)
        v.substep(0.01)  # one substep: yaw was 0, so x carries nu_1 only
        dx.append(v.x_m - 0.5)
        dz.append(v.z_m - 50.0)
        dyaw.append(v.yaw_rad)
    c = np.corrcoef([dx, dz, dyaw])
    # independent: |r| ~ 1/sqrt(300) = 0.06; a shared component gives r = 1
    assert np.all(np.abs(c[np.triu_indices(3, 1)]) < 0.25), c


# --- refill (FF IV-D b): over a lake, 0 <= height above the water <= refill_height_m,
# --- v_lin <= v_stall + margin; the report is the mass actually taken


def test_refill_bounds_are_inclusive_and_measured_from_the_water() -> None:
    for z_m in (100.0, 115.0):  # lake at 100 m: on the surface and exactly refill_height_m above
        v = fly(make(pose=(0.0, 0.0, 150.0, 0.0), terrain=Terrain(base_m=100.0), lakes=(LAKE,)))
        v.accept_command(Command(54.7, 0.0, 0.0), DT)  # v_stall + margin exactly
        v.z_m, v.water_kg = z_m, 0.0
        assert v.refill_conditions(), z_m
    v.z_m = 115.5
    assert not v.refill_conditions()


def test_refill_over_a_water_body_follows_its_outline_not_its_disc() -> None:
    """A landscape's lake: over any of its water cells counts, however far from the disc the
    agents aim at; beside the water does not."""
    from fire_uav_common.water import WaterCells

    mask = np.zeros((3, 20), dtype=bool)
    mask[1, :] = True  # a channel 600 m x 30 m, row 0 south; the disc is 30 m wide at its west end
    lake = Lake(15.0, 45.0, 30.0, water=WaterCells(0.0, 0.0, 30.0, mask))
    for x_m, y_m, over in (
        (15.0, 45.0, True),
        (585.0, 45.0, True),
        (15.0, 25.0, False),
        (300.0, 65.0, False),
    ):
        v = fly(make(pose=(x_m, y_m, 50.0, 0.0), lakes=(lake,)))
        v.accept_command(Command(50.0, 0.0, 0.0), DT)
        v.x_m, v.y_m, v.z_m, v.water_kg = x_m, y_m, 10.0, 0.0
        assert v.refill_conditions() == over, (x_m, y_m)


def test_no_refill_below_the_water_surface() -> None:
    # sloped ground under the lake: at x = -40 the ground is 0.4 m below the lake's centre level
    v = fly(make(pose=(-40.0, 0.0, 50.0, 0.0), terrain=Terrain(slope_x=0.01), lakes=(LAKE,)))
    v.accept_command(Command(50.0, 0.0, 0.0), DT)
    v.z_m, v.water_kg = -0.4, 0.0
    assert not v.refill_conditions()


def test_no_refill_on_the_ground_or_with_a_full_tank() -> None:
    v = make(pose=(0.0, 0.0, 0.0, 0.0), lakes=(LAKE,))
    v.water_kg = 0.0
    assert not v.request_refill() and v.release_water() == 0.0 and v.water_kg == 0.0
    v = fly(make(pose=(0.0, 0.0, 10.0, 0.0), lakes=(LAKE,)))
    v.accept_command(Command(50.0, 0.0, 0.0), DT)
    v.z_m = 10.0
    assert v.water_kg == 2000.0 and not v.request_refill()


def test_no_water_without_a_request() -> None:
    v = fly(make(pose=(0.0, 0.0, 10.0, 0.0), lakes=(LAKE,)))
    v.accept_command(Command(50.0, 0.0, 0.0), DT)
    v.z_m, v.water_kg = 10.0, 1000.0
    assert v.refill_conditions()
    assert v.refill_tick(0.01) == 0.0 and v.water_kg == 1000.0


def test_topping_up_reports_the_mass_taken_not_the_pump_rate() -> None:
    v = refilling_at(10.0, 1999.5)  # 0.5 kg short; the pump gives 4 kg per 0.01 s
    assert v.refill_tick(0.01) == pytest.approx(0.5)
    assert v.water_kg == 2000.0 and not v.refilling
    assert v.refill_tick(0.01) == 0.0  # one report per refill


def test_a_tank_within_a_kilogram_is_not_yet_full() -> None:
    v = refilling_at(10.0, 1999.2)
    assert v.refill_tick(0.001) == 0.0 and v.water_kg == pytest.approx(1999.6)  # 0.4 kg in
    assert v.refilling


def test_leaving_the_lake_reports_the_partial_refill_and_stops_it() -> None:
    v = refilling_at(10.0, 0.0)
    for _ in range(10):
        assert v.refill_tick(0.01) == 0.0
    v.z_m = 30.0  # climbed out
    assert v.refill_tick(0.01) == pytest.approx(40.0)
    v.z_m = 10.0  # back down: no new request, no water
    assert v.refill_tick(0.01) == 0.0 and v.water_kg == pytest.approx(40.0)


def test_report_counts_the_whole_refill_across_repeated_requests() -> None:
    v = refilling_at(10.0, 1000.0)
    v.refill_tick(1.0)  # 400 kg
    assert v.request_refill()  # asked again mid-refill: the same refill goes on
    assert v.refill_tick(1.0) == 0.0
    assert v.refill_tick(1.0) == pytest.approx(1000.0)


def test_a_drop_stops_the_refill_and_the_next_report_starts_afresh() -> None:
    v = refilling_at(10.0, 1000.0)
    v.refill_tick(0.25)  # 100 kg taken, then dropped with the rest
    assert v.release_water() == pytest.approx(1100.0) and not v.refilling
    assert v.refill_tick(0.01) == 0.0 and v.water_kg == 0.0  # the drop ended the refill
    assert v.request_refill()
    assert v.refill_tick(5.0) == pytest.approx(2000.0)  # this refill's 2000 kg, not 2100


def test_landing_or_crashing_ends_a_refill() -> None:
    v = refilling_at(0.5, 1000.0)
    v.refill_tick(0.01)
    assert v.accept_command(Command(30.0, 0.0, 0.0), DT).landed
    assert not v.refilling
    w0 = v.water_kg
    v.refill_tick(0.01)
    assert v.water_kg == w0
    v = refilling_at(10.0, 1000.0)
    v.crash("test")
    assert not v.refilling
