"""``testing.compare.same``: the equality the byte-codec tests rest on must tell values apart."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_agent.testing.compare import same


@dataclass(frozen=True)
class _P:
    a: float
    b: tuple


def test_equal_values_are_the_same_nan_included():
    assert same(_P(math.nan, (1, np.arange(3.0))), _P(math.nan, (1, np.arange(3.0))))
    assert same(np.array([math.nan, 1.0]), np.array([math.nan, 1.0]))


def test_every_kind_of_difference_is_seen():
    assert not same(1.0, 1.0 + 1e-15)
    assert not same(0.0, -0.0)
    assert not same(1, 1.0)  # the type, as a decoder returning floats for ints would
    assert not same(math.nan, 1.0)
    assert not same(np.zeros(3), np.zeros(4))
    assert not same(np.zeros((2, 2)), np.zeros(4))
    assert not same(np.zeros(3), np.zeros(3, dtype=np.float32))
    assert not same(np.array([1.0, math.nan]), np.array([1.0, 2.0]))
    assert not same((1, 2), (1, 2, 3))
    assert not same((1, 2), (1, 3))
    assert not same(_P(1.0, ()), _P(2.0, ()))
    assert not same(_P(1.0, (np.zeros(2),)), _P(1.0, (np.ones(2),)))


def test_large_arrays_inside_a_dataclass_are_compared_whole():
    """Not by repr, which elides the middle of a long array."""
    x = np.zeros(5000)
    y = x.copy()
    y[2500] = 1.0
    assert not same(_P(1.0, (x,)), _P(1.0, (y,)))
    assert same(_P(1.0, (x,)), _P(1.0, (x.copy(),)))


@dataclass(frozen=True)
class _Big:
    v: np.ndarray


def test_a_dataclass_holding_an_array_directly_is_compared_field_by_field():
    x = np.zeros(5000)
    y = x.copy()
    y[2500] = 1.0
    assert repr(_Big(x)) == repr(_Big(y))  # what the field-by-field branch is for
    assert not same(_Big(x), _Big(y))
