"""Scenario files: load, validate and expose them as frozen dataclasses (docs/scenario.md).

``load_scenario(path) -> Scenario``. Attribute names are the YAML keys (``Scenario.area.x_min_m``,
``Scenario.vehicle.v_stall_mps``...), with two exceptions forced by Python: the outage key
``from`` is the attribute ``from_`` and ``to`` stays ``to``. Units are in the key names;
positions are in the ``map`` frame (x east, y north, z up, metres).

Any wrong, missing or unknown field raises :class:`ScenarioError`, whose message names the file
and the dotted field path, e.g. ``scenarios/x.yaml: fires.analytic[1].sigma_m: must be > 0, got -3``.

Extensions to docs/scenario.md (all optional, defaults keep the documented behaviour):

- ``fires.drop_radius_m``: radius [m] of a drop's footprint; ``null`` (default) means "the
  fire's sigma" for analytic fires (protocol "Payload") and 20 m for the raster fire.
- ``fires.raster.wet_duration_s``: a wetted cell cannot ignite for this long (default 600 s).
- ``fires.raster.spread_factor``: multiplies every rate of spread (default 1.0), to speed up
  demonstrations without changing the fuel physics.
- ``fires.raster.wind_limit``: ``behave`` (default: Rothermel's 0.9 I_R limit as Behave applies
  it), ``andrews2013`` (rate of spread capped at the effective wind speed) or ``none``.
- ``fires.raster.ignitions[].start_s`` may be negative (a fire already burning when the
  mission starts); ``fires.raster.wind[0].start_s`` must then be at or before the earliest one.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from fire_uav_common.terrain import Hill, Lake, Terrain

__all__ = [
    "AltimeterSpec",
    "AnalyticFire",
    "Area",
    "Comms",
    "FireSensorSpec",
    "Fires",
    "FuelPatch",
    "GpsSpec",
    "GyroSpec",
    "Ignition",
    "Mission",
    "Origin",
    "Outage",
    "Pose",
    "Raster",
    "Scenario",
    "ScenarioError",
    "Sensors",
    "Spacing",
    "Timing",
    "Uavs",
    "Vehicle",
    "Wind",
    "FUEL_MODELS",
    "load_scenario",
    "scenario_from_dict",
]

#: Anderson (1982) / Albini (1976) standard fuel model numbers the raster fire supports.
FUEL_MODELS = (1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13)
#: ``fires.raster.wind_limit`` values (fire_world_sim.fires.rothermel.WIND_LIMITS)
WIND_LIMITS = ("behave", "andrews2013", "none")


class ScenarioError(ValueError):
    """A scenario file is missing, unreadable or invalid; the message names file and field."""


# --- dataclasses ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Area:
    """Mission area [m], map frame."""

    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float

    @property
    def width_m(self) -> float:
        return self.x_max_m - self.x_min_m

    @property
    def height_m(self) -> float:
        return self.y_max_m - self.y_min_m

    def contains(self, x_m: float, y_m: float) -> bool:
        return self.x_min_m <= x_m <= self.x_max_m and self.y_min_m <= y_m <= self.y_max_m


@dataclass(frozen=True)
class Timing:
    control_period_s: float = 0.1
    physics_period_s: float = 0.01
    max_duration_s: float = 900.0

    @property
    def substeps(self) -> int:
        """Physics substeps per control step."""
        return round(self.control_period_s / self.physics_period_s)


@dataclass(frozen=True)
class Vehicle:
    """Vehicle limits and payload (FF II-B, Eq. 5)."""

    v_stall_mps: float = 44.7
    v_max_mps: float = 100.0
    vz_max_mps: float = 100.0
    omega_max_radps: float = 10.0
    water_capacity_kg: float = 2000.0
    flight_height_m: float = 30.0
    process_noise_sigma: float = 1.0
    refill_height_m: float = 15.0
    refill_speed_margin_mps: float = 10.0
    refill_rate_kgps: float = 400.0
    landing_height_m: float = 1.0
    command_timeout_s: float = 3.0
    collision_radius_m: float = 3.0  # [m] two airborne vehicles closer than this (3-D) both crash; 0 = off


@dataclass(frozen=True)
class Pose:
    """Start pose: position [m] map frame, yaw [rad] ccw from +x."""

    x_m: float = 50.0
    y_m: float = 250.0
    z_m: float = 0.0
    yaw_rad: float = -math.pi / 2


@dataclass(frozen=True)
class Spacing:
    dx_m: float = 0.0
    dy_m: float = 30.0


@dataclass(frozen=True)
class Uavs:
    count: int = 5
    first: Pose = field(default_factory=Pose)
    spacing: Spacing = field(default_factory=Spacing)
    takeoff_interval_s: float = 2.0


@dataclass(frozen=True)
class GpsSpec:
    rate_hz: float = 10.0
    sigma_m: float = 3.0
    p_valid: float = 0.9


@dataclass(frozen=True)
class AltimeterSpec:
    rate_hz: float = 25.0
    sigma_m: float = 1.5
    p_valid: float = 0.8
    max_range_m: float = 40.0


@dataclass(frozen=True)
class GyroSpec:
    rate_hz: float = 100.0
    sigma_radps: float = 0.3
    p_valid: float = 0.7


@dataclass(frozen=True)
class FireSensorSpec:
    rate_hz: float = 10.0
    range_m: float = 70.0
    position_sigma_m: float = 2.0
    extent_sigma_m: float = 1.0
    p_valid: float = 1.0


@dataclass(frozen=True)
class Sensors:
    gps: GpsSpec = field(default_factory=GpsSpec)
    altimeter: AltimeterSpec = field(default_factory=AltimeterSpec)
    gyro: GyroSpec = field(default_factory=GyroSpec)
    fire: FireSensorSpec = field(default_factory=FireSensorSpec)


@dataclass(frozen=True)
class AnalyticFire:
    """FF IV-A Gaussian fire: centre [m] drifting at (vx_mps, vy_mps) from start_s [s]."""

    x_m: float
    y_m: float
    sigma_m: float
    vx_mps: float = 0.0
    vy_mps: float = 0.0
    start_s: float = 0.0


@dataclass(frozen=True)
class Origin:
    x_m: float = 0.0
    y_m: float = 0.0


@dataclass(frozen=True)
class FuelPatch:
    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float
    fuel_model: int


@dataclass(frozen=True)
class Wind:
    """Piecewise-constant wind from start_s [s]: speed [m/s], direction it blows TOWARD [deg ccw from +x]."""

    start_s: float
    speed_mps: float
    direction_deg: float


@dataclass(frozen=True)
class Ignition:
    x_m: float
    y_m: float
    start_s: float = 0.0


@dataclass(frozen=True)
class Raster:
    cell_size_m: float = 5.0
    nx: int = 200
    ny: int = 200
    origin: Origin = field(default_factory=Origin)
    fuel_model: int = 1
    fuel_patches: tuple[FuelPatch, ...] = ()
    moisture: float = 0.06
    wind: tuple[Wind, ...] = (Wind(0.0, 0.0, 0.0),)
    ignitions: tuple[Ignition, ...] = ()
    wet_duration_s: float = 600.0
    spread_factor: float = 1.0
    wind_limit: str = "behave"  # behave | andrews2013 | none (fire_world_sim.fires.rothermel)


@dataclass(frozen=True)
class Fires:
    model: str = "analytic"
    extinction_sigma_m: float = 2.0
    drop_radius_m: float | None = None
    analytic: tuple[AnalyticFire, ...] = ()
    raster: Raster | None = None


@dataclass(frozen=True)
class Outage:
    """Directed link outage ``from_ -> to`` between start_s and end_s [s] (YAML key ``from``)."""

    from_: int
    to: int
    start_s: float
    end_s: float


@dataclass(frozen=True)
class Comms:
    loss_probability: float = 0.05
    outages: tuple[Outage, ...] = ()


@dataclass(frozen=True)
class Mission:
    crash_threshold_steps: int = 10
    grid_resolution_m: float = 5.0
    sigma_water_m: float = 40.0
    sigma_landing_m: float = 10.0
    use_safety_band: bool = True
    safety_radius_m: float = 10.0
    monitors_per_fire: int = 0
    search_first: bool = False
    tactic: str = "head"  # raster suppression: head | flank (TACTICS; fire_uav_agent.tactics)
    prior_fires: str = "unknown"  # known: agents start with noisy estimates of every fire (FF III-C, IV-D c)
    prior_position_sigma_m: float = 10.0  # [m] noise of a known fire's initial centre estimate
    prior_extent_sigma_fraction: float = 0.2  # [-] relative noise of a known fire's initial extent


PRIOR_FIRES_MODES = ("unknown", "known")


@dataclass(frozen=True)
class Scenario:
    """A validated scenario; ``path`` is the file it came from ('' when built from a dict)."""

    name: str
    area: Area
    description: str = ""
    seed: int = 0
    terrain: Terrain = field(default_factory=Terrain)
    lakes: tuple[Lake, ...] = ()
    timing: Timing = field(default_factory=Timing)
    vehicle: Vehicle = field(default_factory=Vehicle)
    uavs: Uavs = field(default_factory=Uavs)
    sensors: Sensors = field(default_factory=Sensors)
    fires: Fires = field(default_factory=Fires)
    comms: Comms = field(default_factory=Comms)
    mission: Mission = field(default_factory=Mission)
    path: str = ""

    def uav_start_poses(self, count: int | None = None) -> list[tuple[float, float, float, float]]:
        """Start poses (x_m, y_m, z_m, yaw_rad) of UAVs 0..count-1 (default ``uavs.count``)."""
        n = self.uavs.count if count is None else count
        if n < 0:
            raise ValueError(f"count must be >= 0, got {n}")
        f, s = self.uavs.first, self.uavs.spacing
        return [(f.x_m + i * s.dx_m, f.y_m + i * s.dy_m, f.z_m, f.yaw_rad) for i in range(n)]

    def takeoff_time_s(self, uav_id: int) -> float:
        """Earliest sim time [s] UAV ``uav_id`` may take off (FF IV-D a)."""
        return uav_id * self.uavs.takeoff_interval_s


# --- validation helpers -----------------------------------------------------------------------
class _Ctx:
    def __init__(self, file: str) -> None:
        self.file = file

    def fail(self, path: str, msg: str) -> ScenarioError:
        return ScenarioError(f"{self.file}: {path}: {msg}" if path else f"{self.file}: {msg}")


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _mapping(
    ctx: _Ctx, value: Any, path: str, allowed: set[str], required: frozenset[str] | set[str] = frozenset()
) -> dict:
    if value is None:
        value = {}
    if not isinstance(value, Mapping):
        raise ctx.fail(path, f"must be a mapping, got {type(value).__name__}")
    for k in value:
        if not isinstance(k, str):
            raise ctx.fail(path, f"keys must be strings, got {k!r}")
        if k not in allowed:
            raise ctx.fail(_join(path, k), f"unknown field; expected one of {sorted(allowed)}")
    for k in sorted(required):
        if k not in value:
            raise ctx.fail(_join(path, k), "required field missing")
    return dict(value)


def _num(
    ctx: _Ctx,
    d: dict,
    key: str,
    path: str,
    default: float | None = None,
    *,
    gt: float | None = None,
    ge: float | None = None,
    le: float | None = None,
    lt: float | None = None,
) -> float:
    p = _join(path, key)
    if key not in d or (d[key] is None and default is not None):
        if default is None:
            raise ctx.fail(p, "required field missing")
        return float(default)
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ctx.fail(p, f"must be a number, got {v!r}")
    v = float(v)
    if not math.isfinite(v):
        raise ctx.fail(p, f"must be finite, got {v}")
    if gt is not None and not v > gt:
        raise ctx.fail(p, f"must be > {gt:g}, got {v:g}")
    if ge is not None and not v >= ge:
        raise ctx.fail(p, f"must be >= {ge:g}, got {v:g}")
    if le is not None and not v <= le:
        raise ctx.fail(p, f"must be <= {le:g}, got {v:g}")
    if lt is not None and not v < lt:
        raise ctx.fail(p, f"must be < {lt:g}, got {v:g}")
    return v


def _int(
    ctx: _Ctx, d: dict, key: str, path: str, default: int | None = None, *, ge: int | None = None
) -> int:
    p = _join(path, key)
    if key not in d:
        if default is None:
            raise ctx.fail(p, "required field missing")
        return int(default)
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, int):
        raise ctx.fail(p, f"must be an integer, got {v!r}")
    if ge is not None and v < ge:
        raise ctx.fail(p, f"must be >= {ge}, got {v}")
    return int(v)


def _bool(ctx: _Ctx, d: dict, key: str, path: str, default: bool) -> bool:
    if key not in d:
        return default
    v = d[key]
    if not isinstance(v, bool):
        raise ctx.fail(_join(path, key), f"must be true or false, got {v!r}")
    return v


def _str(ctx: _Ctx, d: dict, key: str, path: str, default: str | None = None) -> str:
    p = _join(path, key)
    if key not in d:
        if default is None:
            raise ctx.fail(p, "required field missing")
        return default
    v = d[key]
    if not isinstance(v, str) or (default is None and not v.strip()):
        raise ctx.fail(p, f"must be a non-empty string, got {v!r}")
    return v


def _list(ctx: _Ctx, d: dict, key: str, path: str) -> list:
    v = d.get(key)
    if v is None:
        return []
    if not isinstance(v, list):
        raise ctx.fail(_join(path, key), f"must be a list, got {type(v).__name__}")
    return v


# --- sections ---------------------------------------------------------------------------------
def _area(ctx: _Ctx, raw: Any) -> Area:
    keys = {"x_min_m", "x_max_m", "y_min_m", "y_max_m"}
    d = _mapping(ctx, raw, "area", keys, keys)
    a = Area(*(_num(ctx, d, k, "area") for k in ("x_min_m", "x_max_m", "y_min_m", "y_max_m")))
    if not a.x_max_m > a.x_min_m:
        raise ctx.fail("area.x_max_m", f"must be > x_min_m ({a.x_min_m:g}), got {a.x_max_m:g}")
    if not a.y_max_m > a.y_min_m:
        raise ctx.fail("area.y_max_m", f"must be > y_min_m ({a.y_min_m:g}), got {a.y_max_m:g}")
    return a


def _terrain(ctx: _Ctx, raw: Any) -> Terrain:
    d = _mapping(ctx, raw, "terrain", {"base_m", "slope_x", "slope_y", "hills"})
    hills = []
    for i, h in enumerate(_list(ctx, d, "hills", "terrain")):
        p = f"terrain.hills[{i}]"
        keys = {"x_m", "y_m", "height_m", "sigma_m"}
        hd = _mapping(ctx, h, p, keys, keys)
        hills.append(
            Hill(
                x_m=_num(ctx, hd, "x_m", p),
                y_m=_num(ctx, hd, "y_m", p),
                height_m=_num(ctx, hd, "height_m", p),
                sigma_m=_num(ctx, hd, "sigma_m", p, gt=0),
            )
        )
    return Terrain(
        base_m=_num(ctx, d, "base_m", "terrain", 0.0),
        slope_x=_num(ctx, d, "slope_x", "terrain", 0.0),
        slope_y=_num(ctx, d, "slope_y", "terrain", 0.0),
        hills=tuple(hills),
    )


def _lakes(ctx: _Ctx, raw: Any) -> tuple[Lake, ...]:
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise ctx.fail("lakes", f"must be a list, got {type(raw).__name__}")
    out = []
    for i, item in enumerate(raw):
        p = f"lakes[{i}]"
        keys = {"x_m", "y_m", "diameter_m"}
        d = _mapping(ctx, item, p, keys, keys)
        out.append(Lake(_num(ctx, d, "x_m", p), _num(ctx, d, "y_m", p), _num(ctx, d, "diameter_m", p, gt=0)))
    return tuple(out)


def _timing(ctx: _Ctx, raw: Any) -> Timing:
    p = "timing"
    d = _mapping(ctx, raw, p, {"control_period_s", "physics_period_s", "max_duration_s"})
    t = Timing(
        control_period_s=_num(ctx, d, "control_period_s", p, 0.1, gt=0),
        physics_period_s=_num(ctx, d, "physics_period_s", p, 0.01, gt=0),
        max_duration_s=_num(ctx, d, "max_duration_s", p, 900.0, gt=0),
    )
    ratio = t.control_period_s / t.physics_period_s
    if ratio < 1 - 1e-9 or abs(ratio - round(ratio)) > 1e-6:
        raise ctx.fail(
            "timing.physics_period_s",
            f"must divide control_period_s ({t.control_period_s:g}), got {t.physics_period_s:g}",
        )
    return t


def _vehicle(ctx: _Ctx, raw: Any) -> Vehicle:
    p = "vehicle"
    defaults = Vehicle()
    names = list(Vehicle.__dataclass_fields__)
    d = _mapping(ctx, raw, p, set(names))
    vals = {}
    for k in names:
        may_be_zero = k in ("process_noise_sigma", "collision_radius_m")
        vals[k] = _num(ctx, d, k, p, getattr(defaults, k), ge=0 if may_be_zero else None)
        if not may_be_zero and not vals[k] > 0:
            raise ctx.fail(_join(p, k), f"must be > 0, got {vals[k]:g}")
    v = Vehicle(**vals)
    if not v.v_max_mps > v.v_stall_mps:
        raise ctx.fail("vehicle.v_max_mps", f"must be > v_stall_mps ({v.v_stall_mps:g}), got {v.v_max_mps:g}")
    return v


def _uavs(ctx: _Ctx, raw: Any) -> Uavs:
    p = "uavs"
    d = _mapping(ctx, raw, p, {"count", "first", "spacing", "takeoff_interval_s"})
    fp = "uavs.first"
    fd = _mapping(ctx, d.get("first"), fp, {"x_m", "y_m", "z_m", "yaw_rad"})
    dflt = Pose()
    first = Pose(
        x_m=_num(ctx, fd, "x_m", fp, dflt.x_m),
        y_m=_num(ctx, fd, "y_m", fp, dflt.y_m),
        z_m=_num(ctx, fd, "z_m", fp, dflt.z_m),
        yaw_rad=_num(ctx, fd, "yaw_rad", fp, dflt.yaw_rad),
    )
    sp = "uavs.spacing"
    sd = _mapping(ctx, d.get("spacing"), sp, {"dx_m", "dy_m"})
    spacing = Spacing(_num(ctx, sd, "dx_m", sp, 0.0), _num(ctx, sd, "dy_m", sp, 30.0))
    count = _int(ctx, d, "count", p, 5, ge=1)
    if count > 255:
        raise ctx.fail("uavs.count", f"must be <= 255 (uint8 ids), got {count}")
    return Uavs(
        count=count,
        first=first,
        spacing=spacing,
        takeoff_interval_s=_num(ctx, d, "takeoff_interval_s", p, 2.0, ge=0),
    )


def _sensors(ctx: _Ctx, raw: Any) -> Sensors:
    d = _mapping(ctx, raw, "sensors", {"gps", "altimeter", "gyro", "fire"})
    out = {}
    for key, cls in (
        ("gps", GpsSpec),
        ("altimeter", AltimeterSpec),
        ("gyro", GyroSpec),
        ("fire", FireSensorSpec),
    ):
        p = f"sensors.{key}"
        names = list(cls.__dataclass_fields__)
        sd = _mapping(ctx, d.get(key), p, set(names))
        dflt = cls()
        vals = {}
        for n in names:
            if n == "p_valid":
                vals[n] = _num(ctx, sd, n, p, dflt.p_valid, ge=0, le=1)
            elif n.startswith("sigma") or n.endswith("sigma_m"):
                vals[n] = _num(ctx, sd, n, p, getattr(dflt, n), ge=0)
            else:
                vals[n] = _num(ctx, sd, n, p, getattr(dflt, n), gt=0)
        out[key] = cls(**vals)
    return Sensors(**out)  # type: ignore[arg-type]  # keys are the four field names


def _raster(ctx: _Ctx, raw: Any) -> Raster:
    p = "fires.raster"
    allowed = set(Raster.__dataclass_fields__)
    d = _mapping(ctx, raw, p, allowed)
    dflt = Raster()
    od = _mapping(ctx, d.get("origin"), "fires.raster.origin", {"x_m", "y_m"})
    origin = Origin(
        _num(ctx, od, "x_m", "fires.raster.origin", 0.0), _num(ctx, od, "y_m", "fires.raster.origin", 0.0)
    )
    fuel = _int(ctx, d, "fuel_model", p, dflt.fuel_model)
    if fuel not in FUEL_MODELS:
        raise ctx.fail("fires.raster.fuel_model", f"must be one of {list(FUEL_MODELS)}, got {fuel}")
    patches = []
    for i, item in enumerate(_list(ctx, d, "fuel_patches", p)):
        pp = f"fires.raster.fuel_patches[{i}]"
        keys = {"x_min_m", "x_max_m", "y_min_m", "y_max_m", "fuel_model"}
        pd = _mapping(ctx, item, pp, keys, keys)
        fm = _int(ctx, pd, "fuel_model", pp)
        if fm not in FUEL_MODELS:
            raise ctx.fail(f"{pp}.fuel_model", f"must be one of {list(FUEL_MODELS)}, got {fm}")
        patch = FuelPatch(
            x_min_m=_num(ctx, pd, "x_min_m", pp),
            x_max_m=_num(ctx, pd, "x_max_m", pp),
            y_min_m=_num(ctx, pd, "y_min_m", pp),
            y_max_m=_num(ctx, pd, "y_max_m", pp),
            fuel_model=fm,
        )
        if not (patch.x_max_m > patch.x_min_m and patch.y_max_m > patch.y_min_m):
            raise ctx.fail(pp, "must have x_max_m > x_min_m and y_max_m > y_min_m")
        patches.append(patch)
    winds: list[Wind] = []
    for i, item in enumerate(_list(ctx, d, "wind", p)):
        wp = f"fires.raster.wind[{i}]"
        keys = {"start_s", "speed_mps", "direction_deg"}
        wd = _mapping(ctx, item, wp, keys, {"speed_mps", "direction_deg"})
        w = Wind(
            start_s=_num(ctx, wd, "start_s", wp, 0.0),
            speed_mps=_num(ctx, wd, "speed_mps", wp, ge=0),
            direction_deg=_num(ctx, wd, "direction_deg", wp),
        )
        if winds and not w.start_s > winds[-1].start_s:
            raise ctx.fail(
                f"{wp}.start_s", f"must be > the previous start_s ({winds[-1].start_s:g}), got {w.start_s:g}"
            )
        winds.append(w)
    ignitions = []
    for i, item in enumerate(_list(ctx, d, "ignitions", p)):
        ip = f"fires.raster.ignitions[{i}]"
        idd = _mapping(ctx, item, ip, {"x_m", "y_m", "start_s"}, {"x_m", "y_m"})
        ignitions.append(
            Ignition(_num(ctx, idd, "x_m", ip), _num(ctx, idd, "y_m", ip), _num(ctx, idd, "start_s", ip, 0.0))
        )
    first = min([0.0, *(ig.start_s for ig in ignitions)])
    if not winds:
        winds = [Wind(first, dflt.wind[0].speed_mps, dflt.wind[0].direction_deg)]
    elif winds[0].start_s > first:
        raise ctx.fail(
            "fires.raster.wind[0].start_s",
            f"must be 0 or earlier: at or before the earliest ignition ({first:g}), got {winds[0].start_s:g}",
        )
    wind_limit = _str(ctx, d, "wind_limit", p, dflt.wind_limit)
    if wind_limit not in WIND_LIMITS:
        raise ctx.fail("fires.raster.wind_limit", f"must be one of {list(WIND_LIMITS)}, got {wind_limit!r}")
    r = Raster(
        cell_size_m=_num(ctx, d, "cell_size_m", p, dflt.cell_size_m, gt=0),
        nx=_int(ctx, d, "nx", p, dflt.nx, ge=3),
        ny=_int(ctx, d, "ny", p, dflt.ny, ge=3),
        origin=origin,
        fuel_model=fuel,
        fuel_patches=tuple(patches),
        moisture=_num(ctx, d, "moisture", p, dflt.moisture, ge=0.01, le=0.6),
        wind=tuple(winds),
        ignitions=tuple(ignitions),
        wet_duration_s=_num(ctx, d, "wet_duration_s", p, dflt.wet_duration_s, ge=0),
        spread_factor=_num(ctx, d, "spread_factor", p, dflt.spread_factor, gt=0),
        wind_limit=wind_limit,
    )
    x_max = r.origin.x_m + r.nx * r.cell_size_m
    y_max = r.origin.y_m + r.ny * r.cell_size_m
    for i, ig in enumerate(r.ignitions):
        if not (r.origin.x_m <= ig.x_m < x_max and r.origin.y_m <= ig.y_m < y_max):
            raise ctx.fail(
                f"fires.raster.ignitions[{i}]", f"({ig.x_m:g}, {ig.y_m:g}) is outside the raster grid"
            )
    return r


def _fires(ctx: _Ctx, raw: Any) -> Fires:
    p = "fires"
    d = _mapping(ctx, raw, p, {"model", "extinction_sigma_m", "drop_radius_m", "analytic", "raster"})
    model = _str(ctx, d, "model", p, "analytic")
    if model not in ("analytic", "raster"):
        raise ctx.fail("fires.model", f"must be 'analytic' or 'raster', got {model!r}")
    drop_radius = None
    if d.get("drop_radius_m") is not None:
        drop_radius = _num(ctx, d, "drop_radius_m", p, gt=0)
    analytic = []
    for i, item in enumerate(_list(ctx, d, "analytic", p)):
        fp = f"fires.analytic[{i}]"
        fd = _mapping(
            ctx, item, fp, {"x_m", "y_m", "sigma_m", "vx_mps", "vy_mps", "start_s"}, {"x_m", "y_m", "sigma_m"}
        )
        analytic.append(
            AnalyticFire(
                x_m=_num(ctx, fd, "x_m", fp),
                y_m=_num(ctx, fd, "y_m", fp),
                sigma_m=_num(ctx, fd, "sigma_m", fp, gt=0),
                vx_mps=_num(ctx, fd, "vx_mps", fp, 0.0),
                vy_mps=_num(ctx, fd, "vy_mps", fp, 0.0),
                start_s=_num(ctx, fd, "start_s", fp, 0.0, ge=0),
            )
        )
    raster = None
    if model == "raster":
        if d.get("raster") is None:
            raise ctx.fail("fires.raster", "required when fires.model is 'raster'")
        raster = _raster(ctx, d["raster"])
    elif d.get("raster") is not None:
        raster = _raster(ctx, d["raster"])  # validated even when unused
    if model == "analytic" and len(analytic) > 255:
        raise ctx.fail("fires.analytic", f"at most 255 fires (uint8 ids), got {len(analytic)}")
    return Fires(
        model=model,
        extinction_sigma_m=_num(ctx, d, "extinction_sigma_m", p, 2.0, gt=0),
        drop_radius_m=drop_radius,
        analytic=tuple(analytic),
        raster=raster,
    )


def _comms(ctx: _Ctx, raw: Any, uav_count: int) -> Comms:
    p = "comms"
    d = _mapping(ctx, raw, p, {"loss_probability", "outages"})
    outages = []
    for i, item in enumerate(_list(ctx, d, "outages", p)):
        op = f"comms.outages[{i}]"
        keys = {"from", "to", "start_s", "end_s"}
        od = _mapping(ctx, item, op, keys, keys)
        o = Outage(
            from_=_int(ctx, od, "from", op, ge=0),
            to=_int(ctx, od, "to", op, ge=0),
            start_s=_num(ctx, od, "start_s", op, ge=0),
            end_s=_num(ctx, od, "end_s", op),
        )
        if not o.end_s > o.start_s:
            raise ctx.fail(f"{op}.end_s", f"must be > start_s ({o.start_s:g}), got {o.end_s:g}")
        if o.from_ == o.to:
            raise ctx.fail(f"{op}.to", f"must differ from 'from' ({o.from_})")
        for key, uid in (("from", o.from_), ("to", o.to)):
            if uid >= uav_count:
                raise ctx.fail(
                    f"{op}.{key}", f"UAV {uid} does not exist: the fleet has ids 0..{uav_count - 1}"
                )
        outages.append(o)
    return Comms(
        loss_probability=_num(ctx, d, "loss_probability", p, 0.05, ge=0, le=1), outages=tuple(outages)
    )


def _mission(ctx: _Ctx, raw: Any) -> Mission:
    p = "mission"
    d = _mapping(ctx, raw, p, set(Mission.__dataclass_fields__))
    m = Mission()
    return Mission(
        crash_threshold_steps=_int(ctx, d, "crash_threshold_steps", p, m.crash_threshold_steps, ge=1),
        grid_resolution_m=_num(ctx, d, "grid_resolution_m", p, m.grid_resolution_m, gt=0),
        sigma_water_m=_num(ctx, d, "sigma_water_m", p, m.sigma_water_m, gt=0),
        sigma_landing_m=_num(ctx, d, "sigma_landing_m", p, m.sigma_landing_m, gt=0),
        use_safety_band=_bool(ctx, d, "use_safety_band", p, m.use_safety_band),
        safety_radius_m=_num(ctx, d, "safety_radius_m", p, m.safety_radius_m, ge=0),
        monitors_per_fire=_int(ctx, d, "monitors_per_fire", p, m.monitors_per_fire, ge=0),
        search_first=_bool(ctx, d, "search_first", p, m.search_first),
        tactic=_tactic(ctx, d, p, m.tactic),
        prior_fires=_prior_fires(ctx, d, p, m.prior_fires),
        prior_position_sigma_m=_num(ctx, d, "prior_position_sigma_m", p, m.prior_position_sigma_m, ge=0),
        prior_extent_sigma_fraction=_num(
            ctx, d, "prior_extent_sigma_fraction", p, m.prior_extent_sigma_fraction, ge=0, le=1
        ),
    )


def _prior_fires(ctx: _Ctx, d: dict, path: str, default: str) -> str:
    v = _str(ctx, d, "prior_fires", path, default)
    if v not in PRIOR_FIRES_MODES:
        raise ctx.fail(
            _join(path, "prior_fires"), f"must be one of {', '.join(PRIOR_FIRES_MODES)}, got {v!r}"
        )
    return v


#: ``mission.tactic`` values: head attack (fastest front first) or flank attack from an anchor
TACTICS = ("head", "flank")


def _tactic(ctx: _Ctx, d: dict, p: str, default: str) -> str:
    t = _str(ctx, d, "tactic", p, default)
    if t not in TACTICS:
        raise ctx.fail(f"{p}.tactic", f"must be one of {list(TACTICS)}, got {t!r}")
    return t


_TOP = {
    "name",
    "description",
    "seed",
    "area",
    "terrain",
    "lakes",
    "timing",
    "vehicle",
    "uavs",
    "sensors",
    "fires",
    "comms",
    "mission",
}


def _apply_overrides(ctx: _Ctx, raw: dict, overrides: Mapping[str, Any]) -> dict:
    """Return a copy of ``raw`` with dotted-path overrides applied (``{"uavs.count": 3, "seed": 7}``)."""
    import copy

    out = copy.deepcopy(raw)
    for dotted, value in overrides.items():
        parts = str(dotted).split(".")
        node = out
        for i, part in enumerate(parts[:-1]):
            nxt = node.get(part)
            if nxt is None:
                nxt = node[part] = {}
            if not isinstance(nxt, dict):
                raise ctx.fail(".".join(parts[: i + 1]), f"override {dotted!r}: not a mapping")
            node = nxt
        node[parts[-1]] = value
    return out


def scenario_from_dict(
    raw: Any, *, file: str = "<dict>", overrides: Mapping[str, Any] | None = None
) -> Scenario:
    """Validate an already-parsed scenario mapping; ``file`` names it in error messages."""
    ctx = _Ctx(file)
    if not isinstance(raw, Mapping):
        raise ctx.fail("", f"top level must be a mapping, got {type(raw).__name__}")
    raw = dict(raw)
    if overrides:
        raw = _apply_overrides(ctx, raw, overrides)
    d = _mapping(ctx, raw, "", _TOP, {"name", "area"})
    seed = _int(ctx, d, "seed", "", 0, ge=0)
    uavs = _uavs(ctx, d.get("uavs"))
    return Scenario(
        name=_str(ctx, d, "name", ""),
        description=_str(ctx, d, "description", "", "") if d.get("description") is not None else "",
        seed=seed,
        area=_area(ctx, d.get("area")),
        terrain=_terrain(ctx, d.get("terrain")),
        lakes=_lakes(ctx, d.get("lakes")),
        timing=_timing(ctx, d.get("timing")),
        vehicle=_vehicle(ctx, d.get("vehicle")),
        uavs=uavs,
        sensors=_sensors(ctx, d.get("sensors")),
        fires=_fires(ctx, d.get("fires")),
        comms=_comms(ctx, d.get("comms"), uavs.count),
        mission=_mission(ctx, d.get("mission")),
        path="" if file == "<dict>" else file,
    )


def load_scenario(path: str | os.PathLike, *, overrides: Mapping[str, Any] | None = None) -> Scenario:
    """Read and validate a scenario YAML file.

    ``overrides`` maps dotted field paths to values applied before validation, e.g.
    ``{"seed": 3, "uavs.count": 2, "comms.loss_probability": 0.0}`` (the runner's flags).
    Raises :class:`ScenarioError` naming the file and the field on any problem.
    """
    file = str(path)
    p = Path(path)
    ctx = _Ctx(file)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ctx.fail("", "file not found") from None
    except IsADirectoryError:
        raise ctx.fail("", "is a directory, not a scenario file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ctx.fail("", f"cannot read: {e}") from None
    try:
        raw = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise ctx.fail("", f"invalid YAML: {e}") from None
    if raw is None:
        raise ctx.fail("", "file is empty")
    return scenario_from_dict(raw, file=file, overrides=overrides)
