"""The perimeter benchmark's analytic helper: the time mean of the worst angle's error when a
stale head's sawtooth rises over a constant floor."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_perimeter", ROOT / "scripts/bench_perimeter.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize(("floor", "peak"), [(9.0, 50.0), (9.0, 20.0), (9.0, 9.0), (9.0, 3.0), (0.0, 40.0)])
def test_sawtooth_mean_is_the_time_mean_of_the_larger(bench, floor, peak):
    u = (np.arange(200_000) + 0.5) / 200_000  # the sawtooth's phase, uniform over a period
    assert bench._sawtooth_mean(floor, peak) == pytest.approx(np.mean(np.maximum(floor, peak * u)), rel=1e-6)
