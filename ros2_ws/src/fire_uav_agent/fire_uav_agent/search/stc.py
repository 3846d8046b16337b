"""Spanning-tree coverage (Gabriely and Rimon) of one region, with turn arcs (CP III-C).

Geometry, units [m; map frame]:

* The region is a 4-connected set of coarse cells of edge ``Delta`` (the :class:`CoverageGrid`).
  Each coarse cell holds 2 x 2 sub-cells of edge ``Delta/2`` = the sensor swath (CP II-A).
* A depth-first spanning tree over the 4-neighbour graph of the coarse cells is rooted at
  ``p_root = argmin (p_y, p_x)`` (CP III-C: rows bottom-to-top, then columns left-to-right).
  Choice: neighbours are explored in the order east, north, west, south (the paper only says
  "depth first").
* The tour circumnavigates the tree counterclockwise (tree on the left) through the sub-cell centres,
  i.e. offset by ``Delta/4`` from the coarse-cell centres, visiting every sub-cell exactly once.
* Every corner is replaced by a circular arc of radius ``turn_radius_m`` (CP III-C uses ``Delta/4``;
  a smaller radius is allowed as long as it is at least the vehicle's minimum turn radius). The path is
  C^1 and closed; a fixed-wing flies it at constant speed without stopping.
* Arc length 0 is where the tour leaves the corner at the bottom-left sub-cell of the root cell
  heading east; a start offset ``s in [0, 1)`` (CP III-C "offset ... in a counterclockwise
  direction") moves the start ``s * L`` further along the tour.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import PathError, SearchConfigError

SEG_LINE = 0
SEG_ARC = 1

# neighbour order of the depth-first search: east, north, west, south (d_iy, d_ix)
_DFS_ORDER = ((0, 1), (1, 0), (0, -1), (-1, 0))


def spanning_tree(
    region: np.ndarray,
) -> tuple[tuple[int, int], list[tuple[tuple[int, int], tuple[int, int]]]]:
    """Depth-first spanning tree of a 4-connected region (bool (ny, nx)).

    Returns ``(root, edges)`` with cells as ``(iy, ix)``; root per CP III-C. Raises
    :class:`PathError` for an empty or disconnected region.
    """
    cells = np.argwhere(region)
    if len(cells) == 0:
        raise PathError("region is empty")
    root = (int(cells[0][0]), int(cells[0][1]))  # argwhere is row-major: min iy, then min ix
    ny, nx = region.shape
    seen = {root}
    edges: list[tuple[tuple[int, int], tuple[int, int]]] = []
    stack = [(root, 0)]
    while stack:
        cell, k = stack[-1]
        if k >= len(_DFS_ORDER):
            stack.pop()
            continue
        stack[-1] = (cell, k + 1)
        dy, dx = _DFS_ORDER[k]
        nb = (cell[0] + dy, cell[1] + dx)
        if 0 <= nb[0] < ny and 0 <= nb[1] < nx and region[nb] and nb not in seen:
            seen.add(nb)
            edges.append((cell, nb))
            stack.append((nb, 0))
    if len(seen) != len(cells):
        raise PathError(f"region is not 4-connected ({len(seen)} of {len(cells)} cells reachable)")
    return root, edges


def stc_subcell_tour(region: np.ndarray) -> np.ndarray:
    """Closed STC tour over the sub-cells, shape (4 * n_cells, 2) as (sy, sx) sub-cell indices.

    Starts at the bottom-left sub-cell of the root. Within a coarse cell the default moves go
    counterclockwise BL -> BR -> TR -> TL -> BL; a tree edge to the east neighbour reroutes
    BR(c) -> BL(e) and TL(e) -> TR(c), a tree edge to the north neighbour reroutes
    TR(c) -> BR(n) and BL(n) -> TL(c). The result is one Hamiltonian cycle around the tree.
    """
    root, edges = spanning_tree(region)
    nxt: dict[tuple[int, int], tuple[int, int]] = {}
    for iy, ix in np.argwhere(region):
        by, bx = 2 * int(iy), 2 * int(ix)
        nxt[(by, bx)] = (by, bx + 1)  # BL -> BR
        nxt[(by, bx + 1)] = (by + 1, bx + 1)  # BR -> TR
        nxt[(by + 1, bx + 1)] = (by + 1, bx)  # TR -> TL
        nxt[(by + 1, bx)] = (by, bx)  # TL -> BL
    for a, b in edges:
        (ay, ax), (by_, bx_) = (a, b) if (a[0], a[1]) < (b[0], b[1]) else (b, a)
        cy, cx, dy, dx = 2 * ay, 2 * ax, 2 * by_, 2 * bx_
        if by_ == ay:  # east edge: a west of b
            nxt[(cy, cx + 1)] = (dy, dx)  # BR(c) -> BL(e)
            nxt[(dy + 1, dx)] = (cy + 1, cx + 1)  # TL(e) -> TR(c)
        else:  # north edge: a south of b
            nxt[(cy + 1, cx + 1)] = (dy, dx + 1)  # TR(c) -> BR(n)
            nxt[(dy, dx)] = (cy + 1, cx)  # BL(n) -> TL(c)
    start = (2 * root[0], 2 * root[1])
    tour = [start]
    cur = nxt[start]
    while cur != start:
        tour.append(cur)
        cur = nxt[cur]
        if len(tour) > len(nxt):
            raise PathError("sub-cell successor map is not a single cycle")  # pragma: no cover
    if len(tour) != len(nxt):
        raise PathError("STC tour does not visit every sub-cell")  # pragma: no cover
    return np.array(tour, dtype=int)


@dataclass(frozen=True)
class CoveragePath:
    """A closed C^1 path of straight segments and circular arcs [m; map frame].

    Segment ``k``: ``kind[k]`` is SEG_LINE (from ``p0_m[k]`` to ``p1_m[k]``) or SEG_ARC (centre
    ``center_m[k]``, radius ``radius_m[k]``, starting at angle ``theta0_rad[k]``, signed sweep
    ``sweep_rad[k]``, + = counterclockwise). ``cum_m`` (S+1,) are cumulative arc lengths.
    """

    kind: np.ndarray = field(repr=False)
    p0_m: np.ndarray = field(repr=False)
    p1_m: np.ndarray = field(repr=False)
    center_m: np.ndarray = field(repr=False)
    radius_m: np.ndarray = field(repr=False)
    theta0_rad: np.ndarray = field(repr=False)
    sweep_rad: np.ndarray = field(repr=False)
    seg_length_m: np.ndarray = field(repr=False)
    cum_m: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        for name in ("kind", "p0_m", "p1_m", "center_m", "radius_m", "theta0_rad", "sweep_rad"):
            getattr(self, name).setflags(write=False)

    @property
    def length_m(self) -> float:
        return float(self.cum_m[-1])

    @property
    def turn_length_m(self) -> float:
        return float(self.seg_length_m[self.kind == SEG_ARC].sum())

    @property
    def straight_length_m(self) -> float:
        return float(self.seg_length_m[self.kind == SEG_LINE].sum())

    @property
    def n_turns(self) -> int:
        return int(np.count_nonzero(self.kind == SEG_ARC))

    @property
    def min_turn_radius_m(self) -> float:
        """Smallest arc radius [m] (inf for a path without turns)."""
        arcs = self.radius_m[self.kind == SEG_ARC]
        return float(arcs.min()) if arcs.size else math.inf

    def _locate(self, s_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        s = np.mod(np.asarray(s_m, dtype=float), self.length_m)
        k = np.clip(np.searchsorted(self.cum_m, s, side="right") - 1, 0, len(self.kind) - 1)
        return k, s - self.cum_m[k]

    def positions_at(self, s_m: np.ndarray) -> np.ndarray:
        """Positions at arc lengths ``s_m`` (wrapped modulo the length), shape (..., 2) [m]."""
        k, u = self._locate(s_m)
        line = self.kind[k] == SEG_LINE
        t = np.where(line, u / np.maximum(self.seg_length_m[k], 1e-12), 0.0)[..., None]
        p_line = self.p0_m[k] + t * (self.p1_m[k] - self.p0_m[k])
        ang = self.theta0_rad[k] + np.sign(self.sweep_rad[k]) * u / np.maximum(self.radius_m[k], 1e-12)
        p_arc = self.center_m[k] + self.radius_m[k][..., None] * np.stack([np.cos(ang), np.sin(ang)], -1)
        return np.where(line[..., None], p_line, p_arc)

    def is_turn_at(self, s_m: np.ndarray) -> np.ndarray:
        """True where the arc length falls on a turn arc."""
        k, _ = self._locate(s_m)
        return self.kind[k] == SEG_ARC

    def headings_at(self, s_m: np.ndarray) -> np.ndarray:
        """Heading [rad, ccw from +x] at arc lengths ``s_m``."""
        k, u = self._locate(s_m)
        d = self.p1_m[k] - self.p0_m[k]
        h_line = np.arctan2(d[..., 1], d[..., 0])
        sgn = np.sign(self.sweep_rad[k])
        ang = self.theta0_rad[k] + sgn * u / np.maximum(self.radius_m[k], 1e-12)
        h_arc = ang + sgn * (math.pi / 2)
        h = np.where(self.kind[k] == SEG_LINE, h_line, h_arc)
        return np.mod(h + math.pi, 2 * math.pi) - math.pi

    def sample(self, spacing_m: float, start_fraction: float = 0.0) -> PathSamples:
        """Samples every ``spacing_m`` along one lap, starting ``start_fraction * L`` along the tour."""
        if not spacing_m > 0.0:
            raise SearchConfigError(f"spacing_m must be > 0, got {spacing_m}")
        if not 0.0 <= start_fraction < 1.0:
            raise SearchConfigError(f"start_fraction must be in [0, 1), got {start_fraction}")
        n = max(1, math.ceil(self.length_m / spacing_m))
        ds = self.length_m / n
        s = start_fraction * self.length_m + ds * np.arange(n)
        return PathSamples(self.positions_at(s), self.is_turn_at(s), ds)


@dataclass(frozen=True)
class PathSamples:
    """Equally spaced samples of one lap of a path (in flight order)."""

    pos_m: np.ndarray  # (K, 2) [m; map frame]
    is_turn: np.ndarray  # (K,) bool, the sample lies on a turn arc
    spacing_m: float  # arc length between consecutive samples [m]


def _fillet_path(corners_m: np.ndarray, radius_m: float) -> CoveragePath:
    """Closed polygon (M, 2) with every corner replaced by an arc of ``radius_m``."""
    m = len(corners_m)
    kinds, p0s, p1s, cens, rads, th0s, sws, lens = [], [], [], [], [], [], [], []
    arcs = []
    for i in range(m):
        a, c, b = corners_m[i - 1], corners_m[i], corners_m[(i + 1) % m]
        u_in = (c - a) / np.linalg.norm(c - a)
        u_out = (b - c) / np.linalg.norm(b - c)
        cross = u_in[0] * u_out[1] - u_in[1] * u_out[0]
        theta = math.atan2(cross, float(u_in @ u_out))  # signed turn angle
        tan_len = radius_m * math.tan(abs(theta) / 2)
        t_in = c - tan_len * u_in
        t_out = c + tan_len * u_out
        left = np.array([-u_in[1], u_in[0]])
        centre = t_in + (left if theta > 0 else -left) * radius_m
        th0 = math.atan2(t_in[1] - centre[1], t_in[0] - centre[0])
        arcs.append((t_in, t_out, centre, th0, theta, tan_len))
    # check fit: tangent lengths on each side of every side must not overlap
    for i in range(m):
        side = float(np.linalg.norm(corners_m[(i + 1) % m] - corners_m[i]))
        if arcs[i][5] + arcs[(i + 1) % m][5] > side + 1e-9:
            raise PathError(
                f"turn radius {radius_m:.3f} m does not fit a side of {side:.3f} m; "
                "use turn_radius_m <= cell_size_m / 4"
            )
    # start: leaving the arc at corner 0; segments: line to corner 1's arc, arc 1, ..., arc 0
    for j in range(1, m + 1):
        i = j % m
        t_in, t_out, centre, th0, theta, _ = arcs[i]
        prev_out = arcs[j - 1][1]
        seg = float(np.linalg.norm(t_in - prev_out))
        if seg > 1e-9:
            kinds.append(SEG_LINE)
            p0s.append(prev_out)
            p1s.append(t_in)
            cens.append(np.zeros(2))
            rads.append(0.0)
            th0s.append(0.0)
            sws.append(0.0)
            lens.append(seg)
        if abs(theta) > 1e-12:
            kinds.append(SEG_ARC)
            p0s.append(t_in)
            p1s.append(t_out)
            cens.append(centre)
            rads.append(radius_m)
            th0s.append(th0)
            sws.append(theta)
            lens.append(radius_m * abs(theta))
    lens_a = np.array(lens)
    return CoveragePath(
        kind=np.array(kinds, dtype=np.int8),
        p0_m=np.array(p0s),
        p1_m=np.array(p1s),
        center_m=np.array(cens),
        radius_m=np.array(rads),
        theta0_rad=np.array(th0s),
        sweep_rad=np.array(sws),
        seg_length_m=lens_a,
        cum_m=np.concatenate([[0.0], np.cumsum(lens_a)]),
    )


def stc_path(
    region: np.ndarray,
    *,
    x_min_m: float,
    y_min_m: float,
    cell_size_m: float,
    turn_radius_m: float | None = None,
) -> CoveragePath:
    """Closed STC coverage path of a region (bool (ny, nx) over the coarse grid).

    ``turn_radius_m`` defaults to ``cell_size_m / 4`` (CP III-C) and must be in
    ``(0, cell_size_m / 4]``: a larger arc does not fit between two corners one sub-cell apart.
    """
    if not cell_size_m > 0.0:
        raise SearchConfigError(f"cell_size_m must be > 0, got {cell_size_m}")
    r = cell_size_m / 4 if turn_radius_m is None else float(turn_radius_m)
    if not 0.0 < r <= cell_size_m / 4 + 1e-9:
        raise PathError(
            f"turn_radius_m must be in (0, cell_size_m/4 = {cell_size_m / 4:.3f}] m, got {r}; "
            "increase the cell size for a vehicle with a larger minimum turn radius"
        )
    tour = stc_subcell_tour(np.asarray(region, dtype=bool))
    half = cell_size_m / 2
    pts = np.stack([x_min_m + (tour[:, 1] + 0.5) * half, y_min_m + (tour[:, 0] + 0.5) * half], axis=1)
    # keep only the corners (where the direction changes)
    d_in = pts - np.roll(pts, 1, axis=0)
    d_out = np.roll(pts, -1, axis=0) - pts
    corner = np.abs(d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]) > 1e-9
    corners = pts[corner]
    # rotate so corner 0 is the start sub-cell (BL of root, always a corner: down then east)
    start_idx = int(np.nonzero(corner)[0][0])
    if start_idx != 0:  # pragma: no cover - the root BL sub-cell is always a corner
        raise PathError("root sub-cell is not a corner")
    return _fillet_path(corners, r)


def loiter_path(center_m: np.ndarray, radius_m: float) -> CoveragePath:
    """A full counterclockwise circle (for an agent whose region is empty: a fixed-wing cannot stop)."""
    c = np.asarray(center_m, dtype=float)
    length = 2 * math.pi * radius_m
    start = c + np.array([0.0, -radius_m])
    return CoveragePath(
        kind=np.array([SEG_ARC], dtype=np.int8),
        p0_m=start[None, :],
        p1_m=start[None, :],
        center_m=c[None, :],
        radius_m=np.array([float(radius_m)]),
        theta0_rad=np.array([-math.pi / 2]),
        sweep_rad=np.array([2 * math.pi]),
        seg_length_m=np.array([length]),
        cum_m=np.array([0.0, length]),
    )
