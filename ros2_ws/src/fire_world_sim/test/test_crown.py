"""Crown fire (Van Wagner 1977; Rothermel 1991; Scott & Reinhardt 2001; FlamMap's Finney method).

Checked against Van Wagner's (1977) worked example and against Behave's crown module
(``data/behave_crown.csv``, ``scripts/behave_tables.py crown``, 450 cases of 5 fuel models, winds,
canopy base heights, bulk densities and foliar moistures): its critical intensity (its surface
intensity over its transition ratio), its active crown rate (its active ratio times ``3 / CBD``)
and, end to end, its fire type, final rate and intensity.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior
from fire_world_sim.fires.crown import (
    FireType,
    critical_active_rate_mps,
    critical_surface_intensity_kwpm,
    crown_fraction_burned,
)

TABLE = Path(__file__).parent / "data" / "behave_crown.csv"
KMH = 1.0 / 3.6
MOISTURE = Moisture(0.06, 0.08, 0.10, 0.75, 0.60)  # as the table's CROWN_MOISTURE


def rows() -> list[dict[str, str]]:
    with TABLE.open() as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


ROWS = rows()
FINNEY = {"surface": FireType.SURFACE, "conditional_crown_fire": FireType.SURFACE}
FINNEY |= {"torching": FireType.PASSIVE, "crowning": FireType.ACTIVE}


def test_van_wagner_1977_worked_example() -> None:
    # Van Wagner (1977): red pine, crown base 6 m, foliar moisture 100 %, bulk density 0.23 kg/m^3:
    # I_0 = (0.010 * 6 * (460 + 25.9 * 100))^1.5 = 183^1.5 = 2475 kW/m; R'_active = 3 / 0.23 = 13 m/min
    assert float(critical_surface_intensity_kwpm(6.0, 1.0)) == pytest.approx(2475.6, rel=1e-3)
    assert float(critical_active_rate_mps(0.23)) * 60.0 == pytest.approx(13.04, rel=1e-3)
    # I_0 grows as CBH^1.5 and with foliar moisture
    assert float(critical_surface_intensity_kwpm(4.0, 1.0)) / float(
        critical_surface_intensity_kwpm(1.0, 1.0)
    ) == (pytest.approx(8.0))
    assert critical_surface_intensity_kwpm(3.0, 1.2) > critical_surface_intensity_kwpm(3.0, 0.9)


def test_critical_intensity_matches_behave() -> None:
    checked = 0
    for d in ROWS:
        if float(d["transition_ratio"]) > 0:
            behave_i0 = float(d["surface_fli_kwm"]) / float(d["transition_ratio"])
            ours = float(critical_surface_intensity_kwpm(float(d["cbh_m"]), float(d["foliar"])))
            assert ours == pytest.approx(behave_i0, rel=2e-3), d
            checked += 1
    assert checked > 400


def test_active_crown_rate_matches_behave() -> None:
    # Behave: active ratio = R_cactive / R'_active with R'_active = 3 / CBD [m/min]
    for d in ROWS:
        behave = float(d["active_ratio"]) * 3.0 / float(d["cbd_kgm3"]) / 60.0
        b = fire_behavior(
            np.array([[10]]),
            np.zeros((1, 1)),
            np.zeros((1, 1)),
            wind_20ft_mps=float(d["wind20_kmh"]) * KMH,
            wind_from_deg=0.0,
            moistures=FuelMoistures(MOISTURE),
            canopy_cover=np.full((1, 1), 1.0),
            canopy_height_m=np.full((1, 1), 100.0),
            canopy_base_height_m=np.full((1, 1), 0.01),  # any fire crowns ...
            canopy_bulk_density_kgpm3=np.full((1, 1), 10.0),  # ... and is active (R'_active 0.3 m/min)
            foliar_moisture=1.0,
            crown="finney",
        )
        assert b.fire_type[0, 0] == FireType.ACTIVE
        r_cactive = float(b.ros_mps[0, 0])  # an active crown fire spreads at R_cactive
        assert r_cactive == pytest.approx(behave, rel=3e-3), d


def test_fire_type_rate_and_intensity_match_behave_end_to_end() -> None:
    # every row as one cell of one landscape per (wind, foliar moisture): fuel, canopy per cell
    groups: dict[tuple[float, float], list[dict[str, str]]] = {}
    for d in ROWS:
        groups.setdefault((float(d["wind20_kmh"]), float(d["foliar"])), []).append(d)
    kinds = set()
    for (wind_kmh, foliar), ds in groups.items():

        def col(k: str, ds: list[dict[str, str]] = ds) -> np.ndarray:
            return np.array([[float(d[k]) for d in ds]])

        b = fire_behavior(
            col("fuel_model").astype(int),
            np.zeros((1, len(ds))),
            np.zeros((1, len(ds))),
            wind_20ft_mps=wind_kmh * KMH,
            wind_from_deg=0.0,
            moistures=FuelMoistures(MOISTURE),
            canopy_cover=col("canopy_cover"),
            canopy_height_m=col("canopy_height_m"),
            canopy_base_height_m=col("cbh_m"),
            canopy_bulk_density_kgpm3=col("cbd_kgm3"),
            foliar_moisture=foliar,
            crown="finney",
        )
        for i, d in enumerate(ds):
            kind = FINNEY[d["fire_type"]]
            kinds.add(kind)
            assert b.fire_type[0, i] == kind, d
            # passive: CFB amplifies the 0.1 % differences of R_s and R'_SA near initiation
            tol = 0.02 if kind == FireType.PASSIVE else 0.005
            assert b.ros_mps[0, i] == pytest.approx(float(d["final_kmh"]) * KMH, rel=tol), d
            assert b.fireline_intensity_kwpm[0, i] == pytest.approx(float(d["final_fli_kwm"]), rel=tol), d
            assert b.flame_length_m[0, i] == pytest.approx(float(d["final_flame_m"]), rel=tol), d
    assert kinds == {FireType.SURFACE, FireType.PASSIVE, FireType.ACTIVE}


def test_crown_fraction_burned_is_linear_from_initiation_to_the_active_surface_rate() -> None:
    r_init, r_sa = np.array([0.01]), np.array([0.2])
    assert crown_fraction_burned(r_init, r_init, r_sa)[0] == pytest.approx(0.0)
    assert crown_fraction_burned(r_init + 0.25 * (r_sa - r_init), r_init, r_sa)[0] == pytest.approx(0.25)
    assert crown_fraction_burned(2 * r_sa, r_init, r_sa)[0] == 1.0


def test_no_canopy_no_crown_fire() -> None:
    b = fire_behavior(
        np.array([[165, 98]]),
        np.zeros((1, 2)),
        np.zeros((1, 2)),
        wind_20ft_mps=15.0,
        wind_from_deg=0.0,
        moistures=FuelMoistures(MOISTURE),
        crown="finney",
    )
    assert list(b.fire_type[0]) == [FireType.SURFACE, FireType.UNBURNABLE]
