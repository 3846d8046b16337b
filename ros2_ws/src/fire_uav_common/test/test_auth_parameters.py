"""fire_uav_common.auth.authenticator_from: a node's ``auth`` / ``fleet_key`` parameters
(docs/security.md) as an Authenticator, None when off, a bad key refused with the caller's error.

The key's use is checked against a hand computation of the documented tag (HMAC-SHA256 of
``DOMAIN || len(topic) || topic || sender || step || body``, RFC 2104), not the module's own.
"""

import hashlib
import hmac
import struct

import pytest
from fire_uav_common.auth import Authenticator, authenticator_from
from fire_uav_common.errors import CommonError, FleetKeyError

KEY_HEX = "00112233445566778899aabbccddeeff0123456789abcdef0123456789ABCDEF"  # 64 hex digits


class CallerError(Exception):
    """A calling package's configuration error: deliberately not a ValueError."""


def documented_tag(key: bytes, topic: str, sender: int, step: int, body: bytes) -> bytes:
    t = topic.encode()
    head = b"fire-uav-auth-cdr-v1\x00" + struct.pack(">I", len(t)) + t + struct.pack(">iq", sender, step)
    return hmac.new(key, head + body, hashlib.sha256).digest()


@pytest.mark.parametrize("key", ["", KEY_HEX, "not a key"])
def test_auth_off_gives_none_whatever_the_key(key: str) -> None:
    assert authenticator_from(False, key) is None
    assert authenticator_from(False, key, CallerError) is None


@pytest.mark.parametrize("text", [KEY_HEX, f"  {KEY_HEX}\n", KEY_HEX.lower(), KEY_HEX.upper()])
def test_auth_on_uses_the_hex_key_of_the_parameter(text: str) -> None:
    a = authenticator_from(True, text)
    assert isinstance(a, Authenticator)
    key = bytes.fromhex(KEY_HEX)
    body = b"\x00\x01\x00\x00" + b"fields"
    assert a.tag("/fleet/state", 3, 41, body) == documented_tag(key, "/fleet/state", 3, 41, body)
    signed = a.sign_serialized(body + bytes(32), "/fleet/state", 3, 41)
    assert signed == body + documented_tag(key, "/fleet/state", 3, 41, body)
    assert a.check_serialized(signed, "/fleet/state", 3, 41)


def test_a_missing_key_is_refused_naming_the_parameter() -> None:
    with pytest.raises(CallerError) as e:
        authenticator_from(True, "", CallerError)
    assert (
        str(e.value)
        == "parameter fleet_key is required when auth is true (the runner writes one per mission)"
    )
    with pytest.raises(FleetKeyError, match="^parameter fleet_key is required when auth is true"):
        authenticator_from(True, "")  # the default: the shared package's own error


@pytest.mark.parametrize(
    ("key", "reason"),
    [
        ("abcde", "fleet key must be 64 hex digits, got 5 characters"),
        (KEY_HEX + "00", "fleet key must be 64 hex digits, got 66 characters"),
        ("zz" * 32, "fleet key must be hex digits only (0-9, a-f)"),
        ("   ", "fleet key must be 64 hex digits, got 0 characters"),
    ],
)
def test_a_malformed_key_is_refused_with_the_callers_error(key: str, reason: str) -> None:
    with pytest.raises(CallerError) as e:
        authenticator_from(True, key, CallerError)
    assert str(e.value) == f"parameter fleet_key: {reason}"  # never the key itself
    assert e.value.__cause__ is None and e.value.__suppress_context__
    with pytest.raises(FleetKeyError) as d:
        authenticator_from(True, key)
    assert str(d.value) == f"parameter fleet_key: {reason}"
    assert isinstance(d.value, CommonError)
