"""On-board sensors (FF II-C): GPS, ultrasonic altimeter, gyro, fire camera/IR.

Each sensor of each UAV has its own seeded stream (``fire_uav_common.rng.stream(seed,
"<sensor>", uav_id)``), samples on the global sim-time grid ``n / rate_hz`` and delivers a
sample with probability ``p_valid`` (dropout otherwise). Noise is zero-mean Gaussian:

- GPS: (x, y) + N(0, sigma_m^2 I) [m], reported variance sigma_m^2 [m^2].
- Altimeter: height above terrain + N(0, sigma_m^2) [m]; no reading when the true height is
  outside [0, max_range_m] (ultrasonic range 0-40 m).
- Gyro: true yaw rate (process noise included) + N(0, sigma_radps^2) [rad/s].
- Fire: every fire seen within ``range_m`` (horizontal) reports its centre + N(0,
  position_sigma_m^2 I) and its extent (Gaussian sigma) + N(0, extent_sigma_m^2), clipped >= 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common.rng import stream
from fire_uav_common.scenario import Sensors as SensorsSpec

__all__ = [
    "AltimeterSample",
    "CellsSample",
    "FireDetectionSample",
    "GpsSample",
    "GyroSample",
    "SensorSuite",
    "samples_due",
]


@dataclass(frozen=True)
class GyroSample:
    stamp_ns: int
    omega_z_radps: float


@dataclass(frozen=True)
class AltimeterSample:
    stamp_ns: int
    range_m: float
    max_range_m: float


@dataclass(frozen=True)
class GpsSample:
    stamp_ns: int
    x_m: float
    y_m: float
    variance_m2: float


@dataclass(frozen=True)
class FireDetectionSample:
    stamp_ns: int
    track_id: int
    x_m: float
    y_m: float
    extent_m: float
    range_m: float


@dataclass(frozen=True)
class CellsSample:
    """Raster cells in the fire sensor footprint: centres [m] and FireCells.CELL_* states."""

    stamp_ns: int
    cell_size_m: float
    x_m: np.ndarray = field(default_factory=lambda: np.zeros(0, np.float32))
    y_m: np.ndarray = field(default_factory=lambda: np.zeros(0, np.float32))
    state: np.ndarray = field(default_factory=lambda: np.zeros(0, np.uint8))


def samples_due(prev_ns: int, now_ns: int, rate_hz: float) -> bool:
    """True when a sample instant n / rate_hz lies in (prev_ns, now_ns]."""
    period_ns = 1e9 / rate_hz
    return math.floor(now_ns / period_ns + 1e-6) > math.floor(prev_ns / period_ns + 1e-6)


class SensorSuite:
    """The four sensors of one UAV, each with its own random stream."""

    def __init__(self, spec: SensorsSpec, seed: int, uav_id: int) -> None:
        self.spec = spec
        self.rng_gps = stream(seed, "gps", uav_id)
        self.rng_alt = stream(seed, "altimeter", uav_id)
        self.rng_gyro = stream(seed, "gyro", uav_id)
        self.rng_fire = stream(seed, "fire_sensor", uav_id)

    def sample_gyro(self, stamp_ns: int, yaw_rate_radps: float) -> GyroSample | None:
        s = self.spec.gyro
        noise = self.rng_gyro.normal(0.0, s.sigma_radps)
        if self.rng_gyro.random() >= s.p_valid:
            return None
        return GyroSample(stamp_ns, yaw_rate_radps + noise)

    def sample_altimeter(self, stamp_ns: int, height_m: float) -> AltimeterSample | None:
        s = self.spec.altimeter
        noise = self.rng_alt.normal(0.0, s.sigma_m)
        valid = self.rng_alt.random() < s.p_valid
        if not valid or not (0.0 <= height_m <= s.max_range_m):
            return None
        return AltimeterSample(stamp_ns, height_m + noise, s.max_range_m)

    def sample_gps(self, stamp_ns: int, x_m: float, y_m: float) -> GpsSample | None:
        s = self.spec.gps
        n = self.rng_gps.normal(0.0, s.sigma_m, 2)
        if self.rng_gps.random() >= s.p_valid:
            return None
        return GpsSample(stamp_ns, x_m + n[0], y_m + n[1], s.sigma_m**2)

    def sample_fires(
        self, stamp_ns: int, x_m: float, y_m: float, seen: list[tuple[int, float, float, float]]
    ) -> list[FireDetectionSample]:
        """``seen``: (fire_id, x_m, y_m, extent_m) of the fires visible from (x_m, y_m)."""
        s = self.spec.fire
        out = []
        for fid, fx, fy, ext in seen:
            n = self.rng_fire.normal(0.0, 1.0, 3)
            if self.rng_fire.random() >= s.p_valid:
                continue
            mx = fx + s.position_sigma_m * n[0]
            my = fy + s.position_sigma_m * n[1]
            me = max(0.0, ext + s.extent_sigma_m * n[2])
            out.append(FireDetectionSample(stamp_ns, fid, mx, my, me, math.hypot(mx - x_m, my - y_m)))
        return out
