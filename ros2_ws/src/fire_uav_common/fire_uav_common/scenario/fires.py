"""Reader of the scenario's ``fires`` section: the analytic fires (FF IV-A) and the raster fire."""

from __future__ import annotations

import math
from typing import Any

from .fields import _choice, _Ctx, _int, _list, _mapping, _num, _record, _str
from .ground import _repo_root, resolve_landscape_source
from .types import (
    CROWN_METHODS,
    DEFAULT_SPEED_UNITS,
    DROP_MODELS,
    FIRE_MODELS,
    FUEL_MODELS,
    SPEED_UNITS,
    WIND_LIMITS,
    AnalyticFire,
    Fires,
    FuelPatch,
    Ignition,
    Moistures,
    Origin,
    Raster,
    RasterLandscape,
    Wind,
    WindGrid,
)

#: fields of ``fires.raster`` that a landscape sets (its grid) and the scenario may not repeat
_GRID_FIELDS = ("cell_size_m", "nx", "ny", "origin", "fuel_model", "fuel_patches", "moisture")


def _fuel_patch(ctx: _Ctx, item: Any, pp: str) -> FuelPatch:
    keys = {"x_min_m", "x_max_m", "y_min_m", "y_max_m", "fuel_model"}
    pd = _mapping(ctx, item, pp, keys, keys)
    fm = _choice(ctx, pd, "fuel_model", pp, FUEL_MODELS)
    x_min, x_max, y_min, y_max = (_num(ctx, pd, k, pp) for k in ("x_min_m", "x_max_m", "y_min_m", "y_max_m"))
    patch = FuelPatch(x_min_m=x_min, x_max_m=x_max, y_min_m=y_min, y_max_m=y_max, fuel_model=fm)
    if not (patch.x_max_m > patch.x_min_m and patch.y_max_m > patch.y_min_m):
        raise ctx.fail(pp, "must have x_max_m > x_min_m and y_max_m > y_min_m")
    return patch


def _grid_file(ctx: _Ctx, d: dict, key: str, p: str) -> str:
    """The absolute path of a wind grid file: relative to the scenario file, else under ``data/``."""
    name = _str(ctx, d, key, p)
    base = ctx.base_dir()
    for candidate in (base / name, _repo_root() / "data" / name):
        if candidate.is_file():
            return str(candidate.resolve())
    raise ctx.fail(f"{p}.{key}", f"{name!r}: file not found (relative to the scenario file, or under data/)")


def _wind_grid(ctx: _Ctx, raw: Any, p: str) -> WindGrid:
    """``fires.raster.wind[i].grid``: WindNinja's ASCII pair ``{vel, ang}`` or a 2-band GeoTIFF ``{tif}``."""
    d = _mapping(ctx, raw, p, {"vel", "ang", "tif", "speed_units"})
    units = _choice(ctx, d, "speed_units", p, tuple(SPEED_UNITS), DEFAULT_SPEED_UNITS)
    if "tif" in d:
        if "vel" in d or "ang" in d:
            raise ctx.fail(
                p, "either tif (a 2-band GeoTIFF) or vel and ang (WindNinja's ASCII pair), not both"
            )
        return WindGrid(_grid_file(ctx, d, "tif", p), None, units)
    if "vel" not in d and "ang" not in d:
        raise ctx.fail(p, "needs vel and ang (WindNinja's *_vel.asc, *_ang.asc) or tif (a 2-band GeoTIFF)")
    return WindGrid(_grid_file(ctx, d, "vel", p), _grid_file(ctx, d, "ang", p), units)


def _winds(ctx: _Ctx, d: dict, p: str) -> list[Wind]:
    """``fires.raster.wind`` entries, each starting after the previous one. An entry with a
    ``grid`` may leave out ``speed_mps`` and ``direction_deg`` (both, or give both): they are
    then the grid's mean wind, filled in by :func:`.ground.apply_landscape` (NaN until then)."""
    winds: list[Wind] = []
    for i, item in enumerate(_list(ctx, d, "wind", p)):
        wp = f"{p}.wind[{i}]"
        wd = _mapping(ctx, item, wp, {"start_s", "speed_mps", "direction_deg", "grid"})
        grid = _wind_grid(ctx, wd["grid"], f"{wp}.grid") if wd.get("grid") is not None else None
        if grid is not None and ("speed_mps" in wd) != ("direction_deg" in wd):
            raise ctx.fail(
                wp, "with a grid give both speed_mps and direction_deg (the domain wind) or neither"
            )
        dflt = math.nan if grid is not None else None
        w = Wind(
            start_s=_num(ctx, wd, "start_s", wp, 0.0),
            speed_mps=_num(ctx, wd, "speed_mps", wp, dflt, ge=0),
            direction_deg=_num(ctx, wd, "direction_deg", wp, dflt),
            grid=grid,
        )
        if winds and not w.start_s > winds[-1].start_s:
            raise ctx.fail(
                f"{wp}.start_s", f"must be > the previous start_s ({winds[-1].start_s:g}), got {w.start_s:g}"
            )
        winds.append(w)
    return winds


def _landscape(ctx: _Ctx, raw: Any, p: str) -> RasterLandscape:
    """``fires.raster.landscape``: the landscape (a shipped name or a path relative to the scenario
    file), its window in projected metres, the cell size and the fuel moistures."""
    keys = {"source", "window", "cell_size_m", "moisture", "foliar_moisture", "crown", "min_lake_diameter_m"}
    d = _mapping(ctx, raw, p, keys, {"source"})
    name = _str(ctx, d, "source", p)
    source = resolve_landscape_source(ctx, name, f"{p}.source")
    window = None
    if d.get("window") is not None:
        wk = ("x_min_m", "y_min_m", "x_max_m", "y_max_m")
        wd = _mapping(ctx, d["window"], f"{p}.window", set(wk), set(wk))
        x0, y0, x1, y1 = (_num(ctx, wd, k, f"{p}.window") for k in wk)
        if not (x1 > x0 and y1 > y0):
            raise ctx.fail(f"{p}.window", "must have x_max_m > x_min_m and y_max_m > y_min_m")
        window = (x0, y0, x1, y1)
    cell = _num(ctx, d, "cell_size_m", p, gt=0) if d.get("cell_size_m") is not None else None
    moisture = _record(
        ctx,
        d.get("moisture"),
        Moistures,
        f"{p}.moisture",
        bounds=dict.fromkeys(Moistures.__dataclass_fields__, {"gt": 0, "le": 5}),
    )
    return RasterLandscape(
        source=source,
        name=name,
        window=window,
        cell_size_m=cell,
        moisture=moisture,
        foliar_moisture=_num(ctx, d, "foliar_moisture", p, 1.0, gt=0, le=5),
        crown=_choice(ctx, d, "crown", p, CROWN_METHODS, "finney"),
        min_lake_diameter_m=_num(ctx, d, "min_lake_diameter_m", p, 60.0, ge=0),
    )


def _raster(ctx: _Ctx, raw: Any) -> Raster:
    p = "fires.raster"
    d = _mapping(ctx, raw, p, set(Raster.__dataclass_fields__))
    land = _landscape(ctx, d["landscape"], f"{p}.landscape") if d.get("landscape") is not None else None
    if land is not None:
        for k in _GRID_FIELDS:
            if k in d:
                raise ctx.fail(f"{p}.{k}", "set by fires.raster.landscape: remove it")
    dflt = Raster()
    origin = _record(ctx, d.get("origin"), Origin, f"{p}.origin")
    fuel = _choice(ctx, d, "fuel_model", p, FUEL_MODELS, dflt.fuel_model)
    patches = tuple(
        _fuel_patch(ctx, item, f"{p}.fuel_patches[{i}]")
        for i, item in enumerate(_list(ctx, d, "fuel_patches", p))
    )
    winds = _winds(ctx, d, p)
    if land is None:
        for i, w in enumerate(winds):
            if w.grid is not None:
                raise ctx.fail(
                    f"{p}.wind[{i}].grid",
                    "needs fires.raster.landscape (a wind grid is placed on it by its CRS)",
                )
    ignitions = tuple(
        _record(ctx, item, Ignition, f"{p}.ignitions[{i}]")
        for i, item in enumerate(_list(ctx, d, "ignitions", p))
    )
    first = min([0.0, *(ig.start_s for ig in ignitions)])  # a fire may already burn at t = 0
    if not winds:
        winds = [Wind(first, dflt.wind[0].speed_mps, dflt.wind[0].direction_deg)]
    elif winds[0].start_s > first:
        raise ctx.fail(
            f"{p}.wind[0].start_s",
            f"must be 0 or earlier: at or before the earliest ignition ({first:g}), got {winds[0].start_s:g}",
        )
    r = Raster(
        cell_size_m=_num(ctx, d, "cell_size_m", p, dflt.cell_size_m, gt=0),
        nx=_int(ctx, d, "nx", p, dflt.nx, ge=3),
        ny=_int(ctx, d, "ny", p, dflt.ny, ge=3),
        origin=origin,
        fuel_model=fuel,
        fuel_patches=patches,
        moisture=_num(ctx, d, "moisture", p, dflt.moisture, ge=0.01, le=0.6),
        wind=tuple(winds),
        ignitions=ignitions,
        wet_duration_s=_num(ctx, d, "wet_duration_s", p, dflt.wet_duration_s, ge=0),
        spread_factor=_num(ctx, d, "spread_factor", p, dflt.spread_factor, gt=0),
        wind_limit=_choice(ctx, d, "wind_limit", p, WIND_LIMITS, dflt.wind_limit),
        landscape=land,
    )
    if land is not None:
        return r  # the grid comes from the landscape (scenario.ground checks the ignitions there)
    x_max = r.origin.x_m + r.nx * r.cell_size_m
    y_max = r.origin.y_m + r.ny * r.cell_size_m
    for i, ig in enumerate(r.ignitions):
        if not (r.origin.x_m <= ig.x_m < x_max and r.origin.y_m <= ig.y_m < y_max):
            raise ctx.fail(f"{p}.ignitions[{i}]", f"({ig.x_m:g}, {ig.y_m:g}) is outside the raster grid")
    return r


def _fires(ctx: _Ctx, raw: Any) -> Fires:
    p = "fires"
    d = _mapping(
        ctx, raw, p, {"model", "extinction_sigma_m", "drop_radius_m", "drop_model", "analytic", "raster"}
    )
    model = _choice(ctx, d, "model", p, FIRE_MODELS, "analytic")
    drop_radius = None
    if d.get("drop_radius_m") is not None:
        drop_radius = _num(ctx, d, "drop_radius_m", p, gt=0)
    analytic = tuple(
        _record(
            ctx,
            item,
            AnalyticFire,
            f"fires.analytic[{i}]",
            bounds={"sigma_m": {"gt": 0}, "start_s": {"ge": 0}},
        )
        for i, item in enumerate(_list(ctx, d, "analytic", p))
    )
    if model == "raster" and d.get("raster") is None:
        raise ctx.fail("fires.raster", "required when fires.model is 'raster'")
    # validated even when unused (an analytic scenario with a raster section)
    raster = _raster(ctx, d["raster"]) if d.get("raster") is not None else None
    if model == "analytic" and len(analytic) > 255:
        raise ctx.fail("fires.analytic", f"at most 255 fires (uint8 ids), got {len(analytic)}")
    return Fires(
        model=model,
        extinction_sigma_m=_num(ctx, d, "extinction_sigma_m", p, 2.0, gt=0),
        drop_radius_m=drop_radius,
        drop_model=_choice(ctx, d, "drop_model", p, DROP_MODELS, "disc"),
        analytic=analytic,
        raster=raster,
    )
