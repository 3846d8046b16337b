"""``scripts/fire_behavior`` (fires/landscape_run.py): FlamMap's basic run over the shipped
Worcester landscape, its GeoTIFFs read back on the landscape's grid and CRS, and exit status 2
with one line for each bad input."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
import rasterio
from fire_uav_common.landscape import load_landscape
from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior
from fire_world_sim.fires.crown import FireType
from fire_world_sim.fires.landscape_run import main

ROOT = Path(__file__).resolve().parents[4]
OUTPUTS = ("ros_mps", "spread_dir_deg", "fireline_intensity_kwpm", "flame_length_m", "fire_type")


@pytest.fixture(scope="module")
def worcester_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("fb")
    args = ["worcester_vt", "--out", str(out), "--moisture", "0.06,0.08,0.10,0.75,0.60"]
    assert main([*args, "--foliar-moisture", "1.2", "--crown", "finney"]) == 0
    return out


def test_geotiffs_are_on_the_landscapes_grid_and_crs(worcester_run: Path) -> None:
    land = load_landscape(ROOT / "data" / "landscapes" / "worcester_vt")
    with rasterio.open(ROOT / "data" / "landscapes" / "worcester_vt" / "fbfm40.tif") as src:
        crs, transform, shape = src.crs, src.transform, src.shape
    for name in OUTPUTS:
        with rasterio.open(worcester_run / f"{name}.tif") as r:
            assert r.crs == crs and r.transform == transform and r.shape == shape, name
            data = r.read(1, masked=True)
        assert (~np.ma.getmaskarray(data) == land.has_data).all(), name  # nodata exactly outside
        assert (worcester_run / f"{name}.png").stat().st_size > 10_000, name
    with rasterio.open(worcester_run / "fire_type.tif") as r:
        types = r.read(1, masked=True).compressed()
    counts = np.bincount(types, minlength=4)
    # a windless day still crowns on the steep conifer slopes; open water and urban do not burn
    assert counts[FireType.SURFACE] > 0.9 * types.size
    assert counts[FireType.PASSIVE] > 0 and counts[FireType.ACTIVE] > 0 and counts[FireType.UNBURNABLE] > 0


def test_the_rasters_hold_the_per_cell_model(worcester_run: Path) -> None:
    land = load_landscape(ROOT / "data" / "landscapes" / "worcester_vt")
    rows, cols = np.nonzero(land.burnable)
    pick = np.linspace(0, rows.size - 1, 200).astype(int)
    r, c = rows[pick], cols[pick]
    b = fire_behavior(
        land.fuel[r, c][None, :],
        land.slope_pct[r, c][None, :],
        land.aspect_deg[r, c][None, :],
        wind_20ft_mps=0.0,
        wind_from_deg=0.0,
        moistures=FuelMoistures(Moisture(0.06, 0.08, 0.10, 0.75, 0.60)),
        canopy_cover=land.canopy_cover[r, c][None, :],
        canopy_height_m=land.canopy_height_m[r, c][None, :],
        canopy_base_height_m=land.canopy_base_height_m[r, c][None, :],
        canopy_bulk_density_kgpm3=land.canopy_bulk_density_kgpm3[r, c][None, :],
        foliar_moisture=1.2,
        crown="finney",
    )
    with rasterio.open(worcester_run / "ros_mps.tif") as t:
        ros = t.read(1)[r, c]
    with rasterio.open(worcester_run / "spread_dir_deg.tif") as t:
        direction = t.read(1)[r, c]
    np.testing.assert_allclose(ros, b.ros_mps[0], rtol=1e-6)
    # no wind: fires head upslope, opposite the aspect (LANDFIRE's aspect is the downslope direction)
    sloped = (land.slope_pct[r, c] > 5) & (land.aspect_deg[r, c] >= 0) & (b.fire_type[0] == FireType.SURFACE)
    diff = (direction[sloped] - (land.aspect_deg[r, c][sloped] + 180.0) + 180.0) % 360.0 - 180.0
    assert sloped.sum() > 50 and np.abs(diff).max() < 0.01


def write_bad_landscape(tmp_path: Path) -> Path:
    (tmp_path / "land.yaml").write_text(
        "landscape:\n  fuel: f.tif\n  elevation: e.tif\n  slope: s.tif\n  aspect: a.tif\n"
    )
    return tmp_path / "land.yaml"


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (
            ["no_such_landscape"],
            r"no_such_landscape: no such landscape file, directory or shipped landscape name",
        ),
        (["worcester_vt", "--moisture", "0.06,0.08"], r"--moisture wants 5 fractions"),
        (["worcester_vt", "--foliar-moisture", "-1"], r"foliar_moisture must be a fraction"),
        (["worcester_vt", "--wind-20ft-mps", "-3"], r"wind_20ft_mps must be >= 0"),
        (["BAD"], r"layer 'fuel': file not found: .*f.tif"),
    ],
)
def test_bad_input_exits_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], match: str
) -> None:
    if args == ["BAD"]:
        args = [str(write_bad_landscape(tmp_path))]
    assert main([*args, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("fire_behavior: error: ") and err.count("\n") == 1
    assert __import__("re").search(match, err), err


@pytest.mark.slow  # starts a process
def test_the_command_line_wrapper_exits_2_on_a_bad_option(tmp_path: Path) -> None:
    p = subprocess.run(
        [str(ROOT / "scripts" / "fire_behavior"), "worcester_vt", "--out", str(tmp_path), "--crown", "scott"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert p.returncode == 2 and "invalid choice: 'scott'" in p.stderr
