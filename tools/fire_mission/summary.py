"""Mission summary from what the supervisor saw live (events, truth, fleet states). ROS-free.

The same quantities are recomputed from the bag by the report (``fire_report``); a system test
checks that the two agree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common.constants import EventType

#: events the agents publish on /fleet/events (stamped with the step they answer)
AGENT_EVENTS = frozenset(
    {
        EventType.PEER_CRASHED,
        EventType.PEER_REJOINED,
        EventType.FIRE_DETECTED,
        EventType.OBJECTIVE,
        EventType.AGENT_READY,
    }
)


@dataclass
class LiveEvent:
    """One MissionEvent as the runner's live summary counts it while the mission runs (t_s: sim
    time [s]); the report's reading of the recorded events is ``fire_report.data.RecordedEvent``."""

    t_s: float
    type: int
    uav_id: int
    peer_id: int
    fire_id: int
    value: float
    detail: str
    x_m: float = math.nan  # where it happened [m; map], when the event says
    y_m: float = math.nan


FIRE_TYPE_KEYS = ("unburnt", "surface", "passive_crown", "active_crown")  # by FireType value


@dataclass
class LiveSummary:
    """Accumulates what the supervisor observes; :meth:`as_dict` gives summary.json."""

    uav_count: int
    events: list[LiveEvent] = field(default_factory=list)
    mission_time_s: float = 0.0
    fires_active: int | None = None
    fires_total: int | None = None
    vehicles_alive: int | None = None
    vehicles_landed: int = 0
    packets: dict[int, tuple[int, int, int]] = field(default_factory=dict)  # uav -> (recv, lost, rejected)
    complete_detail: str | None = None
    complete_success: bool | None = None
    faults: list[str] = field(default_factory=list)  # what the supervisor did (signals), as it did it
    # the same signals as records for readers (the report): kind (kill, freeze, resume, stall), uav_id,
    # t_s (the fault's mission time as given), applied (False: the agent was no longer running)
    fault_records: list[dict] = field(default_factory=list)
    # the link outages the agents apply themselves (src, dst, start [s], end [s]): scheduled, no signal
    outages: list[tuple[int, int, float, float]] = field(default_factory=list)
    last_state_t: dict[int, float] = field(default_factory=dict)  # uav -> stamp of its newest UavState
    alive_view: dict[int, list[int]] = field(default_factory=dict)  # uav -> its newest alive_peers
    objective: dict[int, int] = field(default_factory=dict)  # uav -> its newest objective
    water_at_fault: dict[str, float] = field(default_factory=dict)  # fault text -> true water [kg]
    water_kg: dict[int, float] = field(default_factory=dict)  # uav -> true water now [kg]
    proc_stats: dict[str, object] = field(default_factory=dict)  # process name -> last ProcSample
    raster: bool = False  # the scenario's fire model is the raster fire
    area_t_s: list[float] = field(default_factory=list)  # [s] /world/truth stamps
    area_m2: list[float] = field(default_factory=list)  # [m^2] burned area (sum over fires) at area_t_s
    area_active: list[bool] = field(default_factory=list)  # any fire active at area_t_s
    # burnt cells per fire type (a fire on a landscape only; None: the key stays out of summary.json)
    fire_type_cells: dict[str, int] | None = None

    def add_fire_types(self, grid: np.ndarray) -> None:
        """The newest /world/fire_type grid (0 not burnt, 1 surface, 2 passive, 3 active crown)."""
        n = np.bincount(np.asarray(grid, dtype=np.int64).ravel(), minlength=4)
        self.fire_type_cells = {name: int(n[k]) for k, name in enumerate(FIRE_TYPE_KEYS) if k > 0}

    def add_truth(self, t_s: float, fires: list[tuple[float, bool]]) -> None:
        """One /world/truth sample: ``fires`` as (area_m2, active) per fire."""
        self.area_t_s.append(t_s)
        self.area_m2.append(float(sum(a for a, _ in fires)))
        self.area_active.append(any(on for _, on in fires))

    def suppression(self) -> dict:
        """hit_rate, burned_area_m2, contained_at_s, water, as the report
        computes them from the bag (``fire_report.metrics``), from what the supervisor saw."""
        from fire_report.metrics import containment_from_area, drop_outcomes

        out = drop_outcomes(self.events, self.raster)
        return {
            "hit_rate": round(out["hit_rate"], 4) if out["hit_rate"] is not None else None,
            "burned_area_m2": self.area_m2[-1] if self.area_m2 else None,
            "contained_at_s": containment_from_area(
                np.asarray(self.area_t_s),
                np.asarray(self.area_m2),
                np.asarray(self.area_active, dtype=bool),
                raster=self.raster,
            ),
            "water_released_kg": round(out["water_released_kg"], 1),
            "water_on_burning_kg": round(out["water_on_burning_kg"], 1),
        }

    # FF safety and life-cycle (from /world/truth): separation, collisions, landing at home
    min_separation_m: float = math.inf  # closest 3-D approach of two airborne vehicles [m]
    collisions: int = 0  # colliding pairs (the world crashes both)
    home_xy: dict[int, tuple[float, float]] = field(default_factory=dict)  # uav -> takeoff point [m]
    touchdown_xy: dict[int, tuple[float, float]] = field(default_factory=dict)  # uav -> where it landed [m]
    _states: dict[int, dict[float, tuple]] = field(default_factory=dict)  # uav -> stamp -> state fields

    def add_state(
        self, uav: int, t_s: float, packets: tuple[int, int, int], alive: list[int], objective: int
    ) -> None:
        """A UavState the supervisor saw; the newest few per UAV are kept for :meth:`settle_states`."""
        kept = self._states.setdefault(uav, {})
        kept[round(t_s, 6)] = (packets, alive, objective)
        for old in sorted(kept)[:-4]:
            del kept[old]
        self.last_state_t[uav] = max(kept)
        self.packets[uav], self.alive_view[uav], self.objective[uav] = kept[max(kept)]

    def settle_states(self) -> None:
        """Keep, per UAV, its newest state stamped before the mission's last step.

        The world ends the mission at the step it finds it complete; whether the supervisor sees
        the agents' answers to that last step before it stops them depends on wall time, so they
        are left out, and the summary is the same every time the mission is run.
        """
        end = round(self.mission_time_s, 6)
        # the agents' own events answering the last step race the stop in the same way
        self.events = [e for e in self.events if not (e.type in AGENT_EVENTS and e.t_s >= end - 1e-6)]
        from fire_report.metrics import settled_index

        for uav, kept in self._states.items():
            stamps = sorted(kept)
            t = stamps[settled_index(np.asarray(stamps), end)]
            self.last_state_t[uav] = t
            self.packets[uav], self.alive_view[uav], self.objective[uav] = kept[t]

    def add(self, ev: LiveEvent) -> None:
        self.events.append(ev)
        if ev.type == EventType.LANDED and math.isfinite(ev.x_m) and math.isfinite(ev.y_m):
            self.touchdown_xy.setdefault(ev.uav_id, (ev.x_m, ev.y_m))
        if ev.type == EventType.MISSION_COMPLETE:
            self.complete_detail = ev.detail
            self.complete_success = ev.value >= 1.0

    def of(self, type_: int) -> list[LiveEvent]:
        """Events of one type in a total order (time, then fields: DDS delivers one step's events in any order)."""
        return sorted(
            (e for e in self.events if e.type == type_),
            key=lambda e: (e.t_s, e.uav_id, e.peer_id, e.fire_id, e.value, e.detail),
        )

    def drops(self) -> list[LiveEvent]:
        """Drops that released water (a drop request with an empty tank is not a drop)."""
        return [e for e in self.of(EventType.DROP) if e.value > 0]

    def observe_truth(self, min_separation_m: float, collisions: int) -> None:
        """One ``/world/truth`` sample: the world's running separation figures (FF Eq. 7 band, collisions)."""
        if math.isfinite(min_separation_m):
            self.min_separation_m = min(self.min_separation_m, float(min_separation_m))
        self.collisions = max(self.collisions, int(collisions))

    def landing_error_m(self) -> dict[int, float]:
        """Per landed UAV: horizontal distance [m] from its touchdown point to its takeoff point (FF IV-D d)."""
        return {
            u: math.hypot(x - self.home_xy[u][0], y - self.home_xy[u][1])
            for u, (x, y) in sorted(self.touchdown_xy.items())
            if u in self.home_xy
        }

    def touchdown_spacing_m(self) -> float | None:
        """Smallest horizontal distance [m] between two UAVs' touchdown points (None below two)."""
        pts = list(self.touchdown_xy.values())
        d = [math.dist(a, b) for i, a in enumerate(pts) for b in pts[i + 1 :]]
        return min(d) if d else None

    def hit_rate(self) -> float | None:
        """Drops that hit a fire / drops that released water (None without drops)."""
        drops = self.drops()
        return sum(e.fire_id >= 0 for e in drops) / len(drops) if drops else None

    def lake_passes(self) -> list[LiveEvent]:
        """REFILL events: one per spell over a lake that took water (a pass, full or part-filled)."""
        return [e for e in self.of(EventType.REFILL) if e.value > 0]

    def refill_cycles(self) -> int:
        """Refill cycles: per UAV, the spans between one drop and the next (or the end) with water taken.

        A UAV that empties its tank and takes water in three short passes over the lake before its
        next drop has made one cycle of three passes (FF IV-D b-c: drop, refill, reassess).
        """
        n = 0
        for u in sorted({e.uav_id for e in self.lake_passes()}):
            drops = sorted(e.t_s for e in self.drops() if e.uav_id == u)
            passes = sorted(e.t_s for e in self.lake_passes() if e.uav_id == u)
            bounds = [-math.inf, *drops, math.inf]
            n += sum(any(a < t <= b for t in passes) for a, b in zip(bounds, bounds[1:], strict=False))
        return n

    def faults_injected(self) -> list[str]:
        """Every fault of the mission: the supervisor's signals as applied, then each link outage
        that began before the mission ended (the agents drop the link themselves)."""
        applied = [
            o for o in sorted(self.outages, key=lambda o: (o[2], o[0], o[1])) if o[2] < self.mission_time_s
        ]
        return self.faults + [
            f"outage {a}>{b} from {t0:g} s to {t1:g} s (link dropped by the agents)"
            for a, b, t0, t1 in applied
        ]

    def fault_list(self) -> list[dict]:
        """:meth:`faults_injected` as records: the signals, then each link outage that began
        (kind "outage", ``from``/``to`` UAV ids, ``start_s``/``end_s``)."""
        applied = [
            o for o in sorted(self.outages, key=lambda o: (o[2], o[0], o[1])) if o[2] < self.mission_time_s
        ]
        return [dict(r) for r in self.fault_records] + [
            {"kind": "outage", "from": a, "to": b, "start_s": t0, "end_s": t1} for a, b, t0, t1 in applied
        ]

    def drop_intervals_s(self) -> list[float]:
        """Intervals between consecutive drops of the whole fleet (FF Table I)."""
        ts = sorted(e.t_s for e in self.drops())
        return [b - a for a, b in zip(ts, ts[1:], strict=False)]

    def as_dict(self, *, outcome: str, wall_s: float, steps: int) -> dict:
        drops = self.drops()
        per_fire: dict[str, int] = {}
        for e in drops:
            key = str(e.fire_id) if e.fire_id >= 0 else "missed"
            per_fire[key] = per_fire.get(key, 0) + 1
        intervals = self.drop_intervals_s()
        crashes = [
            {"uav_id": e.uav_id, "t_s": round(e.t_s, 3), "detail": e.detail} for e in self.of(EventType.CRASH)
        ]
        declared: dict[int, list[dict]] = {}
        for e in self.of(EventType.PEER_CRASHED):
            declared.setdefault(e.peer_id, []).append({"by": e.uav_id, "t_s": round(e.t_s, 3)})
        rejoined = [
            {"uav_id": e.peer_id, "by": e.uav_id, "t_s": round(e.t_s, 3)}
            for e in self.of(EventType.PEER_REJOINED)
        ]
        return {
            "outcome": outcome,
            "detail": self.complete_detail,
            "mission_time_s": round(self.mission_time_s, 3),
            "wall_time_s": round(wall_s, 2),
            "steps_per_wall_s": round(steps / wall_s, 2) if wall_s > 0 else None,
            "uav_count": self.uav_count,
            "fires_total": self.fires_total,
            "fires_active_at_end": self.fires_active,
            "extinguished": [
                {"fire_id": e.fire_id, "t_s": round(e.t_s, 3)} for e in self.of(EventType.EXTINGUISHED)
            ],
            "drops_total": len(drops),
            "drops_per_fire": per_fire,
            "mean_inter_drop_interval_s": round(sum(intervals) / len(intervals), 3) if intervals else None,
            "hit_rate": None if self.hit_rate() is None else round(self.hit_rate(), 4),
            "refills": self.refill_cycles(),
            "lake_passes": len(self.lake_passes()),
            "landed": sorted({e.uav_id for e in self.of(EventType.LANDED)}),
            "min_separation_m": round(self.min_separation_m, 3)
            if math.isfinite(self.min_separation_m)
            else None,
            "collisions": self.collisions,
            "landing_error_m": {str(k): round(v, 3) for k, v in self.landing_error_m().items()},
            "touchdown_spacing_m": None
            if self.touchdown_spacing_m() is None
            else round(self.touchdown_spacing_m(), 3),
            "crashes": crashes,
            "declared_crashed": {str(k): v for k, v in sorted(declared.items())},
            "rejoined": rejoined,
            "packets_received": sum(p[0] for p in self.packets.values()),
            "packets_lost": sum(p[1] for p in self.packets.values()),
            "packets_rejected": sum(p[2] for p in self.packets.values()),
            **self.suppression(),
            "faults_injected": self.faults_injected(),
            "faults": self.fault_list(),
            "water_at_fault_kg": self.water_at_fault,
            "last_state_t_s": {str(k): round(v, 3) for k, v in sorted(self.last_state_t.items())},
            "alive_view": {str(k): v for k, v in sorted(self.alive_view.items())},
            "final_objective": {str(k): v for k, v in sorted(self.objective.items())},
            "events": [
                {
                    "t_s": round(e.t_s, 3),
                    "type": e.type,
                    "uav_id": e.uav_id,
                    "peer_id": e.peer_id,
                    "fire_id": e.fire_id,
                    "value": e.value,
                    "detail": e.detail,
                }
                # a total order: events of one step arrive in any order over DDS
                for e in sorted(
                    self.events,
                    key=lambda e: (e.t_s, e.type, e.uav_id, e.peer_id, e.fire_id, e.value, e.detail),
                )
            ],
            "processes": {
                n: {
                    "cpu_s": round(st.cpu_s, 2),
                    "rss_mb": round(st.rss_mb, 1),
                    "peak_rss_mb": round(st.peak_rss_mb, 1),
                }
                for n, st in sorted(self.proc_stats.items())
            },
        } | ({} if self.fire_type_cells is None else {"fire_type_cells": self.fire_type_cells})


def table(summary: dict) -> str:
    """A readable summary table for the terminal."""

    def fmt(v: object) -> str:
        if v is None:
            return "-"
        if isinstance(v, float):
            return f"{v:.2f}" if math.isfinite(v) else str(v)
        if isinstance(v, list):
            return ", ".join(fmt(x) if not isinstance(x, dict) else _d(x) for x in v) or "none"
        if isinstance(v, dict):
            return ", ".join(f"{k}: {fmt(x)}" for k, x in v.items()) or "none"
        return str(v)

    def _d(d: dict) -> str:
        return "(" + " ".join(f"{k}={fmt(x)}" for k, x in d.items()) + ")"

    rows = [
        ("outcome", summary["outcome"]),
        ("detail", summary["detail"]),
        ("mission time [s]", summary["mission_time_s"]),
        ("wall time [s]", summary["wall_time_s"]),
        ("steps per wall second", summary["steps_per_wall_s"]),
        ("UAVs", summary["uav_count"]),
        (
            "fires (active at end / total)",
            f"{fmt(summary['fires_active_at_end'])} / {fmt(summary['fires_total'])}",
        ),
        ("extinguished", summary["extinguished"]),
        ("drops", summary["drops_total"]),
        ("drops per fire", summary["drops_per_fire"]),
        ("mean inter-drop interval [s]", summary["mean_inter_drop_interval_s"]),
        ("hit rate", summary.get("hit_rate")),
        ("refill cycles / lake passes", f"{fmt(summary.get('refills'))} / {fmt(summary.get('lake_passes'))}"),
        (
            "min separation [m] / collisions",
            f"{fmt(summary.get('min_separation_m'))} / {fmt(summary.get('collisions'))}",
        ),
        ("landing error [m]", summary.get("landing_error_m")),
        ("landed", summary["landed"]),
        ("crashes (world)", summary["crashes"]),
        ("declared crashed (peers)", {k: len(v) for k, v in summary["declared_crashed"].items()}),
        ("rejoined", summary["rejoined"]),
        (
            "packets received / lost / rejected",
            f"{summary['packets_received']} / {summary['packets_lost']} / {summary['packets_rejected']}",
        ),
        ("burned area [m^2]", summary.get("burned_area_m2")),
        ("contained at [s]", summary.get("contained_at_s")),
        *([("burnt cells by fire type", summary["fire_type_cells"])] if "fire_type_cells" in summary else []),
        ("faults injected", summary["faults_injected"]),
    ]
    w = max(len(k) for k, _ in rows)
    return "\n".join(f"  {k.ljust(w)}  {fmt(v)}" for k, v in rows)
