"""Inputs of the per-cell fire behaviour: fuel codes, moisture scenarios and FMS files, wind
adjustment edge cases (each bad input gets one line naming what is wrong), and the per-cell
Rothermel kernel against the scalar one (property test)."""

from __future__ import annotations

from dataclasses import astuple
from pathlib import Path

import numpy as np
import pytest
from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior, parse_moisture, read_fms
from fire_world_sim.fires.fuel_models import FUEL_MODELS, NONBURNABLE, fuel_model, is_burnable
from fire_world_sim.fires.rothermel import (
    SpreadParams,
    head_spread,
    head_spread_cells,
    herb_cured_fraction,
    spread_params,
)
from fire_world_sim.fires.wind_adjustment import wind_adjustment_factor
from hypothesis import given, settings
from hypothesis import strategies as st

DRY = FuelMoistures(Moisture(0.06, 0.08, 0.10, 0.75, 0.60))


def run(fuel: list[int], moistures: FuelMoistures = DRY, **kw: object) -> np.ndarray:
    n = len(fuel)
    b = fire_behavior(
        np.array([fuel]),
        np.zeros((1, n)),
        np.zeros((1, n)),
        wind_20ft_mps=5.0,
        wind_from_deg=0.0,
        moistures=moistures,
        **kw,  # type: ignore[arg-type]
    )
    return b.ros_mps[0]


def test_nonburnable_codes_do_not_burn_and_unknown_codes_are_named() -> None:
    assert set(NONBURNABLE) == set(range(91, 100))
    assert not any(run(list(range(91, 100))))
    assert all(run([1, 101, 165, 204]) > 0)
    assert is_burnable(145) and not is_burnable(98)
    with pytest.raises(ValueError, match=r"unknown fuel model code\(s\) \[14, 250\]"):
        run([1, 14, 250])
    with pytest.raises(ValueError, match=r"unknown fuel model 100"):
        fuel_model(100)
    with pytest.raises(ValueError, match=r"unknown fuel model 0"):
        is_burnable(0)


def test_herbaceous_curing_is_linear_between_30_and_120_percent() -> None:
    assert herb_cured_fraction(0.1) == 1.0 and herb_cured_fraction(0.30) == pytest.approx(1.0, abs=1e-3)
    assert herb_cured_fraction(0.75) == pytest.approx(0.5, abs=2e-3)
    assert herb_cured_fraction(1.21) == 0.0 and herb_cured_fraction(2.0) == 0.0


def test_fms_overrides_one_model(tmp_path: Path) -> None:
    fms = tmp_path / "dry.fms"
    fms.write_text("0 6 8 10 75 60\n102 3 4 5 30 60  # cured grass\n")
    m = read_fms(fms)
    assert m.default == Moisture(0.06, 0.08, 0.10, 0.75, 0.60)
    assert m.for_model(102) == Moisture(0.03, 0.04, 0.05, 0.30, 0.60)
    assert m.for_model(1) == m.default
    wet_default = run([102, 1], m)
    same = run([102, 1], DRY)
    assert wet_default[0] > same[0] and wet_default[1] == same[1]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("0 6 8 10 75\n", r"dry.fms:1: FMS line wants MODEL 1H 10H 100H HERB WOODY"),
        ("0 6 8 ten 75 60\n", r"dry.fms:1: FMS line wants numbers"),
        ("0 6 8 10 75 60\n77 6 8 10 75 60\n", r"dry.fms:2: unknown fuel model 77"),
        ("0 -6 8 10 75 60\n", r"dry.fms:1: moisture m_1h must be a fraction"),
        ("# nothing\n", r"dry.fms: no moisture lines"),
    ],
)
def test_bad_fms_lines_are_named(tmp_path: Path, text: str, match: str) -> None:
    fms = tmp_path / "dry.fms"
    fms.write_text(text)
    with pytest.raises(ValueError, match=match):
        read_fms(fms)


def test_moisture_argument() -> None:
    assert parse_moisture("0.06,0.08,0.10,0.75,0.60") == Moisture(0.06, 0.08, 0.10, 0.75, 0.60)
    with pytest.raises(ValueError, match=r"--moisture wants 5 fractions"):
        parse_moisture("0.06,0.08")
    with pytest.raises(ValueError, match=r"--moisture wants numbers"):
        parse_moisture("a,b,c,d,e")
    with pytest.raises(ValueError, match=r"moisture m_herb must be a fraction"):
        parse_moisture("0.06,0.08,0.10,nan,0.6")


def test_bad_run_options_are_named() -> None:
    with pytest.raises(ValueError, match=r"crown must be one of"):
        run([1], crown="scott")
    with pytest.raises(ValueError, match=r"foliar_moisture must be"):
        run([1], foliar_moisture=0.0)


def test_wind_adjustment_factor_properties() -> None:
    # unsheltered: deeper fuel beds feel more of the 20-ft wind; no fuel, no wind
    w = wind_adjustment_factor(np.array([0.0, 0.2, 1.0, 6.0]))
    assert w[0] == 0.0 and 0 < w[1] < w[2] < w[3] < 1
    # sheltered: denser canopy shelters more; a sparse canopy (f < 0.05) does not shelter at all
    dense, light = wind_adjustment_factor(1.0, [0.9, 0.3], 20.0, 0.6)
    assert dense < light < float(wind_adjustment_factor(1.0))
    assert float(wind_adjustment_factor(1.0, 0.1, 20.0, 0.6)) == float(wind_adjustment_factor(1.0))


@settings(max_examples=60, deadline=None)
@given(
    fm=st.sampled_from(sorted(FUEL_MODELS)),
    m1=st.floats(0.02, 0.4),
    herb=st.floats(0.3, 2.0),
    wind=st.floats(0.0, 15.0),
    wind_dir=st.floats(-np.pi, np.pi),
    slope=st.floats(0.0, 1.5),
    up=st.floats(-np.pi, np.pi),
    limit=st.sampled_from(["behave", "andrews2013", "none"]),
)
def test_the_cell_kernel_equals_the_scalar_one(
    fm: int, m1: float, herb: float, wind: float, wind_dir: float, slope: float, up: float, limit: str
) -> None:
    p = spread_params(FUEL_MODELS[fm], m1, m1 + 0.01, m1 + 0.02, herb, 1.0)
    r, d, u = head_spread(p, wind, wind_dir, slope, up, wind_limit=limit)
    cells = SpreadParams(*(np.full((1, 3), v) for v in astuple(p)))
    rc, dc, uc = head_spread_cells(
        cells, np.full((1, 3), wind), wind_dir, np.full((1, 3), slope), up, wind_limit=limit
    )
    assert rc[0, 1] == pytest.approx(r, rel=1e-12, abs=1e-15) and uc[0, 2] == pytest.approx(
        u, rel=1e-9, abs=1e-12
    )
    if r > 0 and (wind > 0 or slope > 0):
        assert abs((dc[0, 0] - d + np.pi) % (2 * np.pi) - np.pi) < 1e-9
