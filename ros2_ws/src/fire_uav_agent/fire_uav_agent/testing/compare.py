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


def assert_same_message(a, b, path: str = "msg") -> None:
    """Assert two ROS messages equal slot for slot (duck-typed by ``get_fields_and_field_types``, so
    no ROS import here); floats by repr, so NaN equals NaN. ``path`` names the slot that differs."""
    if hasattr(a, "get_fields_and_field_types"):
        assert type(a) is type(b), path
        for name in a.get_fields_and_field_types():
            assert_same_message(getattr(a, name), getattr(b, name), f"{path}.{name}")
    elif isinstance(a, (list, tuple, bytes, np.ndarray)) or hasattr(a, "typecode"):
        a, b = list(a), list(b)
        assert len(a) == len(b), path
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            assert_same_message(x, y, f"{path}[{k}]")
    elif isinstance(a, (float, np.floating)) or isinstance(b, (float, np.floating)):
        assert repr(float(a)) == repr(float(b)), f"{path}: {a!r} != {b!r}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"
