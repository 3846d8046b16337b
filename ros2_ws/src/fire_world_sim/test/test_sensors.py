"""Sensor rates, noise statistics, dropout, altimeter range."""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_common.scenario import Sensors
from fire_world_sim.sensors import SensorSuite, samples_due

N = 20000


def test_rates_on_the_ns_grid() -> None:
    dt = 10_000_000  # 0.01 s
    counts = {r: sum(samples_due(j * dt, (j + 1) * dt, r) for j in range(100)) for r in (100, 25, 10)}
    assert counts == {100: 100, 25: 25, 10: 10}


def test_gps_noise_and_dropout() -> None:
    s = SensorSuite(Sensors(), seed=3, uav_id=1)
    samples = [s.sample_gps(i, 10.0, -5.0) for i in range(N)]
    valid = [p for p in samples if p is not None]
    assert len(valid) / N == pytest.approx(0.9, abs=0.01)
    ex = np.array([p.x_m - 10.0 for p in valid])
    ey = np.array([p.y_m + 5.0 for p in valid])
    assert ex.std() == pytest.approx(3.0, rel=0.03) and ey.std() == pytest.approx(3.0, rel=0.03)
    assert abs(ex.mean()) < 0.1 and valid[0].variance_m2 == 9.0


def test_altimeter_noise_dropout_and_range() -> None:
    s = SensorSuite(Sensors(), seed=3, uav_id=1)
    valid = [a for a in (s.sample_altimeter(i, 20.0) for i in range(N)) if a is not None]
    assert len(valid) / N == pytest.approx(0.8, abs=0.01)
    assert np.std([a.range_m for a in valid]) == pytest.approx(1.5, rel=0.03)
    assert all(s.sample_altimeter(i, 41.0) is None for i in range(200))
    assert all(s.sample_altimeter(i, -0.5) is None for i in range(200))


def test_gyro_noise_and_dropout() -> None:
    s = SensorSuite(Sensors(), seed=5, uav_id=0)
    valid = [g for g in (s.sample_gyro(i, 0.2) for i in range(N)) if g is not None]
    assert len(valid) / N == pytest.approx(0.7, abs=0.01)
    w = np.array([g.omega_z_radps for g in valid])
    assert w.std() == pytest.approx(0.3, rel=0.03) and w.mean() == pytest.approx(0.2, abs=0.01)


def test_fire_sensor_noise() -> None:
    s = SensorSuite(Sensors(), seed=5, uav_id=0)
    d = [s.sample_fires(0, 0.0, 0.0, [(1, 30.0, 40.0, 10.0)])[0] for _ in range(5000)]
    assert np.std([x.x_m for x in d]) == pytest.approx(2.0, rel=0.05)
    assert np.std([x.extent_m for x in d]) == pytest.approx(1.0, rel=0.05)
    assert d[0].track_id == 1 and d[0].range_m == pytest.approx(50.0, abs=10)


def test_streams_differ_per_uav_and_repeat_per_seed() -> None:
    a = SensorSuite(Sensors(), 1, 0).sample_gps(0, 0, 0)
    b = SensorSuite(Sensors(), 1, 0).sample_gps(0, 0, 0)
    c = SensorSuite(Sensors(), 1, 1).sample_gps(0, 0, 0)
    assert a == b and a != c


def test_sample_instants_are_half_open_and_survive_ns_rounding() -> None:
    # (prev, now]: the instant 0.1 s belongs to the step that ends on it, not to the next one
    assert samples_due(0, 100_000_000, 10.0) and not samples_due(100_000_000, 150_000_000, 10.0)
    # 1/3 s is 333_333_333.3 ns: the step ending on the integer ns just before it still takes it
    assert samples_due(300_000_000, 333_333_333, 3.0)
    assert sum(samples_due(j * 10_000_000, (j + 1) * 10_000_000, 3.0) for j in range(300)) == 9


def test_altimeter_range_is_inclusive_and_sample_fields() -> None:
    s = SensorSuite(Sensors(), seed=4, uav_id=2)
    for h in (0.0, 40.0):  # both ends of [0, max_range_m] read
        got = [a for a in (s.sample_altimeter(i, h) for i in range(400)) if a is not None]
        assert len(got) / 400 == pytest.approx(0.8, abs=0.08), h
        assert got[0].max_range_m == 40.0 and got[0].stamp_ns < 400
        assert np.mean([a.range_m for a in got]) == pytest.approx(h, abs=0.3)


def test_stamps_pass_through() -> None:
    s = SensorSuite(Sensors(), seed=8, uav_id=0)
    g = next(x for x in (s.sample_gyro(123 + i, 0.0) for i in range(50)) if x is not None)
    p = next(x for x in (s.sample_gps(456 + i, 0.0, 0.0) for i in range(50)) if x is not None)
    assert 123 <= g.stamp_ns < 173 and 456 <= p.stamp_ns < 506
    assert s.sample_fires(789, 0.0, 0.0, [(4, 1.0, 1.0, 1.0)])[0].stamp_ns == 789


def test_fire_sensor_dropout_extent_clip_and_range_from_the_uav() -> None:
    from dataclasses import replace

    spec = Sensors()
    spec = replace(spec, fire=replace(spec.fire, p_valid=0.6))
    s = SensorSuite(spec, seed=6, uav_id=3)
    ux, uy = 100.0, -50.0
    seen = [(1, 130.0, -10.0, 0.5), (2, 60.0, -80.0, 12.0)]  # fire 1 barely extends: clipped at 0
    runs = [s.sample_fires(0, ux, uy, seen) for _ in range(4000)]
    d1 = [d for r in runs for d in r if d.track_id == 1]
    d2 = [d for r in runs for d in r if d.track_id == 2]
    assert len(d1) / 4000 == pytest.approx(0.6, abs=0.03) and len(d2) / 4000 == pytest.approx(0.6, abs=0.03)
    e1 = np.array([d.extent_m for d in d1])
    assert e1.min() == 0.0
    assert np.mean(e1 == 0.0) == pytest.approx(0.3085, abs=0.03)  # P(0.5 + N(0, 1) < 0) = Phi(-0.5)
    assert np.mean([d.extent_m for d in d2]) == pytest.approx(12.0, abs=0.06)
    for d in d1[:50] + d2[:50]:  # range: from the UAV to the reported position
        assert d.range_m == pytest.approx(np.hypot(d.x_m - ux, d.y_m - uy), abs=1e-9)
    y2 = np.array([d.y_m for d in d2])
    assert y2.std() == pytest.approx(2.0, rel=0.06) and y2.mean() == pytest.approx(-80.0, abs=0.1)
    assert np.mean([d.x_m for d in d2]) == pytest.approx(60.0, abs=0.1)
    assert s.sample_fires(0, ux, uy, []) == []


def test_noise_axes_are_independent_and_every_sensor_stream_differs_per_uav() -> None:
    s = SensorSuite(Sensors(), seed=9, uav_id=0)
    g = [p for p in (s.sample_gps(i, 0.0, 0.0) for i in range(4000)) if p is not None]
    assert abs(np.corrcoef([p.x_m for p in g], [p.y_m for p in g])[0, 1]) < 0.08  # N(0, sigma^2 I)
    f = [s.sample_fires(0, 0.0, 0.0, [(1, 0.0, 0.0, 10.0)])[0] for _ in range(3000)]
    xs, ys, es = (np.array([getattr(d, k) for d in f]) for k in ("x_m", "y_m", "extent_m"))
    assert abs(np.corrcoef(xs, ys)[0, 1]) < 0.08 and abs(np.corrcoef(xs, es)[0, 1]) < 0.08
    assert abs(np.corrcoef(ys, es)[0, 1]) < 0.08
    a, b = SensorSuite(Sensors(), 2, 0), SensorSuite(Sensors(), 2, 1)
    alt = [(a.sample_altimeter(i, 20.0), b.sample_altimeter(i, 20.0)) for i in range(20)]
    gyro = [(a.sample_gyro(i, 0.0), b.sample_gyro(i, 0.0)) for i in range(20)]
    fire = [
        (a.sample_fires(0, 0, 0, [(1, 0.0, 0.0, 5.0)]), b.sample_fires(0, 0, 0, [(1, 0.0, 0.0, 5.0)]))
        for _ in range(5)
    ]
    assert any(x != y for x, y in alt) and any(x != y for x, y in gyro) and any(x != y for x, y in fire)
