"""What a water drop's ground pattern needs and gives, shared by the world and the agents (no ROS).

The world lays each drop as a ground pattern (``fire_world_sim.drop_pattern``, equations
(P1)-(P4) there, issue 36; docs/suppression.md); an agent decides from the same numbers whether
its own pattern can put a fuel out at all (``fire_uav_agent.guidance.Guide``). Both read them
here: the fire services' coverage levels by fuel model, the spread law (P3) and the peak
coverage of a pattern (P2 on the centre line, at the middle of the line). The agents may not
import the world (docs/architecture.md), so this module is the one home of these numbers.

**Coverage levels** (:func:`coverage_level`). The fire services rate a drop by its coverage
level (CL), US gallons per 100 ft^2 (1 gal/100 ft^2 = 0.4074 L/m^2); the level needed to hold a
fire depends on its fuel model. Table 1 of the USDA FS MTDC airtanker drop guides (e.g. Johnson
& Jordan 2000, "Ground pattern performance of the Marsh Turbo Thrush", 0057-2835-MTDC; the same
table in every guide of the series), by Fire Behavior Fuel Model (Anderson 1982): CL 1: FBFM 1;
CL 2: FBFM 2, 8, 9; CL 3: FBFM 3, 5, 11; CL 4: FBFM 10 (and southern rough); CL 6: FBFM 4
(chaparral), 6; "greater than 6": FBFM 12, 13 (NWCG glossary, "Coverage level": levels 1-6 for
most fuel models, > 6 for heavy fuels). Our choices: FBFM 7 (southern rough, not in the table by
number) gets 4, the table's southern-rough level; "> 6" is taken as 8. The 40 Scott & Burgan
(2005) models are mapped by family to the FBFM they resemble (:data:`SCOTT_BURGAN_CL`). The
table is for average fire intensity; the guides adjust it "up or down depending on the actual
fire intensity": not modelled here.

**Peak coverage** (:func:`peak_coverage_lpm2`). A load V [L] at flow rate Q [L/s] and ground
speed v lies on a line L = v V / Q (P1) spread across by sigma(h) = sigma_0 + k_h h (P3); on the
centre line at the middle of the line (P2) gives

    c_peak = (V (1 - loss) / L) erf(L / (2 sqrt(2) sigma)) / (sqrt(2 pi) sigma)          (P5)

-> (Q / v) (1 - loss) / (sqrt(2 pi) sigma) for L >> sigma, and V (1 - loss) / (2 pi sigma^2)
for a release at no ground speed (a round heap). No point of the pattern gets more.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import ArgumentError
from .scenario.ground import landscape_of
from .scenario.types import Raster

__all__ = [
    "ANDERSON_CL",
    "L_PER_M2_PER_CL",
    "SCOTT_BURGAN_CL",
    "CoverageLevels",
    "PatternModel",
    "coverage_level",
    "coverage_levels_of",
    "peak_coverage_lpm2",
    "required_coverage_lpm2",
]

#: 1 US gal / 100 ft^2 in L/m^2: 3.785411784 L / 9.290304 m^2
L_PER_M2_PER_CL = 3.785411784 / 9.290304

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

    def sigma_m(self, height_m: float) -> float:
        """The spread (P3) [m] of a release ``height_m`` [m] above the ground."""
        return self.sigma0_m + self.spread_per_m * height_m


def peak_coverage_lpm2(
    volume_l: float,
    flow_lps: float,
    ground_speed_mps: float,
    height_m: float,
    model: PatternModel | None = None,
) -> float:
    """The most coverage [L/m^2] a release's pattern lays anywhere (P5): ``volume_l`` [L] at
    ``flow_lps`` [L/s], ``ground_speed_mps`` [m/s], ``height_m`` [m] above the ground. 0 for no
    load or no flow."""
    m = model or PatternModel()
    if not volume_l > 0 or not flow_lps > 0:
        return 0.0
    sigma = m.sigma_m(height_m)
    if not sigma > 0:
        raise ArgumentError(f"spread sigma must be > 0, got {sigma}")
    v = volume_l * (1.0 - m.loss_fraction)
    length = max(ground_speed_mps, 0.0) * volume_l / flow_lps  # (P1)
    if length > 1e-6 * sigma:
        along = math.erf(length / (2.0 * math.sqrt(2.0) * sigma)) / length  # [1/m]
    else:  # a release at no ground speed: a round Gaussian heap
        along = 1.0 / (math.sqrt(2.0 * math.pi) * sigma)
    return v * along / (math.sqrt(2.0 * math.pi) * sigma)


@dataclass(frozen=True)
class CoverageLevels:
    """The coverage level [gal/100 ft^2] each place's fuel needs, as the fuel map has it (map frame).

    ``base_cl`` everywhere, but in a ``patches`` rectangle (x_min, x_max, y_min, y_max [m], level)
    -- the last one holding the point wins, as the raster fire lays its fuel patches -- or, with
    ``grid`` (levels per cell, row 0 the southern row, cells of ``cell_m`` from (``x0_m``,
    ``y0_m``)), the grid's cell (``base_cl`` outside it). ``inf``: nothing burns there.
    """

    base_cl: float = 1.0
    patches: tuple[tuple[float, float, float, float, float], ...] = ()
    grid: np.ndarray | None = field(default=None, repr=False, compare=False)
    x0_m: float = 0.0
    y0_m: float = 0.0
    cell_m: float = 1.0

    def at(self, x_m: float, y_m: float) -> float:
        """The level [gal/100 ft^2] the fuel at (``x_m``, ``y_m``) [m] needs."""
        if self.grid is not None:
            ny, nx = self.grid.shape
            j = math.floor((x_m - self.x0_m) / self.cell_m)
            i = math.floor((y_m - self.y0_m) / self.cell_m)
            if 0 <= i < ny and 0 <= j < nx:
                return float(self.grid[i, j])
            return self.base_cl
        level = self.base_cl
        for x0, x1, y0, y1, cl in self.patches:
            if x0 <= x_m < x1 and y0 <= y_m < y1:
                level = cl
        return level


def coverage_levels_of(raster: Raster | None) -> CoverageLevels | None:
    """The levels of a raster fire's fuel map (``fires.raster``: its ``fuel_model`` with its
    ``fuel_patches``, or its landscape's fuel layer); None without a raster fire. The fuel map is
    a-priori knowledge of the ground, as the terrain is (LANDFIRE publishes both), not of the fire."""
    if raster is None:
        return None
    if raster.landscape is not None:
        land = landscape_of(raster.landscape)
        levels = required_coverage_lpm2(np.asarray(land.fuel)[::-1]) / L_PER_M2_PER_CL  # row 0 south
        levels.flags.writeable = False
        o = raster.origin  # the grid's south-west corner in the map frame, as the raster fire has it
        return CoverageLevels(math.inf, (), levels, float(o.x_m), float(o.y_m), float(land.cell_size_m))
    patches = tuple(
        (p.x_min_m, p.x_max_m, p.y_min_m, p.y_max_m, coverage_level(p.fuel_model))
        for p in raster.fuel_patches
    )
    return CoverageLevels(coverage_level(raster.fuel_model), patches)
