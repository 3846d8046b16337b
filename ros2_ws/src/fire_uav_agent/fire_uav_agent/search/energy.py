"""Two-regime cruise/turn energy model (CP III-D, Eq. 10).

``E = P_c * sum_{i in S} dt_i + gamma * P_c * sum_{j in T} dt_j``: constant cruise power ``P_c`` [W] on
straight segments, ``P_t = gamma * P_c`` on turns, ``gamma = 1.5`` (CP III-D). At the constant
airspeed ``v`` [m/s] the durations are lengths / v. The paper gives no value for ``P_c``; the default
(choice) is 1 kW, which only scales the cost through ``lambda`` (see :mod:`.evaluate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SearchConfigError
from .stc import CoveragePath, PathSamples


@dataclass(frozen=True)
class EnergyModel:
    """Parameters of Eq. 10."""

    cruise_power_w: float = 1000.0  # P_c [W]
    turn_factor: float = 1.5  # gamma [-], P_t = gamma * P_c
    speed_mps: float = 50.0  # constant airspeed v [m/s]

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cruise_power_w) and self.cruise_power_w > 0.0):
            raise SearchConfigError(f"cruise_power_w must be > 0, got {self.cruise_power_w}")
        if not (math.isfinite(self.turn_factor) and self.turn_factor >= 1.0):
            raise SearchConfigError(f"turn_factor must be >= 1, got {self.turn_factor}")
        if not (math.isfinite(self.speed_mps) and self.speed_mps > 0.0):
            raise SearchConfigError(f"speed_mps must be > 0, got {self.speed_mps}")

    def energy_j(self, cruise_time_s: float, turn_time_s: float) -> float:
        """Eq. 10 from the total cruise and turn durations [s] -> [J]."""
        if cruise_time_s < 0.0 or turn_time_s < 0.0:
            raise SearchConfigError("durations must be >= 0")
        return self.cruise_power_w * (cruise_time_s + self.turn_factor * turn_time_s)

    def segment_energy_j(self, straight_lengths_m: np.ndarray, turn_lengths_m: np.ndarray) -> float:
        """Eq. 10 summed over straight segments S and turns T given their lengths [m] -> [J]."""
        s = float(np.sum(straight_lengths_m))
        t = float(np.sum(turn_lengths_m))
        return self.energy_j(s / self.speed_mps, t / self.speed_mps)

    def path_energy_j(self, path: CoveragePath) -> float:
        """Exact Eq. 10 energy of one lap of a path [J]."""
        return self.segment_energy_j(
            np.array([path.straight_length_m]),
            np.array([path.turn_length_m]),
        )

    def sampled_energy_j(self, samples: PathSamples) -> float:
        """Eq. 10 energy of a sampled lap [J]: each sample stands for ``spacing_m`` of flight."""
        n_turn = int(np.count_nonzero(samples.is_turn))
        n_straight = len(samples.is_turn) - n_turn
        dt = samples.spacing_m / self.speed_mps
        return self.energy_j(n_straight * dt, n_turn * dt)
