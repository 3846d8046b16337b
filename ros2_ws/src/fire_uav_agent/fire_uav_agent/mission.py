"""Mission life-cycle of one UAV (FF IV-D a-d), as a small state machine over objectives.

Objectives are the ``UavState.OBJECTIVE_*`` constants (:class:`Objective`). Transitions:

* GROUNDED -> airborne objective at the takeoff slot ``uav_id * takeoff_interval_s`` (IV-D a).
  If the fleet has agreed to land by then, GROUNDED -> LANDED: the UAV never takes off.
* Airborne objective choice (IV-D c, "reassess"): LAND if the fleet agrees every fire is out;
  REFILL if the tank holds less than ``min_water_fraction``; SUPPRESS if an active fire is known;
  else SEARCH (no fire known yet: FF assumes the fires are seen; our agents must find them).
* SUPPRESS: drop (ACTION_DROP) when within ``min_drop_radius_m`` of the target fire's estimated
  centre, then REFILL. (Not within the estimated extent: the water reaches a fire within the
  larger of the footprint and its true sigma, and an estimate that has not yet seen the last hit
  believes the fire twice its size; releasing at 45 m from a sigma-25 fire missed, FF scenario,
  5 UAVs. Inside the footprint with a margin for the estimation error, every release reaches it.)
* REFILL: request ACTION_REFILL while over a lake (the agent's guidance flies low and slow
  there, IV-D b); reassess when the tank is full.
* LAND when the fleet agrees (IV-D d): this agent's own picture has had every known fire
  extinguished for ``post_search_s`` (meanwhile it SEARCHes) *and* the fleet's sensors have
  covered the whole area since (or for ``post_search_max_s``, whichever comes first), or every
  alive peer's objective is LAND/LANDED; LANDED when the world reports the vehicle landed.

Deviation from IV-D d (land as soon as the fires are out): FF's UAVs know every fire; ours
find fires only with their sensors, and a fleet that converged on the first fire it saw put
it out and landed while a second fire, never seen, kept burning (FF two-fire scenario, 3 UAVs,
seed 2). So after the last known fire is out the fleet sweeps the area (staleness search) and
lands only if nothing new turns up; a new detection resets the sweep.

The sweep's end. Until session 28 it was a fixed time, ``post_search_s`` (45 s on FF's 600 m
map, 150 s on the tankers'). A time is not a sweep: the UAVs that had just dropped spent it
refilling (REFILL comes before SEARCH). On the JSBSim J3Cub's ff_two_fires, seed 2, with the
drop's water shed at its flow rate (a trial, session 27), four of five UAVs were refilling
after the first fire went out at 78.7 s, one searched alone for the 45 s, south and east of
a sigma-50 fire in the middle of the map, and the fleet landed at 212-357 s with that fire
never seen: a time limit, 1 of 2 fires out. Without the trial the same mission completes
because a searcher happens to find that fire in time (its first drop on it at 163.8 s). Now the fleet
lands once its staleness map (:class:`.staleness_search.StalenessSearch`: every grid point of
the area, marked when any UAV's fire sensor covers it) has been covered all over since the
moment the last fire went out (``MissionView.swept_since_s``, the oldest point's last
sighting), after ``post_search_s`` at the least; ``post_search_max_s`` bounds the wait, so a
map the fleet cannot cover (an area wider than its fuel and time allow, a corner behind
terrain) still ends in a landing. Covered is not searched: a point counts once inside a
sensor's range, whatever the sensor's detection probability.

Deadlock of FF V-D (several UAVs circling a frozen centroid over one fire, none passing over
the centre): if a UAV in SUPPRESS with water has not dropped for ``deadlock_timeout_s`` while
its centroid moved less than ``deadlock_centroid_move_m`` in that window, it switches to an
*attack run*: it steers straight at the target fire's centre, bypassing its Voronoi centroid,
until it drops (or ``attack_timeout_s`` passes, then the watch restarts). The same watch in
REFILL (no refill progress, centroid frozen) steers straight to the lake. Only the stalled
UAV deviates; its peers keep Lloyd control, and the tessellation changes as it moves.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

from fire_uav_common.constants import Objective, PayloadAction, VehicleStatus

from .peer_link import FireEntry

__all__ = ["Decision", "Mission", "MissionConfig", "MissionView", "Objective", "VehicleStatus"]


AIRBORNE_OBJECTIVES = (Objective.SUPPRESS, Objective.REFILL, Objective.SEARCH, Objective.MONITOR)


@dataclass(frozen=True)
class MissionConfig:
    takeoff_time_s: float = 0.0  # uav_id * takeoff_interval_s
    water_capacity_kg: float = 2000.0
    full_fraction: float = 0.98  # tank counts as full above this
    min_water_fraction: float = 0.5  # below this, refill before suppressing
    min_drop_radius_m: float = 3.0  # [m] drop within this of the target's estimated centre
    deadlock_timeout_s: float = 20.0
    deadlock_centroid_move_m: float = 10.0
    deadlock_stuck_factor: float = 2.0  # [-] no drop for this * deadlock_timeout_s: attack directly
    attack_timeout_s: float = 30.0
    search_enabled: bool = True
    post_search_s: float = 45.0  # [s] search at least this long after the last known fire is out
    post_search_max_s: float = 300.0  # [s] land this long after it even if the sweep is not complete


@dataclass(frozen=True)
class MissionView:
    """What the life-cycle needs to know at one step. Positions [m; map]."""

    t_s: float
    vehicle: VehicleStatus
    water_kg: float
    pos_xy: tuple[float, float]
    fires: tuple[FireEntry, ...]  # this agent's active fires
    all_out: bool  # at least one fire known and all extinguished (own picture)
    peer_objectives: dict[int, int]  # alive peers' last known objectives
    over_lake: bool
    centroid_xy: tuple[float, float] | None
    target_fire_id: int = -1  # the fire dominating this agent's cell (from coverage)
    monitor_fire_id: int = -1  # a MONITOR planner's assignment, -1 for none
    release: bool | None = None  # raster: the release rule's verdict (tactics); None: the distance rule
    # [s] every point of the search area has been inside a fleet sensor's range since this time
    # (the staleness map's oldest sighting); inf: no map, the sweep counts as done (post_search_s alone)
    swept_since_s: float = math.inf


@dataclass(frozen=True)
class Decision:
    objective: Objective
    target_fire_id: int
    request: int | None  # PayloadRequest.ACTION_* or None
    direct: bool  # steer straight at the target (attack run / stalled refill)
    changed: bool  # objective changed this step


@dataclass
class Mission:
    cfg: MissionConfig
    objective: Objective = Objective.GROUNDED
    target_fire_id: int = -1
    drops: int = 0
    _since_s: float = 0.0  # start of the current stall watch
    _attack_since_s: float | None = None
    _drop_step_guard: int = 0
    _centroids: deque = field(default_factory=lambda: deque(maxlen=4000))
    _all_out_since_s: float | None = None  # when this agent's picture last became "all out"

    def _fleet_agrees_out(self, v: MissionView) -> bool:
        if v.all_out:
            if self._all_out_since_s is None:
                self._all_out_since_s = v.t_s
            if not self.cfg.search_enabled:
                return True
            waited = v.t_s - self._all_out_since_s
            swept = v.swept_since_s >= self._all_out_since_s  # covered all over since they went out
            if waited >= self.cfg.post_search_s and (swept or waited >= self.cfg.post_search_max_s):
                return True
        else:
            self._all_out_since_s = None
        peers = list(v.peer_objectives.values())
        return bool(peers) and all(o in (Objective.LAND, Objective.LANDED) for o in peers)

    def _choose(self, v: MissionView) -> Objective:
        if self._fleet_agrees_out(v):
            return Objective.LAND
        if v.water_kg < self.cfg.min_water_fraction * self.cfg.water_capacity_kg:
            return Objective.REFILL
        if v.monitor_fire_id >= 0:
            return Objective.MONITOR
        if v.fires:
            return Objective.SUPPRESS
        return Objective.SEARCH if self.cfg.search_enabled else Objective.SUPPRESS

    def _set(self, obj: Objective, t_s: float) -> bool:
        if obj == self.objective:
            return False
        self.objective = obj
        self._since_s = t_s
        self._attack_since_s = None
        self._centroids.clear()
        return True

    def _stalled(self, v: MissionView) -> bool:
        if v.centroid_xy is not None:
            self._centroids.append((v.t_s, v.centroid_xy))
        if v.t_s - self._since_s < self.cfg.deadlock_timeout_s or not self._centroids:
            return False
        window = [c for t, c in self._centroids if t >= v.t_s - self.cfg.deadlock_timeout_s]
        if len(window) < 2:
            return False
        xs = [c[0] for c in window]
        ys = [c[1] for c in window]
        if math.hypot(max(xs) - min(xs), max(ys) - min(ys)) < self.cfg.deadlock_centroid_move_m:
            return True
        # A centroid that drifts with its fire, or jitters as a neighbour circles, is not frozen,
        # yet the UAV circling it never comes within the drop radius (fault_drill, 2 UAVs on one
        # sigma-60 fire: each circles its half's centroid ~0.8 sigma out; 0 drops in 240 s).
        # So a UAV with water that has not dropped for deadlock_stuck_factor * the timeout attacks too.
        return v.t_s - self._since_s >= self.cfg.deadlock_stuck_factor * self.cfg.deadlock_timeout_s

    def step(self, v: MissionView) -> Decision:
        before = self.objective
        request = None
        direct = False
        if v.vehicle == VehicleStatus.CRASHED:
            return Decision(self.objective, self.target_fire_id, None, False, False)
        if v.vehicle == VehicleStatus.LANDED and self.objective == Objective.LAND:
            self._set(Objective.LANDED, v.t_s)
        elif self.objective == Objective.GROUNDED:
            if v.t_s >= self.cfg.takeoff_time_s or v.vehicle == VehicleStatus.AIRBORNE:
                want = self._choose(v)
                if want == Objective.LAND and v.vehicle == VehicleStatus.ON_GROUND:
                    # The fleet agreed to land before this UAV's takeoff slot: it never took off,
                    # so it is down already (IV-D d) instead of climbing out just to land again.
                    want = Objective.LANDED
                self._set(want, v.t_s)
        elif self.objective == Objective.LAND or self.objective == Objective.LANDED:
            pass  # terminal: fires do not re-ignite in FF
        elif self.objective == Objective.REFILL:
            if self._drop_step_guard > 0:
                self._drop_step_guard -= 1
            elif self._fleet_agrees_out(v):
                self._set(Objective.LAND, v.t_s)
            elif v.water_kg >= self.cfg.full_fraction * self.cfg.water_capacity_kg:
                self._set(self._choose(v), v.t_s)
            if self.objective == Objective.REFILL:
                if v.over_lake and v.water_kg < self.cfg.water_capacity_kg:
                    request = PayloadAction.REFILL
                    self._since_s = v.t_s  # progress: restart the stall watch
                direct = self._stalled(v)
        else:  # SUPPRESS, SEARCH, MONITOR
            want = self._choose(v)
            self._set(want, v.t_s)
        if self.objective == Objective.SUPPRESS:
            self.target_fire_id = v.target_fire_id
            tgt = next((f for f in v.fires if f.fire_id == self.target_fire_id), None)
            if tgt is None and v.fires:
                tgt = min(v.fires, key=lambda f: math.hypot(f.x_m - v.pos_xy[0], f.y_m - v.pos_xy[1]))
                self.target_fire_id = tgt.fire_id
            if self._attack_since_s is None and self._stalled(v):
                self._attack_since_s = v.t_s
            if self._attack_since_s is not None:
                if v.t_s - self._attack_since_s > self.cfg.attack_timeout_s:
                    self._attack_since_s = None
                    self._since_s = v.t_s
                    self._centroids.clear()
                else:
                    direct = True
            if tgt is not None and v.water_kg > 0:
                d = math.hypot(tgt.x_m - v.pos_xy[0], tgt.y_m - v.pos_xy[1])
                if (d <= self.cfg.min_drop_radius_m) if v.release is None else v.release:
                    request = PayloadAction.DROP
                    self.drops += 1
                    self._set(Objective.REFILL, v.t_s)
                    self._drop_step_guard = 3
                    direct = False
        elif self.objective == Objective.MONITOR:
            self.target_fire_id = v.monitor_fire_id
        elif request != PayloadAction.DROP:
            self.target_fire_id = -1
        return Decision(self.objective, self.target_fire_id, request, direct, self.objective != before)
