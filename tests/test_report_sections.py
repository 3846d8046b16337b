"""The report's PM and CP sections on bags whose answer is known from geometry (no ROS processes).

PM: a disc fire of radius R in the raster truth and a monitor whose 36 bins all read R + 10 m:
the constructed shape is a 36-gon of circumradius R + 10, so the distance error is 10 m less
the polygon's sag (at most (R + 10)(1 - cos 5 deg) = 0.4 m) and the raster's half cell.
CP: two power-diagram seeds 500 m apart with weights 1e5 m^2 apart put the border 100 m off the
middle (|q - s0|^2 - w0 = |q - s1|^2 - w1), so the cells have 0.4 and 0.6 of a 1 km^2 area.
"""

from __future__ import annotations

import math

import fire_uav_recording as bag_io
import numpy as np
import pytest
from fire_report import write_report
from fire_report.sections.cp import incumbent, power_labels
from fire_report.sections.pm import convex_hull, ray_extent_polygon, track_direction_changes
from fire_report.synthetic import SyntheticMission, write_synthetic_mission
from fire_uav_common import topics
from fire_uav_common.constants import CandidateKind, MstKind, PerimeterDirection
from fire_uav_common.stamps import s_to_ns, to_time_msg

R_M, CELL_M, CENTER = 100.0, 5.0, (300.0, 300.0)
BINS = 36
COSTS = [(1, 5.0), (2, 3.0), (3, 4.0), (2, 3.0), (4, 2.0), (5, 2.5)]  # (candidate id, cost); id 2 rebroadcast
AREA_YAML = "name: sections\narea: {x_min_m: 0, x_max_m: 1000, y_min_m: 0, y_max_m: 1000}\n"


def _write(path, *, pm: bool, cp: bool) -> None:
    ts = bag_io.fleet_typestore()
    T = ts.types
    Time, Header = T["builtin_interfaces/msg/Time"], T["std_msgs/msg/Header"]

    def hdr(t: float):
        return Header(stamp=to_time_msg(s_to_ns(t), Time), frame_id="map")

    custom = {bag_io.KEY_SCENARIO_YAML: AREA_YAML, bag_io.KEY_UAV_COUNT: "2"}
    with bag_io.BagWriter(path, custom_data=custom) as bw:

        def conn(name, typ):
            return bw.add_connection(name, typ, typestore=ts)

        def put(c, t, msg):
            bw.write(c, s_to_ns(t), ts.serialize_cdr(msg, msg.__msgtype__))

        if pm:
            c_grid = conn(topics.VIZ_FIRE_GRID, "nav_msgs/msg/OccupancyGrid")
            c_per = conn(topics.FLEET_PERIMETER, "fire_uav_msgs/msg/PerimeterMap")
            n = 120
            xs = (np.arange(n) + 0.5) * CELL_M
            gx, gy = np.meshgrid(xs, xs)
            occ = np.where(np.hypot(gx - CENTER[0], gy - CENTER[1]) <= R_M, 100, 0).astype(np.int8)
            G, Info, Pose = (T["nav_msgs/msg/OccupancyGrid"], T["nav_msgs/msg/MapMetaData"],
                             T["geometry_msgs/msg/Pose"])  # fmt: skip
            Point, Quat = T["geometry_msgs/msg/Point"], T["geometry_msgs/msg/Quaternion"]
            PM = T["fire_uav_msgs/msg/PerimeterMap"]
            dirs = [PerimeterDirection.CCW] * 2 + [PerimeterDirection.CW] * 2 + [PerimeterDirection.CCW]
            changes = [0, 0, 1, 1, 2]
            for k in range(5):
                t = 1.0 + k
                f32 = np.full(BINS, R_M + 10.0, dtype=np.float32)
                put(c_per, t, PM(header=hdr(t), uav_id=1, sequence=k + 1, fire_id=7, center_x_m=CENTER[0],
                                 center_y_m=CENTER[1], outer_distance_m=f32,
                                 outer_visit_time_s=np.full(BINS, t, dtype=np.float32),
                                 spread_rate_mps=np.zeros(BINS, dtype=np.float32),
                                 importance=np.ones(BINS, dtype=np.float32), direction=int(dirs[k]),
                                 direction_changes=changes[k], auth=np.zeros(32, dtype=np.uint8)))  # fmt: skip
                info = Info(map_load_time=to_time_msg(s_to_ns(t), Time), resolution=CELL_M, width=n, height=n,
                            origin=Pose(position=Point(x=0.0, y=0.0, z=0.0),
                                        orientation=Quat(x=0.0, y=0.0, z=0.0, w=1.0)))  # fmt: skip
                put(c_grid, t + 0.05, G(header=hdr(t + 0.05), info=info, data=occ.ravel()))
        if cp:
            c_w = conn(topics.COVERAGE_WEIGHTS, "fire_uav_msgs/msg/CoverageWeight")
            c_c = conn(topics.COVERAGE_CANDIDATES, "fire_uav_msgs/msg/CoverageCandidate")
            c_m = conn(topics.COVERAGE_MST, "fire_uav_msgs/msg/MstFragment")
            c_v = conn("/uav_0/viz", "visualization_msgs/msg/MarkerArray")
            CW, CC, MF = (T["fire_uav_msgs/msg/CoverageWeight"], T["fire_uav_msgs/msg/CoverageCandidate"],
                          T["fire_uav_msgs/msg/MstFragment"])  # fmt: skip
            Point = T["geometry_msgs/msg/Point"]
            for k, (cid, cost) in enumerate(COSTS):
                t = 0.1 * (k + 1)
                seeds = [Point(x=250.0, y=500.0, z=0.0), Point(x=750.0, y=500.0, z=0.0)]
                put(c_c, t, CC(header=hdr(t), uav_id=k % 2, kind=int(CandidateKind.COST), candidate_id=cid,
                               seeds=seeds, start_offsets=np.zeros(2), energy_j=1e3 * cost,
                               radio_radius_m=100.0 + cid, cost=cost))  # fmt: skip
            put(c_c, 0.05, CC(header=hdr(0.05), uav_id=0, kind=int(CandidateKind.PROPOSAL), candidate_id=1,
                              seeds=[], start_offsets=np.zeros(0), energy_j=0.0, radio_radius_m=0.0, cost=0.0))  # fmt: skip
            for it, (w0, w1) in enumerate([(0.0, 0.0), (0.0, 1e5)]):
                t = 1.0 + it
                for u, (sx, w) in enumerate([(250.0, w0), (750.0, w1)]):
                    put(c_w, t, CW(header=hdr(t), uav_id=u, iteration=it, seed_x_m=sx, seed_y_m=500.0,
                                   weight_m2=w, area_m2=0.0, target_area_m2=5e5))  # fmt: skip
            for k, r in enumerate([80.0, 120.0, 95.0]):
                put(c_m, 3.0, MF(header=hdr(3.0), uav_id=0, kind=int(MstKind.DONE), round=2,
                                 sample_index=7000 + k, fragment_id=0, edge_from=0, edge_to=1,
                                 edge_length_m=r, radius_m=r))  # fmt: skip
            put(c_m, 2.5, MF(header=hdr(2.5), uav_id=0, kind=int(MstKind.DONE), round=2, sample_index=3000,
                             fragment_id=0, edge_from=0, edge_to=1, edge_length_m=500.0, radius_m=500.0))  # fmt: skip
            M, MA = T["visualization_msgs/msg/Marker"], T["visualization_msgs/msg/MarkerArray"]
            P, V3, RGBA = (
                T["geometry_msgs/msg/Pose"],
                T["geometry_msgs/msg/Vector3"],
                T["std_msgs/msg/ColorRGBA"],
            )
            Q, D = T["geometry_msgs/msg/Quaternion"], T["builtin_interfaces/msg/Duration"]
            Img = T["sensor_msgs/msg/CompressedImage"]
            line = M(header=hdr(3.0), ns="uav_0_search_path", id=0, type=4, action=0,
                     pose=P(position=Point(x=0.0, y=0.0, z=0.0), orientation=Q(x=0.0, y=0.0, z=0.0, w=1.0)),
                     scale=V3(x=2.0, y=0.0, z=0.0), color=RGBA(r=0.0, g=0.0, b=1.0, a=1.0),
                     lifetime=D(sec=0, nanosec=0), frame_locked=False,
                     points=[Point(x=float(x), y=100.0, z=0.0) for x in (50, 150, 250)], colors=[],
                     texture_resource="", texture=Img(header=hdr(0.0), format="", data=np.zeros(0, np.uint8)),
                     uv_coordinates=[], text="", mesh_resource="", mesh_file=T["visualization_msgs/msg/MeshFile"](
                         filename="", data=np.zeros(0, np.uint8)), mesh_use_embedded_materials=False)  # fmt: skip
            put(c_v, 3.0, MA(markers=[line]))


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    root = tmp_path_factory.mktemp("sections")
    out = {}
    for name, pm, cp in (("pm", True, False), ("cp", False, True)):
        _write(root / f"{name}_bag", pm=pm, cp=cp)
        out[name] = (write_report(root / f"{name}_bag", root / f"{name}_report"), root / f"{name}_report")
    return out


def test_pm_distance_error_is_the_known_offset(reports):
    m, _ = reports["pm"]
    mon = m["sections"]["pm"]["monitors"]["1/7"]
    sag = (R_M + 10.0) * (1 - math.cos(math.pi / BINS))
    assert mon["distance_error_samples"] == 5
    # error at every angle: 10 m + [0, sag], give or take the cell squares: the hull of squares at
    # the map's points and the raster disc's edge each reach half a cell to half a diagonal out
    assert 10.0 - CELL_M <= mon["mean_distance_error_m"] <= 10.0 + sag + CELL_M
    # the maximum finds the worst angle: a square's corner half a diagonal out beside a raster step
    assert 10.0 - CELL_M <= mon["average_max_distance_error_m"] <= 10.0 + sag + 1.5 * CELL_M
    assert 0.0 <= mon["average_max_distance_error_floor_m"] <= 1.2 * CELL_M  # a raster disc: about a cell
    assert mon["direction_changes_reported"] == 2


def test_cp_costs_partition_and_radius(reports):
    m, _ = reports["cp"]
    cp = m["sections"]["cp"]
    assert cp["evaluations"] == 5 and cp["cost_messages"] == 6 and cp["proposals"] == 1
    assert cp["best"]["candidate_id"] == 4 and cp["best"]["cost"] == 2.0 and cp["best"]["evaluation"] == 4
    assert cp["best"]["radio_radius_m"] == 104.0
    assert cp["mst"] == {"r_max_m": 120.0, "instants": 3}  # the newest session only (key 7)
    part = cp["partition"]
    assert part["0"]["iteration"] == 1
    assert part["0"]["area_m2"] == pytest.approx(4e5, rel=0.01)
    assert part["1"]["area_m2"] == pytest.approx(6e5, rel=0.01)
    assert cp["planned_paths"]["0"]["length_m"] == pytest.approx(200.0)


@pytest.mark.parametrize(
    ("name", "heading", "figures"),
    [
        ("pm", "Perimeter monitoring (PM)", ["pm_track.png", "pm_distance_error.png", "pm_direction.png"]),
        ("cp", "Coverage search (CP)", ["cp_partition.png", "cp_cost.png"]),
    ],
)
def test_a_section_is_on_the_page_with_its_figures(reports, name, heading, figures):
    m, out = reports[name]
    page = (out / "index.html").read_text(encoding="utf8")
    assert f"<h2>{heading}</h2>" in page
    for f in figures:
        assert f in m["figures"] and (out / f).stat().st_size > 0 and f'src="{f}"' in page


def test_a_section_is_absent_when_the_mission_did_not_use_it(tmp_path, reports):
    assert "cp" not in reports["pm"][0]["sections"] and "pm" not in reports["cp"][0]["sections"]
    write_synthetic_mission(tmp_path / "bag", SyntheticMission(monitor=None))
    m = write_report(tmp_path / "bag", tmp_path / "report")
    page = (tmp_path / "report" / "index.html").read_text(encoding="utf8")
    assert m["sections"] == {}
    assert "Perimeter monitoring (PM)" not in page and "Coverage search (CP)" not in page


def test_hull_and_ray_extent_of_a_square():
    sq = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1], [0, 0], [0.5, 0.2]], dtype=float)
    hull = convex_hull(sq)
    assert len(hull) == 4
    ang = np.array([0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4 + math.pi])
    assert ray_extent_polygon(hull, (0.0, 0.0), ang) == pytest.approx([1.0, math.sqrt(2), 1.0, math.sqrt(2)])
    assert ray_extent_polygon(hull, (0.5, 0.0), np.array([0.0, math.pi])) == pytest.approx([0.5, 1.5])
    assert np.isnan(ray_extent_polygon(hull, (3.0, 0.0), np.array([0.0]))).all()  # centre outside


def test_direction_changes_seen_in_a_track():
    def arc(a0, a1, n=60):
        a = np.linspace(a0, a1, n)
        return np.stack([100 * np.cos(a), 100 * np.sin(a)], -1)

    there_and_back = np.concatenate([arc(0, 2.0), arc(2.0, 1.0), arc(1.0, 3.0)])
    assert track_direction_changes(there_and_back, (0.0, 0.0)) == 2
    jitter = arc(0, 6.0) + np.tile([[0.0, 0.0], [0.0, 3.0]], (30, 1))
    assert track_direction_changes(jitter, (0.0, 0.0)) == 0
    assert track_direction_changes(arc(0, 4 * math.pi, 200), (0.0, 0.0)) == 0  # laps are no reversals


def test_power_labels_and_incumbent():
    _, _, lab = power_labels(np.array([[0.0, 0.0], [10.0, 0.0]]), np.array([0.0, 0.0]), (0, 10), (0, 1), 1.0)
    assert (lab[0] == [0] * 5 + [1] * 5).all()  # equal weights: the Voronoi bisector
    assert incumbent(np.array([5.0, 3.0, 4.0, 2.0])).tolist() == [5.0, 3.0, 3.0, 2.0]
