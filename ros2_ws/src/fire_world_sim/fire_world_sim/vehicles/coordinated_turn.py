"""A bank-limited fixed-wing: the kinematic guidance model of Beard & McLain, ch. 9.

Beard & McLain, *Small Unmanned Aircraft: Theory and Practice* (2012), section 9.3 (Eqs.
9.18-9.20): with the autopilot loops closed, airspeed, flight-path angle and bank each follow
their command with a first-order response, and the heading turns as a coordinated turn::

    dv/dt     = (v_c - v) / tau_v,         |dv/dt| <= accel_max
    dgamma/dt = (gamma_c - gamma) / tau_g, gamma_c = asin(vz_c / v), vz_c in [-descent, climb]
    dphi/dt   = (phi_c - phi) / tau_phi,   |dphi/dt| <= roll_rate_max, |phi| <= phi_lim
    dpsi/dt   = g tan(phi) / v                                         (B&M Eq. 9.14)
    dx/dt = v cos(psi) cos(gamma) + w_e,   dy/dt = v sin(psi) cos(gamma) + w_n
    dz/dt = v sin(gamma)

The agent commands a turn rate omega_c; the autopilot banks to phi_c = atan(omega_c v / g).
The bank limit phi_lim is the airframe's bank_max and, below it, the stall limit: a turn at
load factor n = 1 / cos(phi) stalls below v_s(m) sqrt(n), so phi_lim = acos((v_s(m) / v)^2).
The commanded speed is held in [v_min, v_max]; the climb rate so that |vz| never exceeds the
climb and descent limits. Process noise (gusts) moves the position only:
nu_1 on the speed along the track, nu_2 on the vertical speed, as FF Eq. 4, from the vehicle's
own stream; the heading turns only as the bank allows.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from fire_uav_common.angles import wrap_angle
from fire_uav_common.scenario import Airframe
from fire_uav_common.scenario.airframes import G_MPS2

from .base import Command, FlightState


def _clip(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


class CoordinatedTurnModel:
    name = "coordinated_turn"
    immediate = False

    def __init__(self, airframe: Airframe, process_noise_sigma: float) -> None:
        self.af = airframe
        self.sigma = float(process_noise_sigma)

    def launch(self, state: FlightState, command: Command) -> FlightState:
        """Airborne at the commanded speed (within the envelope), wings level."""
        v = _clip(command.v_lin_mps, self.af.v_min_mps, self.af.v_max_mps)
        return FlightState(
            state.x_m, state.y_m, state.z_m, state.yaw_rad, v, 0.0, 0.0, 0.0, 0.0, state.water_kg
        )

    def bank_limit_rad(self, v_mps: float, water_kg: float) -> float:
        """The bank limit at airspeed v: bank_max, or less where the turn's load factor would stall."""
        vs = self.af.stall_speed_mps(water_kg)
        ratio = (vs / max(v_mps, 1e-6)) ** 2
        stall_lim = math.acos(ratio) if ratio < 1.0 else 0.0
        return min(self.af.bank_max_rad, stall_lim)

    def step(
        self,
        states: Sequence[FlightState],
        commands: Sequence[Command],
        dt_s: float,
        rngs: Sequence[np.random.Generator],
        wind_mps: tuple[float, float] = (0.0, 0.0),
    ) -> list[FlightState]:
        af = self.af
        out = []
        for s, cmd, rng in zip(states, commands, rngs, strict=True):
            nu = rng.normal(0.0, self.sigma, 2) if self.sigma > 0 else (0.0, 0.0)
            # airspeed: first order, acceleration-limited
            v_c = _clip(cmd.v_lin_mps, af.v_min_mps, af.v_max_mps)
            dv = _clip((v_c - s.airspeed_mps) / af.tau_airspeed_s, -af.accel_max_mps2, af.accel_max_mps2)
            v = max(s.airspeed_mps + dt_s * dv, 1e-3)
            # flight-path angle: first order towards the commanded climb rate
            vz_c = _clip(cmd.v_z_mps, -af.descent_max_mps, af.climb_max_mps)
            gamma = math.asin(_clip(s.climb_mps / max(s.airspeed_mps, 1e-3), -1.0, 1.0))
            gamma_c = math.asin(_clip(vz_c / v, -1.0, 1.0))
            gamma += dt_s * (gamma_c - gamma) / af.tau_gamma_s
            climb = _clip(v * math.sin(gamma), -af.descent_max_mps, af.climb_max_mps)
            # bank: first order, roll-rate and bank limited
            lim = self.bank_limit_rad(v, s.water_kg)
            phi_c = _clip(math.atan(cmd.omega_z_radps * v / G_MPS2), -lim, lim)
            p_max = math.radians(af.roll_rate_max_degps)
            dphi = _clip((phi_c - s.bank_rad) / af.tau_bank_s, -p_max, p_max)
            phi = _clip(s.bank_rad + dt_s * dphi, -lim, lim)
            turn = G_MPS2 * math.tan(phi) / v
            ground_v = math.sqrt(max(v * v - climb * climb, 0.0)) + nu[0]
            c, sn = math.cos(s.yaw_rad), math.sin(s.yaw_rad)
            out.append(
                FlightState(
                    x_m=s.x_m + dt_s * (c * ground_v + wind_mps[0]),
                    y_m=s.y_m + dt_s * (sn * ground_v + wind_mps[1]),
                    z_m=s.z_m + dt_s * (climb + nu[1]),
                    yaw_rad=wrap_angle(s.yaw_rad + dt_s * turn),
                    airspeed_mps=v,
                    climb_mps=climb,
                    bank_rad=phi,
                    turn_rate_radps=turn,
                    yaw_rate_radps=turn,
                    water_kg=s.water_kg,
                )
            )
        return out
