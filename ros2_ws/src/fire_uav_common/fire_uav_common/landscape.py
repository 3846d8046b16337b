"""A LANDFIRE-style landscape: GeoTIFF layers of fuel, terrain and canopy on one grid (no ROS).

A landscape file (YAML) names the layers; paths are relative to that file::

    landscape:
      fuel: fbfm40.tif            # FBFM40 (101-204) or FBFM13 (1-13); 91-99 non-burnable
      fuel_kind: fbfm40           # or fbfm13
      elevation: elevation.tif    # [m]
      slope: slope.tif            # [percent]
      aspect: aspect.tif          # [deg clockwise from north, downslope]; negative = flat
      canopy_cover: cc.tif        # [percent]            (optional, as are the three below)
      canopy_height: ch.tif       # [m x 10]             LANDFIRE's scale
      canopy_base_height: cbh.tif # [m x 10]
      canopy_bulk_density: cbd.tif  # [kg/m^3 x 100]
      scales: {canopy_height: 0.1}  # optional: overrides the LANDFIRE scales above
      window: {x_min_m: .., y_min_m: .., x_max_m: .., y_max_m: ..}  # optional, map metres
      cell_size_m: 60             # optional: resample (fuel nearest or mode, the rest bilinear)
      fuel_resampling: mode       # nearest (default) or mode

The layers must share CRS, transform and shape. Cells where the fuel layer has no data are
outside the landscape (fuel code 0, never burn); a burnable cell with no data in another layer
is an error naming the layer (after resampling, a cell at the edge of the data that lacks any
layer is outside instead). The map frame is the raster's projected metres;
:meth:`Landscape.lonlat` gives WGS84 longitude / latitude through pyproj.

Every bad input raises :class:`LandscapeError` with one line naming the file, layer or field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

__all__ = [
    "FBFM13_CODES",
    "FBFM40_CODES",
    "LAYERS",
    "LANDFIRE_SCALES",
    "Landscape",
    "LandscapeError",
    "LandscapeSpec",
    "NONBURNABLE_CODES",
    "load_landscape",
    "read_landscape_spec",
]

LAYERS = (
    "fuel",
    "elevation",
    "slope",
    "aspect",
    "canopy_cover",
    "canopy_height",
    "canopy_base_height",
    "canopy_bulk_density",
)
REQUIRED = ("fuel", "elevation", "slope", "aspect")
# raster value x scale = the value in the unit the fire model reads (LANDFIRE's storage conventions)
LANDFIRE_SCALES = {
    "elevation": 1.0,  # m
    "slope": 1.0,  # percent
    "aspect": 1.0,  # deg
    "canopy_cover": 0.01,  # percent -> fraction
    "canopy_height": 0.1,  # m x 10 -> m
    "canopy_base_height": 0.1,  # m x 10 -> m
    "canopy_bulk_density": 0.01,  # kg/m^3 x 100 -> kg/m^3
}
NONBURNABLE_CODES = frozenset(range(91, 100))
FBFM13_CODES = frozenset(range(1, 14)) | NONBURNABLE_CODES
_SB40 = (
    *range(101, 110),
    *range(121, 125),
    *range(141, 150),
    *range(161, 166),
    *range(181, 190),
    *range(201, 205),
)
FBFM40_CODES = frozenset(_SB40) | NONBURNABLE_CODES
FUEL_KINDS = {"fbfm13": FBFM13_CODES, "fbfm40": FBFM40_CODES}
FUEL_RESAMPLING = ("nearest", "mode")
OUTSIDE = 0  # fuel code of a cell outside the data


class LandscapeError(ValueError):
    """A bad landscape input; the message is one line naming the file, layer or field."""


@dataclass(frozen=True)
class LandscapeSpec:
    """What a landscape file says: absolute layer paths and the read options."""

    source: Path  # the landscape file (or directory) the paths were resolved against
    paths: dict[str, Path]
    fuel_kind: str = "fbfm40"
    scales: dict[str, float] = field(default_factory=lambda: dict(LANDFIRE_SCALES))
    window: tuple[float, float, float, float] | None = None  # x_min, y_min, x_max, y_max [m]
    cell_size_m: float | None = None
    fuel_resampling: str = "nearest"


def _number(where: str, v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise LandscapeError(f"{where}: expected a number, got {v!r}")
    return float(v)


def read_landscape_spec(path: str | Path, overrides: dict[str, Any] | None = None) -> LandscapeSpec:
    """Read a landscape YAML (or a directory holding ``landscape.yaml``).

    ``overrides`` (e.g. from a scenario) replace keys of the file's ``landscape:`` mapping.
    """
    p = Path(path)
    if p.is_dir():
        p = p / "landscape.yaml"
    if not p.is_file():
        raise LandscapeError(f"{p}: landscape file not found")
    try:
        doc = yaml.safe_load(p.read_text())
    except yaml.YAMLError as e:
        raise LandscapeError(f"{p}: not valid YAML ({str(e).splitlines()[0]})") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("landscape"), dict):
        raise LandscapeError(f"{p}: expected a mapping 'landscape:'")
    d = dict(doc["landscape"])
    d.update(overrides or {})
    return spec_from_dict(d, p)


def spec_from_dict(d: dict[str, Any], source: Path) -> LandscapeSpec:
    """A :class:`LandscapeSpec` from the ``landscape:`` mapping; paths relative to ``source``'s folder."""
    known = {*LAYERS, "name", "fuel_kind", "scales", "window", "cell_size_m", "fuel_resampling"}
    for key in d:
        if key not in known:
            raise LandscapeError(f"{source}: landscape.{key}: unknown field; expected one of {sorted(known)}")
    base = source.parent if source.suffix else source
    paths: dict[str, Path] = {}
    for layer in LAYERS:
        v = d.get(layer)
        if v is None:
            if layer in REQUIRED:
                raise LandscapeError(f"{source}: landscape.{layer}: missing (a GeoTIFF path)")
            continue
        if not isinstance(v, str) or not v:
            raise LandscapeError(f"{source}: landscape.{layer}: expected a file path, got {v!r}")
        paths[layer] = (base / v).resolve()
    kind = d.get("fuel_kind", "fbfm40")
    if kind not in FUEL_KINDS:
        raise LandscapeError(
            f"{source}: landscape.fuel_kind: expected one of {sorted(FUEL_KINDS)}, got {kind!r}"
        )
    scales = dict(LANDFIRE_SCALES)
    for k, v in (d.get("scales") or {}).items():
        if k not in LANDFIRE_SCALES:
            raise LandscapeError(
                f"{source}: landscape.scales.{k}: unknown layer; expected one of {sorted(LANDFIRE_SCALES)}"
            )
        scales[k] = _number(f"{source}: landscape.scales.{k}", v)
    window = None
    if d.get("window") is not None:
        w = d["window"]
        keys = ("x_min_m", "y_min_m", "x_max_m", "y_max_m")
        if not isinstance(w, dict) or set(w) != set(keys):
            raise LandscapeError(f"{source}: landscape.window: expected the keys {list(keys)}")
        x0, y0, x1, y1 = (_number(f"{source}: landscape.window.{k}", w[k]) for k in keys)
        if not (x1 > x0 and y1 > y0):
            raise LandscapeError(f"{source}: landscape.window: x_max_m/y_max_m must exceed x_min_m/y_min_m")
        window = (x0, y0, x1, y1)
    cell = d.get("cell_size_m")
    if cell is not None:
        cell = _number(f"{source}: landscape.cell_size_m", cell)
        if cell <= 0:
            raise LandscapeError(f"{source}: landscape.cell_size_m: must be > 0, got {cell!r}")
    rs = d.get("fuel_resampling", "nearest")
    if rs not in FUEL_RESAMPLING:
        raise LandscapeError(
            f"{source}: landscape.fuel_resampling: expected one of {FUEL_RESAMPLING}, got {rs!r}"
        )
    return LandscapeSpec(source, paths, kind, scales, window, cell, rs)


@dataclass(frozen=True)
class Landscape:
    """Layers on one grid, in the fire model's units; row 0 is the northern edge (GeoTIFF order).

    ``fuel``: fuel model codes (0 outside the data); ``elevation_m``; ``slope_pct``; ``aspect_deg``
    (downslope, clockwise from north, -1 flat); ``canopy_cover`` [fraction]; ``canopy_height_m``,
    ``canopy_base_height_m`` [m]; ``canopy_bulk_density_kgpm3``. Non-fuel layers are 0 where the
    data is missing outside the burnable cells.
    """

    crs_wkt: str
    transform: tuple[float, float, float, float, float, float]  # GDAL affine a, b, c, d, e, f
    fuel_kind: str
    fuel: np.ndarray
    elevation_m: np.ndarray
    slope_pct: np.ndarray
    aspect_deg: np.ndarray
    canopy_cover: np.ndarray
    canopy_height_m: np.ndarray
    canopy_base_height_m: np.ndarray
    canopy_bulk_density_kgpm3: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.fuel.shape[0]), int(self.fuel.shape[1]))

    @property
    def cell_size_m(self) -> float:
        return float(self.transform[0])

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(x_min, y_min, x_max, y_max) in map metres."""
        a, _, c, _, e, f = self.transform
        rows, cols = self.shape
        return (c, f + e * rows, c + a * cols, f)

    @property
    def has_data(self) -> np.ndarray:
        return self.fuel != OUTSIDE

    @property
    def burnable(self) -> np.ndarray:
        return self.has_data & ~np.isin(self.fuel, list(NONBURNABLE_CODES))

    def cell_center(self, row: int | np.ndarray, col: int | np.ndarray) -> tuple[Any, Any]:
        """Map metres (x, y) of a cell's centre."""
        a, b, c, d, e, f = self.transform
        x = c + a * (np.asarray(col) + 0.5) + b * (np.asarray(row) + 0.5)
        y = f + d * (np.asarray(col) + 0.5) + e * (np.asarray(row) + 0.5)
        return x, y

    def cell_of(self, x_m: float, y_m: float) -> tuple[int, int]:
        """(row, col) of the cell holding a map point; LandscapeError outside the grid."""
        a, _, c, _, e, f = self.transform
        col, row = int(math.floor((x_m - c) / a)), int(math.floor((y_m - f) / e))
        rows, cols = self.shape
        if not (0 <= row < rows and 0 <= col < cols):
            raise LandscapeError(f"point ({x_m:.1f}, {y_m:.1f}) m lies outside the landscape {self.bounds}")
        return row, col

    def require_burnable(self, x_m: float, y_m: float, what: str = "ignition") -> tuple[int, int]:
        """(row, col) of a point that must burn (an ignition); LandscapeError naming ``what`` if not."""
        try:
            row, col = self.cell_of(x_m, y_m)
        except LandscapeError as e:
            raise LandscapeError(f"{what}: {e}") from None
        if not self.burnable[row, col]:
            code = int(self.fuel[row, col])
            kind = "outside the data" if code == OUTSIDE else f"non-burnable fuel code {code}"
            raise LandscapeError(f"{what} at ({x_m:.1f}, {y_m:.1f}) m: cell (row {row}, col {col}) is {kind}")
        return row, col

    def lonlat(self, x_m: Any, y_m: Any) -> tuple[Any, Any]:
        """WGS84 (longitude, latitude) [deg] of map points (pyproj)."""
        from pyproj import CRS, Transformer

        t = Transformer.from_crs(CRS.from_wkt(self.crs_wkt), "EPSG:4326", always_xy=True)
        return t.transform(x_m, y_m)


def _open(layer: str, path: Path) -> Any:
    import rasterio
    from rasterio.errors import RasterioIOError

    if not path.is_file():
        raise LandscapeError(f"layer '{layer}': file not found: {path}")
    try:
        return rasterio.open(path)
    except RasterioIOError as e:
        raise LandscapeError(
            f"layer '{layer}': not a readable GeoTIFF: {path} ({str(e).splitlines()[0]})"
        ) from None


def load_landscape(spec: LandscapeSpec | str | Path) -> Landscape:
    """Read, check, window and resample every layer of ``spec`` (module docstring)."""
    import rasterio
    from rasterio.enums import Resampling
    from rasterio.windows import Window, from_bounds
    from rasterio.windows import transform as window_transform

    if not isinstance(spec, LandscapeSpec):
        spec = read_landscape_spec(spec)
    datasets = {layer: _open(layer, path) for layer, path in spec.paths.items()}
    try:
        ref = datasets["fuel"]
        if ref.crs is None:
            raise LandscapeError(f"layer 'fuel' ({spec.paths['fuel']}): has no CRS")
        for layer, ds in datasets.items():
            where = f"layer '{layer}' ({spec.paths[layer]})"
            if ds.crs != ref.crs:
                raise LandscapeError(f"{where}: CRS {ds.crs} differs from the fuel layer's {ref.crs}")
            if ds.transform != ref.transform:
                raise LandscapeError(
                    f"{where}: transform {tuple(ds.transform)[:6]} differs from the fuel layer's {tuple(ref.transform)[:6]}"
                )
            if ds.shape != ref.shape:
                raise LandscapeError(f"{where}: shape {ds.shape} differs from the fuel layer's {ref.shape}")
        if (
            abs(ref.transform.b) > 0
            or abs(ref.transform.d) > 0
            or abs(ref.transform.a + ref.transform.e) > 1e-9
        ):
            raise LandscapeError(
                f"layer 'fuel' ({spec.paths['fuel']}): rotated or non-square cells are not supported"
            )
        full = Window(0, 0, ref.width, ref.height)
        win = full
        if spec.window is not None:
            x0, y0, x1, y1 = spec.window
            left, bottom, right, top = ref.bounds
            if x1 <= left or x0 >= right or y1 <= bottom or y0 >= top:
                raise LandscapeError(
                    f"{spec.source}: landscape.window {spec.window} lies outside the raster bounds "
                    f"({left}, {bottom}, {right}, {top})"
                )
            win = (
                from_bounds(x0, y0, x1, y1, ref.transform).round_offsets(op="floor").round_lengths(op="ceil")
            )
            win = win.intersection(full)
        transform = window_transform(win, ref.transform)
        out_shape = (int(win.height), int(win.width))
        if spec.cell_size_m is not None and abs(spec.cell_size_m - ref.transform.a) > 1e-9:
            factor = spec.cell_size_m / ref.transform.a
            out_shape = (max(1, round(win.height / factor)), max(1, round(win.width / factor)))
            transform = transform @ transform.scale(win.width / out_shape[1], win.height / out_shape[0])
        arrays: dict[str, np.ma.MaskedArray] = {}
        for layer, ds in datasets.items():
            if layer == "fuel":
                rs = Resampling.mode if spec.fuel_resampling == "mode" else Resampling.nearest
            elif layer == "aspect":
                rs = Resampling.nearest  # a circular quantity: no averaging across north
            else:
                rs = Resampling.bilinear
            arrays[layer] = ds.read(1, window=win, out_shape=out_shape, resampling=rs, masked=True)
        crs_wkt = ref.crs.to_wkt()
    finally:
        for ds in datasets.values():
            ds.close()
    del rasterio
    resampled = out_shape != (int(win.height), int(win.width))
    return _assemble(spec, arrays, crs_wkt, tuple(transform)[:6], resampled)


def _assemble(
    spec: LandscapeSpec,
    arrays: dict[str, np.ma.MaskedArray],
    crs_wkt: str,
    transform: tuple[float, ...],
    resampled: bool,
) -> Landscape:
    fuel_m = arrays["fuel"]
    has_data = ~np.ma.getmaskarray(fuel_m)
    if resampled:
        # at the edge of the data, resampling can leave a cell with fuel but no slope (or the
        # reverse): such a cell is outside, as the source grid cannot say what it holds
        for a in arrays.values():
            has_data &= ~np.ma.getmaskarray(a)
    if not has_data.any():
        raise LandscapeError(f"layer 'fuel' ({spec.paths['fuel']}): no data inside the window")
    fuel = np.where(has_data, np.ma.getdata(fuel_m), OUTSIDE).astype(np.int16)
    allowed = FUEL_KINDS[spec.fuel_kind]
    codes = {int(c) for c in np.unique(fuel[has_data])}
    unknown = sorted(codes - allowed)
    if unknown:
        raise LandscapeError(
            f"layer 'fuel' ({spec.paths['fuel']}): unknown {spec.fuel_kind.upper()} fuel code(s) {unknown[:10]}"
        )
    burnable = has_data & ~np.isin(fuel, list(NONBURNABLE_CODES))
    out: dict[str, np.ndarray] = {}
    for layer in LAYERS[1:]:
        if layer not in arrays:
            out[layer] = np.zeros(fuel.shape)
            continue
        a = arrays[layer]
        missing = np.ma.getmaskarray(a) & burnable
        if missing.any():
            r, c = (int(v[0]) for v in np.nonzero(missing))
            raise LandscapeError(
                f"layer '{layer}' ({spec.paths[layer]}): nodata inside the burnable area "
                f"({int(missing.sum())} cells, first at row {r}, col {c})"
            )
        out[layer] = np.ma.filled(a.astype(float), 0.0) * spec.scales[layer]
    aspect = out["aspect"]
    if "aspect" in arrays:
        aspect = np.where(np.ma.getmaskarray(arrays["aspect"]), -1.0, aspect)
    return Landscape(
        crs_wkt=crs_wkt,
        transform=(
            float(transform[0]),
            float(transform[1]),
            float(transform[2]),
            float(transform[3]),
            float(transform[4]),
            float(transform[5]),
        ),
        fuel_kind=spec.fuel_kind,
        fuel=fuel,
        elevation_m=out["elevation"],
        slope_pct=out["slope"],
        aspect_deg=aspect,
        canopy_cover=out["canopy_cover"],
        canopy_height_m=out["canopy_height"],
        canopy_base_height_m=out["canopy_base_height"],
        canopy_bulk_density_kgpm3=out["canopy_bulk_density"],
    )
