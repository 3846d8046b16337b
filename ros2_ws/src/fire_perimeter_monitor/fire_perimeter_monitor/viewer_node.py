"""perimeter_viewer: draws every monitor's on-board fire map (PerimeterMap on /fleet/perimeter)
as markers on /viz/perimeter, for RViz or Foxglove, live or from a replayed bag.

Per monitor: the outer perimeter as a closed line strip (bins with a known distance), and one
sphere per bin coloured by its importance (PM Eq. 4; red = most important).
"""

from __future__ import annotations

import math

import rclpy
from builtin_interfaces.msg import Duration
from fire_uav_common import topics
from fire_uav_common.ros_io import spin
from fire_uav_msgs.msg import PerimeterMap
from geometry_msgs.msg import Point
from rclpy.node import Node
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray


def perimeter_points(msg: PerimeterMap) -> list[tuple[float, float, float]]:
    """(x_m, y_m, importance) of every bin with a known outer distance, in angle order."""
    n = len(msg.outer_distance_m)
    out = []
    for i, d in enumerate(msg.outer_distance_m):
        if not math.isfinite(d):
            continue
        a = 2 * math.pi * (i + 0.5) / n
        imp = msg.importance[i] if i < len(msg.importance) else 0.0
        out.append((msg.center_x_m + d * math.cos(a), msg.center_y_m + d * math.sin(a), imp))
    return out


class PerimeterViewer(Node):
    def __init__(self) -> None:
        super().__init__("perimeter_viewer")
        if not self.has_parameter("use_sim_time"):
            self.declare_parameter("use_sim_time", True)
        self.pub = topics.publisher(self, topics.VIZ_PERIMETER_SPEC)
        topics.subscription(self, topics.FLEET_PERIMETER_SPEC, self.on_map)

    def on_map(self, msg: PerimeterMap) -> None:
        pts = perimeter_points(msg)
        if not pts:
            return
        line = _marker(msg, f"perimeter_uav_{msg.uav_id}", 0, Marker.LINE_STRIP)
        line.scale.x = 1.0
        line.color = ColorRGBA(r=1.0, g=0.5, b=0.0, a=1.0)
        line.points = [Point(x=x, y=y, z=1.0) for x, y, _ in pts] + [Point(x=pts[0][0], y=pts[0][1], z=1.0)]
        dots = _marker(msg, f"importance_uav_{msg.uav_id}", 1, Marker.SPHERE_LIST)
        dots.scale.x = dots.scale.y = dots.scale.z = 2.0
        top = max((i for _, _, i in pts), default=0.0) or 1.0
        dots.points = [Point(x=x, y=y, z=1.5) for x, y, _ in pts]
        dots.colors = [ColorRGBA(r=1.0, g=1.0 - min(1.0, max(0.0, i / top)), b=0.0, a=1.0) for _, _, i in pts]
        self.pub.publish(MarkerArray(markers=[line, dots]))


def _marker(msg: PerimeterMap, ns: str, marker_id: int, kind: int) -> Marker:
    """A marker of this map: its header, added, shown for 5 s unless the next map replaces it."""
    return Marker(
        header=msg.header, ns=ns, id=marker_id, type=kind, action=Marker.ADD, lifetime=Duration(sec=5)
    )


def main(args: list[str] | None = None) -> None:
    rclpy.init(args=args)
    node = PerimeterViewer()
    spin(node)


if __name__ == "__main__":
    main()
