"""One UAV's brain without ROS: the agent as six stages, one control step at a time.

:meth:`Agent.step` runs control step k exactly as docs/protocol.md "Agent, on SensorBundle k"
item 3 orders it, as six named stages:

1. :meth:`Agent._estimate` -- EKF predict with the command sent for step k-1 and update with the
   bundle's samples (FF III-B, Eqs. 16-25);
2. :meth:`Agent._link` -- peer bookkeeping of the step-(k-1) peer messages (FF IV-B, IV-C);
3. :meth:`Agent._fuse` -- fire consensus with the peers' pictures and own detections (FF III-C);
4. :meth:`Agent._decide` -- partition (FF Eqs. 6-7), target fire (Eq. 8), monitor role (PM) and
   the mission life-cycle (FF IV-D);
5. :meth:`Agent._guide` -- the target of the objective and the control law (FF Eqs. 8-15);
6. :meth:`Agent._compose_output` -- what the node publishes (:class:`StepOutput`).

Each stage returns what it produces (:class:`Situation`, :class:`Guidance`, ...) and the next
takes it as an argument; what crosses from one step to the next (the EKF, the peer link, the
fire tracks, the last command and centroid) is kept on the agent and set in :meth:`Agent.step`.

Positions are [m; map frame], yaw [rad], speeds [m/s], times [s of sim time].

Planner hook: objectives SEARCH and MONITOR take their target from a :class:`Planner`
(``planners={Objective.SEARCH: ..., Objective.MONITOR: ...}``, see :mod:`.planning`), which
returns a waypoint or a density on the coverage grid (:class:`PlannerTarget`). The
coverage-search planner (``fire_uav_agent.search``) and the perimeter monitor plug in there;
without one, SEARCH uses :class:`StalenessSearch` and MONITOR is never chosen.
``monitor_assigner`` (optional) decides which fire, if any, this UAV monitors.

The config (:mod:`.agent_config`), the data types (:mod:`.agent_types`), the planner protocols
(:mod:`.planning`) and the default search (:mod:`.staleness_search`) live in their own modules;
their names are re-exported here.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Mapping

import numpy as np
from fire_uav_common.constants import EventType, Objective, PayloadAction, VehicleStatus
from fire_uav_common.terrain import Lake
from fire_uav_common.topics import FLEET_FRONT_SPEC, FLEET_PERIMETER_SPEC

from .agent_config import AgentConfig, GuidanceConfig, config_from_scenario
from .agent_types import AgentEvent, Bundle, MarkersData, OwnState, PeerPerimeter, StepOutput
from .airframe_model import FlownInput, input_noise_sigma, usable_lakes
from .consensus import ConsensusConfig, FireConsensus
from .coverage import gaussian_density_at, make_grid, own_cell_on_grid
from .estimation import EkfConfig, StateEkf
from .fire_front import FrontPicture
from .front_consensus import PeerFront
from .guidance import Guidance, Guide, Situation
from .mission import Decision, Mission, MissionConfig, MissionView
from .monitor_role import MonitorPlanner, MonitorPlannerConfig, RoleConfig, assign_monitors
from .peer_gate import SortedInbox, inbox_order
from .peer_link import FireEntry, PeerFires, PeerLink, PeerState
from .planning import Planner, PlannerTarget, PlannerView
from .raster_role import RasterSuppression
from .separation import PeerAvoidance
from .staleness_search import StalenessSearch
from .tactics import (
    TacticConfig,
)
from .wind_estimation import WindEkfConfig, WindStateEkf

__all__ = [
    "Agent",
    "AgentConfig",
    "AgentEvent",
    "Bundle",
    "EventType",
    "GuidanceConfig",
    "MarkersData",
    "OwnState",
    "PeerPerimeter",
    "Planner",
    "PlannerTarget",
    "PlannerView",
    "StalenessSearch",
    "StepOutput",
    "config_from_scenario",
]


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
        veh, sens, gd = cfg.vehicle, cfg.sensors, cfg.guidance
        ekf_cfg = EkfConfig(
            dt_s=cfg.physics_period_s,
            sigma_nu=input_noise_sigma(cfg.airframe, veh.process_noise_sigma, cfg.physics_period_s),
            sigma_gps_m=sens.gps.sigma_m,
            sigma_alt_m=sens.altimeter.sigma_m,
            sigma_gyro_radps=sens.gyro.sigma_radps,
            alt_max_range_m=sens.altimeter.max_range_m,
            alt_min_m=-math.inf if cfg.airframe is not None else 0.0,
        )
        # FF's EKF (III-B) for FF's unicycle, which the world does not drift; a fixed-wing flies
        # through the air and the world drifts it with the wind: two more states for the wind
        # (fire_uav_agent.wind_estimation)
        self.ekf: StateEkf | WindStateEkf = (
            StateEkf(ekf_cfg, np.array(cfg.start_pose, dtype=float), cfg.terrain)
            if cfg.airframe is None
            else WindStateEkf(WindEkfConfig(ekf_cfg), np.array(cfg.start_pose, dtype=float), cfg.terrain)
        )
        self.flown = FlownInput(cfg.airframe, cfg.limits, cfg.physics_period_s, cfg.control_period_s)
        # a fixed-wing refills only where the lake is long enough for its scoop run; the node logs
        # ``lakes_refused``, one line per lake left out
        self.lakes, self.lakes_refused = usable_lakes(cfg.lakes, cfg.airframe)
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
                negative_range_m=min(
                    gd.consensus_negative_range_max_m, gd.consensus_negative_range_fraction * cfg.fire_range_m
                ),
                position_sigma_m=sens.fire.position_sigma_m,
            ),
        )
        self.fires.brief(cfg.prior_fires, position_sigma_m=cfg.mission.prior_position_sigma_m)
        self.mission = Mission(
            MissionConfig(
                takeoff_time_s=cfg.uav_id * cfg.takeoff_interval_s,
                water_capacity_kg=veh.water_capacity_kg,
                search_enabled=not cfg.fires_known,
                post_search_s=cfg.mission.post_search_s,
                post_search_max_s=cfg.mission.post_search_max_s,
                # release inside the footprint with a margin for estimation error (EKF ~1-2 m)
                min_drop_radius_m=gd.drop_radius_fraction * cfg.drop_radius_m,
            )
        )
        self.grid = make_grid(*cfg.area_m, cfg.mission.grid_resolution_m)
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
                    speed_mps=cfg.limits.v_stall_mps + gd.monitor_speed_margin_mps,
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
        self._last_vehicle = int(VehicleStatus.ON_GROUND)
        self._seq = 0
        self._centroid = (cfg.start_pose[0], cfg.start_pose[1])  # the point the last step steered to
        self._situation: Situation | None = None  # the last step's (for tests and benchmarks)
        self.raster = RasterSuppression(cfg, self.grid)  # idle until a bundle carries FireCells
        lim = cfg.limits
        af = cfg.airframe
        self.avoidance = PeerAvoidance(
            cfg.uav_id, cfg.control_period_s, cfg.separation, lim.v_stall_mps, lim.v_max_mps, lim.omega_max_radps,
            None if af is None else (lambda v: min(lim.omega_max_radps, af.turn_rate_max_radps(v))),
        )  # fmt: skip
        self.guide = Guide(
            cfg, self.grid, self.planners, self.search, self.raster, self.link, self.avoidance, self.flown
        )

    # --- views of the parts (read by tests and benchmarks) -----------------------------------------
    @property
    def front(self) -> FrontPicture | None:
        """The raster front picture (None: no raster fire seen yet)."""
        return self.raster.front

    @property
    def tactic(self) -> TacticConfig:
        return self.raster.tactic

    @property
    def fronts_received(self) -> int:
        return self.raster.fronts_received

    @property
    def avoidance_steps(self) -> int:
        """Control steps the separation filter changed the heading."""
        return self.avoidance.steps_changed

    @property
    def _cell(self) -> np.ndarray:
        """The own Voronoi cell of the last step (all of the grid before the first)."""
        if self._situation is None:
            return np.ones(self.grid.points.shape[0], dtype=bool)
        return self._situation.cell

    @property
    def _front_aim(self) -> tuple[float, float] | None:
        """The last step's aim point on the front (raster), read by the suppression benchmark."""
        return None if self._situation is None else self._situation.front_aim

    # --- lockstep helper ---------------------------------------------------------------------
    def expected_peer_messages(self, step: int) -> set[tuple[int, int]]:
        """(peer, loss_index) of step ``step - 1`` the node should wait for before step ``step``."""
        return self.link.expected(step - 1) if step >= 1 else set()

    # --- one control step -----------------------------------------------------------------------
    def step(
        self,
        bundle: Bundle,
        inbox: Iterable[PeerState | PeerFires | PeerPerimeter | PeerFront] = (),
        want_markers: bool = False,
    ) -> StepOutput | None:
        """Run control step ``bundle.step``; None if a newer bundle was already processed."""
        if bundle.step <= self.last_step:
            return None
        vehicle = VehicleStatus(int(bundle.vehicle))
        events: list[AgentEvent] = []
        s = self._estimate(bundle, vehicle)
        perimeters = self._link(bundle.step, inbox, events)
        active = self._fuse(bundle, vehicle, s, events)
        sit = self._decide(bundle, vehicle, s, active, perimeters, events, self._centroid)
        guidance = self._guide(sit, vehicle, s)
        self._situation = sit
        if guidance.target_xy is not None:
            self._centroid = guidance.target_xy
        return self._compose_output(bundle, sit, s, guidance.command, events, want_markers)

    def _estimate(self, bundle: Bundle, vehicle: VehicleStatus) -> np.ndarray:
        """Stage 1, FF III-B: EKF over the step's samples; returns the estimate s = (x, y, z [m], yaw [rad]).

        Predicts with the command sent for the previous step as the world applied it (clamped,
        Eq. 5; zero speed and turn rate if the vehicle touched down during the step) and, on a
        fixed-wing, as the airframe flew it (:class:`.airframe_model.FlownInput`), at the
        physics period (Eqs. 4, 16-17), and applies the GPS / altimeter / gyro samples in time
        order at their own rates (sequential updates, Eqs. 18-25), from t_k = t_{k+1} - T to
        t_{k+1} = ``bundle.stamp_s`` [s].
        """
        t1 = bundle.stamp_s
        was_airborne = self._last_vehicle == VehicleStatus.AIRBORNE
        moving = vehicle == VehicleStatus.AIRBORNE or was_airborne
        u = self.flown.input(self.last_command, was_airborne, vehicle, float(bundle.water_kg))
        self.ekf.process(bundle.samples, u, t1 - self.cfg.control_period_s, t1, moving=moving)
        return self.ekf.s.copy()

    def _link(
        self,
        step: int,
        inbox: Iterable[PeerState | PeerFires | PeerPerimeter | PeerFront],
        events: list[AgentEvent],
    ) -> list[PeerPerimeter]:
        """Stage 2, FF IV-B/IV-C: peer bookkeeping of the messages received since the last step.

        States and fire pictures go through the peer link (loss on receipt, rejection, crash
        declaration after ``crash_threshold_steps`` missed steps, rejoin); PEER_CRASHED /
        PEER_REJOINED events are appended to ``events``. Returns the accepted peer perimeter maps
        (PM), which are merged in :meth:`_decide`.
        """
        cfg = self.cfg
        # the gate hands them in this order already (a SortedInbox); anything else is sorted here, so
        # that a direct caller in arrival order gets the same result
        msgs = inbox if isinstance(inbox, SortedInbox) else sorted(inbox, key=inbox_order)
        perimeters: list[PeerPerimeter] = []
        for m in msgs:
            if isinstance(m, PeerState):
                self.link.receive_state(m, now_step=step)
            elif isinstance(m, PeerPerimeter):
                if m.uav_id == cfg.uav_id or not 0 <= m.uav_id < cfg.uav_count:
                    continue
                if self.link.is_lost(m.uav_id, m.step, FLEET_PERIMETER_SPEC.draw_index):
                    self.perimeter_lost += 1
                    continue
                perimeters.append(m)
            elif isinstance(m, PeerFront):
                if m.uav_id == cfg.uav_id or not 0 <= m.uav_id < cfg.uav_count:
                    continue
                if not self.link.is_lost(m.uav_id, m.step, FLEET_FRONT_SPEC.draw_index):
                    self.raster.peer_fronts.append(m)
            else:
                self.link.receive_fires(m, now_step=step)
        if step >= 1:
            for ev in self.link.end_step(step):
                typ = EventType.PEER_CRASHED if ev.kind == "crashed" else EventType.PEER_REJOINED
                events.append(
                    AgentEvent(
                        typ, peer_id=ev.peer_id, value=float(cfg.crash_threshold_steps), detail=ev.kind
                    )
                )
        return perimeters

    def _fuse(
        self, bundle: Bundle, vehicle: VehicleStatus, s: np.ndarray, events: list[AgentEvent]
    ) -> tuple[FireEntry, ...]:
        """Stage 3, FF III-C (Eqs. 26-29): fire consensus; returns the active fires at t_{k+1}.

        Predicts every track over one control period, fuses the alive peers' pictures
        (freshness-weighted), then this UAV's own detections (airborne only) near its estimate
        ``s``. A fire this UAV saw first adds a FIRE_DETECTED event to ``events``.
        """
        cfg = self.cfg
        t1 = bundle.stamp_s
        self.fires.predict(cfg.control_period_s)
        new_ids = self.fires.fuse(self.link.alive_fires(), t1)
        det = bundle.fires if vehicle == VehicleStatus.AIRBORNE else np.zeros((0, 4))
        # first: its burning cells gate negative evidence; a peer front of another cell size is a
        # counted rejection ("cell size")
        self.raster.fuse(bundle, vehicle, t1, reject=self.link.count_rejection)
        burning = None if self.front is None else self.front.burning_xy(t1)
        new_ids += self.fires.observe(det, (float(s[0]), float(s[1])), t1, burning)
        for fid in new_ids:
            tr = self.fires.tracks.get(fid)
            if tr is not None and fid >> 16 == cfg.uav_id:
                events.append(
                    AgentEvent(
                        EventType.FIRE_DETECTED, fire_id=fid, x_m=tr.x_m, y_m=tr.y_m, detail="first seen"
                    )
                )
        return tuple(self.fires.active())

    def _decide(
        self,
        bundle: Bundle,
        vehicle: VehicleStatus,
        s: np.ndarray,
        active: tuple[FireEntry, ...],
        perimeters: list[PeerPerimeter],
        events: list[AgentEvent],
        centroid_xy: tuple[float, float],
    ) -> Situation:
        """Stage 4: partition, target fire, monitor role and life-cycle; returns the :class:`Situation`.

        Own Voronoi cell among the flying alive UAVs with the safety band (FF Eqs. 6-7), the
        target fire of largest mass in the cell (Eq. 8 per fire, else the nearest), the fleet's
        staleness map, the fastest-spreading fronts and peers' perimeter maps (PM), this UAV's
        monitor role, and the mission life-cycle (FF IV-D; an OBJECTIVE event on a change).
        ``centroid_xy``: the point the previous step steered to.
        """
        cfg = self.cfg
        t1 = bundle.stamp_s
        peer_states = self.link.alive_states()
        flying = {
            j: (p.x_m, p.y_m)
            for j, p in sorted(peer_states.items())
            if p.objective not in (Objective.GROUNDED, Objective.LANDED)
        }
        pos = np.array(s[:2])
        others = np.array(list(flying.values())).reshape(-1, 2)
        band = cfg.mission.safety_radius_m if cfg.mission.use_safety_band else None
        cell = own_cell_on_grid(self.grid, pos, others, band)
        if vehicle == VehicleStatus.AIRBORNE:
            self.search.observe(t1, np.vstack([pos[None, :], others]))
        target_fire = -1
        if active:
            in_cell = np.flatnonzero(cell)  # Eq. 8 over the own cell: the density there only
            masses = [
                float(gaussian_density_at(self.grid, [(f.x_m, f.y_m)], [f.extent_m], in_cell).sum())
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
            t1, cfg.uav_id, s, self.grid, cell, flying, active,
            cells=bundle.cells if vehicle == VehicleStatus.AIRBORNE else None,
            cell_size_m=float(bundle.cell_size_m),
            peer_roles={j: (int(p.objective), int(p.target_fire_id)) for j, p in peer_states.items()},
            own_published_xy=self._pub_xy,
            own_objective=int(self.mission.objective),
            own_target_fire_id=int(self.mission.target_fire_id),
        )  # fmt: skip
        self._merge_perimeters(perimeters, flying, t1)
        monitor_fire = self.monitor_assigner(pview) if self.monitor_assigner is not None else -1
        prev_obj = self.mission.objective
        aim = self._aim(active)
        release, front_aim = None, None
        if self.front is not None:
            speed = max(cfg.limits.v_stall_mps, float(self.last_command[0]))
            aim, release, front_aim = self.raster.target(bundle, s, aim, cell, speed, peer_states)
        all_out = self.fires.all_out()
        dec = self.mission.step(
            MissionView(
                t_s=t1,
                vehicle=vehicle,
                water_kg=float(bundle.water_kg),
                pos_xy=(float(s[0]), float(s[1])),
                fires=aim,
                all_out=all_out,
                peer_objectives={j: p.objective for j, p in peer_states.items()},
                over_lake=over_lake,
                centroid_xy=centroid_xy,
                target_fire_id=target_fire,
                monitor_fire_id=monitor_fire,
                release=release,
                # read only once the fires are out (a min over the area's grid, 1.4 M points on a 6 km map)
                swept_since_s=self.search.swept_since_s() if all_out else math.inf,
            )
        )
        if dec.request == PayloadAction.DROP and dec.target_fire_id >= 0:
            self.fires.note_drop(dec.target_fire_id, (float(s[0]), float(s[1])), t1, cfg.drop_radius_m)
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
        return Situation(dec, aim, lake, pview, cell, front_aim)

    def _compose_output(
        self,
        bundle: Bundle,
        sit: Situation,
        s: np.ndarray,
        cmd: tuple[float, float, float],
        events: list[AgentEvent],
        want_markers: bool,
    ) -> StepOutput:
        """Stage 6: everything the node publishes for this step, and the bookkeeping for the next.

        The command [m/s, m/s, rad/s], the payload request of the decision (DROP on the target
        fire or REFILL), the UavState fields (estimate, covariance, objective, peers, counters),
        the fire picture with known fronts, the events, the markers when ``want_markers``, and a
        monitor's PerimeterMap every ``perimeter_every_steps`` steps.
        """
        cfg, dec = self.cfg, sit.decision
        requests: list[tuple[int, int]] = []
        if dec.request is not None:
            requests.append(
                (int(dec.request), dec.target_fire_id if dec.request == PayloadAction.DROP else -1)
            )
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
        self._last_vehicle = int(bundle.vehicle)
        self.last_step = bundle.step
        self._seq += 1
        self._pub_xy = (float(s[0]), float(s[1]))
        state = OwnState(
            uav_id=cfg.uav_id,
            sequence=self._seq,
            step=bundle.step,
            stamp_s=bundle.stamp_s,
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
        return StepOutput(
            step=bundle.step,
            stamp_s=bundle.stamp_s,
            command=cmd,
            payload_requests=tuple(requests),
            state=state,
            fires=self._with_fronts(self.fires.entries()),
            fires_sequence=self._seq,
            events=tuple(events),
            markers=self._markers(dec, sit.cell) if want_markers else None,
            direct=dec.direct,
            perimeter=perimeter,
            front=self.raster.message(bundle),
        )

    def _guide(self, sit: Situation, vehicle: VehicleStatus, s: np.ndarray) -> Guidance:
        """Stage 5, FF Eqs. 8-15: the command for the objective (:class:`.guidance.Guide`)."""
        return self.guide.run(sit, vehicle, s, self.last_step)

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
                pass  # malformed: ignored (perimeter_lost counts the injected loss only)

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
        if not self.lakes:
            return None
        return min(self.lakes, key=lambda lk: math.hypot(lk.x_m - pos[0], lk.y_m - pos[1]))

    def _markers(self, dec: Decision, cell: np.ndarray) -> MarkersData:
        ny, nx = self.grid.shape
        m = cell.reshape(ny, nx)
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
