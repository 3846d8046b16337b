"""canonical_bytes field by field against encodings written out by hand from the module doc:
every array and sequence with an 8-byte big-endian length first, strings as UTF-8 with their
length, fixed and bounded arrays, bytes-valued octet fields, nested sequences; the per-class plan
and the struct fast path (used, and equal); tag bytes as the wire may hand them over."""

import struct

import numpy as np
import pytest
from fire_uav_common import auth
from fire_uav_common.auth import TAG_BYTES, Authenticator, canonical_bytes, parse_key


class Generated:
    """Shaped as rosidl generates a message class: the field table a class attribute, read
    through a classmethod that returns a copy (no fire_uav_msgs needed: the mutation stage runs
    without the ROS build)."""

    _fields_and_field_types = {"stamp": "int64", "auth": "uint8[32]", "kind": "uint8", "x": "float"}

    def __init__(self) -> None:
        self.stamp, self.auth, self.kind, self.x = 5, bytes(32), 2, 0.5

    @classmethod
    def get_fields_and_field_types(cls) -> dict:
        return dict(cls._fields_and_field_types)


class Typed:
    def __init__(self, types: dict, **values) -> None:
        self._types = types
        self.__dict__.update(values)

    def get_fields_and_field_types(self) -> dict:
        return dict(self._types)


def Q(n: int) -> bytes:
    return struct.pack(">Q", n)


def test_strings_sequences_and_nested_sequences_by_hand():
    inner = [Typed({"v": "int16"}, v=-3), Typed({"v": "int16"}, v=4)]
    m = Typed(
        {"names": "sequence<string>", "w": "wstring", "b": "string<5>", "kids": "sequence<pkg/Inner>",
         "auth": "uint8[32]", "after": "uint32"},
        names=["a", "bc"], w="\u00e9", b="xy", kids=inner, auth=bytes(32), after=2**32 - 1,
    )  # fmt: skip
    want = (
        Q(2) + Q(1) + b"a" + Q(2) + b"bc"  # sequence<string>
        + Q(2) + "\u00e9".encode()  # a wstring is UTF-8 too
        + Q(2) + b"xy"  # a bounded string is a string, not a sequence
        + Q(2) + struct.pack(">h", -3) + struct.pack(">h", 4)  # nested sequence
        + b"\xff\xff\xff\xff"  # a field after auth is still covered
    )  # fmt: skip
    assert canonical_bytes(m) == want


def test_fixed_bounded_and_bytes_valued_arrays_by_hand():
    m = Typed(
        {"f": "float[3]", "s": "sequence<float, 5>", "o": "octet[2]", "c": "char[2]", "k": "octet",
         "u": "uint8", "d": "double"},
        f=np.array([1.0, -2.0, 0.5]), s=[0.25], o=b"\x01\x02", c=[b"a", b"b"], k=7,
        u=np.uint8(9), d=np.float64(0.1),
    )  # fmt: skip
    want = (
        Q(3) + struct.pack(">3f", 1.0, -2.0, 0.5)
        + Q(1) + struct.pack(">f", 0.25)
        + Q(2) + b"\x01\x02"
        + Q(2) + b"ab"
        + b"\x07"  # an octet scalar given as an int
        + b"\x09"  # a numpy scalar (not an int) in a numeric field
        + struct.pack(">d", 0.1)
    )  # fmt: skip
    assert canonical_bytes(m) == want


def test_the_plan_is_read_once_per_generated_class_and_the_fast_path_is_taken(monkeypatch):
    monkeypatch.setattr(auth, "_PLANS", {})
    calls = []
    monkeypatch.setattr(
        Generated,
        "get_fields_and_field_types",
        classmethod(lambda cls: calls.append(1) or dict(cls._fields_and_field_types)),
    )
    m = Generated()
    first = canonical_bytes(m)
    assert first == struct.pack(">q", 5) + b"\x02" + struct.pack(">f", 0.5)  # auth skipped, order kept
    assert canonical_bytes(m) == first and len(calls) == 1
    plan = auth._PLANS[Generated]
    assert [row[0] for row in plan] == ["stamp", "kind", "x"]
    assert canonical_bytes(Typed({"a": "int8"}, a=1)) == b"\x01" and Typed not in auth._PLANS
    # numeric scalars skip the numpy encoder altogether; the nested header still uses it
    used = []
    monkeypatch.setattr(auth, "_encode", lambda v, t, out, _e=auth._encode: used.append(t) or _e(v, t, out))
    assert canonical_bytes(Typed({"a": "int32", "b": "double", "c": "boolean"}, a=-1, b=0.5, c=True)) == (
        struct.pack(">i", -1) + struct.pack(">d", 0.5) + b"\x01"
    )
    assert used == []


def test_tags_arrive_as_bytes_lists_or_arrays_and_bad_bodies_fail_closed():
    a = Authenticator(parse_key("ab" * 32))
    m = Typed({"x": "float", "auth": "uint8[32]"}, x=1.5, auth=bytes(32))
    a.sign(m, "/fleet/state", 1, 2)
    tag = bytes(m.auth)
    for form in (tag, bytearray(tag), list(tag), np.frombuffer(tag, dtype=np.uint8)):
        m.auth = form
        assert a.check(m, "/fleet/state", 1, 2)
    m.auth = tag
    m.x = "not a number"  # canonical_bytes raises inside check: a failed check, not an exception
    assert a.check(m, "/fleet/state", 1, 2) is False
    assert len(tag) == TAG_BYTES


def test_key_errors_and_repr_are_exact():
    with pytest.raises(ValueError, match=r"^fleet key must be hex digits only \(0-9, a-f\)$"):
        parse_key("zz" * 32)
    assert repr(Authenticator(bytes(32))) == "Authenticator(<key>)"
