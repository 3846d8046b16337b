"""The autopilot that stands for a fixed-wing vehicle's own: it tracks the agent's (v, v_z, omega).

Pure Python, no JSBSim in it: it reads the flown state (:class:`AirState`) and returns the
surface and throttle commands (:class:`Surfaces`, each within its normalised range). The loops are
the successive loop closure of Beard & McLain, *Small Unmanned Aircraft: Theory and Practice*
(2012), ch. 6, with the longitudinal channel of a total-energy control system (TECS: A. A.
Lambregts, "Vertical flight path and speed control autopilot design using total energy
principles", AIAA 83-2239, 1983):

- lateral (B&M 6.3.1-6.3.2): the bank command of the coordinated turn, phi_c = atan(omega_c v / g)
  (B&M Eq. 9.14 solved for phi), limited to the preset's bank_max minus a margin for overshoot
  and slewed at the preset's roll_rate_max;
  aileron = k_p (phi_c - phi) + k_i int(phi_c - phi) - k_d p; the rudder holds the sideslip at zero
  (B&M 6.3.3, turn coordination): rudder = -k_beta beta (JSBSim: positive rudder yaws left and
  makes a positive sideslip).
- longitudinal (TECS): with the flight-path angle gamma = asin(v_z / v) and the commanded
  acceleration vdot_c = k_v (v_c - v) (limited to the preset's accel_max), the specific total-energy
  rate error e_T = (gamma_c - gamma) + (vdot_c - vdot) / g goes to the throttle and the energy
  distribution error e_D = (gamma_c - gamma) - w (vdot_c - vdot) / g to the pitch command, each
  through a PI; both integrators at rest mean gamma = gamma_c and v = v_c. The weight w < 1
  (``tecs_speed_weight``) gives the flight path priority when the throttle saturates (a descent
  at idle gains speed rather than flying a shallower path than commanded). The throttle keeps a
  floor (``throttle_min``): on a propeller aircraft such as the J3Cub the propwash over the tail
  gives the elevator its authority at low speed. The pitch command goes
  to the elevator by a PD on pitch and on the pitch rate beyond a steady turn's (B&M 6.4.1).
- the energy split, on an aircraft short of power (``jsbsim.excess_power``: the PC-7 full of water,
  whose specific excess power at full throttle is 3.2 m/s at best): the weight w shares a
  saturated throttle's shortfall between climb and speed in a ratio that drifts with the state
  (the PC-7 commanded to 75 m/s and a climb traded climb for speed over minutes). So before the TECS
  the commands are split by the measured energy limit (Lambregts' specific energy rate, climb +
  (v / g) dv/dt <= P_s; :meth:`fire_uav_common.scenario.ExcessPower.split`), climb first: the climb
  command within the climb the aircraft holds at this speed, load and bank, the acceleration
  within the rest of P_s, the speed held first at the floor. The TECS then tracks commands the
  aircraft can fly with its throttle off the stop (the split spends 90 % of the measured P_s), in
  the order the agents' model predicts. No table (the J3Cub): no split, the TECS as before.
- the envelope: the course turns at g n sin(phi) / v, more than g tan(phi) / v when a pull-up
  raises the load factor n above level flight's 1 / cos(phi). The bank is further limited to
  asin(tan(bank_max) / n) and the elevator eases the pull where n sin(phi) exceeds 0.9 tan(bank_max),
  so the flown turn stays within the preset's g tan(bank_max) / v. That easing acts on the
  elevator after the pull has begun; on the PC-7 (65 m/s, 40 deg bank, levelling off from a
  descent) it fought the pitch PD in a limit cycle (n 0.8-2.2 every 1.25 s, the pitch command
  wound up 14 deg above the pitch) and the course turned as a 55 deg bank would. So the load
  factor is also limited where the pull is commanded (a load-factor protection, as a fly-by-wire
  normal law's or an autopilot's limit on its pitch command): by the point-mass flight-path
  equation v dgamma/dt = g (n cos(phi) - cos(gamma)) (B&M sec. 9.4's guidance model, lift along
  the body normal), with n within n_max = 0.9 tan(bank_max) / |sin(phi)| (``LOAD_LIMIT_MARGIN``)
  the flight path rises at most at (g / v)(n_max cos(phi) - cos(gamma)); the pitch command noses
  up no faster (its integrator held meanwhile), and the bank is limited to
  atan(0.9 tan(bank_max) / (cos(gamma) + v r / g)), the bank at which the wanted rise
  r = (gamma_c - gamma) / ``PULL_TAU_S`` fits, the flight path first as in Lambregts' TECS (a
  level-off in a turn rolls out part of the bank instead of sinking further). Only where the
  preset's ``jsbsim.load_protection`` says so (the PC-7): the J3Cub, which the easing holds within
  its 40 deg (hardest 39.3 deg over ff_two_fires seeds 1-3), flies as before. Integrators stop while their
  output saturates (anti-windup). The roll integrator also stops while the bank command slews or
  the bank is more than ``ROLL_I_BAND_RAD`` from it (conditional integration: K. J. Astrom, T.
  Hagglund, *Advanced PID Control*, ISA, 2006, sec. 3.5): it is there for the steady error of a
  held bank (B&M 6.3.1), and run through every roll-in, while the bank lags its slewed command by
  tens of degrees, it wound up and carried the J3Cub 2-3 deg past the 5 deg margin after a
  reversal, and over a monitor's orbits held 0.15 of aileron from minutes before
  (docs/airframes.md, "The envelope").

Units: SI and radians; the state in the body/NED conventions of JSBSim (phi right wing down
positive, theta nose up positive, p and q body rates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from fire_uav_common.scenario import Airframe
from fire_uav_common.scenario.airframes import G_MPS2

#: the roll integrator runs only while the bank command has stopped slewing and the bank is
#: within this of it [rad] (conditional integration: module doc)
ROLL_I_BAND_RAD = math.radians(2.0)
#: the load-factor limit's share of n sin(phi) = tan(bank_max) (module doc: the envelope)
LOAD_LIMIT_MARGIN = 0.9
#: the time over which a flight-path error is to be closed when the bank is limited for it [s]
PULL_TAU_S = 1.5


def _clip(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


@dataclass(frozen=True)
class AirState:
    """What the autopilot reads [SI, rad]: true airspeed, vertical speed (up), bank, pitch,
    sideslip, body roll and pitch rates."""

    airspeed_mps: float
    climb_mps: float
    bank_rad: float
    pitch_rad: float
    sideslip_rad: float
    roll_rate_radps: float
    pitch_rate_radps: float
    load_factor: float = 1.0  # normal load factor n = lift / weight [-]


@dataclass(frozen=True)
class Surfaces:
    """Normalised commands: aileron, elevator, rudder in [-1, 1], throttle in [0, 1]."""

    aileron: float
    elevator: float
    rudder: float
    throttle: float


class Autopilot:
    """One vehicle's autopilot; ``trim_throttle`` and ``trim_pitch_rad`` from the trimmed start."""

    def __init__(self, airframe: Airframe, trim_throttle: float, trim_pitch_rad: float) -> None:
        self.af = airframe
        self.js = airframe.jsbsim
        self.trim_throttle = float(trim_throttle)
        self.trim_pitch_rad = float(trim_pitch_rad)
        self.i_roll = 0.0
        self.phi_c_rad = 0.0  # the slewed bank command [rad]
        self.theta_c_rad = self.trim_pitch_rad  # the slewed pitch command [rad]
        self.i_t = 0.0
        self.i_d = 0.0
        self.prev_airspeed_mps: float | None = None

    def bank_limit_rad(self, v_mps: float) -> float:
        """The largest bank the autopilot commands at airspeed v [rad]: bank_max, or less where the
        turn's load factor n = 1 / cos(phi) needs more lift than the aircraft gives below
        v_s sqrt(n) (phi <= acos((v_s / v)^2), v_s the aircraft's own 1 g minimum speed), each
        less the overshoot margin."""
        ratio = (self.js.v_stall_mps / max(v_mps, 1e-6)) ** 2
        stall_lim = math.acos(ratio) if ratio < 1.0 else 0.0
        return max(min(self.af.bank_max_rad, stall_lim) - math.radians(self.js.bank_margin_deg), 0.0)

    def pull_bank_limit_rad(self, v_mps: float, gamma_rad: float, gamma_c_rad: float) -> float:
        """The largest bank at which the flight path can rise toward its command at the rate
        (gamma_c - gamma) / PULL_TAU_S within the load-factor limit [rad] (module doc)."""
        rate = max(gamma_c_rad - gamma_rad, 0.0) / PULL_TAU_S
        n_vert = math.cos(gamma_rad) + max(v_mps, 1.0) * rate / G_MPS2
        return math.atan(LOAD_LIMIT_MARGIN * math.tan(self.af.bank_max_rad) / n_vert)

    def pull_rate_max_radps(self, s: AirState, gamma_rad: float) -> float:
        """The fastest rise of the flight path within the load-factor limit [rad/s, >= 0]."""
        sin_phi = abs(math.sin(s.bank_rad))
        if sin_phi < 1e-3:
            return math.inf
        n_max = LOAD_LIMIT_MARGIN * math.tan(self.af.bank_max_rad) / sin_phi
        v = max(s.airspeed_mps, 1.0)
        return max(G_MPS2 * (n_max * math.cos(s.bank_rad) - math.cos(gamma_rad)) / v, 0.0)

    def speed_command_mps(self, v_lin_mps: float) -> float:
        """The airspeed held [m/s]: the command within [max(v_min, the aircraft's floor), v_max]."""
        lo = max(self.af.v_min_mps, self.js.v_floor_mps)
        return _clip(v_lin_mps, lo, max(lo, self.af.v_max_mps))

    def update(
        self,
        s: AirState,
        v_lin_mps: float,
        v_z_mps: float,
        omega_z_radps: float,
        dt_s: float,
        water_kg: float = 0.0,
    ) -> Surfaces:
        """The surfaces for one substep; ``water_kg`` the load aboard (the energy limit's mass)."""
        af, js = self.af, self.js
        v = max(s.airspeed_mps, 1.0)
        # longitudinal: TECS
        v_c = self.speed_command_mps(v_lin_mps)
        vz_c = _clip(v_z_mps, -af.descent_max_mps, af.climb_max_mps)
        vdot = 0.0 if self.prev_airspeed_mps is None else (s.airspeed_mps - self.prev_airspeed_mps) / dt_s
        self.prev_airspeed_mps = s.airspeed_mps
        vdot_c = _clip(js.k_speed_1ps * (v_c - s.airspeed_mps), -af.accel_max_mps2, af.accel_max_mps2)
        if js.excess_power is not None:  # short of power: climb first, the rest to speed (module doc)
            n_turn = 1.0 / max(math.cos(s.bank_rad), 0.3)
            floor = max(af.v_min_mps, js.v_floor_mps)
            vz_c, vdot_c = js.excess_power.split(
                s.airspeed_mps, water_kg, vz_c, vdot_c, load_factor=n_turn, v_floor_mps=floor
            )
        gamma = math.asin(_clip(s.climb_mps / v, -1.0, 1.0))
        gamma_c = math.asin(_clip(vz_c / v, -1.0, 1.0))
        # lateral: coordinated-turn bank command, roll PID, rudder against sideslip
        # the course turns at g n sin(phi) / v: with the load factor n of a pull-up above level
        # flight's, the bank that keeps it within g tan(bank_max) / v is asin(tan(bank_max) / n)
        n = max(s.load_factor, 1.0)
        n_lim = math.asin(min(1.0, math.tan(af.bank_max_rad) / n)) - math.radians(js.bank_margin_deg)
        lim = min(self.bank_limit_rad(v), n_lim)
        if js.load_protection:  # the bank at which the wanted pull fits (module doc)
            lim = min(lim, self.pull_bank_limit_rad(v, gamma, gamma_c))
        lim = max(lim, 0.0)
        # JSBSim's bank is positive right wing down, a clockwise turn: omega_z (ccw) enters negated
        phi_target = _clip(math.atan(-omega_z_radps * v / G_MPS2), -lim, lim)
        step = math.radians(af.roll_rate_max_degps) * dt_s  # the bank command slews at the roll rate
        phi_c = self.phi_c_rad = _clip(phi_target, self.phi_c_rad - step, self.phi_c_rad + step)
        e_phi = phi_c - s.bank_rad
        ail_raw = js.kp_roll * e_phi + js.ki_roll * self.i_roll - js.kd_roll * s.roll_rate_radps
        ail = _clip(ail_raw, -1.0, 1.0)
        if ail == ail_raw and phi_c == phi_target and abs(e_phi) < ROLL_I_BAND_RAD:
            self.i_roll += e_phi * dt_s
        rud = _clip(-js.k_beta * s.sideslip_rad, -1.0, 1.0)
        e_t = (gamma_c - gamma) + (vdot_c - vdot) / G_MPS2
        e_d = (gamma_c - gamma) - js.tecs_speed_weight * (vdot_c - vdot) / G_MPS2
        thr_raw = self.trim_throttle + js.tecs_kp_t * e_t + js.tecs_ki_t * self.i_t
        thr = _clip(thr_raw, js.throttle_min, 1.0)
        if thr == thr_raw or (thr_raw > 1.0) == (e_t < 0.0):
            self.i_t += e_t * dt_s
        th_max = math.radians(js.pitch_max_deg)
        th_raw = self.trim_pitch_rad + js.tecs_kp_d * e_d + js.tecs_ki_d * self.i_d
        theta_c = _clip(th_raw, -th_max, th_max)
        # the pitch command slews at pitch_rate_max (no sudden pull-up out of a descent), and noses
        # up no faster than the flight path may rise within the load-factor limit (module doc)
        th_step = math.radians(js.pitch_rate_max_degps) * dt_s
        up_step = min(th_step, self.pull_rate_max_radps(s, gamma) * dt_s) if js.load_protection else th_step
        slewed = _clip(theta_c, self.theta_c_rad - th_step, self.theta_c_rad + up_step)
        held = slewed < theta_c and up_step < th_step  # the load limit holds the command back
        if (theta_c == th_raw or (th_raw > th_max) == (e_d < 0.0)) and not (held and e_d > 0.0):
            self.i_d += e_d * dt_s
        theta_c = self.theta_c_rad = slewed
        # pitch PD on the elevator (JSBSim's sign: positive elevator pitches nose down); the rate
        # term damps the pitch rate beyond a steady turn's, q = (g / v) tan(phi) sin(phi)
        q_turn = G_MPS2 * math.tan(s.bank_rad) * math.sin(s.bank_rad) / v
        e_q = s.pitch_rate_radps - q_turn
        elev_raw = -(js.kp_pitch * (theta_c - s.pitch_rad) - js.kd_pitch * e_q)
        # and the pull is eased where n sin(phi) nears tan(bank_max) (a climbing turn)
        excess = n * abs(math.sin(s.bank_rad)) - 0.9 * math.tan(af.bank_max_rad)
        if excess > 0.0:
            elev_raw += js.k_load * excess
        elev = _clip(elev_raw, -1.0, 1.0)
        return Surfaces(aileron=ail, elevator=elev, rudder=rud, throttle=thr)
