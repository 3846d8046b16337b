"""Fire behaviour per cell of a landscape, as FlamMap's basic run computes it (no ROS).

Inputs per cell: fuel model code (the 53 standard models and the non-burnable 91-99), slope,
aspect, canopy cover / height / base height / bulk density; one 20-ft wind (speed, direction)
and the moisture classes (:class:`FuelMoistures`, with per-model overrides as in a FlamMap FMS
file). Outputs per cell: head rate of spread, its direction, Byram's fireline intensity, flame
length, and with ``crown="finney"`` the crown fire type (:mod:`.crown`).

The surface model is :func:`.rothermel.spread_params` once per (fuel model, moisture) and
:func:`.rothermel.head_spread_cells` over all cells; the midflame wind comes from
:func:`.wind_adjustment.wind_adjustment_factor` per cell. Heat per unit area ``H_A = I_R t_r``
with Anderson's (1969) residence time ``t_r = 384 / sigma`` [min]; Byram's (1959) intensity
``I_B = H_A R``; Byram's flame length ``L = 0.45 I_B^0.46`` [ft, Btu/ft/s] (Andrews 2018,
RMRS-GTR-371), as Behave reports them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ..errors import FireBehaviorError
from .crown import CROWN_RATE_FACTOR, CROWN_WAF, FireType, crown_fire, crown_flame_length_m
from .fuel_models import FUEL_MODELS, NONBURNABLE
from .rothermel import DEFAULT_WIND_LIMIT, SpreadParams, head_spread_cells, spread_params
from .wind_adjustment import wind_adjustment_factor

__all__ = [
    "BTU_FT2_TO_KJ_M2",
    "BTU_FT_S_TO_KW_M",
    "CROWN_METHODS",
    "FireBehavior",
    "FuelMoistures",
    "Moisture",
    "fire_behavior",
    "parse_moisture",
    "read_fms",
]

BTU_FT2_TO_KJ_M2 = 1.055056 / 0.3048**2
BTU_FT_S_TO_KW_M = 1.055056 / 0.3048
CROWN_METHODS = ("none", "finney")
_LUT_SIZE = 256


@dataclass(frozen=True)
class Moisture:
    """Fuel moisture by class [fraction of dry mass]."""

    m_1h: float
    m_10h: float
    m_100h: float
    m_herb: float
    m_woody: float

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and 0.0 < v <= 5.0):
                raise FireBehaviorError(f"moisture {f.name} must be a fraction in (0, 5], got {v!r}")


@dataclass(frozen=True)
class FuelMoistures:
    """One moisture scenario with per-model overrides (a FlamMap FMS file's content)."""

    default: Moisture
    overrides: Mapping[int, Moisture] = field(default_factory=dict)

    def for_model(self, code: int) -> Moisture:
        return self.overrides.get(code, self.default)


def parse_moisture(text: str) -> Moisture:
    """``"0.06,0.08,0.10,0.75,0.60"`` (1H,10H,100H,HERB,WOODY fractions) -> :class:`Moisture`."""
    parts = text.split(",")
    if len(parts) != 5:
        raise FireBehaviorError(f"--moisture wants 5 fractions 1H,10H,100H,HERB,WOODY, got {text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise FireBehaviorError(f"--moisture wants numbers, got {text!r}") from None
    return Moisture(*values)


def read_fms(path: Path) -> FuelMoistures:
    """A FlamMap fuel moisture (FMS) file: one line per model ``MODEL 1H 10H 100H HERB WOODY`` [%].

    Model 0 is the default for every model not listed; without a 0 line the first line is.
    """
    rows: dict[int, Moisture] = {}
    for n, line in enumerate(path.read_text().splitlines(), 1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        parts = text.split()
        if len(parts) != 6:
            raise FireBehaviorError(f"{path}:{n}: FMS line wants MODEL 1H 10H 100H HERB WOODY, got {line!r}")
        try:
            code = int(parts[0])
            pct = [float(p) for p in parts[1:]]
        except ValueError:
            raise FireBehaviorError(f"{path}:{n}: FMS line wants numbers, got {line!r}") from None
        if code != 0 and code not in FUEL_MODELS:
            raise FireBehaviorError(f"{path}:{n}: unknown fuel model {code}")
        try:
            rows[code] = Moisture(*(p / 100.0 for p in pct))
        except ValueError as e:
            raise FireBehaviorError(f"{path}:{n}: {e}") from None
    if not rows:
        raise FireBehaviorError(f"{path}: no moisture lines")
    default = rows.pop(0, None) or next(iter(rows.values()))
    return FuelMoistures(default, rows)


@dataclass(frozen=True)
class FireBehavior:
    """Per-cell results (arrays of the fuel grid's shape)."""

    ros_mps: np.ndarray  # head rate of spread [m/s]
    spread_dir_deg: np.ndarray  # head direction [deg clockwise from north]
    fireline_intensity_kwpm: np.ndarray  # [kW/m]
    flame_length_m: np.ndarray  # [m]
    fire_type: np.ndarray  # FireType codes (uint8)
    surface_ros_mps: np.ndarray
    surface_intensity_kwpm: np.ndarray
    heat_per_area_kjpm2: np.ndarray
    midflame_wind_mps: np.ndarray
    waf: np.ndarray
    effective_wind_mps: np.ndarray  # surface fire's effective midflame wind (wind + slope) [m/s]
    residence_s: np.ndarray  # flame residence time 384/sigma min (Anderson 1969) [s]


def _param_grid(
    codes: np.ndarray, moistures: FuelMoistures, fuel_index: np.ndarray
) -> tuple[SpreadParams, np.ndarray]:
    """SpreadParams with one array per field, gathered for every cell from a per-code table."""
    names = [f.name for f in fields(SpreadParams)]
    table = np.zeros((len(names), _LUT_SIZE))
    depth = np.zeros(_LUT_SIZE)
    for code in codes:
        c = int(code)
        if c not in FUEL_MODELS:
            continue
        m = moistures.for_model(c)
        p = spread_params(FUEL_MODELS[c], m.m_1h, m.m_10h, m.m_100h, m.m_herb, m.m_woody)
        table[:, c] = [getattr(p, n) for n in names]
        depth[c] = FUEL_MODELS[c].depth_ft
    cells = {n: table[i][fuel_index] for i, n in enumerate(names)}
    return SpreadParams(**cells), depth[fuel_index]


def _surface_rate_at_active(
    cell: SpreadParams,
    fm10: SpreadParams,
    cbd: np.ndarray,
    waf: np.ndarray,
    wind_to: np.ndarray | float,
    slope_tan: np.ndarray,
    upslope: np.ndarray,
    wind_limit: str,
) -> np.ndarray:
    """R'_SA [m/s]: each cell's surface head rate at the crowning-index wind (S&R 2001 Eqs. 20, 28).

    O'_active is the 20-ft wind at which ``3.34 R_10 = R'_active = 3 / CBD``: with fuel model 10's
    ``R_10 = R0 (1 + phi_w + phi_s)`` (slope added as a scalar, as S&R's Eq. 20 and Behave's
    crowning index do) ``phi_w = R'_active / (3.34 R0) - 1 - phi_s`` and
    ``U_mid = (phi_w (beta/beta_op)^E / C)^(1/B)``, ``O'_active = U_mid / 0.4``.
    """
    from .rothermel import FT_PER_MIN_TO_MPS

    r0 = np.asarray(fm10.r0_mps, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        r_active = np.where(cbd > 0, 3.0 / np.where(cbd > 0, cbd, 1.0) / 60.0, np.inf)
        phi_s = np.asarray(fm10.slope_k, dtype=float) * slope_tan**2
        phi_w = np.maximum(r_active / (CROWN_RATE_FACTOR * r0) - 1.0 - phi_s, 0.0)
        ratio_e = np.asarray(fm10.beta_ratio, dtype=float) ** np.asarray(fm10.e, dtype=float)
        u_mid_ft = np.power(phi_w * ratio_e / np.asarray(fm10.c), 1.0 / np.asarray(fm10.b))
    u20 = np.where(np.isfinite(u_mid_ft), u_mid_ft * FT_PER_MIN_TO_MPS / CROWN_WAF, 0.0)
    r_sa, _, _ = head_spread_cells(cell, waf * u20, wind_to, slope_tan, upslope, wind_limit=wind_limit)
    return np.where(np.isfinite(r_active), r_sa, np.inf)


def _compass_to_math_rad(deg: np.ndarray | float) -> np.ndarray:
    return np.radians(90.0 - np.asarray(deg, dtype=float))


def fire_behavior(
    fuel: np.ndarray,
    slope_pct: np.ndarray,
    aspect_deg: np.ndarray,
    *,
    wind_20ft_mps: float | np.ndarray,
    wind_from_deg: float | np.ndarray,
    moistures: FuelMoistures,
    canopy_cover: np.ndarray | None = None,
    canopy_height_m: np.ndarray | None = None,
    canopy_base_height_m: np.ndarray | None = None,
    canopy_bulk_density_kgpm3: np.ndarray | None = None,
    foliar_moisture: float = 1.0,
    crown: str = "none",
    wind_limit: str = DEFAULT_WIND_LIMIT,
) -> FireBehavior:
    """Surface (and crown) fire behaviour per cell, FlamMap's basic run.

    ``fuel``: fuel model codes; ``slope_pct`` [%]; ``aspect_deg``: the downslope direction [deg
    clockwise from north; negative = flat]; ``canopy_cover`` [fraction]; heights [m]; CBD
    [kg/m^3]; ``wind_20ft_mps`` [m/s] and ``wind_from_deg`` (where the 20-ft wind blows from [deg
    clockwise from north]): one wind, or one per cell (a gridded wind, as FlamMap's wind grids:
    each cell's wind goes through its own WAF exactly as a uniform one); ``foliar_moisture``
    [fraction]. Missing canopy layers mean no canopy (unsheltered wind, no
    crown fire). Unknown fuel codes raise FireBehaviorError (a ValueError) naming the code.
    """
    if crown not in CROWN_METHODS:
        raise FireBehaviorError(f"crown must be one of {CROWN_METHODS}, got {crown!r}")
    wind_arr = np.asarray(wind_20ft_mps, dtype=float)
    if not (np.isfinite(wind_arr).all() and (wind_arr >= 0).all()):
        bad = (
            wind_20ft_mps
            if wind_arr.ndim == 0
            else float(wind_arr[~(np.isfinite(wind_arr) & (wind_arr >= 0))][0])
        )
        raise FireBehaviorError(f"wind_20ft_mps must be >= 0, got {bad!r}")
    if not (math.isfinite(foliar_moisture) and 0.0 < foliar_moisture <= 5.0):
        raise FireBehaviorError(f"foliar_moisture must be a fraction in (0, 5], got {foliar_moisture!r}")
    fuel = np.asarray(fuel)
    codes = np.unique(fuel)
    unknown = [int(c) for c in codes if int(c) not in FUEL_MODELS and int(c) not in NONBURNABLE]
    if unknown:
        raise FireBehaviorError(f"unknown fuel model code(s) {unknown}; expected 1-13, 101-204 or 91-99")
    index = fuel.astype(np.int64)
    zeros = np.zeros(fuel.shape)
    cc = zeros if canopy_cover is None else np.asarray(canopy_cover, dtype=float)
    ch = zeros if canopy_height_m is None else np.asarray(canopy_height_m, dtype=float)
    cbh = zeros if canopy_base_height_m is None else np.asarray(canopy_base_height_m, dtype=float)
    cbd = zeros if canopy_bulk_density_kgpm3 is None else np.asarray(canopy_bulk_density_kgpm3, dtype=float)
    crown_ratio = np.where(ch > 0, np.clip((ch - cbh) / np.where(ch > 0, ch, 1.0), 0.0, 1.0), 0.0)

    params, depth = _param_grid(codes, moistures, index)
    waf = wind_adjustment_factor(depth, cc, ch, crown_ratio)
    midflame = waf * wind_20ft_mps
    wind_to = _compass_to_math_rad(np.asarray(wind_from_deg, dtype=float) + 180.0)
    slope_tan = np.asarray(slope_pct, dtype=float) / 100.0
    aspect = np.asarray(aspect_deg, dtype=float)
    slope_tan = np.where(aspect < 0, 0.0, slope_tan)
    upslope = _compass_to_math_rad(aspect + 180.0)
    ros, direction, ueff = head_spread_cells(
        params, midflame, wind_to, slope_tan, upslope, wind_limit=wind_limit
    )
    spread_dir = (90.0 - np.degrees(direction)) % 360.0

    sigma = np.asarray(params.sigma_per_ft, dtype=float)
    residence_min = np.where(sigma > 0, 384.0 / np.where(sigma > 0, sigma, 1.0), 0.0)
    heat_per_area = params.reaction_intensity_btu_ft2_min * residence_min * BTU_FT2_TO_KJ_M2
    intensity = heat_per_area * ros
    flame = 0.45 * np.power(intensity / BTU_FT_S_TO_KW_M, 0.46) * 0.3048
    fire_type = np.where(ros > 0, FireType.SURFACE, FireType.UNBURNABLE).astype(np.uint8)
    final_ros, final_intensity, final_flame = ros, intensity, flame
    if crown == "finney":
        # Rothermel (1991): fuel model 10 at the cells' moisture, slope and 0.4 x the 20-ft wind
        fm10 = np.full(fuel.shape, 10, dtype=np.int64)
        p10, _ = _param_grid(np.array([10]), moistures, fm10)
        r10, _, _ = head_spread_cells(
            p10,
            np.broadcast_to(CROWN_WAF * wind_arr, fuel.shape),
            wind_to,
            slope_tan,
            upslope,
            wind_limit=wind_limit,
        )
        r_sa = _surface_rate_at_active(params, p10, cbd, waf, wind_to, slope_tan, upslope, wind_limit)
        c = crown_fire(
            ros, intensity, heat_per_area, CROWN_RATE_FACTOR * r10, cbh, cbd, ch, foliar_moisture, r_sa
        )
        fire_type = c["fire_type"]
        crowning = fire_type >= FireType.PASSIVE
        final_ros = c["rate_mps"]
        final_intensity = c["intensity_kwpm"]
        final_flame = np.where(crowning, crown_flame_length_m(final_intensity), flame)
    return FireBehavior(
        ros_mps=final_ros,
        spread_dir_deg=np.where(ros > 0, spread_dir, 0.0),
        fireline_intensity_kwpm=final_intensity,
        flame_length_m=final_flame,
        fire_type=fire_type,
        surface_ros_mps=ros,
        surface_intensity_kwpm=intensity,
        heat_per_area_kjpm2=heat_per_area,
        midflame_wind_mps=midflame,
        waf=waf,
        effective_wind_mps=np.asarray(ueff, dtype=float),
        residence_s=residence_min * 60.0,
    )
