"""A water drop as a ground pattern with a coverage level per cell (issue 36; docs/suppression.md).

No ROS here: pure functions over numpy. Frames: map (x east, y north, metres); headings
counter-clockwise from +x [rad].

**Pattern** (:func:`pattern_of`). A tank of ``volume_l`` [L] released at a constant flow rate
``flow_lps`` [L/s] empties in T = V / Q; the aircraft covers the ground line

    L = v T = v V / Q                                                               (P1)

at ground speed v (the USFS drop guides: "increasing airspeed increases the line length while
reducing the coverage level"; the constant-flow tanks set Q from the coverage level wanted and
the ground speed). Across the line the liquid lies as a Gaussian (Legendre, Becker, Almeras &
Chassagne 2014, "Air tanker drop patterns", Int. J. Wildland Fire 23(2):272-280: "the liquid on
the ground follows a Gaussian distribution" across the pattern); we take the same spread at
both ends of the line, so that the coverage [L/m^2] at along-track s and cross-track n is

    c(s, n) = (V (1 - loss) / L) [Phi(s / sigma) - Phi((s - L) / sigma)] phi(n / sigma) / sigma   (P2)

(Phi, phi the standard normal CDF and density): a line of V/L litres per metre smeared by the
spread sigma; it integrates to V (1 - loss) over the plane, and its peak on the centre line is
(Q / v) (1 - loss) / (sqrt(2 pi) sigma) for L >> sigma -- coverage proportional to Q / v, as the
constant-flow tanks are set.

The spread grows with the release height h (the drop guides: "increasing the drop height
gradually widens the drop while decreasing the coverage levels"):

    sigma(h) = sigma_0 + k_h h                                                      (P3)

A CHOICE, not a fit: sigma_0 = 2 m, k_h = 0.5 make the effective width sqrt(2 pi) sigma about
28 m at h = 18 m (60 ft), the width that the AT-802F's constant-flow settings imply (USDA FS
MTDC drop guide of the Snow Air Tractor AT-802F: settings "coverage level 0.5 to 4" at 77 to
450 gal/s flown at 78-87 kn give Q / (v CL) = 24-33 m).

**Drift.** The liquid is taken to lose its speed relative to the air at once on release (its
forward throw is not modelled) and to fall freely, so that it lands after

    t_fall = sqrt(2 h / g)                                                          (P4)

drifted by the wind times t_fall. Drag makes the real fall slower and the drift larger: the
drift here is a lower bound.

**Coverage levels** (:func:`required_coverage_lpm2`), the spread law's constants
(:class:`PatternModel`) and the peak coverage (P5) live in :mod:`fire_uav_common.drop_coverage`,
where the agents read them too (a UAV skips the low drop run when its pattern cannot reach the
level of the fuel under its aim: ``fire_uav_agent.guidance``); they are re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.drop_coverage import (
    ANDERSON_CL,
    L_PER_M2_PER_CL,
    SCOTT_BURGAN_CL,
    PatternModel,
    coverage_level,
    peak_coverage_lpm2,
    required_coverage_lpm2,
)

from .errors import ConfigError

__all__ = [
    "ANDERSON_CL",
    "G_MPS2",
    "L_PER_M2_PER_CL",
    "MIN_FOOTPRINT_CL",
    "SCOTT_BURGAN_CL",
    "DropPattern",
    "PatternModel",
    "Release",
    "coverage_lpm2",
    "coverage_level",
    "pattern_of",
    "peak_coverage_lpm2",
    "required_coverage_lpm2",
]

#: standard gravity [m/s^2]
G_MPS2 = 9.80665
#: the lowest contour the drop guides draw (0.5 gal/100 ft^2): the edge of a pattern's footprint
MIN_FOOTPRINT_CL = 0.5


@dataclass(frozen=True)
class Release:
    """One load released: where, whither and how (map frame).

    ``x_m, y_m`` where the release starts; ``heading_rad`` the ground track; ``ground_speed_mps``
    along it; ``height_m`` above the ground; ``volume_l`` the load [L] (water: 1 kg = 1 L);
    ``flow_lps`` the tank's flow rate [L/s]; ``wind_mps`` the wind (east, north) it falls through.
    """

    x_m: float
    y_m: float
    heading_rad: float
    ground_speed_mps: float
    height_m: float
    volume_l: float
    flow_lps: float
    wind_mps: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class DropPattern:
    """The ground pattern (P2): a line from (x0, y0) to (x1, y1) [m] of ``volume_l`` litres on the
    ground, spread by ``sigma_m``; ``release`` the release it came from."""

    x0_m: float
    y0_m: float
    x1_m: float
    y1_m: float
    sigma_m: float
    volume_l: float
    release: Release

    @property
    def length_m(self) -> float:
        return math.hypot(self.x1_m - self.x0_m, self.y1_m - self.y0_m)

    @property
    def peak_lpm2(self) -> float:
        """Coverage [L/m^2] at the middle of the centre line."""
        mid_x, mid_y = 0.5 * (self.x0_m + self.x1_m), 0.5 * (self.y0_m + self.y1_m)
        return float(coverage_lpm2(self, np.array([mid_x]), np.array([mid_y]))[0])

    def bounds_m(self, n_sigma: float = 4.0) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) [m] holding all but a ~1e-4 share of the water (4 sigma)."""
        r = n_sigma * self.sigma_m
        return (
            min(self.x0_m, self.x1_m) - r,
            max(self.x0_m, self.x1_m) + r,
            min(self.y0_m, self.y1_m) - r,
            max(self.y0_m, self.y1_m) + r,
        )


def pattern_of(release: Release, model: PatternModel | None = None) -> DropPattern:
    """The ground pattern of ``release`` by (P1), (P3) and (P4). Raises ValueError for a non-positive
    flow rate or spread, or a negative speed, height or volume."""
    m = model or PatternModel()
    r = release
    if not r.flow_lps > 0:
        raise ConfigError(f"flow_lps must be > 0, got {r.flow_lps}")
    if r.ground_speed_mps < 0 or r.height_m < 0 or r.volume_l < 0:
        raise ConfigError("ground_speed_mps, height_m and volume_l must be >= 0")
    sigma = m.sigma_m(r.height_m)  # (P3)
    if not sigma > 0:
        raise ConfigError(f"spread sigma must be > 0, got {sigma}")
    length = r.ground_speed_mps * r.volume_l / r.flow_lps  # (P1)
    t_fall = math.sqrt(2.0 * r.height_m / G_MPS2)  # (P4)
    x0 = r.x_m + r.wind_mps[0] * t_fall
    y0 = r.y_m + r.wind_mps[1] * t_fall
    c, s = math.cos(r.heading_rad), math.sin(r.heading_rad)
    return DropPattern(
        x0, y0, x0 + length * c, y0 + length * s, sigma, r.volume_l * (1.0 - m.loss_fraction), r
    )


_erf = np.frompyfunc(math.erf, 1, 1)


def _phi_cdf(z: np.ndarray) -> np.ndarray:
    return 0.5 * (1.0 + np.asarray(_erf(z / math.sqrt(2.0)), dtype=float))


def coverage_lpm2(p: DropPattern, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
    """Coverage (P2) [L/m^2] of pattern ``p`` at the points (x_m, y_m) [m] (arrays, broadcast)."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    sig = p.sigma_m
    length = p.length_m
    h = p.release.heading_rad
    ux, uy = math.cos(h), math.sin(h)
    dx, dy = x - p.x0_m, y - p.y0_m
    s = dx * ux + dy * uy  # along the track from the start [m]
    n = -dx * uy + dy * ux  # across it [m]
    across = np.exp(-0.5 * (n / sig) ** 2) / (math.sqrt(2.0 * math.pi) * sig)  # [1/m]
    if length > 1e-6 * sig:
        along = (_phi_cdf(s / sig) - _phi_cdf((s - length) / sig)) / length  # [1/m]
    else:  # a release at no ground speed: a round Gaussian heap
        along = np.exp(-0.5 * (s / sig) ** 2) / (math.sqrt(2.0 * math.pi) * sig)
    return p.volume_l * along * across
