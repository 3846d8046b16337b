"""On-board fire map (PM IV-A, Table 1, Listing 2) and the raster cells a fire sensor reports.

Frame: the world "map" frame, x east, y north, metres. Angles are counter-clockwise from +x
around the map centre (the ignition point, or the estimated fire centre when unknown), split
into ``bin_count`` bins (360 in the paper), bin ``k`` covering ``[k, k + 1) * 360 / bin_count``
degrees, as in fire_uav_msgs/PerimeterMap.

Deviations from the paper, and why:
- Table 1 keeps lists of outer and inner cells per angle; we keep one outer and one inner
  cell per bin, the farthest perimeter cell seen in the bin (the outer perimeter), because
  Eq. 1 uses one distance per angle anyway and a fixed-size map is what PerimeterMap carries.
- The paper records only the cell under the UAV (trajectory cells); we record every
  perimeter cell the sensor reports (FireCells: a footprint). A bin seen again within
  ``revisit_gap_s`` of its last sighting is the *same* visit (the outer cell is replaced, the
  inner one kept), otherwise the old outer cell becomes the inner cell (PM IV-A). Without
  this, a footprint sliding over a bin would compute Eq. 1 over a fraction of a second.
- The map never moves a bin inward without evidence. Burned area does not shrink (a cell put
  out stays burned), so a perimeter cell nearer the centre than the bin's outer cell is
  another crossing of the same ray (a ray can cross a notched perimeter several times; Table
  1 keeps lists of cells for this), not a new outer cell: it is not a visit of that bin. Only
  when the sensor sees the outer cell's own place unburned (the map was wrong there) does the
  bin move inward, and its Eq. 1 history restarts. Replacing the outer cell by any later,
  nearer sighting shrank the map and made the next outward sighting a spread-rate spike.
- Eq. 1 baseline: a new visit makes the previous outer cell the inner one only if that cell
  is at least ``max(ros_baseline_s, ros_baseline_cells * cell_size_m / ROS)`` old, ROS the
  bin's current estimate; otherwise the older inner cell is kept (both 0: the paper).
  Distances are quantised to a cell, so Eq. 1 over less than the time the fire takes to
  cross a cell or two gives spikes of one cell per few seconds, or 0; a slow fire needs a
  long baseline and a fast one a short one, hence the part that scales with the ROS.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import CellState, PerimeterDirection

from .errors import ConfigError, InputError

_UNBURNED = int(CellState.UNBURNED)  # a module constant: no enum attribute lookup per call

__all__ = [
    "CellGrid",
    "CellState",
    "Direction",
    "circular_fill",
    "FireMap",
    "angle_bin",
    "as_cell_arrays",
    "direction_sign",
    "reversed_direction",
    "perimeter_mask",
    "sighting",
    "unburned_lookup",
]


#: Travel direction around the fire (``PerimeterMap.DIRECTION_*``). CCW: the bin index (angle
#: about the centre) increases, the fire is on the UAV's left.
Direction = PerimeterDirection


def direction_sign(direction: PerimeterDirection) -> int:
    """+1 for CCW (angle increases), -1 for CW."""
    return 1 if direction == PerimeterDirection.CCW else -1


def reversed_direction(direction: PerimeterDirection) -> PerimeterDirection:
    """The opposite direction of travel."""
    return PerimeterDirection.CW if direction == PerimeterDirection.CCW else PerimeterDirection.CCW


def as_cell_arrays(observed_cells) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(x_m, y_m, state)`` arrays from an ``(n, 3)`` array-like or a 3-tuple of arrays."""
    if isinstance(observed_cells, tuple) and len(observed_cells) == 3:
        x, y, s = (np.asarray(a) for a in observed_cells)
    else:
        arr = np.asarray(observed_cells, dtype=float).reshape(-1, 3)
        x, y, s = arr[:, 0], arr[:, 1], arr[:, 2]
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    s = np.asarray(s).astype(np.int64).ravel()
    if not (x.shape == y.shape == s.shape):
        raise InputError(f"observed cells: x, y, state lengths differ ({x.size}, {y.size}, {s.size})")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError("observed cells: non-finite cell coordinates")
    if s.size and (s.min() < 0 or s.max() > 2):
        raise InputError(f"observed cells: state must be 0, 1 or 2, got values in [{s.min()}, {s.max()}]")
    return x, y, s


@dataclass(frozen=True)
class CellGrid:
    """Square raster: cell (i, j) has its centre at ``origin + (i, j) * cell_size_m``."""

    origin_x_m: float
    origin_y_m: float
    cell_size_m: float

    def __post_init__(self) -> None:
        if not self.cell_size_m > 0:
            raise ConfigError(f"cell_size_m must be > 0, got {self.cell_size_m}")

    def index(self, x_m, y_m) -> tuple[np.ndarray, np.ndarray]:
        """Integer cell indices of points [m] (vectorised)."""
        i = np.rint((np.asarray(x_m, dtype=float) - self.origin_x_m) / self.cell_size_m).astype(np.int64)
        j = np.rint((np.asarray(y_m, dtype=float) - self.origin_y_m) / self.cell_size_m).astype(np.int64)
        return i, j

    def center(self, i, j) -> tuple[np.ndarray, np.ndarray]:
        """Cell centre [m] of indices (vectorised)."""
        return (
            self.origin_x_m + np.asarray(i, dtype=float) * self.cell_size_m,
            self.origin_y_m + np.asarray(j, dtype=float) * self.cell_size_m,
        )


def perimeter_mask(x_m: np.ndarray, y_m: np.ndarray, state: np.ndarray, cell_size_m: float) -> np.ndarray:
    """Which observed cells are perimeter cells.

    A perimeter cell is a burning or burned cell with an *observed* unburned 4-neighbour. A
    neighbour outside the footprint is unknown and does not count, so the footprint's edge
    does not create a false perimeter.
    """
    return sighting(x_m, y_m, state, cell_size_m)[0]


def unburned_lookup(
    x_m: np.ndarray, y_m: np.ndarray, state: np.ndarray, cell_size_m: float
) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """Vectorised test "was the cell at (x_m, y_m) seen unburned in this sighting" [m]."""
    return sighting(x_m, y_m, state, cell_size_m)[1]


def sighting(
    x_m: np.ndarray, y_m: np.ndarray, state: np.ndarray, cell_size_m: float, *, checked: bool = False
) -> tuple[np.ndarray, Callable[[np.ndarray, np.ndarray], np.ndarray]]:
    """:func:`perimeter_mask` and :func:`unburned_lookup` of one sighting, indexed once.

    ``checked``: the arrays are already :func:`as_cell_arrays`' (float, float, int64), as a
    monitor's update has them. Cells are indexed on a grid anchored at the first cell.
    """
    x, y, s = (x_m, y_m, state) if checked else as_cell_arrays((x_m, y_m, state))
    if x.size == 0:
        return np.zeros(0, dtype=bool), _nothing_unburned
    grid = CellGrid(float(x[0]), float(y[0]), cell_size_m)
    i, j = grid.index(x, y)
    # A dense raster over the footprint's bounding box, one cell of margin on every side so
    # that the four neighbours of every cell are inside it.
    i0, j0 = int(i.min()) - 1, int(j.min()) - 1
    i = i - i0
    j = j - j0
    unburned = np.zeros((int(i.max()) + 2, int(j.max()) + 2), dtype=bool)
    u = s == _UNBURNED
    unburned[i[u], j[u]] = True
    near = unburned[i + 1, j] | unburned[i - 1, j] | unburned[i, j + 1] | unburned[i, j - 1]
    per = ~u & near
    if not u.any():
        return per, _nothing_unburned

    def lookup(px: np.ndarray, py: np.ndarray) -> np.ndarray:
        a, b = grid.index(px, py)
        a, b = a - i0, b - j0
        ok = (a >= 0) & (a < unburned.shape[0]) & (b >= 0) & (b < unburned.shape[1])
        out = np.zeros(np.shape(a), dtype=bool)
        out[ok] = unburned[a[ok], b[ok]]
        return out

    return per, lookup


def _nothing_unburned(px: np.ndarray, py: np.ndarray) -> np.ndarray:
    return np.zeros(np.shape(px), dtype=bool)


def angle_bin(x_m, y_m, center_x_m: float, center_y_m: float, bin_count: int = 360) -> np.ndarray:
    """Bin index of points around the centre, CCW from +x (vectorised)."""
    ang = np.arctan2(np.asarray(y_m, dtype=float) - center_y_m, np.asarray(x_m, dtype=float) - center_x_m)
    k = np.floor(np.mod(ang, 2 * np.pi) / (2 * np.pi) * bin_count).astype(np.int64)
    return np.minimum(k, bin_count - 1)


class FireMap:
    """Per-angle outer and inner perimeter cells with distance and visit time (PM Table 1).

    Arrays (length ``bin_count``, NaN where unknown): ``outer_x_m``, ``outer_y_m``,
    ``outer_d_m``, ``outer_t_s``, ``inner_d_m``, ``inner_t_s``. The centre may be set later
    (:meth:`set_center`) when the ignition point is unknown.

    Listing 2: the first time a bin gets an outer cell, the ignition point (distance 0, at
    ``ignition_time_s``) becomes its inner cell. With an unknown ignition time the inner time
    is NaN and that bin's ROS stays unknown until its second visit.
    """

    def __init__(
        self,
        center_x_m: float,
        center_y_m: float,
        *,
        bin_count: int = 360,
        ignition_time_s: float | None = None,
        revisit_gap_s: float = 60.0,
        ros_baseline_s: float = 0.0,
        ros_baseline_cells: float = 0.0,
        cell_size_m: float = 1.0,
    ) -> None:
        if bin_count < 8:
            raise ConfigError(f"bin_count must be >= 8, got {bin_count}")
        if not revisit_gap_s >= 0:
            raise ConfigError(f"revisit_gap_s must be >= 0, got {revisit_gap_s}")
        if not ros_baseline_s >= 0:
            raise ConfigError(f"ros_baseline_s must be >= 0, got {ros_baseline_s}")
        if not ros_baseline_cells >= 0:
            raise ConfigError(f"ros_baseline_cells must be >= 0, got {ros_baseline_cells}")
        if not cell_size_m > 0:
            raise ConfigError(f"cell_size_m must be > 0, got {cell_size_m}")
        if not (math.isfinite(center_x_m) and math.isfinite(center_y_m)):
            raise ConfigError(f"map centre must be finite, got ({center_x_m}, {center_y_m})")
        self.center_x_m = float(center_x_m)
        self.center_y_m = float(center_y_m)
        self.bin_count = int(bin_count)
        self.ignition_time_s = ignition_time_s
        self.revisit_gap_s = float(revisit_gap_s)
        self.ros_baseline_s = float(ros_baseline_s)
        self.ros_baseline_cells = float(ros_baseline_cells)
        self.cell_size_m = float(cell_size_m)
        nan = np.full(self.bin_count, np.nan)
        self.outer_x_m = nan.copy()
        self.outer_y_m = nan.copy()
        self.outer_d_m = nan.copy()
        self.outer_t_s = nan.copy()
        self.inner_d_m = nan.copy()
        self.inner_t_s = nan.copy()
        self._ros_cache: tuple[bytes, np.ndarray] | None = None  # see ros_mps

    # --- geometry ------------------------------------------------------------------------
    def bin_of(self, x_m, y_m) -> np.ndarray:
        return angle_bin(x_m, y_m, self.center_x_m, self.center_y_m, self.bin_count)

    def bin_center_rad(self) -> np.ndarray:
        """Centre angle of every bin [rad]."""
        return (np.arange(self.bin_count) + 0.5) * (2 * np.pi / self.bin_count)

    @property
    def known(self) -> np.ndarray:
        """Bins that have an outer cell."""
        return ~np.isnan(self.outer_d_m)

    # --- updates -------------------------------------------------------------------------
    def record(
        self,
        x_m: np.ndarray,
        y_m: np.ndarray,
        t_s: float,
        link_m: float = 0.0,
        seen_unburned: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
    ) -> np.ndarray:
        """Record perimeter cells [m] seen at time ``t_s``; returns the bins touched.

        Per bin the farthest of the given cells is the candidate outer cell (PM IV-A); one
        nearer than the bin's outer cell is taken only where ``seen_unburned(x_m, y_m)`` (the
        same sighting's unburned cells, vectorised) says the outer cell's place is unburned.

        Deviation: far from the centre a bin is narrower than a cell, so the cells of one
        sighting skip bins, and a skipped bin would keep its stale cell from the last lap
        between fresh ones (a zig-zag perimeter). Bins between two recorded cells at most
        ``link_m`` apart (neighbouring perimeter cells; 0 disables this) are filled with the
        point where the bin's centre ray crosses the segment between the two cells.
        """
        x = np.asarray(x_m, dtype=float).ravel()
        y = np.asarray(y_m, dtype=float).ravel()
        if x.size == 0:
            return np.zeros(0, dtype=np.int64)
        d = np.hypot(x - self.center_x_m, y - self.center_y_m)
        b = self.bin_of(x, y)
        order = np.lexsort((d, b))  # by bin, then distance: the last of each bin is the farthest
        b_sorted = b[order]
        last = np.empty(b_sorted.size, dtype=bool)
        np.not_equal(b_sorted[1:], b_sorted[:-1], out=last[:-1])
        last[-1] = True
        sel = order[last]
        bins, xs, ys, ds = b[sel], x[sel], y[sel], d[sel]
        if link_m > 0 and bins.size >= 2:
            bins, xs, ys, ds = self._fill_skipped(bins, xs, ys, ds, link_m)
        self._visit(bins, xs, ys, ds, float(t_s), seen_unburned)
        return bins

    def _fill_skipped(self, bins, xs, ys, ds, link_m):
        """:meth:`record`'s fill of skipped bins; ``bins`` distinct and ascending."""
        nb = self.bin_count
        n = bins.size
        nxt = np.arange(1, n + 1)
        nxt[-1] = 0  # the next cell round the circle
        gap = (bins[nxt] - bins) % nb
        close = np.hypot(xs[nxt] - xs, ys[nxt] - ys) <= link_m
        ks = np.flatnonzero(close & (gap >= 2) & (gap <= nb // 4))
        if ks.size == 0:
            return bins, xs, ys, ds
        counts = gap[ks] - 1
        k = np.repeat(ks, counts)  # one row per bin to fill, in the order of the gaps
        step = np.arange(k.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1
        px, py = xs[k] - self.center_x_m, ys[k] - self.center_y_m
        ex, ey = xs[nxt[k]] - xs[k], ys[nxt[k]] - ys[k]
        fb = (bins[k] + step) % nb
        th = (fb + 0.5) * (2 * np.pi / nb)
        ux, uy = np.cos(th), np.sin(th)
        den = ux * ey - uy * ex
        with np.errstate(divide="ignore", invalid="ignore"):
            r = (px * ey - py * ex) / den
        present = np.zeros(nb, dtype=bool)
        present[bins] = True
        ok = np.isfinite(r) & (r > 0) & ~present[fb]  # a bin with a cell of its own keeps it
        ab, r, ux, uy = fb[ok], r[ok], ux[ok], uy[ok]
        # several crossings of one bin: the first in the order of the gaps (np.unique's index)
        by_bin = np.argsort(ab, kind="stable")
        ab = ab[by_bin]
        first = np.empty(ab.size, dtype=bool)
        first[:1] = True
        np.not_equal(ab[1:], ab[:-1], out=first[1:])
        ab, sel = ab[first], by_bin[first]
        ax, ay = self.center_x_m + r[sel] * ux[sel], self.center_y_m + r[sel] * uy[sel]
        ad = np.hypot(ax - self.center_x_m, ay - self.center_y_m)
        return (
            np.concatenate((bins, ab)),
            np.concatenate((xs, ax)),
            np.concatenate((ys, ay)),
            np.concatenate((ds, ad)),
        )

    def _visit(
        self,
        bins: np.ndarray,
        x: np.ndarray,
        y: np.ndarray,
        d: np.ndarray,
        t_s: float,
        seen_unburned: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
    ) -> None:
        """Visits of distinct ``bins`` at time ``t_s`` [s]."""
        prev_t = self.outer_t_s[bins]
        first = np.isnan(prev_t)
        # never inward without evidence (module docstring)
        inward = ~first & (d < self.outer_d_m[bins])
        cleared = np.zeros(bins.size, dtype=bool)
        if seen_unburned is not None and inward.any():
            cleared[inward] = np.asarray(
                seen_unburned(self.outer_x_m[bins[inward]], self.outer_y_m[bins[inward]]), dtype=bool
            )
        seen = ~inward | cleared
        same_visit = seen & ~first & (t_s >= prev_t) & (t_s - prev_t < self.revisit_gap_s)  # older: ignored
        new_visit = seen & ~first & ~same_visit & (t_s > prev_t)
        # Listing 2 (iii): the ignition point is the first inner cell.
        if first.any():
            fb = bins[first]
            self.inner_d_m[fb] = 0.0
            self.inner_t_s[fb] = np.nan if self.ignition_time_s is None else self.ignition_time_s
        # PM IV-A: a new visit turns the previous outer cell into the inner cell (if old enough).
        if new_visit.any():
            nv = new_visit & np.isnan(self.inner_t_s[bins])
            k = np.flatnonzero(new_visit & ~nv)
            if k.size:
                nv[k] = t_s - prev_t[k] >= self._baseline_s(bins[k])
            nb = bins[nv]
            self.inner_d_m[nb] = self.outer_d_m[nb]
            self.inner_t_s[nb] = self.outer_t_s[nb]
        # a bin moved inward on evidence: its Eq. 1 history is void
        moved = cleared & (same_visit | new_visit)
        if moved.any():
            cb = bins[moved]
            self.inner_d_m[cb] = d[moved]
            self.inner_t_s[cb] = np.nan
        upd = first | same_visit | new_visit
        ub = bins[upd]
        self.outer_x_m[ub] = x[upd]
        self.outer_y_m[ub] = y[upd]
        self.outer_d_m[ub] = d[upd]
        self.outer_t_s[ub] = t_s

    def _baseline_s(self, bins: np.ndarray) -> np.ndarray:
        """Eq. 1 baseline [s] per bin: ``max(ros_baseline_s, ros_baseline_cells * cell / ROS)``."""
        base = np.full(bins.size, self.ros_baseline_s)
        if self.ros_baseline_cells > 0:
            from .importance import rate_of_spread

            ros = rate_of_spread(  # ros_mps() of these bins only (elementwise: the same values)
                self.outer_d_m[bins], self.inner_d_m[bins], self.outer_t_s[bins], self.inner_t_s[bins]
            )
            with np.errstate(divide="ignore"):
                scaled = np.where(
                    ros > 0, self.ros_baseline_cells * self.cell_size_m / np.where(ros > 0, ros, 1.0), np.inf
                )
            base = np.where(np.isfinite(ros), np.maximum(base, scaled), base)
        return base

    def merge_outer(self, x_m: np.ndarray, y_m: np.ndarray, t_s: np.ndarray) -> int:
        """Merge a peer's outer cells [m] with their visit times [s]; returns bins taken.

        A peer cell is taken where it is newer than ours (then it is a visit by the peer,
        with the same inner-cell rules as :meth:`record`); cells are re-binned in our frame.
        A peer cell is a visit of its bin in time order (ties: in the order given): per bin the
        cells go in time order, each taken if newer than the bin's outer cell at that moment.
        The count includes taken cells that were not a visit (nearer than the outer cell: never
        inward without evidence, and a peer's cell is no evidence).
        """
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        t = np.asarray(t_s, dtype=float)
        ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(t)
        x, y, t = x[ok], y[ok], t[ok]
        if x.size == 0:
            return 0
        b = self.bin_of(x, y)
        d = np.hypot(x - self.center_x_m, y - self.center_y_m)
        # The outer time of a bin only grows, so a cell no newer than its bin's outer cell now is
        # never taken: drop those at once. What is left is a scan per bin in time order, which
        # each cell's outcome depends on (the bin's outer cell the previous one left): a short
        # loop of Python floats (the same IEEE operations as the arrays', so the same bits).
        ours = self.outer_t_s[b]
        keep = np.isnan(ours) | (t > ours)
        if not keep.any():
            return 0
        b, x, y, d, t = b[keep], x[keep], y[keep], d[keep], t[keep]
        order = np.lexsort((t, b))  # by bin, then time; stable: ties in the order given
        return self._merge_scan(
            b[order].tolist(), x[order].tolist(), y[order].tolist(), d[order].tolist(), t[order].tolist()
        )

    def _merge_scan(self, bl: list, xl: list, yl: list, dl: list, tl: list) -> int:
        """:meth:`merge_outer`'s per-bin scan over cells sorted by bin, then time; returns the
        cells taken. :meth:`_visit` for one cell at a time without ``seen_unburned``."""
        gap = self.revisit_gap_s
        base_s = self.ros_baseline_s
        cells = self.ros_baseline_cells
        scale = cells * self.cell_size_m  # Eq. 1 baseline: cells * cell / ROS, in _baseline_s's order
        ign = math.nan if self.ignition_time_s is None else float(self.ignition_time_s)
        oxa, oya, oda, ota, ida, ita = (
            self.outer_x_m,
            self.outer_y_m,
            self.outer_d_m,
            self.outer_t_s,
            self.inner_d_m,
            self.inner_t_s,
        )
        taken = 0
        n = len(bl)
        k = 0
        while k < n:
            kb = bl[k]
            ox, oy, od, ot, idd, it = (
                float(oxa[kb]),
                float(oya[kb]),
                float(oda[kb]),
                float(ota[kb]),
                float(ida[kb]),
                float(ita[kb]),
            )
            changed = False
            while k < n and bl[k] == kb:
                tk = tl[k]
                if ot == ot and not tk > ot:  # not newer than the outer cell (NaN: none yet)
                    k += 1
                    continue
                taken += 1
                if ot != ot:  # Listing 2 (iii): the ignition point is the first inner cell
                    idd, it = 0.0, ign
                elif dl[k] < od:  # never inward without evidence
                    k += 1
                    continue
                elif tk - ot >= gap:  # a new visit (else the same visit: only the outer cell moves)
                    if it != it:
                        idd, it = od, ot
                    else:
                        base = base_s
                        if cells > 0:  # _baseline_s over Eq. 1's ROS (rate_of_spread), per bin
                            dt = ot - it
                            ros = (od - idd) / dt if dt > 0 else math.nan
                            if ros == ros:
                                ros = max(ros, 0.0)  # a negative ROS is clipped to 0
                                if math.isfinite(ros):  # a ROS of 0: no baseline is long enough
                                    base = max(base, scale / ros if ros > 0 else math.inf)
                        if tk - ot >= base:  # PM IV-A: the previous outer cell becomes the inner one
                            idd, it = od, ot
                ox, oy, od, ot = xl[k], yl[k], dl[k], tk
                changed = True
                k += 1
            if changed:
                oxa[kb], oya[kb], oda[kb], ota[kb], ida[kb], ita[kb] = ox, oy, od, ot, idd, it
        return taken

    def set_center(self, center_x_m: float, center_y_m: float, cells) -> None:
        """Re-centre the map and rebuild it from raw perimeter sightings ``(x_m, y_m, t_s)``.

        Used when the ignition point is unknown (PM IV-A: the fire centre is computed after
        the initial lap). Sightings are replayed in time order.
        """
        self.__init__(  # type: ignore[misc]
            center_x_m,
            center_y_m,
            bin_count=self.bin_count,
            ignition_time_s=self.ignition_time_s,
            revisit_gap_s=self.revisit_gap_s,
            ros_baseline_s=self.ros_baseline_s,
            ros_baseline_cells=self.ros_baseline_cells,
            cell_size_m=self.cell_size_m,
        )
        arr = np.asarray(cells, dtype=float).reshape(-1, 3)
        if arr.shape[0] == 0:
            return
        for t in np.unique(arr[:, 2]):
            sel = arr[:, 2] == t
            self.record(arr[sel, 0], arr[sel, 1], float(t))

    # --- derived per-bin quantities ------------------------------------------------------
    def ros_mps(self) -> np.ndarray:
        """Rate of spread per bin [m/s] (PM Eq. 1), NaN where unknown.

        A monitor's step reads it several times between two changes of the map (planning, its
        front, its summary): the last result is kept with the bytes of the four arrays it was
        computed from (a pure function of them, so a write to the arrays from anywhere is seen),
        and a copy returned.
        """
        from .importance import rate_of_spread

        key = (
            self.outer_d_m.tobytes()
            + self.inner_d_m.tobytes()
            + self.outer_t_s.tobytes()
            + self.inner_t_s.tobytes()
        )
        cached = getattr(self, "_ros_cache", None)
        if cached is None or cached[0] != key:
            cached = (key, rate_of_spread(self.outer_d_m, self.inner_d_m, self.outer_t_s, self.inner_t_s))
            self._ros_cache = cached
        return cached[1].copy()

    def filled(self, values: np.ndarray, default: float = 0.0) -> np.ndarray:
        """Per-bin values with NaNs filled by circular linear interpolation over the bins."""
        return circular_fill(values, default)


def circular_fill(values: np.ndarray, default: float = 0.0) -> np.ndarray:
    """Fill NaNs of a circular per-bin array by linear interpolation between known bins."""
    v = np.asarray(values, dtype=float)
    ok = ~np.isnan(v)
    if not ok.any():
        return np.full_like(v, default)
    if ok.all():
        return v.copy()
    n = v.size
    k = np.flatnonzero(ok)
    xp = np.concatenate([k - n, k, k + n])
    fp = np.concatenate([v[k], v[k], v[k]])
    return np.interp(np.arange(n), xp, fp)
