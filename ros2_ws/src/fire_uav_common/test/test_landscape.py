"""fire_uav_common.landscape: the shipped LANDFIRE landscape and every bad input (one line each).

Small GeoTIFFs are written to ``tmp_path`` with rasterio; the shipped Worcester landscape is
checked for its grid, units (LANDFIRE's m x 10 and kg/m^3 x 100 scales) and geolocation.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
import rasterio
import yaml
from fire_uav_common.landscape import (
    FBFM40_CODES,
    Landscape,
    LandscapeError,
    load_landscape,
    read_landscape_spec,
)
from rasterio.transform import from_origin

ROOT = Path(__file__).resolve().parents[4]
WORCESTER = ROOT / "data" / "landscapes" / "worcester_vt"
NODATA = 32767
ORIGIN = (500000.0, 4000000.0)  # x_min, y_max of the toy grid [m]


def write_tif(
    path: Path, data: np.ndarray, *, crs: str = "EPSG:5070", origin: tuple[float, float] = ORIGIN
) -> None:
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        height=data.shape[0],
        width=data.shape[1],
        count=1,
        dtype="int16",
        crs=crs,
        transform=from_origin(origin[0], origin[1], 30.0, 30.0),
        nodata=NODATA,
    ) as dst:
        dst.write(data.astype(np.int16), 1)


def toy(tmp_path: Path, **changes: Any) -> Path:
    """A 6 x 8 landscape: grass (102) with a pond (98), slope 20 %, aspect 180, a canopy."""
    shape = (6, 8)
    layers = {
        "fuel": np.full(shape, 102),
        "elevation": np.arange(48).reshape(shape) + 300,
        "slope": np.full(shape, 20),
        "aspect": np.full(shape, 180),
        "canopy_cover": np.full(shape, 50),
        "canopy_height": np.full(shape, 150),
        "canopy_base_height": np.full(shape, 30),
        "canopy_bulk_density": np.full(shape, 12),
    }
    layers["fuel"][0, 0] = 98
    doc: dict[str, Any] = {"fuel_kind": "fbfm40"}
    for name, data in layers.items():
        data = changes.pop(name, data)
        kw = changes.pop(f"{name}_kw", {})
        write_tif(tmp_path / f"{name}.tif", data, **kw)
        doc[name] = f"{name}.tif"
    doc.update(changes)
    path = tmp_path / "land.yaml"
    path.write_text(yaml.safe_dump({"landscape": doc}))
    return path


def test_the_toy_landscape_reads_in_model_units(tmp_path: Path) -> None:
    land = load_landscape(toy(tmp_path))
    assert land.shape == (6, 8) and land.cell_size_m == 30.0
    assert land.bounds == (500000.0, 4000000.0 - 180.0, 500000.0 + 240.0, 4000000.0)
    assert land.canopy_height_m[1, 1] == pytest.approx(15.0)
    assert land.canopy_base_height_m[1, 1] == pytest.approx(3.0)
    assert land.canopy_bulk_density_kgpm3[1, 1] == pytest.approx(0.12)
    assert land.canopy_cover[1, 1] == pytest.approx(0.5)
    assert not land.burnable[0, 0] and land.burnable[1, 1]
    x, y = land.cell_center(0, 0)
    assert (x, y) == (500015.0, 3999985.0) and land.cell_of(x, y) == (0, 0)


def test_worcester_is_shipped_with_landfire_units_and_geolocation() -> None:
    land = load_landscape(WORCESTER)
    assert land.shape == (613, 549) and land.cell_size_m == 30.0
    assert "Albers" in land.crs_wkt or "5070" in land.crs_wkt
    inside = land.has_data
    assert 0.6 < inside.mean() < 0.7  # about a third of the box is outside the data
    assert set(np.unique(land.fuel[inside]).tolist()) <= FBFM40_CODES
    # LANDFIRE's scales applied: canopy heights 0-50 m, base heights 0-10 m, CBD 0-0.45 kg/m^3
    assert 10.0 < land.canopy_height_m.max() <= 50.0 and land.canopy_base_height_m.max() <= 10.0
    assert 0.2 < land.canopy_bulk_density_kgpm3.max() <= 0.45
    assert 200.0 < land.elevation_m[inside].min() and land.elevation_m.max() < 1200.0
    # the centre of the box is near Worcester, Vermont (44.37 N, 72.55 W)
    x0, y0, x1, y1 = land.bounds
    lon, lat = land.lonlat((x0 + x1) / 2, (y0 + y1) / 2)
    assert abs(lat - 44.37) < 0.15 and abs(lon + 72.55) < 0.15


def test_a_window_and_resampling(tmp_path: Path) -> None:
    w = {"x_min_m": 500030.0, "y_min_m": 3999880.0, "x_max_m": 500150.0, "y_max_m": 3999970.0}
    land = load_landscape(toy(tmp_path, window=w))
    assert land.shape == (3, 4) and land.bounds == (500030.0, 3999880.0, 500150.0, 3999970.0)
    assert land.elevation_m[0, 0] == 300 + 8 + 1  # row 1, col 1 of the source
    coarse = load_landscape(toy(tmp_path, cell_size_m=60.0, fuel_resampling="mode"))
    assert coarse.shape == (3, 4) and coarse.cell_size_m == 60.0
    assert coarse.fuel[0, 0] == 102  # mode: the pond is one cell of four
    # bilinear elevation stays within the source's range
    assert 300 <= coarse.elevation_m.min() and coarse.elevation_m.max() <= 347


def test_nodata_outside_the_fuel_is_outside_the_landscape(tmp_path: Path) -> None:
    fuel = np.full((6, 8), 102)
    fuel[:, :2] = NODATA
    slope = np.full((6, 8), 20)
    slope[:, 0] = NODATA  # no slope where there is no fuel: fine
    land: Landscape = load_landscape(toy(tmp_path, fuel=fuel, slope=slope))
    assert not land.has_data[:, :2].any() and land.burnable[:, 2:].all()


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (
            {"slope_kw": {"crs": "EPSG:32618"}},
            r"layer 'slope' \(.*slope.tif\): CRS EPSG:32618 differs from the fuel layer's EPSG:5070",
        ),
        (
            {"aspect_kw": {"origin": (500030.0, 4000000.0)}},
            r"layer 'aspect' \(.*\): transform .* differs from the fuel layer's",
        ),
        (
            {"elevation": np.zeros((5, 8))},
            r"layer 'elevation' \(.*\): shape \(5, 8\) differs from the fuel layer's \(6, 8\)",
        ),
        ({"fuel": np.full((6, 8), 14)}, r"layer 'fuel' \(.*\): unknown FBFM40 fuel code\(s\) \[14\]"),
        (
            {"canopy_cover": np.where(np.arange(48).reshape(6, 8) == 9, NODATA, 50)},
            r"layer 'canopy_cover' \(.*\): nodata inside the burnable area \(1 cells, first at row 1, col 1\)",
        ),
        ({"fuel": np.full((6, 8), NODATA)}, r"layer 'fuel' \(.*\): no data inside the window"),
        (
            {"window": {"x_min_m": 0.0, "y_min_m": 0.0, "x_max_m": 10.0, "y_max_m": 10.0}},
            r"land.yaml: landscape.window \(0.0, 0.0, 10.0, 10.0\) lies outside the raster bounds",
        ),
        ({"window": {"x_min_m": 1.0}}, r"land.yaml: landscape.window: expected the keys"),
        ({"fuel_kind": "fbfm99"}, r"land.yaml: landscape.fuel_kind: expected one of"),
        ({"cell_size_m": -5}, r"land.yaml: landscape.cell_size_m: must be > 0"),
        ({"colour": "red"}, r"land.yaml: landscape.colour: unknown field"),
    ],
)
def test_bad_input_gets_one_line_naming_it(tmp_path: Path, change: dict[str, Any], match: str) -> None:
    with pytest.raises(LandscapeError, match=match) as e:
        load_landscape(toy(tmp_path, **change))
    assert "\n" not in str(e.value)


def test_missing_and_unreadable_files(tmp_path: Path) -> None:
    path = toy(tmp_path)
    (tmp_path / "slope.tif").unlink()
    with pytest.raises(LandscapeError, match=r"layer 'slope': file not found: .*slope.tif"):
        load_landscape(path)
    (tmp_path / "slope.tif").write_text("not a tiff")
    with pytest.raises(LandscapeError, match=r"layer 'slope': not a readable GeoTIFF: .*slope.tif"):
        load_landscape(path)
    with pytest.raises(LandscapeError, match=r"nowhere.yaml: landscape file not found"):
        read_landscape_spec(tmp_path / "nowhere.yaml")
    doc = yaml.safe_load(path.read_text())
    del doc["landscape"]["aspect"]
    path.write_text(yaml.safe_dump(doc))
    with pytest.raises(LandscapeError, match=r"land.yaml: landscape.aspect: missing"):
        read_landscape_spec(path)


def test_points_outside_the_grid_and_unburnable_ignitions_are_named(tmp_path: Path) -> None:
    fuel = np.full((6, 8), 102)
    fuel[0, 0], fuel[5, 7] = 98, NODATA
    land = load_landscape(toy(tmp_path, fuel=fuel))
    with pytest.raises(LandscapeError, match=r"point \(0.0, 0.0\) m lies outside the landscape"):
        land.cell_of(0.0, 0.0)
    with pytest.raises(LandscapeError, match=r"^ignition: point \(0.0, 0.0\) m lies outside"):
        land.require_burnable(0.0, 0.0)
    with pytest.raises(
        LandscapeError,
        match=r"ignition at \(500015.0, 3999985.0\) m: cell \(row 0, col 0\) is non-burnable fuel code 98",
    ):
        land.require_burnable(*land.cell_center(0, 0))
    with pytest.raises(LandscapeError, match=r"fire 2 at .*: cell \(row 5, col 7\) is outside the data"):
        land.require_burnable(*land.cell_center(5, 7), what="fire 2")
    assert land.require_burnable(*land.cell_center(2, 3)) == (2, 3)


def test_the_fuel_code_sets_match_the_fire_models() -> None:
    fuel_models = pytest.importorskip("fire_world_sim.fires.fuel_models")
    assert FBFM40_CODES == set(fuel_models.SCOTT_BURGAN_40) | set(fuel_models.NONBURNABLE)
