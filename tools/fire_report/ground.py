"""The ground of a mission flown on a landscape: fuel classes, a hillshade and WGS84 positions.

A raster scenario may name a LANDFIRE landscape (``fires.raster.landscape``); the bag stores the
scenario's text, so the report reads the same window of the same landscape the world burned
(:func:`mission_ground`), through the scenario loader (the shipped name or the path relative to
the recorded scenario file). Missions without a landscape have no ground (None) and their report
is unchanged.

- Fuel classes: the 53 standard fuel models grouped into Scott & Burgan's fuel types (Scott &
  Burgan 2005, RMRS-GTR-153, Table 4 / pp. 8-9: GR grass, GS grass-shrub, SH shrub, TU
  timber-understory, TL timber litter, SB slash-blowdown, NB non-burnable), Anderson's 13 into
  the same families (1-3 grass, 4-7 shrub, 8-10 timber litter, 11-13 slash; Anderson 1982,
  INT-GTR-122), open water (98) apart from the other non-burnable codes (91-93, 99).
- Hillshade: Lambertian reflectance of a sun at azimuth 315 deg, altitude 45 deg (the
  cartographic convention, as GDAL's ``gdaldem hillshade`` defaults): the cosine of the angle
  between each cell's surface normal and the sun, by :meth:`matplotlib.colors.LightSource.hillshade`.
- Positions: map (x, y) [m] -> WGS84 (latitude, longitude) [deg] through the landscape's CRS
  (pyproj), the map frame's origin being the window's south-west corner (``projected_origin``).

Pure numpy / matplotlib; no ROS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from fire_uav_common.constants import EventType

from fire_report.data import RecordedMission

__all__ = [
    "FUEL_CLASSES",
    "Ground",
    "fuel_class",
    "hillshade",
    "mission_ground",
    "places",
    "shaded_fuel_rgba",
]

#: (name, colour) of each fuel class, index = class; a cell outside the landscape's data is -1
FUEL_CLASSES: tuple[tuple[str, str], ...] = (
    ("grass", "#e9d66b"),
    ("grass-shrub", "#c2c46a"),
    ("shrub", "#c08a4a"),
    ("timber understory", "#7fb36a"),
    ("timber litter", "#2f7d3b"),
    ("slash, blowdown", "#8e6bb0"),
    ("non-burnable", "#b8b8b8"),
    ("water", "#2f6db5"),
)
WATER = 7
NON_BURNABLE = 6
OUTSIDE = -1

# fuel code ranges -> class (FBFM40 101-204 by Scott & Burgan's hundreds-and-tens families,
# FBFM13 1-13 by Anderson's groups)
_RANGES = (
    (1, 3, 0), (4, 7, 2), (8, 10, 4), (11, 13, 5),
    (101, 109, 0), (121, 124, 1), (141, 149, 2), (161, 165, 3), (181, 189, 4), (201, 204, 5),
    (91, 99, NON_BURNABLE), (98, 98, WATER),
)  # fmt: skip

SUN_AZIMUTH_DEG = 315.0  # from the north-west, clockwise from north
SUN_ALTITUDE_DEG = 45.0


def fuel_class(codes: np.ndarray) -> np.ndarray:
    """The fuel class (index into :data:`FUEL_CLASSES`) of each fuel model code; -1 for 0 (no
    data) and any code outside the 53 models and 91-99."""
    codes = np.asarray(codes)
    out = np.full(codes.shape, OUTSIDE, dtype=np.int8)
    for lo, hi, k in _RANGES:  # water (98) last: it overrides the non-burnable range
        out[(codes >= lo) & (codes <= hi)] = k
    return out


def hillshade(elevation_m: np.ndarray, cell_m: float) -> np.ndarray:
    """Illumination in [0, 1] of each cell of a north-up grid (row 0 the northern edge, as a
    GeoTIFF) by a sun at :data:`SUN_AZIMUTH_DEG`, :data:`SUN_ALTITUDE_DEG` (Lambertian: the
    cosine of the angle between the surface normal and the sun; a flat cell gets sin 45 deg
    before matplotlib rescales the range to [0, 1])."""
    from matplotlib.colors import LightSource

    ls = LightSource(azdeg=SUN_AZIMUTH_DEG, altdeg=SUN_ALTITUDE_DEG)
    return np.asarray(ls.hillshade(np.asarray(elevation_m, dtype=float), vert_exag=1.0, dx=cell_m, dy=cell_m))


def shaded_fuel_rgba(
    fuel: np.ndarray, elevation_m: np.ndarray, cell_m: float, upsample: int = 1
) -> np.ndarray:
    """RGBA image (north-up, ``upsample`` pixels per cell each way) of the fuel classes shaded by
    the terrain: each class colour times a light of 0.35-1.0 by the hillshade, so a class stays
    recognisable in the shadows; cells outside the data transparent. The elevation is
    interpolated bilinearly to the pixels before shading (the relief is smooth, the fuel cells
    keep their edges)."""
    from matplotlib.colors import to_rgb

    k = max(1, int(upsample))
    cls = np.repeat(np.repeat(fuel_class(fuel), k, axis=0), k, axis=1)
    palette = np.array([to_rgb(c) for _, c in FUEL_CLASSES])
    rgb = palette[np.clip(cls, 0, None)]
    elev = np.asarray(elevation_m, dtype=float)
    if min(elev.shape) >= 2:
        if k > 1:
            from scipy import ndimage

            elev = ndimage.zoom(elev, k, order=1, mode="nearest", grid_mode=True)
        shade = hillshade(elev, cell_m / k)
    else:
        shade = np.ones(cls.shape)
    rgb = rgb * (0.35 + 0.65 * shade)[..., None]
    alpha = np.where(cls == OUTSIDE, 0.0, 1.0)[..., None]
    return np.concatenate([np.clip(rgb, 0.0, 1.0), alpha], axis=-1)


@dataclass(frozen=True)
class Ground:
    """A mission's landscape window in the map frame (x east, y north [m], origin the window's
    south-west corner). Rasters are north-up: row 0 is the northern edge."""

    name: str
    fuel: np.ndarray  # fuel model codes (0 outside the data)
    elevation_m: np.ndarray
    cell_m: float
    extent: tuple[float, float, float, float]  # x_min, x_max, y_min, y_max [m, map frame]
    projected_origin: tuple[float, float]  # the map origin in the landscape's CRS [m]
    crs_wkt: str
    lakes: tuple[tuple[float, float, float], ...] = ()  # refill lakes: x, y, diameter [m]
    ignitions: tuple[tuple[float, float, float], ...] = ()  # raster ignitions: x, y [m], start [s]

    def latlon(self, x_m: Any, y_m: Any) -> tuple[Any, Any]:
        """WGS84 (latitude, longitude) [deg] of map points (arrays or scalars), the conversion
        the live view and the recorder use (:class:`fire_uav_recording.geo.GeoFrame`)."""
        from fire_uav_recording.geo import GeoFrame

        return GeoFrame(self.crs_wkt, self.projected_origin).latlon(x_m, y_m)

    def classes_present(self) -> list[int]:
        """The fuel classes found in the window, in :data:`FUEL_CLASSES` order."""
        found = set(np.unique(fuel_class(self.fuel)).tolist())
        return [k for k in range(len(FUEL_CLASSES)) if k in found]


def _has_landscape(scenario: dict[str, Any]) -> bool:
    fires = scenario.get("fires") if isinstance(scenario, dict) else None
    raster = fires.get("raster") if isinstance(fires, dict) else None
    return isinstance(raster, dict) and raster.get("landscape") is not None


def mission_ground(mission: RecordedMission) -> tuple[Ground | None, str | None]:
    """(the mission's ground, None) on a landscape; (None, None) for a mission without one;
    (None, a one-line warning) when the recorded scenario names a landscape that cannot be read
    here (moved, or a scenario this version refuses)."""
    if not _has_landscape(mission.scenario):
        return None, None
    from fire_uav_common.errors import ScenarioError
    from fire_uav_common.landscape import LandscapeError
    from fire_uav_common.scenario import scenario_from_dict
    from fire_uav_common.scenario.ground import landscape_of

    file = mission.custom_data.get("fire_uav.scenario_file") or ""
    where = file if file and Path(file).is_file() else "<dict>"
    name = str(mission.scenario["fires"]["raster"]["landscape"].get("source", "?"))
    try:
        scenario = scenario_from_dict(mission.scenario, file=where)
        land = scenario.fires.raster.landscape  # type: ignore[union-attr]
        assert land is not None
        window = landscape_of(land)
    except (ScenarioError, LandscapeError, OSError) as err:
        return (
            None,
            f"the landscape {name} of the recorded scenario cannot be read here: {err}; the maps show no ground",
        )
    cs = window.cell_size_m
    rows, cols = window.shape
    lakes = tuple(
        (float(lk.x_m), float(lk.y_m), float(getattr(lk, "diameter_m", 0.0))) for lk in scenario.lakes
    )
    return (
        Ground(
            name=land.name or name,
            fuel=np.asarray(window.fuel),
            elevation_m=np.asarray(window.elevation_m, dtype=float),
            cell_m=cs,
            extent=(0.0, cols * cs, 0.0, rows * cs),
            projected_origin=(float(land.projected_origin[0]), float(land.projected_origin[1])),
            crs_wkt=window.crs_wkt,
            lakes=lakes,
            ignitions=tuple(
                (float(ig.x_m), float(ig.y_m), float(ig.start_s))
                for ig in (scenario.fires.raster.ignitions if scenario.fires.raster else ())
            ),
        ),
        None,
    )


def _place(ground: Ground, what: str, t_s: float | None, x: float, y: float, **extra: Any) -> dict[str, Any]:
    lat, lon = ground.latlon(x, y)
    return {"what": what, "t_s": t_s, "x_m": float(x), "y_m": float(y),
            "lat_deg": round(float(lat), 6), "lon_deg": round(float(lon), 6), **extra}  # fmt: skip


def places(mission: RecordedMission, ground: Ground) -> list[dict[str, Any]]:
    """Where things were, with latitude and longitude: each ignition of the scenario, each fire's
    centre when first recorded, each refill lake, each UAV's home, each drop and each UAV lost
    (where its vehicle fell). Rows ``{what, t_s, x_m, y_m, lat_deg, lon_deg, kind}``; ``kind`` is
    one of "ignition", "fire", "lake", "home", "drop", "loss"."""
    out: list[dict[str, Any]] = []
    for i, (x, y, t) in enumerate(ground.ignitions):
        out.append(_place(ground, f"ignition {i}", t, x, y, kind="ignition"))
    for fid, f in sorted(mission.truth_fires.items()):
        if f and f["x"].size:
            what = f"fire {fid}, its centre when first recorded"
            out.append(_place(ground, what, float(f["t"][0]), f["x"][0], f["y"][0], kind="fire"))
    for i, (x, y, d) in enumerate(ground.lakes):
        what = f"lake {i}" + (f" (refill disc {d:.0f} m across)" if d > 0 else "")
        out.append(_place(ground, what, None, x, y, kind="lake"))
    for u, v in sorted(mission.truth_vehicles.items()):
        if v and v["x"].size:
            out.append(_place(ground, f"UAV {u} home", float(v["t"][0]), v["x"][0], v["y"][0], kind="home"))
    for e in mission.world_events:
        if e.type == EventType.DROP and e.value > 0 and math.isfinite(e.x_m) and math.isfinite(e.y_m):
            on = f"on fire {e.fire_id}" if e.fire_id >= 0 else "missed"
            out.append(_place(ground, f"drop by UAV {e.uav_id}, {on}", e.t_s, e.x_m, e.y_m, kind="drop"))
        elif e.type == EventType.CRASH:
            x, y = e.x_m, e.y_m
            track = mission.truth_vehicles.get(e.uav_id)
            if not (math.isfinite(x) and math.isfinite(y)) and track:
                i = max(0, int(np.searchsorted(track["t"], e.t_s, side="right")) - 1)
                x, y = float(track["x"][i]), float(track["y"][i])
            if math.isfinite(x) and math.isfinite(y):
                out.append(_place(ground, f"UAV {e.uav_id} lost", e.t_s, x, y, kind="loss"))
    return out


GROUND_PIXELS = 600  # [px] about this many image pixels across the window's longer side


def draw_ground(ax: Any, ground: Ground, zorder: float = 0.0) -> None:
    """The shaded fuel classes under whatever ``ax`` draws next (map frame, north up)."""
    k = int(np.clip(GROUND_PIXELS // max(ground.fuel.shape), 1, 8))
    ax.imshow(
        shaded_fuel_rgba(ground.fuel, ground.elevation_m, ground.cell_m, k),
        origin="upper",
        extent=ground.extent,
        interpolation="nearest",
        zorder=zorder,
    )


def fuel_legend_handles(ground: Ground) -> list[Any]:
    """Legend patches of the fuel classes present in the window."""
    from matplotlib.patches import Patch

    return [Patch(facecolor=FUEL_CLASSES[k][1], edgecolor="none", label=FUEL_CLASSES[k][0])
            for k in ground.classes_present()]  # fmt: skip
