"""``fires.raster.wind[].grid`` in a scenario on a landscape: the loader resolves, reads and checks
the grid once, fills the entry's domain wind from it, and names the file and the field of every
bad input in one line (ScenarioError)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import rasterio
import yaml
from fire_uav_common.errors import ScenarioError
from fire_uav_common.scenario import load_scenario
from fire_uav_common.scenario.ground import landscape_of

ROOT = Path(__file__).resolve().parents[4]
SCENARIO = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / "worcester_vt.yaml"
SAMPLE = "wind/worcester_vt/worcester_vt_270_8_120m"


def window() -> tuple[float, float, float, float]:
    return landscape_of(load_scenario(SCENARIO).fires.raster.landscape).bounds


def write_pair(
    folder: Path,
    speed: float | np.ndarray,
    from_deg: float | np.ndarray,
    *,
    crs: str = "EPSG:5070",
    margin_m: float = 180.0,
) -> tuple[Path, Path]:
    """A 60 m WindNinja-style pair over the scenario's window (plus ``margin_m``; negative: short)."""
    x0, y0, x1, y1 = window()
    cell = 60.0
    cols, rows = int((x1 - x0 + 2 * margin_m) // cell), int((y1 - y0 + 2 * margin_m) // cell)
    header = (
        f"ncols {cols}\nnrows {rows}\nxllcorner {x0 - margin_m}\nyllcorner {y1 + margin_m - rows * cell}\n"
        f"cellsize {cell}\nNODATA_value -9999\n"
    )
    prj = rasterio.crs.CRS.from_string(crs).to_wkt(version="WKT1_ESRI")
    out = []
    for suffix, value in (("vel", speed), ("ang", from_deg)):
        grid = np.broadcast_to(np.asarray(value, dtype=float), (rows, cols))
        p = folder / f"w_{suffix}.asc"
        p.write_text(header + "\n".join(" ".join(f"{v:g}" for v in row) for row in grid) + "\n")
        p.with_suffix(".prj").write_text(prj)
        out.append(p)
    return out[0], out[1]


def scenario_with(tmp_path: Path, wind: list[dict]) -> Path:
    d = yaml.safe_load(SCENARIO.read_text())
    d["fires"]["raster"]["wind"] = wind
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(d))
    return p


def test_a_grid_relative_to_the_scenario_and_its_mean_domain_wind(tmp_path: Path) -> None:
    write_pair(tmp_path, 20.0, 180.0)  # 20 mi/h (WindNinja's default unit) from the south
    s = load_scenario(
        scenario_with(tmp_path, [{"start_s": -600, "grid": {"vel": "w_vel.asc", "ang": "w_ang.asc"}}])
    )
    (w,) = s.fires.raster.wind
    assert w.grid is not None and w.grid.speed_path == str((tmp_path / "w_vel.asc").resolve())
    assert w.grid.speed_units == "mph"
    assert w.speed_mps == pytest.approx(20.0 * 0.44704, rel=1e-6)  # the vehicles' drift: mean wind
    assert w.direction_deg == pytest.approx(90.0, abs=1e-5)  # toward north, ccw from +x


def test_the_shipped_sample_resolves_under_data_and_keeps_a_given_domain_wind(tmp_path: Path) -> None:
    grid = {"vel": f"{SAMPLE}_vel.asc", "ang": f"{SAMPLE}_ang.asc", "speed_units": "mps"}
    s = load_scenario(
        scenario_with(tmp_path, [{"start_s": -600, "grid": grid, "speed_mps": 8.0, "direction_deg": 0.0}])
    )
    (w,) = s.fires.raster.wind
    assert (w.speed_mps, w.direction_deg) == (8.0, 0.0)
    assert w.grid is not None and w.grid.speed_path == str(ROOT / "data" / f"{SAMPLE}_vel.asc")


@pytest.mark.parametrize(
    ("case", "pattern"),
    [
        ("missing", r"s\.yaml: fires\.raster\.wind\[0\]\.grid\.ang: 'nope_ang\.asc': file not found"),
        (
            "crs",
            r"s\.yaml: fires\.raster\.wind\[0\]\.grid: .*w_vel\.asc: CRS EPSG:32618 differs from the landscape's EPSG:5070",
        ),
        (
            "short",
            r"s\.yaml: fires\.raster\.wind\[0\]\.grid: .*w_vel\.asc: the wind grid does not cover \d+ burnable cells",
        ),
        (
            "angle",
            r"s\.yaml: fires\.raster\.wind\[0\]\.grid: .*w_ang\.asc: direction -5 deg at row 0, col 0 is outside \[0, 360\]",
        ),
        (
            "units",
            r"s\.yaml: fires\.raster\.wind\[0\]\.grid\.speed_units: must be one of \['mps', 'mph', 'kph', 'kts'\]",
        ),
        ("both", r"s\.yaml: fires\.raster\.wind\[0\]\.grid: either tif .* or vel and ang"),
        ("half", r"s\.yaml: fires\.raster\.wind\[0\]: with a grid give both speed_mps and direction_deg"),
        ("nogrid", r"s\.yaml: fires\.raster\.wind\[0\]\.direction_deg: required field missing"),
    ],
)
def test_bad_wind_grids_name_the_file_and_the_field(tmp_path: Path, case: str, pattern: str) -> None:
    speed, from_deg = 10.0, np.full((1, 1), 270.0)
    kw: dict = {}
    if case == "crs":
        kw["crs"] = "EPSG:32618"
    if case == "short":
        kw["margin_m"] = -300.0
    write_pair(tmp_path, speed, from_deg, **kw)
    if case == "angle":  # one value below 0 in the north-west corner
        text = (tmp_path / "w_ang.asc").read_text().splitlines()
        text[6] = "-5 " + text[6].split(" ", 1)[1]
        (tmp_path / "w_ang.asc").write_text("\n".join(text) + "\n")
    entry: dict = {"start_s": -600, "grid": {"vel": "w_vel.asc", "ang": "w_ang.asc"}}
    if case == "missing":
        entry["grid"]["ang"] = "nope_ang.asc"
    if case == "units":
        entry["grid"]["speed_units"] = "furlongs"
    if case == "both":
        entry["grid"]["tif"] = "w_vel.asc"
    if case == "half":
        entry["speed_mps"] = 3.0
    if case == "nogrid":
        entry = {"start_s": -600, "speed_mps": 3.0}
    with pytest.raises(ScenarioError, match=pattern) as e:
        load_scenario(scenario_with(tmp_path, [entry]))
    assert "\n" not in str(e.value)


def test_a_grid_without_a_landscape_is_refused(tmp_path: Path) -> None:
    vel, ang = write_pair(tmp_path, 5.0, 270.0)
    d = yaml.safe_load((ROOT / "ros2_ws/src/fire_world_sim/scenarios/grass_running.yaml").read_text())
    d["fires"]["raster"]["wind"] = [{"start_s": 0, "grid": {"vel": str(vel), "ang": str(ang)}}]
    p = tmp_path / "g.yaml"
    p.write_text(yaml.safe_dump(d))
    with pytest.raises(
        ScenarioError, match=r"g\.yaml: fires\.raster\.wind\[0\]\.grid: needs fires\.raster\.landscape"
    ):
        load_scenario(p)


def test_uniform_entries_are_unchanged(tmp_path: Path) -> None:
    s = load_scenario(scenario_with(tmp_path, [{"start_s": -600, "speed_mps": 8.0, "direction_deg": 0.0}]))
    (w,) = s.fires.raster.wind
    assert (w.start_s, w.speed_mps, w.direction_deg, w.grid) == (-600.0, 8.0, 0.0, None)
    assert not math.isnan(w.speed_mps)
