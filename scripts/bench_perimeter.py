#!/usr/bin/env python3
"""Benchmark of the importance-based perimeter monitor (PM VI-B, VI-E); prints, asserts nothing.

1. Direction changes vs the heterogeneity factor alpha on one recorded fire (PM Fig. 11:
   0, 8, 11, 15, 20, 43 for alpha 0, 0.8, 1.0, 1.2, 1.5, 5.0).
2. Importance-based vs circling: mean over time of the maximum distance error at 360 angles
   between the true fire shape and the convex hull of the on-board perimeter cells (PM VI-E:
   7.3 vs 8.5 on a fire that speeds up, 12.2 vs 15.8 on a fast wind-driven fire, in cells).

Fires come from fire_perimeter_monitor.synthetic_fire (arrival-time rasters, not DEVS-FIRE):
fire_world_sim's raster fire did not exist when this was written.
Run: .venv/bin/python scripts/bench_perimeter.py  (about 1-3 minutes)
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "ros2_ws/src/fire_perimeter_monitor"))

from fire_perimeter_monitor.planner import CirclingMonitor, ImportanceMonitor, MonitorConfig
from fire_perimeter_monitor.synthetic_fire import elliptical_ros, fly, spread_fire

CELL_M = 30.0  # [m] raster cell
SPEED_MPS = 10.0  # [m/s] UAV speed along the perimeter
SENSOR_M = 1.5 * CELL_M  # [m] fire sensor footprint radius
SHAPE = (140, 140)  # cells
IGNITION = (100, 100)  # north-east of the centre; the fires run south-west
DEPLOY_S = 3600.0  # the UAV arrives 1 h after ignition (PM VI-A)
MONITOR_S = 3 * 3600.0  # [s] monitoring time
ERROR_EVERY = 3  # measure the VI-E error at every 3rd new cell (the hull is the costly part)
SW = math.radians(225.0)


def wind_fire():
    """Fast spread south-west from the start (PM Fig. 13a / 16b)."""
    return spread_fire(SHAPE, CELL_M, IGNITION, elliptical_ros(0.25, 0.75, SW))


def fuel_change_fire():
    """Slow, mildly wind-driven fire that speeds up 4x in the south-west half's fuel (PM Fig. 12a / 16a)."""
    ii, jj = np.meshgrid(np.arange(SHAPE[0]), np.arange(SHAPE[1]), indexing="ij")
    fuel = np.where(ii + jj < 150, 4.0, 1.0)
    return spread_fire(SHAPE, CELL_M, IGNITION, elliptical_ros(0.06, 0.5, SW), fuel_factor=fuel)


def config(fire, alpha=1.0):
    cx, cy = fire.ignition_xy_m
    return MonitorConfig(
        cell_size_m=CELL_M,
        speed_mps=SPEED_MPS,
        alpha=alpha,
        center_x_m=cx,
        center_y_m=cy,
        ignition_time_s=0.0,
    )


def run(fire, monitor):
    return fly(
        fire,
        monitor,
        start_angle_rad=math.radians(45.0),
        t_start_s=DEPLOY_S,
        t_end_s=DEPLOY_S + MONITOR_S,
        speed_mps=SPEED_MPS,
        sensor_range_m=SENSOR_M,
    )


def run_with_error(fire, monitor):
    """Fly and measure the VI-E error every ERROR_EVERY cells; returns mean max error [cells]."""
    from fire_perimeter_monitor.shape import max_distance_error, polygon_radial_extent

    errors = []
    orig = monitor.update

    def update(cells, pos, t):
        d = orig(cells, pos, t)
        if monitor.steps % ERROR_EVERY == 0:
            est = polygon_radial_extent(monitor.hull_m(), *fire.ignition_xy_m, 360)
            errors.append(max_distance_error(fire.true_extent(t), est))
        return d

    monitor.update = update  # type: ignore[method-assign]
    run(fire, monitor)
    return float(np.nanmean(errors)) / CELL_M


def main() -> None:
    t0 = time.time()
    wind, fuel = wind_fire(), fuel_change_fire()
    print(
        f"fires built in {time.time() - t0:.1f} s; cell {CELL_M:.0f} m, UAV {SPEED_MPS:.0f} m/s, "
        f"sensor radius {SENSOR_M:.0f} m, monitoring {MONITOR_S / 3600:.0f} h from 1 h after ignition"
    )

    print("\n1. direction changes vs alpha (wind-driven fire; paper Fig. 11: 0, 8, 11, 15, 20, 43)")
    for alpha in (0.0, 0.8, 1.0, 1.2, 1.5, 5.0):
        m = ImportanceMonitor(config(wind, alpha))
        run(wind, m)
        print(f"   alpha {alpha:3.1f}: {m.direction_changes:5d} direction changes")

    print("\n2. mean over time of the max distance error [cells] (PM VI-E)")
    print("   fire          importance  circling  ratio   (paper: 7.3/8.5 = 0.86, 12.2/15.8 = 0.77)")
    for name, fire in (("fuel change", fuel), ("wind-driven", wind)):
        e_imp = run_with_error(fire, ImportanceMonitor(config(fire)))
        e_circ = run_with_error(fire, CirclingMonitor(config(fire)))
        print(f"   {name:12s}  {e_imp:10.2f}  {e_circ:8.2f}  {e_imp / e_circ:5.2f}")
    print(f"\ntotal {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
