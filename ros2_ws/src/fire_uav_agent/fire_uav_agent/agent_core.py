"""One UAV's brain without ROS: EKF + peer link + consensus + life-cycle + Lloyd control.

:class:`Agent.step` runs one control step exactly as docs/protocol.md "Agent, on SensorBundle
k" item 3 orders it: EKF predict with the command sent for step k-1 and update with the
bundle's samples; peer bookkeeping of the step-(k-1) peer messages; fire consensus; mission
life-cycle; coverage control. It returns everything the node publishes (:class:`StepOutput`).

Positions are [m; map frame], yaw [rad], speeds [m/s], times [s of sim time].

Planner hook: objectives SEARCH and MONITOR take their target from a :class:`Planner`
(``planners={Objective.SEARCH: ..., Objective.MONITOR: ...}``), which returns a waypoint or a
density on the coverage grid (:class:`PlannerTarget`). The coverage-search planner
(``fire_uav_agent.search``) and the perimeter monitor plug in there; without one, SEARCH uses
:class:`StalenessSearch` (a greedy frontier on a "time since anyone's sensor saw this cell"
density) and MONITOR is never chosen. ``monitor_assigner`` (optional) decides which fire, if
any, this UAV monitors.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from fire_uav_common.terrain import Lake, Terrain

from .consensus import ConsensusConfig, FireConsensus
from .coverage import (
    ControlGains,
    Grid,
    VehicleLimits,
    control_law,
    gaussian_density,
    make_grid,
    mass_centroid,
    own_cell,
)
from .estimation import EkfConfig, Samples, StateEkf
from .mission import Decision, Mission, MissionConfig, MissionView, Objective, Vehicle
from .monitor_role import MonitorPlanner, MonitorPlannerConfig, RoleConfig, assign_monitors
from .peer_link import FireEntry, Outage, PeerFires, PeerLink, PeerState

TOPIC_PERIMETER = 2  # topic_index of /fleet/perimeter in the peer-link loss draw

__all__ = [
    "Agent",
    "AgentConfig",
    "AgentEvent",
    "Bundle",
    "EventType",
    "OwnState",
    "PeerPerimeter",
    "Planner",
    "PlannerTarget",
    "PlannerView",
    "StalenessSearch",
    "StepOutput",
    "config_from_scenario",
]


class EventType:
    """MissionEvent.TYPE_* the agent emits."""

    PEER_CRASHED = 7
    PEER_REJOINED = 8
    FIRE_DETECTED = 11
    OBJECTIVE = 12


ACTION_DROP = 1
ACTION_REFILL = 2


@dataclass(frozen=True)
class AgentConfig:
    """Everything an agent knows a priori (scenario parts + parameters). Units in names."""

    uav_id: int
    uav_count: int
    seed: int = 0
    control_period_s: float = 0.1
    physics_period_s: float = 0.01
    area_m: tuple[float, float, float, float] = (0.0, 600.0, 0.0, 600.0)  # x_min, x_max, y_min, y_max
    grid_resolution_m: float = 5.0
    terrain: Terrain = field(default_factory=Terrain)
    lakes: tuple[Lake, ...] = ()
    start_pose: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # x, y, z [m], yaw [rad]
    takeoff_interval_s: float = 2.0
    limits: VehicleLimits = field(default_factory=VehicleLimits)
    gains: ControlGains = field(default_factory=ControlGains)
    flight_height_m: float = 30.0
    water_capacity_kg: float = 2000.0
    process_noise_sigma: float = 1.0
    refill_height_m: float = 15.0
    refill_speed_margin_mps: float = 10.0
    landing_height_m: float = 1.0
    sigma_gps_m: float = 3.0
    sigma_alt_m: float = 1.5
    alt_max_range_m: float = 40.0
    sigma_gyro_radps: float = 0.3
    fire_range_m: float = 70.0
    loss_probability: float = 0.05
    outages: tuple[Outage, ...] = ()
    crash_threshold_steps: int = 10
    sigma_water_m: float = 40.0
    sigma_landing_m: float = 10.0
    use_safety_band: bool = True
    safety_radius_m: float = 10.0
    extinction_extent_m: float = 2.0
    search_first: bool = False
    drop_radius_m: float = (
        20.0  # water footprint radius (scenario fires.drop_radius_m; world hits within max(this, sigma))
    )
    land_approach_radius_m: float = 120.0  # start descending this close to the start point
    monitors_per_fire: int = 0  # PM: UAVs per active fire that monitor its perimeter (scenario mission.)
    monitor_circling: bool = False  # monitors circle (PM VI-E baseline) instead of importance-based
    monitor_alpha: float = 1.0  # PM Eq. 7 heterogeneity-adjusting factor
    perimeter_every_steps: int = 10  # publish the monitor's PerimeterMap every n steps (~1 Hz)

    def __post_init__(self) -> None:
        if not 0 <= self.uav_id < self.uav_count:
            raise ValueError(
                f"uav_id must be in 0..uav_count-1, got uav_id={self.uav_id}, uav_count={self.uav_count}"
            )
        if not self.control_period_s > 0 or not self.physics_period_s > 0:
            raise ValueError("control_period_s and physics_period_s must be > 0")
        if self.crash_threshold_steps < 1:
            raise ValueError(f"crash_threshold_steps must be >= 1, got {self.crash_threshold_steps}")
        if not 0.0 <= self.loss_probability <= 1.0:
            raise ValueError(f"loss_probability must be in [0, 1], got {self.loss_probability}")


def _get(obj: Any, *names: str, default: Any = None) -> Any:
    for n in names:
        if obj is not None and hasattr(obj, n):
            return getattr(obj, n)
        if isinstance(obj, Mapping) and n in obj:
            return obj[n]
    return default


def config_from_scenario(
    scenario: Any,
    uav_id: int,
    uav_count: int | None = None,
    seed: int | None = None,
    loss_probability: float | None = None,
    outages: tuple[Outage, ...] | None = None,
    crash_threshold_steps: int | None = None,
) -> AgentConfig:
    """Build the agent's a-priori config from a ``fire_uav_common.scenario.Scenario``.

    Reads only area, terrain, lakes, timing, vehicle, sensors, uavs (own start pose), comms,
    mission -- never the fires. Arguments not None override the scenario (runner flags).
    """
    n = int(uav_count if uav_count is not None else scenario.uavs.count)
    pose = scenario.uav_start_poses(n)[uav_id]
    if isinstance(pose, (tuple, list, np.ndarray)):
        start = tuple(float(v) for v in pose[:4])
    else:
        start = (float(pose.x_m), float(pose.y_m), float(pose.z_m), float(pose.yaw_rad))
    a, tm, veh, sens, mis, com = (
        scenario.area,
        scenario.timing,
        scenario.vehicle,
        scenario.sensors,
        scenario.mission,
        scenario.comms,
    )
    if outages is None:
        outages = tuple(
            Outage(
                int(_get(o, "from_id", "from_", "from", "src")),
                int(_get(o, "to_id", "to", "dst")),
                float(o.start_s),
                float(o.end_s),
            )
            for o in (_get(com, "outages", default=()) or ())
        )
    return AgentConfig(
        uav_id=uav_id,
        uav_count=n,
        seed=int(seed if seed is not None else scenario.seed),
        control_period_s=float(tm.control_period_s),
        physics_period_s=float(tm.physics_period_s),
        area_m=(float(a.x_min_m), float(a.x_max_m), float(a.y_min_m), float(a.y_max_m)),
        grid_resolution_m=float(mis.grid_resolution_m),
        terrain=scenario.terrain,
        lakes=tuple(scenario.lakes),
        start_pose=start,
        takeoff_interval_s=float(scenario.uavs.takeoff_interval_s),
        limits=VehicleLimits(
            float(veh.v_stall_mps), float(veh.v_max_mps), float(veh.vz_max_mps), float(veh.omega_max_radps)
        ),
        flight_height_m=float(veh.flight_height_m),
        water_capacity_kg=float(veh.water_capacity_kg),
        process_noise_sigma=float(veh.process_noise_sigma),
        refill_height_m=float(veh.refill_height_m),
        refill_speed_margin_mps=float(veh.refill_speed_margin_mps),
        landing_height_m=float(veh.landing_height_m),
        sigma_gps_m=float(sens.gps.sigma_m),
        sigma_alt_m=float(sens.altimeter.sigma_m),
        alt_max_range_m=float(sens.altimeter.max_range_m),
        sigma_gyro_radps=float(sens.gyro.sigma_radps),
        fire_range_m=float(sens.fire.range_m),
        loss_probability=float(loss_probability if loss_probability is not None else com.loss_probability),
        outages=tuple(outages),
        crash_threshold_steps=int(
            crash_threshold_steps if crash_threshold_steps is not None else mis.crash_threshold_steps
        ),
        sigma_water_m=float(mis.sigma_water_m),
        sigma_landing_m=float(mis.sigma_landing_m),
        use_safety_band=bool(mis.use_safety_band),
        safety_radius_m=float(mis.safety_radius_m),
        search_first=bool(_get(mis, "search_first", default=False)),
        drop_radius_m=float(_get(scenario.fires, "drop_radius_m", default=None) or 20.0),
        monitors_per_fire=int(_get(mis, "monitors_per_fire", default=0) or 0),
    )


# --- bundle / outputs ---------------------------------------------------------------------
@dataclass
class Bundle:
    """One SensorBundle, ROS-free. fires: (N, 4) rows (t_s, x_m, y_m, extent_m)."""

    step: int
    stamp_s: float  # t_{k+1}
    samples: Samples
    fires: np.ndarray
    water_kg: float
    vehicle: int  # SensorBundle.VEHICLE_*
    control_period_s: float = 0.1
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # FireCells: x_m, y_m, state
    cell_size_m: float = 0.0  # [m] FireCells.cell_size_m, 0 without a raster fire


@dataclass(frozen=True)
class PeerPerimeter:
    """A peer monitor's PerimeterMap, ROS-free (``summary``: PerimeterMonitor.to_summary() fields)."""

    uav_id: int
    sequence: int
    step: int
    fire_id: int
    summary: dict


@dataclass(frozen=True)
class OwnState:
    """Fields of this agent's UavState."""

    uav_id: int
    sequence: int
    step: int
    stamp_s: float
    s: np.ndarray  # (x, y, z, yaw)
    covariance: np.ndarray  # 4x4
    objective: int
    target_fire_id: int
    water_kg: float
    centroid_xy: tuple[float, float]
    alive_peers: tuple[int, ...]
    crashed_peers: tuple[int, ...]
    packets_received: int
    packets_lost: int
    packets_rejected: int

    def as_peer_state(self) -> PeerState:
        return PeerState(
            self.uav_id,
            self.sequence,
            self.step,
            *(float(v) for v in self.s),
            self.objective,
            self.target_fire_id,
            self.water_kg,
            *self.centroid_xy,
        )


@dataclass(frozen=True)
class AgentEvent:
    type: int  # MissionEvent.TYPE_*
    peer_id: int = -1
    fire_id: int = -1
    x_m: float = math.nan
    y_m: float = math.nan
    value: float = 0.0
    detail: str = ""


@dataclass(frozen=True)
class MarkersData:
    cell_boundary_xy: np.ndarray  # (K, 2) grid points on this agent's cell border
    centroid_xy: tuple[float, float]
    objective: int
    text: str


@dataclass(frozen=True)
class StepOutput:
    step: int
    stamp_s: float
    command: tuple[float, float, float]  # v_lin [m/s], v_z [m/s], omega_z [rad/s]
    payload_requests: tuple[tuple[int, int], ...]  # (ACTION_*, target_fire_id)
    state: OwnState
    fires: tuple[FireEntry, ...]
    fires_sequence: int
    events: tuple[AgentEvent, ...]
    markers: MarkersData | None
    direct: bool  # attack run / stalled-refill mode in effect
    perimeter: tuple[int, dict] | None = None  # (fire_id, PerimeterMap fields) to publish this step


# --- planners -------------------------------------------------------------------------------
@dataclass(frozen=True)
class PlannerView:
    t_s: float
    uav_id: int
    s: np.ndarray  # own estimate (x, y, z, yaw)
    grid: Grid
    cell_mask: np.ndarray  # (M,) own Voronoi cell
    peers_xy: dict[int, tuple[float, float]]  # alive flying peers' last known positions
    fires: tuple[FireEntry, ...]
    target_fire_id: int = -1  # MONITOR: the fire this UAV monitors
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # this step's FireCells
    cell_size_m: float = 0.0  # [m]
    peer_roles: dict[int, tuple[int, int]] = field(
        default_factory=dict
    )  # alive peer -> (objective, target fire)
    own_published_xy: tuple[float, float] | None = None  # own position as peers last received it
    own_objective: int = -1
    own_target_fire_id: int = -1


@dataclass(frozen=True)
class PlannerTarget:
    """Either a waypoint [m; map] or a density on ``grid.points`` (then the cell centroid)."""

    waypoint_xy: tuple[float, float] | None = None
    density: np.ndarray | None = None
    height_m: float | None = None  # above terrain; None: flight height
    speed_cap_mps: float | None = None


class Planner(Protocol):
    def plan(self, view: PlannerView) -> PlannerTarget | None: ...


class StalenessSearch:
    """Default SEARCH planner: a greedy frontier over the fleet's staleness map.

    Staleness = time since any UAV's fire sensor covered a grid point (saturating after
    ``horizon_s``). Every agent updates the map from the same information (own estimate +
    peers' states). The UAV flies to the *nearest of the stalest points of its own Voronoi
    cell* (within ``stale_band`` of the cell's maximum staleness), so the fleet partitions the
    search like the Lloyd controller partitions suppression.

    Why not a staleness density and the Lloyd centroid: that was the first version, and in
    system runs two UAVs circled fixed centroids for four minutes, 73 m from an undetected
    fire: the fresh disc around a circling UAV balances the rest of its cell, an equilibrium
    that stops exploring. A waypoint on the stale frontier is seen as the UAV reaches it, so
    the target always moves on.
    """

    def __init__(
        self, grid: Grid, sensor_range_m: float, horizon_s: float = 120.0, stale_band: float = 0.05
    ) -> None:
        self.grid = grid
        self.r2 = sensor_range_m**2
        self.horizon_s = horizon_s
        self.stale_band = stale_band
        self.last_seen = np.full(grid.points.shape[0], -horizon_s)

    def observe(self, t_s: float, positions_xy: np.ndarray) -> None:
        p = np.asarray(positions_xy, dtype=float).reshape(-1, 2)
        if p.shape[0] == 0:
            return
        dx = self.grid.points[:, 0:1] - p[None, :, 0]
        dy = self.grid.points[:, 1:2] - p[None, :, 1]
        seen = ((dx * dx + dy * dy) <= self.r2).any(axis=1)
        self.last_seen[seen] = t_s

    def staleness(self, t_s: float) -> np.ndarray:
        """Per grid point, in [0, 1]: 1 = not seen for ``horizon_s`` (or never)."""
        return np.clip((t_s - self.last_seen) / self.horizon_s, 0.0, 1.0)

    def plan(self, view: PlannerView) -> PlannerTarget | None:
        age = self.staleness(view.t_s)
        mask = view.cell_mask
        cand = np.flatnonzero(mask) if mask is not None and np.any(mask) else np.arange(age.size)
        a = age[cand]
        sel = cand[a >= a.max() - self.stale_band]
        pts = self.grid.points[sel]
        d2 = (pts[:, 0] - view.s[0]) ** 2 + (pts[:, 1] - view.s[1]) ** 2
        x, y = pts[int(np.argmin(d2))]
        return PlannerTarget(waypoint_xy=(float(x), float(y)))


# --- the agent --------------------------------------------------------------------------------
class Agent:
    """One UAV's control step; see the module doc."""

    def __init__(
        self,
        cfg: AgentConfig,
        planners: Mapping[int, Planner] | None = None,
        monitor_assigner: Callable[[PlannerView], int] | None = None,
    ) -> None:
        self.cfg = cfg
        self.ekf = StateEkf(
            EkfConfig(
                dt_s=cfg.physics_period_s,
                sigma_nu=(cfg.process_noise_sigma,) * 3,
                sigma_gps_m=cfg.sigma_gps_m,
                sigma_alt_m=cfg.sigma_alt_m,
                sigma_gyro_radps=cfg.sigma_gyro_radps,
                alt_max_range_m=cfg.alt_max_range_m,
            ),
            np.array(cfg.start_pose, dtype=float),
            cfg.terrain,
        )
        self.link = PeerLink(
            cfg.uav_id,
            cfg.uav_count,
            cfg.seed,
            cfg.loss_probability,
            cfg.control_period_s,
            cfg.crash_threshold_steps,
            cfg.outages,
        )
        self.fires = FireConsensus(
            cfg.uav_id,
            ConsensusConfig(
                control_period_s=cfg.control_period_s,
                sensor_range_m=cfg.fire_range_m,
                extinction_extent_m=cfg.extinction_extent_m,
                negative_range_m=min(50.0, 0.7 * cfg.fire_range_m),
            ),
        )
        self.mission = Mission(
            MissionConfig(
                takeoff_time_s=cfg.uav_id * cfg.takeoff_interval_s,
                water_capacity_kg=cfg.water_capacity_kg,
                search_enabled=True,
                # release inside the footprint with a margin for estimation error (EKF ~1-2 m)
                min_drop_radius_m=0.7 * cfg.drop_radius_m,
            )
        )
        self.grid = make_grid(*cfg.area_m, cfg.grid_resolution_m)
        self.search = StalenessSearch(self.grid, cfg.fire_range_m)
        self.planners: dict[int, Planner] = dict(planners or {})
        self.planners.setdefault(int(Objective.SEARCH), self.search)
        self.monitor_assigner = monitor_assigner
        self.role_cfg = RoleConfig(monitors_per_fire=cfg.monitors_per_fire)
        self.monitor: MonitorPlanner | None = None
        if cfg.monitors_per_fire > 0 and int(Objective.MONITOR) not in self.planners:
            self.monitor = MonitorPlanner(
                cfg.uav_id,
                MonitorPlannerConfig(
                    speed_mps=cfg.limits.v_stall_mps + 5.0,
                    alpha=cfg.monitor_alpha,
                    circling=cfg.monitor_circling,
                ),
            )
            self.planners[int(Objective.MONITOR)] = self.monitor
        if self.monitor_assigner is None and cfg.monitors_per_fire > 0:
            self.monitor_assigner = self.assign_monitor
        self.roles: dict[int, tuple[int, ...]] = {}
        self._pub_xy: tuple[float, float] | None = None
        self._fronts: dict[int, tuple[float, float, float]] = {}  # fire id -> (x, y, ros) from monitors
        self.perimeter_received = 0
        self.perimeter_lost = 0
        self.last_step = -1
        self.last_command = np.zeros(3)
        self._last_vehicle = int(Vehicle.ON_GROUND)
        self._seq = 0
        self._centroid = (cfg.start_pose[0], cfg.start_pose[1])
        self._cell = np.ones(self.grid.points.shape[0], dtype=bool)
        self._start_xy = np.array(cfg.start_pose[:2], dtype=float)

    # --- lockstep helper ---------------------------------------------------------------------
    def expected_peer_messages(self, step: int) -> set[tuple[int, int]]:
        """(peer, topic_index) of step ``step - 1`` the node should wait for before step ``step``."""
        return self.link.expected(step - 1) if step >= 1 else set()

    def _world_applied(self, cmd: np.ndarray, airborne: bool) -> np.ndarray:
        """The command as the world applies it (clamped to the limits) for the EKF prediction."""
        lim = self.cfg.limits
        v = float(np.clip(cmd[0], lim.v_stall_mps, lim.v_max_mps)) if airborne else float(cmd[0])
        return np.array(
            [
                v,
                float(np.clip(cmd[1], -lim.vz_max_mps, lim.vz_max_mps)),
                float(np.clip(cmd[2], -lim.omega_max_radps, lim.omega_max_radps)),
            ]
        )

    # --- one control step -----------------------------------------------------------------------
    def step(
        self, bundle: Bundle, inbox: Iterable[PeerState | PeerFires] = (), want_markers: bool = False
    ) -> StepOutput | None:
        """Run control step ``bundle.step``; None if a newer bundle was already processed."""
        if bundle.step <= self.last_step:
            return None
        cfg = self.cfg
        T = cfg.control_period_s
        t1 = bundle.stamp_s
        events: list[AgentEvent] = []
        vehicle = Vehicle(int(bundle.vehicle))
        # 1. EKF (FF III-B)
        moving = vehicle == Vehicle.AIRBORNE or self._last_vehicle == Vehicle.AIRBORNE
        u = self._world_applied(self.last_command, self._last_vehicle == Vehicle.AIRBORNE)
        if vehicle in (Vehicle.LANDED, Vehicle.ON_GROUND) and self._last_vehicle == Vehicle.AIRBORNE:
            u = np.array([0.0, u[1], 0.0])  # touched down during the step
        self.ekf.process(bundle.samples, u, t1 - T, t1, moving=moving)
        s = self.ekf.s.copy()
        # 2. peer bookkeeping (protocol "Peer link")
        msgs = sorted(
            inbox,
            key=lambda m: (m.step, m.uav_id if isinstance(m.uav_id, int) else -1, isinstance(m, PeerFires)),
        )
        perimeters: list[PeerPerimeter] = []
        for m in msgs:
            if isinstance(m, PeerState):
                self.link.receive_state(m)
            elif isinstance(m, PeerPerimeter):
                if m.uav_id == cfg.uav_id or not 0 <= m.uav_id < cfg.uav_count:
                    continue
                if self.link.is_lost(m.uav_id, m.step, TOPIC_PERIMETER):
                    self.perimeter_lost += 1
                    continue
                perimeters.append(m)
            else:
                self.link.receive_fires(m)
        if bundle.step >= 1:
            for ev in self.link.end_step(bundle.step):
                typ = EventType.PEER_CRASHED if ev.kind == "crashed" else EventType.PEER_REJOINED
                events.append(
                    AgentEvent(
                        typ, peer_id=ev.peer_id, value=float(cfg.crash_threshold_steps), detail=ev.kind
                    )
                )
        peer_states = self.link.alive_states()
        # 3. consensus (FF III-C)
        self.fires.predict(T)
        new_ids = self.fires.fuse(self.link.alive_fires(), t1)
        det = bundle.fires if vehicle == Vehicle.AIRBORNE else np.zeros((0, 4))
        new_ids += self.fires.observe(det, (float(s[0]), float(s[1])), t1)
        for fid in new_ids:
            tr = self.fires.tracks.get(fid)
            if tr is not None and fid >> 16 == cfg.uav_id:
                events.append(
                    AgentEvent(
                        EventType.FIRE_DETECTED, fire_id=fid, x_m=tr.x_m, y_m=tr.y_m, detail="first seen"
                    )
                )
        active = tuple(self.fires.active())
        # 4. partition (FF Eqs. 6-7) among flying alive UAVs
        flying = {
            j: (p.x_m, p.y_m)
            for j, p in sorted(peer_states.items())
            if p.objective not in (Objective.GROUNDED, Objective.LANDED)
        }
        pos = np.array(s[:2])
        others = np.array(list(flying.values())).reshape(-1, 2)
        band = cfg.safety_radius_m if cfg.use_safety_band else None
        self._cell = own_cell(self.grid.points, pos, others, band)
        if vehicle == Vehicle.AIRBORNE:
            self.search.observe(t1, np.vstack([pos[None, :], others]))
        # target fire = the one with the largest mass in this cell (Eq. 8 per fire)
        target_fire = -1
        if active:
            masses = [
                float(gaussian_density(self.grid, [(f.x_m, f.y_m)], [f.extent_m])[self._cell].sum())
                for f in active
            ]
            if max(masses) > 0:
                target_fire = active[int(np.argmax(masses))].fire_id
            else:
                target_fire = min(active, key=lambda f: math.hypot(f.x_m - s[0], f.y_m - s[1])).fire_id
        lake = self._nearest_lake(pos)
        over_lake = lake is not None and lake.contains(float(s[0]), float(s[1]))
        self._collect_fronts(active)
        pview = PlannerView(
            t1, cfg.uav_id, s, self.grid, self._cell, flying, active,
            cells=bundle.cells if vehicle == Vehicle.AIRBORNE else None,
            cell_size_m=float(bundle.cell_size_m),
            peer_roles={j: (int(p.objective), int(p.target_fire_id)) for j, p in peer_states.items()},
            own_published_xy=self._pub_xy,
            own_objective=int(self.mission.objective),
            own_target_fire_id=int(self.mission.target_fire_id),
        )  # fmt: skip
        self._merge_perimeters(perimeters, flying, t1)
        monitor_fire = self.monitor_assigner(pview) if self.monitor_assigner is not None else -1
        # 5. life-cycle (FF IV-D)
        prev_obj = self.mission.objective
        dec = self.mission.step(
            MissionView(
                t_s=t1,
                vehicle=vehicle,
                water_kg=float(bundle.water_kg),
                pos_xy=(float(s[0]), float(s[1])),
                fires=self._aim(active),
                all_out=self.fires.all_out(),
                peer_objectives={j: p.objective for j, p in peer_states.items()},
                over_lake=over_lake,
                centroid_xy=self._centroid,
                target_fire_id=target_fire,
                monitor_fire_id=monitor_fire,
            )
        )
        if dec.changed:
            events.append(
                AgentEvent(
                    EventType.OBJECTIVE,
                    fire_id=dec.target_fire_id,
                    x_m=float(s[0]),
                    y_m=float(s[1]),
                    value=float(dec.objective),
                    detail=f"{Objective(prev_obj).name} -> {dec.objective.name}",
                )
            )
        requests: list[tuple[int, int]] = []
        if dec.request is not None:
            requests.append((dec.request, dec.target_fire_id if dec.request == ACTION_DROP else -1))
        # 6. guidance (FF Eqs. 8-15)
        cmd = self._guidance(dec, vehicle, s, self._aim(active), lake, pview)
        perimeter = None
        mon = self.monitor.active if self.monitor is not None else None
        if (
            dec.objective == Objective.MONITOR
            and mon is not None
            and mon.grid is not None
            and bundle.step % max(1, cfg.perimeter_every_steps) == 0
        ):
            perimeter = (int(dec.target_fire_id), mon.to_summary())
        self.last_command = np.array(cmd, dtype=float)
        self._last_vehicle = int(vehicle)
        self.last_step = bundle.step
        self._seq += 1
        self._pub_xy = (float(s[0]), float(s[1]))
        state = OwnState(
            uav_id=cfg.uav_id,
            sequence=self._seq,
            step=bundle.step,
            stamp_s=t1,
            s=s,
            covariance=self.ekf.P.copy(),
            objective=int(dec.objective),
            target_fire_id=int(dec.target_fire_id),
            water_kg=float(bundle.water_kg),
            centroid_xy=(float(self._centroid[0]), float(self._centroid[1])),
            alive_peers=tuple(self.link.alive_ids()),
            crashed_peers=tuple(self.link.crashed_ids()),
            packets_received=self.link.received,
            packets_lost=self.link.lost,
            packets_rejected=self.link.rejected,
        )
        markers = self._markers(dec) if want_markers else None
        return StepOutput(
            step=bundle.step,
            stamp_s=t1,
            command=cmd,
            payload_requests=tuple(requests),
            state=state,
            fires=self._with_fronts(self.fires.entries()),
            fires_sequence=self._seq,
            events=tuple(events),
            markers=markers,
            direct=dec.direct,
            perimeter=perimeter,
        )

    # --- perimeter monitoring (PM) ----------------------------------------------------------------
    def assign_monitor(self, view: PlannerView) -> int:
        """Default ``monitor_assigner``: the fire this UAV monitors by :func:`assign_monitors`, or -1.

        Every agent uses the same information: peers' step k-1 states (position, objective,
        target) and its own step k-1 published state, as its peers received it.
        """
        uavs = {
            j: (xy[0], xy[1], *view.peer_roles.get(j, (int(Objective.SEARCH), -1)))
            for j, xy in view.peers_xy.items()
        }
        if view.own_published_xy is not None:
            uavs[view.uav_id] = (*view.own_published_xy, view.own_objective, view.own_target_fire_id)
        self.roles = assign_monitors(((f.fire_id, f.x_m, f.y_m) for f in view.fires), uavs, self.role_cfg)
        return next((fid for fid, ids in self.roles.items() if view.uav_id in ids), -1)

    def _merge_perimeters(self, perimeters: list[PeerPerimeter], flying: dict, t_s: float) -> None:
        if self.monitor is None:
            return
        for p in perimeters:
            m = self.monitor.monitors.get(p.fire_id)
            if m is None:
                continue
            try:
                m.merge(p.summary, peer_id=p.uav_id, peer_pos_m=flying.get(p.uav_id), t_s=t_s)
                self.perimeter_received += 1
            except ValueError:
                self.perimeter_lost += 0  # malformed: ignored (counted nowhere else)

    def _collect_fronts(self, active: tuple[FireEntry, ...]) -> None:
        """Fastest-spreading fronts: own monitors first, else peers' published fronts."""
        ids = {f.fire_id for f in active}
        fronts: dict[int, tuple[float, float, float]] = {}
        for pf in self.link.alive_fires().values():
            for e in pf.fires:
                if e.fire_id in ids and math.isfinite(e.front_x_m) and math.isfinite(e.front_y_m):
                    old = fronts.get(e.fire_id)
                    if old is None or e.max_spread_rate_mps > old[2]:
                        fronts[e.fire_id] = (e.front_x_m, e.front_y_m, e.max_spread_rate_mps)
        if self.monitor is not None:
            for fid in ids:
                fr = self.monitor.front(fid)
                if fr is not None:
                    fronts[fid] = fr
        self._fronts = fronts

    def _with_fronts(self, entries: tuple[FireEntry, ...]) -> tuple[FireEntry, ...]:
        return tuple(
            dataclasses.replace(
                e, front_x_m=self._fronts[e.fire_id][0], front_y_m=self._fronts[e.fire_id][1],
                max_spread_rate_mps=self._fronts[e.fire_id][2],
            )
            if e.fire_id in self._fronts else e
            for e in entries
        )  # fmt: skip

    def _aim(self, active: tuple[FireEntry, ...]) -> tuple[FireEntry, ...]:
        """Fires as suppression sees them: centred on the known fastest-spreading front (PM)."""
        return tuple(
            dataclasses.replace(e, x_m=self._fronts[e.fire_id][0], y_m=self._fronts[e.fire_id][1])
            if e.fire_id in self._fronts else e
            for e in active
        )  # fmt: skip

    # --- helpers --------------------------------------------------------------------------------
    def _nearest_lake(self, pos: np.ndarray) -> Lake | None:
        if not self.cfg.lakes:
            return None
        return min(self.cfg.lakes, key=lambda lk: math.hypot(lk.x_m - pos[0], lk.y_m - pos[1]))

    def _centroid_of(self, density: np.ndarray, fallback_xy: tuple[float, float]) -> tuple[float, float]:
        _, c = mass_centroid(self.grid.points, density, self._cell, self.grid.cell_area_m2)
        return (float(c[0]), float(c[1])) if c is not None else fallback_xy

    def _guidance(
        self,
        dec: Decision,
        vehicle: Vehicle,
        s: np.ndarray,
        active: tuple[FireEntry, ...],
        lake: Lake | None,
        pview: PlannerView,
    ) -> tuple[float, float, float]:
        cfg, lim = self.cfg, self.cfg.limits
        obj = dec.objective
        if vehicle in (Vehicle.CRASHED, Vehicle.LANDED) or obj == Objective.LANDED:
            return (0.0, 0.0, 0.0)
        if obj == Objective.GROUNDED:
            return (0.0, 0.0, 0.0)
        if vehicle == Vehicle.ON_GROUND:  # takeoff slot reached: v >= v_stall and v_z > 0
            return (lim.v_stall_mps, min(lim.vz_max_mps, cfg.gains.vz_cmd_max_mps), 0.0)
        height = cfg.flight_height_m
        v_cap = None
        pos = (float(s[0]), float(s[1]))
        target: tuple[float, float]
        if obj == Objective.SUPPRESS and active:
            tgt = next((f for f in active if f.fire_id == dec.target_fire_id), active[0])
            if dec.direct:
                target = (tgt.x_m, tgt.y_m)
            else:
                dens = gaussian_density(
                    self.grid, [(f.x_m, f.y_m) for f in active], [f.extent_m for f in active]
                )  # Eq. 13
                target = self._centroid_of(dens, (tgt.x_m, tgt.y_m))
        elif obj == Objective.REFILL and lake is not None:
            lake_xy = (lake.x_m, lake.y_m)
            if dec.direct:
                target = lake_xy
            else:
                dens = gaussian_density(self.grid, [lake_xy], [cfg.sigma_water_m])  # Eq. 14
                target = self._centroid_of(dens, lake_xy)
            if math.hypot(pos[0] - lake.x_m, pos[1] - lake.y_m) < lake.diameter_m / 2 + 150.0:
                height = 0.5 * cfg.refill_height_m  # low ...
                v_cap = lim.v_stall_mps + 0.3 * cfg.refill_speed_margin_mps  # ... and slow (FF IV-D b)
        elif obj == Objective.LAND:
            start = (float(self._start_xy[0]), float(self._start_xy[1]))
            dens = gaussian_density(self.grid, [start], [cfg.sigma_landing_m])  # Eq. 15
            target = self._centroid_of(dens, start)
            d = math.hypot(pos[0] - start[0], pos[1] - start[1])
            r = cfg.land_approach_radius_m
            if d < r:
                v_cap = lim.v_stall_mps
                height = 0.5 * cfg.landing_height_m + (
                    cfg.flight_height_m - 0.5 * cfg.landing_height_m
                ) * max(0.0, (d - 0.3 * r) / (0.7 * r))
                agl = float(s[2] - cfg.terrain.elevation(pos[0], pos[1]))
                if agl < 0.8 * cfg.landing_height_m:
                    return (0.0, -0.5, 0.0)  # below stall speed near the ground: the world lands it
        else:  # SEARCH, MONITOR, or SUPPRESS/REFILL without fire/lake
            planner = self.planners.get(int(obj)) or self.search
            plan = planner.plan(dataclasses.replace(pview, target_fire_id=int(dec.target_fire_id)))
            if plan is None:
                plan = self.search.plan(pview)
            if plan.waypoint_xy is not None:
                target = (float(plan.waypoint_xy[0]), float(plan.waypoint_xy[1]))
            else:
                target = self._centroid_of(np.asarray(plan.density, dtype=float), pos)
            if plan.height_m is not None:
                height = plan.height_m
            v_cap = plan.speed_cap_mps
        self._centroid = target
        return control_law(s, np.array(target), height, cfg.terrain, lim, cfg.gains, v_cap)

    def _markers(self, dec: Decision) -> MarkersData:
        ny, nx = self.grid.shape
        m = self._cell.reshape(ny, nx)
        inner = m.copy()
        inner[1:, :] &= m[:-1, :]
        inner[:-1, :] &= m[1:, :]
        inner[:, 1:] &= m[:, :-1]
        inner[:, :-1] &= m[:, 1:]
        border = (m & ~inner).ravel()
        text = f"uav {self.cfg.uav_id}: {dec.objective.name}" + (
            f" fire {dec.target_fire_id}" if dec.target_fire_id >= 0 else ""
        )
        return MarkersData(self.grid.points[border], self._centroid, int(dec.objective), text)
