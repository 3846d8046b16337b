"""``scripts/fire_behavior``: fire behaviour over a landscape, like FlamMap's basic run (no ROS).

    scripts/fire_behavior LANDSCAPE --out DIR [--wind-20ft-mps U] [--wind-from-deg D]
        [--wind-grid VEL.asc,ANG.asc | --wind-grid WIND.tif] [--wind-speed-units mph|mps|kph|kts]
        [--moisture 1H,10H,100H,HERB,WOODY] [--fms FILE] [--foliar-moisture F] [--crown none|finney]

LANDSCAPE is a landscape YAML, a directory holding ``landscape.yaml``, or the name of a landscape
shipped in ``data/landscapes/`` (e.g. ``worcester_vt``). Writes, on the landscape's grid and CRS,
``ros_mps.tif`` (head rate of spread), ``spread_dir_deg.tif`` (its direction, clockwise from north),
``fireline_intensity_kwpm.tif``, ``flame_length_m.tif``, ``fire_type.tif`` (0 unburnable, 1
surface, 2 passive crown, 3 active crown) and a PNG of each. Cells outside the landscape's data
are nodata (-9999, 255 for the fire type). ``--wind-grid`` replaces the uniform wind by a gridded
20-ft wind: WindNinja's ASCII pair (speed, direction it blows from) or a 2-band GeoTIFF, in the
landscape's CRS, resampled to its cells (:mod:`fire_uav_common.scenario.wind_grid`; its speed unit
``--wind-speed-units``, WindNinja's default mph unless given). Bad input: one line on stderr,
exit status 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from fire_uav_common.landscape import Landscape, LandscapeError, load_landscape, read_landscape_spec
from fire_uav_common.scenario.types import DEFAULT_SPEED_UNITS, SPEED_UNITS
from fire_uav_common.scenario.wind_grid import parse_wind_grid_arg, wind_on_landscape

from .behavior import CROWN_METHODS, FireBehavior, FuelMoistures, fire_behavior, parse_moisture, read_fms
from .crown import FireType

__all__ = ["LAYER_FILES", "landscape_path", "main", "write_outputs"]

FLOAT_NODATA = -9999.0
TYPE_NODATA = 255
LAYER_FILES = {
    "ros_mps": "head rate of spread [m/s]",
    "spread_dir_deg": "direction of spread [deg clockwise from north]",
    "fireline_intensity_kwpm": "fireline intensity [kW/m]",
    "flame_length_m": "flame length [m]",
    "fire_type": "fire type",
}
FIRE_TYPE_NAMES = ("unburnable", "surface", "passive crown", "active crown")


def repo_root() -> Path:
    return Path(__file__).resolve().parents[5]


def landscape_path(arg: str) -> Path:
    """A path as given, else the shipped ``data/landscapes/<name>``; LandscapeError if neither."""
    p = Path(arg)
    if p.exists():
        return p
    shipped = repo_root() / "data" / "landscapes" / arg
    if shipped.is_dir():
        return shipped
    raise LandscapeError(f"{arg}: no such landscape file, directory or shipped landscape name")


def write_outputs(out: Path, land: Landscape, b: FireBehavior) -> list[Path]:
    """The five GeoTIFFs (DEFLATE) and their PNGs; returns the paths written."""
    import rasterio
    from rasterio.transform import Affine

    out.mkdir(parents=True, exist_ok=True)
    outside = ~land.has_data
    layers = {
        "ros_mps": b.ros_mps,
        "spread_dir_deg": b.spread_dir_deg,
        "fireline_intensity_kwpm": b.fireline_intensity_kwpm,
        "flame_length_m": b.flame_length_m,
    }
    rows, cols = land.shape
    common = {
        "driver": "GTiff",
        "height": rows,
        "width": cols,
        "count": 1,
        "crs": rasterio.crs.CRS.from_wkt(land.crs_wkt),
        "transform": Affine(*land.transform),
        "compress": "deflate",
    }
    written = []
    for name, values in layers.items():
        path = out / f"{name}.tif"
        data = np.where(outside, FLOAT_NODATA, values).astype(np.float32)
        with rasterio.open(path, "w", dtype="float32", nodata=FLOAT_NODATA, **common) as dst:
            dst.write(data, 1)
            dst.set_band_description(1, LAYER_FILES[name])
        written.append(path)
    path = out / "fire_type.tif"
    with rasterio.open(path, "w", dtype="uint8", nodata=TYPE_NODATA, **common) as dst:
        dst.write(np.where(outside, TYPE_NODATA, b.fire_type).astype(np.uint8), 1)
        dst.set_band_description(1, "fire type: 0 unburnable, 1 surface, 2 passive crown, 3 active crown")
    written.append(path)
    written += _pngs(out, land, {**layers, "fire_type": b.fire_type.astype(float)}, outside)
    return written


def _pngs(out: Path, land: Landscape, layers: dict[str, np.ndarray], outside: np.ndarray) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap

    x0, y0, x1, y1 = land.bounds
    extent = (x0 / 1000.0, x1 / 1000.0, y0 / 1000.0, y1 / 1000.0)
    written = []
    for name, values in layers.items():
        fig, ax = plt.subplots(figsize=(6, 6))
        masked = np.ma.masked_where(outside, values)
        if name == "fire_type":
            cmap = ListedColormap(["#bdbdbd", "#fdae61", "#d7191c", "#67001f"])
            im = ax.imshow(masked, extent=extent, cmap=cmap, norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4))
            cb = fig.colorbar(im, ax=ax, ticks=[0, 1, 2, 3], shrink=0.8)
            cb.ax.set_yticklabels(FIRE_TYPE_NAMES)
        else:
            cmap_name = "twilight" if name == "spread_dir_deg" else "inferno"
            im = ax.imshow(masked, extent=extent, cmap=cmap_name)
            fig.colorbar(im, ax=ax, shrink=0.8, label=LAYER_FILES[name])
        ax.set_title(LAYER_FILES[name])
        ax.set_xlabel("x [km]")
        ax.set_ylabel("y [km]")
        path = out / f"{name}.png"
        fig.savefig(path, dpi=80)
        plt.close(fig)
        written.append(path)
    return written


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(prog="fire_behavior", description=__doc__.split("\n\n")[0])
    ap.add_argument("landscape", help="landscape YAML, a directory with landscape.yaml, or a shipped name")
    ap.add_argument("--out", required=True, type=Path, help="output directory")
    ap.add_argument("--wind-20ft-mps", type=float, default=0.0, help="20-ft wind speed [m/s] (default 0)")
    ap.add_argument("--wind-from-deg", type=float, default=0.0, help="wind blows from [deg cw from north]")
    ap.add_argument(
        "--wind-grid",
        metavar="VEL.asc,ANG.asc|WIND.tif",
        help="gridded 20-ft wind instead of the uniform one: WindNinja's *_vel.asc,*_ang.asc or a 2-band GeoTIFF",
    )
    ap.add_argument(
        "--wind-speed-units",
        choices=sorted(SPEED_UNITS),
        default=DEFAULT_SPEED_UNITS,
        help=f"speed unit of --wind-grid (default {DEFAULT_SPEED_UNITS}, WindNinja's default output)",
    )
    ap.add_argument(
        "--moisture",
        default="0.06,0.08,0.10,0.75,0.60",
        help="1H,10H,100H,HERB,WOODY fractions (default 6/8/10/75/60 %%)",
    )
    ap.add_argument(
        "--fms", type=Path, help="FlamMap FMS file: per-model moistures [%%] (overrides --moisture)"
    )
    ap.add_argument(
        "--foliar-moisture", type=float, default=1.0, help="foliar moisture [fraction] (default 1.0)"
    )
    ap.add_argument("--crown", choices=CROWN_METHODS, default="none", help="crown fire method (default none)")
    ap.add_argument("--wind-limit", choices=("behave", "andrews2013", "none"), default="behave")
    return ap.parse_args(argv)


def run(args: argparse.Namespace) -> tuple[Landscape, FireBehavior]:
    land = load_landscape(read_landscape_spec(landscape_path(args.landscape)))
    moistures = read_fms(args.fms) if args.fms else FuelMoistures(parse_moisture(args.moisture))
    fuel = np.where(land.has_data, land.fuel, 99)  # outside the data: as barren, then masked on output
    speed: float | np.ndarray = args.wind_20ft_mps
    from_deg: float | np.ndarray = args.wind_from_deg
    if args.wind_grid:
        w = wind_on_landscape(parse_wind_grid_arg(args.wind_grid, args.wind_speed_units), land)
        speed, from_deg = w.speed_mps, w.from_deg
    b = fire_behavior(
        fuel,
        land.slope_pct,
        land.aspect_deg,
        wind_20ft_mps=speed,
        wind_from_deg=from_deg,
        moistures=moistures,
        canopy_cover=land.canopy_cover,
        canopy_height_m=land.canopy_height_m,
        canopy_base_height_m=land.canopy_base_height_m,
        canopy_bulk_density_kgpm3=land.canopy_bulk_density_kgpm3,
        foliar_moisture=args.foliar_moisture,
        crown=args.crown,
        wind_limit=args.wind_limit,
    )
    return land, b


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        land, b = run(args)
        write_outputs(args.out, land, b)
    except (LandscapeError, ValueError, OSError) as e:
        sys.stderr.write(f"fire_behavior: error: {e}\n")
        return 2
    inside = land.has_data
    counts = {FIRE_TYPE_NAMES[t]: int(((b.fire_type == t) & inside).sum()) for t in FireType}
    lon, lat = land.lonlat(
        *(0.5 * (land.bounds[0] + land.bounds[2]), 0.5 * (land.bounds[1] + land.bounds[3]))
    )
    sys.stdout.write(
        f"fire_behavior: {land.shape[0]} x {land.shape[1]} cells of {land.cell_size_m:g} m, centre "
        f"{lat:.4f} N {lon:.4f} E; max head rate {b.ros_mps[inside].max():.3f} m/s, "
        f"max flame {b.flame_length_m[inside].max():.1f} m; cells by fire type {counts}; wrote {args.out}\n"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
