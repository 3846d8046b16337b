"""Placement checks of a scenario: every position it gives must lie in its mission area.

A fire, an ignition, a lake or a UAV start outside ``area`` is a mistake the mission cannot show
(the fleet searches and partitions only the area, so such a fire is never found); an ignition
in a lake never burns. Each check raises :class:`ScenarioError` naming the file and the field.
"""

from __future__ import annotations

from .fields import _Ctx
from .types import Scenario


def _outside(ctx: _Ctx, path: str, what: str, x_m: float, y_m: float, scenario: Scenario) -> None:
    a = scenario.area
    if not a.contains(x_m, y_m):
        raise ctx.fail(
            path,
            f"{what} ({x_m:g}, {y_m:g}) m is outside the area "
            f"x {a.x_min_m:g}..{a.x_max_m:g}, y {a.y_min_m:g}..{a.y_max_m:g} m",
        )


def check_uav_starts(ctx: _Ctx, scenario: Scenario, count: int) -> None:
    """The start of each of UAVs 0..count-1 (``uavs.first`` + k ``uavs.spacing``) lies in the area.

    Only the file's own ``uavs.count`` is checked: a larger fleet asked of the runner extends the
    line of starts, which may leave the area (FF Table I's 14 UAVs do in ff_two_fires)."""
    for k, (x, y, _, _) in enumerate(scenario.uav_start_poses(count)):
        path = "uavs.first" if k == 0 else "uavs.spacing"
        _outside(ctx, path, f"UAV {k} starts at", x, y, scenario)


def check_placement(ctx: _Ctx, scenario: Scenario) -> None:
    """Fires, ignitions, lakes and the UAV starts of ``uavs.count`` lie in the area; no ignition
    lies in a lake (a lake's cells hold no fuel)."""
    for i, f in enumerate(scenario.fires.analytic):
        _outside(ctx, f"fires.analytic[{i}]", "fire centre", f.x_m, f.y_m, scenario)
    for i, lake in enumerate(scenario.lakes):
        _outside(ctx, f"lakes[{i}]", "lake centre", lake.x_m, lake.y_m, scenario)
    raster = scenario.fires.raster
    if raster is not None:
        for i, ig in enumerate(raster.ignitions):
            p = f"fires.raster.ignitions[{i}]"
            _outside(ctx, p, "ignition", ig.x_m, ig.y_m, scenario)
            for j, lake in enumerate(scenario.lakes):
                if lake.contains(ig.x_m, ig.y_m):
                    raise ctx.fail(
                        p, f"ignition ({ig.x_m:g}, {ig.y_m:g}) m is in lakes[{j}]: a non-burnable cell"
                    )
    check_uav_starts(ctx, scenario, scenario.uavs.count)
