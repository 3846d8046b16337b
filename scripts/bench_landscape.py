#!/usr/bin/env python3
"""Fire over a whole landscape, ours against pyretechnics: the per-cell kernel and free spread.

Usage (in the project's environment: ``source scripts/env.sh``):
    python scripts/bench_landscape.py [--reps N] [--wind-20ft-mps U] \
        [--pyretechnics-python /path/to/other/venv/bin/python]
    python scripts/bench_landscape.py --spread [--hours H] [--wind-20ft-mps U] \
        [--pyretechnics-python /path/to/other/venv/bin/python]

``--spread``: a free-burning fire (no fleet) across all of ``worcester_vt`` for H hours of fire
time, with the shipped scenario's moistures (4/5/6/30/70 %), foliar moisture 100 %, crown fire
by Finney's method and its ignition point, under a 20-ft wind from the west (default 8 m/s as
the scenario). Ours is the world's :class:`RasterFireModel` stepped in 1 s steps (the world's
update period, 0.5 s); pyretechnics' is ``eulerian_level_set.spread_fire_with_phi_field`` on
the same layers and weather. Prints cells burned, CPU seconds and cells burned per CPU-second
for both, and how far the two burned areas agree (intersection over union). Our CPU seconds
are the spread's; the set-up (layers, fire behaviour per cell) and the once-per-process load
of the compiled kernels (a small fire burnt first) are printed apart.

Both sides compute FlamMap's basic run (head rate, direction, intensity, flame length, fire type
with crown fire) for every cell of the shipped ``worcester_vt`` landscape (549 x 613 cells of
30 m), with moistures 6/8/10/75/60 %, foliar moisture 120 %, the given 20-ft wind from the west.
Ours is ``fire_world_sim.fires.behavior.fire_behavior`` (crown "finney"); pyretechnics' is
``burn_cells.burn_all_cells_as_head_fire`` (Cython, cell by cell). pyretechnics pins numpy 1.26
and rasterio 1.4, so it runs in its own venv (``python -m venv V && V/bin/pip install
pyretechnics``, about 4 minutes of compiling): this script starts itself there with
``--as-pyretechnics`` and reads its results back.

Prints CPU seconds per run (best of --reps, process time, so other load on the machine counts
less) and cells per CPU-second, and the per-cell agreement of the two (rate, fire type). No
assertions: figures only.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
LAND = ROOT / "data" / "landscapes" / "worcester_vt"
MOISTURE = (0.06, 0.08, 0.10, 0.75, 0.60)
FOLIAR = 1.2
WIND_FROM_DEG = 270.0
TEN_METRE_PER_20FT = 1.15  # pyretechnics' 10-m to 20-ft wind ratio


def read_layers() -> dict[str, np.ndarray]:
    """The landscape's layers in model units without our loader (the pyretechnics venv has no yaml)."""
    import rasterio

    def band(name: str) -> np.ma.MaskedArray:
        with rasterio.open(LAND / f"{name}.tif") as r:
            return r.read(1, masked=True)

    fuel = band("fbfm40")
    outside = np.ma.getmaskarray(fuel)
    out = {"fuel": np.where(outside, 99, fuel.filled(99)).astype(np.int64)}
    for name, scale in (
        ("slope", 0.01),
        ("aspect", 1.0),
        ("canopy_cover", 0.01),
        ("canopy_height", 0.1),
        ("canopy_base_height", 0.1),
        ("canopy_bulk_density", 0.01),
    ):
        out[name] = band(name).filled(0).astype(float) * scale
    out["outside"] = outside
    return out


def run_pyretechnics(reps: int, wind_20ft_mps: float, out: Path) -> None:
    from pyretechnics.burn_cells import burn_all_cells_as_head_fire
    from pyretechnics.space_time_cube import SpaceTimeCube

    layers = read_layers()
    rows, cols = layers["fuel"].shape
    shape = (1, rows, cols)
    cubes = {
        "slope": SpaceTimeCube(shape, layers["slope"].astype(np.float32)),
        "aspect": SpaceTimeCube(
            shape, np.where(layers["aspect"] < 0, 0.0, layers["aspect"]).astype(np.float32)
        ),
        "fuel_model": SpaceTimeCube(shape, layers["fuel"].astype(np.float32)),
        "canopy_cover": SpaceTimeCube(shape, layers["canopy_cover"].astype(np.float32)),
        "canopy_height": SpaceTimeCube(shape, layers["canopy_height"].astype(np.float32)),
        "canopy_base_height": SpaceTimeCube(shape, layers["canopy_base_height"].astype(np.float32)),
        "canopy_bulk_density": SpaceTimeCube(shape, layers["canopy_bulk_density"].astype(np.float32)),
        "wind_speed_10m": SpaceTimeCube(shape, wind_20ft_mps * 3.6 * TEN_METRE_PER_20FT),
        "upwind_direction": SpaceTimeCube(shape, WIND_FROM_DEG),
        "fuel_moisture_dead_1hr": SpaceTimeCube(shape, MOISTURE[0]),
        "fuel_moisture_dead_10hr": SpaceTimeCube(shape, MOISTURE[1]),
        "fuel_moisture_dead_100hr": SpaceTimeCube(shape, MOISTURE[2]),
        "fuel_moisture_live_herbaceous": SpaceTimeCube(shape, MOISTURE[3]),
        "fuel_moisture_live_woody": SpaceTimeCube(shape, MOISTURE[4]),
        "foliar_moisture": SpaceTimeCube(shape, FOLIAR),
    }
    best = float("inf")
    result: dict[str, np.ndarray] = {}
    for _ in range(reps):
        t0 = time.process_time()
        result = burn_all_cells_as_head_fire(cubes, 0)
        best = min(best, time.process_time() - t0)
    np.savez(out, cpu_s=best, ros_mps=result["spread_rate"] / 60.0, fire_type=result["fire_type"])


def run_ours(reps: int, wind_20ft_mps: float) -> tuple[float, dict[str, np.ndarray]]:
    from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior

    layers = read_layers()
    best = float("inf")
    b = None
    for _ in range(reps):
        t0 = time.process_time()
        b = fire_behavior(
            layers["fuel"],
            layers["slope"] * 100.0,
            layers["aspect"],
            wind_20ft_mps=wind_20ft_mps,
            wind_from_deg=WIND_FROM_DEG,
            moistures=FuelMoistures(Moisture(*MOISTURE)),
            canopy_cover=layers["canopy_cover"],
            canopy_height_m=layers["canopy_height"],
            canopy_base_height_m=layers["canopy_base_height"],
            canopy_bulk_density_kgpm3=layers["canopy_bulk_density"],
            foliar_moisture=FOLIAR,
            crown="finney",
        )
        best = min(best, time.process_time() - t0)
    assert b is not None
    return best, {"ros_mps": b.ros_mps, "fire_type": b.fire_type, "outside": layers["outside"]}


SCENARIO = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / "worcester_vt.yaml"
SPREAD_MOISTURE = (0.04, 0.05, 0.06, 0.30, 0.70)  # the shipped scenario's
SPREAD_FOLIAR = 1.0


def spread_ignition() -> tuple[float, float]:
    """The shipped scenario's ignition point in the landscape's projected metres."""
    import yaml

    raw = yaml.safe_load(SCENARIO.read_text())
    win = raw["fires"]["raster"]["landscape"]["window"]
    ig = raw["fires"]["raster"]["ignitions"][0]
    return win["x_min_m"] + ig["x_m"], win["y_min_m"] + ig["y_m"]


def spread_scenario(wind_20ft_mps: float, start_s: float = 0.0, uavs: int = 1, max_duration_s: float = 900.0):
    """The shipped scenario over the whole landscape: its ignition lit at ``start_s`` [s], the wind
    from the west."""
    from fire_uav_common.landscape import load_landscape, read_landscape_spec
    from fire_uav_common.scenario import load_scenario

    x0, y0, x1, y1 = load_landscape(read_landscape_spec(LAND)).bounds
    px, py = spread_ignition()
    return load_scenario(
        SCENARIO,
        overrides={
            "fires.raster.landscape.window": None,
            "area": {"x_min_m": 0.0, "y_min_m": 0.0, "x_max_m": x1 - x0, "y_max_m": y1 - y0},
            "fires.raster.ignitions": [{"x_m": px - x0, "y_m": py - y0, "start_s": start_s}],
            "fires.raster.wind": [
                {"start_s": min(start_s, 0.0), "speed_mps": wind_20ft_mps, "direction_deg": 0.0}
            ],
            "uavs.count": uavs,
            "timing.max_duration_s": max_duration_s,
        },
    )


def spread_ours(hours: float, wind_20ft_mps: float) -> dict[str, object]:
    """A free fire over the whole landscape with the world's raster model; burned mask row 0 north."""
    from fire_world_sim.fires.raster import RasterFireModel

    sc = spread_scenario(wind_20ft_mps)
    t0 = time.process_time()
    model = RasterFireModel(sc.fires.raster, sc.terrain, lakes=sc.lakes)  # type: ignore[arg-type]
    setup_s = time.process_time() - t0
    t0 = time.process_time()
    t = 0.0
    while t < hours * 3600.0 - 1e-9:
        model.step(t, 1.0)
        t += 1.0
    cpu_s = time.process_time() - t0
    burned = (model.state_grid() != 0)[::-1]
    arrival_s = model.t_ign[model._inner][::-1]  # [s] each cell's ignition time, inf unburned
    return {"cpu_s": cpu_s, "setup_cpu_s": setup_s, "burned": burned, "arrival_s": arrival_s}


def spread_pyretechnics(hours: float, wind_20ft_mps: float, ignition: tuple[float, float], out: Path) -> None:
    """The same fire with pyretechnics (run in its own venv); saves its burned mask, row 0 north."""
    import rasterio
    from pyretechnics.eulerian_level_set import SpreadState, spread_fire_with_phi_field
    from pyretechnics.space_time_cube import SpaceTimeCube

    layers = read_layers()
    rows, cols = layers["fuel"].shape
    shape = (1, rows, cols)
    m = SPREAD_MOISTURE
    cubes = {
        "slope": SpaceTimeCube(shape, layers["slope"].astype(np.float32)),
        "aspect": SpaceTimeCube(
            shape, np.where(layers["aspect"] < 0, 0.0, layers["aspect"]).astype(np.float32)
        ),
        "fuel_model": SpaceTimeCube(shape, layers["fuel"].astype(np.float32)),
        "canopy_cover": SpaceTimeCube(shape, layers["canopy_cover"].astype(np.float32)),
        "canopy_height": SpaceTimeCube(shape, layers["canopy_height"].astype(np.float32)),
        "canopy_base_height": SpaceTimeCube(shape, layers["canopy_base_height"].astype(np.float32)),
        "canopy_bulk_density": SpaceTimeCube(shape, layers["canopy_bulk_density"].astype(np.float32)),
        "wind_speed_10m": SpaceTimeCube(shape, wind_20ft_mps * 3.6 * TEN_METRE_PER_20FT),
        "upwind_direction": SpaceTimeCube(shape, WIND_FROM_DEG),
        "fuel_moisture_dead_1hr": SpaceTimeCube(shape, m[0]),
        "fuel_moisture_dead_10hr": SpaceTimeCube(shape, m[1]),
        "fuel_moisture_dead_100hr": SpaceTimeCube(shape, m[2]),
        "fuel_moisture_live_herbaceous": SpaceTimeCube(shape, m[3]),
        "fuel_moisture_live_woody": SpaceTimeCube(shape, m[4]),
        "foliar_moisture": SpaceTimeCube(shape, SPREAD_FOLIAR),
    }
    with rasterio.open(LAND / "fbfm40.tif") as r:
        row, col = r.index(*ignition)
    minutes = hours * 60.0
    t0 = time.process_time()
    state = SpreadState(shape).ignite_cell((row, col))
    result = spread_fire_with_phi_field(cubes, state, (minutes + 1.0, 30.0, 30.0), 0.0, minutes)
    cpu_s = time.process_time() - t0
    mats = result["spread_state"].get_full_matrices(["phi", "fire_type"])
    np.savez(out, cpu_s=cpu_s, burned=mats["phi"] < 0.0, fire_type=mats["fire_type"])


GRASS_CELLS = 600  # the grass case: 600 x 600 cells of 30 m, fuel model 1 at 6 %, flat
GRASS_MOISTURE = 0.06


def grass_ignition() -> tuple[int, int]:
    """(row from the north, column) of the grass case's ignition: mid-height, 1/6 from the west."""
    return GRASS_CELLS // 2, GRASS_CELLS // 6


def spread_grass_ours(hours: float, wind_20ft_mps: float) -> dict[str, object]:
    """The grass case with the world's raster model (its wind is the midflame wind: the 20-ft
    wind times fuel model 1's unsheltered wind adjustment factor)."""
    from fire_uav_common.scenario import Ignition, Raster, Wind
    from fire_uav_common.terrain import Terrain
    from fire_world_sim.fires.fuel_models import fuel_model
    from fire_world_sim.fires.raster import RasterFireModel
    from fire_world_sim.fires.wind_adjustment import wind_adjustment_factor

    cs = 30.0
    waf = float(wind_adjustment_factor(fuel_model(1).depth_ft))
    row, col = grass_ignition()
    spec = Raster(
        cell_size_m=cs,
        nx=GRASS_CELLS,
        ny=GRASS_CELLS,
        fuel_model=1,
        moisture=GRASS_MOISTURE,
        wind=(Wind(0.0, wind_20ft_mps * waf, 0.0),),
        ignitions=(Ignition((col + 0.5) * cs, (GRASS_CELLS - row - 0.5) * cs, 0.0),),
    )
    t0 = time.process_time()
    model = RasterFireModel(spec, Terrain())
    setup_s = time.process_time() - t0
    t0 = time.process_time()
    t = 0.0
    while t < hours * 3600.0 - 1e-9:
        model.step(t, 1.0)
        t += 1.0
    cpu_s = time.process_time() - t0
    arrival_s = model.t_ign[model._inner][::-1]  # [s] each cell's ignition time, inf unburned
    return {
        "cpu_s": cpu_s,
        "setup_cpu_s": setup_s,
        "burned": (model.state_grid() != 0)[::-1],
        "arrival_s": arrival_s,
    }


def spread_grass_pyretechnics(hours: float, wind_20ft_mps: float, out: Path) -> None:
    from pyretechnics.eulerian_level_set import SpreadState, spread_fire_with_phi_field
    from pyretechnics.space_time_cube import SpaceTimeCube

    shape = (1, GRASS_CELLS, GRASS_CELLS)
    m = GRASS_MOISTURE
    cubes = {
        "slope": SpaceTimeCube(shape, 0.0),
        "aspect": SpaceTimeCube(shape, 0.0),
        "fuel_model": SpaceTimeCube(shape, 1),
        "canopy_cover": SpaceTimeCube(shape, 0.0),
        "canopy_height": SpaceTimeCube(shape, 0.0),
        "canopy_base_height": SpaceTimeCube(shape, 0.0),
        "canopy_bulk_density": SpaceTimeCube(shape, 0.0),
        "wind_speed_10m": SpaceTimeCube(shape, wind_20ft_mps * 3.6 * TEN_METRE_PER_20FT),
        "upwind_direction": SpaceTimeCube(shape, WIND_FROM_DEG),
        "fuel_moisture_dead_1hr": SpaceTimeCube(shape, m),
        "fuel_moisture_dead_10hr": SpaceTimeCube(shape, m),
        "fuel_moisture_dead_100hr": SpaceTimeCube(shape, m),
        "fuel_moisture_live_herbaceous": SpaceTimeCube(shape, 0.9),
        "fuel_moisture_live_woody": SpaceTimeCube(shape, 0.9),
        "foliar_moisture": SpaceTimeCube(shape, 1.0),
    }
    minutes = hours * 60.0
    t0 = time.process_time()
    state = SpreadState(shape).ignite_cell(grass_ignition())
    result = spread_fire_with_phi_field(cubes, state, (minutes + 1.0, 30.0, 30.0), 0.0, minutes)
    cpu_s = time.process_time() - t0
    mats = result["spread_state"].get_full_matrices(["phi"])
    np.savez(out, cpu_s=cpu_s, burned=mats["phi"] < 0.0)


def main_world(args: argparse.Namespace) -> None:
    """World steps (pure World, no agents, no ROS) with a fire lit ``--hours`` before t = 0 and
    ``--uavs`` UAVs flying scripted turns, over the whole landscape."""
    from bench_world import commands
    from fire_world_sim.world import World

    sc = spread_scenario(args.wind_20ft_mps, start_s=-args.hours * 3600.0, uavs=args.uavs, max_duration_s=1e6)
    t0 = time.process_time()
    world = World(sc, 0, args.uavs)
    setup_s = time.process_time() - t0
    times = []
    cpu0 = time.process_time()
    r = None
    for k in range(args.steps):
        t = time.process_time()
        r = world.step(commands(args.uavs, k))
        times.append(time.process_time() - t)
    cpu_s = time.process_time() - cpu0
    assert r is not None
    times.sort()
    sim_s = args.steps * world.control_period_s
    print(
        json.dumps(
            {
                "uavs": args.uavs,
                "fire_lit_hours_before": args.hours,
                "wind_20ft_mps_from_west": args.wind_20ft_mps,
                "grid_cells": int(world.fires.nx * world.fires.ny),  # type: ignore[attr-defined]
                "fire_cells_burned_or_burning": int(sum(f.area_m2 for f in r.fires) / 900.0),
                "setup_cpu_s_incl_preburn": round(setup_s, 2),
                "control_period_s": world.control_period_s,
                "steps": args.steps,
                "step_cpu_ms_mean": round(1000 * sum(times) / len(times), 2),
                "step_cpu_ms_p95": round(1000 * times[int(0.95 * (len(times) - 1))], 2),
                "step_cpu_ms_max": round(1000 * times[-1], 2),
                "sim_s_per_cpu_s": round(sim_s / cpu_s, 2),
            },
            indent=2,
        )
    )


def load_kernels() -> float:
    """Load the raster fire's compiled kernels (from their on-disk cache, or compile them) by
    burning a small fire for two minutes; returns its CPU seconds. A process pays this once
    (numba loads a kernel at its first call), so it is kept out of the spread's own time."""
    from fire_uav_common.scenario import Ignition, Raster, Wind
    from fire_uav_common.terrain import Terrain
    from fire_world_sim.fires.raster import RasterFireModel

    t0 = time.process_time()
    spec = Raster(
        cell_size_m=30.0,
        nx=20,
        ny=20,
        fuel_model=1,
        moisture=GRASS_MOISTURE,
        wind=(Wind(0.0, 2.0, 0.0),),
        ignitions=(Ignition(300.0, 300.0, 0.0),),
    )
    model = RasterFireModel(spec, Terrain())
    for k in range(120):
        model.step(float(k), 1.0)
    return time.process_time() - t0


def main_spread(args: argparse.Namespace) -> None:
    load_s = load_kernels()
    ours = (spread_grass_ours if args.grass else spread_ours)(args.hours, args.wind_20ft_mps)
    n_ours = int(np.sum(ours["burned"]))  # type: ignore[call-overload]
    report: dict[str, object] = {
        "case": "grass 600 x 600, fuel model 1" if args.grass else "worcester_vt",
        "free_spread_hours": args.hours,
        "wind_20ft_mps_from_west": args.wind_20ft_mps,
        "ours_cells_burned": n_ours,
        "ours_cpu_s": round(float(ours["cpu_s"]), 2),  # type: ignore[arg-type]
        "ours_setup_cpu_s": round(float(ours["setup_cpu_s"]), 2),  # type: ignore[arg-type]
        "ours_kernel_load_cpu_s": round(load_s, 2),
        "ours_cells_per_cpu_s": round(n_ours / float(ours["cpu_s"])),  # type: ignore[arg-type]
    }
    if args.pyretechnics_python:
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "pyretechnics.npz"
            cmd = [str(args.pyretechnics_python), __file__, "--spread", "--as-pyretechnics", str(out)]
            cmd += ["--hours", str(args.hours), "--wind-20ft-mps", str(args.wind_20ft_mps)]
            cmd += ["--grass"] if args.grass else ["--ignition", *map(str, spread_ignition())]
            subprocess.run(cmd, check=True)
            theirs = dict(np.load(out))
        n_theirs = int(theirs["burned"].sum())
        both = ours["burned"] & theirs["burned"]  # type: ignore[operator]
        either = ours["burned"] | theirs["burned"]  # type: ignore[operator]
        report |= {
            "pyretechnics_cells_burned": n_theirs,
            "pyretechnics_cpu_s": round(float(theirs["cpu_s"]), 2),
            "pyretechnics_cells_per_cpu_s": round(n_theirs / float(theirs["cpu_s"])),
            "burned_area_ratio_ours_over_pyretechnics": round(n_ours / max(n_theirs, 1), 3),
            "burned_intersection_over_union": round(float(both.sum() / max(either.sum(), 1)), 3),
        }
    print(json.dumps(report, indent=2))
    if args.pyretechnics_python:  # the row of docs/fire_behavior.md's table
        r = report
        rate = float(r["ours_cells_per_cpu_s"]) / float(r["pyretechnics_cells_per_cpu_s"])  # type: ignore[arg-type]
        cells = (
            f"{r['ours_cells_burned']:,} / {r['ours_cpu_s']} | {r['ours_cells_per_cpu_s']:,} | "
            f"{r['pyretechnics_cells_burned']:,} / {r['pyretechnics_cpu_s']} | {r['pyretechnics_cells_per_cpu_s']:,}"
        )
        print(
            f"| {'grass 600 x 600' if args.grass else 'worcester_vt'} | {args.hours:g} | {args.wind_20ft_mps:g} | "
            f"{cells} | {rate:.2f} | {r['burned_area_ratio_ours_over_pyretechnics']:.2f} | "
            f"{r['burned_intersection_over_union']:.3f} |"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--wind-20ft-mps", type=float, default=0.0)
    ap.add_argument("--pyretechnics-python", type=Path, help="python of a venv with pyretechnics installed")
    ap.add_argument(
        "--spread", action="store_true", help="free-burning spread instead of the per-cell kernel"
    )
    ap.add_argument(
        "--grass", action="store_true", help="--spread: 600 x 600 cells of 30 m of fuel model 1 at 6 %%, flat"
    )
    ap.add_argument("--hours", type=float, default=2.0, help="--spread / --world: hours of fire (default 2)")
    ap.add_argument(
        "--world", action="store_true", help="world step time with a landscape fire and --uavs UAVs"
    )
    ap.add_argument("--uavs", type=int, default=20, help="--world: UAVs (default 20)")
    ap.add_argument("--steps", type=int, default=600, help="--world: control steps timed (default 600)")
    ap.add_argument("--as-pyretechnics", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--ignition", type=float, nargs=2, help=argparse.SUPPRESS)  # the venv there has no yaml
    args = ap.parse_args()
    if args.spread and args.as_pyretechnics and args.grass:
        spread_grass_pyretechnics(args.hours, args.wind_20ft_mps, args.as_pyretechnics)
        return
    if args.spread and args.as_pyretechnics:
        spread_pyretechnics(args.hours, args.wind_20ft_mps, tuple(args.ignition), args.as_pyretechnics)
        return
    if args.world:
        main_world(args)
        return
    if args.spread:
        main_spread(args)
        return
    if args.as_pyretechnics:
        run_pyretechnics(args.reps, args.wind_20ft_mps, args.as_pyretechnics)
        return
    ours_s, ours = run_ours(args.reps, args.wind_20ft_mps)
    cells = ours["ros_mps"].size
    report: dict[str, object] = {
        "cells": cells,
        "wind_20ft_mps": args.wind_20ft_mps,
        "ours_cpu_s": round(ours_s, 3),
        "ours_cells_per_cpu_s": round(cells / ours_s),
    }
    if args.pyretechnics_python:
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "pyretechnics.npz"
            cmd = [str(args.pyretechnics_python), __file__, "--as-pyretechnics", str(out)]
            cmd += ["--reps", str(args.reps), "--wind-20ft-mps", str(args.wind_20ft_mps)]
            subprocess.run(cmd, check=True)
            theirs = dict(np.load(out))
        inside = ~ours["outside"]
        burns = inside & (theirs["ros_mps"] > 0) & (ours["ros_mps"] > 0)
        rel = np.abs(ours["ros_mps"][burns] - theirs["ros_mps"][burns]) / theirs["ros_mps"][burns]
        report |= {
            "pyretechnics_cpu_s": round(float(theirs["cpu_s"]), 3),
            "pyretechnics_cells_per_cpu_s": round(cells / float(theirs["cpu_s"])),
            "speed_ratio_ours_over_pyretechnics": round(float(theirs["cpu_s"]) / ours_s, 2),
            "same_fire_type_fraction": round(
                float((ours["fire_type"] == theirs["fire_type"])[inside].mean()), 5
            ),
            "rate_rel_diff_median": float(np.median(rel)),
            "rate_rel_diff_p99": float(np.percentile(rel, 99)),
            "rate_rel_diff_max": float(rel.max()),
        }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
