"""metrics.json + figures + index.html for one bag."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from fire_report import debrief
from fire_report.data import RecordedMission, load_mission
from fire_report.errors import ReportError
from fire_report.figures import make_figures
from fire_report.ground import Ground, mission_ground, places
from fire_report.metrics import compute_metrics, suppression_metrics
from fire_report.page import render_page
from fire_report.sections import Figure, Section, cp, pm
from fire_report.sections.bagdata import load_section_data

#: which part of the page shows a figure (by file name prefix); the rest go to the diagnostics
FIGURE_PLACES = (
    ("landscape", "maps"),
    ("voronoi_phases", "maps"),
    ("raster_front", "maps"),
    ("drops", "fires"),
    ("burned_area", "fires"),
    ("perimeter", "fires"),
    ("faults", "faults"),
)


def make_sections(mission: RecordedMission, out: Path, *, salvage: bool = True) -> list[Section]:
    """Every capability section the bag has data for (perimeter monitoring, coverage search),
    figures written into ``out``."""
    data = load_section_data(mission.path, mission.topics, salvage=salvage)
    found = [mod.build(mission, data, out) for mod in (pm, cp)]
    return [s for s in found if s is not None]


def place_figures(figures: list[Figure]) -> dict[str, list[Figure]]:
    """The figures grouped by the part of the page that shows them (see ``FIGURE_PLACES``)."""
    out: dict[str, list[Figure]] = {}
    for name, cap in figures:
        place = next((p for prefix, p in FIGURE_PLACES if name.startswith(prefix)), "diagnostics")
        out.setdefault(place, []).append((name, cap))
    return out


def _scenario_value(scenario: dict[str, Any], *path: str) -> Any:
    node: Any = scenario
    for key in path:
        node = node.get(key) if isinstance(node, dict) else None
    return node


def loss_probability(mission: RecordedMission) -> float | None:
    """The random loss rate the agents applied: the runner's ``--loss`` (the agents' parameters
    beside the bag) if given, else the scenario's ``comms.loss_probability`` (default 0.05)."""
    try:
        return float(debrief.agent_params(mission.path)["loss_probability"])
    except (KeyError, TypeError, ValueError):
        pass
    if not mission.uav_ids:
        return None
    v = _scenario_value(mission.scenario, "comms", "loss_probability")
    try:
        return float(v) if v is not None else 0.05
    except (TypeError, ValueError):
        return None


def collision_radius_m(mission: RecordedMission) -> float | None:
    """The scenario's collision radius [m] (its default when the scenario leaves it out); None
    when the bag holds no valid scenario."""
    from fire_uav_common.scenario import ScenarioError, scenario_from_dict

    try:
        return float(scenario_from_dict(mission.scenario).vehicle.collision_radius_m)
    except (ScenarioError, ValueError, TypeError, KeyError):
        return None


def with_latlon(rows: list[dict[str, Any]], ground: Ground) -> list[dict[str, Any]]:
    """Table rows with ``x_m``/``y_m`` given ``lat_deg``/``lon_deg`` too (WGS84, 6 decimals)."""
    out = []
    for r in rows:
        r = dict(r)
        if r.get("x_m") is not None and r.get("y_m") is not None:
            lat, lon = ground.latlon(r["x_m"], r["y_m"])
            r["lat_deg"], r["lon_deg"] = round(float(lat), 6), round(float(lon), 6)
        out.append(r)
    return out


def geo_metrics(mission: RecordedMission, ground: Ground, metrics: dict[str, Any]) -> list[dict[str, Any]]:
    """The places of a landscape mission (``ground.places``), stored in ``metrics["geo"]`` with
    the landscape and its map origin, and returned for the page."""
    rows = places(mission, ground)
    metrics["geo"] = {
        "landscape": ground.name,
        "projected_origin_m": list(ground.projected_origin),
        "places": rows,
    }
    return rows


def write_report(
    bag: str | Path, out_dir: str | Path, *, salvage: bool = True, baseline: str | Path | None = None
) -> dict[str, Any]:
    """Read ``bag`` and write metrics.json, the PNG figures and index.html into ``out_dir``.

    ``baseline``: a bag of the same scenario and seed with no fleet (``--uavs 0``) for the
    burned-area comparison (``baseline_burned_area_m2`` and the figure)."""
    mission = load_mission(bag, salvage=salvage)
    base = load_mission(baseline, salvage=salvage) if baseline is not None else None
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ReportError(f"{out}: cannot create the output directory: {err.strerror}") from None
    metrics = compute_metrics(mission)
    if base is not None:
        metrics["baseline_burned_area_m2"] = suppression_metrics(base)["burned_area_m2"]
    metrics["loss_probability"] = loss_probability(mission)
    if mission.fire_type_cells is not None:  # a fire on a landscape: burnt cells per fire type
        metrics["fire_type_cells"] = dict(
            zip(("surface", "passive_crown", "active_crown"), mission.fire_type_cells, strict=True)
        )
        metrics["fire_type_cell_m"] = mission.fire_type_cell_m
    notes = debrief.run_scenario_notes(mission.path)
    if notes:  # e.g. water left out as too small for a refill pass
        metrics["scenario_notes"] = notes
    known = debrief.run_summary_found(mission.path)
    metrics["injected_faults_known"] = known
    faults = debrief.with_responses(
        debrief.scenario_outages(mission.scenario) + debrief.run_faults(mission.path), mission
    )
    metrics["faults"] = [
        {"kind": f.kind, "t_s": f.t_s, "uav_id": f.uav, "peer_id": f.peer, "end_s": f.end_s,
         "source": f.source, "response": f.response}
        for f in faults
    ]  # fmt: skip
    outages = [(f.t_s, f.end_s) for f in faults if f.kind == "outage" and f.end_s is not None]
    ground, ground_warning = mission_ground(mission)
    if ground_warning:
        metrics.setdefault("warnings", []).append(ground_warning)
    where = geo_metrics(mission, ground, metrics) if ground is not None else []
    figures = make_figures(mission, out, base, outages, ground)
    sections = make_sections(mission, out, salvage=salvage)
    metrics["figures"] = [name for name, _ in figures] + [name for s in sections for name, _ in s.figures]
    metrics["sections"] = {s.key: s.metrics for s in sections}
    raster = _scenario_value(mission.scenario, "fires", "model") == "raster"
    radius = collision_radius_m(mission)
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2, default=str) + "\n", encoding="utf8")
    fires = debrief.fire_rows(mission, metrics, raster)
    if ground is not None:
        fires = with_latlon(fires, ground)
    page = render_page(
        metrics,
        mission.custom_data,
        entries=debrief.timeline(mission, metrics, faults, known=known),
        fires=fires,
        uavs=debrief.uav_rows(mission, metrics, faults, known=known),
        faults=faults,
        figures=place_figures(figures),
        sections=sections,
        raster=raster,
        collision_radius_m=radius,
        places=where,
        landscape=ground.name if ground is not None else None,
    )
    (out / "index.html").write_text(page, encoding="utf8")
    return metrics
