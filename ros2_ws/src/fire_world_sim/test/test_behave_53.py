"""Per-cell fire behaviour of all 53 standard fuel models against Behave.

The reference is ``data/behave_53.csv`` (grid and columns in ``scripts/behave_tables.py``, made
offline from Behave's C++ core through ``pyrothermel``): head rate, its direction, Byram's fireline
intensity, flame length and the midflame wind from a 20-ft wind through the wind adjustment
factor (open and sheltered by a canopy). Rows are run in groups of one weather as arrays of cells,
the way the landscape command runs them. ``docs/behave_agreement.md`` tabulates the same
comparison per model.
"""

from __future__ import annotations

import csv
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest
from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior
from fire_world_sim.fires.fuel_models import ANDERSON_13, FUEL_MODELS, SCOTT_BURGAN_40

TABLE = Path(__file__).parent / "data" / "behave_53.csv"
MPH = 0.44704
FT = 0.3048
BTU_FT_S = 1.055056 / FT  # [kW/m]
MOISTURE_KEYS = ("m1h", "m10h", "m100h", "mherb", "mwoody")


def rows() -> list[dict[str, float]]:
    with TABLE.open() as f:
        r = csv.DictReader(line for line in f if not line.startswith("#"))
        return [{k: float(v) for k, v in d.items()} for d in r]


ROWS = rows()


def run_groups() -> list[tuple[dict[str, float], tuple[float, float, float, float, float]]]:
    """(row, (head ft/min, dir deg, fli Btu/ft/s, flame ft, midflame mi/h)) for every row."""
    groups: dict[tuple[float, ...], list[dict[str, float]]] = defaultdict(list)
    for d in ROWS:
        groups[(*(d[k] for k in MOISTURE_KEYS), d["wind20_mph"], d["wind_from_deg"])].append(d)
    out = []
    for key, ds in groups.items():

        def col(k: str, ds: list[dict[str, float]] = ds) -> np.ndarray:
            return np.array([[d[k] for d in ds]])

        b = fire_behavior(
            col("fuel_model").astype(int),
            col("slope_pct"),
            col("aspect_deg"),
            wind_20ft_mps=key[5] * MPH,
            wind_from_deg=key[6],
            moistures=FuelMoistures(Moisture(*key[:5])),
            canopy_cover=col("canopy_cover"),
            canopy_height_m=col("canopy_height_m"),
            canopy_base_height_m=col("canopy_height_m") * (1.0 - col("crown_ratio")),
        )
        for i, d in enumerate(ds):
            out.append(
                (
                    d,
                    (
                        b.ros_mps[0, i] * 60.0 / FT,
                        b.spread_dir_deg[0, i],
                        b.fireline_intensity_kwpm[0, i] / BTU_FT_S,
                        b.flame_length_m[0, i] / FT,
                        b.midflame_wind_mps[0, i] / MPH,
                    ),
                )
            )
    return out


RESULTS = run_groups()


def test_table_covers_all_53_models_and_the_dynamic_transfer() -> None:
    assert {int(d["fuel_model"]) for d in ROWS} == set(FUEL_MODELS) == set(ANDERSON_13) | set(SCOTT_BURGAN_40)
    assert len(FUEL_MODELS) == 53
    herb = {d["mherb"] for d in ROWS}
    assert min(herb) <= 0.30 and max(herb) >= 1.20 and any(0.30 < h < 1.20 for h in herb)
    assert {d["canopy_cover"] for d in ROWS} == {0.0, 0.5}


@pytest.mark.parametrize("fm", sorted(FUEL_MODELS))
def test_per_cell_behaviour_matches_behave(fm: int) -> None:
    checked = 0
    for d, (head, direction, fli, flame, midflame) in RESULTS:
        if int(d["fuel_model"]) != fm:
            continue
        assert midflame == pytest.approx(d["midflame_mph"], rel=1e-4, abs=1e-9), d
        if d["head_ft_min"] == 0.0:
            assert head == 0.0, d
            continue
        assert head == pytest.approx(d["head_ft_min"], rel=0.005), d
        assert fli == pytest.approx(d["fli_btu_ft_s"], rel=0.006), d
        assert flame == pytest.approx(d["flame_ft"], rel=0.005), d
        if d["wind20_mph"] > 0 or d["slope_pct"] > 0:
            assert abs((direction - d["head_dir_deg"] + 180.0) % 360.0 - 180.0) < 0.1, d
        checked += 1
    assert checked >= 40, fm  # most of the 80 cases burn


def test_the_dynamic_models_cure_by_herbaceous_moisture() -> None:
    # GR2 (dynamic): the same weather except the herbaceous moisture; the drier the herb, the
    # more of its load is dead fine fuel and the faster the fire (Scott & Burgan 2005 p. 8)
    def head(m_herb: float) -> float:
        b = fire_behavior(
            np.array([[102, 2]]),
            np.zeros((1, 2)),
            np.zeros((1, 2)),
            wind_20ft_mps=4.0,
            wind_from_deg=0.0,
            moistures=FuelMoistures(Moisture(0.06, 0.07, 0.08, m_herb, 1.0)),
        )
        return float(b.ros_mps[0, 0])

    rates = [head(m) for m in (0.30, 0.60, 0.90, 1.20)]
    assert rates == sorted(rates, reverse=True) and rates[0] > 2 * rates[-1]
