"""EKF for a fixed-wing's pose and the horizontal wind: x = (x, y, z, yaw, w_x, w_y).

FF's EKF (III-B, Eqs. 16-25; :class:`.estimation.StateEkf`) predicts the position with the
commanded speed along the heading (FF Eq. 4): FF's unicycle flies over the ground. A fixed-wing
flies through the air, and the air moves: the world drifts its ``coordinated_turn`` and ``jsbsim``
aircraft with the raster fire's wind (3-3.5 m/s on ``grass_running`` / ``grass_brush_hill``), and
FF's filter, which has no wind, was 19-30 m off with NEES 300-840 there (docs/airframes.md). This
filter adds the wind as two states, as Beard & McLain's GPS-smoothing EKF does (R. W. Beard, T. W.
McLain, *Small Unmanned Aircraft: Theory and Practice*, 2012, sec. 8.7 "GPS smoothing": states
p_n, p_e, V_g, chi, w_n, w_e, psi, the wind constant up to process noise, the ground velocity
the airspeed along the heading plus the wind: the wind triangle of sec. 2.5).

State: ``x_m, y_m`` [m; map frame, east/north], ``z_m`` [m], ``yaw_rad`` [rad, ccw from +x], and
``wind_x_mps, wind_y_mps`` [m/s]: the air's velocity over the ground (the direction it blows
*toward*, as the scenario's ``fires.raster.wind``). Inputs u = (v [m/s], v_z [m/s], omega
[rad/s]), as :class:`.estimation.StateEkf`: on a fixed-wing the horizontal airspeed, climb rate and
turn rate as flown (:class:`.airframe_model.FlownInput`).

Prediction per physics substep dt (FF Eq. 16 over the ground: the wind triangle, B&M sec. 2.5):

    x' = x + (v cos(yaw) + w_x) dt,   y' = y + (v sin(yaw) + w_y) dt
    z' = z + v_z dt,                  yaw' = yaw + omega dt,   w' = w

and P' = A P A^T + G Q G^T + Q_w (FF Eq. 17), where A is FF's Jacobian with two more unit columns
(dx'/dw_x = dy'/dw_y = dt), G Q G^T FF's input noise on (v, v_z, omega) exactly as
:class:`.estimation.StateEkf` (the world's own noise model: white speed and climb noise per
substep, FF Eq. 4), and Q_w = diag(q_w^2 dt, q_w^2 dt) the wind's random walk.

Why the wind becomes observable: GPS fixes measure the ground track; its difference from dead
reckoning along the heading is the wind plus the heading error times v. Flying straight, the
along-track part gives the wind along the track; the cross-track part is shared between the
crosswind and a heading error until the heading changes, and a turn separates them (B&M sec. 8.7).

Updates: FF's GPS rows (x, y) and the altimeter row h = z - E(x, y) (the terrain map, as in
:class:`.estimation.StateEkf`) with two zero columns for the wind; Joseph form; the gyro as the
exact augmented-state update of :mod:`.estimation` (its module doc).

Noise and prior (:class:`WindEkfConfig`):

* ``wind_walk_mps_per_sqrt_s`` q_w = 0.1 m/s per sqrt(s): twice PX4 EKF2's wind process noise
  spectral density (parameter ``EKF2_WIND_NSD``, default 0.05 m/s^2/sqrt(Hz): "when unaided, the
  wind estimate uncertainty (1-sigma, in m/s) increases by this amount every second"), i.e. a wind
  that wanders some 0.8 m/s a minute. PX4's value is for a wind that changes smoothly; the
  scenarios' wind changes in steps (``grass_brush_hill``: 1.8 and 2.5 m/s at 240 s and 480 s, a
  veer every 4 minutes), which q_w = 0.1 makes a 1-sigma change over 320-625 s. Measured on the
  world's ``coordinated_turn`` with its own noise and sensors, a step from 3 m/s toward 15 deg to
  3.5 m/s toward 45 deg (2.0 m/s): over the 10 s after it, NEES 18.2 (PX4's 0.05), 9.9 / 5.4 (0.1,
  two seeds), 5.6 (0.2); the estimate within 0.3 m/s of the new wind 20 s after it (0.1); in the
  steady wind before it NEES 2.5-3.2 whichever q_w.
* ``wind_prior_sigma_mps`` = 5 m/s per axis, zero mean. The agents are not told the scenario's wind
  (``AgentConfig`` carries no forecast; the raster fire's wind is the world's), so the prior is
  the calm with a spread that covers a moderate breeze (|w| <= 10 m/s at 2 sigma; 3-3.5 m/s in the
  scenarios), below small_uav's lowest commanded speed 15.6 m/s.

Where this departs from FF III-B: FF's state is (x, y, z, yaw) and its Eq. 4 has no wind; this
adds two wind states (B&M sec. 8.7) and predicts over the ground with airspeed plus wind.
Everything else (inputs, Q on the inputs, the gyro, the altimeter row, the Joseph form, the
partial updates in timestamp order) is :class:`.estimation.StateEkf`'s. ``ff_paper`` agents keep
:class:`.estimation.StateEkf`, whose numbers this module does not touch.

The pose estimate and its covariance are ``s`` (4,) and ``P`` (4 x 4, the pose block), as
:class:`.estimation.StateEkf` exposes them (the agent publishes them to its peers); the wind is
``wind_mps`` and the whole covariance ``P_full`` (6 x 6).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common.angles import wrap_angle
from fire_uav_common.codecs.sensor_bundle import Samples
from fire_uav_common.terrain import Terrain

from .errors import ConfigError
from .estimation import EkfConfig, fuse_fixes, fusion_schedule

__all__ = ["WindEkfConfig", "WindStateEkf"]

_N = 6
_I6 = np.eye(_N)
_I6.flags.writeable = False
_H_GPS = np.zeros((2, _N))  # GPS rows (FF Eq. 19): x and y
_H_GPS[0, 0] = _H_GPS[1, 1] = 1.0
_H_GPS.flags.writeable = False


@dataclass(frozen=True)
class WindEkfConfig:
    """FF's noise model (``ekf``) and the wind's: prior sigma [m/s] per axis, random walk [m/s/sqrt(s)]."""

    ekf: EkfConfig = field(default_factory=EkfConfig)
    wind_prior_sigma_mps: float = 5.0
    wind_walk_mps_per_sqrt_s: float = 0.1  # twice PX4 EKF2_WIND_NSD's default (module doc)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.wind_prior_sigma_mps) and self.wind_prior_sigma_mps > 0):
            raise ConfigError(f"wind_prior_sigma_mps must be finite and > 0, got {self.wind_prior_sigma_mps}")
        if not (math.isfinite(self.wind_walk_mps_per_sqrt_s) and self.wind_walk_mps_per_sqrt_s >= 0):
            raise ConfigError(
                f"wind_walk_mps_per_sqrt_s must be finite and >= 0, got {self.wind_walk_mps_per_sqrt_s}"
            )


class WindStateEkf:
    """FF III-B's EKF with two wind states (module doc); the pose as ``s`` / ``P``, the wind as ``wind_mps``."""

    def __init__(
        self,
        config: WindEkfConfig,
        s0: np.ndarray,
        terrain: Terrain | None = None,
        wind0_mps: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        # FF's noise model as StateEkf keeps it (fuse_fixes reads its altimeter bounds); the wind's
        # two numbers are read here once, so the config itself is not kept
        self.cfg = config.ekf
        self.terrain = terrain or Terrain()
        pose = np.asarray(s0, dtype=float)
        if pose.shape != (4,) or not np.all(np.isfinite(pose)):
            raise ConfigError(f"s0 must be 4 finite numbers, got {s0!r}")
        w0 = np.asarray(wind0_mps, dtype=float)
        if w0.shape != (2,) or not np.all(np.isfinite(w0)):
            raise ConfigError(f"wind0_mps must be 2 finite numbers, got {wind0_mps!r}")
        self.x = np.concatenate([pose, w0])
        self.x[3] = wrap_angle(self.x[3])
        sig = list(self.cfg.initial_sigma) + [config.wind_prior_sigma_mps] * 2
        self.P_full = np.diag(np.square(sig)).astype(float)
        q = np.square(np.asarray(self.cfg.sigma_nu, dtype=float))
        self._q0, self._q1, self._q2 = (float(v) for v in q)
        self._k_gyro = self._q2 / (self._q2 + self.cfg.sigma_gyro_radps**2)
        self._qw = config.wind_walk_mps_per_sqrt_s**2  # wind variance growth [m^2/s^3]
        self._a = np.eye(_N)  # A: predict sets its yaw column; the wind columns are dt
        self._gqg = np.zeros((_N, _N))
        self.updates = {"gps": 0, "alt": 0, "gyro": 0}
        self._r_alt = np.array([[self.cfg.sigma_alt_m**2]])

    # --- the pose as StateEkf exposes it ----------------------------------------------------
    @property
    def s(self) -> np.ndarray:
        """The pose estimate (x, y, z [m], yaw [rad]) (a copy)."""
        return self.x[:4].copy()

    @s.setter
    def s(self, pose: np.ndarray) -> None:
        """Set the pose (x, y, z, yaw); the wind and the covariance stay."""
        self.x[:4] = np.asarray(pose, dtype=float)
        self.x[3] = wrap_angle(self.x[3])

    @property
    def P(self) -> np.ndarray:
        """The pose block (4 x 4) of the covariance (a copy)."""
        return self.P_full[:4, :4].copy()

    @property
    def wind_mps(self) -> tuple[float, float]:
        """The estimated wind (east, north) [m/s]: the air's velocity over the ground."""
        return (float(self.x[4]), float(self.x[5]))

    @property
    def wind_cov(self) -> np.ndarray:
        """The wind's covariance (2 x 2) [m^2/s^2] (a copy)."""
        return self.P_full[4:, 4:].copy()

    @property
    def yaw_rad(self) -> float:
        return float(self.x[3])

    # --- prediction (FF Eqs. 16-17 with the wind) ------------------------------------------
    def predict(self, u: np.ndarray, dt_s: float, gyro_radps: float | None = None) -> None:
        """One substep with input u = (v, v_z, omega) and the gyro sample of this substep if any."""
        v, vz, om = float(u[0]), float(u[1]), float(u[2])
        x, y, z, th, wx, wy = self.x.tolist()
        self.x = np.array(self._predict_floats(x, y, z, th, wx, wy, v, vz, om, dt_s, gyro_radps))

    def _predict_floats(
        self,
        x: float,
        y: float,
        z: float,
        th: float,
        wx: float,
        wy: float,
        v: float,
        vz: float,
        om: float,
        dt_s: float,
        gyro_radps: float | None,
    ) -> tuple[float, float, float, float, float, float]:
        q_om = self._q2
        if gyro_radps is not None and math.isfinite(gyro_radps):
            om = om + self._k_gyro * (gyro_radps - om)  # augmented-state update (estimation's doc)
            q_om = (1.0 - self._k_gyro) * q_om
            self.updates["gyro"] += 1
        c, s = math.cos(th), math.sin(th)
        a = self._a
        a[0, 3] = -v * s * dt_s
        a[1, 3] = v * c * dt_s
        a[0, 4] = a[1, 5] = dt_s
        g0, g1 = c * dt_s, s * dt_s
        gq0, gq1 = g0 * self._q0, g1 * self._q0
        gqg = self._gqg
        gqg[0, 0] = gq0 * g0
        gqg[0, 1] = gq0 * g1
        gqg[1, 0] = gq1 * g0
        gqg[1, 1] = gq1 * g1
        gqg[2, 2] = (dt_s * self._q1) * dt_s
        gqg[3, 3] = (dt_s * q_om) * dt_s
        gqg[4, 4] = gqg[5, 5] = self._qw * dt_s
        p = a @ self.P_full @ a.T + gqg
        self.P_full = 0.5 * (p + p.T)
        return (
            x + (v * c + wx) * dt_s,
            y + (v * s + wy) * dt_s,
            z + vz * dt_s,
            wrap_angle(th + om * dt_s),
            wx,
            wy,
        )

    # --- updates (FF Eqs. 21-25, Joseph form) ----------------------------------------------
    def _update(self, y: np.ndarray, h: np.ndarray, r: np.ndarray) -> None:
        hp = h @ self.P_full
        s_mat = hp @ h.T + r  # Eq. 22
        k = np.linalg.solve(s_mat, hp).T  # Eq. 23
        self.x = self.x + k @ y  # Eq. 24
        self.x[3] = wrap_angle(self.x[3])
        ikh = _I6 - k @ h
        p = ikh @ self.P_full @ ikh.T + k @ r @ k.T  # Joseph form of Eq. 25
        self.P_full = 0.5 * (p + p.T)

    def update_gps(self, x_m: float, y_m: float, var_m2: float | None = None) -> None:
        var = var_m2 if var_m2 is not None and var_m2 > 0 else self.cfg.sigma_gps_m**2
        self._update(np.array([x_m - self.x[0], y_m - self.x[1]]), _H_GPS, np.eye(2) * var)
        self.updates["gps"] += 1

    def update_altimeter(self, height_m: float) -> None:
        """Height above ground [m]: h(x) = z - E(x, y)."""
        e = float(self.terrain.elevation(self.x[0], self.x[1]))
        dex, dey = self.terrain.gradient(self.x[0], self.x[1])
        h = np.array([[-dex, -dey, 1.0, 0.0, 0.0, 0.0]])
        self._update(np.array([height_m - (self.x[2] - e)]), h, self._r_alt)
        self.updates["alt"] += 1

    # --- one control step (the schedule of StateEkf.process) ------------------------------
    def process(
        self, samples: Samples, command: np.ndarray, t0_s: float, t1_s: float, moving: bool = True
    ) -> None:
        """Advance from t0_s to t1_s with ``command`` held, fusing ``samples`` in time order, with
        :meth:`.estimation.StateEkf.process`'s schedule (a sample stamped t at the end of the
        substep containing it, the gyro during it; ``moving`` False skips the prediction: the
        wind does not move a vehicle on the ground)."""
        dt = self.cfg.dt_s
        gyro_at, segments = fusion_schedule(samples, t0_s, t1_s, dt)
        u = np.asarray(command, dtype=float)
        v, vz, om = float(u[0]), float(u[1]), float(u[2])
        for j, j_end, fixes in segments:
            if moving:
                x, y, z, th, wx, wy = self.x.tolist()
                for i in range(j, j_end + 1):
                    x, y, z, th, wx, wy = self._predict_floats(
                        x, y, z, th, wx, wy, v, vz, om, dt, gyro_at.get(i)
                    )
                self.x = np.array([x, y, z, th, wx, wy])
            fuse_fixes(self, samples, fixes)
