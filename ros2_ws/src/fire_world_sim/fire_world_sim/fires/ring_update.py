"""The raster fire's arrival-time update (:mod:`.raster`, its update (2)) over the 8- and 16-
neighbour rings, as pure numpy functions of flat (raveled, padded) arrays.

:class:`RingGeometry` holds the node offsets of the rings and their vectors to the target cell;
:func:`arrival` is the update's minimum over single nodes and ring segments for a batch of target
cells. :func:`blocked_nodes` marks, per target cell, the ring nodes whose straight path to it
crosses a non-burnable cell. No ROS, no state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RING", "SEGMENTS", "RingGeometry", "arrival", "blocked_nodes", "crossed_cells"]


def _unique(a: np.ndarray, mark: np.ndarray | None = None) -> np.ndarray:
    """Sorted distinct values of ``a`` (as ``np.unique``, whose hashing costs more on the
    update's few thousand indices). Given ``mark``, an all-False bool array longer than any
    value, a large ``a`` is marked and read back in order instead of sorted (linear time); ``mark``
    is left all False."""
    if mark is not None and a.size * 16 > mark.size:
        mark[a] = True
        out = np.flatnonzero(mark)
        mark[out] = False
        return out
    a = np.sort(a)
    keep = np.empty(a.size, dtype=bool)
    keep[:1] = True
    np.not_equal(a[1:], a[:-1], out=keep[1:])
    return a[keep]


def _ring(r: int) -> list[tuple[int, int]]:
    """Offsets (di rows = north, dj cols = east) at Chebyshev distance r, ordered by angle."""
    offs = [(di, dj) for di in range(-r, r + 1) for dj in range(-r, r + 1) if max(abs(di), abs(dj)) == r]
    return sorted(offs, key=lambda o: math.atan2(o[0], o[1]))


#: node offsets of the update (2): the 8- and the 16-neighbour ring, each ordered by angle
RING = tuple(_ring(1) + _ring(2))
#: segments (index pairs into RING) of consecutive nodes of each ring
SEGMENTS = tuple((i, (i + 1) % 8) for i in range(8)) + tuple((8 + i, 8 + (i + 1) % 16) for i in range(16))


def crossed_cells(
    di: int, dj: int
) -> tuple[list[tuple[int, int]], list[tuple[tuple[int, int], tuple[int, int]]]]:
    """The cells the straight path from the cell centre at offset (di, dj) to (0, 0) runs
    through (their interior, end cells left out), and the pairs of cells it squeezes between where
    it passes exactly through a cell corner (the two cells beside the corner, off the path).

    Exact for these small integer offsets: the path crosses a row boundary at i = k + 1/2 and a
    column boundary at j = k + 1/2; between consecutive crossings it is inside one cell, and where a
    row and a column crossing coincide it passes through a corner."""
    ts = {0.0, 1.0}
    for n in (di, dj):
        if n:
            ts |= {(k + 0.5) / abs(n) for k in range(abs(n))}
    ts_sorted = sorted(ts)
    cells: list[tuple[int, int]] = []
    for a, b in zip(ts_sorted[:-1], ts_sorted[1:], strict=True):
        m = 0.5 * (a + b)
        c = (round(di * (1 - m)), round(dj * (1 - m)))
        if c not in ((di, dj), (0, 0)) and c not in cells:
            cells.append(c)
    corners = []
    si, sj = (di > 0) - (di < 0), (dj > 0) - (dj < 0)
    for t in ts_sorted[1:-1]:
        pi, pj = di * (1 - t), dj * (1 - t)
        if si and sj and abs(pi - round(pi - 0.5) - 0.5) < 1e-12 and abs(pj - round(pj - 0.5) - 0.5) < 1e-12:
            # on the way from the node toward the target the path goes -si, -sj: the corner's two
            # side cells are the one ahead in rows only and the one ahead in columns only
            ahead_i, ahead_j = round(pi - 0.5 * si), round(pj - 0.5 * sj)
            behind_i, behind_j = round(pi + 0.5 * si), round(pj + 0.5 * sj)
            corners.append(((ahead_i, behind_j), (behind_i, ahead_j)))
    return cells, corners


def blocked_nodes(nonburn: np.ndarray) -> np.ndarray:
    """Per cell of the padded grid ``nonburn`` (True: never burns: a non-burnable fuel, water,
    outside the data), a bit mask of the ring nodes (bit k: ``RING[k]``) whose straight path to
    the cell crosses a non-burnable cell or squeezes between two at a corner (uint32; the
    grid's outer two rows and columns are left 0, the padding has no targets).

    Without it, the 16-neighbour ring lets fire jump a one-cell barrier (a road or a stream 30 m
    wide), which a fire spreading cell to cell across the barrier cannot: minimum-travel-time
    spread (Finney 2002) sums the travel time through every cell a path crosses, so a non-burnable
    cell on the path stops it, and the level-set spread of pyretechnics and FARSITE's barriers
    stop it too."""
    ny, nx = nonburn.shape
    out = np.zeros((ny, nx), dtype=np.uint32)
    inner = (slice(2, ny - 2), slice(2, nx - 2))

    def at(oi: int, oj: int) -> np.ndarray:
        return nonburn[2 + oi : ny - 2 + oi, 2 + oj : nx - 2 + oj]

    for k, (di, dj) in enumerate(RING):
        cells, corners = crossed_cells(di, dj)
        hit = np.zeros((ny - 4, nx - 4), dtype=bool)
        for oi, oj in cells:
            hit |= at(oi, oj)
        for (ai, aj), (bi, bj) in corners:
            hit |= at(ai, aj) & at(bi, bj)
        out[inner] |= hit.astype(np.uint32) << np.uint32(k)
    return out


@dataclass(frozen=True)
class RingGeometry:
    """Flat offsets of the ring nodes in a padded grid ``width`` cells wide, the vectors node ->
    target [m] (east vx, north vy) and, per segment s1 -> s2, its direction d = v2 - v1 with the
    closed-form minimiser's constants (|d|, v1 . d^, |v1 x d^|)."""

    ring_flat: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    vn: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    dn: np.ndarray
    p_par: np.ndarray
    p_perp: np.ndarray

    @classmethod
    def of(cls, width: int, cell_m: float) -> RingGeometry:
        offs = np.array(RING)
        vx = -offs[:, 1] * cell_m  # east
        vy = -offs[:, 0] * cell_m  # north
        seg = np.array(SEGMENTS)
        s1, s2 = seg[:, 0], seg[:, 1]
        dx = vx[s2] - vx[s1]
        dy = vy[s2] - vy[s1]
        dn = np.hypot(dx, dy)
        return cls(
            ring_flat=offs[:, 0] * width + offs[:, 1],
            vx=vx,
            vy=vy,
            vn=np.hypot(vx, vy),
            s1=s1,
            s2=s2,
            dx=dx,
            dy=dy,
            dn=dn,
            p_par=(vx[s1] * dx + vy[s1] * dy) / dn,  # v1 . d^
            p_perp=np.abs(vx[s1] * dy - vy[s1] * dx) / dn,  # |v1 x d^|
        )


def arrival(
    geom: RingGeometry,
    tgt: np.ndarray,
    src: np.ndarray,
    t1: float,
    t_ign: np.ndarray,
    extinguished: np.ndarray,
    label: np.ndarray,
    a_spm: np.ndarray,
    cx_spm: np.ndarray,
    cy_spm: np.ndarray,
    blocked: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Arrival time (2) [s] and fire id of the flat target cells ``tgt`` from their ring nodes
    (every ignited node ignited at or before ``t1``; ``src`` marks the burning ones). The flat
    arrays: ignition times [s], extinguished, fire ids, and the wavelet (1) tau(v) = A |v| - Cx vx
    - Cy vy [s/m] of each cell; ``blocked`` (:func:`blocked_nodes`, flat): nodes whose path to the
    target crosses a non-burnable cell count as not ignited (nor as segment end points)."""
    nodes = tgt[:, None] + geom.ring_flat[None, :]  # (n, 24)
    t_node = t_ign[nodes]
    valid = (t_node <= t1) & ~extinguished[nodes]
    if blocked is not None:
        valid &= ((blocked[tgt][:, None] >> np.arange(len(RING), dtype=np.uint32)[None, :]) & 1) == 0
    t_node = np.where(valid, t_node, np.inf)
    burning = src[nodes]
    a = a_spm[tgt][:, None]
    cx = cx_spm[tgt][:, None]
    cy = cy_spm[tgt][:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        # single-node Huygens updates (segment end points)
        single = t_node + a * geom.vn - cx * geom.vx - cy * geom.vy
        single = np.where(burning, single, np.inf)
        # segments: f(l) = T1 + l (T2 - T1) + A |v1 + l d| - C . (v1 + l d)
        s1, s2 = geom.s1, geom.s2
        t1n, t2n = t_node[:, s1], t_node[:, s2]
        ok = np.isfinite(t1n) & np.isfinite(t2n) & (burning[:, s1] | burning[:, s2]) & np.isfinite(a)
        k = (t2n - t1n) - (cx * geom.dx + cy * geom.dy)
        g = np.clip(-k / (a * geom.dn), -0.999999, 0.999999)  # cos(angle(v, d)) at the minimum
        lam = (g * geom.p_perp / np.sqrt(1.0 - g * g) - geom.p_par) / geom.dn
        lam = np.clip(np.where(ok, lam, 0.0), 0.0, 1.0)
        vx = geom.vx[s1] + lam * geom.dx
        vy = geom.vy[s1] + lam * geom.dy
        seg = t1n + lam * (t2n - t1n) + a * np.hypot(vx, vy) - cx * vx - cy * vy
        seg = np.where(ok, seg, np.inf)
    cand = np.concatenate([single, seg], axis=1)
    j = np.argmin(cand, axis=1)
    best = cand[np.arange(tgt.size), j]
    node = np.where(j < len(RING), j, geom.s1[np.clip(j - len(RING), 0, len(SEGMENTS) - 1)])
    lab = label[nodes[np.arange(tgt.size), node]]
    return best, lab
