"""A scenario on real ground: the raster fire's grid, the terrain and the lakes from a landscape.

``fires.raster.landscape`` names a LANDFIRE landscape (:mod:`fire_uav_common.landscape`): a
shipped name (``data/landscapes/<name>``) or a landscape file / directory relative to the
scenario file. :func:`apply_landscape` reads its window once and derives

- the raster grid: cell size, ``nx`` x ``ny`` cells, origin (0, 0) at the window's south-west
  corner; the map frame is the landscape's projected metres minus that corner;
- the terrain: a :class:`~fire_uav_common.terrain.GridTerrain` of the elevation layer, served to
  the world (ground, altimeter, collisions) and to the agents (their a-priori map) alike;
- the lakes: every body of open water (fuel code 98) becomes a lake by its real outline, its
  water cells (:class:`~fire_uav_common.water.WaterCells`): a UAV is over the lake when the cell
  under it is water. Each lake also carries the largest disc inside it (its centre the water
  cell farthest from the shore, its diameter twice that distance), where the agents aim, and its
  longest straight run over water (:func:`~fire_uav_common.water.longest_straight_run`). A body
  whose disc is narrower than ``min_lake_diameter_m``, or (under a fixed-wing airframe) whose
  longest run is shorter than the airframe's scoop run, is too small for a refill pass: left
  out, with a note in ``Scenario.notes`` that the world logs and summary.json and the report
  show. When that leaves a fixed-wing fleet no lake at all, the scenario is refused.

Every ignition must lie on a burnable cell of the window. Errors name the file and the field.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from pathlib import Path

import numpy as np

from ..landscape import Landscape, LandscapeError, load_landscape, read_landscape_spec
from ..terrain import GridTerrain, Lake, Terrain
from ..water import WaterCells, longest_straight_run
from .fields import _Ctx
from .types import RasterLandscape, Scenario, Wind, WindGrid
from .wind_grid import WindOnLandscape, grid_mean_wind, wind_on_landscape

__all__ = [
    "OPEN_WATER",
    "apply_landscape",
    "geo_summary",
    "landscape_of",
    "resolve_landscape_source",
    "water_lakes",
    "wind_cells",
]

OPEN_WATER = 98  # LANDFIRE FBFM13/FBFM40 code of open water


def _repo_root() -> Path:
    return Path(__file__).resolve().parents[5]


def resolve_landscape_source(ctx: _Ctx, name: str, path: str) -> str:
    """The absolute landscape file or directory ``name`` stands for: a path relative to the
    scenario file, else a landscape shipped in ``data/landscapes/``."""
    base = ctx.base_dir()
    p = (base / name).resolve()
    if p.exists():
        return str(p)
    shipped = _repo_root() / "data" / "landscapes" / name
    if shipped.is_dir():
        return str(shipped)
    raise ctx.fail(
        path,
        f"{name!r} is neither a landscape file or directory (relative to the scenario) nor a shipped landscape name",
    )


@functools.lru_cache(maxsize=4)
def _load(
    source: str, window: tuple[float, float, float, float] | None, cell_size_m: float | None
) -> Landscape:
    overrides: dict[str, object] = {}
    if window is not None:
        overrides["window"] = dict(zip(("x_min_m", "y_min_m", "x_max_m", "y_max_m"), window, strict=True))
    if cell_size_m is not None:
        overrides["cell_size_m"] = cell_size_m
    return load_landscape(read_landscape_spec(source, overrides))


def landscape_of(land: RasterLandscape) -> Landscape:
    """The landscape window ``land`` names (read once per process). Raises LandscapeError."""
    return _load(land.source, land.window, land.cell_size_m)


def water_lakes(
    landscape: Landscape, min_diameter_m: float, min_run_m: float = 0.0, run_owner: str = "the airframe's"
) -> tuple[list[Lake], list[str]]:
    """A lake per open-water body (its water cells, the largest disc inside it and its longest
    straight run), in projected metres, and a note per body left out as too small for a refill
    pass: its disc narrower than ``min_diameter_m``, or its longest run shorter than
    ``min_run_m`` (a fixed-wing's scoop run; ``run_owner`` names whose, e.g. "the tanker
    preset's")."""
    from scipy import ndimage

    water = landscape.fuel == OPEN_WATER
    labels, n = ndimage.label(water)
    # distance to the nearest non-water cell centre [cells]; the map's edge counts as shore
    dist = ndimage.distance_transform_edt(np.pad(water, 1))[1:-1, 1:-1]
    lakes: list[Lake] = []
    notes: list[str] = []
    cs = landscape.cell_size_m
    for k in range(1, n + 1):
        body = labels == k
        flat = int(np.argmax(np.where(body, dist, 0.0)))
        r, c = (int(v) for v in np.unravel_index(flat, body.shape))
        x, y = landscape.cell_center(r, c)
        # the disc reaches half a cell short of the nearest shore cell's centre
        diameter = 2.0 * (float(dist[r, c]) - 0.5) * cs
        area_ha = float(body.sum()) * cs * cs / 1e4
        if diameter < max(min_diameter_m, 1e-9):
            notes.append(
                f"open water at ({float(x):.0f}, {float(y):.0f}) m ({area_ha:.1f} ha) left out: its widest "
                f"disc ({diameter:.0f} m) is narrower than a refill pass needs ({min_diameter_m:g} m)"
            )
            continue
        rows, cols = np.nonzero(body)
        r0, r1, c0, c1 = int(rows.min()), int(rows.max()) + 1, int(cols.min()), int(cols.max()) + 1
        left, _, _, top = landscape.bounds
        cells = WaterCells(  # flipped: row 0 the southern row, as the map frame
            x0_m=left + c0 * cs, y0_m=top - r1 * cs, cell_m=cs, mask=body[r0:r1, c0:c1][::-1]
        )
        run = longest_straight_run(cells)
        if run.length_m < min_run_m:
            notes.append(
                f"open water at ({float(x):.0f}, {float(y):.0f}) m ({area_ha:.1f} ha) left out: its longest "
                f"straight run ({run.length_m:.0f} m) is shorter than {run_owner} {min_run_m:.0f} m scoop run"
            )
            continue
        lakes.append(Lake(float(x), float(y), diameter, water=cells, run=run))
    return lakes, notes


@functools.lru_cache(maxsize=8)
def wind_cells(
    grid: WindGrid, source: str, window: tuple[float, float, float, float] | None, cell_size_m: float | None
) -> WindOnLandscape:
    """A wind grid resampled to the landscape window a scenario names (:func:`.wind_grid.wind_on_landscape`),
    read once per process. Raises WindGridError (a LandscapeError)."""
    return wind_on_landscape(grid, _load(source, window, cell_size_m))


def _gridded_winds(
    ctx: _Ctx, winds: tuple[Wind, ...], land: RasterLandscape, landscape: Landscape
) -> tuple[Wind, ...]:
    """Each wind entry with a grid, its grid read, checked and resampled to the landscape once
    (an error names the entry); a grid entry without ``speed_mps`` gets the grid's mean wind."""
    out = []
    for i, w in enumerate(winds):
        if w.grid is not None:
            try:
                cells = wind_cells(w.grid, land.source, land.window, land.cell_size_m)
            except LandscapeError as e:
                raise ctx.fail(f"fires.raster.wind[{i}].grid", str(e)) from None
            if math.isnan(w.speed_mps):
                speed, toward = grid_mean_wind(cells, landscape)
                w = dataclasses.replace(w, speed_mps=round(speed, 6), direction_deg=round(toward, 6))
        out.append(w)
    return tuple(out)


def apply_landscape(
    ctx: _Ctx, scenario: Scenario, *, terrain_given: bool, run_owner: str = "the airframe's"
) -> Scenario:
    """``scenario`` with its raster grid, terrain and lakes from ``fires.raster.landscape``.

    Under a fixed-wing airframe a water body shorter than its scoop run is left out; if no lake
    is left at all (none written in the scenario either), a :class:`ScenarioError` names the
    field: the fleet could never refill. ``run_owner`` names the preset in these lines."""
    raster = scenario.fires.raster
    if raster is None or raster.landscape is None:
        return scenario
    p = "fires.raster.landscape"
    land = raster.landscape
    try:
        landscape = landscape_of(land)
    except LandscapeError as e:
        raise ctx.fail(p, str(e)) from None
    if terrain_given:
        raise ctx.fail("terrain", f"set by {p} (its elevation layer): remove it")
    x0, y0, _, _ = landscape.bounds
    rows, cols = landscape.shape
    cs = landscape.cell_size_m
    for i, ig in enumerate(raster.ignitions):
        try:
            landscape.require_burnable(ig.x_m + x0, ig.y_m + y0, "ignition")
        except LandscapeError as e:
            raise ctx.fail(
                f"fires.raster.ignitions[{i}]", f"({ig.x_m:g}, {ig.y_m:g}) m in the map frame: {e}"
            ) from None
    grid = dataclasses.replace(
        raster,
        cell_size_m=cs,
        nx=cols,
        ny=rows,
        wind=_gridded_winds(ctx, raster.wind, land, landscape),
        landscape=dataclasses.replace(land, projected_origin=(x0, y0)),
    )
    elevation = np.ascontiguousarray(landscape.elevation_m[::-1])  # row 0 south, as the raster fire
    terrain: Terrain = GridTerrain(elevation_m=elevation, x0_m=0.0, y0_m=0.0, cell_m=cs, source=land.name)
    airframe = scenario.uavs.airframe
    need = 0.0 if airframe is None else airframe.scoop_run_m
    found, notes = water_lakes(landscape, land.min_lake_diameter_m, need, run_owner)
    lakes = [lk.shifted(-x0, -y0) for lk in found]
    lakes = [lk for lk in lakes if scenario.area.contains(lk.x_m, lk.y_m)]
    # water there was, but none a fixed-wing can scoop from: its fleet could never refill
    if need > 0 and not lakes and not scenario.lakes and notes:
        raise ctx.fail(
            p,
            f"no lake left for refills: every water body's longest straight run is shorter than "
            f"{run_owner} {need:.0f} m scoop run (or its disc narrower than min_lake_diameter_m "
            f"{land.min_lake_diameter_m:g} m)",
        )
    notes = [f"{p}: {n}" for n in notes]
    return dataclasses.replace(
        scenario,
        fires=dataclasses.replace(scenario.fires, raster=grid),
        terrain=terrain,
        lakes=(*scenario.lakes, *lakes),
        notes=(*scenario.notes, *notes),
    )


def geo_summary(scenario: Scenario, uav_count: int | None = None) -> dict | None:
    """WGS84 latitude / longitude [deg] of the ignitions and the UAV homes of a scenario on a
    landscape (None without one), for the mission summary: people and map tools read degrees."""
    raster = scenario.fires.raster
    if raster is None or raster.landscape is None:
        return None
    land = raster.landscape
    ox, oy = land.projected_origin
    landscape = landscape_of(land)

    def point(x_m: float, y_m: float) -> dict[str, float]:
        lon, lat = landscape.lonlat(x_m + ox, y_m + oy)
        return {"x_m": x_m, "y_m": y_m, "lat_deg": round(float(lat), 6), "lon_deg": round(float(lon), 6)}

    return {
        "landscape": land.name,
        "projected_origin_m": [ox, oy],
        "ignitions": [point(ig.x_m, ig.y_m) for ig in raster.ignitions],
        "uav_homes": [point(x, y) for x, y, _, _ in scenario.uav_start_poses(uav_count)],
    }
