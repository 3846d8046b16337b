"""Field-for-field equality of the agent's ROS-free values, for tests that compare two decoders."""

from __future__ import annotations

import numpy as np


def same(a, b) -> bool:
    """Equal field for field: dataclasses, tuples and dicts element-wise, arrays by dtype, shape and
    value, floats by ``repr`` (so NaN equals NaN and 0.0 differs from -0.0; repr round-trips a float)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b, equal_nan=True)
    if isinstance(a, tuple):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if hasattr(a, "__dataclass_fields__"):
        return all(same(getattr(a, f), getattr(b, f)) for f in a.__dataclass_fields__)
    return repr(a) == repr(b)
