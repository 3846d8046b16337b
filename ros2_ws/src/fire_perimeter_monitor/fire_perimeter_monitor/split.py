"""Splitting a fire's perimeter between monitors: by spread rate, or as a relay at the head
(both ours; not in PM).

PM plans for one UAV per fire and leaves several UAVs to future work (Section VII: "we want
to extend the algorithm to support multiple UASs"); its predecessor [3] (Hu, Bent and Sun,
ICUAS 2019, cited in PM Sections I and II) assigns each UAV a region of the perimeter that it
monitors back and forth, adjacent UAVs negotiating their common boundary "to maintain a
balanced responsibility". This module is that balance, computed by each monitor on its own
from the shared map: the work a stretch of perimeter carries is its spread rate times its
length (the distance the fire moves out along it per second, PM Eq. 1's ROS times the
stretch), with Eq. 7's heterogeneity-adjusted ROS so that PM's alpha stays the knob (alpha =
0: every cell alike, the split is by length; larger alpha: the fast arc weighs more).

The work leaves out the time since a cell was last seen (Eq. 4's other factor): the split says
where the fire moves, and the turning rule inside each arc (importance.worst_angle_turn) how
stale each part of it is. Measured on monitor_grass (two monitors, 10 seeds, the package
README): 12.8 m against 12.0 m for the split by angle, so ``MonitorConfig.split`` keeps
"angle" as the default.

The relay (:func:`relay_split`, two monitors) coordinates them in time instead: the monitor
nearer the head holds an arc about it, the other works the rest, and the roles swap when the
other gets nearer. Measured on monitor_grass (10 seeds): 12.0 m, the angle split's figure, so
it is not the default either (the package README says why).

Cells are the constructed perimeter in the order of PM Eqs. 5-6: index 0 is the UAV's cell
and the index grows *against* the flying direction, so the cell just ahead of the UAV is the
last one. Pure functions over numpy arrays.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError

__all__ = ["arc_work", "head_index", "relay_split", "work_bisector_split"]

# Added to every cell's rate as this fraction of the mean rate, so a stretch where the map
# knows no spread still splits by length instead of leaving a boundary anywhere in it.
_LENGTH_SHARE = 0.05


def arc_work(ros_mps: np.ndarray, spacing_m: float) -> np.ndarray:
    """Work per perimeter cell [m^2/s]: ``(ROS + 5 % of the mean ROS) * spacing``.

    ``ros_mps`` per cell (NaN or negative counts 0). The small length share keeps a split
    defined on a stretch of zero spread (by length there).
    """
    r = np.nan_to_num(np.asarray(ros_mps, dtype=float), nan=0.0)
    r = np.maximum(r, 0.0)
    if r.ndim != 1:
        raise InputError(f"ros_mps must be 1-D, got shape {r.shape}")
    mean = float(np.mean(r)) if r.size else 0.0
    return (r + (_LENGTH_SHARE * mean if mean > 0 else 1.0)) * float(spacing_m)


def _half_work_index(cum: np.ndarray, lo: int, hi: int) -> int:
    """First index ``k`` in ``[lo, hi]`` where the work from ``lo`` reaches half the work of
    ``lo .. hi - 1``; ``cum`` is the running sum with a leading 0."""
    half = 0.5 * (cum[hi] - cum[lo])
    k = int(np.searchsorted(cum, cum[lo] + half, side="left"))
    return min(max(k, lo), hi)


def work_bisector_split(work: np.ndarray, peer_index: np.ndarray) -> np.ndarray:
    """Cells this monitor owns: its arc reaches halfway, in work, to the nearest peer each way.

    ``work`` per cell (:func:`arc_work`), index 0 the UAV's cell, growing against the flying
    direction; ``peer_index``: the cells the live peers are at (1 .. M-1; a peer on our own
    cell is placed on cell 1 or M-1 by the caller). Between us and the nearest peer behind
    (smallest index ``p``) the boundary is where the work from us reaches half the work of
    cells ``0 .. p-1``; between the nearest peer ahead (largest index ``q``) and us, half the
    work of ``q .. M-1``. So with one peer each monitor owns exactly half the perimeter's work,
    and each boundary lies nearer, in length, to the monitor on its faster side. With the
    work proportional to length this is the length bisector, the split by angle's analogue
    along the perimeter.

    Returns a boolean mask over the cells (True: ours). With no peer, every cell is ours.
    """
    w = np.asarray(work, dtype=float)
    if w.ndim != 1:
        raise InputError(f"work must be 1-D, got shape {w.shape}")
    m = w.size
    owned = np.ones(m, dtype=bool)
    p_idx = np.asarray(peer_index, dtype=int).ravel()
    if m < 2 or p_idx.size == 0:
        return owned
    if np.any((p_idx < 1) | (p_idx > m - 1)):
        raise InputError(f"peer cells must lie in 1 .. {m - 1}, got {p_idx.tolist()}")
    cum = np.concatenate([[0.0], np.cumsum(w)])
    p, q = int(p_idx.min()), int(p_idx.max())
    b_behind = _half_work_index(cum, 0, p)  # cells 0 .. b_behind - 1 are ours
    b_ahead = _half_work_index(cum, q, m)  # cells b_ahead .. m - 1 are ours
    owned[:] = False
    owned[:b_behind] = True
    owned[b_ahead:] = True
    owned[0] = True
    return owned


def _smoothed_ros(ros_mps: np.ndarray, smooth_cells: int) -> np.ndarray:
    """Per-cell ROS (NaN and negative count 0) averaged circularly over ``+-k`` cells,
    ``k = min(smooth_cells, (M - 1) // 2)``."""
    r = np.maximum(np.nan_to_num(np.asarray(ros_mps, dtype=float), nan=0.0), 0.0)
    if r.ndim != 1 or r.size == 0:
        raise InputError(f"ros_mps must be a non-empty 1-D array, got shape {r.shape}")
    k = min(int(smooth_cells), (r.size - 1) // 2)
    if k > 0:
        ext = np.concatenate([r[-k:], r, r[:k]])
        c = np.cumsum(np.concatenate([[0.0], ext]))
        r = (c[2 * k + 1 :] - c[: -2 * k - 1]) / (2 * k + 1)
    return r


def head_index(ros_mps: np.ndarray, smooth_cells: int = 2) -> int:
    """Index of the fastest cell of a closed perimeter: the argmax of the per-cell ROS
    averaged circularly over ``+-smooth_cells`` cells (NaN counts 0), so one noisy cell does
    not take the head from a fast stretch. Ties: the lowest index."""
    return int(np.argmax(_smoothed_ros(ros_mps, smooth_cells)))


def relay_split(
    ros_mps: np.ndarray,
    spacing_m: float,
    peer_index: int,
    head_half_m: float,
    mine_on_tie: bool,
    fast_fraction: float = 0.0,
) -> np.ndarray:
    """Cells this monitor owns in a relay of two monitors at the head (ours; not in PM or [3]).

    One monitor holds the head: it owns the cells within ``head_half_m`` of the fastest cell
    (:func:`head_index`) along the perimeter, and sweeps them back and forth; the other owns
    the rest of the perimeter. The holder is the monitor nearer the head along the perimeter
    (``mine_on_tie``: ours at equal distance), so the roles swap when the other monitor,
    coming round, gets there first: the holder leaves the head as its peer arrives, and the
    head is out of sight only while neither is within the footprint of it. The half-width is
    capped at a quarter of the perimeter, so the holder never owns more than half.

    ``fast_fraction`` > 0 widens the arc to the contiguous stretch about the head whose ROS is
    at least that fraction of the head's rate (the head's flanks spread fast too: on
    monitor_grass the angles spreading at >= 2 m/s about the ignition point span 300-550 m of
    perimeter, not a point), still within the cap. The head's rate is its smoothed rate, the
    mean over ``+-2`` cells that :func:`head_index` maximises, not the head cell's own: the
    smoothed argmax can land on a cell reading 0 between fast ones (whole-cell distances over
    a short baseline give zeros, PM Eq. 1), and a comparison with 0 took every cell as fast,
    the whole capped arc. Not the largest rate in the window either: that is the one noisy
    cell the smoothing is there to discount (a spike among 3 m/s cells would leave the 3 m/s
    stretch out of the arc). A head whose smoothed rate is 0 (no spread known about it) is
    not widened.

    Departs from PM, where one UAV weighs all cells by Eq. 4 (the time since the last visit
    times the ROS) in its windows (Eqs. 5-6): here the importance of a cell is zeroed unless
    it is in this monitor's role's arc, as with the other splits.

    ``ros_mps`` per cell (Eq. 7's ROS), index 0 the UAV's cell, growing against the flying
    direction (as :func:`work_bisector_split`); ``peer_index``: the peer's cell, 1 .. M-1.
    Returns a boolean mask over the cells (True: ours).
    """
    r = np.asarray(ros_mps, dtype=float)
    if r.ndim != 1:
        raise InputError(f"ros_mps must be 1-D, got shape {r.shape}")
    m = r.size
    if m < 2:
        return np.ones(m, dtype=bool)
    if not 1 <= int(peer_index) <= m - 1:
        raise InputError(f"peer cell must lie in 1 .. {m - 1}, got {peer_index}")
    if not (spacing_m > 0 and head_half_m >= 0):
        raise InputError(f"spacing_m must be > 0 and head_half_m >= 0, got {spacing_m}, {head_half_m}")
    smooth = _smoothed_ros(r, 2)
    h = int(np.argmax(smooth))  # head_index(r)
    idx = np.arange(m)
    dist_head = np.minimum(np.abs(idx - h), m - np.abs(idx - h)) * float(spacing_m)
    half = float(head_half_m)
    if fast_fraction > 0 and smooth[h] > 0:  # widen: the stretch at >= fraction of the head's rate
        rr = np.maximum(np.nan_to_num(r, nan=0.0), 0.0)
        fast = rr >= fast_fraction * smooth[h]
        for step in (1, -1):
            j, n = h, 0
            while n < m // 2 and fast[(j + step) % m]:
                j, n = (j + step) % m, n + 1
            half = max(half, n * float(spacing_m))
    in_head = dist_head <= min(half, 0.25 * m * float(spacing_m))
    me_d, peer_d = dist_head[0], dist_head[int(peer_index)]
    holder = me_d < peer_d or (me_d == peer_d and mine_on_tie)
    owned = in_head if holder else ~in_head
    owned = owned.copy()
    owned[0] = True  # the UAV's own cell is always its own (it is there)
    return owned
