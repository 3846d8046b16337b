"""The raster fire's compiled update (fire_world_sim.fires.ring_kernel) against the numpy reference.

Truths: the numpy path (``RasterFireModel(..., compiled=False)``, the update as it was before the
kernels, and :func:`.ring_update.arrival`) gives the reference arrival times; the compiled path
must give the same bits (``numpy.array_equal``), on random small landscapes (hypothesis) and over
whole fires: several ignitions, a wind shift, fuel patches, a lake, drops that put out burning
cells and wet others, and the worcester_vt landscape. Plus an analytic check: in a homogeneous
fuel with a steady wind the arrival time along the head at distance d is d / R_h (Behave's
ellipse, R_h from fire_world_sim.fires.rothermel)."""

from __future__ import annotations

import math

import numpy as np
from fire_uav_common.scenario import FuelPatch, Ignition, Raster, Wind, load_scenario
from fire_uav_common.terrain import Lake, Terrain
from fire_world_sim.fires import ring_kernel
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.raster import PAD, RasterFireModel
from fire_world_sim.fires.ring_update import RingGeometry, arrival, blocked_nodes
from fire_world_sim.fires.rothermel import head_spread, spread_params
from hypothesis import given, settings
from hypothesis import strategies as st

from .conftest import SCENARIOS

STATE = ("t_ign", "t_out", "label", "extinguished", "_burn_type")


def same_fire(a: RasterFireModel, b: RasterFireModel) -> None:
    for name in STATE:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.last_ignition_s == b.last_ignition_s
    assert sorted(a._sources(a._t_updated).tolist()) == sorted(b._sources(b._t_updated).tolist())


def step_both(models: list[RasterFireModel], t1: float, dt: float, drops=()) -> list[list]:
    """Step each model from 0 to t1; drops: (t, x, y, r). Returns each one's events."""
    out = []
    for m in models:
        events = []
        t = 0.0
        k = 0
        while t < t1 - 1e-9:
            events += m.step(t, dt)
            t += dt
            k += 1
            for td, x, y, r in drops:
                if abs(t - td) < dt / 2:
                    events.append(("drop", tuple(m.apply_drop(x, y, r))))
        out.append(events)
    return out


@st.composite
def landscapes(draw):
    """A random padded 12 x 14 grid: ignition times, extinguished and live cells, wavelets."""
    ny, nx = 12, 14
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    n = ny * nx
    t_ign = np.where(rng.random(n) < draw(st.floats(0.1, 0.9)), rng.uniform(-50.0, 100.0, n), np.inf)
    ext = rng.random(n) < 0.1
    live = np.isfinite(t_ign) & (rng.random(n) < 0.6)
    a = rng.uniform(0.05, 5.0, n)
    e = rng.uniform(0.0, 0.95, n)
    c = a * e
    h = rng.uniform(-math.pi, math.pi, n)
    a[rng.random(n) < 0.05] = np.inf  # cells that cannot burn
    cx = np.where(np.isfinite(a), c * np.cos(h), 0.0)
    cy = np.where(np.isfinite(a), c * np.sin(h), 0.0)
    label = rng.integers(-1, 4, n).astype(np.int32)
    ii, jj = np.mgrid[PAD : ny - PAD, PAD : nx - PAD]
    tgt = (ii * nx + jj).ravel().astype(np.int64)
    t1 = draw(st.floats(-20.0, 120.0))
    cell = draw(st.sampled_from([1.0, 5.0, 30.0]))
    # ring nodes blocked by a non-burnable cell on the path (blocked_nodes of random barriers)
    blk = blocked_nodes(rng.random((ny, nx)) < draw(st.floats(0.0, 0.3))).ravel()
    return RingGeometry.of(nx, cell), tgt, t1, t_ign, ext, label, live, a, cx, cy, blk


@settings(max_examples=60, deadline=None)
@given(landscapes())
def test_compiled_arrival_equals_numpy_arrival(case) -> None:
    geom, tgt, t1, t_ign, ext, label, live, a, cx, cy, blk = case
    ref_t, ref_lab = arrival(geom, tgt, live, t1, t_ign, ext, label, a, cx, cy, blk)
    gi, gf = ring_kernel.pack_geometry(geom)
    got_t, got_lab = ring_kernel.arrival_batch(tgt, t1, t_ign, ext, label, live, a, cx, cy, gi, gf, blk)
    assert np.array_equal(got_t, ref_t)
    finite = np.isfinite(ref_t)
    assert np.array_equal(got_lab[finite], ref_lab[finite])  # the id of an unreachable cell is moot


def grass(compiled: bool, **kw) -> RasterFireModel:
    spec = Raster(
        cell_size_m=10.0,
        nx=60,
        ny=50,
        fuel_model=1,
        moisture=0.06,
        wind=(Wind(-120.0, 2.0, 20.0), Wind(400.0, 3.5, 100.0), Wind(700.0, 1.0, 250.0)),
        ignitions=(
            Ignition(120.0, 250.0, -120.0),
            Ignition(450.0, 150.0, 200.0),
            Ignition(300.0, 420.0, 350.0),
        ),
        fuel_patches=(FuelPatch(250.0, 320.0, 0.0, 300.0, 3),),
        spread_factor=3.0,
    )
    return RasterFireModel(spec, Terrain(), lakes=(Lake(330.0, 330.0, 60.0),), compiled=compiled, **kw)


def test_whole_grass_fire_is_the_same_compiled_and_in_numpy() -> None:
    """Three fires (one pre-burnt), three wind segments, a faster fuel patch and a lake."""
    ref, got = grass(False), grass(True)
    ev_ref, ev_got = step_both([ref, got], 1000.0, 1.0)
    assert np.isfinite(ref.t_ign).sum() > 800  # a fire that went somewhere
    same_fire(ref, got)
    assert ev_ref == ev_got


def test_fire_with_drops_is_the_same_compiled_and_in_numpy() -> None:
    """Drops put out burning cells and wet unburned ones; the world's 0.1 s steps."""
    drops = [(20.0 + 17.0 * k, 60.0 + (97.0 * k) % 540.0, 60.0 + (61.0 * k) % 400.0, 35.0) for k in range(40)]
    ref, got = grass(False), grass(True)
    ev_ref, ev_got = step_both([ref, got], 700.0, 0.1, drops)
    assert ref.extinguished.sum() > 10 and (ref.wet_until > -np.inf).sum() > 10  # the drops did something
    same_fire(ref, got)
    assert ev_ref == ev_got


def test_landscape_fire_is_the_same_compiled_and_in_numpy() -> None:
    """worcester_vt (per-cell fuels, slope, crown fire), 8 m/s then 15 m/s."""
    over = {
        "fires.raster.wind": [
            {"start_s": -600.0, "speed_mps": 8.0, "direction_deg": 0.0},
            {"start_s": 300.0, "speed_mps": 15.0, "direction_deg": 30.0},
        ]
    }
    s = load_scenario(SCENARIOS / "worcester_vt.yaml", overrides=over)
    ref, got = (RasterFireModel(s.fires.raster, s.terrain, lakes=s.lakes, compiled=c) for c in (False, True))
    ev_ref, ev_got = step_both([ref, got], 900.0, 1.0)
    assert np.isfinite(ref.t_ign).sum() > 50
    same_fire(ref, got)
    assert ev_ref == ev_got


def test_head_arrival_is_distance_over_head_rate() -> None:
    """Homogeneous fuel model 1, a steady east wind, flat: along the head (east of the ignition),
    T(d) - T(d0) = (d - d0) / R_h within a cell's travel (discretisation), R_h from Rothermel."""
    cs, n = 10.0, 80
    wind = 2.0
    spec = Raster(
        cell_size_m=cs,
        nx=n,
        ny=21,
        fuel_model=1,
        moisture=0.06,
        wind=(Wind(0.0, wind, 0.0),),
        ignitions=(Ignition(5.0 * cs + cs / 2, 10.0 * cs + cs / 2, 0.0),),
    )
    m = RasterFireModel(spec, Terrain())
    r_h = float(np.asarray(head_spread(spread_params(fuel_model(1), 0.06), wind, 0.0, 0.0, 0.0)[0]))
    t = 0.0
    while t < (n - 10) * cs / r_h:
        m.step(t, 1.0)
        t += 1.0
    row = m.t_ign[PAD + 10, PAD + 5 :]
    d = np.arange(row.size) * cs
    ok = np.isfinite(row)
    assert ok.sum() > 40
    expected = d[ok] / r_h
    assert np.max(np.abs(row[ok] - expected)) <= cs / r_h  # within one cell's travel at the head rate


def test_truth_between_updates_is_the_same_compiled_and_in_numpy() -> None:
    """The world's 0.1 s steps against a 0.5 s update, asking the truth at every step: which
    fires burn between two updates (cells burnt out since the last one), drops and a new
    ignition included, as the numpy path says; and the compiled path skips updates that
    cannot change the fire without changing it."""
    drops = [
        (300.2 + 23.0 * k, 150.0 + (71.0 * k) % 300.0, 150.0 + (53.0 * k) % 250.0, 40.0) for k in range(12)
    ]
    ref, got = grass(False), grass(True)
    for m in (ref, got):
        m._records = []  # type: ignore[attr-defined]
    t = 0.0
    while t < 900.0 - 1e-9:
        for m in (ref, got):
            ev = m.step(t, 0.1)
            for td, x, y, r in drops:
                if abs(t + 0.1 - td) < 0.05:
                    ev.append(("drop", tuple(m.apply_drop(x, y, r))))
            m._records.append((ev, m.truth(), m.all_out))  # type: ignore[attr-defined]
        t += 0.1
    same_fire(ref, got)
    assert ref._records == got._records  # type: ignore[attr-defined]
    statuses = {tuple(r.status for r in rec[1]) for rec in ref._records}  # type: ignore[attr-defined]
    assert len(statuses) > 2  # fires started and went out along the way


@settings(max_examples=80, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(0.0, 100.0), st.floats(0.0, 60.0))
def test_burning_fires_from_the_burn_out_heap_equal_a_scan(seed, t_s, behind_s) -> None:
    """ring_kernel.active_fires from the live cells per fire less the heap's top (cells burnt out
    between the last update t0 and t_s), against a scan of every cell: burning at t_s is
    t_ign <= t_s < t_out; the cells gone by t0 leave the heap, which stays a heap."""
    rng = np.random.default_rng(seed)
    width, n_fires = 10, 4
    geom = RingGeometry.of(width, 30.0)
    gi, _ = ring_kernel.pack_geometry(geom)
    inner = np.array([i * width + j for i in range(PAD, width - PAD) for j in range(PAD, width - PAD)])
    cells = rng.choice(inner, size=int(rng.integers(1, inner.size + 1)), replace=False).astype(np.int64)
    n = width * width
    t_ign = np.full(n, np.inf)
    t_ign[cells] = rng.uniform(-50.0, 0.0, cells.size)
    t_out = np.full(n, np.inf)
    t_out[cells] = t_ign[cells] + rng.uniform(0.0, 150.0, cells.size)
    label = np.full(n, -1, dtype=np.int32)
    label[cells] = rng.integers(0, n_fires, cells.size)
    ext = np.zeros(n, dtype=bool)
    live_buf = np.zeros(n, dtype=np.int64)
    live_buf[: cells.size] = cells
    live_mask = np.zeros(n, dtype=bool)
    live_mask[cells] = True
    counts = np.bincount(label[cells] + 1, minlength=n_fires + 1).astype(np.int64)
    meta = np.array([cells.size, 0, 0, 1, 0, 0], dtype=np.int64)  # meta[3]: build the heap
    t0 = t_s - behind_s
    burning = (t_ign[cells] <= t_s) & (t_s < t_out[cells]) & (t_out[cells] > t0)
    expected = np.zeros(n_fires + 1, dtype=bool)
    expected[label[cells][burning] + 1] = True
    left = cells[t_out[cells] > t0]
    for ign_ok in (True, False):
        st_ = (
            live_buf.copy(),
            live_mask.copy(),
            np.zeros(n),
            np.zeros(n, dtype=np.int64),
            np.zeros(n, dtype=bool),
        )
        book = (*st_, counts.copy(), gi, meta.copy(), np.zeros(2))
        flags = np.zeros(n_fires + 1, dtype=bool)
        ring_kernel.active_fires(t_s, t0, ign_ok, t_ign, t_out, ext, label, *book, flags)
        assert np.array_equal(flags, expected)
        heap = book[0][: book[-2][0]]
        assert sorted(heap.tolist()) == sorted(left.tolist())
        keys = t_out[heap]
        assert all(keys[(i - 1) // 2] <= keys[i] for i in range(1, keys.size))  # a min-heap
        assert np.array_equal(book[5], np.bincount(label[left] + 1, minlength=n_fires + 1))


def test_band_heap_compacted_when_full_gives_the_same_fire() -> None:
    """A band heap far smaller than the grid (400 entries) fills up with stale entries many
    times over a fire of 800+ cells and is compacted in place: still the numpy path's fire."""
    ref, got = grass(False), grass(True)
    got._heap = (np.empty(400), *(np.empty(400, dtype=d) for d in (np.int64, np.int64, np.int32)))
    got._kst = None  # the kernels' arguments again, with this heap
    got._meta[5] = 1  # rebuilt from the band (the pre-burn's entries were in the other one)
    ev_ref, ev_got = step_both([ref, got], 1000.0, 1.0)
    assert np.isfinite(ref.t_ign).sum() > 800  # more cells ignited (one push each at least) than entries
    same_fire(ref, got)
    assert ev_ref == ev_got
