"""Small self-contained raster test fires and a perimeter-flight driver (tests and benchmarks).

Not a fire simulator: each fire is a precomputed arrival-time raster (when each cell ignites),
so that the state at any time is a lookup. Frame: map frame, cell (i, j) centred at
``((i + 0.5) * cell_size_m, (j + 0.5) * cell_size_m)``, i east, j north.

- :func:`star_fire`: arrival = t0 + distance / ROS(angle), any ROS per angle about the
  ignition point, e.g. the linear ROS of the paper's representative scenario (PM V-A).
- :func:`spread_fire`: shortest arrival times over a 16-neighbour stencil with a ROS that
  depends on the cell (fuel) and the heading (wind, elliptical spread), as a cheap stand-in
  for DEVS-FIRE (PM VI-A).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .boundary import is_boundary_cell, lookup_from_grid
from .errors import ConfigError, InputError
from .fire_map import CellGrid, CellState
from .planner import PerimeterMonitor
from .shape import max_distance_error, polygon_radial_extent

__all__ = [
    "FlightTrace",
    "RasterFire",
    "elliptical_ros",
    "fly",
    "linear_ros",
    "spread_fire",
    "star_fire",
]


@dataclass
class RasterFire:
    """A fire given by per-cell arrival times [s] (inf: never burns)."""

    arrival_s: np.ndarray  # (ni, nj)
    cell_size_m: float
    ignition_xy_m: tuple[float, float]
    burn_duration_s: float = 1800.0
    _rays: np.ndarray | None = field(default=None, repr=False)
    _ray_r: np.ndarray | None = field(default=None, repr=False)

    @property
    def grid(self) -> CellGrid:
        h = self.cell_size_m / 2
        return CellGrid(h, h, self.cell_size_m)

    def fire_mask(self, t_s: float) -> np.ndarray:
        return self.arrival_s <= t_s

    def state(self, t_s: float) -> np.ndarray:
        """Cell states (CellState) at ``t_s``."""
        s = np.full(self.arrival_s.shape, CellState.UNBURNED, dtype=np.uint8)
        s[self.arrival_s <= t_s] = CellState.BURNING
        s[self.arrival_s <= t_s - self.burn_duration_s] = CellState.BURNED
        return s

    def observe(self, x_m: float, y_m: float, range_m: float, t_s: float):
        """Cells whose centres are within ``range_m`` of (x_m, y_m): ``(x_m, y_m, state)`` arrays."""
        g = self.grid
        ci, cj = (int(v) for v in g.index(x_m, y_m))
        r = int(math.ceil(range_m / self.cell_size_m))
        ni, nj = self.arrival_s.shape
        i0, i1 = max(ci - r, 0), min(ci + r, ni - 1)
        j0, j1 = max(cj - r, 0), min(cj + r, nj - 1)
        ii, jj = np.meshgrid(np.arange(i0, i1 + 1), np.arange(j0, j1 + 1), indexing="ij")
        cx, cy = g.center(ii, jj)
        near = np.hypot(cx - x_m, cy - y_m) <= range_m + 1e-9
        a = self.arrival_s[ii[near], jj[near]]
        st = np.where(a <= t_s - self.burn_duration_s, 2, np.where(a <= t_s, 1, 0)).astype(np.uint8)
        return cx[near], cy[near], st

    def boundary_cell_at_angle(self, angle_rad: float, t_s: float) -> tuple[int, int]:
        """Outermost burning cell along a ray from the ignition point (a deployment cell)."""
        g = self.grid
        mask = self.fire_mask(t_s)
        best = tuple(int(v) for v in g.index(*self.ignition_xy_m))
        look = lookup_from_grid(mask, g)
        for r in np.arange(0.0, max(mask.shape) * self.cell_size_m * 1.5, self.cell_size_m / 4):
            x = self.ignition_xy_m[0] + r * math.cos(angle_rad)
            y = self.ignition_xy_m[1] + r * math.sin(angle_rad)
            i, j = g.index(x, y)
            c = (int(i), int(j))
            if look(*c) and is_boundary_cell(look, c):
                best = c
        return best  # type: ignore[return-value]

    def true_extent(self, t_s: float, bin_count: int = 360) -> np.ndarray:
        """Farthest distance [m] of the burned area along rays from the ignition point (PM VI-E)."""
        if self._rays is None or self._rays.shape[0] != bin_count:
            g = self.grid
            ni, nj = self.arrival_s.shape
            r = np.arange(0.0, math.hypot(ni, nj) * self.cell_size_m, self.cell_size_m / 4)
            th = (np.arange(bin_count) + 0.5) * (2 * np.pi / bin_count)
            x = self.ignition_xy_m[0] + np.outer(np.cos(th), r)
            y = self.ignition_xy_m[1] + np.outer(np.sin(th), r)
            i, j = g.index(x, y)
            inside = (i >= 0) & (i < ni) & (j >= 0) & (j < nj)
            a = np.full(x.shape, np.inf)
            a[inside] = self.arrival_s[i[inside], j[inside]]
            self._rays, self._ray_r = a, r
        assert self._ray_r is not None
        burnt = self._rays <= t_s
        any_b = burnt.any(axis=1)
        last = burnt.shape[1] - 1 - np.argmax(burnt[:, ::-1], axis=1)
        return np.where(any_b, self._ray_r[last], np.nan)


def _cell_centers(shape: tuple[int, int], cell_size_m: float) -> tuple[np.ndarray, np.ndarray]:
    ii, jj = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    return (ii + 0.5) * cell_size_m, (jj + 0.5) * cell_size_m


def linear_ros(
    r_min_mps: float, r_max_mps: float, min_angle_rad: float
) -> Callable[[np.ndarray], np.ndarray]:
    """PM V-A representative scenario: ROS grows linearly with the angle from the minimum
    direction, from ``r_min`` there to ``r_max`` opposite, symmetric on both sides."""

    def ros(theta: np.ndarray) -> np.ndarray:
        d = np.abs((np.asarray(theta) - min_angle_rad + np.pi) % (2 * np.pi) - np.pi)
        return r_min_mps + (r_max_mps - r_min_mps) * d / np.pi

    return ros


def elliptical_ros(
    head_mps: float, eccentricity: float, wind_to_rad: float
) -> Callable[[np.ndarray], np.ndarray]:
    """Elliptical fire spread from the rear focus: ``R(phi) = R_head (1 - e) / (1 - e cos(phi - wind))``."""
    if not 0 <= eccentricity < 1:
        raise ConfigError(f"eccentricity must be in [0, 1), got {eccentricity}")

    def ros(phi: np.ndarray) -> np.ndarray:
        return head_mps * (1 - eccentricity) / (1 - eccentricity * np.cos(np.asarray(phi) - wind_to_rad))

    return ros


def star_fire(
    shape: tuple[int, int],
    cell_size_m: float,
    ignition_cell: tuple[int, int],
    ros_of_angle: Callable[[np.ndarray], np.ndarray],
    *,
    t0_s: float = 0.0,
    burn_duration_s: float = 1800.0,
) -> RasterFire:
    """Star-shaped fire: a cell ignites at ``t0 + distance / ROS(angle)`` from the ignition cell."""
    x, y = _cell_centers(shape, cell_size_m)
    ix, iy = (ignition_cell[0] + 0.5) * cell_size_m, (ignition_cell[1] + 0.5) * cell_size_m
    d = np.hypot(x - ix, y - iy)
    th = np.arctan2(y - iy, x - ix)
    arrival = t0_s + d / np.maximum(ros_of_angle(th), 1e-12)
    return RasterFire(arrival, cell_size_m, (ix, iy), burn_duration_s)


_STENCIL = [
    (di, dj)
    for di in range(-2, 3)
    for dj in range(-2, 3)
    if (di, dj) != (0, 0) and math.gcd(abs(di), abs(dj)) == 1
]


def spread_fire(
    shape: tuple[int, int],
    cell_size_m: float,
    ignition_cell: tuple[int, int],
    ros_of_heading: Callable[[np.ndarray], np.ndarray],
    *,
    fuel_factor: np.ndarray | None = None,
    t0_s: float = 0.0,
    burn_duration_s: float = 1800.0,
    max_iter: int = 2000,
) -> RasterFire:
    """Fire spreading cell to cell: the earliest arrival over a 16-neighbour stencil.

    A step of heading ``phi`` and length ``L`` out of cell p takes ``L / (ROS(phi) * fuel[p])``.
    Solved by vectorised Bellman-Ford relaxation (a few hundred sweeps on 200 x 200).
    """
    ff = np.ones(shape) if fuel_factor is None else np.asarray(fuel_factor, dtype=float)
    if ff.shape != tuple(shape):
        raise InputError(f"fuel_factor shape {ff.shape} != grid shape {shape}")
    t = np.full(shape, np.inf)
    t[ignition_cell] = t0_s
    costs = []
    for di, dj in _STENCIL:
        step = math.hypot(di, dj) * cell_size_m
        rate = float(ros_of_heading(np.array(math.atan2(dj, di)))) * ff
        with np.errstate(divide="ignore"):
            costs.append(np.where(rate > 0, step / np.where(rate > 0, rate, 1.0), np.inf))
    ni, nj = shape
    for _ in range(max_iter):
        new = t.copy()
        for (di, dj), cost in zip(_STENCIL, costs, strict=True):
            src = t + cost  # arrival at p + (di, dj) through p
            si = slice(max(0, -di), ni - max(0, di))
            sj = slice(max(0, -dj), nj - max(0, dj))
            di_ = slice(max(0, di), ni - max(0, -di))
            dj_ = slice(max(0, dj), nj - max(0, -dj))
            np.minimum(new[di_, dj_], src[si, sj], out=new[di_, dj_])
        if np.array_equal(new, t):
            break
        t = new
    ix, iy = (ignition_cell[0] + 0.5) * cell_size_m, (ignition_cell[1] + 0.5) * cell_size_m
    return RasterFire(t, cell_size_m, (ix, iy), burn_duration_s)


@dataclass
class FlightTrace:
    """What :func:`fly` recorded, one entry per cell reached."""

    t_s: list[float] = field(default_factory=list)
    x_m: list[float] = field(default_factory=list)
    y_m: list[float] = field(default_factory=list)
    direction: list[int] = field(default_factory=list)
    max_error_m: list[float] = field(default_factory=list)  # PM VI-E, if measured


def fly(
    fire: RasterFire,
    monitor: PerimeterMonitor,
    *,
    start_angle_rad: float,
    t_start_s: float,
    t_end_s: float,
    speed_mps: float,
    sensor_range_m: float,
    measure_error: bool = False,
    max_steps: int = 1_000_000,
) -> FlightTrace:
    """Fly a monitor along a raster fire: deploy on the perimeter, then cell to cell.

    Each step the UAV senses the cells within ``sensor_range_m``, the monitor updates and
    gives the next waypoint, and the UAV flies there in straight line at ``speed_mps``
    (perfect tracking). With ``measure_error`` the PM VI-E maximum distance error between the
    true shape and the hull of the on-board perimeter cells is recorded at each new cell.
    """
    g = fire.grid
    cell = fire.boundary_cell_at_angle(start_angle_rad, t_start_s)
    x, y = (float(v) for v in g.center(*cell))
    t = t_start_s
    trace = FlightTrace()
    for _ in range(max_steps):
        if t > t_end_s:
            break
        monitor.update(fire.observe(x, y, sensor_range_m, t), (x, y), t)
        trace.t_s.append(t)
        trace.x_m.append(x)
        trace.y_m.append(y)
        trace.direction.append(int(monitor.direction))
        if measure_error:
            hull = monitor.hull_m()
            est = polygon_radial_extent(hull, *fire.ignition_xy_m, 360)
            trace.max_error_m.append(max_distance_error(fire.true_extent(t), est))
        nx, ny = monitor.next_waypoint()
        dist = math.hypot(nx - x, ny - y)
        t += max(dist, 1e-3 * fire.cell_size_m) / speed_mps
        x, y = nx, ny
    return trace
