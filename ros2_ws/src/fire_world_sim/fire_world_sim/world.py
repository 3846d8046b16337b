"""The world without ROS: vehicles, fires, sensors and payload, one control step at a time.

``World(scenario, seed, uav_count).step(commands, payload)`` performs docs/protocol.md
"World, step k", item 1: apply the payload requests received with the previous step's
commands (at the vehicles' true positions at t_k), apply each vehicle's command (clamped),
integrate FF Eq. 4 at the physics period from t_k to t_{k+1} while sampling gyro, altimeter,
GPS and fire sensors at their own rates, advance the fires to t_{k+1}, and return one
:class:`SensorBundleRecord` per vehicle not crashed, the truth and the events. Times are integers in
nanoseconds of sim time (``stamp_ns``) so that stamps compare exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common.constants import EventType
from fire_uav_common.constants import PayloadAction as Action
from fire_uav_common.rng import stream
from fire_uav_common.scenario import Scenario, check_fleet_size

from .drop_pattern import DropPattern, Release, pattern_of
from .errors import ConfigError
from .fires import FireModel, FireTruthRecord, make_fire_model
from .measures import SuppressionMeasures
from .sensors import (
    AltimeterSample,
    CellsSample,
    FireDetectionSample,
    GpsSample,
    GyroSample,
    SensorSuite,
    samples_due,
)
from .vehicle import Command, Status, VehicleSim
from .vehicles import FfPaperModel, make_vehicle_model

__all__ = [
    "Action",
    "Command",
    "EventType",
    "MissionEventRecord",
    "SensorBundleRecord",
    "Status",
    "StepResult",
    "VehicleTruthRecord",
    "World",
]


@dataclass(frozen=True)
class MissionEventRecord:
    """One event of the step (mirrors fire_uav_msgs/MissionEvent; -1 / NaN where it names no
    vehicle, fire or place)."""

    type: EventType
    stamp_ns: int
    uav_id: int = -1
    fire_id: int = -1
    x_m: float = math.nan
    y_m: float = math.nan
    value: float = 0.0
    detail: str = ""


@dataclass
class SensorBundleRecord:
    """All samples one UAV took during step ``step`` (mirrors fire_uav_msgs/SensorBundle)."""

    uav_id: int
    step: int
    stamp_ns: int
    control_period_s: float
    gyro: list[GyroSample] = field(default_factory=list)
    altimeter: list[AltimeterSample] = field(default_factory=list)
    gps: list[GpsSample] = field(default_factory=list)
    fires: list[FireDetectionSample] = field(default_factory=list)
    cells: CellsSample | None = None
    water_kg: float = 0.0
    vehicle_status: int = 0


@dataclass(frozen=True)
class VehicleTruthRecord:
    """One vehicle's truth after the step; speeds and turn rate are the flown ones (without the
    process noise), which for FF's unicycle are its applied command."""

    uav_id: int
    status: int
    x_m: float
    y_m: float
    z_m: float
    yaw_rad: float
    v_lin_mps: float
    v_z_mps: float
    omega_z_radps: float
    water_kg: float
    commands_clamped: int
    commands_missed: int


@dataclass
class StepResult:
    step: int
    stamp_ns: int  # t_{k+1}
    bundles: dict[int, SensorBundleRecord]
    vehicles: list[VehicleTruthRecord]
    fires: list[FireTruthRecord]
    events: list[MissionEventRecord]
    complete: bool = False
    complete_reason: str = ""
    min_separation_m: float = math.inf  # closest airborne pair so far [m] (physics rate)
    collisions: int = 0  # colliding pairs so far


_FLOOR_MARGIN_M = 1e-6  # [m] far above any rounding of the terrain's elevation (1e-13 m at 1 km)
CLAMP_EVENT_PERIOD_S = 5.0  # throttle of COMMAND_CLAMPED events per vehicle [s sim]
MISS_EVENT_EVERY = 10  # a COMMAND_MISSED event at the first miss and every N-th after


class World:
    """Pure world simulation; ``seed`` seeds every stream, ``uav_count`` 0 = the scenario's.

    ``no_fleet=True``: no vehicle at all (``uav_count`` must be 0): the fire burns alone, the
    baseline that suppression is measured against (``scripts/run_mission SCENARIO --uavs 0``).
    ``measures`` (:class:`~.measures.SuppressionMeasures`) holds burned area, hit rate, water
    on burning cells and time to containment, updated every step.
    """

    def __init__(
        self, scenario: Scenario, seed: int | None = None, uav_count: int = 0, *, no_fleet: bool = False
    ) -> None:
        if uav_count < 0 or uav_count > 255:
            raise ConfigError(f"uav_count must be in 0..255, got {uav_count}")
        if no_fleet and uav_count != 0:
            raise ConfigError(f"no_fleet needs uav_count 0, got {uav_count}")
        self.scenario = scenario
        self.seed = scenario.seed if seed is None else int(seed)
        if self.seed < 0:
            raise ConfigError(f"seed must be >= 0, got {self.seed}")
        self.uav_count = 0 if no_fleet else (uav_count or scenario.uavs.count)
        if self.uav_count:
            check_fleet_size(scenario, self.uav_count)  # the scenario's outages name UAVs of this fleet
        tm = scenario.timing
        self.period_ns = round(tm.control_period_s * 1e9)
        self.substeps = tm.substeps
        self.dt_ns = self.period_ns // self.substeps
        if self.dt_ns * self.substeps != self.period_ns:
            raise ConfigError("physics_period_s must divide control_period_s in whole nanoseconds")
        self.dt_s = self.dt_ns * 1e-9
        self.control_period_s = self.period_ns * 1e-9
        self.max_steps = math.ceil(tm.max_duration_s / tm.control_period_s - 1e-9)
        self.vehicle_model = make_vehicle_model(scenario)
        # FF Eq. 4 for the whole fleet in one numpy pass per substep (the per-vehicle backend
        # interface stays for every other model)
        self._fleet_fast = type(self.vehicle_model) is FfPaperModel
        # a backend that holds its vehicle's state (jsbsim) gets one instance per vehicle
        per_vehicle = getattr(self.vehicle_model, "per_vehicle", False)
        self.vehicles = [
            VehicleSim(
                i,
                scenario.vehicle,
                pose,
                scenario.terrain,
                scenario.lakes,
                stream(self.seed, "process_noise", i),
                make_vehicle_model(scenario) if per_vehicle else self.vehicle_model,
            )
            for i, pose in enumerate(scenario.uav_start_poses(self.uav_count))
        ]
        self.sensors = [SensorSuite(scenario.sensors, self.seed, i) for i in range(self.uav_count)]
        self.fires: FireModel = make_fire_model(scenario.fires, scenario.terrain, scenario.lakes)
        self.step_index = 0
        self._last_clamp_event_ns = [-(10**18)] * self.uav_count
        self.complete = False
        self.complete_reason = ""
        self.min_separation_m = math.inf  # closest 3-D approach of two airborne vehicles so far [m]
        self.collisions = 0  # colliding pairs so far
        self._pairs: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # triu_indices(n, 1) by n
        self.measures = SuppressionMeasures()
        self._pattern_drops = scenario.fires.drop_model == "pattern"

    # --- queries -----------------------------------------------------------------------------
    @property
    def t_ns(self) -> int:
        """Sim time t_k at the start of the next step [ns]."""
        return self.step_index * self.period_ns

    def stamp_ns(self, step: int) -> int:
        """Stamp of bundle ``step``: t_{step+1} [ns]."""
        return (step + 1) * self.period_ns

    def awaited_uavs(self) -> list[int]:
        """Agents the lockstep waits for: vehicle not crashed and agent not silent past the timeout."""
        return [v.uav_id for v in self.vehicles if v.status != Status.CRASHED and v.responsive]

    def live_uavs(self) -> list[int]:
        """Vehicles that still receive bundles (not crashed)."""
        return [v.uav_id for v in self.vehicles if v.status != Status.CRASHED]

    # --- the step ----------------------------------------------------------------------------
    def step(
        self, commands: dict[int, Command | None], payload: dict[int, list[int]] | None = None
    ) -> StepResult:
        """Advance one control step k. ``commands[i]``: UAV i's command stamped t_k (None/absent =
        missed); ``payload[i]``: ``Action`` values stamped t_k, applied first at the true positions."""
        k = self.step_index
        t0_ns = k * self.period_ns
        t0_s = t0_ns * 1e-9
        events: list[MissionEventRecord] = []
        # 1. payload requests stamped t_k (sent with the commands answering bundle k-1)
        for uid, actions in sorted((payload or {}).items()):
            if 0 <= uid < self.uav_count:
                for a in actions:
                    events += self._apply_payload(uid, int(a), t0_ns)
        # 2. commands (step 0 answers no bundle: a missing command there is not a miss)
        for v in self.vehicles:
            was = v.status
            cmd = commands.get(v.uav_id)
            if cmd is None and k == 0:
                continue
            out = v.accept_command(cmd, self.control_period_s)
            events += self._command_events(v, was, out, t0_ns)
        bundles = {
            v.uav_id: SensorBundleRecord(v.uav_id, k, self.stamp_ns(k), self.control_period_s)
            for v in self.vehicles
            if v.status != Status.CRASHED
        }
        # 3. physics substeps + sensor sampling
        wind = self.wind_mps(t0_s)
        noise = self._fleet_noise() if self._fleet_fast else None
        for j in range(self.substeps):
            prev_ns = t0_ns + j * self.dt_ns
            now_ns = prev_ns + self.dt_ns
            if noise is not None:
                self._fleet_substep(noise[:, j, :])
            due = self._due(prev_ns, now_ns)
            for v in self.vehicles:
                if v.status == Status.CRASHED:
                    continue
                if noise is None:
                    v.substep(self.dt_s, wind)
                taken = v.refill_tick(self.dt_s)
                if taken > 0:
                    events.append(
                        MissionEventRecord(
                            EventType.REFILL,
                            now_ns,
                            v.uav_id,
                            -1,
                            v.x_m,
                            v.y_m,
                            taken,
                            "tank full"
                            if v.water_kg >= v.spec.water_capacity_kg - 1e-6
                            else "left the lake part-filled",
                        )
                    )
                self._sample(v, bundles[v.uav_id], now_ns, due)
            events += self._collisions(now_ns)
        # 4. fires
        t1_ns = t0_ns + self.period_ns
        for fid, what in self.fires.step(t0_s, self.control_period_s):
            fires = self.fires.truth()
            f = fires[fid]
            et = EventType.IGNITION if what == "ignition" else EventType.EXTINGUISHED
            events.append(MissionEventRecord(et, t1_ns, -1, fid, f.x_m, f.y_m, 0.0, what))
        # 5. fire sensor (rate-limited, against the fire state at t_{k+1})
        spec = self.scenario.sensors.fire
        fire_due = [  # the substeps' ends at which the fire sensor samples: one grid for the fleet
            t0_ns + (j + 1) * self.dt_ns
            for j in range(self.substeps)
            if samples_due(t0_ns + j * self.dt_ns, t0_ns + (j + 1) * self.dt_ns, spec.rate_hz)
        ]
        for v in self.vehicles:
            if v.uav_id not in bundles:
                continue  # crashed before this step: no bundle
            b = bundles[v.uav_id]
            b.water_kg = v.water_kg
            b.vehicle_status = int(v.status)
            if v.status == Status.CRASHED:
                continue  # crashed during this step: its agent learns it from this last bundle
            for now_ns in fire_due:
                seen = self.fires.detections_near(v.x_m, v.y_m, spec.range_m)
                b.fires += self.sensors[v.uav_id].sample_fires(now_ns, v.x_m, v.y_m, seen)
            b.cells = self.fires.cells_near(v.x_m, v.y_m, spec.range_m, t1_ns)
        self.step_index += 1
        fires = self.fires.truth()
        self._update_measures(t1_ns * 1e-9, fires)
        vehicles = [self._vehicle_truth(v) for v in self.vehicles]
        if not self.complete:
            down = all(v.status in (Status.LANDED, Status.CRASHED, Status.ON_GROUND) for v in self.vehicles)
            airborne_ever = any(v.status != Status.ON_GROUND for v in self.vehicles)
            success = False
            if self.fires.all_out and down and airborne_ever:
                self.complete, self.complete_reason = True, "all fires out and every surviving vehicle landed"
                success = True
            elif self.step_index >= self.max_steps:
                self.complete = True
                self.complete_reason = f"max_duration_s reached ({self.scenario.timing.max_duration_s:g} s)"
            if self.complete:
                events.append(
                    # value 1 = success, 0 = time limit (docs/protocol.md, Events)
                    MissionEventRecord(
                        EventType.MISSION_COMPLETE,
                        t1_ns,
                        value=1.0 if success else 0.0,
                        detail=self.complete_reason,
                    )
                )
        return StepResult(
            k,
            t1_ns,
            bundles,
            vehicles,
            fires,
            events,
            self.complete,
            self.complete_reason,
            self.min_separation_m,
            self.collisions,
        )

    def wind_mps(self, t_s: float) -> tuple[float, float]:
        """The wind (east, north) [m/s] the vehicles drift with at ``t_s``: the raster fire's
        piecewise-constant wind (``fires.raster.wind``, the speed it blows toward), else calm."""
        raster = self.scenario.fires.raster
        if self.scenario.fires.model != "raster" or raster is None:
            return (0.0, 0.0)
        current = None
        for w in raster.wind:
            if w.start_s <= t_s + 1e-9:
                current = w
        if current is None:
            return (0.0, 0.0)
        a = math.radians(current.direction_deg)
        return (current.speed_mps * math.cos(a), current.speed_mps * math.sin(a))

    # --- helpers -----------------------------------------------------------------------------
    def _collisions(self, t_ns: int) -> list[MissionEventRecord]:
        """Track the closest airborne pair; crash both vehicles of every pair closer than the radius.

        Checked at every physics substep in 3-D, so that separation is measured, never assumed (a
        check per control step would miss two vehicles passing through each other between
        steps). Only airborne vehicles collide: on the ground they stand at their start poses.
        """
        air = [v for v in self.vehicles if v.status == Status.AIRBORNE]
        if len(air) < 2:
            return []
        p = np.array([(v.x_m, v.y_m, v.z_m) for v in air])
        d = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=-1))
        iu = self._pairs.get(len(air))
        if iu is None:
            iu = self._pairs[len(air)] = np.triu_indices(len(air), 1)
        pair_d = d[iu]
        self.min_separation_m = min(self.min_separation_m, float(pair_d.min()))
        radius = self.scenario.vehicle.collision_radius_m
        if radius <= 0:
            return []
        events: list[MissionEventRecord] = []
        close = pair_d < radius  # the pairs in row-major order, as the loop over them was
        hit = list(zip(iu[0][close].tolist(), iu[1][close].tolist(), strict=True)) if close.any() else []
        for a, b in hit:
            self.collisions += 1
            for me, other in ((air[a], air[b]), (air[b], air[a])):
                if me.status == Status.CRASHED:
                    continue
                me.crash(f"collision with uav {other.uav_id} ({d[a, b]:.1f} m apart)")
                events.append(
                    MissionEventRecord(
                        EventType.CRASH, t_ns, me.uav_id, -1, me.x_m, me.y_m, 0.0, me.crash_reason
                    )
                )
        return events

    def _due(self, prev_ns: int, now_ns: int) -> tuple[bool, bool, bool]:
        """Whether the gyro, altimeter and GPS sample in (prev_ns, now_ns]: one grid for the fleet."""
        s = self.scenario.sensors
        return (
            samples_due(prev_ns, now_ns, s.gyro.rate_hz),
            samples_due(prev_ns, now_ns, s.altimeter.rate_hz),
            samples_due(prev_ns, now_ns, s.gps.rate_hz),
        )

    def _fleet_noise(self) -> np.ndarray:
        """The process noise of this step for every vehicle, (n, substeps, 3): each airborne
        vehicle's block drawn from its own stream in one call, the same numbers as one
        ``normal(0, sigma, 3)`` per substep (a vehicle that crashes during the step never draws
        again, so the rows it leaves unused change nothing)."""
        model = self.vehicle_model
        assert isinstance(model, FfPaperModel)
        out = np.zeros((self.uav_count, self.substeps, 3))
        if model.sigma > 0:
            for v in self.vehicles:
                if v.status == Status.AIRBORNE:
                    out[v.uav_id] = v.rng.normal(0.0, model.sigma, (self.substeps, 3))
        return out

    def _fleet_substep(self, nu: np.ndarray) -> None:
        """One physics substep of every airborne vehicle in one numpy pass (FF Eq. 4,
        :meth:`FfPaperModel.step_fleet`), then the terrain floor; the same as
        :meth:`VehicleSim.substep` per vehicle, to the bit."""
        air = []
        for v in self.vehicles:
            if v.status == Status.AIRBORNE:
                air.append(v)
            elif v.status != Status.CRASHED:
                v.yaw_rate_radps = 0.0
        if not air:
            return
        ids = [v.uav_id for v in air]
        x, y, z, yaw, rate = FfPaperModel.step_fleet(
            np.array([v.x_m for v in air]),
            np.array([v.y_m for v in air]),
            np.array([v.z_m for v in air]),
            np.array([v.yaw_rad for v in air]),
            np.array([v.v_lin_mps for v in air]),
            np.array([v.v_z_mps for v in air]),
            np.array([v.omega_z_radps for v in air]),
            nu[ids],
            self.dt_s,
        )
        # terrain is a floor. The array elevation finds the vehicles near it; the floor itself is
        # the scalar elevation VehicleSim.substep uses (numpy's exp on an array may differ from
        # its exp on one value in the last bit, and the altimeter reads z minus that floor)
        terrain = self.scenario.terrain
        low = np.flatnonzero(z < terrain.elevation(x, y) + _FLOOR_MARGIN_M).tolist()
        zl = z.tolist()
        for i in low:
            ground = float(terrain.elevation(float(x[i]), float(y[i])))
            if zl[i] < ground:
                zl[i] = ground
        for v, xi, yi, zi, wi, ri in zip(
            air, x.tolist(), y.tolist(), zl, yaw.tolist(), rate.tolist(), strict=True
        ):
            v.x_m, v.y_m, v.z_m, v.yaw_rad, v.yaw_rate_radps = xi, yi, zi, wi, ri
            v.airspeed_mps, v.climb_mps, v.bank_rad = v.v_lin_mps, v.v_z_mps, 0.0
            v.turn_rate_radps = v.omega_z_radps

    def _sample(
        self, v: VehicleSim, b: SensorBundleRecord, now_ns: int, due: tuple[bool, bool, bool]
    ) -> None:
        suite = self.sensors[v.uav_id]
        gyro_due, alt_due, gps_due = due
        if gyro_due:
            g = suite.sample_gyro(now_ns, v.yaw_rate_radps)
            if g is not None:
                b.gyro.append(g)
        if alt_due:
            a = suite.sample_altimeter(now_ns, v.height_above_terrain_m())
            if a is not None:
                b.altimeter.append(a)
        if gps_due:
            p = suite.sample_gps(now_ns, v.x_m, v.y_m)
            if p is not None:
                b.gps.append(p)

    def _command_events(self, v: VehicleSim, was: Status, out, t_ns: int) -> list[MissionEventRecord]:
        ev = []
        uid = v.uav_id
        if out.took_off:
            ev.append(MissionEventRecord(EventType.TAKEOFF, t_ns, uid, -1, v.x_m, v.y_m, 0.0, "takeoff"))
        if out.landed:
            ev.append(MissionEventRecord(EventType.LANDED, t_ns, uid, -1, v.x_m, v.y_m, 0.0, "landed"))
        if out.crashed:
            ev.append(MissionEventRecord(EventType.CRASH, t_ns, uid, -1, v.x_m, v.y_m, 0.0, v.crash_reason))
        if out.clamped and t_ns - self._last_clamp_event_ns[uid] >= CLAMP_EVENT_PERIOD_S * 1e9:
            self._last_clamp_event_ns[uid] = t_ns
            ev.append(
                MissionEventRecord(
                    EventType.COMMAND_CLAMPED,
                    t_ns,
                    uid,
                    -1,
                    v.x_m,
                    v.y_m,
                    float(v.commands_clamped),
                    "command outside the vehicle limits",
                )
            )
        if out.missed and was != Status.CRASHED and (v.commands_missed - 1) % MISS_EVENT_EVERY == 0:
            ev.append(
                MissionEventRecord(
                    EventType.COMMAND_MISSED,
                    t_ns,
                    uid,
                    -1,
                    v.x_m,
                    v.y_m,
                    float(v.commands_missed),
                    "no valid command for this step",
                )
            )
        return ev

    def _apply_payload(self, uid: int, action: int, t_ns: int) -> list[MissionEventRecord]:
        v = self.vehicles[uid]
        if v.status == Status.CRASHED:
            return []
        if action == Action.DROP:
            kg = v.release_water()
            if v.status != Status.AIRBORNE:
                return []
            pattern = self._drop_pattern(v, kg, t_ns) if kg > 0 and self._pattern_drops else None
            if pattern is not None:
                hit = self.fires.apply_pattern(pattern)
            else:
                hit = self.fires.apply_drop(v.x_m, v.y_m, None) if kg > 0 else []
            cells = self.fires.last_drop_cells if kg > 0 else None
            burning_cells, footprint_cells = cells if cells is not None else (0, 0)
            self.measures.add_drop(kg, burning_cells, footprint_cells, hit=bool(hit))
            cell_text = f", {cells[0]} of {cells[1]} cells burning" if cells is not None else ""
            if pattern is not None:
                cell_text += _pattern_text(pattern, getattr(self.fires, "last_drop_out_cells", None))
            ev = [
                MissionEventRecord(
                    EventType.DROP,
                    t_ns,
                    uid,
                    hit[0] if hit else -1,
                    v.x_m,
                    v.y_m,
                    kg,
                    (f"hit fires {hit}" if hit else ("missed" if kg > 0 else "tank empty")) + cell_text,
                )
            ]
            truth = self.fires.truth()
            for fid in self.fires.drop_extinctions(hit):
                ev.append(
                    MissionEventRecord(
                        EventType.EXTINGUISHED, t_ns, -1, fid, truth[fid].x_m, truth[fid].y_m, 0.0, "drop"
                    )
                )
            return ev
        if action == Action.REFILL:
            v.request_refill()
        return []

    def _drop_pattern(self, v: VehicleSim, kg: float, t_ns: int) -> DropPattern:
        """The ground pattern of ``v``'s load of ``kg`` released now (``fires.drop_model: pattern``):
        from its true position, heading, speed and height above the terrain, the envelope's flow
        rate and the wind (:func:`.drop_pattern.pattern_of`). The track is the heading, plus the
        wind for a model that drifts with it (every backend but FF's unicycle)."""
        wind = self.wind_mps(t_ns * 1e-9)
        vx = v.airspeed_mps * math.cos(v.yaw_rad)
        vy = v.airspeed_mps * math.sin(v.yaw_rad)
        if not isinstance(self.vehicle_model, FfPaperModel):
            vx, vy = vx + wind[0], vy + wind[1]
        release = Release(
            x_m=v.x_m,
            y_m=v.y_m,
            heading_rad=math.atan2(vy, vx),
            ground_speed_mps=math.hypot(vx, vy),
            height_m=max(0.0, v.height_above_terrain_m()),
            volume_l=kg,  # water: 1 kg = 1 L
            flow_lps=self.scenario.vehicle.drop_flow_lps,
            wind_mps=wind,
        )
        return pattern_of(release)

    def _update_measures(self, t_s: float, fires: list) -> None:
        """Burned area (sum of the fires' areas [m^2]) and containment at ``t_s`` [s].

        Raster: containment from the model's latest cell ignition time; analytic fires do not
        spread cell by cell, so they count as contained only once all are out.
        """
        area = float(sum(f.area_m2 for f in fires if f.started))
        last = float(self.fires.last_ignition_s)
        self.measures.update(t_s, area, last, burning=not self.fires.all_out)

    @staticmethod
    def _vehicle_truth(v: VehicleSim) -> VehicleTruthRecord:
        return VehicleTruthRecord(
            v.uav_id,
            int(v.status),
            v.x_m,
            v.y_m,
            v.z_m,
            v.yaw_rad,
            v.airspeed_mps,
            v.climb_mps,
            v.turn_rate_radps,
            v.water_kg,
            v.commands_clamped,
            v.commands_missed,
        )


def _pattern_text(p: DropPattern, out_cells: int | None) -> str:
    """The DROP event's words for a pattern: its line (start -> end), spread and peak coverage,
    and how many burning cells it put out (the report draws the line from these)."""
    out = f", {out_cells} put out" if out_cells is not None else ""
    return (
        f"{out}; pattern ({p.x0_m:.1f}, {p.y0_m:.1f}) -> ({p.x1_m:.1f}, {p.y1_m:.1f}) m, "
        f"sigma {p.sigma_m:.1f} m, peak {p.peak_lpm2:.2f} L/m2"
    )
