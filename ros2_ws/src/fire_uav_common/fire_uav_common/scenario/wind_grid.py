"""A gridded 20-ft wind on a landscape: WindNinja's ASCII pair or a 2-band GeoTIFF (no ROS).

WindNinja (firelab/windninja) writes its ASCII output as a pair of ESRI ASCII grids,
``<name>_vel.asc`` (speed) and ``<name>_ang.asc`` (the direction the wind blows FROM, degrees
clockwise from north), each with a ``.prj`` beside it holding the CRS. Neither file states the
speed's unit: it is the run's ``output_speed_units`` (``mph`` unless set otherwise; ``mps``,
``kph``, ``kts``), and the height is the run's ``output_wind_height`` (FlamMap and FARSITE read
the 20-ft wind: run WindNinja at 20 ft). A GeoTIFF holds the same two quantities as two bands of
one file (band 1 speed, band 2 from-direction).

:func:`wind_on_landscape` reads a grid, checks its CRS against the landscape's and resamples it
to the landscape's cell centres: bilinear on the (east, north) components of the vector the wind
blows toward, ``u = -S sin(D)``, ``v = -S cos(D)``, never on the angle (the mean of 350 and 10 deg
is north, not south); the cell's speed is ``hypot(u, v)`` and its from-direction
``atan2(-u, -v)``. A cell centre inside the grid's extent but beyond its outermost cell centres
takes the edge value along that axis. A burnable cell whose centre lies outside the grid, or that
would read a nodata value, is an error naming the file; a cell that cannot burn gets a calm.
The per-cell 20-ft wind then goes through each cell's wind adjustment factor exactly as a uniform
20-ft wind does (FlamMap computes the WAF "the same for gridded inputs as for stream inputs").

Every bad input raises :class:`WindGridError` (a :class:`~fire_uav_common.landscape.LandscapeError`)
with one line naming the file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..landscape import Landscape, LandscapeError
from .types import DEFAULT_SPEED_UNITS, SPEED_UNITS, WindGrid

__all__ = [
    "SPEED_UNITS",
    "WindGrid",
    "WindGridError",
    "WindOnLandscape",
    "grid_mean_wind",
    "parse_wind_grid_arg",
    "wind_on_landscape",
]


class WindGridError(LandscapeError):
    """A bad wind grid; the message is one line naming the file."""


@dataclass(frozen=True)
class WindOnLandscape:
    """A grid resampled to a landscape's cells (GeoTIFF row order: row 0 the northern row)."""

    speed_mps: np.ndarray  # 20-ft wind speed [m/s]
    from_deg: np.ndarray  # direction it blows from [deg clockwise from north, 0-360)


def parse_wind_grid_arg(text: str, speed_units: str = DEFAULT_SPEED_UNITS) -> WindGrid:
    """``VEL.asc,ANG.asc`` or ``WIND.tif`` (a command line's ``--wind-grid``) -> :class:`WindGrid`."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) > 2 or not all(parts):
        raise WindGridError(f"--wind-grid wants VEL.asc,ANG.asc or one 2-band GeoTIFF, got {text!r}")
    if speed_units not in SPEED_UNITS:
        raise WindGridError(
            f"wind grid speed units must be one of {sorted(SPEED_UNITS)}, got {speed_units!r}"
        )
    paths = [str(Path(p).resolve()) for p in parts]
    return WindGrid(paths[0], paths[1] if len(paths) == 2 else None, speed_units)


def _open(path: str, what: str) -> Any:
    import rasterio
    from rasterio.errors import RasterioIOError

    if not Path(path).is_file():
        raise WindGridError(f"{path}: {what} file not found")
    try:
        return rasterio.open(path)
    except RasterioIOError as e:
        raise WindGridError(f"{path}: not a readable grid ({str(e).splitlines()[0]})") from None


def _read(grid: WindGrid, crs_wkt: str) -> tuple[np.ma.MaskedArray, np.ma.MaskedArray, tuple[float, ...]]:
    """Speed [grid units] and from-direction [deg] as masked arrays, and the grid's transform;
    checks CRS, band count, shapes and value ranges."""
    from rasterio.crs import CRS

    land_crs = CRS.from_wkt(crs_wkt)
    names = [grid.speed_path] if grid.direction_path is None else [grid.speed_path, grid.direction_path]
    datasets = [_open(p, w) for p, w in zip(names, ("speed", "direction"), strict=False)]
    try:
        ref = datasets[0]
        if grid.direction_path is None and ref.count != 2:
            raise WindGridError(
                f"{grid.speed_path}: a wind GeoTIFF needs 2 bands (speed, from-direction), it has {ref.count}"
            )
        for path, ds in zip(names, datasets, strict=True):
            if ds.crs is None:
                raise WindGridError(
                    f"{path}: no CRS (WindNinja writes a .prj beside each .asc; expected the landscape's)"
                )
            if ds.crs != land_crs:
                raise WindGridError(
                    f"{path}: CRS {ds.crs.to_string()} differs from the landscape's {land_crs.to_string()}"
                )
            t = ds.transform
            if abs(t.b) > 0 or abs(t.d) > 0 or t.a <= 0 or t.e >= 0:
                raise WindGridError(f"{path}: rotated or flipped grids are not supported")
            if ds.shape != ref.shape or ds.transform != ref.transform:
                raise WindGridError(
                    f"{path}: grid {ds.shape} at {tuple(ds.transform)[:6]} differs from {names[0]}'s"
                )
        if grid.direction_path is None:
            speed = ref.read(1, masked=True)
            direction = ref.read(2, masked=True)
        else:
            speed = datasets[0].read(1, masked=True)
            direction = datasets[1].read(1, masked=True)
        transform = tuple(ref.transform)[:6]
    finally:
        for ds in datasets:
            ds.close()
    dir_path = grid.direction_path or f"{grid.speed_path} band 2"
    sv, dv = speed.astype(float), direction.astype(float)
    bad = ~np.ma.getmaskarray(dv) & ~((np.ma.getdata(dv) >= 0.0) & (np.ma.getdata(dv) <= 360.0))
    if bad.any():
        r, c = (int(v[0]) for v in np.nonzero(bad))
        raise WindGridError(
            f"{dir_path}: direction {float(dv.data[r, c]):g} deg at row {r}, col {c} is outside [0, 360] "
            f"({int(bad.sum())} cells)"
        )
    bad = ~np.ma.getmaskarray(sv) & ~((np.ma.getdata(sv) >= 0.0) & np.isfinite(np.ma.getdata(sv)))
    if bad.any():
        r, c = (int(v[0]) for v in np.nonzero(bad))
        raise WindGridError(
            f"{grid.speed_path}: speed {float(sv.data[r, c]):g} at row {r}, col {c} is not >= 0 ({int(bad.sum())} cells)"
        )
    return sv, dv, transform


def _axis(
    coord: np.ndarray, origin: float, step: float, n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Bilinear indices along one axis: (i0, i1, weight of i1, inside the grid's extent)."""
    f = (coord - origin) / step - 0.5  # fractional index of the cell centres
    inside = (f >= -0.5) & (f <= n - 0.5)
    f = np.clip(f, 0.0, n - 1.0)
    i0 = np.clip(np.floor(f).astype(np.int64), 0, max(n - 2, 0))
    i1 = np.minimum(i0 + 1, n - 1)
    w = np.where(i1 > i0, f - i0, 0.0)
    return i0, i1, w, inside


def wind_on_landscape(grid: WindGrid, land: Landscape) -> WindOnLandscape:
    """``grid`` resampled to every cell of ``land`` (module docstring). Raises WindGridError."""
    if grid.speed_units not in SPEED_UNITS:
        raise WindGridError(
            f"{grid.speed_path}: speed units must be one of {sorted(SPEED_UNITS)}, got {grid.speed_units!r}"
        )
    speed, direction, (a, _, c, _, e, f) = _read(grid, land.crs_wkt)
    rows, cols = speed.shape
    scale = SPEED_UNITS[grid.speed_units]
    rad = np.radians(np.ma.getdata(direction))
    s = np.ma.getdata(speed) * scale
    u = -s * np.sin(rad)  # [m/s] east component of the vector the wind blows toward
    v = -s * np.cos(rad)  # [m/s] north
    nodata = np.ma.getmaskarray(speed) | np.ma.getmaskarray(direction)
    xs, _ = land.cell_center(0, np.arange(land.shape[1]))
    _, ys = land.cell_center(np.arange(land.shape[0]), 0)
    c0, c1, wc, cin = _axis(np.asarray(xs, dtype=float), c, a, cols)
    r0, r1, wr, rin = _axis(np.asarray(ys, dtype=float), f, e, rows)
    R0, R1, WR = r0[:, None], r1[:, None], wr[:, None]
    C0, C1, WC = c0[None, :], c1[None, :], wc[None, :]

    def lerp(q: np.ndarray) -> np.ndarray:
        top = q[R0, C0] + WC * (q[R0, C1] - q[R0, C0])
        bottom = q[R1, C0] + WC * (q[R1, C1] - q[R1, C0])
        return top + WR * (bottom - top)  # type: ignore[no-any-return]

    # a nodata value with a weight > 0 spoils the cell
    spoiled = (
        (nodata[R0, C0] & ((1 - WR) * (1 - WC) > 0))
        | (nodata[R0, C1] & ((1 - WR) * WC > 0))
        | (nodata[R1, C0] & (WR * (1 - WC) > 0))
        | (nodata[R1, C1] & (WR * WC > 0))
    )
    covered = rin[:, None] & cin[None, :] & ~spoiled
    missing = land.burnable & ~covered
    if missing.any():
        r, col = (int(q[0]) for q in np.nonzero(missing))
        x, y = land.cell_center(r, col)
        raise WindGridError(
            f"{grid.speed_path}: the wind grid does not cover {int(missing.sum())} burnable cells of the landscape "
            f"(first at row {r}, col {col}, ({float(x):.0f}, {float(y):.0f}) m); grid extent "
            f"x {c:.1f} to {c + a * cols:.1f} m, y {f + e * rows:.1f} to {f:.1f} m"
        )
    uu = np.where(covered, lerp(np.where(nodata, 0.0, u)), 0.0)
    vv = np.where(covered, lerp(np.where(nodata, 0.0, v)), 0.0)
    spd = np.hypot(uu, vv)
    frm = np.degrees(np.arctan2(-uu, -vv)) % 360.0
    return WindOnLandscape(speed_mps=spd, from_deg=np.where(spd > 0, frm, 0.0))


def grid_mean_wind(w: WindOnLandscape, land: Landscape) -> tuple[float, float]:
    """(speed [m/s], direction it blows TOWARD [deg ccw from +x]) of the mean wind vector over the
    landscape's burnable cells: the one domain wind of a grid entry (the vehicles' drift)."""
    cells = land.burnable
    if not cells.any():
        return 0.0, 0.0
    rad = np.radians(w.from_deg[cells])
    u = float(np.mean(-w.speed_mps[cells] * np.sin(rad)))
    v = float(np.mean(-w.speed_mps[cells] * np.cos(rad)))
    return math.hypot(u, v), math.degrees(math.atan2(v, u)) % 360.0
