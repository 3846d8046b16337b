"""Angle helpers shared by the world and the agents (yaw is counter-clockwise from +x)."""

from __future__ import annotations

import math

__all__ = ["wrap_angle"]


def wrap_angle(a: float) -> float:
    """Wrap an angle [rad] to (-pi, pi]."""
    w = math.fmod(a + math.pi, 2.0 * math.pi)
    if w <= 0.0:
        w += 2.0 * math.pi
    return w - math.pi
