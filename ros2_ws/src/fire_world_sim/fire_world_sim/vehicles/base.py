"""The flight state every backend integrates and the backend interface."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np


@dataclass(frozen=True)
class Command:
    """Control input (FF Eq. 2): v_lin [m/s], v_z [m/s], omega_z [rad/s]."""

    v_lin_mps: float
    v_z_mps: float
    omega_z_radps: float

    def is_finite(self) -> bool:
        return all(math.isfinite(v) for v in (self.v_lin_mps, self.v_z_mps, self.omega_z_radps))


@dataclass(frozen=True)
class FlightState:
    """One airborne vehicle [map frame: x east, y north, z up; m, rad, m/s].

    ``yaw_rad``: heading ccw from +x; ``airspeed_mps``: speed through the air; ``climb_mps``:
    vertical speed; ``bank_rad``: roll angle (0 for the unicycle); ``turn_rate_radps``: the flown
    heading rate without process noise; ``yaw_rate_radps``: the true yaw rate of the last substep,
    noise included, which the gyro reads; ``water_kg``: load aboard (stall speed).
    """

    x_m: float
    y_m: float
    z_m: float
    yaw_rad: float
    airspeed_mps: float = 0.0
    climb_mps: float = 0.0
    bank_rad: float = 0.0
    turn_rate_radps: float = 0.0
    yaw_rate_radps: float = 0.0
    water_kg: float = 0.0


class VehicleModel(Protocol):
    """A backend: integrates airborne vehicles over one substep ``dt_s`` [s].

    ``commands[i]`` is vehicle i's applied command (v_lin [m/s], v_z [m/s], omega_z [rad/s]),
    ``rngs[i]`` its own process-noise stream, ``wind_mps`` the wind (east, north) [m/s] it drifts
    with. ``immediate``: the vehicle flies its command at once (no dynamics of its own).
    """

    name: str
    immediate: bool

    def step(
        self,
        states: Sequence[FlightState],
        commands: Sequence[Command],
        dt_s: float,
        rngs: Sequence[np.random.Generator],
        wind_mps: tuple[float, float] = (0.0, 0.0),
    ) -> list[FlightState]: ...

    def launch(self, state: FlightState, command: Command) -> FlightState:
        """The state at takeoff (a fixed-wing leaves the ground at its commanded speed)."""
        ...
