"""fire_uav_common.auth: HMAC-SHA256 against RFC 4231's test vectors, tamper and binding properties."""

import hashlib
import hmac
import secrets
import struct

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
    with pytest.raises(ValueError) as e:
        parse_key(bad)
    assert str(e.value) == "fleet key must be hex digits only (0-9, a-f)"  # and so never the key
    with pytest.raises(ValueError, match="32 bytes, got 3"):
        Authenticator(b"abc")
    assert repr(Authenticator(bytes(32))) == "Authenticator(<key>)"  # never the key


HEADER = b"\x00\x01\x00\x00"  # a CDR encapsulation header (little-endian CDR)


def serialised(body: bytes) -> bytes:
    """Stand-in for a serialised message: a header, the fields' bytes, a zero auth field last."""
    return HEADER + body + bytes(TAG_BYTES)


def test_the_tag_is_the_documented_hmac_of_the_bytes_before_it():
    """An independent hand computation of docs/security.md's construction."""
    key = bytes(range(32))
    body = HEADER + b"\x07\x00\x00\x00field bytes"
    signed = Authenticator(key).sign_serialized(body + bytes(32), "/fleet/state", 3, 17)
    t = b"/fleet/state"
    want = hmac.new(
        key,
        b"fire-uav-auth-cdr-v1\x00" + struct.pack(">I", len(t)) + t + struct.pack(">iq", 3, 17) + body,
        hashlib.sha256,
    ).digest()
    assert signed == body + want


@settings(max_examples=100, deadline=None)
@given(
    st.binary(max_size=200),
    st.integers(0, 255),
    st.integers(0, 2**40),
    st.integers(0, 10_000),
    st.integers(0, 7),
)
def test_any_change_to_the_bytes_sender_step_or_topic_fails(body, sender, step, pos, bit):
    a = Authenticator(secrets.token_bytes(32))
    data = a.sign_serialized(serialised(body), "/fleet/state", sender, step)
    assert len(data) == len(serialised(body)) and data[-TAG_BYTES:] != bytes(TAG_BYTES)
    assert a.check_serialized(data, "/fleet/state", sender, step)
    assert not a.check_serialized(data, "/fleet/fires", sender, step)
    assert not a.check_serialized(data, "/fleet/state", sender + 1, step)
    assert not a.check_serialized(data, "/fleet/state", sender, step + 1)
    assert not Authenticator(secrets.token_bytes(32)).check_serialized(data, "/fleet/state", sender, step)
    i = pos % len(data)  # any byte: header, fields, padding or the tag itself
    flipped = data[:i] + bytes([data[i] ^ (1 << bit)]) + data[i + 1 :]
    assert not a.check_serialized(flipped, "/fleet/state", sender, step)


@settings(max_examples=100, deadline=None)
@given(
    st.one_of(st.binary(), st.lists(st.integers(0, 255), max_size=40), st.none(), st.integers(), st.text())
)
def test_garbage_is_rejected_not_raised(data):
    a = Authenticator(bytes(range(32)))
    assert a.check_serialized(data, "/t", 0, 0) is False


def test_signing_names_what_is_wrong_with_its_input():
    a = Authenticator(bytes(range(32)))
    with pytest.raises(ValueError) as e:
        a.sign_serialized(HEADER + b"x" + bytes([1]) * TAG_BYTES, "/t", 0, 0)
    assert str(e.value) == (
        "sign_serialized: the last 32 bytes are not a zero auth field: the message type's auth must be "
        "its last field, and the message must be serialised before it is signed (auth all zeros)"
    )
    signed = a.sign_serialized(serialised(b"x"), "/t", 0, 0)
    with pytest.raises(ValueError, match="last 32 bytes are not a zero auth field"):
        a.sign_serialized(signed, "/t", 0, 0)  # signed twice
    for bad, what in [(b"", "bytes of length 0"), (HEADER + bytes(TAG_BYTES - 1), "bytes of length 35"),
                      (bytearray(64), "bytearray of length 64"), (None, "NoneType of length ?")]:  # fmt: skip
        with pytest.raises(ValueError) as e:
            a.sign_serialized(bad, "/t", 0, 0)  # type: ignore[arg-type]
        assert str(e.value) == f"sign_serialized: expected the CDR bytes of a message, got {what}"


def _reference_tag(key: bytes, topic: str, sender: int, step: int, body: bytes) -> bytes:
    """``Authenticator.tag`` as it was written before its keyed states were kept: one
    ``hmac.new`` over the whole text (docs/security.md's construction)."""
    t = topic.encode("utf-8")
    head = b"fire-uav-auth-cdr-v1\x00" + struct.pack(">I", len(t)) + t + struct.pack(">iq", sender, step)
    return hmac.new(key, head + body, hashlib.sha256).digest()


@settings(max_examples=200, deadline=None)
@given(
    st.binary(min_size=32, max_size=32),
    st.lists(st.text(max_size=80), min_size=1, max_size=5),
    st.integers(-(2**31), 2**31 - 1),
    st.integers(-(2**63), 2**63 - 1),
    st.binary(max_size=300),
)
def test_the_kept_keyed_states_give_hmac_news_tags(key, topic_list, sender, step, body):
    """The tag from the keyed hashes kept per Authenticator and per topic (RFC 2104 written out)
    is ``hmac.new``'s, for any key, topic (empty, non-ASCII, longer than a block), sender, step
    and body, asked again and after more topics than are kept; checked from bytes, a bytearray
    or a memoryview of them alike."""
    a = Authenticator(key)
    for _ in range(2):  # the second time from the kept states
        for topic in topic_list:
            want = _reference_tag(key, topic, sender, step, body)
            assert a.tag(topic, sender, step, body) == want
            assert a.tag(topic, sender, step, memoryview(body)) == want
            signed = HEADER + body + _reference_tag(key, topic, sender, step, HEADER + body)
            assert a.check_serialized(signed, topic, sender, step)
            assert a.check_serialized(bytearray(signed), topic, sender, step)
    for i in range(70):  # beyond the topics kept: each still tagged as hmac.new tags it
        assert a.tag(f"/t{i}", sender, step, body) == _reference_tag(key, f"/t{i}", sender, step, body)
    assert a.tag(topic_list[0], sender, step, body) == _reference_tag(key, topic_list[0], sender, step, body)
