"""The live view's lakes (/viz/world, ns "lake"): a scenario's disc lake stays the flat cylinder it
was; a landscape's water body is drawn by its real outline, a triangle list over its water cells
at its water level."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from fire_uav_common.scenario import load_scenario
from fire_uav_common.terrain import Lake
from fire_world_sim import viz

ROOT = Path(__file__).resolve().parents[4]
SCENARIOS = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios"


def _lake_markers(lakes, ground=None) -> list[viz.MarkerSpec]:
    out = viz.world_markers([], [], lakes, draw_fires=True, legend_xy_m=(0.0, 0.0), ground=ground)
    return [m for m in out if m.ns == "lake"]


def test_a_disc_lake_is_the_same_cylinder_as_before() -> None:
    (m,) = _lake_markers([Lake(50.0, 50.0, 90.0)], ground=lambda x, y: 123.0)
    assert m == viz.MarkerSpec(
        "lake", 0, "cylinder", x_m=50.0, y_m=50.0, scale_m=(90.0, 90.0, 0.5), rgba=viz.COLOURS["lake"]
    )


def _triangles_area(points: np.ndarray) -> float:
    a, b, c = points[0::3, :2], points[1::3, :2], points[2::3, :2]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return float(np.sum(np.abs(cross)) / 2)


def test_a_landscape_pond_is_drawn_by_its_water_cells_at_its_level() -> None:
    sc = load_scenario(SCENARIOS / "worcester_vt.yaml")
    (pond,) = sc.lakes
    assert pond.water is not None
    (m,) = _lake_markers(sc.lakes, ground=lambda x, y: float(sc.terrain.elevation(x, y)))
    assert m.kind == "triangle_list" and (m.x_m, m.y_m, m.yaw_rad) == (0.0, 0.0, 0.0)
    assert m.z_m == pytest.approx(float(sc.terrain.elevation(pond.x_m, pond.y_m)) + 0.25)
    pts = np.array(m.points)
    assert len(pts) % 3 == 0 and np.all(pts[:, 2] == 0.0)
    # the triangles fill the water exactly: their area is the body's, and the centre of every
    # triangle lies over the water (so none is drawn over land)
    assert _triangles_area(pts) == pytest.approx(pond.water.area_m2)
    centroids = (pts[0::3] + pts[1::3] + pts[2::3]) / 3
    assert np.all(pond.water.contains(centroids[:, 0], centroids[:, 1]))
    # larger than the disc the agents aim at: the outline, not the disc
    assert pond.water.area_m2 > np.pi * (pond.diameter_m / 2) ** 2


def test_the_triangle_list_reaches_the_message() -> None:
    ros_messages = pytest.importorskip("fire_world_sim.ros_messages")
    from fire_uav_common.water import WaterCells
    from visualization_msgs.msg import Marker

    w = np.array([[1, 1, 0], [0, 1, 1]], dtype=bool)
    lake = Lake(15.0, 15.0, 10.0, water=WaterCells(0.0, 0.0, 10.0, w))
    specs = _lake_markers([lake], ground=lambda x, y: 5.0)
    (mk,) = ros_messages.marker_array(specs, 0).markers
    assert mk.type == Marker.TRIANGLE_LIST and mk.ns == "lake"
    assert len(mk.points) == 2 * 6 and mk.pose.position.z == pytest.approx(5.25)
    # row 0 (south): cells 0-1, one rectangle 0..20 x 0..10 m; row 1: cells 1-2, 10..30 x 10..20 m
    assert [(p.x, p.y) for p in mk.points[:3]] == [(0.0, 0.0), (20.0, 0.0), (20.0, 10.0)]
    assert [(p.x, p.y) for p in mk.points[6:9]] == [(10.0, 10.0), (30.0, 10.0), (30.0, 20.0)]
