"""Readers of the scenario's sections except ``fires`` (``fires.py``): one function per section.

Each takes the raw YAML value of its section (``None`` when absent) and returns its dataclass,
raising :class:`ScenarioError` naming the file and the dotted field path on any problem.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from fire_uav_common.terrain import Hill, Lake, Terrain

from .airframes import VEHICLE_MODELS, read_airframe
from .fields import _bool, _choice, _Ctx, _int, _list, _mapping, _num, _record
from .types import (
    LAKE_SEQUENCES,
    PRIOR_FIRES_MODES,
    TACTICS,
    VERTICAL_BANDS,
    AltimeterSpec,
    Area,
    Comms,
    FireSensorSpec,
    GpsSpec,
    GyroSpec,
    LinkOutage,
    MissionSettings,
    Pose,
    Sensors,
    Spacing,
    Timing,
    Uavs,
    Vehicle,
)


def _area(ctx: _Ctx, raw: Any) -> Area:
    a = _record(ctx, raw, Area, "area")
    if not a.x_max_m > a.x_min_m:
        raise ctx.fail("area.x_max_m", f"must be > x_min_m ({a.x_min_m:g}), got {a.x_max_m:g}")
    if not a.y_max_m > a.y_min_m:
        raise ctx.fail("area.y_max_m", f"must be > y_min_m ({a.y_min_m:g}), got {a.y_max_m:g}")
    return a


def _terrain(ctx: _Ctx, raw: Any) -> Terrain:
    d = _mapping(ctx, raw, "terrain", {"base_m", "slope_x", "slope_y", "hills"})
    hills = tuple(
        _record(ctx, h, Hill, f"terrain.hills[{i}]", bounds={"sigma_m": {"gt": 0}})
        for i, h in enumerate(_list(ctx, d, "hills", "terrain"))
    )
    return Terrain(
        base_m=_num(ctx, d, "base_m", "terrain", 0.0),
        slope_x=_num(ctx, d, "slope_x", "terrain", 0.0),
        slope_y=_num(ctx, d, "slope_y", "terrain", 0.0),
        hills=hills,
    )


def _lakes(ctx: _Ctx, raw: Any) -> tuple[Lake, ...]:
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise ctx.fail("lakes", f"must be a list, got {type(raw).__name__}")
    discs = (
        _record(ctx, item, _LakeDisc, f"lakes[{i}]", bounds={"diameter_m": {"gt": 0}})
        for i, item in enumerate(raw)
    )
    return tuple(Lake(d.x_m, d.y_m, d.diameter_m) for d in discs)


@dataclasses.dataclass(frozen=True)
class _LakeDisc:
    """A lake as a scenario writes it: a disc (a landscape's lakes come from its water cells)."""

    x_m: float
    y_m: float
    diameter_m: float


def _timing(ctx: _Ctx, raw: Any) -> Timing:
    t = _record(
        ctx,
        raw,
        Timing,
        "timing",
        bounds=dict.fromkeys(("control_period_s", "physics_period_s", "max_duration_s"), {"gt": 0}),
    )
    ratio = t.control_period_s / t.physics_period_s
    if ratio < 1 - 1e-9 or abs(ratio - round(ratio)) > 1e-6:
        raise ctx.fail(
            "timing.physics_period_s",
            f"must divide control_period_s ({t.control_period_s:g}), got {t.physics_period_s:g}",
        )
    return t


#: vehicle fields that may be 0 (no process noise, collisions off); every other one must be > 0
_VEHICLE_MAY_BE_ZERO = ("process_noise_sigma", "collision_radius_m")


def _vehicle(ctx: _Ctx, raw: Any) -> Vehicle:
    bounds = {k: {"ge": 0} if k in _VEHICLE_MAY_BE_ZERO else {"gt": 0} for k in Vehicle.__dataclass_fields__}
    v = _record(ctx, raw, Vehicle, "vehicle", bounds=bounds)
    if not v.v_max_mps > v.v_stall_mps:
        raise ctx.fail("vehicle.v_max_mps", f"must be > v_stall_mps ({v.v_stall_mps:g}), got {v.v_max_mps:g}")
    return v


def _uavs(ctx: _Ctx, raw: Any) -> Uavs:
    p = "uavs"
    d = _mapping(
        ctx, raw, p, {"count", "first", "spacing", "takeoff_interval_s", "vehicle_model", "airframe"}
    )
    first = _record(ctx, d.get("first"), Pose, "uavs.first")
    spacing = _record(ctx, d.get("spacing"), Spacing, "uavs.spacing")
    count = _int(ctx, d, "count", p, 5, ge=1)
    model = _choice(ctx, d, "vehicle_model", p, VEHICLE_MODELS, "ff_paper")
    if count > 255:
        raise ctx.fail("uavs.count", f"must be <= 255 (uint8 ids), got {count}")
    return Uavs(
        count=count,
        first=first,
        spacing=spacing,
        takeoff_interval_s=_num(ctx, d, "takeoff_interval_s", p, 2.0, ge=0),
        vehicle_model=model,
        airframe=read_airframe(ctx, d, model),
    )


def _sensor_bounds(name: str) -> dict[str, float]:
    """A sensor field's bounds by its name: a probability, a noise (may be 0), else a rate/range (> 0)."""
    if name == "p_valid":
        return {"ge": 0, "le": 1}
    if name.startswith("sigma") or name.endswith("sigma_m"):
        return {"ge": 0}
    return {"gt": 0}


def _sensors(ctx: _Ctx, raw: Any) -> Sensors:
    d = _mapping(ctx, raw, "sensors", {"gps", "altimeter", "gyro", "fire"})
    kinds: dict[str, type[Any]] = {
        "gps": GpsSpec,
        "altimeter": AltimeterSpec,
        "gyro": GyroSpec,
        "fire": FireSensorSpec,
    }
    out: dict[str, Any] = {}
    for key, cls in kinds.items():
        bounds = {f.name: _sensor_bounds(f.name) for f in dataclasses.fields(cls)}
        out[key] = _record(ctx, d.get(key), cls, f"sensors.{key}", bounds=bounds)
    return Sensors(**out)


def _comms(ctx: _Ctx, raw: Any, uav_count: int) -> Comms:
    """``comms``; every outage id must name a UAV of the fleet (0..uav_count-1)."""
    p = "comms"
    d = _mapping(ctx, raw, p, {"loss_probability", "outages"})
    outages = []
    for i, item in enumerate(_list(ctx, d, "outages", p)):
        op = f"comms.outages[{i}]"
        keys = {"from", "to", "start_s", "end_s"}
        od = _mapping(ctx, item, op, keys, keys)
        from_id, to_id = _int(ctx, od, "from", op, ge=0), _int(ctx, od, "to", op, ge=0)
        start_s, end_s = _num(ctx, od, "start_s", op, ge=0), _num(ctx, od, "end_s", op)
        if not end_s > start_s:
            raise ctx.fail(f"{op}.end_s", f"must be > start_s ({start_s:g}), got {end_s:g}")
        if from_id == to_id:
            raise ctx.fail(f"{op}.to", f"must differ from 'from' ({from_id})")
        o = LinkOutage(from_id=from_id, to_id=to_id, start_s=start_s, end_s=end_s)
        _check_outage_ids(ctx, i, o, uav_count)
        outages.append(o)
    return Comms(
        loss_probability=_num(ctx, d, "loss_probability", p, 0.05, ge=0, le=1), outages=tuple(outages)
    )


def _check_outage_ids(ctx: _Ctx, i: int, o: LinkOutage, uav_count: int) -> None:
    """Both ends of outage ``i`` must be UAVs of a fleet of ``uav_count`` (ids 0..uav_count-1)."""
    for key, uid in (("from", o.from_id), ("to", o.to_id)):
        if uid >= uav_count:
            raise ctx.fail(
                f"comms.outages[{i}].{key}", f"UAV {uid} does not exist: the fleet has ids 0..{uav_count - 1}"
            )


def _mission(ctx: _Ctx, raw: Any) -> MissionSettings:
    p = "mission"
    d = _mapping(ctx, raw, p, set(MissionSettings.__dataclass_fields__))
    m = MissionSettings()
    return MissionSettings(
        crash_threshold_steps=_int(ctx, d, "crash_threshold_steps", p, m.crash_threshold_steps, ge=1),
        grid_resolution_m=_num(ctx, d, "grid_resolution_m", p, m.grid_resolution_m, gt=0),
        sigma_water_m=_num(ctx, d, "sigma_water_m", p, m.sigma_water_m, gt=0),
        sigma_landing_m=_num(ctx, d, "sigma_landing_m", p, m.sigma_landing_m, gt=0),
        use_safety_band=_bool(ctx, d, "use_safety_band", p, m.use_safety_band),
        safety_radius_m=_num(ctx, d, "safety_radius_m", p, m.safety_radius_m, ge=0),
        monitors_per_fire=_int(ctx, d, "monitors_per_fire", p, m.monitors_per_fire, ge=0),
        search_first=_bool(ctx, d, "search_first", p, m.search_first),
        tactic=_choice(ctx, d, "tactic", p, TACTICS, m.tactic),
        prior_fires=_choice(ctx, d, "prior_fires", p, PRIOR_FIRES_MODES, m.prior_fires),
        prior_position_sigma_m=_num(ctx, d, "prior_position_sigma_m", p, m.prior_position_sigma_m, ge=0),
        prior_extent_sigma_fraction=_num(
            ctx, d, "prior_extent_sigma_fraction", p, m.prior_extent_sigma_fraction, ge=0, le=1
        ),
        lake_sequence=_choice(ctx, d, "lake_sequence", p, LAKE_SEQUENCES, m.lake_sequence),
        post_search_s=_num(ctx, d, "post_search_s", p, m.post_search_s, ge=0),
        post_search_max_s=_num(ctx, d, "post_search_max_s", p, m.post_search_max_s, ge=0),
        vertical_band=_choice(ctx, d, "vertical_band", p, VERTICAL_BANDS, m.vertical_band),
    )
