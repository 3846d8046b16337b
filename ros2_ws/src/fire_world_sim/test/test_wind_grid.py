"""A gridded 20-ft wind (WindNinja's ASCII pair or a 2-band GeoTIFF) on a landscape.

- a uniform grid gives the uniform wind's fire behaviour and raster fire, cell for cell;
- a grid of two halves gives each half the behaviour of its own wind: Behave's head rate
  (``data/behave_53.csv``, made offline from Behave's C++ core through pyrothermel) on a flat grass
  landscape through ``scripts/fire_behavior``, and the uniform-wind raster fire of that half's wind
  on worcester_vt;
- the shipped synthetic grid for worcester_vt loads and turns the fire;
- bad grids: one line naming the file, exit status 2 (``scripts/fire_behavior``).
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
import rasterio
import yaml
from fire_uav_common.scenario import load_scenario
from fire_uav_common.scenario.ground import landscape_of
from fire_world_sim.fires.landscape_run import main
from fire_world_sim.fires.raster import RasterFireModel
from rasterio.transform import from_origin

from .conftest import SCENARIOS

ROOT = Path(__file__).resolve().parents[4]
BEHAVE = Path(__file__).parent / "data" / "behave_53.csv"
SAMPLE = ROOT / "data" / "wind" / "worcester_vt"
MPH = 0.44704
FT = 0.3048
CRS = "EPSG:5070"


def write_asc_pair(
    base: Path,
    speed: np.ndarray,
    from_deg: np.ndarray,
    *,
    x0: float,
    y_top: float,
    cell_m: float,
    crs: str = CRS,
) -> tuple[Path, Path]:
    """WindNinja's ASCII output: ``base_vel.asc`` / ``base_ang.asc`` with a ``.prj`` beside each."""
    rows, cols = speed.shape
    header = (
        f"ncols {cols}\nnrows {rows}\nxllcorner {x0:.6f}\nyllcorner {y_top - rows * cell_m:.6f}\n"
        f"cellsize {cell_m:g}\nNODATA_value -9999\n"
    )
    prj = rasterio.crs.CRS.from_string(crs).to_wkt(version="WKT1_ESRI")
    out = []
    for suffix, values in (("vel", speed), ("ang", from_deg)):
        p = base.parent / f"{base.name}_{suffix}.asc"
        p.write_text(header + "\n".join(" ".join(f"{v:.6f}" for v in row) for row in values) + "\n")
        p.with_suffix(".prj").write_text(prj)
        out.append(p)
    return out[0], out[1]


def write_two_band(
    path: Path, speed: np.ndarray, from_deg: np.ndarray, *, x0: float, y_top: float, cell_m: float
) -> Path:
    with rasterio.open(
        path, "w", driver="GTiff", height=speed.shape[0], width=speed.shape[1], count=2, dtype="float64",
        crs=CRS, transform=from_origin(x0, y_top, cell_m, cell_m),
    ) as dst:  # fmt: skip
        dst.write(speed, 1)
        dst.write(from_deg, 2)
    return path


def flat_grass(tmp_path: Path, shape: tuple[int, int] = (20, 40)) -> Path:
    """A flat GR2 (102) landscape of 30 m cells, no canopy: the behaviour is Behave's row's."""
    doc = {"fuel_kind": "fbfm40"}
    layers = {"fuel": 102, "elevation": 300, "slope": 0, "aspect": -1}
    for name, value in layers.items():
        with rasterio.open(
            tmp_path / f"{name}.tif", "w", driver="GTiff", height=shape[0], width=shape[1], count=1,
            dtype="int16", crs=CRS, transform=from_origin(500000.0, 4000000.0, 30.0, 30.0), nodata=32767,
        ) as dst:  # fmt: skip
            dst.write(np.full(shape, value, dtype=np.int16), 1)
        doc[name] = f"{name}.tif"
    (tmp_path / "land.yaml").write_text(yaml.safe_dump({"landscape": doc}))
    return tmp_path / "land.yaml"


def behave_head_ft_min(wind_mph: float) -> float:
    """Behave's head rate of GR2 on flat open ground, dead 6/8/10 %, live 75/60 %."""
    with BEHAVE.open() as f:
        for d in csv.DictReader(line for line in f if not line.startswith("#")):
            key = (
                d["fuel_model"],
                d["m1h"],
                d["m10h"],
                d["m100h"],
                d["mherb"],
                d["mwoody"],
                d["slope_pct"],
                d["canopy_cover"],
            )
            if (
                key == ("102", "0.06", "0.08", "0.1", "0.75", "0.6", "0", "0")
                and float(d["wind20_mph"]) == wind_mph
            ):
                return float(d["head_ft_min"])
    raise LookupError(wind_mph)


def read_tif(path: Path) -> np.ndarray:
    with rasterio.open(path) as r:
        return r.read(1)


# --- scripts/fire_behavior -----------------------------------------------------------------------


def test_two_halves_each_burn_at_behaves_rate_for_their_own_wind(tmp_path: Path) -> None:
    """West half 5 mi/h from the south-west, east half 20 mi/h from the east (a 60 m grid over a
    1200 x 600 m landscape of 30 m cells). Behave gives the head rate of each speed; on flat
    ground the head runs where the wind blows (45 and 270 deg)."""
    land = flat_grass(tmp_path)
    speed = np.where(np.arange(20)[None, :] < 10, 5.0, 20.0) * np.ones((10, 1))
    from_deg = np.where(np.arange(20)[None, :] < 10, 225.0, 90.0) * np.ones((10, 1))
    vel, ang = write_asc_pair(tmp_path / "halves", speed, from_deg, x0=500000.0, y_top=4000000.0, cell_m=60.0)
    out = tmp_path / "out"
    assert (
        main([str(land), "--out", str(out), "--wind-grid", f"{vel},{ang}", "--wind-speed-units", "mph"]) == 0
    )
    ros = read_tif(out / "ros_mps.tif") * 60.0 / FT
    direction = read_tif(out / "spread_dir_deg.tif")
    west, east = np.s_[:, :18], np.s_[:, 22:]  # cells whose 4 grid neighbours are all one half's
    assert ros[west] == pytest.approx(behave_head_ft_min(5.0), rel=0.005)
    assert ros[east] == pytest.approx(behave_head_ft_min(20.0), rel=0.005)
    assert direction[west] == pytest.approx(45.0, abs=1e-6)
    assert direction[east] == pytest.approx(270.0, abs=1e-6)
    # and each half is the uniform run of its own wind, cell for cell
    for half, (mph, frm) in ((west, (5.0, 225.0)), (east, (20.0, 90.0))):
        uni = tmp_path / f"uniform_{mph:g}"
        assert (
            main(
                [str(land), "--out", str(uni), "--wind-20ft-mps", str(mph * MPH), "--wind-from-deg", str(frm)]
            )
            == 0
        )
        for name in ("ros_mps", "spread_dir_deg", "fireline_intensity_kwpm", "flame_length_m"):
            np.testing.assert_allclose(
                read_tif(out / f"{name}.tif")[half], read_tif(uni / f"{name}.tif")[half], rtol=1e-6
            )


def test_a_two_band_geotiff_is_read_as_the_ascii_pair(tmp_path: Path) -> None:
    land = flat_grass(tmp_path)
    rng = np.random.default_rng(3)
    speed, from_deg = rng.uniform(0.0, 9.0, (10, 20)), rng.uniform(0.0, 360.0, (10, 20))
    vel, ang = write_asc_pair(tmp_path / "w", speed, from_deg, x0=500000.0, y_top=4000000.0, cell_m=60.0)
    tif = write_two_band(tmp_path / "w.tif", speed, from_deg, x0=500000.0, y_top=4000000.0, cell_m=60.0)
    a, b = tmp_path / "a", tmp_path / "b"
    assert main([str(land), "--out", str(a), "--wind-grid", f"{vel},{ang}", "--wind-speed-units", "mps"]) == 0
    assert main([str(land), "--out", str(b), "--wind-grid", str(tif), "--wind-speed-units", "mps"]) == 0
    np.testing.assert_allclose(read_tif(a / "ros_mps.tif"), read_tif(b / "ros_mps.tif"), rtol=1e-5)


def test_the_cells_wind_is_bilinear_on_the_components_not_on_the_angle(tmp_path: Path) -> None:
    """Two grid columns from 350 and 10 deg, same speed: midway the wind is from the north at
    cos(10 deg) x the speed (the vector mean), not from the south (the angles' mean, 180)."""
    from fire_uav_common.landscape import load_landscape
    from fire_uav_common.scenario.wind_grid import WindGrid, wind_on_landscape

    land = load_landscape(flat_grass(tmp_path, shape=(4, 4)))  # 120 x 120 m
    vel, ang = write_asc_pair(
        tmp_path / "w",
        np.full((2, 2), 5.0),
        np.array([[350.0, 10.0]] * 2),
        x0=500000.0,
        y_top=4000000.0,
        cell_m=60.0,
    )
    w = wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)
    # landscape columns 1 and 2 (centres 45 and 75 m) lie between the grid centres (30 and 90 m)
    for col, frac in ((1, 0.25), (2, 0.75)):
        u = (1 - frac) * -5.0 * math.sin(math.radians(350.0)) + frac * -5.0 * math.sin(math.radians(10.0))
        v = -5.0 * math.cos(math.radians(10.0))
        assert w.speed_mps[:, col] == pytest.approx(math.hypot(u, v), rel=1e-12)
        assert w.from_deg[:, col] == pytest.approx(math.degrees(math.atan2(-u, -v)) % 360.0, abs=1e-9)
    assert w.from_deg[0, 0] == pytest.approx(350.0) and w.from_deg[0, 3] == pytest.approx(10.0)  # edge values


@pytest.mark.parametrize(
    ("grid", "pattern"),
    [
        ("missing", r"no_such_vel\.asc: speed file not found"),
        ("crs", r"w_vel\.asc: CRS EPSG:32618 differs from the landscape's EPSG:5070"),
        ("small", r"w_vel\.asc: the wind grid does not cover 40 burnable cells"),
        ("angle", r"w_ang\.asc: direction 361 deg at row 2, col 3 is outside \[0, 360\]"),
        ("noprj", r"w_vel\.asc: no CRS"),
        ("bands", r"w\.tif: a wind GeoTIFF needs 2 bands"),
    ],
)
def test_bad_grids_are_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], grid: str, pattern: str
) -> None:
    land = flat_grass(tmp_path)
    speed, from_deg = np.full((10, 20), 4.0), np.full((10, 20), 270.0)
    kw: dict = {"x0": 500000.0, "y_top": 4000000.0, "cell_m": 60.0}
    if grid == "crs":
        kw["crs"] = "EPSG:32618"
    if grid == "small":  # one grid column short in the east: the landscape's last 2 columns
        speed, from_deg = speed[:, :19], from_deg[:, :19]
    if grid == "angle":
        from_deg[2, 3] = 361.0
    vel, ang = write_asc_pair(tmp_path / "w", speed, from_deg, **kw)
    arg = f"{vel},{ang}"
    if grid == "missing":
        arg = f"{tmp_path / 'no_such_vel.asc'},{ang}"
    if grid == "noprj":
        vel.with_suffix(".prj").unlink()
    if grid == "bands":
        arg = str(tmp_path / "w.tif")
        with rasterio.open(tmp_path / "w.tif", "w", driver="GTiff", height=10, width=20, count=1, dtype="float64",
                           crs=CRS, transform=from_origin(500000.0, 4000000.0, 60.0, 60.0)) as dst:  # fmt: skip
            dst.write(speed, 1)
    assert main([str(land), "--out", str(tmp_path / "out"), "--wind-grid", arg]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert err.startswith("fire_behavior: error: ")
    assert re.search(pattern, err), err


# --- the raster fire on worcester_vt -------------------------------------------------------------


def scenario_window() -> tuple[float, float, float, float]:
    s = load_scenario(SCENARIOS / "worcester_vt.yaml")
    return landscape_of(s.fires.raster.landscape).bounds


def model(**overrides: object) -> RasterFireModel:
    s = load_scenario(SCENARIOS / "worcester_vt.yaml", overrides=overrides)
    return RasterFireModel(s.fires.raster, s.terrain, lakes=s.lakes, drop_radius_m=s.fires.drop_radius_m)


def grid_over_window(tmp_path: Path, speed_of_col, from_of_col, cell_m: float = 90.0) -> tuple[Path, Path]:
    """A grid of ``cell_m`` covering the scenario's window with a margin, values by column."""
    x0, y0, x1, y1 = scenario_window()
    gx0, gy1 = x0 - 2 * cell_m, y1 + 2 * cell_m
    cols, rows = int((x1 - gx0) / cell_m) + 3, int((gy1 - y0) / cell_m) + 3
    xc = gx0 + (np.arange(cols) + 0.5) * cell_m
    speed = np.tile([speed_of_col(x) for x in xc], (rows, 1))
    from_deg = np.tile([from_of_col(x) for x in xc], (rows, 1))
    return write_asc_pair(tmp_path / "w", speed, from_deg, x0=gx0, y_top=gy1, cell_m=cell_m)


def grid_wind(vel: Path, ang: Path, **extra: object) -> list[dict]:
    return [{"start_s": -600.0, "grid": {"vel": str(vel), "ang": str(ang), "speed_units": "mps"}, **extra}]


def test_a_uniform_grid_is_the_uniform_wind_cell_for_cell(tmp_path: Path) -> None:
    """8 m/s from the west as a grid (the scenario's wind, direction_deg 0 = toward east)."""
    vel, ang = grid_over_window(tmp_path, lambda x: 8.0, lambda x: 270.0)
    uniform = model()
    gridded = model(**{"fires.raster.wind": grid_wind(vel, ang)})
    assert gridded.spec.wind[0].speed_mps == pytest.approx(8.0) and gridded.spec.wind[
        0
    ].direction_deg == pytest.approx(0.0)
    inner = uniform._inner
    for name in ("_head", "_head_dir", "_A", "_Cx", "_Cy", "_res"):
        np.testing.assert_allclose(
            getattr(gridded, name)[inner], getattr(uniform, name)[inner], rtol=1e-9, atol=1e-12
        )
    assert np.array_equal(gridded.fire_type, uniform.fire_type)
    for k in range(120):
        uniform.step(float(k), 1.0)
        gridded.step(float(k), 1.0)
    assert np.array_equal(gridded.state_grid(), uniform.state_grid())
    burnt = np.isfinite(uniform.t_ign)
    assert np.array_equal(np.isfinite(gridded.t_ign), burnt)
    np.testing.assert_allclose(gridded.t_ign[burnt], uniform.t_ign[burnt], rtol=1e-9, atol=1e-6)


def test_each_half_of_a_grid_spreads_as_the_uniform_wind_of_its_own(tmp_path: Path) -> None:
    """West of the window's middle 8 m/s from the west; east of it 4 m/s from the north."""
    x0, _, x1, _ = scenario_window()
    mid = 0.5 * (x0 + x1)
    vel, ang = grid_over_window(
        tmp_path, lambda x: 8.0 if x < mid else 4.0, lambda x: 270.0 if x < mid else 0.0
    )
    gridded = model(**{"fires.raster.wind": grid_wind(vel, ang, speed_mps=8.0, direction_deg=0.0)})
    west = model(**{"fires.raster.wind": [{"start_s": -600.0, "speed_mps": 8.0, "direction_deg": 0.0}]})
    east = model(**{"fires.raster.wind": [{"start_s": -600.0, "speed_mps": 4.0, "direction_deg": 270.0}]})
    xc = west.xc + scenario_window()[0]  # projected x of the cell centres
    for half, ref in ((xc < mid - 90.0, west), (xc > mid + 90.0, east)):
        for name in ("_head", "_head_dir", "_A", "_Cx", "_Cy"):
            got = getattr(gridded, name)[gridded._inner][:, half]
            np.testing.assert_allclose(got, getattr(ref, name)[ref._inner][:, half], rtol=1e-9, atol=1e-12)
    assert not np.allclose(gridded._head[gridded._inner], west._head[west._inner])


def test_the_shipped_synthetic_grid_loads_and_turns_the_fire() -> None:
    vel = SAMPLE / "worcester_vt_270_8_120m_vel.asc"
    ang = SAMPLE / "worcester_vt_270_8_120m_ang.asc"
    wind = [
        {
            "start_s": -600.0,
            "grid": {
                "vel": "wind/worcester_vt/" + vel.name,
                "ang": "wind/worcester_vt/" + ang.name,
                "speed_units": "mps",
            },
        }
    ]
    gridded = model(**{"fires.raster.wind": wind})
    w = gridded.spec.wind[0]
    assert w.grid is not None and w.grid.speed_path == str(vel)
    assert 6.0 < w.speed_mps < 10.0 and (w.direction_deg < 30.0 or w.direction_deg > 330.0)  # about east
    uniform = model()
    heads = gridded._head[gridded._inner][gridded.burnable[gridded._inner]]
    assert not np.allclose(heads, uniform._head[uniform._inner][uniform.burnable[uniform._inner]])
    assert gridded.truth()[0].area_m2 > 0.0


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def _flat(tmp_path: Path, shape: tuple[int, int], fuel: int = 102) -> object:
    """flat_grass with another fuel (99: barren, nothing burnable); the landscape itself."""
    from fire_uav_common.landscape import load_landscape

    sub = tmp_path / f"land{fuel}"
    sub.mkdir()
    doc = {"fuel_kind": "fbfm40"}
    for name, value in {"fuel": fuel, "elevation": 300, "slope": 0, "aspect": -1}.items():
        with rasterio.open(
            sub / f"{name}.tif", "w", driver="GTiff", height=shape[0], width=shape[1], count=1,
            dtype="int16", crs=CRS, transform=from_origin(500000.0, 4000000.0, 30.0, 30.0), nodata=32767,
        ) as dst:  # fmt: skip
            dst.write(np.full(shape, value, dtype=np.int16), 1)
        doc[name] = f"{name}.tif"
    (sub / "land.yaml").write_text(yaml.safe_dump({"landscape": doc}))
    return load_landscape(sub / "land.yaml")


def _tif(path: Path, speed: np.ndarray, from_deg: np.ndarray, transform) -> Path:
    with rasterio.open(
        path, "w", driver="GTiff", height=speed.shape[0], width=speed.shape[1], count=2, dtype="float64",
        crs=CRS, transform=transform,
    ) as dst:  # fmt: skip
        dst.write(speed, 1)
        dst.write(from_deg, 2)
    return path


def test_each_cell_is_the_bilinear_blend_of_its_four_grid_neighbours(tmp_path: Path) -> None:
    """A 4 x 5 grid of 60 m cells with arbitrary winds over an 8 x 10 landscape of 30 m cells:
    each cell's (east, north) components are np.interp along x then along y of the grid's, which
    also holds the outermost centres' values beyond them (the module doc's edge rule)."""
    from fire_uav_common.scenario.wind_grid import WindGrid, wind_on_landscape

    land = _flat(tmp_path, (8, 10))
    rng = np.random.default_rng(7)
    # rounded to the 6 decimals the ASCII grid holds
    speed, from_deg = np.round(rng.uniform(1.0, 9.0, (4, 5)), 6), np.round(rng.uniform(0.0, 360.0, (4, 5)), 6)
    vel, ang = write_asc_pair(tmp_path / "w", speed, from_deg, x0=500000.0, y_top=4000000.0, cell_m=60.0)
    w = wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)
    speed, from_deg = read_tif(vel).astype(float), read_tif(ang).astype(float)  # as the file holds them
    u_g, v_g = -speed * np.sin(np.radians(from_deg)), -speed * np.cos(np.radians(from_deg))
    gx, gy = 30.0 + 60.0 * np.arange(5), -(30.0 + 60.0 * np.arange(4))  # centres, from the top-left corner
    lx, ly = 15.0 + 30.0 * np.arange(10), -(15.0 + 30.0 * np.arange(8))
    for q_g, which in ((u_g, "u"), (v_g, "v")):
        rows = np.array([np.interp(lx, gx, row) for row in q_g])  # (4, 10)
        want = np.array([np.interp(-ly, -gy, rows[:, j]) for j in range(10)]).T  # (8, 10)
        got = (
            (-w.speed_mps * np.sin(np.radians(w.from_deg)))
            if which == "u"
            else (-w.speed_mps * np.cos(np.radians(w.from_deg)))
        )
        assert got == pytest.approx(want, abs=1e-9), which


def test_a_grid_one_column_wide_gives_every_cell_its_column(tmp_path: Path) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, wind_on_landscape

    land = _flat(tmp_path, (4, 2))
    vel, ang = write_asc_pair(
        tmp_path / "w", np.array([[3.0], [5.0]]), np.array([[90.0], [90.0]]), x0=500000.0, y_top=4000000.0,
        cell_m=60.0,
    )  # fmt: skip
    w = wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)
    assert w.speed_mps[:, 0].tolist() == pytest.approx([3.0, 3.5, 4.5, 5.0])
    assert w.speed_mps[:, 1].tolist() == pytest.approx([3.0, 3.5, 4.5, 5.0])


def test_a_grid_short_in_the_west_is_named(tmp_path: Path) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, WindGridError, wind_on_landscape

    land = _flat(tmp_path, (4, 4))
    vel, ang = write_asc_pair(
        tmp_path / "w",
        np.full((2, 2), 4.0),
        np.full((2, 2), 270.0),
        x0=500040.0,
        y_top=4000000.0,
        cell_m=60.0,
    )
    with pytest.raises(WindGridError, match=r"w_vel\.asc: the wind grid does not cover 4 burnable cells"):
        wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)


@pytest.mark.parametrize(
    "transform",
    [
        rasterio.Affine(60.0, 0.0, 500000.0, 0.0, 60.0, 3999880.0),  # south-up
        rasterio.Affine(0.5, 0.0, 500000.0, 0.0, 0.5, 3999880.0),  # south-up, small cells
        rasterio.Affine(-60.0, 0.0, 500120.0, 0.0, -60.0, 4000000.0),  # east-west flipped
        rasterio.Affine(60.0, 0.5, 500000.0, 0.0, -60.0, 4000000.0),  # sheared rows
        rasterio.Affine(60.0, 0.0, 500000.0, 0.5, -60.0, 4000000.0),  # sheared columns
    ],
)
def test_rotated_or_flipped_grids_are_refused_by_name(tmp_path: Path, transform) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, WindGridError, wind_on_landscape

    land = _flat(tmp_path, (4, 4))
    n = 240 if abs(transform.a) < 1 else 2
    path = _tif(tmp_path / "w.tif", np.full((n, n), 4.0), np.full((n, n), 270.0), transform)
    with pytest.raises(WindGridError, match=r"^.*w\.tif: rotated or flipped grids are not supported$"):
        wind_on_landscape(WindGrid(str(path), None, "mps"), land)


def test_a_grid_of_one_metre_cells_is_read(tmp_path: Path) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, wind_on_landscape

    land = _flat(tmp_path, (4, 4))
    path = _tif(
        tmp_path / "w.tif",
        np.full((120, 120), 4.0),
        np.full((120, 120), 270.0),
        from_origin(500000.0, 4000000.0, 1.0, 1.0),
    )
    assert wind_on_landscape(WindGrid(str(path), None, "mps"), land).speed_mps == pytest.approx(
        np.full((4, 4), 4.0)
    )


def test_pair_files_of_two_shapes_or_a_missing_or_unreadable_file_are_named(tmp_path: Path) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, WindGridError, wind_on_landscape

    land = _flat(tmp_path, (4, 4))
    kw: dict = {"x0": 500000.0, "y_top": 4000000.0, "cell_m": 60.0}
    vel, _ = write_asc_pair(tmp_path / "a", np.full((2, 2), 4.0), np.full((2, 2), 270.0), **kw)
    _, ang = write_asc_pair(tmp_path / "b", np.full((2, 3), 4.0), np.full((2, 3), 270.0), **kw)
    with pytest.raises(
        WindGridError,
        match=r"b_ang\.asc: grid \(2, 3\) at \(60\.0, 0\.0, 500000\.0, 0\.0, -60\.0, 4000000\.0\) differs from .*a_vel\.asc's$",
    ):
        wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)
    with pytest.raises(WindGridError, match=r"no_ang\.asc: direction file not found$"):
        wind_on_landscape(WindGrid(str(vel), str(tmp_path / "no_ang.asc"), "mps"), land)
    bad = tmp_path / "bad_ang.asc"
    bad.write_text("this is not a grid\n")
    with pytest.raises(WindGridError) as err:
        wind_on_landscape(WindGrid(str(vel), str(bad), "mps"), land)
    assert (
        str(err.value)
        == f"{bad}: not a readable grid ('{bad}' not recognized as being in a supported file format.)"
    )


def test_the_wind_grid_argument_and_its_units() -> None:
    from fire_uav_common.scenario.wind_grid import WindGridError, parse_wind_grid_arg

    g = parse_wind_grid_arg("v.asc, a.asc", "kts")
    assert (Path(g.speed_path).name, Path(g.direction_path or "").name, g.speed_units) == (
        "v.asc",
        "a.asc",
        "kts",
    )
    for text in ("a.asc,b.asc,c.asc", "v.asc,", ",a.asc"):
        with pytest.raises(
            WindGridError, match=r"^--wind-grid wants VEL\.asc,ANG\.asc or one 2-band GeoTIFF, got "
        ):
            parse_wind_grid_arg(text)
    with pytest.raises(
        WindGridError,
        match=r"^wind grid speed units must be one of \['kph', 'kts', 'mph', 'mps'\], got 'furlongs'$",
    ):
        parse_wind_grid_arg("w.tif", "furlongs")


def test_the_domain_wind_is_the_mean_vector_and_calm_without_burnable_cells(tmp_path: Path) -> None:
    """A north wind everywhere blows toward -y: 270 deg ccw from +x; a landscape with no
    burnable cell has no domain wind."""
    from fire_uav_common.scenario.wind_grid import WindGrid, grid_mean_wind, wind_on_landscape

    kw: dict = {"x0": 500000.0, "y_top": 4000000.0, "cell_m": 60.0}
    vel, ang = write_asc_pair(tmp_path / "w", np.full((2, 2), 4.0), np.full((2, 2), 0.0), **kw)
    land = _flat(tmp_path, (4, 4))
    assert grid_mean_wind(
        wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land), land
    ) == pytest.approx((4.0, 270.0))
    barren = _flat(tmp_path, (4, 4), fuel=99)
    assert grid_mean_wind(wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), barren), barren) == (
        0.0,
        0.0,
    )


def _hat(q: np.ndarray, centres: np.ndarray, j: int) -> np.ndarray:
    """The weight of grid centre j at the points q in a 1-D linear blend held flat beyond the ends."""
    e = np.zeros(len(centres))
    e[j] = 1.0
    return np.interp(q, centres, e)


@pytest.mark.parametrize("geotiff", [False, True])
def test_a_cell_that_would_blend_a_nodata_value_is_named_and_only_those(
    tmp_path: Path, geotiff: bool
) -> None:
    """A 3 x 4 grid (60 m) over a 6 x 8 landscape (30 m), one nodata value at a time, in the speed
    or in the direction: the cells named are those whose blend gives it a weight > 0 (np.interp's
    hat functions); a nodata value no cell blends spoils nothing."""
    from fire_uav_common.scenario.wind_grid import WindGrid, WindGridError, wind_on_landscape

    land = _flat(tmp_path, (6, 8))
    gx, gy = 30.0 + 60.0 * np.arange(4), 30.0 + 60.0 * np.arange(3)  # from the top-left corner
    lx, ly = 15.0 + 30.0 * np.arange(8), 15.0 + 30.0 * np.arange(6)
    cases = [(0, 0, "vel"), (1, 2, "ang"), (2, 3, "vel"), (0, 2, "ang"), (2, 1, "vel"), (0, 1, "ang")]
    for k, (i, j, which) in enumerate(cases):
        speed, from_deg = np.full((3, 4), 4.0), np.full((3, 4), 270.0)
        (speed if which == "vel" else from_deg)[i, j] = -9999.0
        if geotiff:
            path = tmp_path / f"n{k}.tif"
            with rasterio.open(
                path, "w", driver="GTiff", height=3, width=4, count=2, dtype="float64", crs=CRS,
                transform=from_origin(500000.0, 4000000.0, 60.0, 60.0), nodata=-9999.0,
            ) as dst:  # fmt: skip
                dst.write(speed, 1)
                dst.write(from_deg, 2)
            grid = WindGrid(str(path), None, "mps")
        else:
            vel, ang = write_asc_pair(
                tmp_path / f"n{k}", speed, from_deg, x0=500000.0, y_top=4000000.0, cell_m=60.0
            )
            grid = WindGrid(str(vel), str(ang), "mps")
        weight = _hat(ly, gy, i)[:, None] * _hat(lx, gx, j)[None, :]
        n = int((weight > 0).sum())
        assert n > 0
        with pytest.raises(WindGridError) as err:
            wind_on_landscape(grid, land)
        r, c = (int(q[0]) for q in np.nonzero(weight > 0))
        x, y = 500015.0 + 30.0 * c, 3999985.0 - 30.0 * r
        assert str(err.value) == (
            f"{grid.speed_path}: the wind grid does not cover {n} burnable cells of the landscape "
            f"(first at row {r}, col {c}, ({x:.0f}, {y:.0f}) m); grid extent "
            "x 500000.0 to 500240.0 m, y 3999820.0 to 4000000.0 m"
        )


def test_negative_speeds_are_named_and_calm_and_north_are_valid(tmp_path: Path) -> None:
    from fire_uav_common.scenario.wind_grid import WindGrid, WindGridError, wind_on_landscape

    land = _flat(tmp_path, (4, 4))
    kw: dict = {"x0": 500000.0, "y_top": 4000000.0, "cell_m": 60.0}
    speed, from_deg = np.zeros((2, 2)), np.full((2, 2), 360.0)
    vel, ang = write_asc_pair(tmp_path / "calm", speed, from_deg, **kw)
    assert wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land).speed_mps == pytest.approx(
        np.zeros((4, 4))
    )
    speed[1, 0], speed[1, 1] = -1.5, -2.0
    vel, ang = write_asc_pair(tmp_path / "neg", speed, from_deg, **kw)
    with pytest.raises(WindGridError) as err:
        wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), land)
    assert str(err.value) == f"{vel}: speed -1.5 at row 1, col 0 is not >= 0 (2 cells)"
    with pytest.raises(WindGridError) as err:
        wind_on_landscape(WindGrid(str(vel), str(ang), "furlongs"), land)
    assert str(err.value) == f"{vel}: speed units must be one of ['kph', 'kts', 'mph', 'mps'], got 'furlongs'"


def test_cells_that_cannot_burn_get_a_calm_where_the_grid_is_missing_or_nodata(tmp_path: Path) -> None:
    """Module doc: a cell that cannot burn gets a calm (speed 0, from 0 deg), whether the grid does
    not reach it or it would blend a nodata value; a nodata value that is NaN and blended with
    weight 0 leaves its neighbours' wind finite."""
    from fire_uav_common.scenario.wind_grid import WindGrid, wind_on_landscape

    barren = _flat(tmp_path, (4, 4), fuel=99)
    kw: dict = {"x0": 500000.0, "y_top": 4000000.0, "cell_m": 60.0}
    vel, ang = write_asc_pair(tmp_path / "c", np.full((1, 1), 4.0), np.full((1, 1), 90.0), **kw)
    w = wind_on_landscape(WindGrid(str(vel), str(ang), "mps"), barren)
    assert w.speed_mps[:2, :2] == pytest.approx(np.full((2, 2), 4.0))
    assert w.from_deg[:2, :2] == pytest.approx(np.full((2, 2), 90.0))
    outside = np.ones((4, 4), dtype=bool)
    outside[:2, :2] = False
    assert (w.speed_mps[outside] == 0.0).all() and (w.from_deg[outside] == 0.0).all()
    # a NaN nodata value at the grid's south-east corner: the north-west cell blends it with weight 0
    speed = np.full((2, 2), 4.0)
    speed[1, 1] = np.nan
    path = tmp_path / "nan.tif"
    with rasterio.open(
        path, "w", driver="GTiff", height=2, width=2, count=2, dtype="float64", crs=CRS,
        transform=from_origin(500000.0, 4000000.0, 60.0, 60.0), nodata=np.nan,
    ) as dst:  # fmt: skip
        dst.write(speed, 1)
        dst.write(np.full((2, 2), 90.0), 2)
    w = wind_on_landscape(WindGrid(str(path), None, "mps"), barren)
    assert w.speed_mps[0, 0] == pytest.approx(4.0) and np.isfinite(w.speed_mps).all()
    assert (w.speed_mps[2:, 2:] == 0.0).all() and (w.from_deg[2:, 2:] == 0.0).all()
