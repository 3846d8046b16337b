"""fire_uav_common.auth: HMAC-SHA256 against RFC 4231's test vectors, tamper and binding properties."""

import hashlib
import hmac
import secrets
import struct

import pytest
from fire_uav_common.auth import TAG_BYTES, Authenticator, canonical_bytes, new_key_hex, parse_key
from hypothesis import given, settings
from hypothesis import strategies as st


def test_primitive_is_rfc4231_hmac_sha256():
    # RFC 4231 test case 2 (key "Jefe"): the library primitive the module relies on
    mac = hmac.new(b"Jefe", b"what do ya want for nothing?", hashlib.sha256).hexdigest()
    assert mac == "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843"


def test_key_parsing_errors_do_not_echo_the_key():
    assert len(parse_key(new_key_hex())) == 32
    assert new_key_hex() != new_key_hex()
    with pytest.raises(ValueError, match="64 hex digits, got 5 characters"):
        parse_key("abcde")
    bad = "zz" * 32
    with pytest.raises(ValueError, match="hex digits only") as e:
        parse_key(bad)
    assert bad not in str(e.value)
    with pytest.raises(ValueError, match="32 bytes, got 3"):
        Authenticator(b"abc")
    assert "key" in repr(Authenticator(bytes(32))) and bytes(32).hex() not in repr(Authenticator(bytes(32)))


class Msg:
    """Stand-in for a generated ROS message: a field table, a byte body and an ``auth`` field."""

    _FIELDS = {"body": "sequence<uint8>", "auth": "uint8[32]"}

    def __init__(self, body: bytes) -> None:
        self.body = body
        self.auth = bytes(TAG_BYTES)

    @classmethod
    def get_fields_and_field_types(cls) -> dict:
        return dict(cls._FIELDS)


class Typed:
    """A stand-in with one field of every shape the encoder handles (nested, strings, arrays)."""

    def __init__(self, **values) -> None:
        self.__dict__.update(values)

    def get_fields_and_field_types(self) -> dict:
        return self._types


def typed(types: dict, **values) -> Typed:
    t = Typed(**values)
    t._types = types
    return t


@settings(max_examples=100, deadline=None)
@given(
    st.binary(max_size=200),
    st.integers(0, 255),
    st.integers(0, 2**40),
    st.integers(0, 199),
    st.integers(0, 7),
)
def test_any_change_to_payload_sender_step_or_topic_fails(body, sender, step, pos, bit):
    a = Authenticator(secrets.token_bytes(32))
    m = Msg(body)
    a.sign(m, "/fleet/state", sender, step)
    assert len(m.auth) == TAG_BYTES and m.auth != bytes(TAG_BYTES)
    assert a.check(m, "/fleet/state", sender, step)
    assert not a.check(m, "/fleet/fires", sender, step)
    assert not a.check(m, "/fleet/state", sender + 1, step)
    assert not a.check(m, "/fleet/state", sender, step + 1)
    assert not Authenticator(secrets.token_bytes(32)).check(m, "/fleet/state", sender, step)
    if body:
        i = pos % len(body)
        flipped = Msg(body[:i] + bytes([body[i] ^ (1 << bit)]) + body[i + 1 :])
        flipped.auth = m.auth
        assert not a.check(flipped, "/fleet/state", sender, step)


@settings(max_examples=100, deadline=None)
@given(st.one_of(st.binary(), st.lists(st.integers(0, 255), max_size=40), st.none(), st.integers()))
def test_garbage_tags_are_rejected_not_raised(tag):
    a = Authenticator(bytes(range(32)))
    m = Msg(b"x")
    m.auth = tag
    assert a.check(m, "/t", 0, 0) is False


def test_canonical_bytes_are_field_widths_big_endian_without_padding():
    # an independent hand encoding: u8 7 | f32 0.1 | i32 -2 | seq<u16> [1, 2] | string "ab" | nested
    inner = typed({"b": "boolean"}, b=True)
    m = typed(
        {"a": "uint8", "x": "float", "i": "int32", "s": "sequence<uint16>", "t": "string",
         "n": "std_msgs/Header", "auth": "uint8[32]"},
        a=7, x=0.1, i=-2, s=[1, 2], t="ab", n=inner, auth=bytes(32),
    )  # fmt: skip
    want = (
        b"\x07" + struct.pack(">f", 0.1) + struct.pack(">i", -2)
        + struct.pack(">Q", 2) + b"\x00\x01\x00\x02"
        + struct.pack(">Q", 2) + b"ab" + b"\x01"
    )  # fmt: skip
    assert canonical_bytes(m) == want


def test_a_float32_field_checks_after_the_wire_rounded_it():
    # the sender may hold a double in a float32 field; the receiver only sees it rounded
    a = Authenticator(bytes(range(32)))
    sent = typed({"w": "float", "auth": "uint8[32]"}, w=0.1, auth=bytes(32))
    a.sign(sent, "/fleet/state", 1, 3)
    received = typed({"w": "float", "auth": "uint8[32]"}, w=struct.unpack(">f", struct.pack(">f", 0.1))[0])
    received.auth = sent.auth
    assert received.w != sent.w and a.check(received, "/fleet/state", 1, 3)
    received.w = 0.2
    assert not a.check(received, "/fleet/state", 1, 3)
