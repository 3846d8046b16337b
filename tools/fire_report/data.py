"""Read a mission bag into plain numpy arrays (no ROS: rosbags with the bag's own definitions).

Times are sim seconds taken from the messages' ``header.stamp`` (the bag timestamp for
messages without one). Positions are metres in the ``map`` frame (x east, y north, z up).
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import fire_uav_recording as bag_io
import numpy as np
import yaml
from fire_uav_common.constants import EventType
from fire_uav_common.stamps import stamp_to_s
from fire_uav_common.topics import (
    CLOCK,
    FLEET_EVENTS,
    FLEET_FIRES,
    FLEET_FRONT,
    FLEET_PERIMETER,
    FLEET_STATE,
    VIZ_FIRE_GRID,
    WORLD_EVENTS,
    WORLD_FIRE_TYPE,
    WORLD_TRUTH,
)

from fire_report.errors import ReportError

FIRE_GRID_EVERY_S = 10.0  # [s] keep one /viz/fire_grid per this much sim time

#: MissionEvent type -> its name in the report ("drop", "peer_crashed", ...)
TYPE_NAMES: dict[int, str] = {int(e): e.name.lower() for e in EventType}


@dataclass(frozen=True)
class RecordedEvent:
    """One MissionEvent read from the recording. ``source``: "world" or "fleet" (the topic it was
    recorded on); t_s: sim time [s]. The runner's live counterpart: ``fire_mission.summary.LiveEvent``."""

    t_s: float
    type: int
    uav_id: int
    peer_id: int
    fire_id: int
    x_m: float
    y_m: float
    value: float
    detail: str
    source: str

    @property
    def type_name(self) -> str:
        return TYPE_NAMES.get(self.type, f"type_{self.type}")


@dataclass
class RecordedMission:
    """Everything the report needs from one bag, as arrays sorted by time."""

    path: str
    custom_data: dict[str, str]
    scenario: dict[str, Any]
    warnings: list[str]
    topics: dict[str, str]
    t_first_s: float = 0.0  # earliest sim time seen
    t_last_s: float = 0.0  # latest sim time seen
    # per UAV (UavState): t, step, x, y, z, yaw, P (n,4,4), objective, water, lost, received, rejected
    states: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    # per UAV (WorldTruth vehicles): t, step, x, y, z, yaw, status
    truth_vehicles: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    # per fire (WorldTruth fires): t, x, y, extent, area, status, drops
    truth_fires: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    # per (uav, fire_id) (FireEstimateArray): t, x, y, extent, status
    fire_estimates: dict[tuple[int, int], dict[str, np.ndarray]] = field(default_factory=dict)
    # per (uav, fire_id) (PerimeterMap): t, center (n,2), outer (n,bins)
    perimeters: dict[tuple[int, int], dict[str, np.ndarray]] = field(default_factory=dict)
    world_events: list[RecordedEvent] = field(default_factory=list)
    fleet_events: list[RecordedEvent] = field(default_factory=list)
    # raster fire (/viz/fire_grid), one per FIRE_GRID_EVERY_S: t [s], origin (x, y) [m], resolution [m],
    # data (ny, nx) int8 as the world publishes it (unburned 0, wet 20, burnt 60, burning 100)
    fire_grids: list[dict[str, Any]] = field(default_factory=list)
    # a fire on a landscape (/world/fire_type, the newest): burnt cells [surface, passive, active crown]
    fire_type_cells: list[int] | None = None
    fire_type_cell_m: float = 0.0  # [m] its cell side
    # per UAV (/fleet/front): list of {t, x (n,), y (n,), state (n,)} -- its shared front picture
    fronts: dict[int, list[dict[str, Any]]] = field(default_factory=dict)
    # WorldTruth's running safety figures: t [s], min_separation_m [m] (inf until two fly), collisions [-]
    separation: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def uav_ids(self) -> list[int]:
        return sorted(set(self.states) | set(self.truth_vehicles))

    @property
    def fire_ids(self) -> list[int]:
        ids = set(self.truth_fires) | {f for _, f in self.fire_estimates}
        ids |= {
            e.fire_id for e in self.world_events if e.type in (EventType.EXTINGUISHED, EventType.IGNITION)
        }
        return sorted(i for i in ids if i >= 0)


def _stamp_s(msg: Any) -> float:
    return stamp_to_s(msg.header.stamp)


def _arrays(rows: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    rows = sorted(rows, key=lambda r: r["t"])
    return {k: np.asarray([r[k] for r in rows]) for k in rows[0]} if rows else {}


def _event(msg: Any, source: str) -> RecordedEvent:
    return RecordedEvent(
        _stamp_s(msg),
        int(msg.type),
        int(msg.uav_id),
        int(msg.peer_id),
        int(msg.fire_id),
        float(msg.x_m),
        float(msg.y_m),
        float(msg.value),
        str(msg.detail),
        source,
    )


def parse_scenario(text: str) -> dict[str, Any]:
    """The scenario stored in the bag's metadata, as a dict ({} if none or unreadable)."""
    if not text:
        return {}
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError:
        return {}
    return doc if isinstance(doc, dict) else {}


def load_mission(path: str | Path, *, salvage: bool = True) -> RecordedMission:
    """Read the bag at ``path``; raise :class:`ReportError` (one line) when it cannot be read."""
    try:
        with bag_io.open_bag(path, salvage=salvage) as bag:
            return _load(bag, str(path))
    except bag_io.BagError as err:
        raise ReportError(str(err)) from None


def _load(bag: bag_io.MissionBag, path: str) -> RecordedMission:
    custom = dict(bag.custom_data)
    mission = RecordedMission(
        path=path,
        custom_data=custom,
        scenario=parse_scenario(custom.get(bag_io.KEY_SCENARIO_YAML, "")),
        warnings=list(bag.warnings),
        topics=bag.topics,
    )
    states: dict[int, list[dict[str, Any]]] = defaultdict(list)
    tveh: dict[int, list[dict[str, Any]]] = defaultdict(list)
    tfire: dict[int, list[dict[str, Any]]] = defaultdict(list)
    fest: dict[tuple[int, int], list[dict[str, Any]]] = defaultdict(list)
    perim: dict[tuple[int, int], list[dict[str, Any]]] = defaultdict(list)
    sep: list[dict[str, Any]] = []
    wanted = [CLOCK, FLEET_STATE, FLEET_FIRES, FLEET_PERIMETER, FLEET_EVENTS, WORLD_TRUTH, WORLD_EVENTS]
    wanted += [VIZ_FIRE_GRID, FLEET_FRONT, WORLD_FIRE_TYPE]
    t_min, t_max = math.inf, -math.inf
    for topic, t_ns, msg in bag.messages([t for t in wanted if t in mission.topics]):
        if topic == CLOCK:
            t = stamp_to_s(msg.clock)
        elif topic == FLEET_STATE:
            t = _stamp_s(msg)
            states[int(msg.uav_id)].append(
                {
                    "t": t,
                    "step": int(msg.step),
                    "x": msg.x_m,
                    "y": msg.y_m,
                    "z": msg.z_m,
                    "yaw": msg.yaw_rad,
                    "P": np.asarray(msg.covariance, dtype=float).reshape(4, 4),
                    "objective": int(msg.objective),
                    "water": float(msg.water_kg),
                    "lost": int(msg.packets_lost),
                    "received": int(msg.packets_received),
                    "rejected": int(msg.packets_rejected),
                }
            )
            for f in getattr(
                msg, "fires", ()
            ):  # the fire picture rides in the state (bags before: /fleet/fires)
                fest[(int(msg.uav_id), int(f.fire_id))].append(
                    {"t": t, "x": f.x_m, "y": f.y_m, "extent": f.extent_m, "status": int(f.status)}
                )
        elif topic == WORLD_TRUTH:
            t = _stamp_s(msg)
            sep.append(
                {"t": t, "min_separation_m": float(msg.min_separation_m), "collisions": int(msg.collisions)}
            )
            for v in msg.vehicles:
                tveh[int(v.uav_id)].append(
                    {
                        "t": t,
                        "step": int(msg.step),
                        "x": v.x_m,
                        "y": v.y_m,
                        "z": v.z_m,
                        "yaw": v.yaw_rad,
                        "status": int(v.status),
                    }
                )
            for f in msg.fires:
                tfire[int(f.fire_id)].append(
                    {
                        "t": t,
                        "x": f.x_m,
                        "y": f.y_m,
                        "extent": f.extent_m,
                        "area": f.area_m2,
                        "status": int(f.status),
                        "drops": int(f.drops_received),
                    }
                )
        elif topic == FLEET_FIRES:
            t = _stamp_s(msg)
            for f in msg.fires:
                fest[(int(msg.uav_id), int(f.fire_id))].append(
                    {"t": t, "x": f.x_m, "y": f.y_m, "extent": f.extent_m, "status": int(f.status)}
                )
        elif topic == FLEET_PERIMETER:
            t = _stamp_s(msg)
            perim[(int(msg.uav_id), int(msg.fire_id))].append(
                {
                    "t": t,
                    "center": (msg.center_x_m, msg.center_y_m),
                    "outer": np.asarray(msg.outer_distance_m, dtype=float),
                }
            )
        elif topic == WORLD_FIRE_TYPE:  # the newest wins: cells keep their type once burnt
            t = _stamp_s(msg)
            mission.fire_type_cells = np.bincount(np.asarray(msg.data, dtype=np.int64), minlength=4)[
                1:4
            ].tolist()
            mission.fire_type_cell_m = float(msg.info.resolution)
        elif topic == VIZ_FIRE_GRID:
            t = _stamp_s(msg)
            grids = mission.fire_grids
            if not grids or t - grids[-1]["t"] >= FIRE_GRID_EVERY_S - 1e-6:
                info = msg.info
                grids.append(
                    {
                        "t": t,
                        "origin": (float(info.origin.position.x), float(info.origin.position.y)),
                        "resolution": float(info.resolution),
                        "data": np.asarray(msg.data, dtype=np.int8).reshape(info.height, info.width),
                    }
                )
        elif topic == FLEET_FRONT:
            t = _stamp_s(msg)
            mission.fronts.setdefault(int(msg.uav_id), []).append(
                {
                    "t": t,
                    "x": np.asarray(msg.x_m, dtype=float),
                    "y": np.asarray(msg.y_m, dtype=float),
                    "state": np.asarray(msg.state, dtype=np.uint8),
                }
            )
        elif topic in (WORLD_EVENTS, FLEET_EVENTS):
            ev = _event(msg, "world" if topic == WORLD_EVENTS else "fleet")
            (mission.world_events if topic == WORLD_EVENTS else mission.fleet_events).append(ev)
            t = ev.t_s
        else:  # pragma: no cover
            t = t_ns * 1e-9
        t_min, t_max = min(t_min, t), max(t_max, t)
    mission.states = {k: _arrays(v) for k, v in states.items()}
    mission.truth_vehicles = {k: _arrays(v) for k, v in tveh.items()}
    mission.truth_fires = {k: _arrays(v) for k, v in tfire.items()}
    mission.fire_estimates = {k: _arrays(v) for k, v in fest.items()}
    mission.separation = _arrays(sep)
    perimeters = {}
    for key, rows in perim.items():
        rows.sort(key=lambda r: r["t"])
        nbins = max(len(r["outer"]) for r in rows)
        outer = np.full((len(rows), nbins), np.nan)
        for i, r in enumerate(rows):
            outer[i, : len(r["outer"])] = r["outer"]
        perimeters[key] = {
            "t": np.asarray([r["t"] for r in rows]),
            "center": np.asarray([r["center"] for r in rows]),
            "outer": outer,
        }
    mission.perimeters = perimeters
    mission.world_events.sort(key=lambda e: e.t_s)
    mission.fleet_events.sort(key=lambda e: e.t_s)
    if math.isfinite(t_min):
        mission.t_first_s, mission.t_last_s = t_min, t_max
    return mission
