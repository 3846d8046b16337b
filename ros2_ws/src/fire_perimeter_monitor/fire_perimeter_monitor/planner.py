"""Perimeter monitors: importance-based (PM Listing 1) and the circling baseline (PM VI-E).

Both have one small interface, driven by the agent (or a test) once per sensor sample:

    monitor.update(observed_cells, uav_pos_m, t_s)   # FireCells footprint, UAV (x, y) [m], sim time [s]
    x_m, y_m = monitor.next_waypoint()               # centre of the next perimeter cell
    monitor.direction                                 # Direction.CCW / Direction.CW
    monitor.to_summary()                              # PerimeterMap fields as plain arrays
    monitor.merge(peer_summary, ...)                  # a peer monitor's PerimeterMap fields

A planning step (Listing 1, step 2) runs whenever the UAV has reached a new cell.

Two monitors on one fire (not in the single-UAV paper, which leaves several UAVs to future
work, PM Section VII; our choice): each merges the other's map (newer outer cells become
visits, so cells the peer just saw have a small ``t_sinceVisit`` and little importance), and
the perimeter is split between the monitors: a cell of a live peer's arc has importance 0 in
our windows. ``MonitorConfig.split`` chooses where the arcs meet: "angle" (the default) at
the bisectors of the monitors' angles about the centre; "spread" halfway, in spread rate x
perimeter length, between neighbouring monitors (:mod:`.split`, the balanced responsibility
of the multi-UAS work PM cites as [3]); "relay" (two monitors): the one nearer the head holds
an arc about it, the other the rest, the roles swapping as they pass (:func:`.split.relay_split`).
A monitor thus works its own arc, back and forth
when the peer's arc is ahead (as in [3]), and two monitors that meet fly apart in opposite
directions. On monitor_grass the spread split measured worse than the angle split (two
monitors, 10 seeds: 12.8 m against 12.0 m; the package README), so it is not the default;
the relay measured the same 12.0 m, and is not the default either.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .boundary import fire_lookup, nearest_boundary_cell, next_boundary_cell
from .errors import ConfigError, InputError, SequenceError
from .fire_map import (
    CellGrid,
    Direction,
    FireMap,
    as_cell_arrays,
    circular_fill,
    direction_sign,
    reversed_direction,
    sighting,
)
from .importance import (
    WindowImportance,
    adjust_heterogeneity,
    should_turn,
    window_importance,
    worst_angle_turn,
)
from .shape import construct_perimeter, perimeter_cells_hull, resample_closed
from .split import arc_work, relay_split, work_bisector_split

__all__ = ["CirclingMonitor", "ImportanceMonitor", "MonitorConfig", "PerimeterMonitor"]


@dataclass(frozen=True)
class MonitorConfig:
    """Monitor parameters. Distances [m], times [s], speeds [m/s]."""

    cell_size_m: float  # raster cell side (the planning granularity, PM III)
    speed_mps: float  # UAV ground speed along the perimeter (Eq. 3)
    alpha: float = 1.0  # heterogeneity-adjusting factor (Eq. 7), >= 0
    bin_count: int = 360  # angle bins (PM IV-A)
    center_x_m: float | None = None  # ignition point; None: estimated after the initial lap
    center_y_m: float | None = None
    ignition_time_s: float | None = None  # None: ROS known from a bin's second visit on
    initial_direction: Direction = Direction.CCW
    revisit_gap_s: float | None = None  # same-visit window of a bin; default 10 cells of flight
    turn_on_tie: bool = False  # see importance.should_turn
    peer_timeout_s: float = 120.0  # a peer not heard for this long no longer owns an arc
    search_radius_cells: int = 3  # how far to look for the perimeter when off it
    uav_id: int = 0  # breaks the tie between monitors at the same angle (lower id keeps the arc ahead)
    # Hysteresis (not in the paper, see ImportanceMonitor): after a turn, fly on for at least
    # max(min_run_cells, min_run_fraction * perimeter cells) before the next decision, and turn
    # only when IMP_BACK > (1 + turn_margin) * IMP_FRONT. All 0: the paper's Listing 3 exactly.
    min_run_cells: int = 0
    min_run_fraction: float = 0.25
    turn_margin: float = 0.0
    ros_baseline_s: float | None = None  # FireMap: Eq. 1 over at least this long; default 20 cells of flight
    # FireMap: Eq. 1 also over at least the time the fire takes to spread this many cells
    ros_baseline_cells: float = 2.0
    ros_smooth_bins: int = 0  # circular moving average of the per-bin ROS over +-this many bins
    # front(): the head is the farthest outer cell among the bins whose ROS, averaged over
    # +-front_smooth_bins bins, is at least front_ros_fraction of the largest such average
    front_smooth_bins: int = 5
    front_ros_fraction: float = 0.8
    # Turning rule: "worst" (ours, importance.worst_angle_turn: turn when that lowers the
    # largest predicted error at any angle) or "windows" (PM Listing 3: IMP_BACK > IMP_FRONT).
    rule: str = "worst"
    # How far ahead the sensor refreshes the map (worst-angle rule) [m]; None: the footprint's
    # radius as measured from the sensor samples (the farthest cell seen from the UAV)
    reach_m: float | None = None
    # Split of the perimeter with live peers: "angle" (the bisectors of the monitors' angles
    # about the centre) or "spread" (split.work_bisector_split: each boundary halfway in Eq. 7
    # spread rate x length between neighbouring monitors; measured worse on monitor_grass) or
    # "relay" (split.relay_split, with exactly one live peer: the monitor nearer the fastest
    # cell holds the head, the other the rest; more peers: by angle)
    split: str = "angle"
    # relay: the holder's arc reaches reach + speed * relay_head_period_s / 2 either side of
    # the head, so sweeping it the head is out of the footprint at most this long [s]
    relay_head_period_s: float = 3.5
    # relay: the holder's arc also spans the stretch about the head whose Eq. 7 ROS is at least
    # this fraction of the head's smoothed rate (split.relay_split; 0: off)
    relay_fast_fraction: float = 0.5

    def __post_init__(self) -> None:
        if not self.cell_size_m > 0:
            raise ConfigError(f"cell_size_m must be > 0, got {self.cell_size_m}")
        if not self.speed_mps > 0:
            raise ConfigError(f"speed_mps must be > 0, got {self.speed_mps}")
        if not self.alpha >= 0:
            raise ConfigError(f"alpha must be >= 0, got {self.alpha}")
        if (self.center_x_m is None) != (self.center_y_m is None):
            raise ConfigError("give both center_x_m and center_y_m, or neither")
        if self.min_run_cells < 0 or not 0 <= self.min_run_fraction <= 1 or not self.turn_margin >= 0:
            raise ConfigError(
                "min_run_cells must be >= 0, min_run_fraction in [0, 1], turn_margin >= 0; got "
                f"{self.min_run_cells}, {self.min_run_fraction}, {self.turn_margin}"
            )
        if self.rule not in ("worst", "windows"):
            raise ConfigError(f"rule must be 'worst' or 'windows', got {self.rule!r}")
        if self.split not in ("spread", "angle", "relay"):
            raise ConfigError(f"split must be 'spread', 'angle' or 'relay', got {self.split!r}")
        if not self.relay_head_period_s >= 0 or not 0 <= self.relay_fast_fraction <= 1:
            raise ConfigError(
                "relay_head_period_s must be >= 0 and relay_fast_fraction in [0, 1]; got "
                f"{self.relay_head_period_s}, {self.relay_fast_fraction}"
            )
        if self.reach_m is not None and not self.reach_m >= 0:
            raise ConfigError(f"reach_m must be >= 0 or None, got {self.reach_m}")
        if self.front_smooth_bins < 0 or not 0 <= self.front_ros_fraction <= 1:
            raise ConfigError(
                "front_smooth_bins must be >= 0 and front_ros_fraction in [0, 1]; got "
                f"{self.front_smooth_bins}, {self.front_ros_fraction}"
            )
        if self.revisit_gap_s is not None and not self.revisit_gap_s >= 0:
            raise ConfigError(f"revisit_gap_s must be >= 0, got {self.revisit_gap_s}")

    @property
    def gap_s(self) -> float:
        return (
            self.revisit_gap_s if self.revisit_gap_s is not None else 10 * self.cell_size_m / self.speed_mps
        )


@dataclass
class _Peer:
    peer_id: int
    angle_rad: float  # about the map's centre
    heard_s: float
    xy_m: tuple[float, float]  # where the peer was placed (its angle is re-taken when the centre is found)


@dataclass
class _Lap:
    """Initial-lap bookkeeping (Listing 2)."""

    done: bool = False
    start_xy: tuple[float, float] | None = None
    last_angle: float | None = None
    swept_rad: float = 0.0  # [rad] about the map centre
    last_heading: float | None = None
    turned_rad: float = 0.0  # [rad] the UAV's heading, cell to cell
    raw: list[np.ndarray] = field(default_factory=list)  # (n, 3) chunks of (x_m, y_m, t_s) sightings

    def raw_cells(self) -> np.ndarray:
        """All raw sightings so far as one ``(n, 3)`` array, in the order they came."""
        return np.vstack(self.raw) if self.raw else np.zeros((0, 3))


class PerimeterMonitor:
    """Shared machinery: fire map, initial lap, boundary following, summary, peer merge."""

    changes_direction = False

    def __init__(self, config: MonitorConfig) -> None:
        self.config = config
        c = config
        self.center_known = c.center_x_m is not None
        self.fire_map = FireMap(
            c.center_x_m if c.center_x_m is not None else 0.0,
            c.center_y_m if c.center_y_m is not None else 0.0,
            bin_count=c.bin_count,
            ignition_time_s=c.ignition_time_s,
            revisit_gap_s=c.gap_s,
            ros_baseline_s=c.ros_baseline_s
            if c.ros_baseline_s is not None
            else 20 * c.cell_size_m / c.speed_mps,
            ros_baseline_cells=c.ros_baseline_cells,
            cell_size_m=c.cell_size_m,
        )
        self.direction = Direction(c.initial_direction)
        self.direction_changes = 0
        self.grid: CellGrid | None = None
        self.cell: tuple[int, int] | None = None
        self.prev_cell: tuple[int, int] | None = None
        self.uav_xy: tuple[float, float] | None = None
        self.t_s: float = float("nan")
        self.last_window: WindowImportance | None = None
        self.last_cells_m: np.ndarray | None = None  # resampled perimeter of the last decision
        self._lookup: Callable[[int, int], bool] | None = None
        self._link_m = 1.5 * math.sqrt(2) * c.cell_size_m
        self._lap = _Lap()
        self._peers: dict[int, _Peer] = {}
        self.steps = 0
        self.run_cells = 0  # cells flown since the last direction change (or the initial lap)
        self.footprint_m = 0.0  # farthest cell centre seen from the UAV in one sample [m]

    # --- public interface ----------------------------------------------------------------
    @property
    def initial_lap_done(self) -> bool:
        return self._lap.done

    def update(self, observed_cells, uav_pos_m: tuple[float, float], t_s: float) -> Direction:
        """Take one sensor sample; run a planning step if the UAV reached a new cell."""
        x, y, s = as_cell_arrays(observed_cells)
        ux, uy = float(uav_pos_m[0]), float(uav_pos_m[1])
        if not (math.isfinite(ux) and math.isfinite(uy) and math.isfinite(t_s)):
            raise InputError(f"non-finite UAV position or time: ({ux}, {uy}) at {t_s}")
        if self.grid is None:
            if x.size == 0:
                self.uav_xy, self.t_s = (ux, uy), float(t_s)
                return self.direction
            self.grid = CellGrid(float(x[0]), float(y[0]), self.config.cell_size_m)
        self.uav_xy, self.t_s = (ux, uy), float(t_s)
        if x.size:
            self.footprint_m = max(self.footprint_m, float(np.max(np.hypot(x - ux, y - uy))))
        self._lookup = fire_lookup(x, y, s, self.grid)
        per, unburned = sighting(x, y, s, self.config.cell_size_m, checked=True)
        if self.center_known:
            self.fire_map.record(x[per], y[per], t_s, link_m=self._link_m, seen_unburned=unburned)
        else:
            xp, yp = x[per], y[per]
            self._lap.raw.append(np.column_stack([xp, yp, np.full(xp.size, float(t_s))]))
            if self._lap.done:
                self.fire_map.record(x[per], y[per], t_s, link_m=self._link_m, seen_unburned=unburned)
        i, j = self.grid.index(ux, uy)
        cell = (int(i), int(j))
        if cell != self.cell:
            self.prev_cell, self.cell = self.cell, cell
            self.steps += 1
            self.run_cells += 1
            if not self._lap.done:
                self._track_initial_lap(ux, uy)
            elif self.changes_direction:
                self._plan()
        return self.direction

    @property
    def reach_m(self) -> float:
        """How far along the perimeter [m] the sensor refreshes cells ahead of (and behind) the
        UAV: ``MonitorConfig.reach_m``, or the footprint radius seen so far. A perimeter cell
        within the footprint's radius in a straight line is at least as near along the
        perimeter, so the radius is the cautious figure."""
        return self.config.reach_m if self.config.reach_m is not None else self.footprint_m

    def next_waypoint(self) -> tuple[float, float]:
        """Centre [m] of the next cell to fly to along the perimeter in ``direction``."""
        if self.grid is None or self.cell is None or self._lookup is None:
            if self.uav_xy is None:
                raise SequenceError("next_waypoint() before any update()")
            return self.uav_xy
        nxt = next_boundary_cell(self._lookup, self.cell, self.direction, self.prev_cell)
        if nxt is None:
            near = nearest_boundary_cell(self._lookup, self.cell, self.config.search_radius_cells)
            if near is not None and near != self.cell:
                nxt = near
            else:
                nxt = self._step_radially(inside=self._lookup(*self.cell))
        x, y = self.grid.center(*nxt)
        return float(x), float(y)

    def lookahead_waypoint(self, n_cells: int) -> tuple[float, float]:
        """Centre [m] of the perimeter cell ``n_cells`` ahead in ``direction`` (a fast UAV's aim point).

        Walks the boundary of the latest footprint; stops early where it is lost.
        """
        first = self.next_waypoint()
        if self.grid is None or self.cell is None or self._lookup is None or n_cells <= 1:
            return first
        i, j = self.grid.index(*first)
        prev, cur = self.cell, (int(i), int(j))
        for _ in range(n_cells - 1):
            nxt = next_boundary_cell(self._lookup, cur, self.direction, prev)
            if nxt is None or nxt == self.cell:
                break
            prev, cur = cur, nxt
        x, y = self.grid.center(*cur)
        return float(x), float(y)

    def front(self) -> tuple[float, float, float] | None:
        """Head of the fire on the on-board map: ``(x_m, y_m, ros_mps)`` or None.

        Among the bins whose Eq. 1 ROS, averaged over ``front_smooth_bins`` bins either side,
        is at least ``front_ros_fraction`` of the largest such average, the outer cell farthest
        from the map centre; ``ros_mps`` is the largest average. On a fire spreading from the
        centre the farthest of the fast bins is where it has run fastest, i.e. its head.

        Not the paper's (PM has no suppressors to aim). The single bin of largest Eq. 1 ROS
        was a poor head on monitor_grass (bench_perimeter's "front to tip", against the world's
        burning cells): near the head the ROS is flat over 10-20 bins, so its argmax wanders along the
        head by tens of metres, and a bin whose previous outer cell was an inner crossing of its
        ray (a notch cut by a drop, or a ray that grazes a flank) gets a spread rate of 5-7 m/s
        against the head's true 3.8 m/s for as long as that baseline lasts, and won the argmax
        from the flank, 60-100 m from the head.
        """
        if not (self._lap.done or self.center_known):
            return None
        fm = self.fire_map
        ros = fm.ros_mps()
        ok = np.isfinite(ros) & fm.known
        if not ok.any():
            return None
        sm = smooth_circular(np.where(ok, ros, 0.0), self.config.front_smooth_bins)
        sm = np.where(ok, sm, -np.inf)
        top = float(np.max(sm))
        if not top > 0:
            return None
        fast = sm >= self.config.front_ros_fraction * top
        k = int(np.argmax(np.where(fast, fm.outer_d_m, -np.inf)))
        return float(fm.outer_x_m[k]), float(fm.outer_y_m[k]), top

    def to_summary(self) -> dict:
        """PerimeterMap fields (except header, uav_id, sequence, fire_id) as plain values."""
        fm = self.fire_map
        f32 = np.float32
        imp = np.full(fm.bin_count, np.nan)
        if self.last_window is not None and self.last_cells_m is not None:
            b = fm.bin_of(self.last_cells_m[:, 0], self.last_cells_m[:, 1])
            order = np.argsort(self.last_window.importance)
            imp[b[order]] = self.last_window.importance[order]  # max per bin wins
        return {
            "center_x_m": float(fm.center_x_m),
            "center_y_m": float(fm.center_y_m),
            "outer_distance_m": fm.outer_d_m.astype(f32),
            "outer_visit_time_s": fm.outer_t_s.astype(f32),
            "spread_rate_mps": fm.ros_mps().astype(f32),
            "importance": imp.astype(f32),
            "direction": int(self.direction),
            "direction_changes": int(self.direction_changes),
        }

    def merge(
        self, peer_summary: dict, *, peer_id: int = -1, peer_pos_m=None, t_s: float | None = None
    ) -> int:
        """Merge a peer monitor's summary (``to_summary()`` / PerimeterMap fields).

        Returns the number of bins taken from the peer. ``peer_pos_m`` (if known, e.g. from
        /fleet/state) locates the peer for the work split; otherwise its position is taken as
        the circular mean angle of its most recently seen bins. Raises ValueError on a
        malformed summary.
        """
        try:
            cx = float(peer_summary["center_x_m"])
            cy = float(peer_summary["center_y_m"])
            d = np.asarray(peer_summary["outer_distance_m"], dtype=float)
            tv = np.asarray(peer_summary["outer_visit_time_s"], dtype=float)
        except (KeyError, TypeError) as e:
            raise InputError(f"peer summary lacks a PerimeterMap field: {e}") from e
        if d.shape != tv.shape or d.ndim != 1 or d.size < 8:
            raise InputError(f"peer summary arrays must be equal 1-D of >= 8 bins, got {d.shape}, {tv.shape}")
        if not (math.isfinite(cx) and math.isfinite(cy)):
            raise InputError("peer summary centre is not finite")
        th = (np.arange(d.size) + 0.5) * (2 * np.pi / d.size)
        px, py = cx + d * np.cos(th), cy + d * np.sin(th)
        taken = self.fire_map.merge_outer(px, py, tv) if self._lap.done or self.center_known else 0
        if not self._lap.done and not self.center_known:
            ok = np.isfinite(px) & np.isfinite(tv)
            self._lap.raw.append(np.column_stack([px[ok], py[ok], tv[ok]]))
        heard = float(t_s) if t_s is not None else float(np.nanmax(tv)) if np.isfinite(tv).any() else -np.inf
        if peer_pos_m is not None:
            at = (float(peer_pos_m[0]), float(peer_pos_m[1]))
            ang = math.atan2(at[1] - self.fire_map.center_y_m, at[0] - self.fire_map.center_x_m)
        elif np.isfinite(tv).any() and np.isfinite(d).any():
            ok = np.isfinite(tv) & np.isfinite(d)
            recent = ok & (tv >= np.nanmax(tv[ok]) - self.config.cell_size_m / self.config.speed_mps)
            xs, ys = px[recent], py[recent]
            at = (float(np.mean(xs)), float(np.mean(ys)))
            ang = math.atan2(
                float(np.mean(ys - self.fire_map.center_y_m)), float(np.mean(xs - self.fire_map.center_x_m))
            )
        else:
            return taken
        self._peers[peer_id] = _Peer(peer_id, ang, heard, at)
        return taken

    def hull_m(self) -> np.ndarray:
        """Convex hull [m] of the on-board perimeter cells (PM VI-E)."""
        return perimeter_cells_hull(self.fire_map, self.config.cell_size_m)

    # --- internals -----------------------------------------------------------------------
    def _step_radially(self, inside: bool) -> tuple[int, int]:
        """One cell away from (inside the fire) or towards (outside) the map centre."""
        assert self.grid is not None and self.cell is not None and self.uav_xy is not None
        dx = self.uav_xy[0] - self.fire_map.center_x_m
        dy = self.uav_xy[1] - self.fire_map.center_y_m
        if not inside:
            dx, dy = -dx, -dy
        n = math.hypot(dx, dy) or 1.0
        return (self.cell[0] + int(round(dx / n)), self.cell[1] + int(round(dy / n)))

    def _track_initial_lap(self, ux: float, uy: float) -> None:
        """Listing 2: fly on until one lap is done, judged by angle swept.

        The paper flies until back at the deployment angle about the ignition point, as we do
        when the centre is known. With the centre unknown the lap ends when the UAV's own
        heading has turned by a full turn: a closed loop around a fire turns the heading by
        2 pi whatever the fire's shape. A return to the start position is not used: the fire
        grows over the start, and the UAV never gets back to it.
        """
        lap = self._lap
        if lap.start_xy is None:
            lap.start_xy = (ux, uy)
        if self.prev_cell is not None and self.cell is not None:
            heading = math.atan2(self.cell[1] - self.prev_cell[1], self.cell[0] - self.prev_cell[0])
            if lap.last_heading is not None:
                lap.turned_rad += (heading - lap.last_heading + math.pi) % (2 * math.pi) - math.pi
            lap.last_heading = heading
        if self.center_known:
            ang = math.atan2(uy - self.fire_map.center_y_m, ux - self.fire_map.center_x_m)
            if lap.last_angle is not None:
                lap.swept_rad += (ang - lap.last_angle + math.pi) % (2 * math.pi) - math.pi
            lap.last_angle = ang
        # Known centre: the paper's full turn about it, or (a centre outside the fire, which
        # angles about it never go round) the heading's full turn and a quarter: on a fire with
        # a dent the heading can complete its turn a little before the loop closes.
        full = (
            abs(lap.swept_rad) >= 2 * math.pi or abs(lap.turned_rad) >= 2.5 * math.pi
            if self.center_known
            else abs(lap.turned_rad) >= 2 * math.pi
        )
        if not full:
            return
        if not self.center_known:
            raw = lap.raw_cells()
            cx, cy = (
                (float(v) for v in np.ascontiguousarray(raw[:, :2]).mean(axis=0)) if raw.size else (ux, uy)
            )
            self.fire_map.set_center(cx, cy, raw)
            self.center_known = True
            lap.raw.clear()
            # peers merged before the centre was found were placed by their angle about the
            # placeholder centre: place them again about the centre the lap found
            for p in self._peers.values():
                p.angle_rad = math.atan2(p.xy_m[1] - cy, p.xy_m[0] - cx)
        lap.done = True

    def _peer_weight(self, cells_m: np.ndarray, ros_mps: np.ndarray | None = None) -> np.ndarray | None:
        """Per-cell weight (1 ours, 0 a live peer's) of the constructed perimeter ``cells_m``
        (index 0 the UAV's cell, growing against the flying direction), or None without a
        live peer. ``MonitorConfig.split``: "spread" with ``ros_mps`` (the cells' Eq. 7 ROS)
        splits halfway in spread rate x length (:func:`split.work_bisector_split`); "relay"
        with ``ros_mps`` and one live peer gives the head's arc to the monitor nearer it and
        the rest to the other (:func:`split.relay_split`); otherwise at the bisectors of the
        monitors' angles about the centre."""
        live = [p for p in self._peers.values() if self.t_s - p.heard_s <= self.config.peer_timeout_s]
        if not live or self.uav_xy is None:
            return None
        fm = self.fire_map
        ang = np.arctan2(cells_m[:, 1] - fm.center_y_m, cells_m[:, 0] - fm.center_x_m)
        mine = math.atan2(self.uav_xy[1] - fm.center_y_m, self.uav_xy[0] - fm.center_x_m)

        def adist(a, b):
            return np.abs((a - b + np.pi) % (2 * np.pi) - np.pi)

        m = cells_m.shape[0]
        if self.config.split == "relay" and ros_mps is not None and m >= 3 and len(live) == 1:
            p = live[0]
            k = int(np.argmin(adist(ang, p.angle_rad)))
            if k == 0:  # on our cell: the lower id keeps the arc ahead (the peer is just behind)
                k = 1 if self.config.uav_id < p.peer_id else m - 1
            spacing = float(np.mean(np.hypot(*np.diff(np.vstack([cells_m, cells_m[:1]]), axis=0).T)))
            half = self.reach_m + self.config.speed_mps * self.config.relay_head_period_s / 2
            return relay_split(
                ros_mps, spacing, k, half, self.config.uav_id < p.peer_id, self.config.relay_fast_fraction
            ).astype(float)
        if self.config.split == "spread" and ros_mps is not None and m >= 3:
            at = []
            for p in live:
                k = int(np.argmin(adist(ang, p.angle_rad)))
                if k == 0:  # on our cell: the lower id keeps the arc ahead (the peer is just behind)
                    k = 1 if self.config.uav_id < p.peer_id else m - 1
                at.append(k)
            spacing = float(np.mean(np.hypot(*np.diff(np.vstack([cells_m, cells_m[:1]]), axis=0).T)))
            return work_bisector_split(arc_work(ros_mps, spacing), np.asarray(at)).astype(float)
        d_me = adist(ang, mine)
        owned = np.ones(ang.size, dtype=bool)
        eps = math.pi / fm.bin_count
        for p in live:
            rel = (p.angle_rad - mine + math.pi) % (2 * math.pi) - math.pi
            if abs(rel) < eps:  # same place: the lower id sees the peer just behind it
                ahead = direction_sign(self.direction) * eps
                rel = -ahead if self.config.uav_id < p.peer_id else ahead
            owned &= d_me < adist(ang, mine + rel)
        return owned.astype(float)

    def _plan(self) -> None:
        """Listing 1 step 2 (i-iii): construct the perimeter, weigh the windows, maybe turn."""


def smooth_circular(values: np.ndarray, half_width_bins: int) -> np.ndarray:
    """Circular moving average over ``2 * half_width_bins + 1`` bins (0: unchanged)."""
    v = np.asarray(values, dtype=float)
    if half_width_bins <= 0 or v.size == 0:
        return v.copy()
    k = min(int(half_width_bins), (v.size - 1) // 2)
    ext = np.concatenate([v[-k:], v, v[:k]])
    c = np.cumsum(np.concatenate([[0.0], ext]))
    return (c[2 * k + 1 :] - c[: -2 * k - 1]) / (2 * k + 1)


class ImportanceMonitor(PerimeterMonitor):
    """Importance-based perimeter monitor (PM Listings 1-3, Eqs. 1-7).

    The turn decision is ``MonitorConfig.rule``: "worst" (default, ours: turn when that lowers
    the largest Eq. 4 error predicted at any angle, :func:`importance.worst_angle_turn`) or
    "windows" (the paper's Listing 3: IMP_BACK > IMP_FRONT over Eqs. 5-6).
    """

    changes_direction = True

    def _plan(self) -> None:
        assert self.uav_xy is not None
        c = self.config
        fm = self.fire_map
        ux, uy = self.uav_xy
        cp = construct_perimeter(fm, ux, uy, self.direction, self.t_s)
        if cp.vertices_m.shape[0] < 3:
            return
        # Eqs. 5-6 index cells from the UAV against the flying direction.
        backward = np.vstack([cp.vertices_m[:1], cp.vertices_m[:0:-1]])
        cells, spacing = resample_closed(backward, c.cell_size_m)
        bins = fm.bin_of(cells[:, 0], cells[:, 1])
        ros = smooth_circular(circular_fill(fm.ros_mps(), 0.0), c.ros_smooth_bins)[bins]
        t_outer = circular_fill(fm.outer_t_s, self.t_s)[bins]
        since = np.maximum(self.t_s - t_outer, 0.0)
        # Eq. 7's ROS only for the spread split and the relay (the angle split does not read it)
        weight = self._peer_weight(
            cells, adjust_heterogeneity(ros, c.alpha) if c.split in ("spread", "relay") else None
        )
        w = window_importance(ros, since, spacing, c.speed_mps, c.alpha, weight=weight)
        self.last_window, self.last_cells_m = w, cells
        min_run = max(c.min_run_cells, int(math.ceil(c.min_run_fraction * cells.shape[0])))
        if self.direction_changes > 0 and self.run_cells < min_run:
            return  # hysteresis: finish the sweep first
        if c.rule == "worst":
            wa = worst_angle_turn(
                ros,
                since,
                spacing,
                c.speed_mps,
                c.alpha,
                weight=weight,
                reach_m=self.reach_m,
                keep_in_view=weight is None,
            )
            turn = (1.0 + c.turn_margin) * wa.worst_back_m < wa.worst_on_m  # ties: fly on
        else:
            turn = should_turn(w.imp_back, (1.0 + c.turn_margin) * w.imp_front, turn_on_tie=c.turn_on_tie)
        if turn:
            self.direction = reversed_direction(self.direction)
            self.direction_changes += 1
            self.run_cells = 0
            self.prev_cell = None  # going back the way we came is now intended


class CirclingMonitor(PerimeterMonitor):
    """Baseline (PM VI-E): circle the perimeter in one direction for the whole mission."""

    changes_direction = False
