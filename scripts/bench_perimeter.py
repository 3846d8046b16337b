#!/usr/bin/env python3
"""Benchmark of the perimeter monitors (PM VI-B, VI-E); prints figures, asserts nothing.

Distance error: ``fire_perimeter_monitor.distance_error`` (the one definition the report and
metrics.json use too): at 360 angles about the monitor's map centre, |extent of the true fire
- extent of the convex hull of the on-board perimeter cells|, maximum over the angles, sampled
every ``every`` new cells after the initial lap; the table gives the mean of that maximum
over the flight (PM Fig. 16's end value) per seed, in metres and cells, and beside it the
perfect-map floor (the same metric for a map holding the whole current fire). PM: 7.3 vs 8.5
(ratio 0.86) on a fire that speeds up, 12.2 vs 15.8 (0.77) on a fast wind-driven fire.

Monitors: circling (PM VI-E baseline); importance with the worst-angle rule (ours, default);
importance with the paper's window sums (Listing 3, with our hysteresis). Seeds draw the
deployment angle and the initial direction.

Fires (no suppression):
- A. fire_world_sim's raster fire (RasterFireModel, Rothermel, pure Python, no ROS) from the
  scenarios; 5 m cells, UAV 50 m/s, the world's 70 m fire sensor. monitor_grass: the centre
  known (the agents pass the fleet's fire estimate; here the ignition point); grass_wind and
  grass_to_brush: the centre unknown, estimated after the initial lap (PM IV-A).
- B. synthetic arrival-time rasters in the paper's regime: 30 m cells, 10 m/s, sensing one
  cell around the UAV, laps of tens of minutes, 3 h from 1 h after ignition; a wind-driven
  fire (head 15x the back) and a slow fire that reaches a 4x faster fuel (PM Fig. 12a / 16a);
  "narrow head", 4 h from 1 h after ignition: a round fire even for 3 h, then a head 10x the
  back over about a fifth of the perimeter while the fire stays nearly convex (PM Fig. 16a's
  regime; its second table, from 3 h, is where the regime is).

With monitor_grass also: two monitors on the worst-angle rule, each merging the other's map,
with the perimeter split between them by angle, by spread rate, and as a relay at the head
(``MonitorConfig.split``; rows "two (angle)", "two (spread)" and "two (relay)"); what the UAV's speed and footprint allow on that fire (``bounds``:
evenly spaced circling monitors, and a lower bound for any single monitor), and the scenario
as it flies, with suppression (``run_suppressed``: the error against the true fire's hull and
the reported fastest front against the burning tip).

Run: .venv/bin/python scripts/bench_perimeter.py [--quick] [--seeds N] [--fires NAME ...]
[--score-from-s S] [--describe]
(quick: the world's monitor_grass, and grass_wind for its first 2 min; a paper-regime
synthetic flight of 3-4 h takes about half a minute to a minute of CPU; --score-from-s: a second table per fire
over the samples at t >= S only, e.g. the fuel-change fire's uneven phase from 2.1 h (7560 s)
on the same flights; --describe: what the synthetic fires do, no flight, seconds)
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

_SRC = Path(__file__).resolve().parents[1] / "ros2_ws/src"

from fire_perimeter_monitor.boundary import is_boundary_cell, lookup_from_grid  # noqa: E402
from fire_perimeter_monitor.distance_error import (  # noqa: E402
    distance_error,
    hull_extent,
    max_error,
    perfect_map_cells,
    true_extent,
)
from fire_perimeter_monitor.fire_map import CellGrid, Direction  # noqa: E402
from fire_perimeter_monitor.planner import (  # noqa: E402
    CirclingMonitor,
    ImportanceMonitor,
    MonitorConfig,
    PerimeterMonitor,
)
from fire_perimeter_monitor.synthetic_fire import RasterFire, elliptical_ros, fly, spread_fire  # noqa: E402

ALPHAS = (0.0, 0.8, 1.0, 1.2, 1.5, 5.0)
PAPER_CHANGES = (0, 8, 11, 15, 20, 43)
MONITORS = ("circling", "worst", "windows")
TWO_SPLITS = ("angle", "spread", "relay")  # MonitorConfig.split of the two-monitor rows (worst-angle rule)

# --- B. synthetic fires, the paper's regime -------------------------------------------------
CELL_M = 30.0  # [m] raster cell
SPEED_MPS = 10.0  # [m/s] UAV speed along the perimeter
SENSOR_M = 1.5 * CELL_M  # [m] the cell under the UAV and its 8 neighbours
SHAPE = (140, 140)  # cells
IGNITION = (100, 100)  # north-east of the centre; the fires run south-west
SW = math.radians(225.0)


def wind_fire():
    """Fast spread south-west from the start, head 15x the back (PM Fig. 13a / 16b)."""
    return spread_fire(SHAPE, CELL_M, IGNITION, elliptical_ros(0.25, 0.75, SW))


def fuel_change_fire():
    """Slow, mildly wind-driven fire in a fuel that burns 4x faster beyond a line 14 cells
    south-west of the ignition, which the head reaches after about 2 h (PM Fig. 12a / 16a)."""
    ii, jj = np.meshgrid(np.arange(SHAPE[0]), np.arange(SHAPE[1]), indexing="ij")
    fuel = np.where(ii + jj < 180, 4.0, 1.0)
    return spread_fire(SHAPE, CELL_M, IGNITION, elliptical_ros(0.06, 0.5, SW), fuel_factor=fuel)


# "narrow head": PM Fig. 16a's regime on a fire that stays nearly convex (our construction)
NH_SHAPE = (160, 160)  # cells
NH_IGNITION = (95, 95)  # room for the head to run 75 cells south-west and the back 48 north-east
NH_EVEN_MPS = 0.125  # [m/s] 7.5 m/min at every angle until NH_CHANGE_S
NH_CHANGE_S = 3 * 3600.0  # [s] PM VI-B: "during the first 3 hours ... not spreading very fast"
NH_BACK_MPS = 0.0125  # [m/s] after the change, away from the head (a tenth of before)
NH_HEAD_MPS = 0.125  # [m/s] after the change, at the head (keeps the even phase's rate: 10x the back)
NH_WIDTH_RAD = 0.35  # [rad] standard deviation of the head's Gaussian profile in angle (20 deg)


def narrow_head_rate(theta_rad):
    """Spread rate [m/s] per angle about the ignition point after the change: the back's rate plus
    a Gaussian bump of width ``NH_WIDTH_RAD`` centred south-west, reaching ``NH_HEAD_MPS``."""
    d = (np.asarray(theta_rad) - SW + np.pi) % (2 * np.pi) - np.pi
    return NH_BACK_MPS + (NH_HEAD_MPS - NH_BACK_MPS) * np.exp(-0.5 * (d / NH_WIDTH_RAD) ** 2)


def narrow_head_fire() -> RasterFire:
    """A round fire whose spread, even for 3 h, then slows tenfold everywhere but a narrow head.

    Prescribed, not simulated (as ``star_fire``): the extent along the ray at angle theta from
    the ignition point is ``v t`` up to ``t1 = NH_CHANGE_S`` and ``v t1 + rate(theta) (t - t1)``
    after it (``narrow_head_rate``), so a cell at distance rho ignites at ``rho / v`` inside the
    even disc and at ``t1 + (rho - v t1) / rate(theta)`` beyond it. The body is 45 cells in
    radius at the change and the head adds 27 cells by 5 h (0.56 of the radius), so the fire stays nearly
    convex (a bump on a disc; a fast fuel strip or a fast half-plane would leave a finger or a
    fan, see the notes) while only the angles within about 2 widths of the head spread at a
    quarter of its rate or more."""
    ii, jj = np.meshgrid(np.arange(NH_SHAPE[0]), np.arange(NH_SHAPE[1]), indexing="ij")
    ix, iy = (NH_IGNITION[0] + 0.5) * CELL_M, (NH_IGNITION[1] + 0.5) * CELL_M
    dx, dy = (ii + 0.5) * CELL_M - ix, (jj + 0.5) * CELL_M - iy
    rho = np.hypot(dx, dy)
    r1 = NH_EVEN_MPS * NH_CHANGE_S
    arrival = np.where(
        rho <= r1, rho / NH_EVEN_MPS, NH_CHANGE_S + (rho - r1) / narrow_head_rate(np.arctan2(dy, dx))
    )
    return RasterFire(arrival, CELL_M, (ix, iy))


# --- A. fire_world_sim's raster fire ---------------------------------------------------------
WORLD_SPEED_MPS = 50.0  # [m/s] just above the 44.7 m/s stall speed (scenario vehicle:)
WORLD_SENSOR_M = 70.0  # [m] sensors.fire.range_m default


class WorldRasterFire:
    """fire_world_sim's RasterFireModel seen through synthetic_fire.fly's fire interface.

    The model is stepped (at its 0.5 s update period) up to the time of each observation;
    cell (i, j) here is column i (east), row j (north) of the model.
    """

    def __init__(self, scenario_name: str) -> None:
        from fire_uav_common.scenario import load_scenario
        from fire_world_sim.fires.raster import RasterFireModel

        sc = load_scenario(_SRC / "fire_world_sim/scenarios" / f"{scenario_name}.yaml")
        spec = sc.fires.raster
        self.model = RasterFireModel(spec, sc.terrain, lakes=tuple(sc.lakes), update_period_s=0.5)
        self.cell_size_m = float(spec.cell_size_m)
        h = self.cell_size_m / 2
        self.grid = CellGrid(spec.origin.x_m + h, spec.origin.y_m + h, self.cell_size_m)
        ig = spec.ignitions[0]
        self.ignition_xy_m = (float(ig.x_m), float(ig.y_m))
        self._t = 0.0

    def advance(self, t_s: float) -> None:
        while self._t + 0.5 <= t_s + 1e-9:
            self.model.step(self._t, 0.5)
            self._t += 0.5

    def fire_mask(self, t_s: float) -> np.ndarray:
        self.advance(t_s)
        return (self.model.state_grid() > 0).T  # [i east, j north]

    def observe(self, x_m: float, y_m: float, range_m: float, t_s: float):
        self.advance(t_s)
        c = self.model.cells_near(x_m, y_m, range_m, int(t_s * 1e9))
        return c.x_m.astype(float), c.y_m.astype(float), c.state

    def boundary_cell_at_angle(self, angle_rad: float, t_s: float) -> tuple[int, int]:
        mask = self.fire_mask(t_s)
        look = lookup_from_grid(mask, self.grid)
        best = tuple(int(v) for v in self.grid.index(*self.ignition_xy_m))
        for r in np.arange(0.0, max(mask.shape) * self.cell_size_m * 1.5, self.cell_size_m / 4):
            c = tuple(
                int(v)
                for v in self.grid.index(
                    self.ignition_xy_m[0] + r * math.cos(angle_rad),
                    self.ignition_xy_m[1] + r * math.sin(angle_rad),
                )
            )
            if look(*c) and is_boundary_cell(look, c):
                best = c
        return best  # type: ignore[return-value]


@dataclass(frozen=True)
class Setting:
    """One benchmark fire: how it is built and flown."""

    name: str
    t0_s: float  # deployment [s after ignition]
    t1_s: float  # end [s]
    every: int  # distance error every this many new cells
    center_known: bool
    score_from_s: float | None = None  # --score-from-s: also the mean over samples at t >= this [s]

    def fire(self):
        if self.name in SYNTHETIC:
            return SYNTHETIC[self.name]()
        return WorldRasterFire(self.name)

    @property
    def world(self) -> bool:
        return self.name not in SYNTHETIC


SETTINGS = {
    # the world's fires stay inside their grids until t1 (monitor_grass reaches its edge at 120 s)
    "monitor_grass": Setting("monitor_grass", 30.0, 110.0, 5, True),
    "grass_wind": Setting("grass_wind", 120.0, 480.0, 10, False),
    "grass_to_brush": Setting("grass_to_brush", 120.0, 600.0, 10, False),
    "wind-driven": Setting("wind-driven", 3600.0, 4 * 3600.0, 4, True),
    "fuel change": Setting("fuel change", 3600.0, 4 * 3600.0, 4, True),
    # PM VI-B: deployed 1 h after ignition; slow and even for 3 h, then a fast head; scored also
    # from the change on (the second table), where the regime is
    "narrow head": Setting("narrow head", 3600.0, 5 * 3600.0, 4, True, score_from_s=NH_CHANGE_S),
}
SYNTHETIC = {"wind-driven": wind_fire, "fuel change": fuel_change_fire, "narrow head": narrow_head_fire}


def _cell_speed_sensor(s: Setting, fire) -> tuple[float, float, float]:
    if s.world:
        return fire.cell_size_m, WORLD_SPEED_MPS, WORLD_SENSOR_M
    return CELL_M, SPEED_MPS, SENSOR_M


def make_monitor(
    s: Setting, fire, kind: str, seed: int, alpha: float = 1.0, uav_id: int = 0, split: str = "angle"
):
    cell, speed, _ = _cell_speed_sensor(s, fire)
    rng = np.random.default_rng(seed)
    direction = Direction.CCW if rng.random() < 0.5 else Direction.CW
    kw: dict = dict(
        cell_size_m=cell,
        speed_mps=speed,
        alpha=alpha,
        initial_direction=direction,
        uav_id=uav_id,
        split=split,
    )
    if s.center_known:
        kw.update(center_x_m=fire.ignition_xy_m[0], center_y_m=fire.ignition_xy_m[1])
    if not s.world:
        kw.update(ignition_time_s=0.0)
    else:
        kw.update(ros_baseline_s=30.0)  # as the agents (MonitorPlannerConfig)
    if kind == "circling":
        return CirclingMonitor(MonitorConfig(**kw))
    return ImportanceMonitor(MonitorConfig(rule=kind, **kw))


def _fire_cells(fire, t_s: float) -> np.ndarray:
    i, j = np.nonzero(fire.fire_mask(t_s))
    x, y = fire.grid.center(i, j)
    return np.column_stack([x, y])


def _error(fire, m: PerimeterMonitor, t_s: float):
    fm = m.fire_map
    k = fm.known
    return distance_error(
        _fire_cells(fire, t_s),
        np.column_stack([fm.outer_x_m[k], fm.outer_y_m[k]]),
        m.config.cell_size_m,
        (fm.center_x_m, fm.center_y_m),
    )


def start_angle(seed: int) -> float:
    return float(np.random.default_rng(1000 + seed).uniform(0.0, 2 * math.pi))


def late_mean(samples: list[tuple[float, float, float]], from_s: float | None) -> tuple[float, float]:
    """Mean max error and mean floor [m] over the samples ``(t [s], max [m], floor [m])`` taken at
    ``t >= from_s`` (the running average of PM Fig. 16 restarted at ``from_s``); NaN without
    ``from_s`` or without a sample after it."""
    if from_s is None:
        return math.nan, math.nan
    late = [(e, f) for t, e, f in samples if t >= from_s]
    if not late:
        return math.nan, math.nan
    a = np.asarray(late, dtype=float)
    return float(np.mean(a[:, 0])), float(np.mean(a[:, 1]))


def run_one(job: tuple) -> tuple:
    """One flight; returns (job, mean max error [m], mean floor [m], cell [m], direction changes,
    (mean max error, mean floor) over the samples at ``t >= Setting.score_from_s``)."""
    setting, kind, seed, alpha = job
    s = SETTINGS[setting]
    fire = s.fire()
    cell, speed, sensor = _cell_speed_sensor(s, fire)
    m = make_monitor(s, fire, kind, seed, alpha)
    errs: list[tuple[float, float, float]] = []
    orig = m.update

    def update(cells, pos, t):
        d = orig(cells, pos, t)
        if m.steps % s.every == 0 and m.initial_lap_done:
            e = _error(fire, m, t)
            errs.append((t, e.max_m, e.floor_m))
        return d

    m.update = update  # type: ignore[method-assign]
    fly(fire, m, start_angle_rad=start_angle(seed), t_start_s=s.t0_s, t_end_s=s.t1_s, speed_mps=speed,
        sensor_range_m=sensor)  # fmt: skip
    a = np.asarray(errs)[:, 1:] if errs else np.full((1, 2), np.nan)
    late = late_mean(errs, s.score_from_s)
    return job, float(np.nanmean(a[:, 0])), float(np.nanmean(a[:, 1])), cell, m.direction_changes, late


def run_two(job: tuple) -> tuple:
    """Two importance monitors on one fire, deployed apart, each merging the other's map at
    every step; the UAVs move one perimeter cell per step (cell / speed). Error of each
    monitor's (merged) map, averaged over the two. ``job``: (fire, rule, seed[, split]),
    split as ``MonitorConfig.split`` ("angle" by default, "spread" or "relay")."""
    setting, kind, seed = job[:3]
    split = job[3] if len(job) > 3 else "angle"
    s = SETTINGS[setting]
    fire = s.fire()
    cell, speed, sensor = _cell_speed_sensor(s, fire)
    ms = [make_monitor(s, fire, kind, seed, uav_id=k, split=split) for k in (0, 1)]
    a0 = start_angle(seed)
    pos = []
    for k in (0, 1):
        c = fire.boundary_cell_at_angle(a0 + k * math.pi, s.t0_s)
        pos.append(tuple(float(v) for v in fire.grid.center(*c)))
    t, n, errs = s.t0_s, 0, []
    while t <= s.t1_s:
        for k, m in enumerate(ms):
            peer = ms[1 - k]
            if peer.grid is not None:
                m.merge(peer.to_summary(), peer_id=1 - k, peer_pos_m=pos[1 - k], t_s=t)
            m.update(fire.observe(*pos[k], sensor, t), pos[k], t)
        for k, m in enumerate(ms):
            pos[k] = m.next_waypoint()
        n += 1
        if n % s.every == 0 and all(m.initial_lap_done for m in ms):
            es = [_error(fire, m, t) for m in ms]
            errs.append((np.mean([e.max_m for e in es]), es[0].floor_m))
        t += cell / speed
    a = np.asarray(errs) if errs else np.full((1, 2), np.nan)
    return (
        job,
        float(np.nanmean(a[:, 0])),
        float(np.nanmean(a[:, 1])),
        cell,
        sum(m.direction_changes for m in ms),
    )


SUPPRESSION_SEEDS = (2, 3, 4, 5)


def run_suppressed(seed: int) -> tuple:
    """monitor_grass as the scenario flies it (3 UAVs: one monitors, two suppress at the front it
    reports), in process on the lockstep harness; every 10 control steps (1 s) after the
    monitor's first lap, against the true fire:

    - the distance error against the true fire's convex hull (the same rays, the hull of the
      true fire's squares in place of their union: drops cut notches that the on-board map,
      one outer cell per angle, cannot hold, and that no monitor is asked to draw);
    - the plain distance error and its perfect-map floor, as without suppression;
    - the distance from the monitor's fastest front (``PerimeterMonitor.front``, where the
      suppressors aim) to the burning tip, the burning cell farthest from the ignition point.

    Returns (seed, mean hull error [m], mean error [m], mean floor [m], median front-to-tip
    [m], samples, mission end [s]).
    """
    from fire_uav_agent.testing.harness import Harness, scenario_path
    from fire_uav_common.constants import Objective
    from fire_uav_common.scenario import load_scenario

    sc = load_scenario(scenario_path("monitor_grass"))
    h = Harness(sc, seed, 0)
    model = h.world.fires
    cell = float(sc.fires.raster.cell_size_m)
    ig = sc.fires.raster.ignitions[0]
    hull_err, plain, floor, tip = [], [], [], []
    step = 0
    t = 0.0
    while not h.world.complete:
        r = h.step()
        step += 1
        t = r.stamp_ns * 1e-9
        if step % 10:
            continue
        mons = [  # the monitors of the UAVs monitoring now (a UAV gone home keeps its stale map)
            a.monitor.active
            for a, out in zip(h.agents, h.outputs, strict=True)
            if a.monitor is not None and a.monitor.active is not None
            and out is not None and int(out.state.objective) == int(Objective.MONITOR)
        ]  # fmt: skip
        mons = [m for m in mons if m.initial_lap_done and m.fire_map.known.any()]
        st = model.state_grid()  # [row north, col east]
        i, j = np.nonzero(st > 0)
        if not mons or i.size == 0:
            continue
        fire_xy = np.column_stack([model.xc[j], model.yc[i]])
        bi, bj = np.nonzero(st == 1)
        for m in mons:
            fm = m.fire_map
            c = (fm.center_x_m, fm.center_y_m)
            mp = np.column_stack([fm.outer_x_m[fm.known], fm.outer_y_m[fm.known]])
            e = distance_error(fire_xy, mp, cell, c)
            plain.append(e.max_m)
            floor.append(e.floor_m)
            hull_err.append(max_error(hull_extent(fire_xy, cell, c), hull_extent(mp, cell, c)))
            f = m.front()
            if f is not None and bi.size:
                bx, by = model.xc[bj], model.yc[bi]
                q = int(np.argmax(np.hypot(bx - ig.x_m, by - ig.y_m)))
                tip.append(math.hypot(f[0] - bx[q], f[1] - by[q]))
    mean = lambda v: float(np.mean(v)) if v else math.nan  # noqa: E731
    return (seed, mean(hull_err), mean(plain), mean(floor), float(np.median(tip)) if tip else math.nan,
            len(hull_err), t)  # fmt: skip


def _sawtooth_mean(floor_m: float, a_m: float) -> float:
    """Time mean of max(floor, a u) for u uniform on [0, 1]: the worst angle is the floor's
    until the stale head's error ``a u`` passes it."""
    if a_m <= floor_m:
        return floor_m
    q = floor_m / a_m
    return q * floor_m + (1 - q) * (floor_m + a_m) / 2


def bounds(setting: str, dt_s: float = 1.0) -> dict:
    """What the monitors' speed and footprint allow on one fire without suppression.

    Sampled on the true fire about the ignition point from the end of a first lap (where the
    benchmark's samples start) to the end of the flight. Perimeter: the convex hull of the fire's squares (shorter
    than the cell path a UAV flies, so every figure here is on the low side). Per angle the
    true ROS (the extent's growth over +-5 s). A map cell refreshed ``s`` seconds ago at an
    angle spreading at ROS errs by ROS s; the sensor refreshes everything within ``R``.

    - ``k`` evenly spaced circling monitors: the head is refreshed every ``(L / k - 2 R) / v``,
      a sawtooth; the max over the angles is at least the larger of that and the perfect-map
      floor: the time mean of ``max(floor, ROS_head (L / k - 2 R) / v * u)``, u uniform.
    - any single monitor (``two_point_m``): for two angles A and B a perimeter distance d
      apart, a UAV must fly ``tau = (d - 2 R) / v`` between refreshing one and the other; the
      best patrol of two points is to shuttle, and over a shuttle the max of the two errors
      averages at least ``0.75 (ROS_A + ROS_B) tau``; the largest over all pairs, time mean.
    """
    s = SETTINGS[setting]
    fire = s.fire()
    cell, speed, sensor = _cell_speed_sensor(s, fire)
    c = fire.ignition_xy_m
    r0 = np.nan_to_num(hull_extent(_fire_cells(fire, s.t0_s), cell, c))
    th0 = (np.arange(r0.size) + 0.5) * (2 * np.pi / r0.size)
    x0, y0 = r0 * np.cos(th0), r0 * np.sin(th0)
    lap_s = float(np.sum(np.hypot(np.diff(np.r_[x0, x0[0]]), np.diff(np.r_[y0, y0[0]])))) / speed
    ts = np.arange(s.t0_s + lap_s, s.t1_s + 5.0 + 1e-9, dt_s)
    ext, per, hull_r = [], [], []
    for t in ts:
        fc = _fire_cells(fire, t)
        ext.append(true_extent(fc, cell, c))
        per.append(hull_extent(perfect_map_cells(fc, cell, c), cell, c))
        hull_r.append(hull_extent(fc, cell, c))
    ext_a, per_a, hr = (np.nan_to_num(np.asarray(v)) for v in (ext, per, hull_r))
    th = (np.arange(ext_a.shape[1]) + 0.5) * (2 * np.pi / ext_a.shape[1])
    k5 = int(round(5.0 / dt_s))
    circ: dict[int, list[float]] = {1: [], 2: []}
    two, floors, heads, perims = [], [], [], []
    for n in range(k5, len(ts) - k5):
        ros = np.maximum((ext_a[n + k5] - ext_a[n - k5]) / (ts[n + k5] - ts[n - k5]), 0.0)
        floor = float(np.max(np.abs(ext_a[n] - per_a[n])))
        x, y = hr[n] * np.cos(th), hr[n] * np.sin(th)
        seg = np.hypot(np.diff(np.r_[x, x[0]]), np.diff(np.r_[y, y[0]]))
        arc = np.r_[0.0, np.cumsum(seg)[:-1]]
        perim = float(seg.sum())
        for k in circ:
            circ[k].append(_sawtooth_mean(floor, float(ros.max()) * max(perim / k - 2 * sensor, 0.0) / speed))
        d = np.abs(arc[:, None] - arc[None, :])
        tau = np.maximum(np.minimum(d, perim - d) - 2 * sensor, 0.0) / speed
        two.append(float(np.max(0.75 * (ros[:, None] + ros[None, :]) * tau)))
        floors.append(floor)
        heads.append(float(ros.max()))
        perims.append(perim)
    return {
        "head_ros_mps": float(np.mean(heads)),
        "perimeter_m": (perims[0], perims[-1]),
        "floor_m": float(np.mean(floors)),
        "circling_1_m": float(np.mean(circ[1])),
        "circling_2_m": float(np.mean(circ[2])),
        "two_point_m": float(np.mean(two)),
        "two_point_with_floor_m": float(np.mean(np.maximum(two, floors))),
    }


def _shape_at(fire, cell: float, t_s: float, window_s: float):
    """A fire's shape at ``t_s`` per angle bin about its ignition point, from its arrival times:
    its cells, the true extent [m], the extent's growth rate over the next ``window_s`` [m/s], the
    hull's extent [m] and the hull's segment length per bin [m] (their sum: the perimeter)."""
    c = fire.ignition_xy_m
    fc = _fire_cells(fire, t_s)
    ext = np.nan_to_num(true_extent(fc, cell, c))
    ros = (np.nan_to_num(true_extent(_fire_cells(fire, t_s + window_s), cell, c)) - ext) / window_s
    hr = np.nan_to_num(hull_extent(fc, cell, c))
    th = (np.arange(hr.size) + 0.5) * (2 * np.pi / hr.size)
    x, y = hr * np.cos(th), hr * np.sin(th)
    seg = np.hypot(np.diff(np.r_[x, x[0]]), np.diff(np.r_[y, y[0]]))
    return fc, ext, ros, hr, seg


def describe(setting: str, hours: tuple[float, ...] = (1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)) -> list[dict]:
    """What a synthetic fire does, from its arrival times (no flight): at each hour its size, the
    perimeter (hull of the true fire's squares) and the lap it takes at the UAV's speed, the
    spread rate per angle about the ignition point over the next 10 min (head = max, and the
    median), and how far the head runs in one lap [cells] (PM's regime: long laps, uneven spread)."""
    s = SETTINGS[setting]
    fire = s.fire()
    cell, speed, _ = _cell_speed_sensor(s, fire)
    rows = []
    for h in hours:
        fc, _, ros, _, seg = _shape_at(fire, cell, h * 3600.0, 600.0)
        perim = float(np.sum(seg))
        lap_s = perim / speed
        rows.append(
            dict(
                hours=h,
                cells=len(fc),
                perimeter_cells=perim / cell,
                lap_s=lap_s,
                head_mps=float(ros.max()),
                median_mps=float(np.median(ros)),
                head_cells_per_lap=float(ros.max()) * lap_s / cell,
            )
        )
    return rows


def regime(setting: str, hours: tuple[float, ...], window_s: float = 1800.0) -> list[dict]:
    """Is a synthetic fire in PM Fig. 16a's regime at these times? From its arrival times, no
    flight. Per hour:

    - ``fast_share``: the share of the perimeter (the hull of the true fire's squares, per angle
      bin about the ignition point) whose extent grows over the next ``window_s`` at a quarter
      of the fastest bin's rate or more. The window is long because a slow back moves less
      than a cell in 10 min and reads 0 or a whole cell's rate;
    - ``hull_gap_m``: how far the true fire's own convex hull lies outside it, the largest over
      the 360 angles; a convex fire gives about a cell from its squares alone;
    - ``floor_m``: the perfect-map floor (``distance_error``), what a map of the whole fire scores.
    """
    s = SETTINGS[setting]
    fire = s.fire()
    cell, _, _ = _cell_speed_sensor(s, fire)
    c = fire.ignition_xy_m
    rows = []
    for h in hours:
        fc, ext, ros, hr, seg = _shape_at(fire, cell, h * 3600.0, window_s)
        per = np.nan_to_num(hull_extent(perfect_map_cells(fc, cell, c), cell, c))
        rows.append(
            dict(
                hours=h,
                fast_share=float(seg[ros >= 0.25 * ros.max()].sum() / seg.sum()),
                hull_gap_m=float(np.max(hr - ext)),
                floor_m=float(np.max(np.abs(ext - per))),
                head_mps=float(ros.max()),
                median_mps=float(np.median(ros)),
            )
        )
    return rows


def describe_lines(rows: list[dict]) -> list[str]:
    out = []
    for r in rows:
        x = r["head_mps"] / r["median_mps"] if r["median_mps"] > 0 else math.inf
        out.append(
            f"   {r['hours']:3.1f} h: {r['cells']:5d} cells, perimeter {r['perimeter_cells']:4.0f} cells,"
            f" lap {r['lap_s'] / 60:4.1f} min, head {r['head_mps'] * 60:5.2f} m/min, median"
            f" {r['median_mps'] * 60:4.2f} m/min (x{x:4.1f}), head runs {r['head_cells_per_lap']:5.2f} cells a lap"
        )
    return out


def table(setting: str, rows: dict, seeds: int, over: str = "the flight") -> None:
    cell = next(iter(rows.values()))[0][2]
    print(f"\n   {setting} (cell {cell:g} m; mean over {over} of the max distance error, per seed)")
    print("   monitor         mean [m]  [cells]  floor [m]  ratio  turns  per seed [m]")
    base = np.mean([r[0] for r in rows["circling"]]) if "circling" in rows else math.nan
    for kind, rs in rows.items():
        e = np.array([r[0] for r in rs])
        f = np.array([r[1] for r in rs])
        turns = np.mean([r[3] for r in rs])
        per = " ".join(f"{v:5.1f}" for v in e)
        print(f"   {kind:14s}  {e.mean():8.1f}  {e.mean() / cell:7.2f}  {f.mean():9.1f}  {e.mean() / base:5.2f}"
              f"  {turns:5.1f}  {per}")  # fmt: skip
    print(f"   ({seeds} seeds: deployment angle and direction; ratio: against circling)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="monitor_grass, and grass_wind for 2 min, only")
    ap.add_argument("--fires", nargs="+", choices=list(SETTINGS), help="only these fires")
    ap.add_argument("--seeds", type=int, default=4, help="seeds per fire and monitor (default 4)")
    ap.add_argument(
        "--score-from-s",
        type=float,
        metavar="S",
        help="also tabulate, per single-monitor flight, the mean over the samples at t >= S s after"
        " ignition (the running average restarted there), e.g. 7560 for the fuel-change fire's uneven"
        " phase (its head reaches the fast fuel at about 2.1 h); fires whose flight ends before S are"
        " left out of that table",
    )
    ap.add_argument(
        "--describe",
        action="store_true",
        help="only describe the synthetic fires (sizes, laps, spread), no flights",
    )
    args = ap.parse_args()
    t0 = time.time()
    if args.describe:
        synthetic = [f for f in (args.fires or list(SETTINGS)) if not SETTINGS[f].world]
        if not synthetic:
            ap.error("--describe: --fires names no synthetic fire (" + ", ".join(SYNTHETIC) + ")")
        for f in synthetic:
            print(
                f"{f} (the true fire; {CELL_M:g} m cells, {SPEED_MPS:g} m/s; spread per angle about the ignition point)"
            )
            end_h = SETTINGS[f].t1_s / 3600.0
            print("\n".join(describe_lines(describe(f, tuple(np.arange(1.0, end_h + 0.01, 0.5))))))
            for r in regime(f, tuple(np.arange(2.0, end_h - 0.49, 0.5))):
                print(
                    f"   {r['hours']:3.1f} h: perimeter at >= 1/4 of the head's rate (30 min) {r['fast_share']:4.2f},"
                    f" own hull outside the fire by {r['hull_gap_m']:4.0f} m, perfect-map floor {r['floor_m']:4.0f} m"
                )
        return
    if args.quick:
        g = SETTINGS["grass_wind"]
        SETTINGS["grass_wind"] = Setting(g.name, g.t0_s, g.t0_s + 120.0, g.every, g.center_known)
    fires = args.fires or (["monitor_grass", "grass_wind"] if args.quick else list(SETTINGS))
    if args.score_from_s is not None:
        if not math.isfinite(args.score_from_s) or args.score_from_s < 0:
            ap.error(f"--score-from-s must be a time >= 0 s, got {args.score_from_s}")
        for f in fires:  # the workers are forked and read SETTINGS, as --quick's
            SETTINGS[f] = replace(SETTINGS[f], score_from_s=args.score_from_s)
    jobs = [(f, k, seed, 1.0) for f in fires for k in MONITORS for seed in range(args.seeds)]
    alpha_fires = [f for f in ("monitor_grass", "wind-driven", "narrow head") if f in fires]
    alpha_jobs = [(f, "worst", 0, a) for f in alpha_fires for a in ALPHAS]
    two_jobs = (
        [("monitor_grass", "worst", seed, split) for split in TWO_SPLITS for seed in range(args.seeds)]
        if "monitor_grass" in fires
        else []
    )
    supp_seeds = SUPPRESSION_SEEDS if "monitor_grass" in fires else ()
    with ProcessPoolExecutor() as pool:
        res = list(pool.map(run_one, jobs + alpha_jobs))
        two = list(pool.map(run_two, two_jobs))
        supp = list(pool.map(run_suppressed, supp_seeds))
    one = {job: (e, f, c, n) for job, e, f, c, n, _ in res}
    late = {job: (lt[0], lt[1], c, n) for job, _, _, c, n, lt in res}
    print("Distance error (PM VI-E, fire_perimeter_monitor.distance_error); no suppression")
    for f in fires:
        rows = {k: [one[(f, k, seed, 1.0)] for seed in range(args.seeds)] for k in MONITORS}
        if f == "monitor_grass":
            for split in TWO_SPLITS:
                rows[f"two ({split})"] = [(e, fl, c, n) for job, e, fl, c, n in two if job[3] == split]
        table(f, rows, args.seeds)
    for f in fires:
        s_from = SETTINGS[f].score_from_s  # --score-from-s, or the fire's own (narrow head)
        if s_from is None or SETTINGS[f].t1_s <= s_from:
            continue
        rows = {k: [late[(f, k, seed, 1.0)] for seed in range(args.seeds)] for k in MONITORS}
        over = f"t >= {s_from:g} s (flight {SETTINGS[f].t0_s:g}-{SETTINGS[f].t1_s:g} s)"
        table(f, rows, args.seeds, over)
    if "monitor_grass" in fires:
        b = bounds("monitor_grass")
        print(
            "\n   what the speed and footprint allow on monitor_grass (the true fire; bench_perimeter.bounds)"
        )
        print(f"   head ROS {b['head_ros_mps']:.2f} m/s; perimeter {b['perimeter_m'][0]:.0f} -> {b['perimeter_m'][1]:.0f} m;"
              f" perfect-map floor {b['floor_m']:.1f} m")  # fmt: skip
        print(f"   evenly spaced circling monitors (head sawtooth over the floor): 1: {b['circling_1_m']:.1f} m,"
              f" 2: {b['circling_2_m']:.1f} m")  # fmt: skip
        print(f"   any single monitor (two-point shuttle bound): >= {b['two_point_m']:.1f} m,"
              f" with the floor >= {b['two_point_with_floor_m']:.1f} m")  # fmt: skip
    if supp:
        print(
            "\n   monitor_grass with suppression (the scenario's 3 UAVs, in process; 1 s samples while a UAV monitors)"
        )
        print("   seed  vs true hull [m]  error [m]  floor [m]  front to tip, median [m]  samples  end [s]")
        for sd, hull_m, err_m, floor_m, tip_m, n, end_s in supp:
            print(
                f"   {sd:4d}  {hull_m:16.1f}  {err_m:9.1f}  {floor_m:9.1f}  {tip_m:25.1f}  {n:7d}  {end_s:6.0f}"
            )
        hulls = [r[1] for r in supp if r[5]]
        tips = [r[4] for r in supp if r[5] and math.isfinite(r[4])]  # nan: put out before a tip was seen
        print(f"   mean vs true hull {np.mean(hulls):.1f} m (target <= 25); median of the seeds' front-to-tip medians"
              f" {np.median(tips) if tips else math.nan:.1f} m over the {len(tips)} seeds with a burning tip"
              " (target <= 10)")  # fmt: skip
    print("\n   direction changes vs alpha, worst-angle rule, seed 0 (paper Fig. 11: 0, 8, 11, 15, 20, 43)")
    for f in alpha_fires:
        print(f"   {f:14s} " + "  ".join(f"a={a:g}: {one[(f, 'worst', 0, a)][3]}" for a in ALPHAS))
    print(
        "   and the mean max error [cells] vs alpha (the same flights; from the fire's score time where it has one)"
    )
    for f in alpha_fires:
        err = {a: late[(f, "worst", 0, a)][0] if SETTINGS[f].score_from_s is not None else one[(f, "worst", 0, a)][0]
               for a in ALPHAS}  # fmt: skip
        cell = one[(f, "worst", 0, 1.0)][2]
        print(f"   {f:14s} " + "  ".join(f"a={a:g}: {err[a] / cell:4.2f}" for a in ALPHAS))
    print(f"\ntotal {time.time() - t0:.0f} s wall")


if __name__ == "__main__":
    main()
