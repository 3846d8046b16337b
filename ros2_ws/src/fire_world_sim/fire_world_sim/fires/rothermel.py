"""Rothermel (1972) surface fire rate of spread, with Albini (1976) multi-class weighting.

Reference: Rothermel, R.C. 1972, INT-115; Albini, F.A. 1976, INT-30; summarised in Andrews,
P.L. 2018, RMRS-GTR-371. The computation is done in the model's customary units (lb, ft,
Btu, min) and returned in SI. ``spread_params`` precomputes everything that does not depend
on wind and slope (no-wind, no-slope rate ``R0`` and the wind/slope factor coefficients);
:func:`rate_of_spread` and :func:`head_spread` then apply Rothermel's

    R = R0 * (1 + phi_w + phi_s),  phi_w = C U^B (beta/beta_op)^-E,  phi_s = 5.275 beta^-0.3 tan^2(slope)

with U the MIDFLAME wind speed [ft/min]. The wind and slope effects are added as vectors
(the BEHAVE/FARSITE convention) to get the head direction and the effective wind speed
U_eff (the wind alone that gives the combined phi).

Wind limit (``wind_limit``, see :data:`WIND_LIMITS`):

- ``"behave"`` (default): Rothermel's (1972) limit as Behave applies it: when U_eff exceeds
  0.9 I_R (I_R the reaction intensity [Btu/ft^2/min], U in ft/min), U_eff is set to 0.9 I_R and
  ``R = R0 (1 + C U_eff^B (beta/beta_op)^-E)``. With this the head rate matches Behave's
  within 0.4 % for fuel models 1-13 (test_rothermel_behave.py, table from scripts/behave_tables.py).
- ``"andrews2013"``: Andrews, Cruz & Rothermel (2013) drop the limit and instead cap the rate
  of spread at the effective wind speed, ``R <= U_eff``; faster than Behave at high wind on
  fine fuels (up to ~2x).
- ``"none"``: neither.

Length-to-width ratio: Behave evaluates Anderson's (1983) expression
``L/W = 0.936 exp(0.2566 U) + 0.461 exp(-0.1548 U) - 0.397`` with the effective wind speed U in
m/s (Anderson fitted it in mi/h; with mi/h a 4 m/s grass fire reaches the cap of 8, with m/s
L/W is 2.3 at 10 mi/h midflame). We follow Behave, checked against the L/W of Behave's own
ellipse (its backing rate) within 1 %. The cap of 8 (FARSITE's) is kept; it is reached at
U_eff ~ 8.9 m/s, outside Behave's tables here, so it is our choice, not verified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from fire_uav_common.scenario import WIND_LIMITS

from .fuel_models import TONS_PER_ACRE_TO_LB_PER_FT2, FuelModel

__all__ = [
    "DEFAULT_WIND_LIMIT",
    "FT_PER_MIN_TO_MPS",
    "MPS_TO_FT_PER_MIN",
    "WIND_LIMITS",
    "SpreadParams",
    "herb_cured_fraction",
    "ellipse_eccentricity",
    "head_spread",
    "head_spread_cells",
    "length_to_breadth",
    "rate_of_spread",
    "spread_params",
]

FT_PER_MIN_TO_MPS = 0.3048 / 60.0
MPS_TO_FT_PER_MIN = 1.0 / FT_PER_MIN_TO_MPS
RHO_P = 32.0  # particle density [lb/ft^3]
S_T = 0.0555  # total mineral content
S_E = 0.010  # effective mineral content
DEFAULT_WIND_LIMIT = "behave"
MAX_LENGTH_TO_WIDTH = 8.0


@dataclass(frozen=True)
class SpreadParams:
    """Wind/slope-independent part of the Rothermel model for one fuel + moisture."""

    r0_mps: float  # no-wind, no-slope rate of spread [m/s]
    reaction_intensity_btu_ft2_min: float
    sigma_per_ft: float  # characteristic SAV
    beta_ratio: float  # packing ratio / optimum packing ratio
    c: float
    b: float
    e: float
    slope_k: float  # phi_s = slope_k * tan^2(slope)
    residence_time_s: float  # flame residence time 384/sigma min (Anderson 1969)


def _eta_m(m: float, mx: float) -> float:
    if mx <= 0 or m >= mx:
        return 0.0
    r = m / mx
    return max(0.0, 1.0 - 2.59 * r + 5.11 * r**2 - 3.52 * r**3)


def herb_cured_fraction(m_live_herb: float) -> float:
    """Fraction of a dynamic model's herbaceous load transferred to dead (Scott & Burgan 2005 p. 8).

    All of it at live herbaceous moisture <= 30 %, none from 120 %, linear between. The line is
    Behave's rounded form ``1.333 - 1.11 M`` (Behave's ``SurfaceFuelbedIntermediates``; FlamMap
    the same), not the exact ``(1.2 - M) / 0.9``: with the exact line GR6 at M = 119 % spreads 5 %
    slower than Behave; with the rounded one all 53 models agree.
    """
    return min(1.0, max(0.0, 1.333 - 1.11 * m_live_herb))


# SAV bin edges [1/ft] of the size-sorted net-load weights (Albini 1976; Behave's six classes)
_SAV_BINS = (1200.0, 192.0, 96.0, 48.0, 16.0)


def _sav_bin(sav: float) -> int:
    for i, edge in enumerate(_SAV_BINS):
        if sav >= edge:
            return i
    return len(_SAV_BINS)


def _size_sorted(f: list[float], cls: list[tuple[float, float, float]]) -> list[float]:
    """g_ij: each particle's weight is the summed f of the particles in its SAV bin."""
    summed: dict[int, float] = {}
    for fi, (_, s, _) in zip(f, cls, strict=True):
        summed[_sav_bin(s)] = summed.get(_sav_bin(s), 0.0) + fi
    return [summed[_sav_bin(s)] for _, s, _ in cls]


def spread_params(
    fuel: FuelModel,
    m_1h: float,
    m_10h: float | None = None,
    m_100h: float | None = None,
    m_live_herb: float = 1.0,
    m_live_woody: float = 1.0,
) -> SpreadParams:
    """Precompute Rothermel terms for ``fuel`` at the given moistures [fraction of dry mass].

    ``m_10h`` and ``m_100h`` default to ``m_1h + 0.01`` and ``m_1h + 0.02``.
    """
    m_10h = m_1h + 0.01 if m_10h is None else m_10h
    m_100h = m_1h + 0.02 if m_100h is None else m_100h
    k = TONS_PER_ACRE_TO_LB_PER_FT2
    herb_live, herb_dead = fuel.load_live_herb_tpa, 0.0
    if fuel.dynamic:
        cured = herb_cured_fraction(m_live_herb)
        herb_live, herb_dead = fuel.load_live_herb_tpa * (1.0 - cured), fuel.load_live_herb_tpa * cured
    dead = [
        (fuel.load_1h_tpa * k, fuel.sav_1h_per_ft, m_1h),
        (fuel.load_10h_tpa * k, fuel.sav_10h_per_ft, m_10h),
        (fuel.load_100h_tpa * k, fuel.sav_100h_per_ft, m_100h),
        # cured herbaceous: a dead class with the herb's SAV at the 1-h moisture (S&B 2005 p. 8)
        (herb_dead * k, fuel.sav_live_herb_per_ft, m_1h),
    ]
    live = [
        (herb_live * k, fuel.sav_live_herb_per_ft, m_live_herb),
        (fuel.load_live_woody_tpa * k, fuel.sav_live_woody_per_ft, m_live_woody),
    ]
    dead = [c for c in dead if c[0] > 0]
    live = [c for c in live if c[0] > 0]
    h = fuel.heat_btu_per_lb

    def area(cls: list[tuple[float, float, float]]) -> float:
        return sum(w * s / RHO_P for w, s, _ in cls)

    a_dead, a_live = area(dead), area(live)
    a_tot = a_dead + a_live
    if a_tot <= 0:
        return SpreadParams(0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0)

    def weights(cls: list[tuple[float, float, float]], a_cat: float) -> list[float]:
        return [w * s / RHO_P / a_cat for w, s, _ in cls] if a_cat > 0 else []

    f_dead, f_live = weights(dead, a_dead), weights(live, a_live)
    F_dead, F_live = a_dead / a_tot, a_live / a_tot

    sigma_dead = sum(f * s for f, (_, s, _) in zip(f_dead, dead, strict=True))
    sigma_live = sum(f * s for f, (_, s, _) in zip(f_live, live, strict=True))
    sigma = F_dead * sigma_dead + F_live * sigma_live

    w_total = sum(w for w, _, _ in dead + live)
    rho_b = w_total / fuel.depth_ft
    beta = rho_b / RHO_P
    beta_op = 3.348 * sigma**-0.8189
    a_exp = 133.0 * sigma**-0.7913
    gamma_max = sigma**1.5 / (495.0 + 0.0594 * sigma**1.5)
    ratio = beta / beta_op
    gamma = gamma_max * ratio**a_exp * math.exp(a_exp * (1.0 - ratio))

    # net loads per category, weighted by the size-sorted factors g_ij (Albini 1976 as Behave)
    wn_dead = sum(g * w * (1 - S_T) for g, (w, _, _) in zip(_size_sorted(f_dead, dead), dead, strict=True))
    wn_live = sum(g * w * (1 - S_T) for g, (w, _, _) in zip(_size_sorted(f_live, live), live, strict=True))
    mf_dead = sum(f * m for f, (_, _, m) in zip(f_dead, dead, strict=True))
    mf_live = sum(f * m for f, (_, _, m) in zip(f_live, live, strict=True))
    eta_s = min(1.0, 0.174 * S_E**-0.19)
    eta_m_dead = _eta_m(mf_dead, fuel.mx_dead)
    eta_m_live = 0.0
    if live:
        # live moisture of extinction (Albini 1976)
        num = sum(w * math.exp(-138.0 / s) for w, s, _ in dead)
        den = sum(w * math.exp(-500.0 / s) for w, s, _ in live)
        fine_m = sum(w * math.exp(-138.0 / s) * m for w, s, m in dead) / num if num > 0 else 0.0
        w_ratio = num / den if den > 0 else 0.0
        mx_live = max(fuel.mx_dead, 2.9 * w_ratio * (1.0 - fine_m / fuel.mx_dead) - 0.226)
        eta_m_live = _eta_m(mf_live, mx_live)
    i_r = gamma * h * eta_s * (wn_dead * eta_m_dead + wn_live * eta_m_live)

    xi = math.exp((0.792 + 0.681 * sigma**0.5) * (beta + 0.1)) / (192.0 + 0.2595 * sigma)

    def sink(cls: list[tuple[float, float, float]], f: list[float]) -> float:
        return sum(
            fi * math.exp(-138.0 / s) * (250.0 + 1116.0 * m) for fi, (_, s, m) in zip(f, cls, strict=True)
        )

    heat_sink = rho_b * (F_dead * sink(dead, f_dead) + F_live * sink(live, f_live))
    r0_ft_min = i_r * xi / heat_sink if heat_sink > 0 else 0.0

    c = 7.47 * math.exp(-0.133 * sigma**0.55)
    b = 0.02526 * sigma**0.54
    e = 0.715 * math.exp(-3.59e-4 * sigma)
    return SpreadParams(
        r0_mps=r0_ft_min * FT_PER_MIN_TO_MPS,
        reaction_intensity_btu_ft2_min=i_r,
        sigma_per_ft=sigma,
        beta_ratio=ratio,
        c=c,
        b=b,
        e=e,
        slope_k=5.275 * beta**-0.3,
        residence_time_s=384.0 / sigma * 60.0,
    )


def rate_of_spread(
    p: SpreadParams, midflame_wind_mps: float, slope_tan: float = 0.0, wind_limit: str = DEFAULT_WIND_LIMIT
) -> float:
    """Head rate of spread [m/s] with wind blowing upslope (Rothermel 1972 Eq. 52)."""
    return head_spread(p, midflame_wind_mps, 0.0, slope_tan, 0.0, wind_limit=wind_limit)[0]


def head_spread(
    p: SpreadParams,
    wind_mps: float,
    wind_dir_rad: float,
    slope_tan: float,
    upslope_dir_rad: float,
    *,
    wind_limit: str = DEFAULT_WIND_LIMIT,
) -> tuple[Any, Any, Any]:
    """(head rate [m/s], head direction [rad ccw from +x], effective wind [m/s]).

    ``wind_mps``: midflame wind speed. Wind and slope factors are added as vectors.
    ``wind_dir_rad``: direction the wind blows toward; ``upslope_dir_rad``: direction of
    steepest ascent. ``wind_limit``: one of :data:`WIND_LIMITS` (module docstring). Works on
    numpy arrays too.
    """
    if wind_limit not in WIND_LIMITS:
        raise ValueError(f"wind_limit must be one of {WIND_LIMITS}, got {wind_limit!r}")
    if p.r0_mps <= 0:
        z = np.zeros_like(np.asarray(wind_mps, dtype=float))
        return (z if z.ndim else 0.0), wind_dir_rad, (z if z.ndim else 0.0)
    u_ft = np.asarray(wind_mps, dtype=float) * MPS_TO_FT_PER_MIN
    phi_w = p.c * np.power(np.maximum(u_ft, 0.0), p.b) * p.beta_ratio ** (-p.e)
    phi_s = p.slope_k * np.asarray(slope_tan, dtype=float) ** 2
    vx = phi_w * np.cos(wind_dir_rad) + phi_s * np.cos(upslope_dir_rad)
    vy = phi_w * np.sin(wind_dir_rad) + phi_s * np.sin(upslope_dir_rad)
    phi = np.hypot(vx, vy)
    direction = np.arctan2(vy, vx)
    # effective wind speed: the wind alone that would give phi (Albini 1976)
    u_eff_ft = np.power(phi * p.beta_ratio**p.e / p.c, 1.0 / p.b) if p.c > 0 else np.zeros_like(phi)
    r0_ft = p.r0_mps * MPS_TO_FT_PER_MIN
    if wind_limit == "behave":
        # Rothermel 1972: U_eff <= 0.9 I_R [ft/min]; phi recomputed from the limited wind
        lim = 0.9 * p.reaction_intensity_btu_ft2_min
        over = u_eff_ft > lim
        phi = np.where(over, p.c * lim**p.b * p.beta_ratio ** (-p.e), phi)
        u_eff_ft = np.where(over, lim, u_eff_ft)
    r_ft = r0_ft * (1.0 + phi)
    if wind_limit == "andrews2013":
        # Andrews, Cruz & Rothermel 2013: cap the rate of spread at the effective wind speed
        r_ft = np.where(u_eff_ft > 0, np.minimum(r_ft, np.maximum(u_eff_ft, r0_ft)), r_ft)
    r = r_ft * FT_PER_MIN_TO_MPS
    u_eff = u_eff_ft * FT_PER_MIN_TO_MPS
    if r.ndim == 0:
        return float(r), float(direction), float(u_eff)
    return r, direction, u_eff


def length_to_breadth(effective_wind_mps: float | np.ndarray) -> float | np.ndarray:
    """Length-to-width ratio of the spread ellipse, as Behave computes it (module docstring).

    Anderson's (1983) expression evaluated with the effective wind speed in m/s, capped at 8.
    """
    u = np.maximum(np.asarray(effective_wind_mps, dtype=float), 0.0)
    lb = 0.936 * np.exp(0.2566 * u) + 0.461 * np.exp(-0.1548 * u) - 0.397
    lb = np.clip(lb, 1.0, MAX_LENGTH_TO_WIDTH)
    return float(lb) if lb.ndim == 0 else lb


def ellipse_eccentricity(lb: float | np.ndarray) -> float | np.ndarray:
    """Eccentricity of an ellipse with length-to-breadth ratio ``lb``."""
    lb = np.asarray(lb, dtype=float)
    e = np.sqrt(np.maximum(lb**2 - 1.0, 0.0)) / lb
    return float(e) if e.ndim == 0 else e


def head_spread_cells(
    p: SpreadParams,
    wind_mps: np.ndarray,
    wind_dir_rad: np.ndarray | float,
    slope_tan: np.ndarray,
    upslope_dir_rad: np.ndarray | float,
    *,
    wind_limit: str = DEFAULT_WIND_LIMIT,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`head_spread` over cells: every field of ``p`` is an array of the cells' shape.

    Cells whose ``r0_mps`` is 0 (non-burnable, too wet) get rate 0 and effective wind 0.
    """
    if wind_limit not in WIND_LIMITS:
        raise ValueError(f"wind_limit must be one of {WIND_LIMITS}, got {wind_limit!r}")
    burns = np.asarray(p.r0_mps) > 0
    c = np.where(burns, p.c, 1.0)
    b = np.where(burns, p.b, 1.0)
    ratio_e = np.where(burns, np.asarray(p.beta_ratio, dtype=float) ** np.asarray(p.e, dtype=float), 1.0)
    u_ft = np.maximum(np.asarray(wind_mps, dtype=float), 0.0) * MPS_TO_FT_PER_MIN
    phi_w = c * np.power(u_ft, b) / ratio_e
    phi_s = np.asarray(p.slope_k, dtype=float) * np.asarray(slope_tan, dtype=float) ** 2
    vx = phi_w * np.cos(wind_dir_rad) + phi_s * np.cos(upslope_dir_rad)
    vy = phi_w * np.sin(wind_dir_rad) + phi_s * np.sin(upslope_dir_rad)
    phi = np.hypot(vx, vy)
    direction = np.arctan2(vy, vx)
    u_eff_ft = np.power(phi * ratio_e / c, 1.0 / b)
    r0_ft = np.asarray(p.r0_mps, dtype=float) * MPS_TO_FT_PER_MIN
    if wind_limit == "behave":
        lim = 0.9 * np.asarray(p.reaction_intensity_btu_ft2_min, dtype=float)
        over = u_eff_ft > lim
        phi = np.where(over, c * np.power(lim, b) / ratio_e, phi)
        u_eff_ft = np.where(over, lim, u_eff_ft)
    r_ft = r0_ft * (1.0 + phi)
    if wind_limit == "andrews2013":
        r_ft = np.where(u_eff_ft > 0, np.minimum(r_ft, np.maximum(u_eff_ft, r0_ft)), r_ft)
    r = np.where(burns, r_ft * FT_PER_MIN_TO_MPS, 0.0)
    u_eff = np.where(burns, u_eff_ft * FT_PER_MIN_TO_MPS, 0.0)
    return r, direction, u_eff
