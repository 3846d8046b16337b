"""The raster fire's arrival-time update (:mod:`.raster`, its update (2)) over the 8- and 16-
neighbour rings, as pure numpy functions of flat (raveled, padded) arrays.

:class:`RingGeometry` holds the node offsets of the rings and their vectors to the target cell;
:func:`arrival` is the update's minimum over single nodes and ring segments for a batch of target
cells. No ROS, no state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RING", "SEGMENTS", "RingGeometry", "arrival"]


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
) -> tuple[np.ndarray, np.ndarray]:
    """Arrival time (2) [s] and fire id of the flat target cells ``tgt`` from their ring nodes
    (every ignited node ignited at or before ``t1``; ``src`` marks the burning ones). The flat
    arrays: ignition times [s], extinguished, fire ids, and the wavelet (1) tau(v) = A |v| - Cx vx
    - Cy vy [s/m] of each cell."""
    nodes = tgt[:, None] + geom.ring_flat[None, :]  # (n, 24)
    t_node = t_ign[nodes]
    valid = (t_node <= t1) & ~extinguished[nodes]
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
