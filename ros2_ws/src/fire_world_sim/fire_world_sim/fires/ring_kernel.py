"""The raster fire's update (:mod:`.raster`, Eqs. (1)-(2)) as compiled kernels (numba).

The same arithmetic as the numpy reference (:func:`.ring_update.arrival` and the numpy path of
:class:`.raster.RasterFireModel`), operation by operation and in the same order, compiled without
fast-math, so every IEEE result is the same: arrival times, burn-out times and fire ids are
bit-identical to the numpy path (``numpy.array_equal``, tested). What changes is the
bookkeeping around them, which decides only WHICH cells are read, never a value:

- the passes of one update run in one call;
- the narrow band is kept cell by cell (a cell joins it when one of its ring nodes ignites);
  its arrival times wait in a min-heap of (time, cell, cell version, fire id) entries, so that
  a pass computes only the cells queued since the last (their arrival time was invalidated by
  a ring node that ignited or burnt out, or they hold a seed time (1), which counts only while
  its fire burns) and pops the entries due by ``t1``; an entry whose cell has a newer version,
  or is no longer a target, is stale and skipped. After a new wind or a drop the whole band is
  read again and the heap rebuilt (``meta[5]``);
- the live cells (ignited, not burnt out, not extinguished) are a min-heap by burn-out time,
  counted per fire id, so that a pass pops only the cells that burn out, and which fires burn
  comes from the counts (less the heap's top burnt out since the last update); after a drop or
  a changed burn-out time (``meta[3]``) they are filtered whole and the heap rebuilt;
- ``tnext = [a lower bound of the band's next arrival time, the earliest burn-out time]``: an
  update due before both would ignite nothing and burn nothing out, and the model skips it.

Arrays are the model's flat (raveled, padded) grids; ``meta`` is an int64 array
``[n_live, n_band, n_queued, rebuild the live heap, n_heap, rebuild the band heap]`` and the
geometry comes from :class:`.ring_update.RingGeometry` packed by
:func:`pack_geometry`: ``gi = [ring_flat, s1, s2]`` (3, 24) int64 and
``gf = [vx, vy, vn, dx, dy, dn, p_par, p_perp]`` (8, 24) float64 [m]. No ROS, no state.
Compiled on first use and cached on disk (``cache=True``) beside this module.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .ring_update import RingGeometry

__all__ = ["active_fires", "arrival_batch", "ignite", "pack_geometry", "propagate", "remove_gone"]

N_RING = 24  # nodes of the 8- and 16-neighbour rings; as many segments
G_LO, G_HI = -0.999999, 0.999999  # the clip of cos(angle(v, d)) of ring_update.arrival


def pack_geometry(geom: RingGeometry) -> tuple[np.ndarray, np.ndarray]:
    """(gi, gf): the ring geometry as two contiguous arrays for the kernels."""
    gi = np.ascontiguousarray(np.stack([geom.ring_flat, geom.s1, geom.s2]).astype(np.int64))
    rows = [geom.vx, geom.vy, geom.vn, geom.dx, geom.dy, geom.dn, geom.p_par, geom.p_perp]
    gf = np.ascontiguousarray(np.stack(rows).astype(np.float64))
    return gi, gf


@njit(cache=True)
def _arrival_one(
    tg, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br, blk
):  # pragma: no cover
    """Arrival time (2) [s] and fire id of flat target cell ``tg`` (:func:`.ring_update.arrival`
    for one cell; ``tn``/``br`` are scratch arrays of 24; ``blk``: per cell, the ring nodes whose
    path to it crosses a non-burnable cell, :func:`.ring_update.blocked_nodes`)."""
    ring = gi[0]
    bt = blk[tg]
    for k in range(N_RING):
        nd = tg + ring[k]
        t = t_ign[nd]
        tn[k] = t if (t <= t1 and not ext[nd] and not (bt >> k) & 1) else math.inf
        br[k] = live_mask[nd]
    a = a_spm[tg]
    cx = cx_spm[tg]
    cy = cy_spm[tg]
    vx, vy, vn = gf[0], gf[1], gf[2]
    best = math.inf
    bj = 0
    # single-node Huygens updates (segment end points)
    for k in range(N_RING):
        if br[k]:
            s = tn[k] + a * vn[k] - cx * vx[k] - cy * vy[k]
            if s < best:
                best = s
                bj = k
    # segments: f(l) = T1 + l (T2 - T1) + A |v1 + l d| - C . (v1 + l d)
    if math.isfinite(a):
        s1, s2 = gi[1], gi[2]
        dx, dy, dn, p_par, p_perp = gf[3], gf[4], gf[5], gf[6], gf[7]
        for s in range(N_RING):
            i1 = s1[s]
            i2 = s2[s]
            t1n = tn[i1]
            t2n = tn[i2]
            if not (math.isfinite(t1n) and math.isfinite(t2n) and (br[i1] or br[i2])):
                continue
            k_ = (t2n - t1n) - (cx * dx[s] + cy * dy[s])
            g = -k_ / (a * dn[s])
            g = G_LO if g < G_LO else (G_HI if g > G_HI else g)
            lam = (g * p_perp[s] / math.sqrt(1.0 - g * g) - p_par[s]) / dn[s]
            lam = 0.0 if lam < 0.0 else (1.0 if lam > 1.0 else lam)
            wx = vx[i1] + lam * dx[s]
            wy = vy[i1] + lam * dy[s]
            v = t1n + lam * (t2n - t1n) + a * math.hypot(wx, wy) - cx * wx - cy * wy
            if v < best:
                best = v
                bj = N_RING + s
    node = bj if bj < N_RING else gi[1][bj - N_RING]
    return best, label[tg + ring[node]]


@njit(cache=True)
def arrival_batch(
    tgt, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, blk
):  # pragma: no cover
    """:func:`.ring_update.arrival` over the flat target cells ``tgt`` (for the tests)."""
    n = tgt.size
    best = np.empty(n)
    lab = np.empty(n, dtype=label.dtype)
    tn = np.empty(N_RING)
    br = np.empty(N_RING, dtype=np.bool_)
    for q in range(n):
        b, lb = _arrival_one(
            tgt[q], t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br, blk
        )
        best[q] = b
        lab[q] = lb
    return best, lab


@njit(cache=True)
def _sift_down(heap, n, i, key):  # pragma: no cover
    """Restore the min-heap ``heap[:n]`` (of cells keyed by ``key[cell]``) below position ``i``."""
    c = heap[i]
    k = key[c]
    while True:
        lo = 2 * i + 1
        if lo >= n:
            break
        m = lo
        if lo + 1 < n and key[heap[lo + 1]] < key[heap[lo]]:
            m = lo + 1
        if key[heap[m]] < k:
            heap[i] = heap[m]
            i = m
        else:
            break
    heap[i] = c


@njit(cache=True)
def _sift_up(heap, i, key):  # pragma: no cover
    """Restore the min-heap above position ``i`` (a cell just placed there)."""
    c = heap[i]
    k = key[c]
    while i > 0:
        p = (i - 1) // 2
        if k < key[heap[p]]:
            heap[i] = heap[p]
            i = p
        else:
            break
    heap[i] = c


@njit(cache=True)
def _mark_dirty(b, dirty_buf, is_dirty, nd):  # pragma: no cover
    """Queue cell ``b`` (its arrival time was just invalidated); returns the queue's length."""
    if not is_dirty[b]:
        is_dirty[b] = True
        dirty_buf[nd] = b
        nd += 1
    return nd


@njit(cache=True)
def remove_gone(
    t0, t_out, ext, label, live_buf, live_mask, arr_t, dirty_buf, is_dirty, counts, gi, meta, tnext
):  # pragma: no cover
    """Drop from the live cells those burnt out by ``t0`` [s] or extinguished (both for good);
    their targets' arrival times are to be computed again (NaN, queued). The live cells are a
    min-heap by burn-out time, so this pops only the cells that go; after a drop (extinguished
    cells) or a changed burn-out time (``meta[3]`` set) it filters them all and rebuilds the heap.
    Sets ``tnext[1]``, the earliest burn-out time left. Returns how many left."""
    ring = gi[0]
    n = meta[0]
    nd = meta[2]
    gone = 0
    if meta[3]:
        j = 0
        for q in range(n):
            c = live_buf[q]
            if t_out[c] > t0 and not ext[c]:
                live_buf[j] = c
                j += 1
            else:
                gone += 1
                live_mask[c] = False
                counts[label[c] + 1] -= 1
                for k in range(N_RING):
                    b = c - ring[k]
                    arr_t[b] = math.nan
                    nd = _mark_dirty(b, dirty_buf, is_dirty, nd)
        n = j
        for i in range(n // 2 - 1, -1, -1):
            _sift_down(live_buf, n, i, t_out)
        meta[3] = 0
    else:
        while n > 0:
            c = live_buf[0]
            if t_out[c] > t0:
                break
            n -= 1
            live_buf[0] = live_buf[n]
            if n > 1:
                _sift_down(live_buf, n, 0, t_out)
            gone += 1
            live_mask[c] = False
            counts[label[c] + 1] -= 1
            for k in range(N_RING):
                b = c - ring[k]
                arr_t[b] = math.nan
                nd = _mark_dirty(b, dirty_buf, is_dirty, nd)
    meta[0] = n
    meta[2] = nd
    if gone:
        tnext[0] = -math.inf  # arrival times to compute again: no idle update can be assumed
    tnext[1] = t_out[live_buf[0]] if n > 0 else math.inf
    return gone


@njit(cache=True)
def ignite(
    cells,
    times,
    labels,
    t_ign,
    t_out,
    label,
    burn_type,
    fire_type,
    has_land,
    width,
    pad,
    nx,
    t_seed,
    burnable,
    ext,
    a_spm,
    cx_spm,
    cy_spm,
    res_s,
    max_burn_s,
    live_buf,
    live_mask,
    band_buf,
    in_band,
    arr_t,
    dirty_buf,
    is_dirty,
    counts,
    gi,
    gf,
    meta,
    tnext,
    blk,
):  # pragma: no cover
    """Ignite flat cells ``cells`` at ``times`` [s] with fire ids ``labels`` (all first, then each
    one's burn-out time from the ignition times of the whole batch, as the numpy path): the
    cells join the live heap, their ring joins the band and their targets are invalidated
    (queued). Returns the latest ignition time (-inf for none)."""
    ring = gi[0]
    vx, vy, vn = gf[0], gf[1], gf[2]
    n = cells.size
    latest = -math.inf
    n_live0 = meta[0]
    n_live = n_live0
    n_band = meta[1]
    nd = meta[2]
    for q in range(n):
        c = cells[q]
        t = times[q]
        t_ign[c] = t
        if t > latest:
            latest = t
        if live_mask[c]:  # burning again under a new wind: its burn-out time (its key) changes
            counts[label[c] + 1] -= 1
            meta[3] = 1
        else:
            live_mask[c] = True
            live_buf[n_live] = c
            n_live += 1
        label[c] = labels[q]
        counts[labels[q] + 1] += 1
        if has_land:  # the highest type under the winds it burned in
            f = fire_type[(c // width - pad) * nx + (c % width - pad)]
            if f > burn_type[c]:
                burn_type[c] = f
        t_seed[c] = math.inf
        for k in range(N_RING):  # the ring is symmetric: its cells are the ones c is a node for
            b = c + ring[k]
            arr_t[b] = math.nan
            nd = _mark_dirty(b, dirty_buf, is_dirty, nd)
            if not in_band[b]:
                in_band[b] = True
                band_buf[n_band] = b
                n_band += 1
    meta[1] = n_band
    meta[2] = nd
    for q in range(n):
        c = cells[q]
        t = times[q]
        longest = 0.0
        for k in range(N_RING):
            nb = c - ring[k]  # a cell this one is a node for (unless its path is blocked)
            if burnable[nb] and t_ign[nb] > t and not ext[nb] and not (blk[nb] >> k) & 1:
                tau = a_spm[nb] * vn[k] - cx_spm[nb] * vx[k] - cy_spm[nb] * vy[k]
                if tau > longest or math.isnan(tau):
                    longest = tau
        r = res_s[c]
        longest = r if (r > longest or math.isnan(r)) else longest
        t_out[c] = t + (longest if longest < max_burn_s else max_burn_s)
    if not meta[3]:
        for i in range(n_live0, n_live):
            _sift_up(live_buf, i, t_out)
    meta[0] = n_live
    tnext[1] = -math.inf if meta[3] else (t_out[live_buf[0]] if n_live > 0 else math.inf)
    return latest


@njit(cache=True)
def _bh_push(hkey, hcell, hver, hlab, nh, key, c, v, lb):  # pragma: no cover
    """Push (key, cell, version, fire id) on the band's min-heap of ``nh`` entries."""
    i = nh
    while i > 0:
        p = (i - 1) // 2
        if key < hkey[p]:
            hkey[i] = hkey[p]
            hcell[i] = hcell[p]
            hver[i] = hver[p]
            hlab[i] = hlab[p]
            i = p
        else:
            break
    hkey[i] = key
    hcell[i] = c
    hver[i] = v
    hlab[i] = lb
    return nh + 1


@njit(cache=True)
def _bh_down(hkey, hcell, hver, hlab, n, i):  # pragma: no cover
    """Restore the band's min-heap ``[:n]`` below position ``i``."""
    key = hkey[i]
    c = hcell[i]
    v = hver[i]
    lb = hlab[i]
    while True:
        lo = 2 * i + 1
        if lo >= n:
            break
        m = lo
        if lo + 1 < n and hkey[lo + 1] < hkey[lo]:
            m = lo + 1
        if hkey[m] < key:
            hkey[i] = hkey[m]
            hcell[i] = hcell[m]
            hver[i] = hver[m]
            hlab[i] = hlab[m]
            i = m
        else:
            break
    hkey[i] = key
    hcell[i] = c
    hver[i] = v
    hlab[i] = lb


@njit(cache=True)
def _bh_compact(hkey, hcell, hver, hlab, n, ver, in_band, burnable, t_ign, ext):  # pragma: no cover
    """Drop the band heap's stale entries (an older version of their cell, or a cell no longer a
    band target) and heapify what is left; returns its size."""
    j = 0
    for q in range(n):
        c = hcell[q]
        if hver[q] == ver[c] and in_band[c] and burnable[c] and not math.isfinite(t_ign[c]) and not ext[c]:
            hkey[j] = hkey[q]
            hcell[j] = c
            hver[j] = hver[q]
            hlab[j] = hlab[q]
            j += 1
    for i in range(j // 2 - 1, -1, -1):
        _bh_down(hkey, hcell, hver, hlab, j, i)
    return j


@njit(cache=True)
def propagate(
    t0,
    t1,
    max_sweeps,
    t_ign,
    t_out,
    label,
    burn_type,
    fire_type,
    has_land,
    width,
    pad,
    nx,
    t_seed,
    seed_label,
    seeded,
    burnable,
    ext,
    wet_until,
    a_spm,
    cx_spm,
    cy_spm,
    res_s,
    max_burn_s,
    live_buf,
    live_mask,
    band_buf,
    in_band,
    arr_t,
    arr_lab,
    dirty_buf,
    is_dirty,
    counts,
    ver,
    hkey,
    hcell,
    hver,
    hlab,
    gi,
    gf,
    meta,
    tnext,
    blk,
):  # pragma: no cover
    """Ignite every cell whose arrival time (2) is <= ``t1`` [s], in passes: each pass drops the
    sources burnt out by ``t0`` [s] or extinguished, takes every band cell due by ``t1`` from the
    state at the pass' start (seed times (1) of ``seeded`` on top while their fire burns, no
    earlier than the cell's ``wet_until``) and ignites them together, until a pass ignites
    nothing or ``max_sweeps`` passes.

    The band's arrival times wait in a min-heap (entries carry their cell's version; a newer
    one makes them stale): a pass computes only the queued cells (arrival time invalidated, or
    seeded: their seed time counts while their fire burns) and pops the entries due by ``t1``.
    After a new wind or a drop (``meta[5]``) it reads the whole band and rebuilds the heap.
    Sets ``tnext[0]``, a lower bound of the band's next arrival time (-inf when unknown).
    Returns the latest ignition time (-inf for none)."""
    ring = gi[0]
    latest = -math.inf
    tn = np.empty(N_RING)
    br = np.empty(N_RING, dtype=np.bool_)
    new_c = np.empty(16, dtype=np.int64)
    new_t = np.empty(16)
    new_l = np.empty(16, dtype=label.dtype)
    # the seeded cells are band cells
    n_band = meta[1]
    for q in range(seeded.size):
        c = seeded[q]
        if not in_band[c]:
            in_band[c] = True
            band_buf[n_band] = c
            n_band += 1
    meta[1] = n_band
    cap = hkey.size
    for _ in range(max_sweeps):
        remove_gone(
            t0, t_out, ext, label, live_buf, live_mask, arr_t, dirty_buf, is_dirty, counts, gi, meta, tnext
        )
        n_live = meta[0]
        if n_live == 0 and seeded.size == 0:
            tnext[0] = math.inf  # nothing burns: nothing ignites before a new ignition
            return latest
        nd = meta[2]
        for q in range(seeded.size):
            nd = _mark_dirty(seeded[q], dirty_buf, is_dirty, nd)
        nh = meta[4]
        rebuild = meta[5] != 0
        if rebuild:  # every band cell: the queue is moot, the heap starts again
            for q in range(nd):
                is_dirty[dirty_buf[q]] = False
            nd = 0
            nh = 0
            n_scan = meta[1]
        else:
            n_scan = nd
        j = 0
        for q in range(n_scan):
            if rebuild:
                c = band_buf[q]
                if not burnable[c] or math.isfinite(t_ign[c]) or ext[c]:  # no longer a target
                    in_band[c] = False
                    continue
            else:
                c = dirty_buf[q]
                is_dirty[c] = False
                ver[c] += 1  # its entry in the heap, if any, is stale
                if not in_band[c] or not burnable[c] or math.isfinite(t_ign[c]) or ext[c]:
                    continue  # left in the band: dropped by the next rebuild
            if math.isnan(arr_t[c]):
                near = math.isfinite(t_seed[c])
                if not near:
                    for k in range(N_RING):
                        if live_mask[c + ring[k]]:
                            near = True
                            break
                if not near:  # back when one of its ring nodes ignites
                    if rebuild:
                        in_band[c] = False
                    continue
                b, lb = _arrival_one(
                    c, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br, blk
                )
                arr_t[c] = b
                arr_lab[c] = lb
            if rebuild:
                band_buf[j] = c
                j += 1
                ver[c] += 1
            best = arr_t[c]
            lab = arr_lab[c]
            # exact times from the ignition points, while their fire still burns
            seed = t_seed[c]
            if seed < best:
                sf = seed_label[c]
                if counts[sf + 1] > 0:
                    best = seed
                    lab = sf
            w = wet_until[c]
            t_arr = w if (w > best or math.isnan(w)) else best
            if t_arr < math.inf:
                if nh == cap:
                    nh = _bh_compact(hkey, hcell, hver, hlab, nh, ver, in_band, burnable, t_ign, ext)
                nh = _bh_push(hkey, hcell, hver, hlab, nh, t_arr, c, ver[c], lab)
        if rebuild:
            meta[1] = j
            meta[5] = 0
        meta[2] = 0
        # every band cell due by t1, from the heap
        m = 0
        while nh > 0 and hkey[0] <= t1:
            t_arr = hkey[0]
            c = hcell[0]
            v = hver[0]
            lab = hlab[0]
            nh -= 1
            if nh > 0:
                hkey[0] = hkey[nh]
                hcell[0] = hcell[nh]
                hver[0] = hver[nh]
                hlab[0] = hlab[nh]
                _bh_down(hkey, hcell, hver, hlab, nh, 0)
            if v != ver[c] or not in_band[c] or not burnable[c] or math.isfinite(t_ign[c]) or ext[c]:
                continue  # stale
            ver[c] += 1
            if m == new_c.size:
                new_c = np.concatenate((new_c, np.empty(m, dtype=np.int64)))
                new_t = np.concatenate((new_t, np.empty(m)))
                new_l = np.concatenate((new_l, np.empty(m, dtype=label.dtype)))
            new_c[m] = c
            new_t[m] = t_arr
            new_l[m] = lab
            m += 1
        meta[4] = nh
        if m == 0:
            tnext[0] = hkey[0] if nh > 0 else math.inf
            return latest
        last = ignite(
            new_c[:m],
            new_t[:m],
            new_l[:m],
            t_ign,
            t_out,
            label,
            burn_type,
            fire_type,
            has_land,
            width,
            pad,
            nx,
            t_seed,
            burnable,
            ext,
            a_spm,
            cx_spm,
            cy_spm,
            res_s,
            max_burn_s,
            live_buf,
            live_mask,
            band_buf,
            in_band,
            arr_t,
            dirty_buf,
            is_dirty,
            counts,
            gi,
            gf,
            meta,
            tnext,
            blk,
        )
        if last > latest:
            latest = last
    tnext[0] = -math.inf  # passes left undone
    return latest


@njit(cache=True)
def active_fires(
    t_s,
    t0,
    ign_ok,
    t_ign,
    t_out,
    ext,
    label,
    live_buf,
    live_mask,
    arr_t,
    dirty_buf,
    is_dirty,
    counts,
    gi,
    meta,
    tnext,
    flags,
):  # pragma: no cover
    """The fire ids burning at ``t_s`` [s] >= ``t0`` [s], the last update (every cell burning then
    is live), as ``flags[id + 1]``; drops the live cells gone by ``t0`` (:func:`remove_gone`) on
    the way. With ``ign_ok`` (no cell ignites after ``t_s``) from the live cells per fire less
    those of the heap's top burnt out by ``t_s``; else from every live cell. Returns whether
    ``flags`` changed."""
    remove_gone(
        t0, t_out, ext, label, live_buf, live_mask, arr_t, dirty_buf, is_dirty, counts, gi, meta, tnext
    )
    n = meta[0]
    on = np.zeros(flags.size, dtype=np.int64)
    if ign_ok:
        for i in range(flags.size):
            on[i] = counts[i]
        if n > 0 and not (t_out[live_buf[0]] > t_s):  # the burnt out by t_s: the heap above them
            stack = np.empty(n, dtype=np.int64)
            stack[0] = 0
            sp = 1
            while sp > 0:
                sp -= 1
                i = stack[sp]
                c = live_buf[i]
                if t_out[c] > t_s:
                    continue
                on[label[c] + 1] -= 1
                lo = 2 * i + 1
                if lo < n:
                    stack[sp] = lo
                    sp += 1
                    if lo + 1 < n:
                        stack[sp] = lo + 1
                        sp += 1
    else:
        for q in range(n):
            c = live_buf[q]
            if t_ign[c] <= t_s and t_s < t_out[c]:
                on[label[c] + 1] += 1
    changed = False
    for i in range(flags.size):
        f = on[i] > 0
        if f != flags[i]:
            flags[i] = f
            changed = True
    return changed
