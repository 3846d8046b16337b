"""Positions on the Earth for map tools (Foxglove's Map panel): each UAV's true position as
``sensor_msgs/NavSatFix`` and the fire's burned area as GeoJSON, for missions on a landscape.

Pure Python (rosbags, numpy, pyproj through :mod:`fire_uav_common`); no rclpy. The Foxglove
bridge feeds :class:`GeoView` the raw CDR of ``/world/truth`` and ``/viz/fire_grid`` and sends what
it returns; the recorder writes the same fixes into the bag (``docs/recording.md``).

- The map frame of a scenario on a landscape is the landscape's projected metres (its CRS, e.g.
  EPSG:5070) minus the window's south-west corner (``projected_origin``); :class:`GeoFrame`
  turns map (x, y) [m] into WGS84 (latitude, longitude) [deg] through pyproj. A scenario
  without a landscape has no geographic frame: nothing is sent.
- :func:`truth_fixes`: one NavSatFix per vehicle of a ``WorldTruth``, on
  ``/uav_<k>/geo/truth_fix`` (:func:`truth_fix_topic`): the world's TRUE position, not the
  agent's estimate; ``header.frame_id`` the vehicle's truth frame ``uav_<k>``; ``altitude`` the
  map z [m] above the landscape's vertical datum (LANDFIRE elevation: NAVD88, about mean sea
  level), not above the WGS84 ellipsoid (the geoid separation is not applied); status FIX,
  service GPS; covariance type UNKNOWN (the truth carries no error figure).
- :func:`burned_area_geojson`: a GeoJSON FeatureCollection (RFC 7946: WGS84 longitude,
  latitude; outer rings counter-clockwise, holes clockwise) with a MultiPolygon of the burned
  area (burnt or burning cells of the fire grid) and one of the burning cells, the cells' union
  traced along their edges (:func:`cell_polygons`), on ``/geo/fire_area`` (``foxglove.GeoJSON``).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "FIRE_AREA_TOPIC",
    "GRID_BURNING",
    "GRID_BURNT",
    "NAVSAT_TYPE",
    "GeoFrame",
    "GeoView",
    "burned_area_geojson",
    "cell_polygons",
    "geo_frame_of_bag",
    "geo_frame_of_scenario",
    "truth_fix_topic",
    "truth_fixes",
]

NAVSAT_TYPE = "sensor_msgs/msg/NavSatFix"
TRUTH_TYPE = "fire_uav_msgs/msg/WorldTruth"
GRID_TYPE = "nav_msgs/msg/OccupancyGrid"
FIRE_AREA_TOPIC = "/geo/fire_area"
GRID_BURNT = (
    60  # /viz/fire_grid cell values (the world's grid_msg): unburned 0, wet 20, burnt 60, burning 100
)
GRID_BURNING = 100


def truth_fix_topic(uav_id: int) -> str:
    """The topic of UAV ``uav_id``'s true position as NavSatFix."""
    return f"/uav_{uav_id}/geo/truth_fix"


@dataclass(frozen=True)
class GeoFrame:
    """The map frame of a scenario on a landscape: map (x, y) = projected (x, y) - origin."""

    crs_wkt: str
    projected_origin: tuple[float, float]  # [m] in the landscape's CRS
    landscape: str = ""
    uav_count: int = 0  # the fleet the scenario (or the bag) names

    def latlon(self, x_m: Any, y_m: Any) -> tuple[np.ndarray, np.ndarray]:
        """WGS84 (latitude, longitude) [deg] of map points."""
        lon, lat = _transformer(self.crs_wkt).transform(
            np.asarray(x_m, dtype=float) + self.projected_origin[0],
            np.asarray(y_m, dtype=float) + self.projected_origin[1],
        )
        return np.asarray(lat), np.asarray(lon)


_TRANSFORMERS: dict[str, Any] = {}


def _transformer(crs_wkt: str) -> Any:
    if crs_wkt not in _TRANSFORMERS:
        from pyproj import CRS, Transformer

        _TRANSFORMERS[crs_wkt] = Transformer.from_crs(CRS.from_wkt(crs_wkt), "EPSG:4326", always_xy=True)
    return _TRANSFORMERS[crs_wkt]


def geo_frame_of_scenario(raw: Mapping[str, Any], file: str = "") -> GeoFrame | None:
    """The geographic frame of a parsed scenario (``file``: where it was read, so a landscape path
    relative to it resolves), None without a landscape. Raises the scenario loader's
    ``ScenarioError`` (one line naming the file and field) when it names one that cannot be read."""
    fires = raw.get("fires") if isinstance(raw, Mapping) else None
    raster = fires.get("raster") if isinstance(fires, Mapping) else None
    if not (isinstance(raster, Mapping) and raster.get("landscape") is not None):
        return None
    from fire_uav_common.scenario import scenario_from_dict
    from fire_uav_common.scenario.ground import landscape_of

    where = file if file and Path(file).is_file() else "<dict>"
    scenario = scenario_from_dict(dict(raw), file=where)
    land = scenario.fires.raster.landscape  # type: ignore[union-attr]
    assert land is not None
    window = landscape_of(land)
    ox, oy = land.projected_origin
    return GeoFrame(window.crs_wkt, (float(ox), float(oy)), land.name, int(scenario.uavs.count))


def geo_frame_of_scenario_file(path: str | Path) -> GeoFrame | None:
    """:func:`geo_frame_of_scenario` of a scenario YAML file."""
    import yaml

    raw = yaml.safe_load(Path(path).read_text(encoding="utf8"))
    return geo_frame_of_scenario(raw if isinstance(raw, Mapping) else {}, str(path))


def geo_frame_of_bag(path: str | Path) -> GeoFrame | None:
    """:func:`geo_frame_of_scenario` of the scenario a mission bag recorded (its metadata)."""
    import yaml

    import fire_uav_recording as rec

    with rec.open_bag(path) as bag:
        custom = dict(bag.custom_data)
    text = custom.get(rec.KEY_SCENARIO_YAML, "")
    raw = yaml.safe_load(text) if text else None
    frame = geo_frame_of_scenario(
        raw if isinstance(raw, Mapping) else {}, custom.get(rec.KEY_SCENARIO_FILE, "")
    )
    try:  # the fleet that flew (the runner's --uavs), not the scenario's default
        return dataclasses.replace(frame, uav_count=int(custom[rec.KEY_UAV_COUNT])) if frame else None
    except (KeyError, ValueError):
        return frame


def truth_fixes(typestore: Any, truth: Any, frame: GeoFrame) -> list[tuple[str, bytes]]:
    """(topic, CDR bytes of a ``sensor_msgs/NavSatFix``) for each vehicle of a deserialised
    ``WorldTruth`` (module docstring), stamped with the truth's stamp."""
    vehicles = list(truth.vehicles)
    if not vehicles:
        return []
    lat, lon = frame.latlon([v.x_m for v in vehicles], [v.y_m for v in vehicles])
    types = typestore.types
    fix_cls, status_cls = types[NAVSAT_TYPE], types["sensor_msgs/msg/NavSatStatus"]
    header_cls = types["std_msgs/msg/Header"]
    stamp = truth.header.stamp
    out = []
    for v, la, lo in zip(vehicles, np.atleast_1d(lat), np.atleast_1d(lon), strict=True):
        k = int(v.uav_id)
        msg = fix_cls(
            header=header_cls(stamp=stamp, frame_id=f"uav_{k}"),
            status=status_cls(status=status_cls.STATUS_FIX, service=status_cls.SERVICE_GPS),
            latitude=float(la),
            longitude=float(lo),
            altitude=float(v.z_m),
            position_covariance=np.zeros(9, dtype=np.float64),
            position_covariance_type=fix_cls.COVARIANCE_TYPE_UNKNOWN,
        )
        out.append((truth_fix_topic(k), bytes(typestore.serialize_cdr(msg, NAVSAT_TYPE))))
    return out


# --- the burned area as polygons -----------------------------------------------------------------
_STEP = {(1, 0): 0, (0, 1): 1, (-1, 0): 2, (0, -1): 3}  # direction -> index, counter-clockwise


def cell_polygons(mask: np.ndarray) -> list[list[list[tuple[int, int]]]]:
    """The union of the set cells of ``mask`` (rows = y, row 0 at y = 0) as polygons in cell-corner
    coordinates (column, row): each ``[outer ring, hole rings...]``, rings closed (first vertex
    repeated), outer rings counter-clockwise and holes clockwise, collinear vertices dropped.

    Each set cell contributes its edges that border an unset cell, directed with the cell on
    their left; they are joined into rings, turning left where two rings meet at a corner
    (cells touching only diagonally stay separate polygons), and a ring that still touches
    itself is split there (:func:`_split_at_touches`), so every ring is simple.
    """
    m = np.pad(np.asarray(mask, dtype=bool), 1)
    r, c = np.nonzero(m[1:-1, 1:-1])
    r, c = r + 1, c + 1  # indices in the padded array; corners below are in the unpadded frame
    nxt: dict[tuple[int, int], list[tuple[int, int]]] = {}

    def add(sel: np.ndarray, x0: np.ndarray, y0: np.ndarray, dx: int, dy: int) -> None:
        for a, b in zip(x0[sel].tolist(), y0[sel].tolist(), strict=True):
            nxt.setdefault((a, b), []).append((a + dx, b + dy))

    x, y = c - 1, r - 1
    add(~m[r - 1, c], x, y, 1, 0)  # bottom edge, eastward
    add(~m[r, c + 1], x + 1, y, 0, 1)  # right edge, northward
    add(~m[r + 1, c], x + 1, y + 1, -1, 0)  # top edge, westward
    add(~m[r, c - 1], x, y + 1, 0, -1)  # left edge, southward
    rings: list[list[tuple[int, int]]] = []
    while nxt:
        start = next(iter(nxt))
        first = nxt[start].pop(0)
        if not nxt[start]:
            del nxt[start]
        ring = [start]
        prev_dir, cur = (first[0] - start[0], first[1] - start[1]), first
        while True:
            outs = nxt.get(cur, [])
            if cur == start:  # back at the start: close unless the turn rule leaves by another edge
                end = _turn_left(cur, prev_dir, [first, *outs])
                if end == first:
                    break
            else:
                end = _turn_left(cur, prev_dir, outs)
            ring.append(cur)
            outs.remove(end)
            if not outs:
                del nxt[cur]
            prev_dir, cur = (end[0] - cur[0], end[1] - cur[1]), end
        rings += [_simplify(loop) for loop in _split_at_touches(ring)]
    outers = [rg for rg in rings if _signed_area(rg) > 0]
    holes = [rg for rg in rings if _signed_area(rg) < 0]
    polys: list[list[list[tuple[int, int]]]] = [[o] for o in outers]
    if holes and outers:
        # the unset cell on the right of each hole's first edge lies inside that hole
        pts = np.array(
            [(h[0][0] + 0.5 * (h[1][0] - h[0][0]) + 0.5 * (h[1][1] - h[0][1]),
              h[0][1] + 0.5 * (h[1][1] - h[0][1]) - 0.5 * (h[1][0] - h[0][0])) for h in holes]
        )  # fmt: skip
        inside = np.array([_contains_points(o, pts) for o in outers])  # (outer, hole)
        size = np.array([_signed_area(o) for o in outers])
        for k, h in enumerate(holes):
            cands = np.flatnonzero(inside[:, k])
            if cands.size:
                polys[int(cands[np.argmin(size[cands])])].append(h)
    return [[[*rg, rg[0]] for rg in p] for p in polys]


def _turn_left(at: tuple[int, int], came: tuple[int, int], outs: list[tuple[int, int]]) -> tuple[int, int]:
    """The edge end of ``outs`` that turns most to the left of direction ``came`` (left, then
    straight on, then right)."""
    if len(outs) == 1:
        return outs[0]
    left = _STEP[came] + 1
    return min(outs, key=lambda e: (left - _STEP[(e[0] - at[0], e[1] - at[1])]) % 4)


def _split_at_touches(ring: list[tuple[int, int]]) -> list[list[tuple[int, int]]]:
    """A ring that passes a corner twice (it touches itself there: a C of cells whose tips meet
    diagonally) as the simple loops it is made of: the loop between the two visits, then the
    rest. A counter-clockwise loop is a polygon, a clockwise one a hole (OGC simple features
    and RFC 7946 want simple rings; a hole may touch its outer ring at a point)."""
    out, todo = [], [ring]
    while todo:
        rg = todo.pop()
        seen: dict[tuple[int, int], int] = {}
        for j, v in enumerate(rg):
            if v in seen:
                i = seen[v]
                todo += [rg[i:j], rg[:i] + rg[j:]]
                break
            seen[v] = j
        else:
            out.append(rg)
    return out


def _simplify(ring: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The ring without the vertices where it goes straight on."""
    n = len(ring)
    keep = []
    for i in range(n):
        (ax, ay), (bx, by), (cx, cy) = ring[i - 1], ring[i], ring[(i + 1) % n]
        if (bx - ax) * (cy - by) - (by - ay) * (cx - bx) != 0:
            keep.append(ring[i])
    return keep


def _signed_area(ring: list[tuple[int, int]]) -> float:
    """Shoelace formula: > 0 for a counter-clockwise ring."""
    a = 0.0
    for i in range(len(ring)):
        (x0, y0), (x1, y1) = ring[i - 1], ring[i]
        a += x0 * y1 - x1 * y0
    return 0.5 * a


def _contains_points(ring: list[tuple[int, int]], pts: np.ndarray) -> np.ndarray:
    """Which of ``pts`` (n, 2) lie inside ``ring`` (even-odd rule, counting the edges a ray to
    +x crosses; the points are cell centres, never on an edge)."""
    v = np.asarray(ring, dtype=float)
    x0, y0 = v[:, 0], v[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    px, py = pts[:, 0:1], pts[:, 1:2]
    spans = (y0 > py) != (y1 > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = px < x0 + (py - y0) * (x1 - x0) / (y1 - y0)
    return np.asarray(np.count_nonzero(spans & cross, axis=1) % 2 == 1)


def _multipolygon(
    mask: np.ndarray, origin: tuple[float, float], resolution_m: float, frame: GeoFrame
) -> dict[str, Any]:
    polys = cell_polygons(mask)
    coords = []
    for p in polys:
        rings = []
        for rg in p:
            xy = np.asarray(rg, dtype=float) * resolution_m
            lat, lon = frame.latlon(xy[:, 0] + origin[0], xy[:, 1] + origin[1])
            rings.append([[round(float(a), 7), round(float(b), 7)] for a, b in zip(lon, lat, strict=True)])
        coords.append(rings)
    return {"type": "MultiPolygon", "coordinates": coords}


def burned_area_geojson(
    data: np.ndarray, origin: tuple[float, float], resolution_m: float, frame: GeoFrame, t_s: float
) -> str:
    """The GeoJSON text of the fire grid ``data`` (rows = y from ``origin`` [m, map frame], cell
    values as ``/viz/fire_grid``): a FeatureCollection of the burned area (burnt or burning
    cells) and the burning cells, each a MultiPolygon in WGS84 with its area [m^2] (on the
    map), the sim time [s] and a style for the Map panel. Longitude and latitude to 1e-7 deg
    (about 1 cm)."""
    data = np.asarray(data)
    cell_area = resolution_m * resolution_m
    features = []
    for name, mask, color in (
        ("burned area", data >= GRID_BURNT, "#555555"),
        ("burning", data >= GRID_BURNING, "#ff6a00"),
    ):
        features.append(
            {
                "type": "Feature",
                "properties": {
                    "name": name,
                    "t_s": round(float(t_s), 3),
                    "area_m2": float(mask.sum()) * cell_area,
                    "style": {"color": color, "fillColor": color, "fillOpacity": 0.35, "weight": 2},
                },
                "geometry": _multipolygon(mask, origin, resolution_m, frame),
            }
        )
    return json.dumps({"type": "FeatureCollection", "features": features}, separators=(",", ":"))


class GeoView:
    """The map view of a mission on a landscape, fed raw CDR (no ROS): ``on_truth`` gives each
    UAV's NavSatFix, ``on_fire_grid`` the burned area's GeoJSON at most once per
    ``fire_area_period_s`` of sim time (the grid can be large; the Map panel needs no more)."""

    def __init__(self, typestore: Any, frame: GeoFrame, fire_area_period_s: float = 1.0) -> None:
        import fire_uav_recording as rec

        for t in (NAVSAT_TYPE, TRUTH_TYPE, GRID_TYPE):
            if not rec.ensure_type(typestore, t):
                raise rec.BagError(f"type {t} has no .msg definition in AMENT_PREFIX_PATH")
        self.typestore = typestore
        self.frame = frame
        self.fire_area_period_s = fire_area_period_s
        self._last_area_s = -math.inf

    def on_truth(self, data: bytes) -> list[tuple[str, bytes]]:
        """(topic, NavSatFix CDR) per vehicle of one ``/world/truth`` message."""
        return truth_fixes(self.typestore, self.typestore.deserialize_cdr(data, TRUTH_TYPE), self.frame)

    def on_fire_grid(self, data: bytes) -> str | None:
        """The GeoJSON of one ``/viz/fire_grid`` message, or None within the period of the last."""
        grid = self.typestore.deserialize_cdr(data, GRID_TYPE)
        t = grid.header.stamp.sec + grid.header.stamp.nanosec * 1e-9
        if t - self._last_area_s < self.fire_area_period_s - 1e-9:
            return None
        self._last_area_s = t
        info = grid.info
        cells = np.asarray(grid.data, dtype=np.int8).reshape(info.height, info.width)
        origin = (float(info.origin.position.x), float(info.origin.position.y))
        return burned_area_geojson(cells, origin, float(info.resolution), self.frame, t)
