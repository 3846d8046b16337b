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
