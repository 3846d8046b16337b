"""Terrain following over a hill (FF Eq. 12 with the climb-limited speed, coverage.control_law).

Issue [suppression]: over grass_brush_hill two UAVs collided at ~0 m above ground, far below
their altitude layers: at 100 m/s on the hill's ~30 % slope the ground rose faster than the
20 m/s climb cap. Truth here is the vehicle model itself (FF Eq. 4, noise-free): the unicycle
integrated at the world's 0.01 s physics step with the commands of the 0.1 s control step, the
terrain a floor. A height hold is good when the height above ground stays near the command.
"""

import math

import numpy as np
import pytest
from fire_uav_agent.coverage import ControlGains, VehicleLimits, control_law
from fire_uav_common.terrain import Hill, Terrain

HILL = Terrain(hills=(Hill(x_m=700.0, y_m=500.0, height_m=120.0, sigma_m=180.0),))  # grass_brush_hill's
LIM, GAINS = VehicleLimits(), ControlGains()
T_CTRL, T_PHYS = 0.1, 0.01  # [s] the scenarios' control and physics periods


def fly(terrain: Terrain, start_xy, target_xy, height_m: float, seconds: float, gains=GAINS):
    """Height above ground [m] at every physics step of a flight from start_xy toward target_xy
    (level at height_m above the start's ground, heading at the target)."""
    x, y = start_xy
    z = float(terrain.elevation(x, y)) + height_m
    th = math.atan2(target_xy[1] - y, target_xy[0] - x)
    agl = []
    for _ in range(round(seconds / T_CTRL)):
        v, vz, om = control_law(np.array([x, y, z, th]), np.array(target_xy), height_m, terrain, LIM, gains)
        v = min(max(v, LIM.v_stall_mps), LIM.v_max_mps)  # the vehicle's limits (fire_world_sim.vehicle)
        vz = min(max(vz, -LIM.vz_max_mps), LIM.vz_max_mps)
        for _ in range(round(T_CTRL / T_PHYS)):
            x += T_PHYS * v * math.cos(th)
            y += T_PHYS * v * math.sin(th)
            z = max(z + T_PHYS * vz, float(terrain.elevation(x, y)))  # terrain is a floor
            th += T_PHYS * om
            agl.append(z - float(terrain.elevation(x, y)))
    return np.array(agl)


@pytest.mark.parametrize("height_m", [12.0, 36.0])  # the lowest and highest raster layer
@pytest.mark.parametrize(
    "start_xy, target_xy",
    [
        ((330.0, 450.0), (1000.0, 520.0)),  # from the fire's ignition, up and over the summit
        ((1000.0, 300.0), (380.0, 560.0)),  # down the west flank toward the fire
        ((400.0, 150.0), (950.0, 900.0)),  # across the north-west slope
    ],
)
def test_height_above_ground_holds_over_the_hill(height_m, start_xy, target_xy):
    """Full speed at the hill: the height stays within 2.5 m of the command (without the
    climb-limited speed it fell to 0 m, the floor, on the climb and rose > 10 m on the descent)."""
    agl = fly(HILL, start_xy, target_xy, height_m, seconds=10.0)
    assert agl.min() > height_m - 2.5, f"fell to {agl.min():.1f} m above ground (command {height_m} m)"
    assert agl.max() < height_m + 2.5, f"rose to {agl.max():.1f} m above ground (command {height_m} m)"


def test_without_the_speed_cap_the_climb_falls_behind():
    """The failure this guards against is real: with the speed cap off (climb_fraction huge) the
    same climb reaches the floor, i.e. the test above can fail."""
    off = ControlGains(climb_fraction=1e9)
    agl = fly(HILL, (330.0, 450.0), (1000.0, 520.0), 30.0, seconds=10.0, gains=off)
    assert agl.min() < 1.0


def test_flat_ground_keeps_full_speed():
    """No grade, no cap: v_lin is Eq. 10's clamp (v_max far from the target)."""
    v, _, _ = control_law(
        np.array([0.0, 0.0, 30.0, 0.0]), np.array([500.0, 0.0]), 30.0, Terrain(), LIM, GAINS
    )
    assert v == LIM.v_max_mps
