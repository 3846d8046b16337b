"""What the world shows on ``/viz/world`` (ROS-free): markers with stable ids, deleted when gone.

:func:`world_markers` lists what should be on screen after a step: one arrow per flying UAV
(``ns="uav"``, ``id = uav_id``), a cross per crashed UAV (``ns="crash"``), one cylinder per
burning analytic fire (``ns="fire"``, ``id = fire_id``; a raster fire is drawn by
``/viz/fire_grid`` instead), one marker per lake (``ns="lake"``, ``id`` = index: a scenario's disc
lake a flat cylinder, a landscape's water body a triangle list of its water cells, so the live view
shows its real outline at its water level) and a colour legend
(``ns="legend"``). :class:`MarkerBook` turns each such list into what to send: an ADD for every
wanted marker (same ``(ns, id)`` replaces the old one in RViz and Foxglove) and a DELETE for every
``(ns, id)`` shown before and no longer wanted, so an extinguished fire's cylinder and a crashed
UAV's arrow disappear at once. The node converts :class:`MarkerSpec` to
``visualization_msgs/Marker`` in one place.

Colours are RGBA in [0, 1]; positions [m] and yaw [rad] in the ``map`` frame.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

from fire_uav_common.constants import FireStatus, VehicleStatus

from .errors import SequenceError

__all__ = ["COLOURS", "LEGEND", "MarkerBook", "MarkerSpec", "world_markers"]

RGBA = tuple[float, float, float, float]
COLOURS: dict[str, RGBA] = {
    "uav": (0.1, 0.9, 1.0, 1.0),
    "crash": (1.0, 0.0, 1.0, 1.0),
    "fire": (1.0, 0.3, 0.0, 0.7),
    "lake": (0.0, 0.3, 1.0, 0.6),
}
#: legend lines: (namespace whose colour it shows, text)
LEGEND: tuple[tuple[str, str], ...] = (
    ("uav", "UAV (arrow: heading)"),
    ("crash", "crashed UAV"),
    ("fire", "fire (analytic: disc of its extent)"),
    ("lake", "lake (refill)"),
)
LEGEND_LINE_M = 25.0  # legend line spacing [m]
LEGEND_TEXT_M = 18.0  # legend text height [m]


@dataclass(frozen=True)
class MarkerSpec:
    """One marker: ``kind`` in {arrow, cylinder, sphere, text, triangle_list}; ``action`` "add"
    or "delete". ``points``: a triangle list's vertices [m], relative to (x_m, y_m, z_m)."""

    ns: str
    id: int
    kind: str = "arrow"
    action: str = "add"
    x_m: float = 0.0
    y_m: float = 0.0
    z_m: float = 0.0
    yaw_rad: float = 0.0
    scale_m: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rgba: RGBA = (1.0, 1.0, 1.0, 1.0)
    text: str = ""
    points: tuple[tuple[float, float, float], ...] = ()

    @property
    def key(self) -> tuple[str, int]:
        return (self.ns, self.id)


def world_markers(
    vehicles: Iterable[object],
    fires: Iterable[object],
    lakes: Sequence[object],
    *,
    draw_fires: bool,
    legend_xy_m: tuple[float, float],
    ground: Callable[[float, float], float] | None = None,
) -> list[MarkerSpec]:
    """The markers wanted now (records with the fields of ``VehicleTruthRecord``/``FireTruthRecord``,
    lakes with ``x_m, y_m, diameter_m`` and ``water``); ``draw_fires=False`` for the raster model.

    ``ground(x, y)`` [m]: the terrain's elevation, the water level of a landscape lake (taken at
    its disc's centre, as the world's refill check does). A disc lake keeps its cylinder at z 0."""
    out: list[MarkerSpec] = []
    for i, lake in enumerate(lakes):
        water = getattr(lake, "water", None)
        if water is not None:
            out.append(_water_marker(i, water, lake, ground))
            continue
        d = float(lake.diameter_m)  # type: ignore[attr-defined]
        out.append(
            MarkerSpec("lake", i, "cylinder", x_m=float(lake.x_m), y_m=float(lake.y_m),  # type: ignore[attr-defined]
                       scale_m=(d, d, 0.5), rgba=COLOURS["lake"])
        )  # fmt: skip
    for v in vehicles:
        x, y, z = float(v.x_m), float(v.y_m), float(v.z_m)  # type: ignore[attr-defined]
        uid = int(v.uav_id)  # type: ignore[attr-defined]
        if int(v.status) == VehicleStatus.CRASHED:  # type: ignore[attr-defined]
            out.append(MarkerSpec("crash", uid, "sphere", x_m=x, y_m=y, z_m=z, scale_m=(8.0, 8.0, 8.0),
                                  rgba=COLOURS["crash"]))  # fmt: skip
        else:
            out.append(MarkerSpec("uav", uid, "arrow", x_m=x, y_m=y, z_m=z, yaw_rad=float(v.yaw_rad),  # type: ignore[attr-defined]
                                  scale_m=(15.0, 4.0, 4.0), rgba=COLOURS["uav"]))  # fmt: skip
    if draw_fires:
        for f in fires:
            extent = float(f.extent_m)  # type: ignore[attr-defined]
            if int(f.status) != FireStatus.ACTIVE or not extent > 0:  # type: ignore[attr-defined]
                continue
            out.append(MarkerSpec("fire", int(f.fire_id), "cylinder", x_m=float(f.x_m), y_m=float(f.y_m),  # type: ignore[attr-defined]
                                  scale_m=(2 * extent, 2 * extent, 1.0), rgba=COLOURS["fire"]))  # fmt: skip
    x0, y0 = legend_xy_m
    for i, (ns, text) in enumerate(LEGEND):
        out.append(MarkerSpec("legend", i, "text", x_m=x0, y_m=y0 - i * LEGEND_LINE_M, z_m=1.0,
                              scale_m=(1.0, 1.0, LEGEND_TEXT_M), rgba=COLOURS[ns], text=text))  # fmt: skip
    return out


def _water_marker(
    i: int, water: object, lake: object, ground: Callable[[float, float], float] | None
) -> MarkerSpec:
    """A landscape lake as a flat triangle list over its water cells (two triangles per row run,
    :meth:`~fire_uav_common.water.WaterCells.row_runs`), 0.25 m above its water level like the
    middle of a disc lake's 0.5 m cylinder."""
    x, y = float(lake.x_m), float(lake.y_m)  # type: ignore[attr-defined]
    level = 0.0 if ground is None else float(ground(x, y))
    pts: list[tuple[float, float, float]] = []
    for x0, y0, x1, y1 in water.row_runs().tolist():  # type: ignore[attr-defined]
        pts += [(x0, y0, 0.0), (x1, y0, 0.0), (x1, y1, 0.0), (x0, y0, 0.0), (x1, y1, 0.0), (x0, y1, 0.0)]
    return MarkerSpec("lake", i, "triangle_list", z_m=level + 0.25, rgba=COLOURS["lake"], points=tuple(pts))


class MarkerBook:
    """Remembers what is on screen; :meth:`frame` adds DELETEs for what is no longer wanted."""

    def __init__(self) -> None:
        self.shown: set[tuple[str, int]] = set()

    def frame(self, wanted: Iterable[MarkerSpec]) -> list[MarkerSpec]:
        wanted = list(wanted)
        keys = [m.key for m in wanted]
        if len(set(keys)) != len(keys):
            dup = sorted({k for k in keys if keys.count(k) > 1})
            raise SequenceError(f"marker ids not unique: {dup}")
        gone = sorted(self.shown - set(keys))
        self.shown = set(keys)
        return wanted + [MarkerSpec(ns, i, action="delete") for ns, i in gone]


def yaw_quaternion(yaw_rad: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by ``yaw_rad`` about z."""
    return (0.0, 0.0, math.sin(yaw_rad / 2), math.cos(yaw_rad / 2))
