"""Fire-shape construction by the scan method (PM IV-B), convex hull and distance error (PM VI-E).

Frame: map frame, metres; angles CCW from +x about the fire map's centre.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .fire_map import Direction, FireMap, direction_sign

__all__ = [
    "ConstructedPerimeter",
    "construct_perimeter",
    "convex_hull",
    "max_distance_error",
    "perimeter_cells_hull",
    "polygon_radial_extent",
    "resample_closed",
]


class ConstructedPerimeter(NamedTuple):
    """The on-board perimeter closed at the UAV (PM IV-B, Fig. 5)."""

    vertices_m: np.ndarray  # (k, 2) closed polygon, vertex 0 = UAV, ordered in the flying direction
    anchor_bin: int  # bin the straight closing line starts from (-1: the UAV itself)
    best_bin: int  # bin of the scan's best cell (-1: no closing line was needed)
    replaced_bins: np.ndarray  # bins whose stale cells the closing line replaced


def construct_perimeter(
    fmap: FireMap,
    uav_x_m: float,
    uav_y_m: float,
    direction: Direction,
    t_s: float,
    *,
    fresh_s: float | None = None,
    angle_tol_rad: float = 0.02,
) -> ConstructedPerimeter:
    """Close the on-board perimeter at the UAV with the scan method (PM IV-B).

    Known outer cells are taken in the flying direction from the UAV's bin. Ahead of the UAV
    the map holds cells of the previous lap, inside today's fire. The scan starts at the first
    of those stale cells and goes on, in the flying direction, while the bearing from the
    anchor to the cell keeps turning the same way (by more than ``-angle_tol_rad``, for raster
    noise); the best cell is the extreme one, i.e. the tangent point under the paper's
    convexity assumption, and the stale cells between the anchor and the best cell are
    replaced by the straight line (Fig. 5b).

    Deviation: the paper's UAV records only the cell under it, so the scan starts at the UAV.
    Our UAV sees a footprint, so cells just ahead may be fresh (seen within ``fresh_s``,
    default the map's revisit gap); the anchor of the closing line is then the last fresh
    cell ahead rather than the UAV. The scan is limited to half a turn ahead.
    """
    if fresh_s is None:
        fresh_s = fmap.revisit_gap_s
    nb = fmap.bin_count
    sign = direction_sign(direction)
    bu = int(fmap.bin_of(uav_x_m, uav_y_m))
    uav = np.array([[uav_x_m, uav_y_m]], dtype=float)
    steps = np.arange(1, nb)
    order = (bu + sign * steps) % nb
    known = fmap.known[order]
    seq = order[known]
    seq_steps = steps[known]
    if seq.size == 0:
        return ConstructedPerimeter(uav, -1, -1, np.zeros(0, dtype=np.int64))
    pts = np.column_stack([fmap.outer_x_m[seq], fmap.outer_y_m[seq]])
    fresh = fmap.outer_t_s[seq] >= t_s - fresh_s
    n_fresh = int(np.argmin(fresh)) if not fresh.all() else seq.size
    if n_fresh == seq.size:
        return ConstructedPerimeter(np.vstack([uav, pts]), -1, -1, np.zeros(0, dtype=np.int64))
    anchor = pts[n_fresh - 1] if n_fresh > 0 else uav[0]
    anchor_bin = int(seq[n_fresh - 1]) if n_fresh > 0 else -1
    cand = np.flatnonzero((np.arange(seq.size) >= n_fresh) & (seq_steps <= nb // 2))
    if cand.size == 0:
        return ConstructedPerimeter(np.vstack([uav, pts]), anchor_bin, -1, np.zeros(0, dtype=np.int64))
    vec = pts[cand] - anchor
    bearing = np.unwrap(np.arctan2(vec[:, 1], vec[:, 0]))
    # CCW flight: the view of the stale perimeter ahead turns clockwise up to the tangent point.
    s = (-sign * bearing).tolist()  # Python floats: the same values, without numpy scalars in the loop
    best = 0
    run_max = s[0]
    for k in range(1, len(s)):
        if s[k] < s[k - 1] - angle_tol_rad:
            break
        if s[k] >= run_max:
            run_max = s[k]
            best = k
    best_idx = int(cand[best])
    replaced = seq[n_fresh:best_idx]
    keep = np.ones(seq.size, dtype=bool)
    keep[n_fresh:best_idx] = False
    return ConstructedPerimeter(np.vstack([uav, pts[keep]]), anchor_bin, int(seq[best_idx]), replaced)


def resample_closed(vertices_m: np.ndarray, spacing_m: float) -> tuple[np.ndarray, float]:
    """Points every ~``spacing_m`` along a closed polygon from vertex 0; returns (points, spacing).

    The count is ``max(2, round(L / spacing_m))`` (even counts are not forced) and the actual
    spacing is ``L / count``, so that the points tile the loop exactly.
    """
    v = np.asarray(vertices_m, dtype=float)
    if v.shape[0] < 2:
        return v.copy(), float(spacing_m)
    closed = np.vstack([v, v[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    length = float(cum[-1])
    if length <= 0:
        return v[:1].copy(), float(spacing_m)
    m = max(2, int(round(length / spacing_m)))
    s = np.arange(m) * (length / m)
    x = np.interp(s, cum, closed[:, 0])
    y = np.interp(s, cum, closed[:, 1])
    return np.column_stack([x, y]), length / m


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points, CCW, no repeated first vertex (Andrew's monotone chain)."""
    p = np.unique(np.asarray(points, dtype=float).reshape(-1, 2), axis=0)
    if p.shape[0] < 3:
        return p
    pts = [(float(a), float(b)) for a, b in p]

    def half(seq: list) -> list:
        out: list = []
        for qx, qy in seq:
            while len(out) >= 2:
                (ox, oy), (ax, ay) = out[-2], out[-1]
                if (ax - ox) * (qy - oy) - (ay - oy) * (qx - ox) > 0:
                    break
                out.pop()
            out.append((qx, qy))
        return out

    lower = half(pts)
    upper = half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def perimeter_cells_hull(fmap: FireMap, cell_size_m: float) -> np.ndarray:
    """Convex hull of the on-board perimeter cells (PM VI-E): the squares of the outer cells.

    Corners rather than centres, so that a fully known convex fire gives a near-zero error.
    """
    k = fmap.known
    centres = convex_hull(np.column_stack([fmap.outer_x_m[k], fmap.outer_y_m[k]]))
    if centres.shape[0] == 0:
        return centres
    cx, cy = centres[:, 0], centres[:, 1]  # the corners' hull is that of the centres' hull's corners
    h = cell_size_m / 2
    corners = np.concatenate(
        [np.column_stack([cx + dx, cy + dy]) for dx in (-h, h) for dy in (-h, h)], axis=0
    )
    return convex_hull(corners)


def polygon_radial_extent(
    polygon_m: np.ndarray, center_x_m: float, center_y_m: float, bin_count: int = 360
) -> np.ndarray:
    """Farthest distance [m] of a closed polygon along rays from the centre at bin-centre angles.

    NaN where a ray misses the polygon (fewer than 3 vertices, or the centre outside and the
    ray pointing away).
    """
    poly = np.asarray(polygon_m, dtype=float).reshape(-1, 2)
    if poly.shape[0] < 3:
        return np.full(bin_count, np.nan)
    th = (np.arange(bin_count) + 0.5) * (2 * np.pi / bin_count)
    u = np.column_stack([np.cos(th), np.sin(th)])  # (B, 2)
    p = poly - [center_x_m, center_y_m]
    q = np.roll(p, -1, axis=0)
    e = q - p  # (E, 2)
    den = u[:, None, 0] * e[None, :, 1] - u[:, None, 1] * e[None, :, 0]  # cross(u, e)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = (p[None, :, 0] * e[None, :, 1] - p[None, :, 1] * e[None, :, 0]) / den  # cross(p, e)/cross(u, e)
        s = (p[None, :, 0] * u[:, None, 1] - p[None, :, 1] * u[:, None, 0]) / den  # cross(p, u)/cross(u, e)
    ok = (np.abs(den) > 1e-12) & (s >= -1e-9) & (s <= 1 + 1e-9) & (r >= 0)
    r = np.where(ok, r, -np.inf)
    out = r.max(axis=1)
    return np.where(np.isfinite(out), out, np.nan)


def max_distance_error(true_extent_m: np.ndarray, estimated_extent_m: np.ndarray) -> float:
    """PM VI-E: the largest |true - constructed| radial distance over the angles [m].

    An angle where the constructed shape is unknown counts the whole true extent as error.
    """
    t = np.asarray(true_extent_m, dtype=float)
    e = np.asarray(estimated_extent_m, dtype=float)
    e = np.where(np.isnan(e), 0.0, e)
    ok = ~np.isnan(t)
    if not ok.any():
        return float("nan")
    return float(np.max(np.abs(t[ok] - e[ok])))
