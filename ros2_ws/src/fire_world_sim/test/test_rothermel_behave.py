"""Rothermel core against Behave: head rate, length-to-width ratio and head direction.

The reference is ``data/behave_tables.csv``, made offline by ``scripts/behave_tables.py`` from
Behave's own C++ core (``pyrothermel``); see that script for the grid and the columns. No
Behave is needed to run these tests.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import NamedTuple

import pytest
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.rothermel import (
    FT_PER_MIN_TO_MPS,
    head_spread,
    length_to_breadth,
    rate_of_spread,
    spread_params,
)

TABLE = Path(__file__).parent / "data" / "behave_tables.csv"
MPH = 0.44704  # [m/s]
NORTH = math.pi / 2  # upslope in the table (aspect 180: the slope faces south)


class Row(NamedTuple):
    fuel_model: int
    moisture: float
    wind_mph: float
    slope_pct: float
    cross: int
    head_ft_min: float
    back_ft_min: float
    head_dir_deg: float  # clockwise from upslope (north)
    lw: float


def rows() -> list[Row]:
    with TABLE.open() as f:
        r = csv.DictReader(line for line in f if not line.startswith("#"))
        return [
            Row(
                int(d["fuel_model"]),
                float(d["moisture"]),
                float(d["wind_mph"]),
                float(d["slope_pct"]),
                int(d["cross"]),
                float(d["head_ft_min"]),
                float(d["back_ft_min"]),
                float(d["head_dir_deg"]),
                float(d["lw"]),
            )
            for d in r
        ]


ROWS = rows()


def project(row: Row, wind_limit: str = "behave") -> tuple[float, float, float]:
    """(head rate [ft/min], L/W, head direction [deg clockwise from north]) of our model."""
    p = spread_params(fuel_model(row.fuel_model), row.moisture)
    wind_dir = 0.0 if row.cross else NORTH  # cross: toward the east, 90 deg clockwise of upslope
    r, d, u = head_spread(
        p, row.wind_mph * MPH, wind_dir, row.slope_pct / 100.0, NORTH, wind_limit=wind_limit
    )
    compass = (90.0 - math.degrees(d)) % 360.0
    return r / FT_PER_MIN_TO_MPS, float(length_to_breadth(u)), compass


def test_table_covers_the_grid() -> None:
    assert {r.fuel_model for r in ROWS} == set(range(1, 14))
    assert {r.moisture for r in ROWS} == {0.03, 0.06, 0.09, 0.12}
    assert {r.wind_mph for r in ROWS} == {0, 2, 4, 6, 8, 10}
    assert {r.slope_pct for r in ROWS} == {0, 15, 30}


@pytest.mark.parametrize("fm", range(1, 14))
def test_head_rate_and_length_to_width_match_behave(fm: int) -> None:
    checked = 0
    for row in (r for r in ROWS if r.fuel_model == fm):
        head, lw, direction = project(row)
        if row.head_ft_min == 0.0:
            assert head == 0.0, row
            continue
        assert head == pytest.approx(row.head_ft_min, rel=0.01), row
        if not math.isnan(row.lw):
            assert lw == pytest.approx(row.lw, rel=0.01), row
        if row.cross:
            assert abs((direction - row.head_dir_deg + 180.0) % 360.0 - 180.0) < 0.5, row
        checked += 1
    assert checked >= 60  # fuel model 1 at 12 % is the only set near extinction


def test_andrews2013_and_none_are_never_slower_than_behave() -> None:
    faster = 0
    for row in ROWS:
        if row.head_ft_min == 0.0:
            continue
        behave = project(row, "behave")[0]
        none = project(row, "none")[0]
        andrews = project(row, "andrews2013")[0]
        assert none >= behave * (1 - 1e-12)
        assert andrews <= none * (1 + 1e-12)
        faster += andrews > behave * 1.01
    assert faster > 0  # the choice matters somewhere in the grid (fine fuels, high wind)


def test_unknown_wind_limit_is_rejected() -> None:
    p = spread_params(fuel_model(1), 0.06)
    with pytest.raises(ValueError, match=r"wind_limit must be one of"):
        rate_of_spread(p, 2.0, wind_limit="rothermel")
