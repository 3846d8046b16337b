"""Write the synthetic WindNinja-format wind grid of worcester_vt (run offline, not in CI).

    python data/wind/worcester_vt/make_sample.py      # rewrites the four files beside this script

NOT WindNinja output (WindNinja does not run here): a documented stand-in in WindNinja's ASCII
format, the worcester_vt scenario's 20-ft wind (8 m/s from the west) turned by the terrain with
two plain rules, on a 120 m grid over the whole landscape (EPSG:5070, the landscape's CRS):

- speed: ``8 m/s x clip(1 + dz / 200 m, 0.5, 1.6)``, dz the cell's elevation above the mean
  elevation within 1 km (ridges windier, hollows sheltered);
- direction: the part of the wind blowing up or down the smoothed slope is cut by
  ``min(slope / 0.3, 0.6)`` (the wind turns along the contours on steep ground).

Files: ``worcester_vt_270_8_120m_vel.asc`` (speed [m/s]: written with WindNinja's
``output_speed_units`` mps), ``worcester_vt_270_8_120m_ang.asc`` (direction the wind blows FROM
[deg clockwise from north]) and a ``.prj`` beside each (the landscape's CRS, ESRI WKT).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import rasterio
from scipy import ndimage

HERE = Path(__file__).resolve().parent
LANDSCAPE = HERE.parents[1] / "landscapes" / "worcester_vt" / "elevation.tif"
NAME = "worcester_vt_270_8_120m"
CELL_M = 120.0
SPEED_MPS = 8.0  # the worcester_vt scenario's 20-ft wind
FROM_DEG = 270.0  # from the west (the scenario's direction_deg 0: toward +x, east)


def main() -> None:
    with rasterio.open(LANDSCAPE) as src:
        z = src.read(1, masked=True).astype(float).filled(np.nan)
        t, crs = src.transform, src.crs
    k = int(round(CELL_M / t.a))  # 4 landscape cells per grid cell
    rows, cols = -(-z.shape[0] // k), -(-z.shape[1] // k)
    pad = np.full((rows * k, cols * k), np.nan)
    pad[: z.shape[0], : z.shape[1]] = z
    blocks = pad.reshape(rows, k, cols, k)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # blocks wholly outside the data
        zc = np.nanmean(blocks, axis=(1, 3))
    zc = np.where(np.isfinite(zc), zc, np.nanmean(zc))
    smooth = ndimage.uniform_filter(zc, size=int(round(2000 / CELL_M)) | 1, mode="nearest")
    dz = zc - smooth
    speed = SPEED_MPS * np.clip(1.0 + dz / 200.0, 0.5, 1.6)
    gy, gx = np.gradient(ndimage.uniform_filter(zc, size=3, mode="nearest"), CELL_M)
    gy = -gy  # rows run south: north is -row
    slope = np.hypot(gx, gy)
    nx, ny = (
        np.where(slope > 0, gx / np.where(slope > 0, slope, 1), 0.0),
        np.where(slope > 0, gy / np.where(slope > 0, slope, 1), 0.0),
    )
    to = np.radians(FROM_DEG + 180.0)
    ux, uy = np.sin(to), np.cos(to)  # unit vector the wind blows toward (east, north)
    cut = np.minimum(slope / 0.3, 0.6) * (ux * nx + uy * ny)
    ux, uy = ux - cut * nx, uy - cut * ny
    from_deg = np.round(np.degrees(np.arctan2(-ux, -uy)) % 360.0, 1) % 360.0
    header = (
        f"ncols        {cols}\nnrows        {rows}\nxllcorner    {t.c:.6f}\n"
        f"yllcorner    {t.f - rows * CELL_M:.6f}\ncellsize     {CELL_M:g}\nNODATA_value -9999\n"
    )
    prj = crs.to_wkt(version="WKT1_ESRI")  # as WindNinja (GDAL) writes a .prj
    for suffix, values, fmt in (("vel", speed, "{:.2f}"), ("ang", from_deg, "{:.1f}")):
        body = "\n".join(" ".join(fmt.format(v) for v in row) for row in values)
        (HERE / f"{NAME}_{suffix}.asc").write_text(header + body + "\n")
        (HERE / f"{NAME}_{suffix}.prj").write_text(prj)


if __name__ == "__main__":
    main()
