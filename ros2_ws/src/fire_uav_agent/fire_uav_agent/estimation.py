"""EKF for one UAV's state s = (x, y, z, yaw) (FF III-B, Eqs. 16-25).

State: ``x_m, y_m`` [m; map frame, east/north], ``z_m`` [m above datum], ``yaw_rad`` [rad,
ccw from +x, wrapped to (-pi, pi]]. Inputs u = (v_lin [m/s], v_z [m/s], omega_z [rad/s])
(FF Eq. 2), applied by the world with additive noise nu ~ N(0, diag(sigma_nu^2)) per input and
physics substep (FF Eq. 4).

Prediction runs at the physics rate ``dt_s`` (0.01 s) with the commanded inputs:
``s^- = f(s, u)`` (Eq. 16), ``P^- = A P A^T + G Q G^T`` (Eq. 17) with A and G the Jacobians
printed under Eq. 17 and Q = diag(sigma_nu^2) per *input* (v_lin, v_z, omega). The paper labels
Q's entries sigma_ux, sigma_uy, sigma_omega, which does not match the three inputs of Eq. 4 that
G multiplies; we follow Eq. 4.

Updates (Eqs. 21-25) are partial: each measurement that arrived updates only its rows of H
(GPS: x, y; altimeter: z), in timestamp order, interleaved with the physics substeps. The
covariance update uses the Joseph form ``P = (I-KH) P (I-KH)^T + K R K^T`` (a stable
equivalent of Eq. 25) and P is re-symmetrised after every step.

Deviations from the paper, and why:

* Altimeter. The ultrasonic sensor measures height above *ground*, not z (FF II-C says
  "altitude above ground level" while Eq. 19 writes z). We use the honest nonlinear
  h(s) = z - E(x, y) with Jacobian H = [-dE/dx, -dE/dy, 1, 0] (E: the a-priori terrain map,
  ``fire_uav_common.terrain``). On flat terrain this is exactly Eq. 19's z row.
* Gyro. Eq. 19 models the gyro as (theta_k - theta_{k-1}) / dt with H = 1/dt, treating
  theta_{k-1} as known. That ignores the correlation between theta_{k-1} and theta_k and, with
  dt = 0.01 s, feeds the filter an innovation scaled by 100. We instead treat the gyro for what
  it measures: the yaw rate actually applied during the substep, omega = omega_cmd + nu_3.
  Augmenting the state with that substep's rate (prior N(omega_cmd, sigma_nu^2), independent of
  s) and updating it with the gyro sample (H = 1, R = sigma_gyro^2) gives
  omega_hat = omega_cmd + k (m - omega_cmd), var = (1 - k) sigma_nu^2, k = sigma_nu^2 /
  (sigma_nu^2 + sigma_gyro^2); the yaw is then propagated with omega_hat and the reduced
  variance. This is the exact Kalman update of the augmented linear-Gaussian model, not an
  approximation, and it is what makes the 100 Hz gyro useful.
* When the vehicle is on the ground it does not move (docs/protocol.md), so prediction is
  skipped then (no motion, no process noise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from fire_uav_common.angles import wrap_angle  # re-exported: callers import it from here
from fire_uav_common.codecs.sensor_bundle import Samples  # re-exported: the EKF's input
from fire_uav_common.terrain import Terrain

from .errors import ConfigError

__all__ = ["EkfConfig", "Samples", "StateEkf", "wrap_angle"]

_I4 = np.eye(4)
_I4.flags.writeable = False
_H_GPS = np.zeros((2, 4))  # GPS rows of H (Eq. 19): x and y
_H_GPS[0, 0] = _H_GPS[1, 1] = 1.0
_H_GPS.flags.writeable = False
# numpy's LAPACK gufunc behind np.linalg.solve (a private module of numpy, pinned in
# requirements/py.txt); a numpy without it falls back to np.linalg.solve itself
_solve_gufunc = getattr(getattr(np.linalg, "_umath_linalg", None), "solve", None)


def _solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.linalg.solve(a, b)`` for float64 matrices, bit for bit: the same LAPACK gufunc, without
    the wrapper's checks and error-state context (~10 us of each EKF update). A result that is not
    finite (a singular or non-finite ``a``) is computed again by ``np.linalg.solve``, which raises
    its ``LinAlgError`` or returns the same numbers."""
    if _solve_gufunc is None:  # pragma: no cover - numpy 2.4.6 has it
        return np.linalg.solve(a, b)
    x = _solve_gufunc(a, b, signature="dd->d")
    if not math.isfinite(float(x.sum())):
        return np.linalg.solve(a, b)
    return x


@dataclass(frozen=True)
class EkfConfig:
    """Noise model. Sigmas are standard deviations in the units of the quantity."""

    dt_s: float = 0.01  # physics substep [s]
    sigma_nu: tuple[float, float, float] = (1.0, 1.0, 1.0)  # input noise (v_lin, v_z, omega) Eq. 4
    sigma_gps_m: float = 3.0  # FF II-C
    sigma_alt_m: float = 1.5
    sigma_gyro_radps: float = 0.3
    alt_max_range_m: float = 40.0  # altimeter samples above this are ignored
    # altimeter samples below this are ignored [m]. The sensor adds its noise to the true height
    # (the world sends a sample whenever the true height is in range), so a reading below 0 near
    # the ground is a valid one, and dropping it biases the estimate up by up to 0.8 sigma at
    # touch-down height (a J3Cub on the floor was estimated 0.6-0.9 m up and never touched down).
    # 0.0 keeps FF's missions as they were (ff_paper); a fixed-wing agent uses -inf.
    alt_min_m: float = 0.0
    initial_sigma: tuple[float, float, float, float] = (3.0, 3.0, 1.5, 0.05)  # P0 diagonal sqrt

    def __post_init__(self) -> None:
        if not self.dt_s > 0:
            raise ConfigError(f"dt_s must be > 0, got {self.dt_s}")
        for name in ("sigma_gps_m", "sigma_alt_m", "sigma_gyro_radps"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"{name} must be > 0, got {getattr(self, name)}")


class StateEkf:
    """EKF of FF III-B over s = (x, y, z, yaw); see the module docstring for the model."""

    def __init__(self, config: EkfConfig, s0: np.ndarray, terrain: Terrain | None = None) -> None:
        self.cfg = config
        self.terrain = terrain or Terrain()
        self.s = np.asarray(s0, dtype=float).copy()
        if self.s.shape != (4,) or not np.all(np.isfinite(self.s)):
            raise ConfigError(f"s0 must be 4 finite numbers, got {s0!r}")
        self.s[3] = wrap_angle(self.s[3])
        self.P = np.diag(np.square(config.initial_sigma)).astype(float)
        self._q = np.square(np.asarray(config.sigma_nu, dtype=float))
        self._k_gyro = self._q[2] / (self._q[2] + config.sigma_gyro_radps**2)
        self._q0, self._q1, self._q2 = (float(x) for x in self._q)
        self._a = np.eye(4)  # the Jacobian A of Eq. 17; predict sets its two yaw entries
        self._a_t = self._a.T  # a view: follows the entries predict sets
        self._gqg = np.zeros((4, 4))  # G Q G^T of Eq. 17; predict sets its six non-zero entries
        self.updates = {"gps": 0, "alt": 0, "gyro": 0}
        self._r_alt = np.array([[config.sigma_alt_m**2]])  # R of the altimeter row (Eq. 20)
        self._r_alt.flags.writeable = False

    # --- prediction (Eqs. 16-17) ------------------------------------------------------
    def predict(self, u: np.ndarray, dt_s: float, gyro_radps: float | None = None) -> None:
        """One substep with input u = (v_lin, v_z, omega); gyro sample of this substep if any.

        The same numbers as ``P = A P A^T + G Q G^T`` with numpy's products (Eq. 17), in fewer
        numpy calls: A lives in one array of the filter (only its two yaw entries change), and
        G Q G^T, whose every entry is a single product (each row of G has one non-zero entry),
        is written out in the order numpy's ``(G @ Q) @ G.T`` multiplies. A P A^T stays numpy's
        matrix product: its entries sum two products, and BLAS's order (and fused multiply-adds)
        is not reproduced in plain floats (a 1e-15 difference changed a 14-UAV mission, docs/profile.md).
        """
        self._predict(float(u[0]), float(u[1]), float(u[2]), dt_s, gyro_radps)

    def _predict(self, v: float, vz: float, om: float, dt_s: float, gyro_radps: float | None) -> None:
        """:meth:`predict` with the input as three floats."""
        x, y, z, th = self.s.tolist()
        self.s = np.array(self._predict_floats(x, y, z, th, v, vz, om, dt_s, gyro_radps))

    def _predict_floats(
        self,
        x: float,
        y: float,
        z: float,
        th: float,
        v: float,
        vz: float,
        om: float,
        dt_s: float,
        gyro_radps: float | None,
    ) -> tuple[float, float, float, float]:
        """One substep of Eqs. 16-17 on the state as four floats (returned), P updated. ``process``
        keeps the state in floats from one measurement update to the next (no array per substep);
        each float is the one ``float(s[i])`` gave, so the numbers are the same."""
        q_om = self._q2
        if gyro_radps is not None and math.isfinite(gyro_radps):
            om = om + self._k_gyro * (gyro_radps - om)  # augmented-state update (module doc)
            q_om = (1.0 - self._k_gyro) * q_om
            self.updates["gyro"] += 1
        c, s = math.cos(th), math.sin(th)
        a = self._a
        a[0, 3] = -v * s * dt_s
        a[1, 3] = v * c * dt_s
        g0, g1 = c * dt_s, s * dt_s  # G[0, 0], G[1, 0]; G[2, 1] = G[3, 2] = dt_s
        gq0, gq1 = g0 * self._q0, g1 * self._q0  # (G Q)[0, 0], (G Q)[1, 0]
        gqg = self._gqg
        gqg[0, 0] = gq0 * g0
        gqg[0, 1] = gq0 * g1
        gqg[1, 0] = gq1 * g0
        gqg[1, 1] = gq1 * g1
        gqg[2, 2] = (dt_s * self._q1) * dt_s
        gqg[3, 3] = (dt_s * q_om) * dt_s
        p = a @ self.P @ self._a_t + gqg
        self.P = 0.5 * (p + p.T)  # _symmetrise
        return x + v * c * dt_s, y + v * s * dt_s, z + vz * dt_s, wrap_angle(th + om * dt_s)

    # --- updates (Eqs. 21-25, Joseph form) ------------------------------------------
    def _update(self, y: np.ndarray, h: np.ndarray, r: np.ndarray) -> None:
        hp = h @ self.P  # (h @ P) @ h.T is how ``h @ P @ h.T`` groups: the same product
        s_mat = hp @ h.T + r  # Eq. 22
        k = _solve(s_mat, hp).T  # Eq. 23 (P symmetric)
        self.s = self.s + k @ y  # Eq. 24
        self.s[3] = wrap_angle(self.s[3])
        ikh = _I4 - k @ h
        self.P = ikh @ self.P @ ikh.T + k @ r @ k.T  # Joseph form of Eq. 25
        self._symmetrise()

    def update_gps(self, x_m: float, y_m: float, var_m2: float | None = None) -> None:
        var = var_m2 if var_m2 is not None and var_m2 > 0 else self.cfg.sigma_gps_m**2
        self._update(np.array([x_m - self.s[0], y_m - self.s[1]]), _H_GPS, np.eye(2) * var)
        self.updates["gps"] += 1

    def update_altimeter(self, height_m: float) -> None:
        """Height above ground [m]: h(s) = z - E(x, y)."""
        e = float(self.terrain.elevation(self.s[0], self.s[1]))
        dex, dey = self.terrain.gradient(self.s[0], self.s[1])
        h = np.array([[-dex, -dey, 1.0, 0.0]])
        y = np.array([height_m - (self.s[2] - e)])
        self._update(y, h, self._r_alt)
        self.updates["alt"] += 1

    def _symmetrise(self) -> None:
        self.P = 0.5 * (self.P + self.P.T)

    # --- one control step ---------------------------------------------------------------
    def process(
        self, samples: Samples, command: np.ndarray, t0_s: float, t1_s: float, moving: bool = True
    ) -> None:
        """Advance from t0_s to t1_s with ``command`` held, fusing ``samples`` in time order.

        Substep j covers (t0 + (j-1) dt, t0 + j dt]; a sample stamped t is applied at the end
        of the substep containing t (gyro: during it, see module doc). ``moving`` False (vehicle
        on the ground) skips the prediction.
        """
        dt = self.cfg.dt_s
        gyro_at, segments = fusion_schedule(samples, t0_s, t1_s, dt)
        u = np.asarray(command, dtype=float)
        v, vz, om = float(u[0]), float(u[1]), float(u[2])
        for j, j_end, fixes in segments:
            # the substeps up to the next one with a measurement (or the last), on the state as floats
            if moving:
                x, y, z, th = self.s.tolist()
                for i in range(j, j_end + 1):
                    x, y, z, th = self._predict_floats(x, y, z, th, v, vz, om, dt, gyro_at.get(i))
                self.s = np.array([x, y, z, th])
            fuse_fixes(self, samples, fixes)

    @property
    def yaw_rad(self) -> float:
        return float(self.s[3])


Segment = tuple[int, int, list[tuple[int, int]]]


def fusion_schedule(
    samples: Samples, t0_s: float, t1_s: float, dt_s: float
) -> tuple[dict[int, float], list[Segment]]:
    """When each sample of a control step is fused: the schedule every filter here shares.

    The step from ``t0_s`` to ``t1_s`` is cut into physics substeps of ``dt_s``; substep j covers
    (t0 + (j-1) dt, t0 + j dt] and a sample stamped t belongs to the substep containing it (clipped
    to 1..n; a non-finite stamp: substep 1). Returns ``gyro_at`` (substep -> the finite gyro rate
    measured during it; at 100 Hz at most one per substep, a later one replaces an earlier) and
    the segments ``(j, j_end, fixes)``: predict substeps j..j_end, then apply ``fixes``, the GPS
    (kind 0) and altimeter (kind 1) rows stamped in substep j_end as ``(kind, row)`` in
    timestamp order (FF III-B's partial updates "in timestamp order"). The last segment ends at
    the step's last substep, with or without fixes.
    """
    n_sub = max(1, int(round((t1_s - t0_s) / dt_s)))
    eps = 1e-6 * dt_s

    def sub_index(t: float) -> int:
        """The substep containing stamp ``t`` [s], clipped to 1..n_sub (a non-finite stamp: 1)."""
        x = (t - t0_s - eps) / dt_s
        return min(max(math.ceil(x), 1), n_sub) if math.isfinite(x) else 1

    gyro_at: dict[int, float] = {}
    if samples.gyro.size:
        for t, w in samples.gyro[:, :2].tolist():
            if math.isfinite(w):
                gyro_at[sub_index(t)] = w
    events: list[tuple[int, float, int, int]] = []  # (substep, t, kind, row)
    if samples.gps.size:
        for r, t in enumerate(samples.gps[:, 0].tolist()):
            events.append((sub_index(t), t, 0, r))
    if samples.alt.size:
        for r, t in enumerate(samples.alt[:, 0].tolist()):
            events.append((sub_index(t), t, 1, r))
    events.sort()
    segments: list[Segment] = []
    ei, n_ev, j = 0, len(events), 1
    while j <= n_sub:
        j_end = events[ei][0] if ei < n_ev else n_sub
        fixes: list[tuple[int, int]] = []
        while ei < n_ev and events[ei][0] == j_end:
            fixes.append((events[ei][2], events[ei][3]))
            ei += 1
        segments.append((j, j_end, fixes))
        j = j_end + 1
    return gyro_at, segments


class FixSink(Protocol):
    """What :func:`fuse_fixes` needs of a filter: its :class:`EkfConfig` and its two updates."""

    cfg: EkfConfig

    def update_gps(self, x_m: float, y_m: float, var_m2: float | None = None) -> None: ...

    def update_altimeter(self, height_m: float) -> None: ...


def fuse_fixes(ekf: FixSink, samples: Samples, fixes: list[tuple[int, int]]) -> None:
    """Apply one segment's GPS / altimeter rows (:func:`fusion_schedule`) to ``ekf`` in order;
    a non-finite fix, or a height outside the altimeter's range, is skipped."""
    for kind, r in fixes:
        if kind == 0:
            gx, gy = samples.gps[r, 1], samples.gps[r, 2]
            var = float(samples.gps_var_m2[r]) if samples.gps_var_m2.size > r else 0.0
            if math.isfinite(gx) and math.isfinite(gy):
                ekf.update_gps(float(gx), float(gy), var)
        else:
            hgt = float(samples.alt[r, 1])
            if math.isfinite(hgt) and ekf.cfg.alt_min_m <= hgt <= ekf.cfg.alt_max_range_m:
                ekf.update_altimeter(hgt)
