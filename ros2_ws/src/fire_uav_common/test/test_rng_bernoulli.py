"""rng.bernoulli: the loss draw depends only on its arguments and has the asked-for rate."""

from __future__ import annotations

import math

import pytest
from fire_uav_common.rng import bernoulli


def test_rate_is_p_within_binomial_bounds():
    n = 20000
    for p in (0.05, 0.2, 0.5):
        hits = sum(bernoulli(p, 7, "loss", j % 5, 1, j // 5, 0) for j in range(n))
        sd = math.sqrt(n * p * (1 - p))
        assert abs(hits - n * p) < 5 * sd, (p, hits)


def test_same_arguments_same_draw_in_any_order():
    args = [(3, "loss", j, i, s, t) for j in range(3) for i in range(3) for s in range(50) for t in range(3)]
    first = [bernoulli(0.3, *a) for a in args]
    again = [bernoulli(0.3, *a) for a in reversed(args)][::-1]
    assert first == again


def test_draws_differ_between_seeds_and_purposes():
    a = [bernoulli(0.5, 1, "loss", 0, 1, s, 0) for s in range(400)]
    b = [bernoulli(0.5, 2, "loss", 0, 1, s, 0) for s in range(400)]
    c = [bernoulli(0.5, 1, "other", 0, 1, s, 0) for s in range(400)]
    assert a != b and a != c
    assert 0.4 < sum(x == y for x, y in zip(a, b, strict=True)) / 400 < 0.6  # independent: ~half agree


def test_edges_and_errors():
    assert not any(bernoulli(0.0, 1, "loss", 0, 1, s, 0) for s in range(100))
    assert all(bernoulli(1.0, 1, "loss", 0, 1, s, 0) for s in range(100))
    with pytest.raises(ValueError, match=r"probability must be in \[0, 1\], got 1.5"):
        bernoulli(1.5, 1, "loss", 0)
    with pytest.raises(ValueError, match="seed and ids must be >= 0"):
        bernoulli(0.5, 1, "loss", -1)
