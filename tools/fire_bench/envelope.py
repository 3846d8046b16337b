"""How far the world's truth flies beyond a fixed-wing envelope (docs/airframes.md).

A coordinated turn at airspeed v and bank phi turns at omega = g tan(phi) / v (Beard & McLain,
Eq. 9.14), so a truth sample with |omega| > g tan(phi_max) / v banks beyond phi_max. The bank a
sample needs is atan(|omega| v / g).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario.airframes import G_MPS2

from .errors import BenchError

__all__ = ["EnvelopeShare", "envelope_share", "needed_bank_deg"]


def needed_bank_deg(v_mps: float, omega_radps: float) -> float:
    """The bank [deg] of a coordinated turn at airspeed ``v_mps`` [m/s] and rate ``omega_radps``."""
    return math.degrees(math.atan(abs(omega_radps) * v_mps / G_MPS2))


@dataclass(frozen=True)
class EnvelopeShare:
    airborne: int  # airborne truth samples
    beyond: int  # of them, turning harder than bank_max_deg allows
    max_bank_deg: float  # hardest sample's bank [deg] (0 without airborne samples)

    @property
    def share(self) -> float:
        return self.beyond / self.airborne if self.airborne else 0.0


def envelope_share(samples: Iterable[tuple[int, float, float]], bank_max_deg: float) -> EnvelopeShare:
    """``samples``: (status, v [m/s], omega [rad/s]) of vehicle truth; only AIRBORNE ones count.

    A sample is beyond the envelope when |omega| > g tan(bank_max) / v (with v > 0).
    """
    if not 0 < bank_max_deg < 90:
        raise BenchError(f"bank_max_deg must be in (0, 90), got {bank_max_deg}")
    limit = math.tan(math.radians(bank_max_deg))
    air = beyond = 0
    worst = 0.0
    for status, v, omega in samples:
        if status != VehicleStatus.AIRBORNE:
            continue
        air += 1
        if abs(omega) * v / G_MPS2 > limit * (1 + 1e-9):
            beyond += 1
        worst = max(worst, needed_bank_deg(v, omega))
    return EnvelopeShare(air, beyond, worst)
