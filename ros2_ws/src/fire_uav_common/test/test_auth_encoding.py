"""canonical_bytes field by field against encodings written out by hand from the module doc:
every array and sequence with an 8-byte big-endian length first, strings as UTF-8 with their
length, fixed and bounded arrays, bytes-valued octet fields, nested sequences; the per-class plan
and the struct fast path (used, and equal); tag bytes as the wire may hand them over."""

import array
import math
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


class Stamp:
    _fields_and_field_types = {"sec": "int32", "nanosec": "uint32"}

    def __init__(self, sec: int = 1, nanosec: int = 2) -> None:
        self.sec, self.nanosec = sec, nanosec

    @classmethod
    def get_fields_and_field_types(cls) -> dict:
        return dict(cls._fields_and_field_types)


class Item:
    _fields_and_field_types = {"id": "uint16", "t": "pkg/Stamp", "auth": "uint8[4]", "w": "double"}

    def __init__(self, i: int) -> None:
        self.id, self.t, self.auth, self.w = i, Stamp(i, 7), b"zzzz", 0.5 * i

    @classmethod
    def get_fields_and_field_types(cls) -> dict:
        return dict(cls._fields_and_field_types)


class Outer:
    """A generated-shaped message with a nested message, arrays as rclpy holds them, a string and
    a sequence of nested messages: the flattened plan's bytes, written out by hand."""

    _fields_and_field_types = {
        "t": "pkg/Stamp", "frame": "string", "a": "uint8", "cov": "double[2]", "ids": "sequence<uint16>",
        "f": "sequence<float>", "items": "sequence<pkg/Item>", "auth": "uint8[32]", "last": "boolean",
        "k": "octet", "none": "sequence<uint8>", "words": "sequence<wstring>",
    }  # fmt: skip

    def __init__(self) -> None:
        import array

        self.t, self.frame, self.a = Stamp(-1, 3), "map", 9
        self.cov = np.array([0.25, -1.0])
        self.ids = array.array("H", [1, 65535])
        self.f = array.array("f", [0.1])
        self.items = [Item(1), Item(2)]
        self.auth, self.last = bytes(32), True
        self.k, self.none, self.words = 7, array.array("B"), ["\u00e9"]

    @classmethod
    def get_fields_and_field_types(cls) -> dict:
        return dict(cls._fields_and_field_types)


def test_a_generated_message_is_flattened_into_runs_with_the_same_bytes(monkeypatch):
    monkeypatch.setattr(auth, "_PLANS", {})
    m = Outer()
    want = (
        struct.pack(">iI", -1, 3) + Q(3) + b"map" + b"\x09"
        + Q(2) + struct.pack(">2d", 0.25, -1.0)  # a fixed array has its length too
        + Q(2) + struct.pack(">2H", 1, 65535)
        + Q(1) + struct.pack(">f", array_f32(0.1))
        + Q(2) + struct.pack(">HiId", 1, 1, 7, 0.5) + struct.pack(">HiId", 2, 2, 7, 1.0)
        + b"\x01"
        + b"\x07"  # an octet: not a struct scalar, _encode's
        + Q(0)  # an empty array.array
        + Q(1) + Q(2) + "\u00e9".encode()  # a sequence of wstrings is no sequence of messages
    )  # fmt: skip
    assert canonical_bytes(m) == want
    assert [s.names for s in auth._PLANS[Outer]] == [
        ("t.sec", "t.nanosec"), ("frame",), ("a",), ("cov",), ("ids",), ("f",), ("items",), ("last",),
        ("k",), ("none",), ("words",),
    ]  # fmt: skip
    assert [s.names for s in auth._PLANS[Item]] == [("id", "t.sec", "t.nanosec", "w")]  # auth left out
    # the shortcuts give the numpy cast's bytes: the same message held as plain lists
    m.cov, m.ids, m.f = [0.25, -1.0], [1, 65535], [array_f32(0.1)]
    assert canonical_bytes(m) == want
    m.frame = b"map"  # not a str: _encode's str() of it
    assert canonical_bytes(m) == want.replace(Q(3) + b"map", Q(6) + b"b'map'")
    m.frame, m.ids = "map", array.array("u", "ab")  # a typecode with no number: _encode refuses it
    with pytest.raises(ValueError):
        canonical_bytes(m)


def test_the_generic_encoder_writes_nested_messages_alone_and_in_sequences():
    """_encode, the path every shortcut falls back to, on nested messages (what a message that
    is not a generated class holds): one as its fields, a sequence with its length first."""
    out: list[bytes] = []
    auth._encode([Stamp(1, 2), Stamp(-3, 4)], "sequence<builtin_interfaces/Time>", out)
    auth._encode(Stamp(5, 6), "builtin_interfaces/Time", out)
    auth._encode([], "pkg/Stamp[]", out)
    assert b"".join(out) == Q(2) + struct.pack(">iIiI", 1, 2, -3, 4) + struct.pack(">iI", 5, 6) + Q(0)


def array_f32(x: float) -> float:
    return struct.unpack(">f", struct.pack(">f", x))[0]


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
    assert [step.names for step in plan] == [("stamp", "kind", "x")]  # one run, one struct call
    assert canonical_bytes(Typed({"a": "int8"}, a=1)) == b"\x01" and Typed not in auth._PLANS
    # numeric scalars skip the numpy encoder altogether; the nested header still uses it
    used = []
    monkeypatch.setattr(auth, "_encode", lambda v, t, out, _e=auth._encode: used.append(t) or _e(v, t, out))
    assert canonical_bytes(Typed({"a": "int32", "b": "double", "c": "boolean"}, a=-1, b=0.5, c=True)) == (
        struct.pack(">i", -1) + struct.pack(">d", 0.5) + b"\x01"
    )
    assert used == []


def test_runs_of_scalars_split_at_other_fields_and_fall_back_field_by_field():
    """A run packs its fields as one call per field would; a value a run cannot pack (out of
    range, or not a plain number) sends the whole run through the numpy cast, field by field."""
    fields = {"a": "uint8", "b": "float", "s": "string", "c": "int16", "d": "double", "e": "boolean"}

    def msg(**kw):
        vals = {"a": 1, "b": 0.5, "s": "hi", "c": -2, "d": 0.25, "e": False} | kw
        return Typed(dict(fields), **vals)

    tail = struct.pack(">hd", -2, 0.25) + b"\x00"
    assert canonical_bytes(msg()) == b"\x01" + struct.pack(">f", 0.5) + Q(2) + b"hi" + tail
    # 300 in a uint8: struct refuses; numpy's unsafe cast wraps it to 44, and b is still packed
    assert canonical_bytes(msg(a=300)) == b"\x2c" + struct.pack(">f", 0.5) + Q(2) + b"hi" + tail
    # a float32 field beyond float32's range: numpy's cast gives inf, as the wire does
    assert canonical_bytes(msg(b=1e40)) == b"\x01" + struct.pack(">f", math.inf) + Q(2) + b"hi" + tail
    # a numpy scalar in the second run: that run goes through _encode, the first does not
    assert canonical_bytes(msg(d=np.float32(0.25))) == canonical_bytes(msg())


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
