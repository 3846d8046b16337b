"""The map view the Foxglove bridge sends for a mission on a landscape, decoded as a client would.

NavSatFix: the CDR the bridge logs, decoded with ``mcap-ros2-support``'s decoder (independent of
the rosbags code that wrote it) from the schema text the channel announces, against the
latitude / longitude the mission summary gives for the same points (``geo_summary``). GeoJSON:
the burned area's polygons, checked as properties of any grid (their area is the cells' area,
every burnt cell centre inside, every other outside, simple rings with the RFC 7946
orientation) and, in WGS84, by projecting them back to the landscape's metres.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import fire_uav_recording as rec
import foxglove.messages
import numpy as np
import pytest
import yaml
from fire_uav_common.scenario import load_scenario
from fire_uav_common.scenario.ground import geo_summary
from fire_uav_recording.geo import (
    FIRE_AREA_TOPIC,
    NAVSAT_TYPE,
    GeoView,
    cell_polygons,
    geo_frame_of_scenario,
    geo_frame_of_scenario_file,
    truth_fix_topic,
)
from fire_uav_recording.raw_topics import schema_text
from matplotlib.path import Path as MplPath
from mcap_ros2._dynamic import generate_dynamic

SCENARIOS = Path(__file__).resolve().parents[2] / "fire_world_sim" / "scenarios"
WORCESTER = SCENARIOS / "worcester_vt.yaml"


# --- polygons of cells --------------------------------------------------------------------------
def _area(ring: list) -> float:
    return 0.5 * sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring[:-1], ring[1:], strict=True))


def _inside(poly: list, x: float, y: float) -> bool:
    def within(ring: list) -> bool:
        return bool(MplPath(np.asarray(ring[:-1], dtype=float)).contains_point((x, y)))

    return within(poly[0]) and not any(within(h) for h in poly[1:])


def check_polygons(mask: np.ndarray) -> list:
    polys = cell_polygons(mask)
    total = 0.0
    for poly in polys:
        for k, ring in enumerate(poly):
            body = ring[:-1]
            assert ring[0] == ring[-1] and len(body) >= 4
            assert len(set(body)) == len(body), f"ring touches itself: {ring}"
            a = _area(ring)
            assert (a > 0) == (k == 0), "outer rings counter-clockwise, holes clockwise"
            total += a
    assert total == pytest.approx(float(mask.sum()))
    for r in range(mask.shape[0]):
        for c in range(mask.shape[1]):
            assert any(_inside(p, c + 0.5, r + 0.5) for p in polys) == bool(mask[r, c]), (r, c)
    return polys


def test_shapes_whose_polygons_are_known():
    assert cell_polygons(np.array([[1]])) == [[[(0, 0), (1, 0), (1, 1), (0, 1), (0, 0)]]]
    assert len(check_polygons(np.array([[1, 0], [0, 1]]))) == 2  # diagonal cells: two polygons
    ring = np.ones((3, 3), dtype=bool)
    ring[1, 1] = False
    (poly,) = check_polygons(ring)  # one polygon with one hole
    assert len(poly) == 2 and _area(poly[1]) == -1.0
    c_shape = np.array([[1, 1, 1], [1, 0, 0], [1, 0, 1], [1, 1, 0]], dtype=bool)[::-1]
    check_polygons(c_shape)  # the C's tips meet at a corner: still simple rings
    assert check_polygons(np.zeros((3, 4), dtype=bool)) == []
    check_polygons(np.indices((7, 7)).sum(0) % 2 == 0)  # a checkerboard: every corner a touch


def test_polygons_of_random_grids():
    rng = np.random.default_rng(3)
    for _ in range(150):
        shape = (int(rng.integers(1, 13)), int(rng.integers(1, 13)))
        check_polygons(rng.random(shape) < rng.random())


# --- the messages of a landscape mission --------------------------------------------------------
@pytest.fixture(scope="module")
def frame():
    f = geo_frame_of_scenario_file(WORCESTER)
    assert f is not None and f.landscape == "worcester_vt"
    return f


@pytest.fixture(scope="module")
def typestore():
    return rec.fleet_typestore()


def test_a_mission_without_a_landscape_has_no_map_view():
    for name in ("ff_two_fires", "grass_running"):
        raw = yaml.safe_load((SCENARIOS / f"{name}.yaml").read_text())
        assert geo_frame_of_scenario(raw, str(SCENARIOS / f"{name}.yaml")) is None


def _truth(typestore, homes: list[dict], t_s: float) -> bytes:
    T = typestore.types
    vehicles = [
        T["fire_uav_msgs/msg/VehicleTruth"](
            uav_id=k, status=1, x_m=p["x_m"], y_m=p["y_m"], z_m=400.0 + k, yaw_rad=0.0, v_lin_mps=0.0,
            v_z_mps=0.0, omega_z_radps=0.0, water_kg=0.0, commands_clamped=0, commands_missed=0,
        )
        for k, p in enumerate(homes)
    ]  # fmt: skip
    stamp = T["builtin_interfaces/msg/Time"](sec=int(t_s), nanosec=int(round((t_s % 1) * 1e9)))
    msg = T["fire_uav_msgs/msg/WorldTruth"](
        header=T["std_msgs/msg/Header"](stamp=stamp, frame_id="map"), step=3, min_separation_m=math.inf,
        collisions=0, vehicles=vehicles, fires=[],
    )  # fmt: skip
    return bytes(typestore.serialize_cdr(msg, "fire_uav_msgs/msg/WorldTruth"))


def test_navsat_fix_per_uav_decodes_to_the_summarys_lat_lon(frame, typestore):
    homes = geo_summary(load_scenario(WORCESTER))["uav_homes"]  # type: ignore[index]
    view = GeoView(typestore, frame)
    out = view.on_truth(_truth(typestore, homes, 12.5))
    assert [t for t, _ in out] == [truth_fix_topic(k) for k in range(len(homes))]
    assert truth_fix_topic(3) == "/uav_3/geo/truth_fix"
    decode = generate_dynamic(NAVSAT_TYPE, schema_text(typestore, NAVSAT_TYPE))[NAVSAT_TYPE]
    for k, ((_, data), home) in enumerate(zip(out, homes, strict=True)):
        fix = decode(data)
        assert fix.header.frame_id == f"uav_{k}"
        assert (fix.header.stamp.sec, fix.header.stamp.nanosec) == (12, 500_000_000)
        assert round(fix.latitude, 6) == home["lat_deg"] and round(fix.longitude, 6) == home["lon_deg"]
        assert fix.altitude == 400.0 + k
        assert (fix.status.status, fix.status.service) == (0, 1)  # STATUS_FIX, SERVICE_GPS
        assert fix.position_covariance_type == 0  # UNKNOWN: the truth has no error figure


def _grid(typestore, data: np.ndarray, t_s: float, origin=(0.0, 0.0), res=30.0) -> bytes:
    T = typestore.types
    info = T["nav_msgs/msg/MapMetaData"](
        map_load_time=T["builtin_interfaces/msg/Time"](sec=0, nanosec=0), resolution=res,
        width=data.shape[1], height=data.shape[0],
        origin=T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=origin[0], y=origin[1], z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        ),
    )  # fmt: skip
    stamp = T["builtin_interfaces/msg/Time"](sec=int(t_s), nanosec=int(round((t_s % 1) * 1e9)))
    msg = T["nav_msgs/msg/OccupancyGrid"](
        header=T["std_msgs/msg/Header"](stamp=stamp, frame_id="map"), info=info,
        data=np.asarray(data, dtype=np.int8).ravel(),
    )  # fmt: skip
    return bytes(typestore.serialize_cdr(msg, "nav_msgs/msg/OccupancyGrid"))


def test_burned_area_geojson_is_the_grids_area_in_wgs84(frame, typestore):
    from pyproj import CRS, Transformer

    yy, xx = np.mgrid[0:40, 0:50]
    data = np.zeros((40, 50), dtype=np.int8)
    burned = (xx - 12) ** 2 + ((yy - 20) * 1.4) ** 2 < 64
    data[burned] = 60
    data[burned & (xx >= 17)] = 100  # the head burning
    data[20, 12] = 20  # a wet cell inside: a hole
    view = GeoView(typestore, frame, fire_area_period_s=1.0)
    text = view.on_fire_grid(_grid(typestore, data, 10.0))
    assert text is not None
    doc = json.loads(text)
    assert doc["type"] == "FeatureCollection"
    names = [f["properties"]["name"] for f in doc["features"]]
    assert names == ["burned area", "burning"]
    back = Transformer.from_crs("EPSG:4326", CRS.from_wkt(frame.crs_wkt), always_xy=True)
    for feature, mask in zip(doc["features"], (data >= 60, data >= 100), strict=True):
        geom = feature["geometry"]
        assert geom["type"] == "MultiPolygon" and feature["properties"]["t_s"] == 10.0
        area = 0.0
        for poly in geom["coordinates"]:
            for k, ring in enumerate(poly):
                lon, lat = np.asarray(ring).T
                assert ring[0] == ring[-1]
                assert np.all((44.34 < lat) & (lat < 44.37) & (-72.53 < lon) & (lon < -72.49))
                x, y = back.transform(lon, lat)
                x, y = x - frame.projected_origin[0], y - frame.projected_origin[1]
                a = 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))
                assert (a > 0) == (k == 0)  # RFC 7946: exterior counter-clockwise
                area += a
        cells = float(mask.sum()) * 900.0
        # coordinates to 1e-7 deg (about 1 cm) along a perimeter of a few hundred metres
        assert area == pytest.approx(cells, rel=1e-4) and feature["properties"]["area_m2"] == cells
    # the first burned cell's south-west corner is where the landscape puts that map point
    lat0, lon0 = frame.latlon(0.0, 0.0)
    assert (float(lat0), float(lon0)) == pytest.approx((44.3502523, -72.5195742), abs=1e-6)
    # what the channel sends: foxglove.GeoJSON carrying the text
    assert text.encode() in foxglove.messages.GeoJson(geojson=text).encode()
    assert FIRE_AREA_TOPIC == "/geo/fire_area"


def test_the_burned_area_is_sent_once_per_period_of_sim_time(frame, typestore):
    data = np.zeros((4, 4), dtype=np.int8)
    data[1:3, 1:3] = 100
    view = GeoView(typestore, frame, fire_area_period_s=1.0)
    sent = [view.on_fire_grid(_grid(typestore, data, t)) is not None for t in (0.0, 0.5, 0.99, 1.0, 1.2, 2.5)]
    assert sent == [True, False, False, True, False, True]
