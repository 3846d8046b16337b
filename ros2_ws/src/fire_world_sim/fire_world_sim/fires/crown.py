"""Crown fire: initiation, spread and fire type per cell (vectorised numpy).

- Initiation (Van Wagner 1977, Eq. 4): the critical surface fireline intensity
  ``I_0 = (0.010 CBH (460 + 25.9 FMC))^1.5`` [kW/m], CBH canopy base height [m], FMC foliar
  moisture [%]. A surface fire with Byram's intensity ``I_B >= I_0`` starts a crown fire.
- Active spread (Rothermel 1991, RP-438): ``R_cactive = 3.34 R_10``, with R_10 the surface head
  rate of fuel model 10 at the scenario's moistures, slope and a wind adjustment factor of 0.4
  on the 20-ft wind (as Behave's ``Crown`` computes it).
- Critical active rate (Van Wagner 1977, Eq. 9; Scott & Reinhardt 2001 Eq. 11):
  ``R'_active = 3.0 / CBD`` [m/min], CBD canopy bulk density [kg/m^3].
- Fire type, FlamMap's "Finney" method (Finney 1998, RMRS-RP-4; Scott & Reinhardt 2001 p. 10):
  surface if ``I_B < I_0``; else active if ``R_cactive >= R'_active``, else passive. Unlike Scott &
  Reinhardt's own method no "conditional" class: a fire that does not initiate stays surface.
- Crown fraction burned (Scott & Reinhardt 2001 Eq. 28, linear, as Behave applies it; not Van
  Wagner's 1993 exponential form FARSITE used): ``CFB = (R_s - R'_init) / (R'_SA - R'_init)`` with
  ``R'_init = 60 I_0 / H_A`` (Eq. 12) and R'_SA the surface rate at the crowning-index wind
  O'_active (Eq. 20; computed in :mod:`.behavior`); 1 for active.
- Final rate (Scott & Reinhardt 2001 Eq. 23): passive ``R_s + CFB (R_cactive - R_s)``; active
  ``R_cactive``, also where a fast surface fire (SH5 in wind) outruns it, as Behave does.
- Intensity (Scott & Reinhardt 2001 Eq. 22): ``I = R (H_A + CFB CBD (CH - CBH) H_c) / 60`` with the
  canopy fuel's heat content H_c = 8000 Btu/lb = 18,608 kJ/kg as Behave takes it (S&R print 18,000;
  with 18,000 an active fire's intensity is 2 % below Behave's); flame length of a crown fire
  (passive or active) from Thomas (1963), ``L = 0.2 I^(2/3)`` in feet and Btu/ft/s as Rothermel
  (1991) and Behave use it (``0.0266 I^(2/3)`` in m and kW/m).

All inputs in SI: rates [m/s] at the interface, [m/min] inside the published formulas.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

__all__ = [
    "CANOPY_HEAT_KJ_PER_KG",
    "FireType",
    "crown_fraction_burned",
    "critical_active_rate_mps",
    "critical_surface_intensity_kwpm",
    "crown_flame_length_m",
    "crown_fire",
]

CANOPY_HEAT_KJ_PER_KG = 8000.0 * 2.326  # [kJ/kg]
_BTU_FT_S_TO_KW_M = 1.055056 / 0.3048
CROWN_WAF = 0.4
CROWN_RATE_FACTOR = 3.34


class FireType(IntEnum):
    UNBURNABLE = 0
    SURFACE = 1
    PASSIVE = 2
    ACTIVE = 3


def critical_surface_intensity_kwpm(
    cbh_m: np.ndarray | float, foliar_moisture: float | np.ndarray
) -> np.ndarray:
    """Van Wagner (1977) Eq. 4. ``foliar_moisture`` as a fraction (1.0 = 100 %)."""
    fmc_pct = np.asarray(foliar_moisture, dtype=float) * 100.0
    return np.power(0.010 * np.maximum(np.asarray(cbh_m, dtype=float), 0.0) * (460.0 + 25.9 * fmc_pct), 1.5)


def critical_active_rate_mps(cbd_kgpm3: np.ndarray | float) -> np.ndarray:
    """Van Wagner (1977): ``R'_active = 3.0 / CBD`` [m/min] -> [m/s]; inf where CBD is 0."""
    cbd = np.asarray(cbd_kgpm3, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(cbd > 0, 3.0 / np.where(cbd > 0, cbd, 1.0) / 60.0, np.inf)


def crown_fraction_burned(
    surface_rate_mps: np.ndarray, initiation_rate_mps: np.ndarray, active_surface_rate_mps: np.ndarray
) -> np.ndarray:
    """Scott & Reinhardt (2001) Eq. 28: ``CFB = (R_s - R'_init) / (R'_SA - R'_init)``, clipped to [0, 1]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        span = active_surface_rate_mps - initiation_rate_mps
        cfb = np.where(
            span > 0, (surface_rate_mps - initiation_rate_mps) / np.where(span > 0, span, 1.0), 1.0
        )
    return np.clip(np.nan_to_num(cfb, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)


def crown_flame_length_m(intensity_kwpm: np.ndarray) -> np.ndarray:
    """Thomas (1963) in Rothermel's (1991) units: ``L = 0.2 I^(2/3)`` [ft, Btu/ft/s] -> [m]."""
    i_btu = np.maximum(np.asarray(intensity_kwpm, dtype=float), 0.0) / _BTU_FT_S_TO_KW_M
    return 0.2 * np.power(i_btu, 2.0 / 3.0) * 0.3048


def crown_fire(
    surface_rate_mps: np.ndarray,
    surface_intensity_kwpm: np.ndarray,
    heat_per_area_kjpm2: np.ndarray,
    crown_active_rate_mps: np.ndarray,
    cbh_m: np.ndarray,
    cbd_kgpm3: np.ndarray,
    canopy_height_m: np.ndarray,
    foliar_moisture: float,
    surface_rate_at_active_mps: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Fire type and final behaviour per cell by FlamMap's Finney method (module docstring).

    Returns ``fire_type`` (:class:`FireType` codes; 0 where the surface rate is 0),
    ``rate_mps``, ``intensity_kwpm``, ``cfb``, ``transition_ratio`` (I_B / I_0) and ``active_ratio``
    (R_cactive / R'_active). Cells without canopy (CBD or canopy height 0) stay surface fires.
    ``surface_rate_at_active_mps``: R'_SA, the surface rate at the wind that makes the crown fire
    active (S&R 2001 Eq. 28), the upper end of the crown fraction burned; R'_active if omitted.
    """
    i0 = critical_surface_intensity_kwpm(cbh_m, foliar_moisture)
    r_crit = critical_active_rate_mps(cbd_kgpm3)
    has_canopy = (np.asarray(cbd_kgpm3) > 0) & (np.asarray(canopy_height_m) > 0)
    burns = surface_rate_mps > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        transition = np.where(i0 > 0, surface_intensity_kwpm / np.where(i0 > 0, i0, 1.0), np.inf)
        active_ratio = np.where(np.isfinite(r_crit), crown_active_rate_mps / r_crit, 0.0)
        # R'_initiation = 60 I_0 / H_A [m/min] (S&R 2001 Eq. 12) -> m/s
        r_init = np.where(
            heat_per_area_kjpm2 > 0, i0 / np.where(heat_per_area_kjpm2 > 0, heat_per_area_kjpm2, 1.0), np.inf
        )
    crowns = burns & has_canopy & (transition >= 1.0)
    active = crowns & (active_ratio >= 1.0)
    passive = crowns & ~active
    fire_type = np.where(burns, FireType.SURFACE, FireType.UNBURNABLE).astype(np.uint8)
    fire_type[passive] = FireType.PASSIVE
    fire_type[active] = FireType.ACTIVE
    r_sa = r_crit if surface_rate_at_active_mps is None else surface_rate_at_active_mps
    cfb = np.where(passive, crown_fraction_burned(surface_rate_mps, r_init, r_sa), 0.0)
    cfb = np.where(active, 1.0, cfb)
    rate = np.where(
        passive, surface_rate_mps + cfb * (crown_active_rate_mps - surface_rate_mps), surface_rate_mps
    )
    rate = np.where(active, crown_active_rate_mps, rate)
    canopy_load = np.asarray(cbd_kgpm3) * np.maximum(np.asarray(canopy_height_m) - np.asarray(cbh_m), 0.0)
    intensity = np.where(
        crowns,
        rate * (heat_per_area_kjpm2 + cfb * canopy_load * CANOPY_HEAT_KJ_PER_KG),
        surface_intensity_kwpm,
    )
    return {
        "fire_type": fire_type,
        "rate_mps": rate,
        "intensity_kwpm": intensity,
        "cfb": cfb,
        "transition_ratio": transition,
        "active_ratio": active_ratio,
    }
