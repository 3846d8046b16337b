"""The agent's own model of its airframe: how the commands it sends are flown, and how tight it can turn.

An agent on a fixed-wing (scenario ``uavs.airframe``) knows its envelope from the same preset the
world flies. Two uses, both ROS-free:

* **The EKF's input as flown** (:class:`FlownInput`). FF's EKF (Eqs. 16-17) predicts with the
  command, which FF's unicycle flies at once. A fixed-wing does not: airspeed, flight-path angle
  and bank follow their commands as first-order responses, the bank is limited, and the turn
  rate is g tan(phi) / v (Beard & McLain, *Small Unmanned Aircraft*, 2012, ch. 9, Eqs. 9.14,
  9.18-9.20). Predicting with the command made one UAV's estimate drift 14 m from the truth
  while reporting a standard deviation below 1 m. So the agent runs that first-order model on
  board, from the commands it sent, over each control period at the physics rate, and hands the
  EKF the mean flown (horizontal speed, vertical speed, turn rate) of the period; the gyro still
  corrects the turn rate at every substep. Without an airframe (``ff_paper``) the input is the
  command as the world clamps it (FF Eq. 5), exactly as before. On an aircraft short of power
  (``Airframe.excess_power``: the tanker's PC-7 on ``jsbsim``) the speed and climb rate also obey
  its energy limit, climb + (v / g) dv/dt <= P_s(v, m, n), spent climb first as the world's autopilot
  spends it (:meth:`fire_uav_common.scenario.ExcessPower.split`): without it the model reached
  75 m/s in 30 s that the PC-7 full of water takes over two minutes to near (12 m/s rms off).
* **The EKF's process noise** (:func:`input_noise_sigma`). FF's nu (Eq. 4) is white noise per
  physics substep, which the world draws for ``ff_paper`` and ``coordinated_turn``. An aircraft that
  is not the first-order model (``jsbsim``) departs from the modelled speed and climb rate by an
  error correlated over seconds (``Airframe.model_error_mps``), which white noise of FF's size
  covers a hundred times too little (NEES 69 on one J3Cub, its height estimate 0.19 m sure and
  0.9 m off). Its white-noise equivalent has the same position variance growth: intensity
  2 sigma^2 tau_c [m^2/s] (a first-order Gauss-Markov error of correlation time tau_c), that is
  sigma_nu^2 = 2 sigma^2 tau_c / dt per substep.
* **Turn geometry** (:func:`turn_radius_m`, :func:`inside_turn_circle`): the smallest radius
  r = v^2 / (g tan(phi_max)) (B&M Eq. 9.14 with psi_dot = v / r) that guidance and separation
  plan with, and the lined-up landing approach (:class:`FinalApproach`).
* **Scoop run** (:func:`usable_lakes`): a fixed-wing scoops on a straight run over the water; a
  lake too short for the run that fills the tank is not used. It must reach the water slow
  enough to scoop: :func:`slowdown_m` is how far ahead of the lake it has to start slowing, and
  low enough: :func:`descent_m` how far ahead it has to start descending.

Units: [m], [s], [m/s], [rad], [kg]; positions in the map frame.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import Airframe
from fire_uav_common.scenario.airframes import G_MPS2
from fire_uav_common.terrain import Lake

from .coverage import VehicleLimits

__all__ = [
    "FinalApproach",
    "FlownInput",
    "OnboardState",
    "final_approach_course",
    "descent_m",
    "input_noise_sigma",
    "inside_turn_circle",
    "line_gain_per_m",
    "scoop_run_m",
    "slowdown_m",
    "turn_radius_m",
    "usable_lakes",
]


def _clip(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


def turn_radius_m(airframe: Airframe, speed_mps: float, water_kg: float | None = None) -> float:
    """Smallest turn radius [m] at airspeed ``speed_mps``: v^2 / (g tan(phi_lim)) (B&M Eq. 9.14).

    phi_lim is the bank limit, or less where a turn at load factor 1 / cos(phi) would stall at the
    water load ``water_kg`` (None: full tank, the worst case).
    """
    v = max(speed_mps, 1e-3)
    return v * v / (G_MPS2 * max(math.tan(bank_limit_rad(airframe, v, water_kg)), 1e-9))


#: [s] correlation time of the airframe's model error (the order of the J3Cub's 3.5 s airspeed
#: and 1.5 s climb-rate responses; docs/airframes.md)
MODEL_ERROR_TIME_S = 2.0


def input_noise_sigma(
    airframe: Airframe | None, process_noise_sigma: float, physics_period_s: float
) -> tuple[float, float, float]:
    """The EKF's per-substep input noise sigma_nu (v_lin [m/s], v_z [m/s], omega [rad/s]) (module doc).

    FF's ``process_noise_sigma`` for each input, raised for speed and climb rate to the white-noise
    equivalent sqrt(2 sigma_m^2 tau_c / dt) of the airframe's model error sigma_m
    (``Airframe.model_error_mps``), tau_c = :data:`MODEL_ERROR_TIME_S`, dt the physics period.
    The turn rate keeps FF's: the gyro measures it at every substep."""
    s = float(process_noise_sigma)
    if airframe is None or airframe.model_error_mps <= 0.0:
        return (s, s, s)
    eq = math.sqrt(2.0 * airframe.model_error_mps**2 * MODEL_ERROR_TIME_S / physics_period_s)
    return (max(s, eq), max(s, eq), s)


def scoop_run_m(airframe: Airframe) -> float:
    """The straight run [m] over water that fills the empty tank: the scoop time
    water_capacity / refill_rate at the lowest commanded speed (the slowest the airframe flies)."""
    return airframe.v_min_mps * airframe.water_capacity_kg / airframe.refill_rate_kgps


def slowdown_m(airframe: Airframe, from_mps: float, to_mps: float) -> float:
    """The distance [m] the airframe flies while it slows from ``from_mps`` to ``to_mps`` at its
    deceleration limit: (v0^2 - v1^2) / (2 accel_max) (B&M Eq. 9.18's first-order airspeed response,
    limited to |dV/dt| <= accel_max; 0 when it is not faster).

    The limit holds while the speed error exceeds accel_max tau_airspeed; the first-order tail
    below it is not counted, so the airframe arrives within accel_max tau_airspeed of ``to_mps``
    (tanker: 4 m/s, inside the world's refill speed margin of 10 m/s over the lowest speed).
    The tanker slowing from its 75 m/s to the 49.8 m/s of the low-and-slow lake approach flies
    1,572 m, to its 46.8 m/s final approach speed 1,717 m; small_uav from 30 to 18.6 m/s 92 m, to
    15.6 m/s 109 m.
    """
    v0, v1 = float(from_mps), float(to_mps)
    if v0 <= v1:
        return 0.0
    return (v0 * v0 - v1 * v1) / (2.0 * airframe.accel_max_mps2)


def descent_m(airframe: Airframe, speed_mps: float, height_m: float) -> float:
    """The distance [m] the airframe flies at ``speed_mps`` while it descends ``height_m`` at its
    descent limit (B&M Eq. 9.19's flight-path angle, limited to |v_z| <= descent_max; 0 for no
    descent). The lag of the height loop is not counted.

    The J3Cub (1.4 m/s, its steepest descent held at 22 m/s) descending from the 37 m layer to the
    7.5 m scoop height at 25 m/s flies 527 m, from the 23 m layer 277 m; small_uav (5 m/s) 110 m
    and the tanker (8 m/s) 184 m, less than their lake approach margins already.
    """
    if height_m <= 0.0:
        return 0.0
    return float(speed_mps) * float(height_m) / airframe.descent_max_mps


def usable_lakes(
    lakes: Sequence[Lake], airframe: Airframe | None
) -> tuple[tuple[Lake, ...], tuple[str, ...]]:
    """The lakes a fixed-wing can scoop from, and one line for each lake it cannot use.

    A lake's longest straight run over water (``Lake.longest_run``: its diameter for a disc, the
    outline's for a landscape water body) shorter than :func:`scoop_run_m` cannot fill the tank
    on one pass, and the lake is not used (the scenario loader applies the same rule). Without an airframe (FF's unicycle hovers
    over the water as long as it needs) every lake is usable.
    """
    if airframe is None:
        return tuple(lakes), ()
    need = scoop_run_m(airframe)
    ok = tuple(lk for lk in lakes if lk.longest_run.length_m >= need)
    refused = tuple(
        f"lake at ({lk.x_m:g}, {lk.y_m:g}) m not used for refills: its longest run "
        f"{lk.longest_run.length_m:.0f} m is shorter than the {need:.0f} m scoop run of this airframe"
        for lk in lakes
        if lk.longest_run.length_m < need
    )
    return ok, refused


def bank_limit_rad(airframe: Airframe, speed_mps: float, water_kg: float | None = None) -> float:
    """The bank limit at airspeed v: bank_max, or acos((V_S(m) / v)^2) where that is lower (stall)."""
    w = airframe.water_capacity_kg if water_kg is None else water_kg
    ratio = (airframe.stall_speed_mps(w) / max(speed_mps, 1e-6)) ** 2
    stall_lim = math.acos(ratio) if ratio < 1.0 else 0.0
    return min(airframe.bank_max_rad, stall_lim)


def inside_turn_circle(
    pose: tuple[float, float, float], point_xy: tuple[float, float], radius_m: float
) -> bool:
    """Whether ``point_xy`` lies inside either of the two turn circles of radius ``radius_m``
    tangent to the heading at ``pose`` (x, y, yaw): a vehicle at that turn radius cannot reach it
    by turning toward it (a Dubins path has to fly away first)."""
    x, y, th = pose
    for side in (1.0, -1.0):
        cx = x - side * radius_m * math.sin(th)
        cy = y + side * radius_m * math.cos(th)
        if math.hypot(point_xy[0] - cx, point_xy[1] - cy) < radius_m - 1e-9:
            return True
    return False


@dataclass
class OnboardState:
    """The modelled flight state: airspeed [m/s], vertical speed [m/s], bank [rad]."""

    airspeed_mps: float = 0.0
    climb_mps: float = 0.0
    bank_rad: float = 0.0

    @property
    def turn_rate_radps(self) -> float:
        return G_MPS2 * math.tan(self.bank_rad) / max(self.airspeed_mps, 1e-3)


class FlownInput:
    """The EKF's input over one control period: the command as the airframe flies it (module doc).

    ``airframe`` None: FF's unicycle, which flies the clamped command at once. ``limits``: the
    ``vehicle:`` limits the world clamps every command to (FF Eq. 5; under an airframe they come
    from the same preset). ``physics_period_s`` / ``control_period_s``: the world's substep and
    step [s].
    """

    def __init__(
        self,
        airframe: Airframe | None,
        limits: VehicleLimits,
        physics_period_s: float,
        control_period_s: float,
    ) -> None:
        self.af, self.lim = airframe, limits
        self.dt_s = physics_period_s
        self.substeps = max(1, int(round(control_period_s / physics_period_s)))
        self.state = OnboardState()

    def clamped(self, cmd: np.ndarray, airborne: bool) -> np.ndarray:
        """The command as the world applies it (clamped to the limits, FF Eq. 5)."""
        lim = self.lim
        v = float(np.clip(cmd[0], lim.v_stall_mps, lim.v_max_mps)) if airborne else float(cmd[0])
        return np.array(
            [
                v,
                float(np.clip(cmd[1], -lim.vz_max_mps, lim.vz_max_mps)),
                float(np.clip(cmd[2], -lim.omega_max_radps, lim.omega_max_radps)),
            ]
        )

    def input(
        self, cmd: np.ndarray, was_airborne: bool, vehicle: VehicleStatus, water_kg: float
    ) -> np.ndarray:
        """(v_lin [m/s], v_z [m/s], omega [rad/s]) for the EKF over the period the command ``cmd``
        (sent at the previous step) was flown: ``was_airborne`` the status at the previous step,
        ``vehicle`` the status now, ``water_kg`` the load aboard (stall speed)."""
        now_flying = vehicle == VehicleStatus.AIRBORNE
        touched_down = vehicle in (VehicleStatus.LANDED, VehicleStatus.ON_GROUND) and was_airborne
        u = self.clamped(cmd, was_airborne)
        if self.af is not None and now_flying:
            if not was_airborne:  # took off at the start of the period: wings level, at speed
                self.state = OnboardState(_clip(u[0], self.af.v_min_mps, self.af.v_max_mps), 0.0, 0.0)
            u = self._fly(self.clamped(cmd, True), water_kg)
        elif self.af is not None:
            self.state = OnboardState()
        if touched_down:
            u = np.array([0.0, u[1], 0.0])  # touched down during the step
        return u

    def _fly(self, u: np.ndarray, water_kg: float) -> np.ndarray:
        """Integrate B&M Eqs. 9.14, 9.18-9.20 over the period; the mean (ground speed, climb, turn rate)."""
        af = self.af
        assert af is not None
        dt, st = self.dt_s, self.state
        v, climb, phi = st.airspeed_mps, st.climb_mps, st.bank_rad
        v_c = _clip(float(u[0]), af.v_min_mps, af.v_max_mps)
        vz_c = _clip(float(u[1]), -af.descent_max_mps, af.climb_max_mps)
        p_max = math.radians(af.roll_rate_max_degps)
        energy = af.excess_power
        sum_g = sum_z = sum_w = 0.0
        for _ in range(self.substeps):
            v_old = max(v, 1e-3)
            dv = _clip((v_c - v) / af.tau_airspeed_s, -af.accel_max_mps2, af.accel_max_mps2)
            vz_t = vz_c
            if energy is not None:  # the energy limit: climb first, the modelled climb spends P_s
                n_turn = 1.0 / max(math.cos(phi), 0.3)
                vz_t, dv = energy.split(v_old, water_kg, vz_c, dv, climb, n_turn, af.v_min_mps)
            v = max(v + dt * dv, 1e-3)
            gamma = math.asin(_clip(climb / v_old, -1.0, 1.0))
            gamma_c = math.asin(_clip(vz_t / v, -1.0, 1.0))
            gamma += dt * (gamma_c - gamma) / af.tau_gamma_s
            climb = _clip(v * math.sin(gamma), -af.descent_max_mps, af.climb_max_mps)
            lim = bank_limit_rad(af, v, water_kg)
            phi_c = _clip(math.atan(float(u[2]) * v / G_MPS2), -lim, lim)
            dphi = _clip((phi_c - phi) / af.tau_bank_s, -p_max, p_max)
            phi = _clip(phi + dt * dphi, -lim, lim)
            sum_g += math.sqrt(max(v * v - climb * climb, 0.0))
            sum_z += climb
            sum_w += G_MPS2 * math.tan(phi) / v
        self.state = OnboardState(v, climb, phi)
        n = float(self.substeps)
        return np.array([sum_g / n, sum_z / n, sum_w / n])


def final_approach_course(
    start_xy: tuple[float, float], area_m: tuple[float, float, float, float], start_yaw_rad: float
) -> float:
    """The course [rad] of the final leg to the takeoff point: from the area's centre toward the
    takeoff point, snapped to a multiple of 90 deg so that neighbours' takeoff points in a row get
    parallel finals (the entry lies inside the area); the takeoff heading when the point is the centre."""
    cx, cy = 0.5 * (area_m[0] + area_m[1]), 0.5 * (area_m[2] + area_m[3])
    dx, dy = start_xy[0] - cx, start_xy[1] - cy
    if math.hypot(dx, dy) < 1.0:
        return start_yaw_rad
    b = math.atan2(dy, dx)
    return math.remainder(round(b / (0.5 * math.pi)) * 0.5 * math.pi, math.tau)


#: damping ratio of the final's linearised lateral loop (:func:`line_gain_per_m`)
LINE_DAMPING = 0.7


def line_gain_per_m(heading_gain_1ps: float, speed_mps: float, approach_angle_rad: float) -> float:
    """k [1/m] of B&M's straight-line vector field (Eq. 10.8) for a final flown at ``speed_mps``
    under the heading loop omega = K_a (chi_c - psi) (FF Eq. 11, K_a = ``heading_gain_1ps``).

    Linearised about the line (B&M Eq. 10.8 near e = 0: chi_c - chi_q = -K e, K = chi_inf (2/pi) k;
    de/dt = v (psi - chi_q); dpsi/dt = K_a (chi_c - psi)) the cross-track error obeys
    e'' + K_a e' + K_a v K e = 0: natural frequency w_n = sqrt(K_a v K), damping zeta =
    sqrt(K_a / (4 v K)). k is chosen for zeta = :data:`LINE_DAMPING`, K = K_a / (4 zeta^2 v).
    Two reasons to be as stiff as that damping allows: the steady offset from a heading error delta
    (the EKF's heading estimate, a crab angle not corrected) is delta / K, and the estimate's wander
    is followed within about 1 / (zeta w_n). k = 1 / r (the default) gives zeta 1.0 on small_uav
    (K_a 1.67 1/s, 15.6 m/s, r 24.8 m): an offset of 0.65 m per degree of heading error, 3.2 m for
    the 5 deg (2 sd) the EKF's heading was off on the final (ff_two_fires, coordinated_turn), past
    the 2.5 m touch-down disc. zeta 0.7 gives k = 2.03 / r there (0.32 m per degree), 1.14 / r
    for the J3Cub (K_a 0.56 1/s, 22 m/s) and 1.83 / r for the tanker (K_a 0.5 1/s, 46.8 m/s).
    The bank lag tau_b adds a third pole; the loop stays stable while v K tau_b < 1 (Routh-Hurwitz
    on tau_b s^3 + s^2 + K_a s + K_a v K): 0.26 for small_uav (tau_b 0.3 s, K 0.055 rad/m).
    """
    k_rad_per_m = heading_gain_1ps / (4.0 * LINE_DAMPING**2 * max(speed_mps, 1e-3))
    return k_rad_per_m / (approach_angle_rad * 2.0 / math.pi)


@dataclass(frozen=True)
class FinalApproach:
    """A landing approach lined up with the takeoff point (the threshold): a straight final leg of
    ``length_m`` on ``course_rad``, entered from behind, for an airframe turning on ``turn_radius_m``.

    Captured (behind the threshold within ``length_m`` + 3 r, within 3 r of the centre line, heading
    within 90 deg of the course), the vehicle follows the line with Beard & McLain's straight-line
    vector field (*Small Unmanned Aircraft*, 2012, Eq. 10.8): course chi_c = chi_q - chi_inf (2/pi)
    atan(k e), e the cross-track error, chi_inf = 60 deg, k = ``line_gain_per_m`` (0: 1 / r; the
    landing's final sizes it with :func:`line_gain_per_m`, within ``line_band_m`` of the line: beyond
    it the argument of atan grows as e / r, so the capture from far off is B&M's k = 1 / r, shifted
    by (k - 1 / r) ``line_band_m``). Otherwise it flies to the entry
    point, ``length_m`` + r behind the threshold; within 2 r of it and heading the wrong way, it
    turns at its limit toward the course, on the side of the line (the turn ends captured).
    """

    threshold_xy: tuple[float, float]
    course_rad: float
    length_m: float
    turn_radius_m: float
    approach_angle_rad: float = math.radians(60.0)  # chi_inf of B&M Eq. 10.8
    line_gain_per_m: float = 0.0  # k of B&M Eq. 10.8 [1/m]; 0: 1 / turn_radius_m
    # [m] > 0: line_gain_per_m only within this of the line; beyond it the slope is 1 / turn_radius_m
    line_band_m: float = 0.0

    @property
    def entry_xy(self) -> tuple[float, float]:
        d = self.length_m + self.turn_radius_m
        return (
            self.threshold_xy[0] - d * math.cos(self.course_rad),
            self.threshold_xy[1] - d * math.sin(self.course_rad),
        )

    def frame(self, xy: tuple[float, float]) -> tuple[float, float]:
        """(along [m], cross [m]): along the course from the threshold (< 0 before it), left of the line > 0."""
        ex, ey = xy[0] - self.threshold_xy[0], xy[1] - self.threshold_xy[1]
        c, s = math.cos(self.course_rad), math.sin(self.course_rad)
        return ex * c + ey * s, -ex * s + ey * c

    def captured(self, pose: tuple[float, float, float]) -> bool:
        along, cross = self.frame((pose[0], pose[1]))
        r = self.turn_radius_m
        return (
            -(self.length_m + 3.0 * r) <= along <= 0.5 * r
            and abs(cross) <= 3.0 * r
            and abs(math.remainder(pose[2] - self.course_rad, math.tau)) <= 0.5 * math.pi
        )

    def at_threshold(self, xy: tuple[float, float], step_m: float, radius_m: float) -> bool:
        """Whether to touch down here: within ``radius_m`` of the threshold, or, for an airframe that
        flies more than ``radius_m`` in one control step (``step_m``: the tanker's 4.7 m at 46.8 m/s
        against the 2.5 m touch-down disc), at the step nearest to it along the line (-step / 2 <=
        along < step / 2: half-open, so that of two steps straddling the threshold exactly one
        touches down) within ``radius_m`` of the line. Without the second rule a pass stepped over the
        disc whenever its cross-track error exceeded about 1 m, and the tanker went round again."""
        along, cross = self.frame(xy)
        if math.hypot(along, cross) <= radius_m:
            return True
        return step_m > radius_m and -0.5 * step_m <= along < 0.5 * step_m and abs(cross) <= radius_m

    def line_course(self, xy: tuple[float, float]) -> float:
        """B&M Eq. 10.8: the course that brings the vehicle onto the line."""
        _, cross = self.frame(xy)
        k0 = 1.0 / max(self.turn_radius_m, 1e-3)
        k = self.line_gain_per_m if self.line_gain_per_m > 0.0 else k0
        if self.line_band_m > 0.0:  # k within the band, B&M's 1 / r beyond it (the capture unchanged)
            b = self.line_band_m
            u = k0 * cross + (k - k0) * _clip(cross, -b, b)
        else:
            u = k * cross
        return self.course_rad - self.approach_angle_rad * (2.0 / math.pi) * math.atan(u)

    def turn_side(self, pose: tuple[float, float, float]) -> float:
        """+1 (left) or -1 (right): the turn whose circle centre lies nearer the centre line."""
        best, side = math.inf, 1.0
        for sd in (1.0, -1.0):
            cx = pose[0] - sd * self.turn_radius_m * math.sin(pose[2])
            cy = pose[1] + sd * self.turn_radius_m * math.cos(pose[2])
            d = abs(self.frame((cx, cy))[1])
            if d < best:
                best, side = d, sd
        return side
