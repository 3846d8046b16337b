"""The 13 standard fire behaviour fuel models (Albini 1976, GTR INT-30; Anderson 1982, GTR INT-122).

Values in the customary units of the sources: loads in tons/acre, surface-area-to-volume
ratios in 1/ft, depth in ft, moisture of extinction as a fraction. The 10-h and 100-h
classes have SAV 109 and 30 1/ft; heat content 8000 Btu/lb for every class; particle density
32 lb/ft^3; total mineral content 0.0555; effective mineral content 0.010. Model 7's live woody
SAV is 1500 1/ft as in Behave (Anderson 1982 prints 1550); with 1550 the head rate is 0.5-1.2 %
below Behave's.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FUEL_MODELS", "FuelModel", "fuel_model"]

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


def fuel_model(number: int) -> FuelModel:
    try:
        return FUEL_MODELS[number]
    except KeyError:
        raise ValueError(f"unknown fuel model {number}; expected one of {sorted(FUEL_MODELS)}") from None
