"""Scenario files: load, validate and expose them as frozen dataclasses (docs/scenario.md).

``load_scenario(path) -> Scenario``. Attribute names are the YAML keys (``Scenario.area.x_min_m``,
``Scenario.vehicle.v_stall_mps``...), with two exceptions forced by Python: the outage key
``from`` is the attribute ``from_`` and ``to`` stays ``to``. Units are in the key names;
positions are in the ``map`` frame (x east, y north, z up, metres).

The package: ``types`` (the dataclasses), ``fields`` (the one-value readers and their
path-naming errors), ``sections`` and ``fires`` (one reader per section); this module the entry
points. Any wrong, missing or unknown field raises :class:`ScenarioError`, whose message names the file
and the dotted field path, e.g. ``scenarios/x.yaml: fires.analytic[1].sigma_m: must be > 0, got -3``.

Extensions to docs/scenario.md (all optional, defaults keep the documented behaviour):

- ``uavs.vehicle_model``: ``ff_paper`` (default, FF Eq. 4) or ``coordinated_turn``;
  ``uavs.airframe``: a preset name or ``{preset: NAME, <field>: value}`` for the fixed-wing
  models (default ``small_uav``); the preset replaces the envelope fields of ``vehicle``
  (``airframes.envelope_vehicle``, docs/airframes.md).
- ``fires.drop_radius_m``: radius [m] of a drop's footprint; ``null`` (default) means "the
  fire's sigma" for analytic fires (protocol "Payload") and 20 m for the raster fire.
- ``fires.drop_model``: ``disc`` (default: every burning cell within ``drop_radius_m`` goes out)
  or ``pattern`` (a ground pattern with a coverage per cell from the vehicle's speed, height and
  ``drop_flow_lps``: ``vehicle.drop_flow_lps`` or the airframe preset's; docs/suppression.md).
- ``fires.raster.wet_duration_s``: a wetted cell cannot ignite for this long (default 600 s;
  with ``drop_model: pattern`` scaled by the cell's coverage over the coverage it needs).
- ``fires.raster.spread_factor``: multiplies every rate of spread (default 1.0), to speed up
  demonstrations without changing the fuel physics.
- ``fires.raster.wind_limit``: ``behave`` (default: Rothermel's 0.9 I_R limit as Behave applies
  it), ``andrews2013`` (rate of spread capped at the effective wind speed) or ``none``.
- ``fires.raster.ignitions[].start_s`` may be negative (a fire already burning when the
  mission starts); ``fires.raster.wind[0].start_s`` must then be at or before the earliest one.
- ``fires.raster.wind[].grid`` (with a landscape): a gridded 20-ft wind, WindNinja's ASCII pair
  ``{vel: A_vel.asc, ang: A_ang.asc, speed_units: mph}`` or a 2-band GeoTIFF ``{tif: W.tif}``
  (:mod:`.wind_grid`); the entry's ``speed_mps`` / ``direction_deg`` are then optional.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from ..errors import ScenarioError
from .airframes import (
    AIRFRAMES,
    DEFAULT_AIRFRAME,
    DEFAULT_AIRFRAMES,
    VEHICLE_MODELS,
    Airframe,
    ExcessPower,
    envelope_vehicle,
)
from .fields import _Ctx, _int, _mapping, _str
from .fires import _fires
from .ground import apply_landscape
from .placement import check_placement
from .sections import (
    _area,
    _check_outage_ids,
    _comms,
    _lakes,
    _mission,
    _sensors,
    _terrain,
    _timing,
    _uavs,
    _vehicle,
)
from .types import (
    DROP_MODELS,
    FIRE_MODELS,
    FUEL_MODELS,
    LAKE_SEQUENCES,
    PRIOR_FIRES_MODES,
    TACTICS,
    VERTICAL_BANDS,
    WIND_LIMITS,
    AltimeterSpec,
    AnalyticFire,
    Area,
    Comms,
    Fires,
    FireSensorSpec,
    FuelPatch,
    GpsSpec,
    GyroSpec,
    Ignition,
    LinkOutage,
    MissionSettings,
    Moistures,
    Origin,
    Pose,
    Raster,
    RasterLandscape,
    Scenario,
    Sensors,
    Spacing,
    Timing,
    Uavs,
    Vehicle,
    Wind,
    WindGrid,
)

__all__ = [
    "AIRFRAMES",
    "Airframe",
    "ExcessPower",
    "VEHICLE_MODELS",
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
    "MissionSettings",
    "Origin",
    "LinkOutage",
    "Pose",
    "Moistures",
    "Raster",
    "RasterLandscape",
    "Scenario",
    "ScenarioError",
    "Sensors",
    "Spacing",
    "Timing",
    "Uavs",
    "Vehicle",
    "Wind",
    "WindGrid",
    "DROP_MODELS",
    "FIRE_MODELS",
    "FUEL_MODELS",
    "LAKE_SEQUENCES",
    "VERTICAL_BANDS",
    "PRIOR_FIRES_MODES",
    "TACTICS",
    "WIND_LIMITS",
    "load_scenario",
    "check_fleet_size",
    "scenario_from_dict",
]


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
    "paths_relative_to",
}


def _apply_overrides(ctx: _Ctx, raw: dict, overrides: Mapping[str, Any]) -> dict:
    """Return a copy of ``raw`` with dotted-path overrides applied (``{"uavs.count": 3, "seed": 7}``)."""
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


def _preset_owner(raw_uavs: Any) -> str:
    """Whose scoop run an error line names: "the tanker preset's" (the ``uavs.airframe`` preset,
    already validated), or "uavs.airframe's" when the run is not a preset's own."""
    raw = raw_uavs.get("airframe") if isinstance(raw_uavs, Mapping) else None
    model = raw_uavs.get("vehicle_model") if isinstance(raw_uavs, Mapping) else None
    default = DEFAULT_AIRFRAMES.get(model, DEFAULT_AIRFRAME) if isinstance(model, str) else DEFAULT_AIRFRAME
    if raw is None:
        return f"the {default} preset's"
    if isinstance(raw, str):
        return f"the {raw} preset's"
    if isinstance(raw, Mapping):
        # a preset with fields replaced: its scoop run may no longer be the preset's
        if set(raw) <= {"preset"}:
            return f"the {raw.get('preset', default)} preset's"
        return "uavs.airframe's"
    return "uavs.airframe's"


def _check_lake_runs(ctx: _Ctx, scenario: Scenario, owner: str) -> None:
    """A lake written in the scenario must be long enough for the airframe's scoop run: a
    fixed-wing scoops on a straight pass and a disc's longest one is its diameter. FF's unicycle
    (no airframe) hovers over any lake as long as it needs."""
    airframe = scenario.uavs.airframe
    if airframe is None:
        return
    need = airframe.scoop_run_m
    for i, lake in enumerate(scenario.lakes):
        if lake.longest_run.length_m < need:
            raise ctx.fail(
                f"lakes[{i}].diameter_m",
                f"{lake.diameter_m:g} m is shorter than {owner} {need:.0f} m scoop run "
                "(a fixed-wing scoops on one straight pass over the water)",
            )


def _base_dir(ctx: _Ctx, d: dict) -> str:
    """``paths_relative_to``: an absolute folder the scenario's relative file paths start from,
    instead of the scenario file's own folder. ``run_mission --set`` writes it into the copy of the
    scenario it leaves in the run folder, so that the copy's landscape and wind grid paths still
    name the files beside the original."""
    base = _str(ctx, d, "paths_relative_to", "")
    if not Path(base).is_absolute():
        raise ctx.fail("paths_relative_to", f"must be an absolute path, got {base!r}")
    if not Path(base).is_dir():
        raise ctx.fail("paths_relative_to", f"{base!r} is not a directory")
    return base


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
    if d.get("paths_relative_to") is not None:  # before any field that names a file
        ctx.paths_relative_to = _base_dir(ctx, d)
    seed = _int(ctx, d, "seed", "", 0, ge=0)
    uavs = _uavs(ctx, d.get("uavs"))
    scenario = Scenario(
        name=_str(ctx, d, "name", ""),
        description=_str(ctx, d, "description", "", "") if d.get("description") is not None else "",
        seed=seed,
        area=_area(ctx, d.get("area")),
        terrain=_terrain(ctx, d.get("terrain")),
        lakes=_lakes(ctx, d.get("lakes")),
        timing=_timing(ctx, d.get("timing")),
        vehicle=envelope_vehicle(_vehicle(ctx, d.get("vehicle")), uavs.airframe),
        uavs=uavs,
        sensors=_sensors(ctx, d.get("sensors")),
        fires=_fires(ctx, d.get("fires")),
        comms=_comms(ctx, d.get("comms"), uavs.count),
        mission=_mission(ctx, d.get("mission")),
        path="" if file == "<dict>" else file,
    )
    owner = _preset_owner(d.get("uavs"))
    _check_lake_runs(ctx, scenario, owner)
    if scenario.mission.prior_fires == "known" and scenario.fires.model != "analytic":
        # the briefing (fire_world_sim.dispatch) holds analytic fires only, and an agent told its
        # fires are known does not search: on a raster fire it would have nothing to find them by
        raise ctx.fail(
            "mission.prior_fires",
            f"'known' briefs analytic fires only, got fires.model {scenario.fires.model!r} "
            "(a raster fire has no single centre and extent: leave it 'unknown', the fleet searches)",
        )
    scenario = apply_landscape(ctx, scenario, terrain_given=d.get("terrain") is not None, run_owner=owner)
    check_placement(ctx, scenario)
    return scenario


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


def check_fleet_size(scenario: Scenario, uav_count: int) -> None:
    """Check the scenario against a fleet of ``uav_count`` UAVs (the runner's ``--uavs`` may differ
    from ``uavs.count``): every ``comms.outages`` id must be one of them. Raises
    :class:`ScenarioError` naming the file and the field."""
    ctx = _Ctx(scenario.path or "<dict>")
    for i, o in enumerate(scenario.comms.outages):
        _check_outage_ids(ctx, i, o, uav_count)
