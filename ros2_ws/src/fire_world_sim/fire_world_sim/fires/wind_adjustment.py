"""Wind adjustment factor: the 20-ft wind to the midflame wind, per cell.

Albini, F.A.; Baughman, R.G. 1979, INT-221, as Behave (``WindAdjustmentFactor``) and FlamMap
apply it (Andrews 2012, RMRS-GTR-266, Eqs. 1-2):

- the fraction of the canopy layer filled with crowns ``f = CC * CR / 3`` (conical crowns;
  CC canopy cover, CR crown ratio, both fractions);
- unsheltered (``CC == 0``, ``f < 0.05`` or canopy height < 6 ft):
  ``WAF = 1.83 / ln((20 + 0.36 H) / (0.13 H))`` with H the fuel bed depth [ft];
- sheltered: ``WAF = 0.555 / (sqrt(f H_c) ln((20 + 0.36 H_c) / (0.13 H_c)))`` with H_c the canopy
  height [ft].

Works on numpy arrays (one value per cell) and on scalars.
"""

from __future__ import annotations

import numpy as np

__all__ = ["M_TO_FT", "crown_fraction", "wind_adjustment_factor"]

M_TO_FT = 1.0 / 0.3048
MIN_SHELTER_FRACTION = 0.05
MIN_CANOPY_HEIGHT_FT = 6.0


def crown_fraction(canopy_cover: np.ndarray | float, crown_ratio: np.ndarray | float) -> np.ndarray:
    """``f = CC * CR / 3``: the volume fraction of the canopy layer occupied by crowns."""
    return np.asarray(canopy_cover, dtype=float) * np.asarray(crown_ratio, dtype=float) / 3.0


def wind_adjustment_factor(
    fuel_bed_depth_ft: np.ndarray | float,
    canopy_cover: np.ndarray | float = 0.0,
    canopy_height_m: np.ndarray | float = 0.0,
    crown_ratio: np.ndarray | float = 0.0,
) -> np.ndarray:
    """Midflame / 20-ft wind ratio per cell.

    ``fuel_bed_depth_ft`` [ft] (the fuel model's depth), ``canopy_cover`` and ``crown_ratio``
    [fractions 0-1], ``canopy_height_m`` [m]. Cells without fuel depth get 0 (nothing burns).
    """
    depth = np.asarray(fuel_bed_depth_ft, dtype=float)
    cc = np.asarray(canopy_cover, dtype=float)
    h_ft = np.asarray(canopy_height_m, dtype=float) * M_TO_FT
    f = crown_fraction(cc, crown_ratio)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(depth > 0, depth, 1.0)
        unsheltered = 1.83 / np.log((20.0 + 0.36 * d) / (0.13 * d))
        hc = np.where(h_ft > 0, h_ft, 1.0)
        fs = np.where(f > 0, f, 1.0)
        sheltered = 0.555 / (np.sqrt(fs * hc) * np.log((20.0 + 0.36 * hc) / (0.13 * hc)))
    is_sheltered = (cc > 0) & (f >= MIN_SHELTER_FRACTION) & (h_ft >= MIN_CANOPY_HEIGHT_FT)
    waf = np.where(is_sheltered, sheltered, unsheltered)
    return np.where(depth > 0, waf, 0.0)
