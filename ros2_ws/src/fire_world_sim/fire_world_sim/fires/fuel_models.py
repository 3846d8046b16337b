"""The 53 standard fire behaviour fuel models and the non-burnable codes 91-99.

- Anderson's 13 (Albini 1976, GTR INT-30; Anderson 1982, GTR INT-122), codes 1-13.
- Scott & Burgan's 40 (Scott, J.H.; Burgan, R.E. 2005, RMRS-GTR-153, Table 7), codes 101-204, with
  the dynamic transfer of live herbaceous load to a dead herbaceous class by its moisture (S&B 2005
  p. 8; applied in :func:`~.rothermel.spread_params`): ``dynamic`` is true for the models S&B mark
  (D). Values as Behave carries them (loads to its rounding); TL5 has no live load.
- Non-burnable (Scott & Burgan 2005 p. 11; LANDFIRE FBFM13/FBFM40): 91 urban, 92 snow/ice, 93
  agriculture, 98 open water, 99 barren; 94-97 are reserved and treated as non-burnable too.

Values in the customary units of the sources: loads in tons/acre, surface-area-to-volume
ratios in 1/ft, depth in ft, moisture of extinction as a fraction. The 10-h and 100-h
classes have SAV 109 and 30 1/ft; heat content 8000 Btu/lb for every class (9000 for GR6, as
S&B 2005 and Behave); particle density 32 lb/ft^3; total mineral content 0.0555; effective
mineral content 0.010. Model 7's live woody SAV is 1500 1/ft as in Behave (Anderson 1982 prints
1550); with 1550 the head rate is 0.5-1.2 % below Behave's.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

__all__ = [
    "ANDERSON_13",
    "FUEL_MODELS",
    "NONBURNABLE",
    "SCOTT_BURGAN_40",
    "FuelModel",
    "fuel_model",
    "is_burnable",
    "known_fuel_code",
]

TONS_PER_ACRE_TO_LB_PER_FT2 = 2000.0 / 43560.0


@dataclass(frozen=True)
class FuelModel:
    number: int
    name: str
    load_1h_tpa: float
    load_10h_tpa: float
    load_100h_tpa: float
    load_live_herb_tpa: float
    load_live_woody_tpa: float
    sav_1h_per_ft: float
    sav_live_herb_per_ft: float
    sav_live_woody_per_ft: float
    depth_ft: float
    mx_dead: float  # moisture of extinction, dead fuel [fraction]
    heat_btu_per_lb: float = 8000.0
    sav_10h_per_ft: float = 109.0
    sav_100h_per_ft: float = 30.0
    code: str = ""  # short code (FM1, GR1, ...)
    dynamic: bool = False  # herbaceous load cures to dead by its moisture (Scott & Burgan 2005)


_M = FuelModel
FUEL_MODELS: dict[int, FuelModel] = {
    1: _M(1, "short grass (1 ft)", 0.74, 0.0, 0.0, 0.0, 0.0, 3500, 1500, 1500, 1.0, 0.12),
    2: _M(2, "timber (grass and understory)", 2.0, 1.0, 0.5, 0.5, 0.0, 3000, 1500, 1500, 1.0, 0.15),
    3: _M(3, "tall grass (2.5 ft)", 3.01, 0.0, 0.0, 0.0, 0.0, 1500, 1500, 1500, 2.5, 0.25),
    4: _M(4, "chaparral (6 ft)", 5.01, 4.01, 2.0, 0.0, 5.01, 2000, 1500, 1500, 6.0, 0.20),
    5: _M(5, "brush (2 ft)", 1.0, 0.5, 0.0, 0.0, 2.0, 2000, 1500, 1500, 2.0, 0.20),
    6: _M(6, "dormant brush, hardwood slash", 1.5, 2.5, 2.0, 0.0, 0.0, 1750, 1500, 1500, 2.5, 0.25),
    7: _M(7, "southern rough", 1.13, 1.87, 1.5, 0.0, 0.37, 1750, 1500, 1500, 2.5, 0.40),  # Behave: 1500
    8: _M(8, "closed timber litter", 1.5, 1.0, 2.5, 0.0, 0.0, 2000, 1500, 1500, 0.2, 0.30),
    9: _M(9, "hardwood litter", 2.92, 0.41, 0.15, 0.0, 0.0, 2500, 1500, 1500, 0.2, 0.25),
    10: _M(10, "timber (litter and understory)", 3.01, 2.0, 5.01, 0.0, 2.0, 2000, 1500, 1500, 1.0, 0.25),
    11: _M(11, "light logging slash", 1.5, 4.51, 5.51, 0.0, 0.0, 1500, 1500, 1500, 1.0, 0.15),
    12: _M(12, "medium logging slash", 4.01, 14.03, 16.53, 0.0, 0.0, 1500, 1500, 1500, 2.3, 0.20),
    13: _M(13, "heavy logging slash", 7.01, 23.04, 28.05, 0.0, 0.0, 1500, 1500, 1500, 3.0, 0.25),
}
ANDERSON_13: dict[int, FuelModel] = {n: replace(m, code=f"FM{n}") for n, m in FUEL_MODELS.items()}
FUEL_MODELS.update(ANDERSON_13)


def _S(
    number: int,
    code: str,
    name: str,
    *values: float,
    heat_btu_per_lb: float = 8000.0,
    dynamic: bool = False,
) -> FuelModel:
    l1, l10, l100, lh, lw, s1, sh, sw, depth, mx = values
    return FuelModel(
        number,
        name,
        l1,
        l10,
        l100,
        lh,
        lw,
        s1,
        sh,
        sw,
        depth,
        mx,
        heat_btu_per_lb,
        code=code,
        dynamic=dynamic,
    )


# number: code, name, loads 1h/10h/100h/herb/woody [t/ac], SAV 1h/herb/woody [1/ft], depth [ft], Mx
# (a table: one fuel model a row, as Scott & Burgan 2005 print it; left as it is by ruff format)
# fmt: off
SCOTT_BURGAN_40: dict[int, FuelModel] = {
    101: _S(101, "GR1", "Short, sparse, dry climate grass", 0.1, 0, 0, 0.3, 0, 2200, 2000, 1500, 0.4, 0.15, dynamic=True),
    102: _S(102, "GR2", "Low load, dry climate grass", 0.1, 0, 0, 1, 0, 2000, 1800, 1500, 1, 0.15, dynamic=True),
    103: _S(103, "GR3", "Low load, very coarse, humid climate grass", 0.1, 0.4, 0, 1.5, 0, 1500, 1300, 1500, 2, 0.3, dynamic=True),
    104: _S(104, "GR4", "Moderate load, dry climate grass", 0.25, 0, 0, 1.9, 0, 2000, 1800, 1500, 2, 0.15, dynamic=True),
    105: _S(105, "GR5", "Low load, humid climate grass", 0.4, 0, 0, 2.5, 0, 1800, 1600, 1500, 1.5, 0.4, dynamic=True),
    106: _S(106, "GR6", "Moderate load, humid climate grass", 0.1, 0, 0, 3.4, 0, 2200, 2000, 1500, 1.5, 0.4, heat_btu_per_lb=9000.0, dynamic=True),
    107: _S(107, "GR7", "High load, dry climate grass", 1, 0, 0, 5.4, 0, 2000, 1800, 1500, 3, 0.15, dynamic=True),
    108: _S(108, "GR8", "High load, very coarse, humid climate grass", 0.5, 1, 0, 7.3, 0, 1500, 1300, 1500, 4, 0.3, dynamic=True),
    109: _S(109, "GR9", "Very high load, humid climate grass", 1, 1, 0, 9, 0, 1800, 1600, 1500, 5, 0.4, dynamic=True),
    121: _S(121, "GS1", "Low load, dry climate grass-shrub", 0.2, 0, 0, 0.5, 0.65, 2000, 1800, 1800, 0.9, 0.15, dynamic=True),
    122: _S(122, "GS2", "Moderate load, dry climate grass-shrub", 0.5, 0.5, 0, 0.6, 1, 2000, 1800, 1800, 1.5, 0.15, dynamic=True),
    123: _S(123, "GS3", "Moderate load, humid climate grass-shrub", 0.3, 0.25, 0, 1.45, 1.25, 1800, 1600, 1600, 1.8, 0.4, dynamic=True),
    124: _S(124, "GS4", "High load, humid climate grass-shrub", 1.9, 0.3, 0.1, 3.4, 7.1, 1800, 1600, 1600, 2.1, 0.4, dynamic=True),
    141: _S(141, "SH1", "Low load, dry climate shrub", 0.25, 0.25, 0, 0.15, 1.3, 2000, 1800, 1600, 1, 0.15, dynamic=True),
    142: _S(142, "SH2", "Moderate load, dry climate shrub", 1.35, 2.4, 0.75, 0, 3.85, 2000, 1800, 1600, 1, 0.15, dynamic=False),
    143: _S(143, "SH3", "Moderate load, humid climate shrub", 0.45, 3, 0, 0, 6.2, 1600, 1800, 1400, 2.4, 0.4, dynamic=False),
    144: _S(144, "SH4", "Low load, humid climate timber-shrub", 0.85, 1.15, 0.2, 0, 2.55, 2000, 1800, 1600, 3, 0.3, dynamic=False),
    145: _S(145, "SH5", "High load, dry climate shrub", 3.6, 2.1, 0, 0, 2.9, 750, 1800, 1600, 6, 0.15, dynamic=False),
    146: _S(146, "SH6", "Low load, humid climate shrub", 2.9, 1.45, 0, 0, 1.4, 750, 1800, 1600, 2, 0.3, dynamic=False),
    147: _S(147, "SH7", "Very high load, dry climate shrub", 3.5, 5.3, 2.2, 0, 3.4, 750, 1800, 1600, 6, 0.15, dynamic=False),
    148: _S(148, "SH8", "High load, humid climate shrub", 2.05, 3.4, 0.85, 0, 4.35, 750, 1800, 1600, 3, 0.4, dynamic=False),
    149: _S(149, "SH9", "Very high load, humid climate shrub", 4.5, 2.45, 0, 1.55, 7, 750, 1800, 1500, 4.4, 0.4, dynamic=True),
    161: _S(161, "TU1", "Light load, dry climate timber-grass-shrub", 0.2, 0.9, 1.5, 0.2, 0.9, 2000, 1800, 1600, 0.6, 0.2, dynamic=True),
    162: _S(162, "TU2", "Moderate load, humid climate timber-shrub", 0.95, 1.8, 1.25, 0, 0.2, 2000, 1800, 1600, 1, 0.3, dynamic=False),
    163: _S(163, "TU3", "Moderate load, humid climate timber-grass-shrub", 1.1, 0.15, 0.25, 0.65, 1.1, 1800, 1600, 1400, 1.3, 0.3, dynamic=True),
    164: _S(164, "TU4", "Dwarf conifer understory", 4.5, 0, 0, 0, 2, 2300, 1800, 2000, 0.5, 0.12, dynamic=False),
    165: _S(165, "TU5", "Very high load, dry climate timber-shrub", 4, 4, 3, 0, 3, 1500, 1800, 750, 1, 0.25, dynamic=False),
    181: _S(181, "TL1", "Low load, compact conifer litter", 1, 2.2, 3.6, 0, 0, 2000, 1800, 1600, 0.2, 0.3, dynamic=False),
    182: _S(182, "TL2", "Low load broadleaf litter", 1.4, 2.3, 2.2, 0, 0, 2000, 1800, 1600, 0.2, 0.25, dynamic=False),
    183: _S(183, "TL3", "Moderate load conifer litter", 0.5, 2.2, 2.8, 0, 0, 2000, 1800, 1600, 0.3, 0.2, dynamic=False),
    184: _S(184, "TL4", "Small downed logs", 0.5, 1.5, 4.2, 0, 0, 2000, 1800, 1600, 0.4, 0.25, dynamic=False),
    185: _S(185, "TL5", "High load conifer litter", 1.15, 2.5, 4.4, 0, 0, 2000, 1800, 1600, 0.6, 0.25, dynamic=False),
    186: _S(186, "TL6", "High load broadleaf litter", 2.4, 1.2, 1.2, 0, 0, 2000, 1800, 1600, 0.3, 0.25, dynamic=False),
    187: _S(187, "TL7", "Large downed logs", 0.3, 1.4, 8.1, 0, 0, 2000, 1800, 1600, 0.4, 0.25, dynamic=False),
    188: _S(188, "TL8", "Long-needle litter", 5.8, 1.4, 1.1, 0, 0, 1800, 1800, 1600, 0.3, 0.35, dynamic=False),
    189: _S(189, "TL9", "Very high load broadleaf litter", 6.65, 3.3, 4.15, 0, 0, 1800, 1800, 1600, 0.6, 0.35, dynamic=False),
    201: _S(201, "SB1", "Low load activity fuel", 1.5, 3, 11, 0, 0, 2000, 1800, 1600, 1, 0.25, dynamic=False),
    202: _S(202, "SB2", "Moderate load activity or low load blowdown", 4.5, 4.25, 4, 0, 0, 2000, 1800, 1600, 1, 0.25, dynamic=False),
    203: _S(203, "SB3", "High load activity fuel or moderate load blowdown", 5.5, 2.75, 3, 0, 0, 2000, 1800, 1600, 1.2, 0.25, dynamic=False),
    204: _S(204, "SB4", "High load blowdown", 5.25, 3.5, 5.25, 0, 0, 2000, 1800, 1600, 2.7, 0.25, dynamic=False),
}
# fmt: on
FUEL_MODELS.update(SCOTT_BURGAN_40)

NONBURNABLE: dict[int, str] = {
    91: "urban",
    92: "snow/ice",
    93: "agriculture",
    94: "reserved",
    95: "reserved",
    96: "reserved",
    97: "reserved",
    98: "open water",
    99: "barren",
}


def fuel_model(number: int) -> FuelModel:
    try:
        return FUEL_MODELS[number]
    except KeyError:
        raise ValueError(
            f"unknown fuel model {number}; expected 1-13, 101-204 (standard) or 91-99 (non-burnable)"
        ) from None


def is_burnable(number: int) -> bool:
    """True for the 53 standard models, False for 91-99; ValueError for any other code."""
    if number in FUEL_MODELS:
        return True
    if number in NONBURNABLE:
        return False
    raise ValueError(
        f"unknown fuel model {number}; expected 1-13, 101-204 (standard) or 91-99 (non-burnable)"
    )


def known_fuel_code(number: int) -> bool:
    return number in FUEL_MODELS or number in NONBURNABLE
