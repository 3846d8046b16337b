"""One vehicle: limits, life-cycle and tank around a swappable flight model (``vehicles``).

State ``(x_m, y_m, z_m, yaw_rad)`` in the map frame (x east, y north, z up above the datum,
yaw ccw from +x wrapped to (-pi, pi]). Inputs ``u = (v_lin_mps, v_z_mps, omega_z_radps)``.
One physics substep of length ``dt_s`` is integrated by the vehicle model: by default FF Eq. 4
(:class:`~fire_world_sim.vehicles.FfPaperModel`)::

    x += cos(yaw) * dt * (v_lin + nu_1);  y += sin(yaw) * dt * (v_lin + nu_1)
    z += dt * (v_z + nu_2);               yaw += dt * (omega_z + nu_3)

with ``nu ~ N(0, process_noise_sigma^2 I)`` drawn per substep from the vehicle's own seeded
stream. ``v_lin_mps``, ``v_z_mps``, ``omega_z_radps`` are the applied (clamped) command; the
flown values (``airspeed_mps``, ``climb_mps``, ``bank_rad``, ``turn_rate_radps``,
``yaw_rate_radps``) are the model's, which sensors and truth read.
Life-cycle (docs/protocol.md "Commands"): ON_GROUND -> AIRBORNE on a takeoff
command (v_lin >= v_stall and v_z > 0); AIRBORNE -> LANDED when below ``landing_height_m``
above terrain and commanded v_lin < v_stall; any -> CRASHED when the agent is silent for
``command_timeout_s`` (a LANDED vehicle stays landed). Terrain is a floor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from fire_uav_common.angles import wrap_angle  # re-exported: callers import it from here
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import Vehicle as VehicleSpec
from fire_uav_common.terrain import Lake, Terrain

from .vehicles import Command, FfPaperModel, FlightState, VehicleModel

__all__ = ["Command", "Status", "StepOutcome", "VehicleSim", "wrap_angle"]


#: ``SensorBundle.VEHICLE_*`` (the one definition lives in fire_uav_common.constants)
Status = VehicleStatus


@dataclass
class StepOutcome:
    """What happened to one vehicle during one control step (the world turns it into events)."""

    took_off: bool = False
    landed: bool = False
    crashed: bool = False
    clamped: bool = False
    missed: bool = False
    refill_done_kg: float = 0.0  # > 0 when the tank became full this step


class VehicleSim:
    """One simulated fixed-wing UAV. ``rng`` is its own process-noise stream."""

    def __init__(
        self,
        uav_id: int,
        spec: VehicleSpec,
        pose: tuple[float, float, float, float],
        terrain: Terrain,
        lakes: tuple[Lake, ...],
        rng: np.random.Generator,
        model: VehicleModel | None = None,
    ) -> None:
        self.uav_id = uav_id
        self.model: VehicleModel = model if model is not None else FfPaperModel(spec.process_noise_sigma)
        self.spec = spec
        self.terrain = terrain
        self.lakes = lakes
        self.rng = rng
        x, y, z, yaw = pose
        ground = float(terrain.elevation(x, y))
        self.x_m, self.y_m, self.z_m, self.yaw_rad = (
            float(x),
            float(y),
            max(float(z), ground),
            wrap_angle(yaw),
        )
        self.status = Status.ON_GROUND
        self.water_kg = float(spec.water_capacity_kg)
        # applied inputs (after limits), what the vehicle currently does
        self.v_lin_mps = 0.0
        self.v_z_mps = 0.0
        self.omega_z_radps = 0.0
        # flown values (the model's): airspeed, vertical speed, bank, noise-free turn rate
        self.airspeed_mps = self.climb_mps = self.bank_rad = self.turn_rate_radps = 0.0
        self.yaw_rate_radps = 0.0  # true yaw rate of the last substep, noise included (gyro truth)
        self.last_command: Command | None = None
        self.commands_clamped = 0
        self.commands_missed = 0  # consecutive
        self.refilling = False
        self.refill_taken_kg = 0.0
        self.responsive = True  # False once silent for command_timeout_s (the world stops waiting)
        self.crash_reason = ""

    # --- queries ---------------------------------------------------------------------------
    @property
    def pose(self) -> tuple[float, float, float, float]:
        return (self.x_m, self.y_m, self.z_m, self.yaw_rad)

    def height_above_terrain_m(self) -> float:
        return self.z_m - float(self.terrain.elevation(self.x_m, self.y_m))

    def lake_below(self) -> Lake | None:
        for lake in self.lakes:
            if lake.contains(self.x_m, self.y_m):
                return lake
        return None

    def refill_conditions(self) -> bool:
        """Over a lake, low (<= refill_height_m above the water) and slow (FF IV-D b)."""
        if self.status != Status.AIRBORNE:
            return False
        lake = self.lake_below()
        if lake is None:
            return False
        water_level_m = float(self.terrain.elevation(lake.x_m, lake.y_m))
        height = self.z_m - water_level_m
        return (
            -1e-9 <= height <= self.spec.refill_height_m
            and self.airspeed_mps <= self.spec.v_stall_mps + self.spec.refill_speed_margin_mps
        )

    # --- commands --------------------------------------------------------------------------
    def accept_command(self, cmd: Command | None, control_period_s: float) -> StepOutcome:
        """Take the command for this step (None or non-finite = missed); update the status."""
        out = StepOutcome()
        if self.status == Status.CRASHED:
            return out
        if cmd is None or not cmd.is_finite():
            out.missed = True
            self.commands_missed += 1
            silent_s = self.commands_missed * control_period_s
            if silent_s >= self.spec.command_timeout_s - 1e-9:
                self.responsive = False
                if self.status != Status.LANDED:
                    self.crash(f"no valid command for {silent_s:.1f} s")
                    out.crashed = True
            return out
        self.commands_missed = 0
        self.responsive = True
        self.last_command = cmd
        s = self.spec
        if self.status == Status.ON_GROUND:
            if cmd.v_lin_mps >= s.v_stall_mps and cmd.v_z_mps > 0:
                self.status = Status.AIRBORNE
                out.took_off = True
                self._set_flight(self.model.launch(self._flight(), cmd))
        elif self.status == Status.AIRBORNE:
            if cmd.v_lin_mps < s.v_stall_mps and self.height_above_terrain_m() < s.landing_height_m:
                self._land()
                out.landed = True
        out.clamped = self._apply_limits(cmd)
        if out.clamped:
            self.commands_clamped += 1
        return out

    def _apply_limits(self, cmd: Command) -> bool:
        s = self.spec
        if self.status != Status.AIRBORNE:
            self.v_lin_mps = self.v_z_mps = self.omega_z_radps = 0.0
            # On the ground only a takeoff counts; nothing to clamp there.
            return False
        v = min(max(cmd.v_lin_mps, s.v_stall_mps), s.v_max_mps)
        vz = min(max(cmd.v_z_mps, -s.vz_max_mps), s.vz_max_mps)
        w = min(max(cmd.omega_z_radps, -s.omega_max_radps), s.omega_max_radps)
        clamped = (v, vz, w) != (cmd.v_lin_mps, cmd.v_z_mps, cmd.omega_z_radps)
        self.v_lin_mps, self.v_z_mps, self.omega_z_radps = float(v), float(vz), float(w)
        if self.model.immediate:  # the unicycle flies its command from this instant
            self.airspeed_mps, self.climb_mps, self.turn_rate_radps = float(v), float(vz), float(w)
        return clamped

    def _land(self) -> None:
        self.status = Status.LANDED
        self.z_m = float(self.terrain.elevation(self.x_m, self.y_m))
        self.v_lin_mps = self.v_z_mps = self.omega_z_radps = self.yaw_rate_radps = 0.0
        self.airspeed_mps = self.climb_mps = self.bank_rad = self.turn_rate_radps = 0.0
        self.refilling = False

    def crash(self, reason: str) -> None:
        self.status = Status.CRASHED
        self.crash_reason = reason
        self.z_m = float(self.terrain.elevation(self.x_m, self.y_m))
        self.v_lin_mps = self.v_z_mps = self.omega_z_radps = self.yaw_rate_radps = 0.0
        self.airspeed_mps = self.climb_mps = self.bank_rad = self.turn_rate_radps = 0.0
        self.refilling = False

    # --- physics ---------------------------------------------------------------------------
    def _flight(self) -> FlightState:
        return FlightState(
            self.x_m,
            self.y_m,
            self.z_m,
            self.yaw_rad,
            self.airspeed_mps,
            self.climb_mps,
            self.bank_rad,
            self.turn_rate_radps,
            self.yaw_rate_radps,
            self.water_kg,
        )

    def _set_flight(self, f: FlightState) -> None:
        self.x_m, self.y_m, self.z_m, self.yaw_rad = f.x_m, f.y_m, f.z_m, f.yaw_rad
        self.airspeed_mps, self.climb_mps, self.bank_rad = f.airspeed_mps, f.climb_mps, f.bank_rad
        self.turn_rate_radps, self.yaw_rate_radps = f.turn_rate_radps, f.yaw_rate_radps

    def substep(self, dt_s: float, wind_mps: tuple[float, float] = (0.0, 0.0)) -> None:
        """Integrate one physics substep with the vehicle model (only when airborne)."""
        if self.status != Status.AIRBORNE:
            self.yaw_rate_radps = 0.0
            return
        cmd = Command(self.v_lin_mps, self.v_z_mps, self.omega_z_radps)
        (flown,) = self.model.step([self._flight()], [cmd], dt_s, [self.rng], wind_mps)
        self._set_flight(flown)
        ground = float(self.terrain.elevation(self.x_m, self.y_m))
        if self.z_m < ground:
            self.z_m = ground  # terrain is a floor; landing needs a slow command

    def refill_tick(self, dt_s: float) -> float:
        """Advance an ongoing refill by dt_s; returns the kg taken when the refill ended this
        substep (tank full, or the vehicle left the refill conditions part-filled), else 0."""
        if not self.refilling:
            return 0.0
        if not self.refill_conditions():
            self.refilling = False
            taken, self.refill_taken_kg = self.refill_taken_kg, 0.0
            return taken
        cap = self.spec.water_capacity_kg
        add = min(self.spec.refill_rate_kgps * dt_s, cap - self.water_kg)
        self.water_kg += add
        self.refill_taken_kg += add
        if self.water_kg >= cap - 1e-9:
            self.water_kg = cap
            self.refilling = False
            taken, self.refill_taken_kg = self.refill_taken_kg, 0.0
            return max(taken, 1e-12)
        return 0.0

    def request_refill(self) -> bool:
        """Start refilling if the conditions hold now; returns whether it started."""
        if self.water_kg >= self.spec.water_capacity_kg or not self.refill_conditions():
            return False
        if not self.refilling:
            self.refill_taken_kg = 0.0
        self.refilling = True
        return True

    def release_water(self) -> float:
        """Open the tank: returns the kg released (0 when empty or not airborne)."""
        if self.status != Status.AIRBORNE:
            return 0.0
        kg, self.water_kg = self.water_kg, 0.0
        self.refilling = False
        return kg
