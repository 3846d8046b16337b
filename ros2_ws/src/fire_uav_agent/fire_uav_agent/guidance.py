"""Stage 5 of the agent's control step: the command for the objective (FF Eqs. 8-15), and the
types the stages around it hand over (:class:`Situation` in, :class:`Guidance` out). ROS-free.

Positions are [m; map frame], yaw [rad], speeds [m/s], times [s of sim time].
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import Objective, VehicleStatus
from fire_uav_common.drop_coverage import L_PER_M2_PER_CL, peak_coverage_lpm2
from fire_uav_common.terrain import Lake

from .agent_config import AgentConfig
from .airframe_model import (
    FinalApproach,
    FlownInput,
    descent_m,
    final_approach_course,
    inside_turn_circle,
    line_gain_per_m,
    slowdown_m,
    turn_radius_m,
)
from .coverage import Grid, control_law, density_centroid, gaussian_density, mass_centroid
from .lake_sequence import LakeSequenceConfig, LakeUser, hold_rank, lake_holder
from .mission import Decision
from .peer_link import FireEntry, PeerLink
from .planning import Planner, PlannerView
from .raster_role import RasterSuppression
from .separation import PeerAvoidance, hold_layer
from .staleness_search import StalenessSearch
from .tactics import direct_run_point, front_tangent, layer_height

__all__ = ["Guidance", "Guide", "Situation"]


@dataclass(frozen=True)
class Situation:
    """What :meth:`Agent._decide` found and :meth:`Agent._guide` acts on (one control step)."""

    decision: Decision
    aim: tuple[FireEntry, ...]  # active fires as suppression sees them (centred on known fronts)
    lake: Lake | None  # nearest lake
    view: PlannerView
    cell: np.ndarray  # the own Voronoi cell on the grid (bool per grid point, FF Eqs. 6-7)
    front_aim: tuple[float, float] | None = None  # raster: the aim point on the front (tactics)


@dataclass(frozen=True)
class Guidance:
    """What :meth:`Agent._guide` produced: the command and the point it steers to.

    ``target_xy`` None: no target this step (on the ground); the agent keeps the previous one, which
    the next step's mission life-cycle reads as the centroid (FF Eq. 13) and the UavState carries.
    """

    command: tuple[float, float, float]  # v_lin [m/s], v_z [m/s], omega_z [rad/s]
    target_xy: tuple[float, float] | None = None


class Guide:
    """Stage 5 with what it reads: the config, the grid, the planners, the raster tactic, the peer
    link (peers' states near the landing point) and the avoidance of the peers."""

    def __init__(
        self,
        cfg: AgentConfig,
        grid: Grid,
        planners: Mapping[int, Planner],
        search: StalenessSearch,
        raster: RasterSuppression,
        link: PeerLink,
        avoidance: PeerAvoidance,
        flown: FlownInput | None = None,
    ) -> None:
        self.cfg, self.grid, self.planners, self.search = cfg, grid, planners, search
        self.raster, self.link, self.avoidance = raster, link, avoidance
        self.start_xy = np.array(cfg.start_pose[:2], dtype=float)
        self.flown = flown  # the airframe's modelled flight state (its airspeed sets the turn radius)
        self.approach: FinalApproach | None = None  # a fixed-wing's lined-up landing approach
        self.on_final = False  # established on the final (_land_lined_up)
        self._resolve_vertical = True  # the vertical resolution this step (run: not while landing)
        # [m] the estimated heights above ground of the last second on the final (_land_lined_up)
        self._final_agl: deque[float] = deque(maxlen=max(1, round(1.0 / cfg.control_period_s)))
        # [m] low and slow this far beyond the lake's shore (FF IV-D b); a fixed-wing starts where it
        # can still slow from its top speed to the refill speed (airframe_model.slowdown_m): the
        # tanker, slowing at 1 m/s^2 from 75 m/s, crossed the 150 m margin and FF's lake x 10 at
        # 60-70 m/s, above the world's refill speed, and never refilled (ff_two_fires_tanker)
        self.lake_margin_m = cfg.guidance.lake_approach_margin_m
        self.lake_clear_m = 0.0  # [m] beyond the shore, a low UAV leaving the lake still holds it
        # mission.lake_sequence: stack (opt-in): one fixed-wing at a time low over the lake
        self.lake_sequenced = cfg.airframe is not None and cfg.mission.lake_sequence == "stack"
        lim, gd, veh = cfg.limits, cfg.guidance, cfg.vehicle
        # [m/s] low and slow: the speed of the lake approach (FF IV-D b) and of a pattern drop's run
        self.v_slow_mps = lim.v_stall_mps + gd.refill_speed_fraction * veh.refill_speed_margin_mps
        # [m] pattern drops (AgentConfig.pattern_drops): within this of its aim point on a raster
        # front a UAV flies its drop run low and slow (_drop_run); 0: no drop run. The agent makes
        # its raster tactic whatever the fire (it stays idle until FireCells arrive), so the run is
        # sized here from the config alone and flown only where the tactic gives an aim point on a
        # raster front (Situation.front_aim)
        self.drop_run_m = self._drop_run_m() if cfg.pattern_drops else 0.0
        # the drop run's last leg along the front (_drop_leg): the pattern's length at the run's
        # speed (drop_pattern (P1): v V / Q; 0 without a flow rate: no leg), the turn radius there
        # and the leg's length before the aim
        af0 = cfg.airframe
        load_l = veh.water_capacity_kg if af0 is None else af0.water_capacity_kg
        flow_lps = veh.drop_flow_lps if af0 is None else af0.drop_flow_lps
        self.pattern_m = self.v_slow_mps * load_l / flow_lps if flow_lps > 0 else 0.0
        if af0 is None:
            self.run_turn_m = self.v_slow_mps / max(lim.omega_max_radps, 1e-6)
        else:
            self.run_turn_m = turn_radius_m(af0, self.v_slow_mps)
        self.lead_in_m = min(self.drop_run_m, 3.0 * self.run_turn_m + raster.tactic.release_radius_m)
        # [L/m^2] the most the own pattern lays from the drop run (the lowest raster layer, the run's
        # speed; fire_uav_common.drop_coverage (P5)): a run whose pattern cannot reach the coverage
        # level of the fuel under the aim is not flown (_drop_run); how many steps skipped it, and
        # the first skip's reason (the node logs it once)
        self.run_peak_lpm2 = peak_coverage_lpm2(
            load_l, flow_lps, self.v_slow_mps, raster.tactic.layer_height_m(0)
        )
        self.run_skips = 0
        self.skip_note: str | None = None
        self.leg: FinalApproach | None = None  # the drop run's leg along the front (_drop_leg)
        # the estimated poses (x, y, yaw) of the last second: the crab angle on the leg (_crab_rad)
        self._poses: deque[tuple[float, float, float]] = deque(
            maxlen=max(2, round(1.0 / cfg.control_period_s) + 1)
        )
        # how each new leg went: lined up, or today's straight run for want of front cells near the
        # aim ("few_cells") or of room to turn onto the leg before the aim ("no_room")
        self.leg_counts = {"leg": 0, "few_cells": 0, "no_room": 0}
        # _lake_rung's configuration per lake (fixed per agent and lake: made once, not per step)
        self._lake_seq: dict[tuple[float, float, float], LakeSequenceConfig] = {}
        af = cfg.airframe
        if af is not None:
            start = (float(self.start_xy[0]), float(self.start_xy[1]))
            refill_v = self.v_slow_mps
            self.lake_margin_m = max(self.lake_margin_m, slowdown_m(af, af.v_max_mps, refill_v))
            # ... and where it can still descend from its layer to the scoop height at its descent
            # limit (airframe_model.descent_m): the J3Cub (1.4 m/s) reached the shore from the 37 m
            # layer 150 m out at about 27 m, above the world's 15 m refill height, flew over, turned
            # on its 59 m radius and tried again (ff_two_fires on jsbsim, 5 UAVs, seed 1: 5 refills
            # in 700 s, four UAVs in REFILL from 86-133 s to the end of the suppression at 697 s)
            layer = layer_height(cfg.uav_id, veh.flight_height_m, max(1, gd.ff_layers), gd.ff_layer_step_m)
            scoop_h = gd.refill_height_fraction * veh.refill_height_m
            self.lake_margin_m = max(self.lake_margin_m, descent_m(af, refill_v, layer - scoop_h))
            # one fixed-wing at a time low over the lake (lake_sequence), the others on their layers
            self.lake_clear_m = 2.0 * turn_radius_m(af, lim.v_stall_mps)
            # the height loop of Eq. 12 around the lagging flight-path angle (B&M Eq. 9.19: tau_gamma)
            # is a second-order loop, damped 0.7 at K_z = 1 / (2 tau_gamma); FF's K_z = 5 1/s rings
            # +-0.7 m around the 0.5 m approach height and never passes below the touchdown height.
            # The heading loop of Eq. 11 around the lagging bank (B&M Eq. 9.20: tau_bank) likewise,
            # K_a = 1 / (2 tau_bank): with FF's K_a = 5 1/s the J3Cub (tau_bank 0.9 s) swung +-20 deg
            # about the final's course at the turn-rate limit, +-8 m across the line, and missed the
            # touch-down point: one UAV sent home 30 s after takeoff landed at 490 s after several
            # go-arounds on seeds 2 and 3, at 125-146 s on its first final with K_a = 0.56 1/s
            self.land_gains = dataclasses.replace(
                cfg.gains,
                kz=min(cfg.gains.kz, 0.5 / af.tau_gamma_s),
                ka=min(cfg.gains.ka, 0.5 / af.tau_bank_s),
            )
            r = turn_radius_m(af, lim.v_stall_mps)
            course = final_approach_course(start, cfg.area_m, float(cfg.start_pose[3]))
            # the final leg: long enough for the turn onto it (4 r), for the descent from the
            # highest layer at half the climb-rate limit (the height loop then tracks, not saturates)
            # and to slow from the top speed to the approach speed (airframe_model.slowdown_m): the
            # tanker, slowing at 1 m/s^2, captured the 893 m (4 r) final at 60-75 m/s, descended
            # too fast for its height loop (K_z = 0.25 1/s), crossed the threshold 1-4 m up and went
            # round again and again (ff_two_fires_tanker seed 2: one UAV landed 990 s after the fleet
            # agreed to land); the 1,717 m it needs to slow brings it to the threshold below 0.2 m
            top = max(
                veh.flight_height_m,
                layer_height(cfg.uav_id, veh.flight_height_m, max(1, gd.ff_layers), gd.ff_layer_step_m),
            )
            low = gd.land_height_fraction * veh.landing_height_m
            descent = 2.0 * lim.v_stall_mps * (top - low) / lim.vz_max_mps
            slow = slowdown_m(af, af.v_max_mps, lim.v_stall_mps)
            # the line's gain k (B&M Eq. 10.8) sized for the final's heading loop and speed
            # (airframe_model.line_gain_per_m) within the touch-down radius of the line: k = 1 / r held
            # a final 2.7-4.2 m beside the line when the EKF's heading was a few degrees off, and the
            # UAV went round. Beyond it k = 1 / r: with the stiffer field everywhere the capture
            # at the back of the final steepened, and two UAVs capturing neighbouring finals from
            # 50-65 m off came to 5.9 m (ff_two_fires, coordinated_turn, seed 6; docs/airframes.md)
            chi_inf = FinalApproach.approach_angle_rad
            k_line = line_gain_per_m(self.land_gains.ka, lim.v_stall_mps, chi_inf)
            length = max(gd.land_approach_radius_m, 4.0 * r, descent, slow)
            self.approach = FinalApproach(start, course, length, r, chi_inf, k_line, gd.touchdown_radius_m)

    def run(self, sit: Situation, vehicle: VehicleStatus, s: np.ndarray, last_step: int) -> Guidance:
        """Stage 5, FF Eqs. 8-15: the command (v_lin [m/s], v_z [m/s], omega_z [rad/s]) for the objective.

        SUPPRESS: centroid of the fire density in the own cell (Eq. 13) or, on an attack run,
        the target fire itself; REFILL: the lake density (Eq. 14), low and slow near the lake
        (FF IV-D b; with ``mission.lake_sequence: stack`` a fixed-wing over analytic fires only while
        it holds the lake, straight at its centre, else in the stack above it: :mod:`.lake_sequence`);
        LAND: the start-point density (Eq. 15), descending inside ``guidance.land_approach_radius_m``;
        SEARCH / MONITOR: the planner's waypoint or density. The target goes through the control
        law (Eqs. 10-12) at the objective's height above terrain. Zero on the ground before
        takeoff, after landing or a crash. ``last_step``: the step the agent last ran (the peers'
        states are of the step before).
        """
        cfg, lim, gd, veh = self.cfg, self.cfg.limits, self.cfg.guidance, self.cfg.vehicle
        dec, active, lake, pview, cell = sit.decision, sit.aim, sit.lake, sit.view, sit.cell
        obj = dec.objective
        # the vertical resolution (separation.vertical_sense) not while landing: hold_layer keeps its layers
        self._resolve_vertical = obj != Objective.LAND
        if vehicle in (VehicleStatus.CRASHED, VehicleStatus.LANDED) or obj == Objective.LANDED:
            return Guidance((0.0, 0.0, 0.0))
        if obj == Objective.GROUNDED:
            return Guidance((0.0, 0.0, 0.0))
        if vehicle == VehicleStatus.ON_GROUND:  # takeoff slot reached: v >= v_stall and v_z > 0
            return Guidance((lim.v_stall_mps, min(lim.vz_max_mps, cfg.gains.vz_cmd_max_mps), 0.0))
        cruise = veh.flight_height_m
        if self.raster.front is None:  # FF mode: altitude layers (GuidanceConfig.ff_layers)
            cruise = layer_height(cfg.uav_id, veh.flight_height_m, max(1, gd.ff_layers), gd.ff_layer_step_m)
        height = cruise
        v_cap = None
        pos = (float(s[0]), float(s[1]))
        target: tuple[float, float]
        steer: tuple[float, float] | None = None  # where the control law steers, if not the target
        on_leg = False
        if obj == Objective.SUPPRESS and active:
            tgt = next((f for f in active if f.fire_id == dec.target_fire_id), active[0])
            if sit.front_aim is not None:  # raster: the aim point on the front (tactics)
                target = sit.front_aim
                run = self._drop_run(pos, target)
                if run is not None:
                    height, v_cap = run
                    if cfg.drop_leg:  # off by default (AgentConfig.drop_leg)
                        steer = self._drop_leg(s, target, sit.view.t_s)
                        on_leg = True
            elif dec.direct:
                target = (tgt.x_m, tgt.y_m)
                if self.raster.front is not None:
                    # raster with no front left (contained): a direct run sent every stalled UAV
                    # to the one track centre (two collided there); each flies at its own point
                    # of a circle around it instead (tactics.direct_run_point)
                    target = direct_run_point(target, cfg.uav_id, self.raster.tactic)
            else:
                target = self._density_centroid_of(
                    [(f.x_m, f.y_m) for f in active], [f.extent_m for f in active], (tgt.x_m, tgt.y_m), cell
                )  # Eq. 13
        elif obj == Objective.REFILL and lake is not None:
            lake_xy = (lake.x_m, lake.y_m)
            if dec.direct:
                target = lake_xy
            else:
                target = self._density_centroid_of(
                    [lake_xy], [cfg.mission.sigma_water_m], lake_xy, cell
                )  # Eq. 14
            if math.hypot(pos[0] - lake.x_m, pos[1] - lake.y_m) < lake.diameter_m / 2 + self.lake_margin_m:
                height = gd.refill_height_fraction * veh.refill_height_m  # low ...
                v_cap = self.v_slow_mps  # ... and slow
                sequenced = self.raster.front is None and self.lake_sequenced
                rung = self._lake_rung(s, lake) if sequenced else None
                if rung is not None:
                    # a fixed-wing waits in the stack above the lake until it holds it (lake_sequence)
                    height = rung
                elif sequenced:
                    # the holder flies straight at the lake's centre and on across it (_within_turn
                    # keeps it straight once the centre is inside its turn circles): a run through
                    # the centre is the lake's longest, at least the scoop run (usable_lakes). Not the
                    # centroid of Eq. 14 in its own Voronoi cell: a peer waiting in the stack above
                    # the lake holds the lake in its cell, and the holder flew along the cell's edge
                    target = lake_xy
                elif self.raster.front is not None and self._onto_low_peer(s):
                    # not down onto a peer at the scoop height below it: keep a layer step above
                    height = max(
                        height + self.raster.tactic.layer_step_m,
                        self.raster.tactic.layer_height_m(cfg.uav_id),
                    )
                    v_cap = None
        elif obj == Objective.LAND and self.approach is not None and self._home_in_area():
            return self._land_lined_up(s, cruise, last_step)
        elif obj == Objective.LAND:
            start = (float(self.start_xy[0]), float(self.start_xy[1]))
            d = math.hypot(pos[0] - start[0], pos[1] - start[1])
            r = gd.land_approach_radius_m
            x0, x1, y0, y1 = cfg.area_m
            home_in_area = x0 <= start[0] <= x1 and y0 <= start[1] <= y1
            if d < r or not home_in_area:
                target = start  # final approach: straight at the own takeoff point (FF IV-D d)
            else:
                dens = gaussian_density(self.grid, [start], [cfg.mission.sigma_landing_m])  # Eq. 15
                target = self._centroid_of(dens, start, cell)
            if d < r:
                v_cap = lim.v_stall_mps
                low = gd.land_height_fraction * veh.landing_height_m
                flat = gd.land_flat_fraction
                height = low + (cruise - low) * max(0.0, (d - flat * r) / ((1.0 - flat) * r))
                below = [
                    (p.x_m, p.y_m, p.z_m)
                    for j, p in self.link.alive_states().items()
                    if j < cfg.uav_id and p.objective not in (Objective.GROUNDED, Objective.LANDED)
                ]
                if hold_layer((pos[0], pos[1], float(s[2])), below, cfg.separation):
                    height = max(height, cruise)  # keep the layer over a landing right-of-way peer
                agl = float(s[2] - cfg.terrain.elevation(pos[0], pos[1]))
                if agl < gd.touchdown_agl_fraction * veh.landing_height_m and d <= gd.touchdown_radius_m:
                    return Guidance((0.0, -gd.touchdown_sink_mps, 0.0))  # below stall speed: it lands
                bearing = math.atan2(start[1] - pos[1], start[0] - pos[0])
                if d < gd.go_around_radius_m and abs(math.remainder(bearing - float(s[3]), math.tau)) > (
                    gd.go_around_heading_rad
                ):
                    # not lined up this close: a unicycle at v_stall circles a point inside its turning
                    # circle for ever, so fly straight out and come back lined up
                    v, vz, _ = control_law(s, np.array(start), height, cfg.terrain, lim, cfg.gains, v_cap)
                    cmd = (v, vz, 0.0)
                    if cfg.avoidance:
                        cmd = self._separate(s, cmd, start, last_step, straight=True)
                    return Guidance(cmd, start)
        else:  # SEARCH, MONITOR, or SUPPRESS/REFILL without fire/lake
            planner = self.planners.get(int(obj)) or self.search
            plan = planner.plan(dataclasses.replace(pview, target_fire_id=int(dec.target_fire_id)))
            if plan is None:
                plan = self.search.plan(pview)
            assert plan is not None, "the staleness search always returns a target"
            if plan.waypoint_xy is not None:
                target = (float(plan.waypoint_xy[0]), float(plan.waypoint_xy[1]))
            else:
                target = self._centroid_of(np.asarray(plan.density, dtype=float), pos, cell)
            if plan.height_m is not None:
                height = plan.height_m
            v_cap = plan.speed_cap_mps
        if not on_leg:
            self.leg = None
        if self.raster.front is not None and obj != Objective.LAND and height == veh.flight_height_m:
            height = self.raster.tactic.layer_height_m(cfg.uav_id)
        goal = target if steer is None else steer
        if cfg.drop_leg:  # the crab angle's poses (_crab_rad): kept only for the leg
            self._poses.append((pos[0], pos[1], float(s[3])))
        cmd = control_law(s, np.array(goal), height, cfg.terrain, lim, cfg.gains, v_cap)
        if self.raster.front is None:  # analytic fires only (_within_turn)
            cmd = self._within_turn(s, cmd, goal)
        return Guidance(self._separate(s, cmd, goal, last_step) if cfg.avoidance else cmd, target)

    def _drop_run_m(self) -> float:
        """Where a pattern drop's run begins [m from the aim point]: the release radius
        (``tactics.release_now``) plus the distance the airframe needs to slow from its top speed
        to the drop speed (``airframe_model.slowdown_m``) and to descend from its layer to the
        lowest (``airframe_model.descent_m``); FF's unicycle changes both at once, so twice the
        release radius."""
        cfg = self.cfg
        tactic = self.raster.tactic
        release = tactic.release_radius_m
        af = cfg.airframe
        if af is None:
            return 2.0 * release
        v_drop = self.v_slow_mps
        drop_h = tactic.layer_height_m(cfg.uav_id) - tactic.layer_height_m(0)
        return release + max(slowdown_m(af, af.v_max_mps, v_drop), descent_m(af, v_drop, drop_h))

    def _drop_run(self, pos: tuple[float, float], aim: tuple[float, float]) -> tuple[float, float] | None:
        """The height [m above terrain] and speed cap [m/s] of a pattern drop's run, or None away from it.

        A drop laid as a ground pattern (world ``fires.drop_model: pattern``, drop_pattern (P2)-(P3))
        has its peak coverage proportional to Q / v and inversely to its spread, which grows with
        the release height: "increasing the drop height gradually widens the drop while decreasing
        the coverage levels" and "increasing airspeed increases the line length while reducing the
        coverage level" (USDA FS MTDC airtanker drop guides). From the 22 and 36 m raster layers the
        tanker's 757 L/s at 75 m/s put 0.19-0.32 L/m^2 on grass, under the 0.41 L/m^2 it needs, so
        only drops from the lowest layer put cells out (grass_running_tanker, docs/airframes.md).
        So within ``drop_run_m`` of its aim point a UAV flies its run at the lowest raster layer
        (``tactics.TacticConfig.layer_height_m`` of id 0: the floor the layers were sized for) and
        at the speed of the lake approach (FF IV-D b's "low and slow"). Our addition; FF's drop is
        a disc at any height.

        No run (None) where even the run's pattern cannot put the fuel under the aim point out: its
        peak coverage (``run_peak_lpm2``, drop_coverage (P5)) under the coverage level that fuel
        needs (``AgentConfig.coverage_levels``, the drop guides' table). Such a run would only bring
        the fleet down to one layer for nothing: the small UAV's 10 L at 5 L/s peaks at
        0.02 L/m^2 from 8 m, a twentieth of grass's 0.41 L/m^2, and its fleet on the run's single
        layer passed under FF's 10 m in 4 of 6 missions (grass_running, docs/suppression.md). The
        UAV then keeps its own layer and speed (and still releases over the front)."""
        if self.drop_run_m <= 0.0 or math.hypot(pos[0] - aim[0], pos[1] - aim[1]) >= self.drop_run_m:
            return None
        levels = self.cfg.coverage_levels
        if levels is not None:
            need_cl = levels.at(aim[0], aim[1])
            if self.run_peak_lpm2 < need_cl * L_PER_M2_PER_CL:
                self.run_skips += 1
                if self.skip_note is None:
                    h = self.raster.tactic.layer_height_m(0)
                    self.skip_note = (
                        f"drop run skipped (kept the own layer and speed): the own pattern from the "
                        f"{h:.0f} m layer at {self.v_slow_mps:.1f} m/s peaks at {self.run_peak_lpm2:.3f} L/m2 "
                        f"(coverage level {self.run_peak_lpm2 / L_PER_M2_PER_CL:.2f}), under the level "
                        f"{need_cl:g} the fuel at ({aim[0]:.0f}, {aim[1]:.0f}) m needs"
                    )
                return None
        return self.raster.tactic.layer_height_m(0), self.v_slow_mps

    def _drop_leg(self, s: np.ndarray, aim: tuple[float, float], t_s: float) -> tuple[float, float]:
        """Where a pattern drop's run steers [m]: onto a leg along the front through the aim point, so
        that the pattern (a line ``pattern_m`` long from the release on, along the track) is laid
        along the fire's edge, not across it. Our addition; FF's drop is a disc. Only with
        ``AgentConfig.drop_leg`` (off by default: on grass_running_tanker it put fewer cells out
        than the straight run, docs/airframes.md).

        Fire services lay retardant and water lines along the edge: a direct-attack drop goes next to
        the fire's edge, a parallel one along and within about 30 m of the perimeter, each line
        started from an anchor point and extended by the next (NWCG Interagency Aerial Supervision
        Guide, PMS 505, ch. 8, as taught in its aerial strategy and tactics unit; the airtanker
        glossary's "anchor point" and "extend"); the lead plane or bird dog sets each run's
        direction, and the tanker flies a circuit onto it as onto a runway (downwind, base, final).
        Here the agent sets it from its OWN front picture (never the world's): the leg's direction
        is the principal axis of the front cells it believes burning within a pattern length of the
        aim (:func:`.tactics.front_tangent`), flown in the sense that needs the smaller turn from the
        UAV's heading via the leg's entry. The leg is flown as the lined-up landing's final
        (:class:`.airframe_model.FinalApproach`, Beard & McLain's straight-line vector field, Eq.
        10.8) with the aim point as its threshold, ``lead_in_m`` long (three turn radii at the run's
        speed plus the release radius, at most ``drop_run_m``): to the entry point until captured,
        a full-rate turn toward the course there if heading the wrong way, then along the line. The
        release is the agent's rule as before (:func:`.tactics.release_now`: on the peak of the
        burning cells under it), so the pattern starts where the leg meets the burning edge and
        runs on along it. The leg is kept while the aim stays within half a pattern of its aim point
        (a farther aim: a new leg, in the same sense), and dropped half a pattern past it with no
        release (a new leg next step).

        Today's straight run at the aim (returned unchanged) where there is no line to follow: fewer
        than 5 front cells near the aim, or no clear direction among them ("few_cells"); or where a
        UAV without a leg is already within ``lead_in_m`` of the aim and not captured by the final,
        without the room to turn onto it on its turn radius before the aim ("no_room"). ``t_s``: the
        step's time, at which the tactic read the picture (the same cached front)."""
        front = self.raster.front
        if front is None:
            return aim
        pos = (float(s[0]), float(s[1]))
        pose = (pos[0], pos[1], float(s[3]))
        r = self.run_turn_m
        leg = self.leg
        fresh = leg is None
        if (
            leg is None
            or math.hypot(aim[0] - leg.threshold_xy[0], aim[1] - leg.threshold_xy[1]) > 0.5 * self.pattern_m
        ):
            t = front_tangent(front.front(t_s), aim, self.pattern_m)
            if t is None:
                self.leg = None
                self.leg_counts["few_cells"] += 1
                return aim
            leg = self._new_leg(aim, t, pose, None if leg is None else leg.course_rad)
        along, _ = leg.frame(pos)
        if along > 0.5 * self.pattern_m:  # half a pattern past the aim, no release: a new leg
            self.leg = None
            return aim
        captured = leg.captured(pose)
        if fresh:
            if not captured and math.hypot(pos[0] - aim[0], pos[1] - aim[1]) < self.lead_in_m:
                self.leg_counts["no_room"] += 1
                return aim  # no leg yet: asked again next step
            self.leg_counts["leg"] += 1
        self.leg = leg
        if captured:
            psi = leg.line_course(pos) - self._crab_rad()  # the heading that flies that course
            return (pos[0] + 4.0 * r * math.cos(psi), pos[1] + 4.0 * r * math.sin(psi))
        entry = leg.entry_xy
        wrong_way = abs(math.remainder(pose[2] - leg.course_rad, math.tau)) > 0.5 * math.pi
        if math.hypot(pos[0] - entry[0], pos[1] - entry[1]) < 2.0 * r and wrong_way:
            # at the entry heading the wrong way: a full-rate turn toward the course (_land_lined_up)
            side = leg.turn_side(pose)
            return (
                pos[0] + r * math.cos(pose[2] + side * 0.5 * math.pi),
                pos[1] + r * math.sin(pose[2] + side * 0.5 * math.pi),
            )
        return entry

    def _crab_rad(self) -> float:
        """The crab angle [rad], course over the ground less heading, over the last second of estimated
        poses (0 before a second of them, or when the UAV moved less than 1 m). B&M's vector field
        gives a course; the control law steers the heading, and the world drifts a fixed-wing with
        the wind: in grass_running_tanker's 3 m/s at the run's 49.8 m/s a crosswind is a 3.5 deg
        crab, which the field (k = 1 / r, r = 253 m) would hold off the line by about 22 m, more
        than the pattern's half width (sigma 6 m from 8 m up). Clipped to +-30 deg."""
        if len(self._poses) < (self._poses.maxlen or 0):
            return 0.0
        x0, y0, _ = self._poses[0]
        x1, y1, _ = self._poses[-1]
        if math.hypot(x1 - x0, y1 - y0) < 1.0:
            return 0.0
        mean_yaw = math.atan2(
            sum(math.sin(p[2]) for p in self._poses), sum(math.cos(p[2]) for p in self._poses)
        )
        crab = math.remainder(math.atan2(y1 - y0, x1 - x0) - mean_yaw, math.tau)
        return max(-math.radians(30.0), min(math.radians(30.0), crab))

    def _new_leg(
        self,
        aim: tuple[float, float],
        t: tuple[float, float],
        pose: tuple[float, float, float],
        prev_rad: float | None,
    ) -> FinalApproach:
        """The leg along the front direction ``t`` (unit, either sense) through ``aim``, in the sense of
        the previous leg's course ``prev_rad`` (None: the sense that needs the smaller turn from the
        heading to the leg's entry point, then onto the leg)."""
        r = self.run_turn_m

        def leg_of(course: float) -> FinalApproach:
            return FinalApproach(aim, course, self.lead_in_m, r)

        def turn(leg: FinalApproach) -> float:
            ex, ey = leg.entry_xy
            if math.hypot(ex - pose[0], ey - pose[1]) < r:
                return abs(math.remainder(leg.course_rad - pose[2], math.tau))
            b = math.atan2(ey - pose[1], ex - pose[0])
            return abs(math.remainder(b - pose[2], math.tau)) + abs(
                math.remainder(leg.course_rad - b, math.tau)
            )

        course = math.atan2(t[1], t[0])
        if prev_rad is not None:
            same = abs(math.remainder(course - prev_rad, math.tau)) <= 0.5 * math.pi
            return leg_of(course if same else course + math.pi)
        return min((leg_of(course), leg_of(course + math.pi)), key=turn)

    def _lake_rung(self, s: np.ndarray, lake: Lake) -> float | None:
        """None if this fixed-wing holds the lake (FF mode; :func:`.lake_sequence.lake_holder`): it
        descends to scoop; else its rung [m above terrain] in the stack above the lake, the lowest
        FF layer (:func:`.tactics.layer_height`) plus a layer step per rank. From its own estimate
        and the peers' last states (the step's before); landing, landed and grounded peers are
        left out. A UAV is low below the lowest rung less a quarter step (3.5 m: above the height
        tracking error, ``tactics.TRACKING_ERROR_M``)."""
        cfg, gd = self.cfg, self.cfg.guidance
        terrain = cfg.terrain
        step = gd.ff_layer_step_m
        bottom = cfg.vehicle.flight_height_m - step * (max(1, gd.ff_layers) - 1) / 2.0
        key = (lake.x_m, lake.y_m, lake.diameter_m)
        seq = self._lake_seq.get(key)
        if seq is None:
            r_lake = lake.diameter_m / 2
            seq = self._lake_seq[key] = LakeSequenceConfig(
                radius_m=r_lake + self.lake_margin_m,
                clear_radius_m=r_lake + self.lake_clear_m,
                low_agl_m=bottom - 0.25 * step,
            )
        x, y = float(s[0]), float(s[1])
        users = [LakeUser(cfg.uav_id, x, y, float(s[2] - terrain.elevation(x, y)), True)]
        users += [
            LakeUser(
                j,
                p.x_m,
                p.y_m,
                float(p.z_m - terrain.elevation(p.x_m, p.y_m)),
                p.objective == Objective.REFILL,
            )
            for j, p in self.link.alive_states().items()
            if p.objective not in (Objective.GROUNDED, Objective.LANDED, Objective.LAND)
        ]
        lake_xy = (lake.x_m, lake.y_m)
        if lake_holder(users, lake_xy, seq) == cfg.uav_id:
            return None
        return bottom + step * hold_rank(cfg.uav_id, users, lake_xy, seq)

    def _onto_low_peer(self, s: np.ndarray) -> bool:
        """Whether a refilling UAV above the scoop height would descend onto a peer near it that is
        low already (raster fires; our addition, FF IV-D b says only "low and slow").

        Over a raster fire the layers (8 / 22 / 36 m) keep UAVs apart, but near the lake every
        refilling UAV descends to the 7.5 m scoop height: two UAVs that dropped together flew to
        the lake side by side on the 8 and 22 m layers, and UAV 1 descended onto UAV 0 (grass_running,
        6 UAVs, head, seed 1, 868.0 s: 5.66 m). Scooper crews hold above the water while another
        aircraft is on the scoop run (USDA Forest Service, Amphibious Water Scooper Aircraft
        Operations Plan, 2016), so this UAV holds a layer step (the avoider's vertical band plus
        twice the height tracking error, :func:`.tactics.raster_layers`) above the scoop height while
        any peer below half a step above it is within ``separation.radius_m`` horizontally and
        below it (:func:`.separation.hold_layer`, the landing's rule). Peers' states are the step's
        before (0.1 s old)."""
        cfg, gd, veh = self.cfg, self.cfg.guidance, self.cfg.vehicle
        low_below_m = gd.refill_height_fraction * veh.refill_height_m + 0.5 * self.raster.tactic.layer_step_m
        if float(s[2] - cfg.terrain.elevation(float(s[0]), float(s[1]))) < low_below_m:
            return False  # low already: on its scoop run
        under = [
            (p.x_m, p.y_m, p.z_m)
            for p in self.link.alive_states().values()
            if p.objective not in (Objective.GROUNDED, Objective.LANDED)
            and float(p.z_m - cfg.terrain.elevation(p.x_m, p.y_m)) < low_below_m
        ]
        return hold_layer((float(s[0]), float(s[1]), float(s[2])), under, cfg.separation)

    def _home_in_area(self) -> bool:
        x0, x1, y0, y1 = self.cfg.area_m
        return bool(x0 <= self.start_xy[0] <= x1 and y0 <= self.start_xy[1] <= y1)

    def _within_turn(
        self, s: np.ndarray, cmd: tuple[float, float, float], target: tuple[float, float]
    ) -> tuple[float, float, float]:
        """A fixed-wing does not turn toward a point inside its turn circles (it would circle it for
        ever): it flies straight until the point is outside them, then turns (a Dubins path's
        straight-then-turn). The radius is v^2 / (g tan phi_max) at the faster of the commanded and
        the modelled airspeed. Unchanged without an airframe. Not applied over a raster fire: the
        tactic's aim point on the front moves with the UAV and stayed inside its turn circle, so it
        flew straight on (grass_running, 3 UAVs, seed 1: no drop in 150 s, against 4 without the
        rule)."""
        af = self.cfg.airframe
        if af is None:
            return cmd
        v = max(cmd[0], self.flown.state.airspeed_mps if self.flown is not None else 0.0)
        if inside_turn_circle((float(s[0]), float(s[1]), float(s[3])), target, turn_radius_m(af, v)):
            return (cmd[0], cmd[1], 0.0)
        return cmd

    def _land_lined_up(self, s: np.ndarray, cruise: float, last_step: int) -> Guidance:
        """LAND on a fixed-wing: the final leg lined up with the takeoff point
        (:class:`.airframe_model.FinalApproach`), at the lowest commanded speed, descending along it
        as FF IV-D d's approach does by distance (``guidance.land_*``), touching down at the point."""
        cfg, lim, gd, veh = self.cfg, self.cfg.limits, self.cfg.guidance, self.cfg.vehicle
        ap = self.approach
        assert ap is not None
        pos = (float(s[0]), float(s[1]))
        pose = (pos[0], pos[1], float(s[3]))
        start = ap.threshold_xy
        r = ap.turn_radius_m
        below = [
            (p.x_m, p.y_m, p.z_m)
            for j, p in self.link.alive_states().items()
            if j < cfg.uav_id and p.objective not in (Objective.GROUNDED, Objective.LANDED)
        ]
        low = gd.land_height_fraction * veh.landing_height_m
        flat = gd.land_flat_fraction
        length = ap.length_m
        agl = float(s[2] - cfg.terrain.elevation(pos[0], pos[1]))
        captured = ap.captured(pose)
        if captured and not self.on_final:
            # established only at or below the glide path, or above it by no more than the spare
            # descent (half the limit less the path's) brings it down before the flat: a UAV told
            # to land while inside the capture zone 300-600 m out on its layer took the final there,
            # crossed the threshold 4-21 m up and went round, 110 s a circuit (ff_two_fires on
            # jsbsim, seeds 1 and 2); above the path it flies to the entry instead
            dist = max(-ap.frame(pos)[0], 0.0)
            path_rate = (cruise - low) / ((1.0 - flat) * length)  # [m/m] the path's descent
            spare = max(0.0, 0.5 * lim.vz_max_mps / lim.v_stall_mps - path_rate)
            above = agl - _glide_height(dist, cruise, low, flat, length)
            self.on_final = above <= max(2.0, spare * max(0.0, dist - flat * length))
            self._poses.clear()  # the crab angle of the final is measured on the final (_crab_rad)
        if not captured:
            self.on_final = False
            self._final_agl.clear()
        if self.on_final:
            along, _ = ap.frame(pos)
            dist = max(-along, 0.0)
            height = _glide_height(dist, cruise, low, flat, length)
            if hold_layer((pos[0], pos[1], float(s[2])), below, cfg.separation):
                height = max(height, cruise)  # keep the layer over a landing right-of-way peer
            self._final_agl.append(agl)
            # the height decides on the mean estimate of the last second: the EKF's height is
            # +-0.7 m (1 sd) about a J3Cub flying level at 0.5 m, over 0.8 m on one of the two or
            # three steps in the touch-down disc, and one UAV went round twice on the line at
            # 0.3-0.5 m (ff_two_fires on jsbsim, seed 1; the world lands it below 1 m)
            settled = len(self._final_agl) == self._final_agl.maxlen and (
                sum(self._final_agl) / len(self._final_agl) < gd.touchdown_agl_fraction * veh.landing_height_m
            )
            step_m = lim.v_stall_mps * cfg.control_period_s  # the final is flown at the lowest speed
            if (agl < gd.touchdown_agl_fraction * veh.landing_height_m or settled) and ap.at_threshold(
                pos, step_m, gd.touchdown_radius_m
            ):
                return Guidance((0.0, -gd.touchdown_sink_mps, 0.0))  # below stall speed: it lands
            # B&M's field gives a course; the control law steers the heading. The heading that flies
            # that course is the course less the crab angle (_crab_rad, as the drop leg does): here
            # mostly the EKF's heading error (no wind on FF's map), which held the UAV off the line
            # by delta / K (airframe_model.line_gain_per_m)
            self._poses.append((pos[0], pos[1], float(s[3])))
            chi = ap.line_course(pos)
            if abs(ap.frame(pos)[1]) <= r:  # near the line, not in the capture turn
                chi -= self._crab_rad()
            aim = (pos[0] + 4.0 * r * math.cos(chi), pos[1] + 4.0 * r * math.sin(chi))
            cmd = control_law(s, np.array(aim), height, cfg.terrain, lim, self.land_gains, lim.v_stall_mps)
            # on the final the height is the glide path's: heading only (separation.vertical_sense)
            if cfg.avoidance:
                cmd = self._separate(s, cmd, aim, last_step, resolve_vertical=False)
            return Guidance(cmd, start)
        entry = ap.entry_xy
        to_entry = math.hypot(pos[0] - entry[0], pos[1] - entry[1])
        height = cruise  # to the entry on the layer (hold_layer's rule holds it there anyway)
        if self.lake_sequenced and to_entry < 6.0 * r and self._entry_taken(entry, r):
            # one UAV of a layer at a time in its entry area: above every FF layer until it is free
            height = cruise + gd.ff_layer_step_m * max(1, gd.ff_layers)
        v_cap = lim.v_stall_mps if to_entry < 4.0 * r else None
        v, vz, om = control_law(s, np.array(entry), height, cfg.terrain, lim, cfg.gains, v_cap)
        if to_entry < 2.0 * r and abs(math.remainder(pose[2] - ap.course_rad, math.tau)) > 0.5 * math.pi:
            # at the entry heading the wrong way: a full-rate turn toward the course, ending captured
            cmd = (v, vz, ap.turn_side(pose) * lim.omega_max_radps)
            return Guidance(
                self._separate(s, cmd, entry, last_step, straight=True) if cfg.avoidance else cmd, entry
            )
        cmd = self._within_turn(s, (v, vz, om), entry)
        return Guidance(self._separate(s, cmd, entry, last_step) if cfg.avoidance else cmd, entry)

    def _entry_taken(self, entry_xy: tuple[float, float], r_m: float) -> bool:
        """Whether a lower-id peer of this UAV's FF layer, landing, is in this UAV's landing entry
        area: within four turn radii plus the separation radius of its entry (with
        ``mission.lake_sequence: stack`` only; our addition). The finals of one layer are 60 m apart
        and their entries abreast, and each UAV reverses onto its final on its turn radius: the
        turns overlap (docs/airframes.md, the landing entries)."""
        cfg, gd = self.cfg, self.cfg.guidance
        layers = max(1, gd.ff_layers)
        own = layer_height(cfg.uav_id, 0.0, layers, gd.ff_layer_step_m)
        reach = 4.0 * r_m + cfg.separation.radius_m
        return any(
            j < cfg.uav_id
            and p.objective == Objective.LAND
            and abs(layer_height(j, 0.0, layers, gd.ff_layer_step_m) - own) < 1e-6
            and math.hypot(p.x_m - entry_xy[0], p.y_m - entry_xy[1]) < reach
            for j, p in self.link.alive_states().items()
        )

    def _separate(
        self,
        s: np.ndarray,
        cmd: tuple[float, float, float],
        target: tuple[float, float],
        last_step: int,
        straight: bool = False,
        resolve_vertical: bool = True,
    ) -> tuple[float, float, float]:
        """Turn-rate-limited avoidance of the alive peers (:class:`.separation.PeerAvoidance`), and on
        a fixed-wing its vertical resolution (not on a landing's final: ``resolve_vertical``)."""
        agl = float(s[2] - self.cfg.terrain.elevation(float(s[0]), float(s[1])))
        vertical = resolve_vertical and self._resolve_vertical
        return self.avoidance.command(
            s, cmd, target, self.link.alive_states(), last_step, straight, agl, vertical
        )

    def _centroid_of(
        self, density: np.ndarray, fallback_xy: tuple[float, float], cell: np.ndarray
    ) -> tuple[float, float]:
        _, c = mass_centroid(self.grid.points, density, cell, self.grid.cell_area_m2)
        return (float(c[0]), float(c[1])) if c is not None else fallback_xy

    def _density_centroid_of(
        self, centres: list, sigmas: list, fallback_xy: tuple[float, float], cell: np.ndarray
    ) -> tuple[float, float]:
        """:meth:`_centroid_of` the Gaussian density of ``centres`` (Eqs. 13-14), computed in
        ``cell`` only (:func:`.coverage.density_centroid`: the same numbers)."""
        _, c = density_centroid(self.grid, centres, sigmas, cell)
        return (float(c[0]), float(c[1])) if c is not None else fallback_xy


def _glide_height(dist_m: float, cruise_m: float, low_m: float, flat: float, length_m: float) -> float:
    """The lined-up final's height [m above terrain] ``dist_m`` before the threshold: the layer
    ``cruise_m`` down to ``low_m`` linearly over the leg's first (1 - ``flat``) of ``length_m``,
    then flat (FF IV-D d's approach by distance, ``guidance.land_*``)."""
    return low_m + (cruise_m - low_m) * min(
        1.0, max(0.0, (dist_m - flat * length_m) / ((1.0 - flat) * length_m))
    )
