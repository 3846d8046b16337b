"""Terrain elevation E(x, y) (FF Eq. 12), shared by the world (truth) and the agents (a priori map).

A terrain is a base plane plus Gaussian hills; lakes are flat discs at the local elevation.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import ArgumentError

__all__ = ["Hill", "Lake", "Terrain"]


@dataclass(frozen=True)
class Hill:
    """Gaussian hill: height_m * exp(-|q - c|^2 / (2 sigma_m^2))."""

    x_m: float
    y_m: float
    height_m: float
    sigma_m: float

    def __post_init__(self) -> None:
        if not self.sigma_m > 0:
            raise ArgumentError(f"hill sigma_m must be > 0, got {self.sigma_m}")


@dataclass(frozen=True)
class Lake:
    """Water source: a disc of diameter_m centred at (x_m, y_m)."""

    x_m: float
    y_m: float
    diameter_m: float

    def __post_init__(self) -> None:
        if not self.diameter_m > 0:
            raise ArgumentError(f"lake diameter_m must be > 0, got {self.diameter_m}")

    def contains(self, x_m: float, y_m: float) -> bool:
        return (x_m - self.x_m) ** 2 + (y_m - self.y_m) ** 2 <= (self.diameter_m / 2) ** 2


@dataclass(frozen=True)
class Terrain:
    """E(x, y) = base_m + slope_x * x + slope_y * y + sum of hills [m above datum]."""

    base_m: float = 0.0
    slope_x: float = 0.0  # [m/m] rise per metre east
    slope_y: float = 0.0  # [m/m] rise per metre north
    hills: tuple[Hill, ...] = field(default_factory=tuple)

    def elevation(self, x_m: float | np.ndarray, y_m: float | np.ndarray) -> float | np.ndarray:
        """Ground height [m] at (x_m, y_m), map frame; vectorised over arrays."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        e = self.base_m + self.slope_x * x + self.slope_y * y
        for h in self.hills:
            e = e + h.height_m * np.exp(-((x - h.x_m) ** 2 + (y - h.y_m) ** 2) / (2 * h.sigma_m**2))
        return float(e) if e.ndim == 0 else e

    def gradient(self, x_m: float, y_m: float, eps_m: float = 0.5) -> tuple[float, float]:
        """(dE/dx, dE/dy) [m/m] by central differences."""
        dx = (self.elevation(x_m + eps_m, y_m) - self.elevation(x_m - eps_m, y_m)) / (2 * eps_m)
        dy = (self.elevation(x_m, y_m + eps_m) - self.elevation(x_m, y_m - eps_m)) / (2 * eps_m)
        return float(dx), float(dy)

    @classmethod
    def from_dict(cls, d: dict) -> Terrain:
        """Build from a scenario's ``terrain:`` mapping (keys: base_m, slope_x, slope_y, hills)."""
        hills = tuple(Hill(**h) for h in d.get("hills", []) or [])
        return cls(
            base_m=float(d.get("base_m", 0.0)),
            slope_x=float(d.get("slope_x", 0.0)),
            slope_y=float(d.get("slope_y", 0.0)),
            hills=hills,
        )
