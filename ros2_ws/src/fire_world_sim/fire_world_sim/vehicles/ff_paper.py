"""FF Eq. 4: the unicycle with altitude and process noise, following its command at once.

One substep of length dt::

    x += cos(yaw) dt (v_lin + nu_1);  y += sin(yaw) dt (v_lin + nu_1)
    z += dt (v_z + nu_2);             yaw += dt (omega_z + nu_3)

with ``nu ~ N(0, sigma^2 I)`` drawn per substep from the vehicle's own stream. Wind is ignored,
as in the paper.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from fire_uav_common.angles import wrap_angle

from .base import Command, FlightState


class FfPaperModel:
    name = "ff_paper"
    immediate = True

    def __init__(self, process_noise_sigma: float) -> None:
        self.sigma = float(process_noise_sigma)

    def launch(self, state: FlightState, command: Command) -> FlightState:
        return state

    def step(
        self,
        states: Sequence[FlightState],
        commands: Sequence[Command],
        dt_s: float,
        rngs: Sequence[np.random.Generator],
        wind_mps: tuple[float, float] = (0.0, 0.0),
    ) -> list[FlightState]:
        out = []
        for s, cmd, rng in zip(states, commands, rngs, strict=True):
            nu = rng.normal(0.0, self.sigma, 3) if self.sigma > 0 else (0, 0, 0)
            v = cmd.v_lin_mps + nu[0]
            c, sn = math.cos(s.yaw_rad), math.sin(s.yaw_rad)
            yaw_rate = cmd.omega_z_radps + nu[2]
            out.append(
                dataclasses.replace(
                    s,
                    x_m=s.x_m + c * dt_s * v,
                    y_m=s.y_m + sn * dt_s * v,
                    z_m=s.z_m + dt_s * (cmd.v_z_mps + nu[1]),
                    yaw_rad=wrap_angle(s.yaw_rad + dt_s * yaw_rate),
                    airspeed_mps=cmd.v_lin_mps,
                    climb_mps=cmd.v_z_mps,
                    bank_rad=0.0,
                    turn_rate_radps=cmd.omega_z_radps,
                    yaw_rate_radps=yaw_rate,
                )
            )
        return out

    @staticmethod
    def step_fleet(
        x_m: np.ndarray,
        y_m: np.ndarray,
        z_m: np.ndarray,
        yaw_rad: np.ndarray,
        v_lin_mps: np.ndarray,
        v_z_mps: np.ndarray,
        omega_z_radps: np.ndarray,
        nu: np.ndarray,
        dt_s: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`step` for a whole fleet in one numpy pass: arrays of the airborne vehicles'
        states and applied commands, ``nu`` their (n, 3) noise of this substep. Returns the new
        (x_m, y_m, z_m, yaw_rad) and the flown yaw rate (noise included).

        The same float operations in the same order as :meth:`step`, element by element (``nu``
        drawn as :meth:`step` draws it: ``rng.normal(0, sigma, 3)`` per substep is the row of one
        ``rng.normal(0, sigma, (substeps, 3))`` block), so both give the same flight to the bit.
        """
        v = v_lin_mps + nu[:, 0]
        c, sn = np.cos(yaw_rad), np.sin(yaw_rad)
        yaw_rate = omega_z_radps + nu[:, 2]
        w = np.fmod(yaw_rad + dt_s * yaw_rate + math.pi, 2.0 * math.pi)  # wrap_angle, vectorised
        w = np.where(w <= 0.0, w + 2.0 * math.pi, w) - math.pi
        return (
            x_m + c * dt_s * v,
            y_m + sn * dt_s * v,
            z_m + dt_s * (v_z_mps + nu[:, 1]),
            w,
            yaw_rate,
        )
