"""The numbers of metrics.json, computed from a :class:`~fire_report.data.RecordedMission` (pure numpy).

Sources: drops, extinctions, crashes and mission completion come from ``/world/events``
(the world is the authority); peers declared crashed from ``/fleet/events``; packet
counters from the last ``UavState`` of each UAV; EKF errors from ``UavState`` matched to
``WorldTruth`` by control step. All times are sim seconds.
"""

from __future__ import annotations

import math
import re
from typing import Any

import fire_perimeter_monitor.distance_error as de
import numpy as np
from fire_uav_common.constants import EventType, FireStatus

from fire_report.data import (
    RecordedMission,
)

PERCENTILES = (50, 90, 95, 99)
AXES = ("x", "y", "z", "yaw")


def wrap_angle(a: np.ndarray) -> np.ndarray:
    """Wrap radians to (-pi, pi]."""
    w = np.mod(a + np.pi, 2 * np.pi) - np.pi
    return np.where(w == -np.pi, np.pi, w)


def ekf_errors(mission: RecordedMission, uav: int) -> dict[str, np.ndarray]:
    """Estimate minus truth per axis for ``uav`` at the control steps both were recorded and
    the vehicle was airborne (FF Fig. 4 is about flight; on the ground the filter is idle).

    Returns t [s], x/y/z [m], yaw [rad] errors and trace_p (empty arrays when no match).
    """
    est, tru = mission.states.get(uav), mission.truth_vehicles.get(uav)
    empty = {k: np.zeros(0) for k in ("t", *AXES, "trace_p")}
    if not est or not tru:
        return empty
    _, ie, it = np.intersect1d(est["step"], tru["step"], return_indices=True)
    if "status" in tru:
        airborne = np.asarray(tru["status"])[it] == 1  # SensorBundle.VEHICLE_AIRBORNE
        ie, it = ie[airborne], it[airborne]
    if ie.size == 0:
        return empty
    out = {"t": est["t"][ie]}
    for ax in ("x", "y", "z"):
        out[ax] = est[ax][ie] - tru[ax][it]
    out["yaw"] = wrap_angle(est["yaw"][ie] - tru["yaw"][it])
    out["trace_p"] = np.trace(est["P"][ie], axis1=1, axis2=2)
    return out


def _percentiles(values: np.ndarray) -> dict[str, float] | None:
    if values.size == 0:
        return None
    a = np.abs(values)
    out = {f"p{p}": float(np.percentile(a, p)) for p in PERCENTILES}
    out["max"] = float(a.max())
    out["mean"] = float(a.mean())
    return out


def settled_index(stamps_s: np.ndarray, end_s: float) -> int:
    """Index of a UAV's state that counts as its final one: the newest stamped before the
    mission's last step ``end_s`` [s], else the newest of all.

    The world ends the mission at the step it finds it complete; whether the agents' answers to
    that step reach a subscriber before they are stopped depends on wall time (the supervisor
    may miss them, the recorder may hold them), so neither side counts them: the console summary
    and the report then give the same packet counts on every run.
    """
    t = np.asarray(stamps_s, dtype=float)
    before = np.flatnonzero(t < end_s - 1e-6)
    return int(before[np.argmax(t[before])]) if before.size else int(np.argmax(t))


def _fire_key(fire_id: int) -> str:
    return str(fire_id) if fire_id >= 0 else "missed"


def outcome(mission: RecordedMission) -> tuple[str, str]:
    """("complete" | "time_limit" | "incomplete", detail), as the mission runner names them.

    complete: the world's MISSION_COMPLETE has value 1 (every fire out and every surviving
    vehicle landed); time_limit: value 0 (max_duration_s reached); incomplete: no completion
    event (the recording stopped first). See docs/protocol.md, Events.
    """
    done = [e for e in mission.world_events if e.type == EventType.MISSION_COMPLETE]
    if not done:
        return "incomplete", "no MISSION_COMPLETE event in the bag"
    return ("complete" if done[-1].value >= 1.0 else "time_limit"), done[-1].detail


def mission_duration_s(mission: RecordedMission) -> float:
    """Sim time of MISSION_COMPLETE, else of the last message, measured from t = 0."""
    done = [e.t_s for e in mission.world_events if e.type == EventType.MISSION_COMPLETE]
    return float(done[-1] if done else mission.t_last_s)


def compute_metrics(mission: RecordedMission) -> dict[str, Any]:
    """Every metric of the report as a JSON-ready dict (see docs/recording.md for the keys)."""
    world, fleet = mission.world_events, mission.fleet_events
    # a drop request with an empty tank releases nothing: it is not a drop (value = kg released)
    drops = [e for e in world if e.type == EventType.DROP and e.value > 0]
    drop_times = np.asarray(sorted(e.t_s for e in drops), dtype=float)
    intervals = np.diff(drop_times)
    drops_per_fire: dict[str, int] = {}
    for e in drops:
        drops_per_fire[_fire_key(e.fire_id)] = drops_per_fire.get(_fire_key(e.fire_id), 0) + 1
    drops_per_uav: dict[str, int] = {}
    for e in drops:
        drops_per_uav[str(e.uav_id)] = drops_per_uav.get(str(e.uav_id), 0) + 1

    extinction: dict[str, float] = {}
    for e in world:
        if e.type == EventType.EXTINGUISHED and _fire_key(e.fire_id) not in extinction:
            extinction[_fire_key(e.fire_id)] = e.t_s

    end_s = mission_duration_s(mission)
    packets: dict[str, dict[str, int]] = {}
    for uav, s in sorted(mission.states.items()):
        if s:
            i = settled_index(s["t"], end_s)
            packets[str(uav)] = {k: int(s[k][i]) for k in ("received", "lost", "rejected")}

    errs = {uav: ekf_errors(mission, uav) for uav in mission.uav_ids}
    ekf: dict[str, Any] = {"samples": int(sum(e["t"].size for e in errs.values()))}
    for ax in AXES:
        ekf[ax] = _percentiles(np.concatenate([e[ax] for e in errs.values()]) if errs else np.zeros(0))
    horiz = [np.hypot(e["x"], e["y"]) for e in errs.values()]
    ekf["horizontal"] = _percentiles(np.concatenate(horiz) if horiz else np.zeros(0))
    ekf["per_uav"] = {
        str(uav): {
            **{ax: _percentiles(e[ax]) for ax in AXES},
            "horizontal": _percentiles(np.hypot(e["x"], e["y"])),
        }
        for uav, e in errs.items()
        if e["t"].size
    }
    ekf["units"] = {"x": "m", "y": "m", "z": "m", "yaw": "rad", "horizontal": "m"}

    event_counts: dict[str, int] = {}
    for e in world + fleet:
        key = f"{e.source}.{e.type_name}"
        event_counts[key] = event_counts.get(key, 0) + 1

    result, detail = outcome(mission)
    scenario = mission.scenario
    outages = ((scenario.get("comms") or {}).get("outages") or []) if isinstance(scenario, dict) else []
    return {
        "bag": mission.path,
        "scenario": scenario.get("name") if isinstance(scenario, dict) else None,
        "seed": _int_or_none(mission.custom_data.get("fire_uav.seed")),
        "uav_count": _int_or_none(mission.custom_data.get("fire_uav.uav_count")) or len(mission.uav_ids),
        "outcome": result,
        "outcome_detail": detail,
        "mission_duration_s": mission_duration_s(mission),
        "drop_count": len(drops),
        "drops_per_fire": dict(sorted(drops_per_fire.items())),
        "drops_per_uav": dict(sorted(drops_per_uav.items(), key=lambda kv: int(kv[0]))),
        "drop_times_s": [float(t) for t in drop_times],
        "mean_inter_drop_interval_s": float(intervals.mean()) if intervals.size else None,
        "inter_drop_intervals_s": [float(x) for x in intervals],
        "extinction_times_s": dict(sorted(extinction.items())),
        "crash_events": [
            {"t_s": e.t_s, "uav_id": e.uav_id, "detail": e.detail} for e in world if e.type == EventType.CRASH
        ],
        "peers_declared_crashed": [
            {"t_s": e.t_s, "by_uav": e.uav_id, "peer_id": e.peer_id}
            for e in fleet
            if e.type == EventType.PEER_CRASHED
        ],
        "peers_rejoined": [
            {"t_s": e.t_s, "by_uav": e.uav_id, "peer_id": e.peer_id}
            for e in fleet
            if e.type == EventType.PEER_REJOINED
        ],
        "packets": packets,
        "packets_lost_total": int(sum(p["lost"] for p in packets.values())),
        "packets_rejected_total": int(sum(p["rejected"] for p in packets.values())),
        "link_outages_scheduled": outages,
        **safety_metrics(mission),
        **fire_counts(mission),
        "ekf_error": ekf,
        "perimeter_distance_error_m": perimeter_errors(mission),
        "perimeter_distance_error_floor_m": perimeter_error_floors(mission),
        **suppression_metrics(mission),
        "event_counts": dict(sorted(event_counts.items())),
        "recorder_closed_cleanly": mission.custom_data.get("fire_uav.closed_cleanly") == "true",
        "warnings": list(mission.warnings),
    }


def home_xy(mission: RecordedMission) -> dict[int, tuple[float, float]]:
    """Takeoff point (x, y) [m; map] of every UAV: the scenario's start poses (as the runner's
    summary takes them), else, for a bag without a readable scenario, the first true position."""
    from fire_uav_common.scenario import ScenarioError, scenario_from_dict

    n = _int_or_none(mission.custom_data.get("fire_uav.uav_count"))
    try:
        sc = scenario_from_dict(mission.scenario)
        poses = sc.uav_start_poses(n if n is not None else len(mission.uav_ids))
        return {i: (float(p[0]), float(p[1])) for i, p in enumerate(poses)}
    except (ScenarioError, ValueError, TypeError, KeyError):
        return {u: (float(v["x"][0]), float(v["y"][0])) for u, v in mission.truth_vehicles.items() if v}


def safety_metrics(mission: RecordedMission) -> dict[str, Any]:
    """Closest approach, collisions and landings (FF IV-D d), as the runner's summary has them.

    min_separation_m: the least 3-D distance between two airborne vehicles over the mission [m]
    (the world's running figure in ``/world/truth``; None if never two flew at once);
    collisions: colliding pairs; landing_error_m: per landed UAV, the horizontal distance from
    its touchdown (its first LANDED event) to its takeoff point [m]; touchdown_spacing_m: the
    least distance between two touchdown points [m].
    """
    sep = mission.separation
    finite = sep["min_separation_m"][np.isfinite(sep["min_separation_m"])] if sep else np.zeros(0)
    touchdown: dict[int, tuple[float, float]] = {}
    for e in mission.world_events:
        if e.type == EventType.LANDED and math.isfinite(e.x_m) and math.isfinite(e.y_m):
            touchdown.setdefault(e.uav_id, (e.x_m, e.y_m))
    home = home_xy(mission) if touchdown else {}
    errors = {
        str(u): math.hypot(x - home[u][0], y - home[u][1])
        for u, (x, y) in sorted(touchdown.items())
        if u in home
    }
    pts = list(touchdown.values())
    spacing = [math.dist(a, b) for i, a in enumerate(pts) for b in pts[i + 1 :]]
    return {
        "min_separation_m": float(finite.min()) if finite.size else None,
        "collisions": int(sep["collisions"].max()) if sep else 0,
        "landed": sorted({e.uav_id for e in mission.world_events if e.type == EventType.LANDED}),
        "landing_error_m": errors,
        "touchdown_spacing_m": min(spacing) if spacing else None,
    }


def fire_counts(mission: RecordedMission) -> dict[str, Any]:
    """fires_total and fires_active_at_end from the last ``/world/truth`` sample of each fire."""
    last = [int(f["status"][-1]) for f in mission.truth_fires.values() if f]
    return {
        "fires_total": len(last) if last else None,
        "fires_active_at_end": sum(s == FireStatus.ACTIVE for s in last) if last else None,
    }


def _int_or_none(text: str | None) -> int | None:
    try:
        return int(text) if text is not None else None
    except ValueError:
        return None


def perimeter_distance_error(mission: RecordedMission, uav: int, fire: int) -> dict[str, np.ndarray]:
    """PM VI-E distance error [m] per PerimeterMap without a raster: the maximum over 360 angles of
    |true extent - extent of the hull of the map's bin points|, the truth the circle of the fire's
    equivalent radius sqrt(area/pi) from /world/truth at the nearest step (convex: floor 0)."""
    per, tru = mission.perimeters.get((uav, fire)), mission.truth_fires.get(fire)
    if not per or not tru:
        return {"t": np.zeros(0), "error_m": np.zeros(0), "floor_m": np.zeros(0)}
    idx = np.clip(np.searchsorted(tru["t"], per["t"]), 0, tru["t"].size - 1)
    radius = np.sqrt(np.maximum(tru["area"][idx], 0.0) / math.pi)
    ts, errs = [], []
    for k in range(per["t"].size):
        pts = de.bin_points(tuple(per["center"][k]), per["outer"][k])
        if pts.shape[0] < 3:
            continue
        est = de.hull_extent(pts, 1e-6, tuple(per["center"][k]))  # points: no raster cell
        e = de.max_error(np.full(de.N_ANGLES, radius[k]), est)
        if math.isfinite(e):
            ts.append(per["t"][k])
            errs.append(e)
    return {"t": np.asarray(ts), "error_m": np.asarray(errs), "floor_m": np.zeros(len(errs))}


def perimeter_errors(mission: RecordedMission) -> dict[str, float]:
    """'uav/fire' -> mean over the mission of the maximum distance error [m] (PM Fig. 16's value)."""
    return {k: v[0] for k, v in _perimeter_error_pairs(mission).items()}


def perimeter_error_floors(mission: RecordedMission) -> dict[str, float]:
    """'uav/fire' -> the same for the perfect, instantaneous map [m] (what the hull alone costs)."""
    return {k: v[1] for k, v in _perimeter_error_pairs(mission).items()}


def _perimeter_error_pairs(mission: RecordedMission) -> dict[str, tuple[float, float]]:
    out = {}
    for uav, fire in sorted(mission.perimeters):
        fn = perimeter_distance_error_raster if mission.fire_grids else perimeter_distance_error
        e = fn(mission, uav, fire)
        if e["error_m"].size:
            out[f"{uav}/{fire}"] = (float(e["error_m"].mean()), float(e["floor_m"].mean()))
    return out


def voronoi_labels(
    sites_xy: np.ndarray, x_range: tuple[float, float], y_range: tuple[float, float], resolution_m: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest-site label of every grid cell centre (FF III-A partition on a grid).

    Returns (xs, ys, labels[ny, nx]) with labels indexing ``sites_xy`` rows; -1 if no sites.
    """
    xs = np.arange(x_range[0] + resolution_m / 2, x_range[1], resolution_m)
    ys = np.arange(y_range[0] + resolution_m / 2, y_range[1], resolution_m)
    if len(sites_xy) == 0:
        return xs, ys, np.full((ys.size, xs.size), -1)
    gx, gy = np.meshgrid(xs, ys)
    d2 = (gx[..., None] - sites_xy[:, 0]) ** 2 + (gy[..., None] - sites_xy[:, 1]) ** 2
    return xs, ys, np.argmin(d2, axis=-1)


# --- suppression measures, recomputed from the bag ---------------------------
CONTAINMENT_WINDOW_S = 60.0  # [s] as fire_world_sim.measures.CONTAINMENT_WINDOW_S
_CELLS_BURNING = re.compile(r"(\d+) of (\d+) cells burning")


def containment_from_area(
    t_s: np.ndarray, area_m2: np.ndarray, active: np.ndarray, *, raster: bool
) -> float | None:
    """Time to containment [s] from the burned-area history of ``/world/truth``, or None.

    Same definition as the world's (``fire_world_sim.measures.Containment``), recomputed from
    what the bag holds: the fire is contained at a sample t when no fire is active, or when the
    burned area has not grown in (t - 60 s, t] (the area grows exactly when a cell ignites);
    the result is the first sample from which that holds to the end. The world uses the cells'
    exact ignition times; this uses the sample at which the area changed, so the two agree to
    within the fire's propagation update (0.5 s). ``active``: any fire ACTIVE at each sample.

    ``raster`` False (analytic fires): they do not spread cell by cell, so an area that stays put
    says nothing; as for the world, they are contained only once every fire is out.
    """
    t = np.asarray(t_s, dtype=float)
    a = np.asarray(area_m2, dtype=float)
    on = np.asarray(active, dtype=bool)
    if t.size == 0:
        return None
    grew = np.r_[True, np.diff(a) > 0]
    last_growth = np.maximum.accumulate(np.where(grew, t, -np.inf))
    quiet = ~on | (t - last_growth >= CONTAINMENT_WINDOW_S - 1e-9) if raster else ~on
    if not quiet[-1]:
        return None
    breaks = np.flatnonzero(~quiet)
    first = int(breaks[-1]) + 1 if breaks.size else 0
    return float(t[first])


def drop_outcomes(events: list, is_raster: bool) -> dict[str, Any]:
    """Hit rate and water on burning cells [kg] from ``/world/events`` DROP events.

    A drop (value = kg released > 0) hits when it names a fire (``fire_id`` >= 0: it wet at
    least one burning cell). Water on burning cells: raster drops carry "B of M cells burning"
    in their detail (kg x B / M); an analytic hit counts its whole load.
    """
    drops = [e for e in events if e.type == EventType.DROP and e.value > 0]
    hits = [e for e in drops if e.fire_id >= 0]
    on = 0.0
    for e in drops:
        m = _CELLS_BURNING.search(e.detail)
        if m and int(m.group(2)) > 0:
            on += e.value * int(m.group(1)) / int(m.group(2))
        elif not is_raster and e.fire_id >= 0:
            on += e.value
    return {
        "drops": len(drops),
        "hits": len(hits),
        "hit_rate": len(hits) / len(drops) if drops else None,
        "water_released_kg": float(sum(e.value for e in drops)),
        "water_on_burning_kg": on,
    }


def burned_area_series(mission: RecordedMission) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t [s], burned area [m^2] summed over fires, any fire active) per ``/world/truth`` sample."""
    fires = [f for f in mission.truth_fires.values() if f]
    if not fires:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool)
    t = np.unique(np.concatenate([f["t"] for f in fires]))
    area = np.zeros(t.size)
    active = np.zeros(t.size, dtype=bool)
    for f in fires:
        idx = np.clip(np.searchsorted(f["t"], t, side="right") - 1, 0, f["t"].size - 1)
        seen = t >= f["t"][0]
        area += np.where(seen, f["area"][idx], 0.0)
        active |= seen & (f["status"][idx] == FireStatus.ACTIVE)
    return t, area, active


def suppression_metrics(mission: RecordedMission) -> dict[str, Any]:
    """hit_rate, burned_area_m2, contained_at_s (+ drops, water) from the bag, any fire model."""
    fires = mission.scenario.get("fires") if isinstance(mission.scenario, dict) else None
    is_raster = isinstance(fires, dict) and fires.get("model") == "raster"
    t, area, active = burned_area_series(mission)
    out = drop_outcomes(mission.world_events, is_raster)
    out["burned_area_m2"] = float(area[-1]) if area.size else None
    out["contained_at_s"] = containment_from_area(t, area, active, raster=is_raster)
    return out


def baseline_area(baseline: RecordedMission | None) -> dict[str, Any] | None:
    """Burned area [m^2] over time of a baseline mission (the same scenario and seed recorded with
    ``scripts/run_mission SCENARIO --uavs 0``: the fire alone), or None without one."""
    if baseline is None:
        return None
    t, area, _ = burned_area_series(baseline)
    return {"t_s": t, "area_m2": area} if t.size else None


def true_outer_distance(grid: dict[str, Any], center_xy: tuple[float, float], bins: int) -> np.ndarray:
    """Per angle bin around ``center_xy``, the farthest burnt or burning cell of a /viz/fire_grid [m]
    (PM's true perimeter for the distance-error metric); NaN where the bin has no such cell."""
    data = grid["data"]
    i, j = np.nonzero(data >= 60)  # burnt (60) or burning (100)
    out = np.full(bins, np.nan)
    if i.size == 0:
        return out
    res = grid["resolution"]
    x = grid["origin"][0] + (j + 0.5) * res - center_xy[0]
    y = grid["origin"][1] + (i + 0.5) * res - center_xy[1]
    b = (np.floor(np.mod(np.arctan2(y, x), 2 * np.pi) / (2 * np.pi) * bins).astype(int)) % bins
    d = np.hypot(x, y)
    np.fmax.at(out, b, d)
    return out


def perimeter_distance_error_raster(mission: RecordedMission, uav: int, fire: int) -> dict[str, np.ndarray]:
    """PM VI-E distance error [m] per PerimeterMap against the true raster fire (/viz/fire_grid),
    ``fire_perimeter_monitor.distance_error`` (as the report's PM section and the benchmark):
    maximum over 360 angles about the map's centre of |true extent - extent of the hull of the
    map's cells|, and the perfect map's floor, against the fire grid nearest in time (kept every
    10 s). The fleet's fire ids are not the world's, so no id matching is needed here."""
    per = mission.perimeters.get((uav, fire))
    grids = mission.fire_grids
    if not per or not grids:
        return {"t": np.zeros(0), "error_m": np.zeros(0), "floor_m": np.zeros(0)}
    gt = np.asarray([g["t"] for g in grids])
    ts, errs, floors = [], [], []
    for k in range(per["t"].size):
        g = grids[int(np.argmin(np.abs(gt - per["t"][k])))]
        res = float(g["resolution"])
        cells = de.grid_cells(g["data"] >= 60, g["origin"][0], g["origin"][1], res)  # burnt or burning
        pts = de.bin_points(tuple(per["center"][k]), per["outer"][k])
        if pts.shape[0] == 0:
            continue
        e = de.distance_error(cells, pts, res, (float(per["center"][k][0]), float(per["center"][k][1])))
        if math.isfinite(e.max_m):
            ts.append(per["t"][k])
            errs.append(e.max_m)
            floors.append(e.floor_m)
    return {"t": np.asarray(ts), "error_m": np.asarray(errs), "floor_m": np.asarray(floors)}
