"""fire_uav_common.auth: HMAC-SHA256 against RFC 4231's test vectors, tamper and binding properties."""

import hashlib
import hmac
import secrets

import pytest
from fire_uav_common.auth import TAG_BYTES, Authenticator, new_key_hex, parse_key
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
    """Stand-in for a ROS message with an ``auth`` field; serialised as its fields' bytes."""

    def __init__(self, body: bytes) -> None:
        self.body = body
        self.auth = bytes(TAG_BYTES)


def ser(m: Msg) -> bytes:
    return bytes(m.auth) + m.body


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
    a.sign(m, "/fleet/state", sender, step, ser)
    assert len(m.auth) == TAG_BYTES and m.auth != bytes(TAG_BYTES)
    assert a.check(m, "/fleet/state", sender, step, ser)
    assert not a.check(m, "/fleet/fires", sender, step, ser)
    assert not a.check(m, "/fleet/state", sender + 1, step, ser)
    assert not a.check(m, "/fleet/state", sender, step + 1, ser)
    assert not Authenticator(secrets.token_bytes(32)).check(m, "/fleet/state", sender, step, ser)
    if body:
        i = pos % len(body)
        flipped = Msg(body[:i] + bytes([body[i] ^ (1 << bit)]) + body[i + 1 :])
        flipped.auth = m.auth
        assert not a.check(flipped, "/fleet/state", sender, step, ser)


@settings(max_examples=100, deadline=None)
@given(st.one_of(st.binary(), st.lists(st.integers(0, 255), max_size=40), st.none(), st.integers()))
def test_garbage_tags_are_rejected_not_raised(tag):
    a = Authenticator(bytes(range(32)))
    m = Msg(b"x")
    m.auth = tag
    assert a.check(m, "/t", 0, 0, ser) is False
