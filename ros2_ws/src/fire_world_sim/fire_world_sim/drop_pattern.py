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

**Coverage levels** (:func:`required_coverage_lpm2`). The fire services rate a drop by its
coverage level (CL), US gallons per 100 ft^2 (1 gal/100 ft^2 = 0.4074 L/m^2); the level needed
to hold a fire depends on its fuel model. Table 1 of the USDA FS MTDC airtanker drop guides
(e.g. Johnson & Jordan 2000, "Ground pattern performance of the Marsh Turbo Thrush",
0057-2835-MTDC; the same table in every guide of the series), by Fire Behavior Fuel Model
(Anderson 1982): CL 1: FBFM 1; CL 2: FBFM 2, 8, 9; CL 3: FBFM 3, 5, 11; CL 4: FBFM 10 (and
southern rough); CL 6: FBFM 4 (chaparral), 6; "greater than 6": FBFM 12, 13 (NWCG glossary,
"Coverage level": levels 1-6 for most fuel models, > 6 for heavy fuels). Our choices: FBFM 7
(southern rough, not in the table by number) gets 4, the table's southern-rough level; "> 6"
is taken as 8. The 40 Scott & Burgan (2005) models are mapped by family to the FBFM they
resemble (:data:`SCOTT_BURGAN_CL`). The table is for average fire intensity; the guides adjust
it "up or down depending on the actual fire intensity": not modelled here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

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
    "required_coverage_lpm2",
]

#: standard gravity [m/s^2]
G_MPS2 = 9.80665
#: 1 US gal / 100 ft^2 in L/m^2: 3.785411784 L / 9.290304 m^2
L_PER_M2_PER_CL = 3.785411784 / 9.290304
#: the lowest contour the drop guides draw (0.5 gal/100 ft^2): the edge of a pattern's footprint
MIN_FOOTPRINT_CL = 0.5

#: coverage level [gal/100 ft^2] by Anderson (1982) fire behavior fuel model (drop guides' Table 1)
ANDERSON_CL: dict[int, float] = {
    1: 1.0,  # short grass (NFDRS A, L, S)
    2: 2.0,  # timber with grass (C, T)
    3: 3.0,  # tall grass (N, sawgrass)
    4: 6.0,  # chaparral (B, O)
    5: 3.0,  # brush, green (F)
    6: 6.0,  # dormant brush (F, Q)
    7: 4.0,  # southern rough: the table's southern-rough level (choice, see the module text)
    8: 2.0,  # closed short-needle conifer (H, R)
    9: 2.0,  # long-needle conifer, hardwood litter (E, P, U)
    10: 4.0,  # timber with heavy dead litter (G)
    11: 3.0,  # light slash (K)
    12: 8.0,  # medium slash (J): "greater than 6", taken as 8
    13: 8.0,  # heavy slash (I): "greater than 6", taken as 8
}

#: Scott & Burgan (2005) models by family -> the Anderson model whose level they take (choice):
#: GR1-2 short grass (1), GR3-9 tall / dense grass (3); GS grass-shrub (2, sagebrush with grass);
#: SH1-4 low shrub (5), SH5-9 high-load shrub (4); TU1-3 timber understory (2), TU4-5 (10);
#: TL timber litter (8; TL 7-9 heavy litter: 10); SB1 (11), SB2 (12), SB3-4 (13).
_SB_AS_ANDERSON: dict[int, int] = {
    **{m: 1 for m in (101, 102)},
    **{m: 3 for m in range(103, 110)},
    **{m: 2 for m in range(121, 125)},
    **{m: 5 for m in range(141, 145)},
    **{m: 4 for m in range(145, 150)},
    **{m: 2 for m in (161, 162, 163)},
    **{m: 10 for m in (164, 165)},
    **{m: 8 for m in range(181, 187)},
    **{m: 10 for m in (187, 188, 189)},
    201: 11,
    202: 12,
    203: 13,
    204: 13,
}
SCOTT_BURGAN_CL: dict[int, float] = {m: ANDERSON_CL[a] for m, a in _SB_AS_ANDERSON.items()}


def coverage_level(fuel_model: int) -> float:
    """Coverage level [gal/100 ft^2] needed to hold a fire of average intensity in ``fuel_model``
    (Anderson 1-13 or Scott & Burgan 101-204); ``inf`` for a model that does not burn."""
    fm = int(fuel_model)
    if fm in ANDERSON_CL:
        return ANDERSON_CL[fm]
    return SCOTT_BURGAN_CL.get(fm, math.inf)


def required_coverage_lpm2(fuel: np.ndarray) -> np.ndarray:
    """Per cell of the fuel-model grid ``fuel``: the coverage [L/m^2] that puts a burning cell out."""
    out = np.full(np.shape(fuel), np.inf)
    for m in np.unique(fuel):
        out[fuel == m] = coverage_level(int(m)) * L_PER_M2_PER_CL
    return out


@dataclass(frozen=True)
class PatternModel:
    """Constants of (P1)-(P4): the spread sigma = ``sigma0_m`` + ``spread_per_m`` h [m], and the
    share of the load lost before reaching the ground (``loss_fraction``; 0: none modelled)."""

    sigma0_m: float = 2.0
    spread_per_m: float = 0.5
    loss_fraction: float = 0.0


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
    sigma = m.sigma0_m + m.spread_per_m * r.height_m
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
