"""The raster fire's update (:mod:`.raster`, Eqs. (1)-(2)) as compiled kernels (numba).

The same arithmetic as the numpy reference (:func:`.ring_update.arrival` and the numpy path of
:class:`.raster.RasterFireModel`), operation by operation and in the same order, compiled without
fast-math, so every IEEE result is the same: arrival times, burn-out times and fire ids are
bit-identical to the numpy path (``numpy.array_equal``, tested). What changes is the
bookkeeping around them: the passes of one update run in one call, the narrow band is kept
cell by cell (a cell joins it when one of its ring nodes ignites and leaves it when it is no
longer a target, or when its arrival time is to be computed and no ring node burns), and the
live cells (ignited, not burnt out, not extinguished) are a buffer compacted in place.

Arrays are the model's flat (raveled, padded) grids; ``meta`` is an int64 array
``[n_live, n_band]`` and the geometry comes from :class:`.ring_update.RingGeometry` packed by
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
    tg, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br
):  # pragma: no cover
    """Arrival time (2) [s] and fire id of flat target cell ``tg`` (:func:`.ring_update.arrival`
    for one cell; ``tn``/``br`` are scratch arrays of 24)."""
    ring = gi[0]
    for k in range(N_RING):
        nd = tg + ring[k]
        t = t_ign[nd]
        tn[k] = t if (t <= t1 and not ext[nd]) else math.inf
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
def arrival_batch(tgt, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf):  # pragma: no cover
    """:func:`.ring_update.arrival` over the flat target cells ``tgt`` (for the tests)."""
    n = tgt.size
    best = np.empty(n)
    lab = np.empty(n, dtype=label.dtype)
    tn = np.empty(N_RING)
    br = np.empty(N_RING, dtype=np.bool_)
    for q in range(n):
        b, lb = _arrival_one(tgt[q], t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br)
        best[q] = b
        lab[q] = lb
    return best, lab


@njit(cache=True)
def remove_gone(t0, t_out, ext, live_buf, live_mask, arr_t, gi, meta):  # pragma: no cover
    """Drop from the live cells those burnt out by ``t0`` [s] or extinguished (both for good);
    their targets' arrival times are to be computed again (NaN). Returns how many left."""
    ring = gi[0]
    n = meta[0]
    j = 0
    gone = 0
    for q in range(n):
        c = live_buf[q]
        if t_out[c] > t0 and not ext[c]:
            live_buf[j] = c
            j += 1
        else:
            live_mask[c] = False
            gone += 1
            for k in range(N_RING):
                arr_t[c - ring[k]] = math.nan
    meta[0] = j
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
    gi,
    gf,
    meta,
):  # pragma: no cover
    """Ignite flat cells ``cells`` at ``times`` [s] with fire ids ``labels`` (all first, then each
    one's burn-out time from the ignition times of the whole batch, as the numpy path): the
    cells join the live buffer, their ring joins the band and their targets are invalidated.
    Returns the latest ignition time (-inf for none)."""
    ring = gi[0]
    vx, vy, vn = gf[0], gf[1], gf[2]
    n = cells.size
    latest = -math.inf
    n_live = meta[0]
    n_band = meta[1]
    for q in range(n):
        c = cells[q]
        t = times[q]
        t_ign[c] = t
        if t > latest:
            latest = t
        label[c] = labels[q]
        if has_land:  # the highest type under the winds it burned in
            f = fire_type[(c // width - pad) * nx + (c % width - pad)]
            if f > burn_type[c]:
                burn_type[c] = f
        t_seed[c] = math.inf
        if not live_mask[c]:
            live_mask[c] = True
            live_buf[n_live] = c
            n_live += 1
        for k in range(N_RING):
            arr_t[c - ring[k]] = math.nan
            b = c + ring[k]
            if not in_band[b]:
                in_band[b] = True
                band_buf[n_band] = b
                n_band += 1
    meta[0] = n_live
    meta[1] = n_band
    for q in range(n):
        c = cells[q]
        t = times[q]
        longest = 0.0
        for k in range(N_RING):
            nb = c - ring[k]  # a cell this one is a node for
            if burnable[nb] and t_ign[nb] > t and not ext[nb]:
                tau = a_spm[nb] * vn[k] - cx_spm[nb] * vx[k] - cy_spm[nb] * vy[k]
                if tau > longest or math.isnan(tau):
                    longest = tau
        r = res_s[c]
        longest = r if (r > longest or math.isnan(r)) else longest
        t_out[c] = t + (longest if longest < max_burn_s else max_burn_s)
    return latest


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
    n_fires,
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
    gi,
    gf,
    meta,
):  # pragma: no cover
    """Ignite every cell whose arrival time (2) is <= ``t1`` [s], in passes: each pass drops the
    sources burnt out by ``t0`` [s] or extinguished, takes every band cell due by ``t1`` from the
    state at the pass' start (seed times (1) of ``seeded`` on top while their fire burns, no
    earlier than the cell's ``wet_until``) and ignites them together, until a pass ignites
    nothing or ``max_sweeps`` passes. Returns the latest ignition time (-inf for none)."""
    ring = gi[0]
    latest = -math.inf
    tn = np.empty(N_RING)
    br = np.empty(N_RING, dtype=np.bool_)
    burning_fires = np.zeros(n_fires + 1, dtype=np.bool_)
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
    for _ in range(max_sweeps):
        remove_gone(t0, t_out, ext, live_buf, live_mask, arr_t, gi, meta)
        n_live = meta[0]
        if n_live == 0 and seeded.size == 0:
            return latest
        fires_known = False
        n_band = meta[1]
        j = 0
        m = 0
        for q in range(n_band):
            c = band_buf[q]
            if not burnable[c] or math.isfinite(t_ign[c]) or ext[c]:  # no longer a target
                in_band[c] = False
                continue
            if math.isnan(arr_t[c]):
                near = math.isfinite(t_seed[c])
                if not near:
                    for k in range(N_RING):
                        if live_mask[c + ring[k]]:
                            near = True
                            break
                if not near:  # back when one of its ring nodes ignites
                    in_band[c] = False
                    continue
                b, lb = _arrival_one(
                    c, t1, t_ign, ext, label, live_mask, a_spm, cx_spm, cy_spm, gi, gf, tn, br
                )
                arr_t[c] = b
                arr_lab[c] = lb
            band_buf[j] = c
            j += 1
            best = arr_t[c]
            lab = arr_lab[c]
            # exact times from the ignition points, while their fire still burns
            seed = t_seed[c]
            if seed < best:
                if not fires_known:
                    burning_fires[:] = False
                    for p in range(n_live):
                        burning_fires[label[live_buf[p]] + 1] = True
                    fires_known = True
                sf = seed_label[c]
                if burning_fires[sf + 1]:
                    best = seed
                    lab = sf
            w = wet_until[c]
            t_arr = w if (w > best or math.isnan(w)) else best
            if t_arr <= t1:
                if m == new_c.size:
                    new_c = np.concatenate((new_c, np.empty(m, dtype=np.int64)))
                    new_t = np.concatenate((new_t, np.empty(m)))
                    new_l = np.concatenate((new_l, np.empty(m, dtype=label.dtype)))
                new_c[m] = c
                new_t[m] = t_arr
                new_l[m] = lab
                m += 1
        meta[1] = j
        if m == 0:
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
            gi,
            gf,
            meta,
        )
        if last > latest:
            latest = last
    return latest


@njit(cache=True)
def active_fires(
    t_s, t0, t_ign, t_out, label, ext, live_buf, live_mask, arr_t, gi, meta, flags
):  # pragma: no cover
    """The fire ids burning at ``t_s`` [s] >= ``t0`` [s], the last update (every cell burning then
    is live), as ``flags[id + 1]``; drops the live cells gone by ``t0`` (as :func:`remove_gone`) on
    the way. Returns whether ``flags`` changed."""
    ring = gi[0]
    before = flags.copy()
    flags[:] = False
    j = 0
    for q in range(meta[0]):
        c = live_buf[q]
        if t_out[c] > t0 and not ext[c]:
            live_buf[j] = c
            j += 1
            if t_ign[c] <= t_s and t_s < t_out[c]:
                flags[label[c] + 1] = True
        else:
            live_mask[c] = False
            for k in range(N_RING):
                arr_t[c - ring[k]] = math.nan
    meta[0] = j
    for i in range(flags.size):
        if flags[i] != before[i]:
            return True
    return False
