#!/usr/bin/env python3
"""Per-cell fire behaviour over a whole landscape: our numpy kernel against pyretechnics.

Usage (in the project's environment: ``source scripts/env.sh``):
    python scripts/bench_landscape.py [--reps N] [--wind-20ft-mps U] \
        [--pyretechnics-python /path/to/other/venv/bin/python]

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
        "aspect": SpaceTimeCube(shape, np.where(layers["aspect"] < 0, 0.0, layers["aspect"]).astype(np.float32)),
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--wind-20ft-mps", type=float, default=0.0)
    ap.add_argument("--pyretechnics-python", type=Path, help="python of a venv with pyretechnics installed")
    ap.add_argument("--as-pyretechnics", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
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
            "same_fire_type_fraction": round(float((ours["fire_type"] == theirs["fire_type"])[inside].mean()), 5),
            "rate_rel_diff_median": float(np.median(rel)),
            "rate_rel_diff_p99": float(np.percentile(rel, 99)),
            "rate_rel_diff_max": float(rel.max()),
        }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
