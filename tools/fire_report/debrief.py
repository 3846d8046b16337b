"""The mission told in plain words: a timeline, per-fire and per-UAV tables, the faults and what
the fleet did about them (pure Python over a :class:`~fire_report.data.RecordedMission` and its metrics;
no matplotlib, no HTML: ``fire_report.page`` renders what this returns).

The faults a run injected from the command line are not in the bag: the runner writes them beside
it (``summary.json``'s ``faults`` records for kills, freezes and stalls, or in a run written before
the records its ``faults_injected`` texts; the agents' parameter files in ``params/`` for link
outages). :func:`run_faults` reads them when the bag sits in a run
directory; scenario outages come from the scenario stored in the bag. Times are sim seconds.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from fire_uav_common.constants import EventType, FireStatus

from fire_report.data import RecordedEvent, RecordedMission
from fire_report.matching import match_tracks_to_fires

DETECTION_GATE_M = 150.0  # a first sighting this close to a burning fire is that fire [m]
DECLARATION_GROUP_S = 2.0  # declarations of one peer this close in time form one timeline line [s]
MAX_DROP_LINES = 40  # more drops than this: one timeline line per fire instead of one per drop


@dataclass(frozen=True)
class Fault:
    """One injected fault. kind: "kill", "freeze", "stall", "outage"; uav: the UAV it hit (the
    sending end of an outage), peer: an outage's receiving end; end_s: when it stopped (None: never)."""

    kind: str
    t_s: float
    uav: int
    peer: int | None = None
    end_s: float | None = None
    source: str = "command line"
    response: str = ""

    @property
    def title(self) -> str:
        if self.kind == "outage":
            return f"Link outage UAV {self.uav} \u2192 UAV {self.peer}, {self.t_s:g}\u2013{self.end_s:g} s"
        if self.kind == "kill":
            return f"UAV {self.uav}'s process killed at {self.t_s:g} s"
        if self.kind == "freeze":
            return f"UAV {self.uav}'s process frozen {self.t_s:g}\u2013{self.end_s:g} s"
        return f"UAV {self.uav}'s process stalled at {self.t_s:g} s"


@dataclass(frozen=True)
class Entry:
    """One line of the timeline: when, what (a sentence), and a kind for the page's styling
    ("fire", "drop", "loss", "fault", "fleet", "end")."""

    t_s: float
    text: str
    kind: str


_KILL = re.compile(r"kill uav (\d+) at ([0-9.eE+-]+) s", re.I)
_FREEZE = re.compile(r"freeze uav (\d+) at ([0-9.eE+-]+) s", re.I)
_RESUME = re.compile(r"resume uav (\d+) at ([0-9.eE+-]+) s", re.I)
_STALL = re.compile(r"stall uav (\d+) at ([0-9.eE+-]+) s", re.I)


def fault_records(records: list[dict]) -> list[Fault]:
    """Kills, freezes (with their resume) and stalls from ``summary.json``'s ``faults`` records (the
    runner's); a fault not applied (the agent was no longer running) is left out, and so are the
    outage records (read from the agents' parameters, :func:`run_faults`). A record that is not one
    of these (another version's) is skipped."""
    out: list[Fault] = []
    resumes: dict[int, float] = {}
    rows = []
    for r in records:
        try:
            if r.get("applied", True):
                rows.append((str(r["kind"]), int(r["uav_id"]), float(r["t_s"])))
        except (AttributeError, KeyError, TypeError, ValueError):
            continue
    for kind, uav, t in rows:
        if kind == "resume":
            resumes[uav] = t
    for kind, uav, t in rows:
        if kind in ("kill", "stall"):
            out.append(Fault(kind, t, uav))
        elif kind == "freeze":
            out.append(Fault("freeze", t, uav, end_s=resumes.get(uav)))
    return out


def parse_fault_texts(texts: list[str]) -> list[Fault]:
    """Kills, freezes (with their resume) and stalls from the runner's fault texts; a fault that
    was "not applied" (the agent was no longer running) is left out, outages are read elsewhere."""
    out: list[Fault] = []
    resumes: dict[int, float] = {}
    for text in texts:
        if "not applied" in text:
            continue
        if m := _RESUME.search(text):
            resumes[int(m[1])] = float(m[2])
    for text in texts:
        if "not applied" in text:
            continue
        if m := _KILL.search(text):
            out.append(Fault("kill", float(m[2]), int(m[1])))
        elif m := _FREEZE.search(text):
            out.append(Fault("freeze", float(m[2]), int(m[1]), end_s=resumes.get(int(m[1]))))
        elif m := _STALL.search(text):
            out.append(Fault("stall", float(m[2]), int(m[1])))
    return out


def scenario_outages(scenario: dict[str, Any]) -> list[Fault]:
    """The link outages the scenario schedules (``comms.outages``)."""
    items = ((scenario.get("comms") or {}).get("outages") or []) if isinstance(scenario, dict) else []
    out = []
    for o in items:
        try:
            out.append(
                Fault(
                    "outage", float(o["start_s"]), int(o["from"]), int(o["to"]), float(o["end_s"]), "scenario"
                )
            )
        except (KeyError, TypeError, ValueError):
            continue
    return out


def agent_params(bag_path: str | Path) -> dict[str, Any]:
    """The parameters the runner gave the agents (``params/agent_0.yaml`` beside the bag; the
    fault and loss settings are the same for every agent), {} when there is none."""
    try:
        doc = yaml.safe_load((Path(bag_path).parent / "params" / "agent_0.yaml").read_text(encoding="utf8"))
        params = next(iter(doc.values()))["ros__parameters"]
    except (OSError, yaml.YAMLError, AttributeError, KeyError, TypeError, StopIteration):
        return {}
    return params if isinstance(params, dict) else {}


def run_summary_found(bag_path: str | Path) -> bool:
    """Whether the runner's ``summary.json`` (its list of injected faults) is beside the bag: without
    it the report cannot tell an injected loss from another."""
    return (Path(bag_path).parent / "summary.json").is_file()


def run_faults(bag_path: str | Path) -> list[Fault]:
    """Faults injected from the command line, from the run directory holding the bag (none when
    the bag is not in one): kills, freezes, stalls from ``summary.json``, link outages from the
    agents' parameters (``params/agent_0.yaml``: every agent gets the same outage list)."""
    run = Path(bag_path).parent
    faults: list[Fault] = []
    try:
        summary = json.loads((run / "summary.json").read_text(encoding="utf8"))
        if isinstance(summary.get("faults"), list):
            faults += fault_records(summary["faults"])
        else:  # a run directory written before the records: the texts
            faults += parse_fault_texts([str(t) for t in summary.get("faults_injected") or []])
    except (OSError, ValueError, AttributeError):
        pass
    p = agent_params(bag_path)
    try:
        for a, b, t0, t1 in zip(
            p.get("outage_from") or [], p.get("outage_to") or [],
            p.get("outage_start_s") or [], p.get("outage_end_s") or [], strict=False,
        ):  # fmt: skip
            faults.append(Fault("outage", float(t0), int(a), int(b), float(t1)))
    except (TypeError, ValueError):
        pass
    return faults


def run_scenario_notes(bag_path: str | Path) -> list[str]:
    """What the scenario's loader noted (e.g. water bodies of a landscape left out as too small
    for a refill pass), from the run's ``summary.json`` beside the bag; [] when there is none."""
    try:
        summary = json.loads((Path(bag_path).parent / "summary.json").read_text(encoding="utf8"))
        return [str(n) for n in summary.get("scenario_notes") or []]
    except (OSError, ValueError, AttributeError):
        return []


def _uavs(ids: list[int]) -> str:
    ids = sorted(set(ids))
    return f"UAV {ids[0]}" if len(ids) == 1 else "UAVs " + ", ".join(str(i) for i in ids)


def with_responses(faults: list[Fault], mission: RecordedMission) -> list[Fault]:
    """Each fault with a sentence on what the world and the fleet did about it, from the events."""
    crashes = [e for e in mission.world_events if e.type == EventType.CRASH]
    declared = [e for e in mission.fleet_events if e.type == EventType.PEER_CRASHED]
    rejoined = [e for e in mission.fleet_events if e.type == EventType.PEER_REJOINED]
    out = []
    for f in sorted(faults, key=lambda f: (f.t_s, f.kind, f.uav)):
        said: list[str] = []
        if f.kind == "outage":
            end = f.end_s if f.end_s is not None else math.inf
            d = [
                e
                for e in declared
                if e.uav_id == f.peer and e.peer_id == f.uav and f.t_s <= e.t_s <= end + 1.0
            ]
            if d:
                said.append(
                    f"UAV {f.peer} stopped hearing UAV {f.uav} and declared it lost at {d[0].t_s:.1f} s "
                    f"({d[0].t_s - f.t_s:.1f} s into the outage)"
                )
                r = [e for e in rejoined if e.uav_id == f.peer and e.peer_id == f.uav and e.t_s >= d[0].t_s]
                said.append(
                    f"heard it again at {r[0].t_s:.1f} s and took it back into the fleet"
                    if r
                    else "did not hear it again before the mission ended"
                )
            else:
                said.append(
                    f"UAV {f.peer} never declared UAV {f.uav} lost (the other messages kept it known)"
                )
        else:
            c = [e for e in crashes if e.uav_id == f.uav and e.t_s >= f.t_s - 1e-6]
            if c:
                said.append(f"its vehicle fell at {c[0].t_s:.1f} s ({c[0].detail or 'no reason given'})")
            d = [e for e in declared if e.peer_id == f.uav and e.t_s >= f.t_s - 1e-6]
            if d:
                said.append(
                    f"{_uavs([e.uav_id for e in d])} declared it lost between {d[0].t_s:.1f} and "
                    f"{d[-1].t_s:.1f} s (first {d[0].t_s - f.t_s:.1f} s after the fault), leaving it out of their "
                    "partition of the area and their fire consensus"
                )
            elif f.kind == "kill":
                said.append("no peer declared it lost")
            r = [e for e in rejoined if e.peer_id == f.uav and e.t_s >= f.t_s]
            if r:
                said.append(f"{_uavs([e.uav_id for e in r])} heard it again from {r[0].t_s:.1f} s")
            if f.kind == "stall" and not (c or d):
                said.append("the fleet waited for it (lockstep) and carried on unchanged")
        out.append(replace(f, response="; ".join(said) + "." if said else "no visible effect."))
    return out


def track_to_fire(mission: RecordedMission) -> dict[int, int]:
    """The fleet's fire track ids -> the true fire each follows (by position, ``matching``)."""
    return (
        match_tracks_to_fires(mission.fire_estimates, mission.truth_fires) if mission.fire_estimates else {}
    )


def _fire_at(mission: RecordedMission, e: RecordedEvent, tracks: dict[int, int]) -> int | None:
    """The true fire a FIRE_DETECTED event is about: its track's match, else the nearest burning
    fire within ``DETECTION_GATE_M`` of where it was seen."""
    if e.fire_id in tracks:
        return tracks[e.fire_id]
    best, best_d = None, DETECTION_GATE_M
    for fid, f in mission.truth_fires.items():
        if not f or not (math.isfinite(e.x_m) and math.isfinite(e.y_m)):
            continue
        i = max(0, int(np.searchsorted(f["t"], e.t_s, side="right")) - 1)
        d = math.hypot(float(f["x"][i]) - e.x_m, float(f["y"][i]) - e.y_m)
        if f["status"][i] == FireStatus.ACTIVE and d <= best_d:
            best, best_d = fid, d
    return best


def first_detections(mission: RecordedMission) -> dict[int, tuple[float, int]]:
    """True fire -> (time [s], UAV) of the fleet's first sighting of it."""
    tracks = track_to_fire(mission)
    out: dict[int, tuple[float, int]] = {}
    for e in mission.fleet_events:
        if e.type == EventType.FIRE_DETECTED:
            fid = _fire_at(mission, e, tracks)
            if fid is not None and fid not in out:
                out[fid] = (e.t_s, e.uav_id)
    return out


def _ignitions(mission: RecordedMission) -> dict[int, float]:
    out = {e.fire_id: e.t_s for e in mission.world_events if e.type == EventType.IGNITION}
    for fid, f in mission.truth_fires.items():
        out.setdefault(fid, float(f["t"][0]) if f else 0.0)
    return out


def flare_ups(mission: RecordedMission) -> list[tuple[int, float]]:
    """(fire, time [s]) at which a fire the world had declared out burned again: its first
    ``/world/truth`` sample back in ACTIVE after an EXTINGUISHED event."""
    out = []
    for fid, f in mission.truth_fires.items():
        outs = sorted(
            e.t_s for e in mission.world_events if e.type == EventType.EXTINGUISHED and e.fire_id == fid
        )
        if not f or not outs:
            continue
        active = f["status"] == FireStatus.ACTIVE
        for t_out in outs:
            back = np.flatnonzero(active & (f["t"] > t_out + 1e-6))
            later = [t for t in outs if t > t_out]
            if back.size and (not later or f["t"][back[0]] < later[0]):
                out.append((fid, float(f["t"][back[0]])))
    return sorted(out, key=lambda x: (x[1], x[0]))


def _drops(mission: RecordedMission) -> list[RecordedEvent]:
    return [e for e in mission.world_events if e.type == EventType.DROP and e.value > 0]


def _lost_why(uav: int, injected: set[int], known: bool) -> str:
    if uav in injected:
        return "injected"
    return "not injected" if known else "injected or not: unknown without the run's summary"


def timeline(
    mission: RecordedMission, metrics: dict[str, Any], faults: list[Fault], *, known: bool = True
) -> list[Entry]:
    """What happened, in time order, in sentences. ``known``: the run's command-line faults are
    known (:func:`run_summary_found`), so a loss that none explains was not injected."""
    out: list[Entry] = []
    ev = mission.world_events
    injected = {f.uav for f in faults if f.kind in ("kill", "freeze")}
    t0 = min((float(f["t"][0]) for f in mission.truth_fires.values() if f), default=0.0)
    starts = _ignitions(mission)
    at_start = sorted(fid for fid, t in starts.items() if t <= t0 + 1e-6)
    if at_start:
        are = "is" if len(at_start) == 1 else "are"
        names = ("Fire " if len(at_start) == 1 else "Fires ") + ", ".join(str(f) for f in at_start)
        out.append(Entry(t0, f"{names} {are} burning when the mission starts.", "fire"))
    for fid, t in sorted(starts.items()):
        if fid not in at_start:
            out.append(Entry(t, f"Fire {fid} starts.", "fire"))
    takeoffs = sorted((e.t_s, e.uav_id) for e in ev if e.type == EventType.TAKEOFF)
    if takeoffs:
        n = len({u for _, u in takeoffs})
        out.append(Entry(takeoffs[0][0], f"UAV {takeoffs[0][1]} takes off, the first of {n}.", "fleet"))
        if n > 1:
            out.append(
                Entry(takeoffs[-1][0], f"UAV {takeoffs[-1][1]} takes off: all {n} are airborne.", "fleet")
            )
    for fid, (t, u) in sorted(first_detections(mission).items(), key=lambda kv: kv[1]):
        out.append(Entry(t, f"UAV {u} detects fire {fid}.", "fire"))
    drops = _drops(mission)
    if len(drops) <= MAX_DROP_LINES:
        for e in drops:
            where = f"on fire {e.fire_id}" if e.fire_id >= 0 else "and misses every fire"
            out.append(Entry(e.t_s, f"UAV {e.uav_id} drops {e.value:,.0f} kg of water {where}.", "drop"))
    else:
        for fid in sorted({e.fire_id for e in drops}):
            d = [e for e in drops if e.fire_id == fid]
            what = f"on fire {fid}" if fid >= 0 else "that miss every fire"
            out.append(
                Entry(d[0].t_s, f"{len(d)} drops {what}, from {d[0].t_s:.1f} to {d[-1].t_s:.1f} s.", "drop")
            )
    went_out: set[int] = set()
    for e in ev:
        if e.type == EventType.EXTINGUISHED:
            n = sum(1 for d in drops if d.fire_id == e.fire_id and d.t_s <= e.t_s + 1e-6)
            again = " again" if e.fire_id in went_out else ""
            went_out.add(e.fire_id)
            out.append(
                Entry(e.t_s, f"Fire {e.fire_id} is out{again}, after {n} drop{'s' * (n != 1)}.", "fire")
            )
        elif e.type == EventType.CRASH:
            why = "injected fault" if e.uav_id in injected else _lost_why(e.uav_id, injected, known)
            out.append(
                Entry(e.t_s, f"UAV {e.uav_id} is lost ({why}): {e.detail or 'no reason given'}.", "loss")
            )
        elif e.type == EventType.AGENT_LOST:
            out.append(
                Entry(e.t_s, f"UAV {e.uav_id}'s process is gone ({e.detail or 'not injected'}).", "loss")
            )
    for f in faults:
        if f.kind == "outage":
            out.append(Entry(f.t_s, f"Link from UAV {f.uav} to UAV {f.peer} cut (injected outage).", "fault"))
            if f.end_s is not None:
                out.append(Entry(f.end_s, f"Link from UAV {f.uav} to UAV {f.peer} restored.", "fault"))
        else:
            verb = {"kill": "killed", "freeze": "frozen", "stall": "stalled"}[f.kind]
            out.append(Entry(f.t_s, f"UAV {f.uav}'s process {verb} (injected fault).", "fault"))
            if f.kind == "freeze" and f.end_s is not None:
                out.append(Entry(f.end_s, f"UAV {f.uav}'s process resumed.", "fault"))
    out += _declarations(mission)
    for fid, t in flare_ups(mission):
        out.append(Entry(t, f"Fire {fid} flares up again (cells the water had not put out).", "fire"))
    for e in ev:
        if e.type == EventType.LANDED:
            err = metrics.get("landing_error_m", {}).get(str(e.uav_id))
            at = f", {err:.1f} m from its takeoff point" if err is not None else ""
            out.append(Entry(e.t_s, f"UAV {e.uav_id} lands{at}.", "fleet"))
        elif e.type == EventType.MISSION_COMPLETE:
            if e.value >= 1.0:
                out.append(
                    Entry(e.t_s, f"Mission complete: {e.detail}." if e.detail else "Mission complete.", "end")
                )
            else:  # the world's detail names its parameter (max_duration_s): say it in words
                out.append(Entry(e.t_s, "The mission reached its time limit.", "end"))
    # at one instant: the cause before its effect (a fault, then the drop, then the fire out)
    order = {"fault": 0, "drop": 1, "fire": 2, "loss": 3, "fleet": 4, "end": 5}
    return sorted(out, key=lambda x: (round(x.t_s, 6), order.get(x.kind, 9)))


def _declarations(mission: RecordedMission) -> list[Entry]:
    """Peers declaring a UAV lost (grouped when close in time) and hearing it again."""
    out: list[Entry] = []
    decl = sorted(
        (e for e in mission.fleet_events if e.type == EventType.PEER_CRASHED),
        key=lambda e: (e.peer_id, e.t_s),
    )
    group: list[RecordedEvent] = []

    def flush() -> None:
        if group:
            out.append(
                Entry(
                    group[0].t_s,
                    f"{_uavs([g.uav_id for g in group])} declare{'s' * (len({g.uav_id for g in group}) == 1)} UAV {group[0].peer_id} lost (not heard for 10 control steps).",
                    "fleet",
                )
            )
            group.clear()

    for e in decl:
        if group and (e.peer_id != group[0].peer_id or e.t_s - group[0].t_s > DECLARATION_GROUP_S):
            flush()
        group.append(e)
    flush()
    for e in mission.fleet_events:
        if e.type == EventType.PEER_REJOINED:
            out.append(Entry(e.t_s, f"UAV {e.uav_id} hears UAV {e.peer_id} again.", "fleet"))
    return out


def fire_rows(mission: RecordedMission, metrics: dict[str, Any], raster: bool) -> list[dict[str, Any]]:
    """One row per true fire: where, when it started, was first seen, was first hit, went out;
    drops and hits; burned area [ha] (raster fires only); its state at the end."""
    detected = first_detections(mission)
    drops = _drops(mission)
    starts = _ignitions(mission)
    out_at: dict[int, float] = {}  # the last time each fire went out (a fire may flare up again)
    for e in mission.world_events:
        if e.type == EventType.EXTINGUISHED and e.fire_id >= 0:
            out_at[e.fire_id] = e.t_s
    rows = []
    for fid in sorted(set(mission.truth_fires) | set(out_at)):
        f = mission.truth_fires.get(fid)
        d = [e for e in drops if e.fire_id == fid]
        burning = bool(f and f["status"][-1] == FireStatus.ACTIVE)
        row = {
            "fire": fid,
            "x_m": float(f["x"][0]) if f else None,
            "y_m": float(f["y"][0]) if f else None,
            "started_s": starts.get(fid),
            "detected_s": detected[fid][0] if fid in detected else None,
            "detected_by": detected[fid][1] if fid in detected else None,
            "drops": len(d),
            "first_drop_s": d[0].t_s if d else None,
            "out_s": None if burning else out_at.get(fid),
            "burning_at_end": burning,
        }
        if raster and f:
            row["burned_ha"] = float(f["area"][-1]) / 1e4
        rows.append(row)
    return rows


def uav_rows(
    mission: RecordedMission, metrics: dict[str, Any], faults: list[Fault], *, known: bool = True
) -> list[dict[str, Any]]:
    """One row per UAV: takeoff, drops, water dropped [kg], how it ended, landing error [m],
    messages received and lost, its own position error (95th percentile, horizontal) [m]."""
    ev = mission.world_events
    injected = {f.uav for f in faults if f.kind in ("kill", "freeze")}
    ekf = metrics.get("ekf_error", {}).get("per_uav", {})
    rows = []
    for u in sorted(set(range(int(metrics.get("uav_count") or 0))) | set(mission.uav_ids)):
        take = [e.t_s for e in ev if e.type == EventType.TAKEOFF and e.uav_id == u]
        crash = [e for e in ev if e.type == EventType.CRASH and e.uav_id == u]
        land = [e.t_s for e in ev if e.type == EventType.LANDED and e.uav_id == u]
        d = [e for e in _drops(mission) if e.uav_id == u]
        if crash:
            end = f"lost at {crash[0].t_s:.1f} s ({_lost_why(u, injected, known)})"
        elif land:
            end = f"landed at {land[0]:.1f} s"
        else:
            end = "still flying at the end"
        p = metrics.get("packets", {}).get(str(u))
        horizontal = (ekf.get(str(u)) or {}).get("horizontal") or {}
        rows.append(
            {
                "uav": u,
                "takeoff_s": take[0] if take else None,
                "drops": len(d),
                "water_kg": float(sum(x.value for x in d)),
                "end": end,
                "landing_error_m": metrics.get("landing_error_m", {}).get(str(u)),
                "received": p["received"] if p else None,
                "lost": p["lost"] if p else None,
                "position_error_p95_m": horizontal.get("p95"),
            }
        )
    return rows
