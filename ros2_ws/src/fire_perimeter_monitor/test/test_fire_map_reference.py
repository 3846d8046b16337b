"""The fast FireMap updates against the array-per-round code they replaced, bit for bit.

``_Reference`` keeps the updates as they were before the perimeter monitor's step was cut
(commit 1a20769): :meth:`FireMap.merge_outer` took one cell per bin per round (a round of
array operations per rank of a cell in its bin's time order). The fast versions must leave
every array of the map with the same bits and return the same counts, whatever the sightings:
random maps here, drawn so that the branches that matter happen (first visits, cells nearer
than the outer cell, the same visit, a new visit under and over the Eq. 1 baseline, equal
times, unknown ignition times, NaN cells).
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_perimeter_monitor.fire_map import FireMap, perimeter_mask, sighting, unburned_lookup
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate)
ARRAYS = ("outer_x_m", "outer_y_m", "outer_d_m", "outer_t_s", "inner_d_m", "inner_t_s")


class _Reference(FireMap):
    """FireMap's updates as of commit 1a20769 (verbatim but for names): ``merge_outer`` and
    ``record`` with its fill of skipped bins, its visit and the Eq. 1 baseline."""

    def merge_outer(self, x_m, y_m, t_s) -> int:
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        t = np.asarray(t_s, dtype=float)
        ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(t)
        x, y, t = x[ok], y[ok], t[ok]
        if x.size == 0:
            return 0
        b = self.bin_of(x, y)
        d = np.hypot(x - self.center_x_m, y - self.center_y_m)
        order = np.argsort(t, kind="stable")
        b, x, y, d, t = b[order], x[order], y[order], d[order], t[order]
        by_bin = np.argsort(b, kind="stable")
        bs = b[by_bin]
        first = np.r_[True, bs[1:] != bs[:-1]]
        rank = np.empty(b.size, dtype=np.int64)
        rank[by_bin] = np.arange(b.size) - np.maximum.accumulate(np.where(first, np.arange(b.size), 0))
        taken = 0
        for r in range(int(rank.max()) + 1):
            sel = np.flatnonzero(rank == r)
            ours = self.outer_t_s[b[sel]]
            sel = sel[np.isnan(ours) | (t[sel] > ours)]
            if sel.size:
                self._ref_visit(b[sel], x[sel], y[sel], d[sel], t[sel])
                taken += int(sel.size)
        return taken

    def record(self, x_m, y_m, t_s, link_m=0.0, seen_unburned=None):
        x = np.asarray(x_m, dtype=float).ravel()
        y = np.asarray(y_m, dtype=float).ravel()
        if x.size == 0:
            return np.zeros(0, dtype=np.int64)
        d = np.hypot(x - self.center_x_m, y - self.center_y_m)
        b = self.bin_of(x, y)
        order = np.lexsort((d, b))
        b_sorted = b[order]
        last = np.r_[b_sorted[1:] != b_sorted[:-1], True]
        sel = order[last]
        bins, xs, ys, ds = b[sel], x[sel], y[sel], d[sel]
        if link_m > 0 and bins.size >= 2:
            bins, xs, ys, ds = self._ref_fill_skipped(bins, xs, ys, ds, link_m)
        self._ref_visit(bins, xs, ys, ds, float(t_s), seen_unburned)
        return bins

    def _ref_fill_skipped(self, bins, xs, ys, ds, link_m):
        nb = self.bin_count
        nxt = np.roll(np.arange(bins.size), -1)
        gap = (bins[nxt] - bins) % nb
        close = np.hypot(xs[nxt] - xs, ys[nxt] - ys) <= link_m
        ks = np.flatnonzero(close & (gap >= 2) & (gap <= nb // 4))
        if ks.size == 0:
            return bins, xs, ys, ds
        counts = gap[ks] - 1
        k = np.repeat(ks, counts)
        step = np.arange(k.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1
        px, py = xs[k] - self.center_x_m, ys[k] - self.center_y_m
        ex, ey = xs[nxt[k]] - xs[k], ys[nxt[k]] - ys[k]
        fb = (bins[k] + step) % nb
        th = (fb + 0.5) * (2 * np.pi / nb)
        ux, uy = np.cos(th), np.sin(th)
        den = ux * ey - uy * ex
        with np.errstate(divide="ignore", invalid="ignore"):
            r = (px * ey - py * ex) / den
        ok = np.isfinite(r) & (r > 0)
        ab, ax, ay = fb[ok], self.center_x_m + r[ok] * ux[ok], self.center_y_m + r[ok] * uy[ok]
        keep = ~np.isin(ab, bins)
        ab, ax, ay = ab[keep], ax[keep], ay[keep]
        ab, first = np.unique(ab, return_index=True)
        ax, ay = ax[first], ay[first]
        ad = np.hypot(ax - self.center_x_m, ay - self.center_y_m)
        return np.r_[bins, ab], np.r_[xs, ax], np.r_[ys, ay], np.r_[ds, ad]

    def _ref_visit(self, bins, x, y, d, t_s, seen_unburned=None) -> None:
        t_s = np.broadcast_to(np.asarray(t_s, dtype=float), bins.shape)
        prev_t = self.outer_t_s[bins]
        first = np.isnan(prev_t)
        inward = ~first & (d < self.outer_d_m[bins])
        cleared = np.zeros(bins.size, dtype=bool)
        if seen_unburned is not None and inward.any():
            cleared[inward] = np.asarray(
                seen_unburned(self.outer_x_m[bins[inward]], self.outer_y_m[bins[inward]]), dtype=bool
            )
        seen = ~inward | cleared
        same_visit = seen & ~first & (t_s >= prev_t) & (t_s - prev_t < self.revisit_gap_s)
        new_visit = seen & ~first & ~same_visit & (t_s > prev_t)
        fb = bins[first]
        self.inner_d_m[fb] = 0.0
        self.inner_t_s[fb] = np.nan if self.ignition_time_s is None else self.ignition_time_s
        nv = new_visit & ((t_s - prev_t >= self._ref_baseline_s(bins)) | np.isnan(self.inner_t_s[bins]))
        nb = bins[nv]
        self.inner_d_m[nb] = self.outer_d_m[nb]
        self.inner_t_s[nb] = self.outer_t_s[nb]
        cb = bins[cleared & (same_visit | new_visit)]
        self.inner_d_m[cb] = d[cleared & (same_visit | new_visit)]
        self.inner_t_s[cb] = np.nan
        upd = first | same_visit | new_visit
        ub = bins[upd]
        self.outer_x_m[ub] = x[upd]
        self.outer_y_m[ub] = y[upd]
        self.outer_d_m[ub] = d[upd]
        self.outer_t_s[ub] = t_s[upd]

    def _ref_baseline_s(self, bins):
        base = np.full(bins.size, self.ros_baseline_s)
        if self.ros_baseline_cells > 0:
            ros = self.ros_mps()[bins]
            with np.errstate(divide="ignore"):
                scaled = np.where(
                    ros > 0, self.ros_baseline_cells * self.cell_size_m / np.where(ros > 0, ros, 1.0), np.inf
                )
            base = np.where(np.isfinite(ros), np.maximum(base, scaled), base)
        return base


def _assert_same_bits(fast: FireMap, ref: FireMap, what: str) -> None:
    for name in ARRAYS:
        a, b = getattr(fast, name), getattr(ref, name)
        assert np.array_equal(a.view(np.int64), b.view(np.int64)), f"{what}: {name} differs"


def _maps(rng: np.random.Generator) -> tuple[FireMap, FireMap]:
    kw = dict(
        bin_count=int(rng.choice([8, 36, 360])),
        ignition_time_s=None if rng.random() < 0.4 else 0.0,
        revisit_gap_s=float(rng.choice([0.0, 1.5, 10.0])),
        ros_baseline_s=float(rng.choice([0.0, 3.0])),
        ros_baseline_cells=float(rng.choice([0.0, 0.5, 2.0])),
        cell_size_m=5.0,
    )
    return FireMap(2.5, -7.5, **kw), _Reference(2.5, -7.5, **kw)


def _peer_cells(rng: np.random.Generator, t_now: float, n: int):
    """Lattice cells about the centre at radii that grow with time, times on a 0.5 s grid (ties
    and exact revisit gaps happen), a few NaNs."""
    th = rng.uniform(0.0, 2 * np.pi, n)
    r = rng.uniform(5.0, 20.0 + 2.0 * t_now, n)
    x = 2.5 + 5.0 * np.rint(r * np.cos(th) / 5.0)
    y = -7.5 + 5.0 * np.rint(r * np.sin(th) / 5.0)
    t = 0.5 * np.rint(rng.uniform(max(t_now - 30.0, 0.0), t_now, n) / 0.5)
    for a in (x, y, t):
        a[rng.random(n) < 0.03] = np.nan
    return x, y, t


def _footprint(rng: np.random.Generator, t_now: float):
    """A sensor footprint: a disc of lattice cells, burned inside a radius about the centre."""
    cx = 2.5 + 5.0 * np.rint(rng.uniform(-60.0, 60.0) / 5.0)
    cy = -7.5 + 5.0 * np.rint(rng.uniform(-60.0, 60.0) / 5.0)
    k = np.arange(-6, 7)
    i, j = np.meshgrid(k, k, indexing="ij")
    disc = i**2 + j**2 <= 36
    x, y = cx + 5.0 * i[disc], cy + 5.0 * j[disc]
    fire_r = 10.0 + 1.5 * t_now + rng.uniform(-5.0, 5.0, x.size)
    s = np.where(np.hypot(x - 2.5, y + 7.5) <= fire_r, rng.choice([1, 2], x.size), 0)
    return x.astype(float), y.astype(float), s


@settings(max_examples=150, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1))
def test_merge_outer_is_the_round_by_round_merge(seed):
    rng = np.random.default_rng(seed)
    fast, ref = _maps(rng)
    t = 0.0
    for step in range(int(rng.integers(1, 8))):
        t += float(rng.choice([0.5, 1.5, 5.0, 12.0]))
        if rng.random() < 0.5:  # own sightings in between, as a monitor has (same code for both)
            x, y, s = _footprint(rng, t)
            look = unburned_lookup(x, y, s, 5.0)
            assert np.array_equal(fast.record(x, y, t, 7.5, look), ref.record(x, y, t, 7.5, look))
        x, y, tt = _peer_cells(rng, t, int(rng.integers(1, 400)))
        assert fast.merge_outer(x, y, tt) == ref.merge_outer(x, y, tt)
        _assert_same_bits(fast, ref, f"merge {step}")


def test_merge_outer_branches_by_hand():
    """One bin, cells in time order: each branch of the scan, with the count it returns."""
    kw = dict(bin_count=8, ignition_time_s=None, revisit_gap_s=10.0, ros_baseline_cells=2.0, cell_size_m=10.0)
    fm, ref = FireMap(0.0, 0.0, **kw), _Reference(0.0, 0.0, **kw)
    calls = (
        ([10.0], [1.0], [5.0]),  # first visit: the inner cell is the ignition point, time unknown
        ([12.0, 30.0], [1.0, 1.0], [6.0, 1.0]),  # older than ours: not taken; 1 s later: same visit
        ([11.0, 20.0], [1.0, 1.0], [7.0, 16.0]),  # nearer: counted, no visit; then a new visit
        ([24.0], [1.0], [26.0]),  # a new visit sooner than 2 cells at the bin's ROS: inner stays
        ([40.0], [1.0], [80.0]),  # long after: the previous outer cell becomes the inner one
    )
    counts = [fm.merge_outer(*c) for c in calls]
    assert counts == [ref.merge_outer(*c) for c in calls] == [1, 1, 2, 1, 1]
    _assert_same_bits(fm, ref, "by hand")
    assert (fm.outer_t_s[0], fm.inner_t_s[0], fm.inner_d_m[0]) == (80.0, 26.0, np.hypot(24.0, 1.0))
    # after the third call the inner cell was (12, 1) at 6 s: ROS 0.8 m/s, a 25 s baseline
    probe = FireMap(0.0, 0.0, **kw)
    for c in calls[:4]:
        probe.merge_outer(*c)
    assert probe.inner_t_s[0] == 6.0 and probe.inner_d_m[0] == np.hypot(12.0, 1.0)


@settings(max_examples=150, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1))
def test_record_is_the_old_record(seed):
    """Footprints of perimeter cells, with the fill of skipped bins and the sighting's unburned
    cells as evidence, on maps that also take peers' cells."""
    rng = np.random.default_rng(seed)
    fast, ref = _maps(rng)
    t = 0.0
    for step in range(int(rng.integers(1, 12))):
        t += float(rng.choice([0.5, 1.5, 5.0, 12.0]))
        x, y, s = _footprint(rng, t)
        per = rng.random(x.size) < 0.6  # any subset: the map does not need a true perimeter
        link = float(rng.choice([0.0, 7.5, 25.0]))
        look = unburned_lookup(x, y, s, 5.0) if rng.random() < 0.8 else None
        assert np.array_equal(
            fast.record(x[per], y[per], t, link, look), ref.record(x[per], y[per], t, link, look)
        )
        _assert_same_bits(fast, ref, f"record {step}")
        if rng.random() < 0.3:
            px, py, pt = _peer_cells(rng, t, 50)
            assert fast.merge_outer(px, py, pt) == ref.merge_outer(px, py, pt)


@pytest.mark.parametrize("n", [0, 1])
def test_merge_outer_of_nothing_new(n):
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0)
    fm.merge_outer([10.0], [0.0], [5.0])
    before = [getattr(fm, a).copy() for a in ARRAYS]
    assert fm.merge_outer([20.0] * n, [0.0] * n, [5.0] * n) == 0  # not newer: nothing taken
    assert all(np.array_equal(a, getattr(fm, k), equal_nan=True) for a, k in zip(before, ARRAYS, strict=True))


@settings(max_examples=100, deadline=None, phases=NO_SHRINK)
@given(st.integers(0, 2**32 - 1))
def test_sighting_is_the_perimeter_and_the_unburned_cells(seed):
    """sighting() indexes a footprint once for both answers: the perimeter mask is the
    brute-force 4-neighbour scan, the lookup is membership in the set of unburned cells (any
    query point, inside the footprint's box or far outside it)."""
    rng = np.random.default_rng(seed)
    x, y, s = _footprint(rng, float(rng.uniform(0.0, 60.0)))
    keep = rng.random(x.size) < float(rng.uniform(0.3, 1.0))  # footprints with holes
    x, y, s = x[keep], y[keep], s[keep]
    per, look = sighting(x, y, s, 5.0)
    assert np.array_equal(per, perimeter_mask(x, y, s, 5.0))
    cells = {(round(a / 5.0), round(b / 5.0)): int(c) for a, b, c in zip(x - 2.5, y + 7.5, s, strict=True)}
    want = [
        c != 0 and any(cells.get((i + di, j + dj)) == 0 for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)))
        for (i, j), c in (
            (k, cells[k])
            for k in zip(
                np.rint((x - 2.5) / 5.0).astype(int), np.rint((y + 7.5) / 5.0).astype(int), strict=True
            )
        )
    ]
    assert per.tolist() == want
    qi = rng.integers(-25, 26, 300)
    qj = rng.integers(-25, 26, 300)
    qx = 2.5 + 5.0 * qi + rng.uniform(-2.4, 2.4, 300)
    qy = -7.5 + 5.0 * qj + rng.uniform(-2.4, 2.4, 300)
    got = look(qx, qy)
    assert got.dtype == bool and got.shape == qx.shape
    assert got.tolist() == [cells.get((int(a), int(b))) == 0 for a, b in zip(qi, qj, strict=True)]
    assert np.array_equal(got, unburned_lookup(x, y, s, 5.0)(qx, qy))


def test_ros_mps_is_recomputed_whenever_an_array_changes():
    """ros_mps keeps its last result: a write to any of the four arrays, by the map or from
    outside, gives the new Eq. 1 values; writing into a returned array changes nothing."""
    fm = FireMap(0.0, 0.0, ignition_time_s=0.0, revisit_gap_s=1.0)
    fm.record([100.0], [0.0], 50.0)
    first = fm.ros_mps()
    assert first[0] == 2.0
    first[0] = 99.0  # the caller's copy
    assert fm.ros_mps()[0] == 2.0
    fm.record([150.0], [0.0], 100.0)  # a new visit: (150 - 100) / 50
    assert fm.ros_mps()[0] == 1.0
    for name, value, want in (
        ("outer_d_m", 200.0, 2.0),
        ("inner_d_m", 50.0, 3.0),
        ("outer_t_s", 150.0, 1.5),
        ("inner_t_s", 0.0, 1.0),
    ):
        getattr(fm, name)[0] = value
        assert fm.ros_mps()[0] == want, name
