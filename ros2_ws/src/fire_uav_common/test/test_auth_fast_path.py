"""canonical_bytes' fast path (per-class plan, struct for numeric scalars) gives exactly the bytes
of the generic numpy encoding, on the real signed message types filled with random values that
rclpy's setters accept (the extremes of every integer width, float32-range and rounded floats,
NaN and infinities, empty and long sequences, nested messages)."""

import math
import struct

import numpy as np
import pytest
from fire_uav_common import auth
from hypothesis import given, settings
from hypothesis import strategies as st

msgs = pytest.importorskip("fire_uav_msgs.msg")  # built by colcon; scripts/test sources it

SIGNED = ("UavState", "FireEstimateArray", "PayloadRequest", "PerimeterMap")
_INT = {
    "boolean": None, "uint8": (0, 2**8 - 1), "int8": (-(2**7), 2**7 - 1), "uint16": (0, 2**16 - 1),
    "int16": (-(2**15), 2**15 - 1), "uint32": (0, 2**32 - 1), "int32": (-(2**31), 2**31 - 1),
    "uint64": (0, 2**64 - 1), "int64": (-(2**63), 2**63 - 1), "octet": (0, 255), "byte": (0, 255),
}  # fmt: skip
_F32_MAX = struct.unpack(">f", bytes.fromhex("7f7fffff"))[0]


def _scalar(base: str, rng: np.random.Generator):
    if base == "boolean":
        return bool(rng.integers(2))
    if base in _INT:
        lo, hi = _INT[base]
        return int(
            [lo, hi, 0, int(rng.integers(lo, hi, endpoint=True, dtype=np.uint64 if lo == 0 else np.int64))][
                rng.integers(4)
            ]
        )
    if base in ("float", "double"):
        top = _F32_MAX if base == "float" else 1.7e308
        return float(
            [0.1, -0.0, math.inf, -math.inf, math.nan, top, -top, rng.normal() * 1e3][rng.integers(8)]
        )
    if base.startswith("string"):
        return "".join(chr(int(c)) for c in rng.integers(32, 0x3000, size=int(rng.integers(0, 6))))
    return None


def _fill(msg, rng: np.random.Generator, depth: int = 0):
    for name, ftype in msg.get_fields_and_field_types().items():
        base, is_array = auth._element_type(ftype)
        if base in ("octet", "byte", "char"):
            continue  # left at their defaults: rclpy wants bytes objects there
        fixed = ftype.endswith("]") and not ftype.startswith("sequence<")
        n = int(ftype[ftype.index("[") + 1 : -1]) if fixed else int(rng.integers(0, 4 if depth else 6))
        if _scalar(base, rng) is None and not base.startswith("string"):  # nested message type
            pkg, name_ = base.split("/")[0], base.split("/")[-1]
            cls = getattr(__import__(f"{pkg}.msg", fromlist=[name_]), name_)
            if depth > 2:
                continue
            items = [_fill(cls(), rng, depth + 1) for _ in range(n if is_array else 1)]
            setattr(msg, name, items if is_array else items[0])
            continue
        if is_array:
            setattr(msg, name, [_scalar(base, rng) for _ in range(n)])
        else:
            setattr(msg, name, _scalar(base, rng))
    return msg


def _generic(msg) -> bytes:
    """The generic path alone: ``_encode`` field by field, nested messages by this function
    (no runs, no array shortcuts, no flattening, no kept plans)."""
    out: list[bytes] = []
    for name, ftype in msg.get_fields_and_field_types().items():
        if name == "auth":
            continue
        value = getattr(msg, name)
        base, is_array = auth._element_type(ftype)
        if base in auth._PRIMITIVE or base.startswith(("string", "wstring")):
            auth._encode(value, ftype, out)
            continue
        items = list(value) if is_array else [value]
        if is_array:
            out.append(struct.pack(">Q", len(items)))
        out.extend(_generic(item) for item in items)
    return b"".join(out)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(SIGNED))
def test_fast_path_bytes_equal_the_generic_encoding(seed, kind):
    msg = _fill(getattr(msgs, kind)(), np.random.default_rng(seed))
    fast = auth.canonical_bytes(msg)
    assert fast == _generic(msg)
    assert auth.canonical_bytes(msg) == fast  # the cached plan gives the same bytes again


def test_the_plan_is_kept_per_generated_class_only():
    auth.canonical_bytes(msgs.UavState())
    assert msgs.UavState in auth._PLANS
    assert all(isinstance(getattr(c, "_fields_and_field_types", None), dict) for c in auth._PLANS)
