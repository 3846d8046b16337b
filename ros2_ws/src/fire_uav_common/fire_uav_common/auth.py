"""Message authentication for fleet and command topics: HMAC-SHA256 with a per-mission key.

docs/security.md. The Fast DDS build in the PyPI wheels has no DDS Security plugins, so SROS2 is
not available; this module is the stand-in. It is ROS-free: the nodes pass their message and a
``serialize`` function (``rclpy.serialization.serialize_message``).

The tag of a message is ``HMAC-SHA256(key, DOMAIN || topic || sender || step || payload)``
(RFC 2104 with SHA-256, FIPS 180-4), where ``payload`` is the message's CDR serialisation with its
``auth`` field set to 32 zero bytes, ``sender`` (int32) and ``step`` (int64) are big-endian, and
``topic`` is the fully qualified topic name, so a tag is bound to one topic, one sender and one
step (for a PayloadRequest, the stamp in nanoseconds). What it does not give: confidentiality,
protection against a replay of an authentic message (the receivers' step plausibility and
duplicate checks handle that), or protection once the key leaks (anyone holding it is the fleet).
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
import struct
from collections.abc import Callable
from typing import Any

__all__ = ["KEY_BYTES", "TAG_BYTES", "Authenticator", "new_key_hex", "parse_key"]

KEY_BYTES = 32  # [B] key length: the SHA-256 block is 64 B; 32 B of entropy is the usual choice
TAG_BYTES = 32  # [B] a full SHA-256 tag (no truncation)
_DOMAIN = b"fire-uav-auth-v1\x00"
_ZERO = bytes(TAG_BYTES)


def new_key_hex() -> str:
    """A fresh random key (``secrets``, the OS CSPRNG) as 64 hex digits; one per mission."""
    return secrets.token_hex(KEY_BYTES)


def parse_key(text: str) -> bytes:
    """64 hex digits -> the 32-byte key; a one-line ValueError (never echoing the key) if not."""
    t = text.strip()
    if len(t) != 2 * KEY_BYTES:
        raise ValueError(f"fleet key must be {2 * KEY_BYTES} hex digits, got {len(t)} characters")
    try:
        return bytes.fromhex(t)
    except ValueError:
        raise ValueError("fleet key must be hex digits only (0-9, a-f)") from None


def _tag_bytes(value: Any) -> bytes:
    """A message's ``auth`` field (bytes, a list or a numpy uint8 array) as bytes; b"" if it is none."""
    if isinstance(value, (bytes, bytearray)):
        return bytes(value)
    if isinstance(value, (int, str)) or not hasattr(value, "__len__") or len(value) != TAG_BYTES:
        return b""  # bytearray(int) would allocate that many bytes
    try:
        return bytes(bytearray(value))
    except (TypeError, ValueError):
        return b""


class Authenticator:
    """Signs and verifies messages that have a ``uint8[32] auth`` field."""

    def __init__(self, key: bytes) -> None:
        if len(key) != KEY_BYTES:
            raise ValueError(f"fleet key must be {KEY_BYTES} bytes, got {len(key)}")
        self._key = key

    def __repr__(self) -> str:  # never show the key
        return "Authenticator(<key>)"

    def tag(self, topic: str, sender: int, step: int, payload: bytes) -> bytes:
        """The 32-byte HMAC-SHA256 tag of ``payload`` bound to ``topic``, ``sender`` and ``step``."""
        t = topic.encode("utf-8")
        head = _DOMAIN + struct.pack(">I", len(t)) + t + struct.pack(">iq", int(sender), int(step))
        return hmac.new(self._key, head + payload, hashlib.sha256).digest()

    def verify(self, topic: str, sender: int, step: int, payload: bytes, tag: bytes) -> bool:
        """Constant-time comparison of ``tag`` with the expected one."""
        if len(tag) != TAG_BYTES:
            return False
        return hmac.compare_digest(self.tag(topic, sender, step, payload), tag)

    # --- on messages ---------------------------------------------------------------------------
    @staticmethod
    def _payload(msg: Any, serialize: Callable[[Any], bytes]) -> bytes:
        saved = msg.auth
        msg.auth = list(_ZERO)  # a list: rclpy's uint8[32] setter takes a sequence of ints, not bytes
        try:
            return bytes(serialize(msg))
        finally:
            msg.auth = saved

    def sign(self, msg: Any, topic: str, sender: int, step: int, serialize: Callable[[Any], bytes]) -> None:
        """Set ``msg.auth`` to the tag of ``msg`` (call after every other field is set)."""
        msg.auth = list(self.tag(topic, sender, step, self._payload(msg, serialize)))

    def check(self, msg: Any, topic: str, sender: int, step: int, serialize: Callable[[Any], bytes]) -> bool:
        """Whether ``msg.auth`` is the tag of ``msg`` for this topic, sender and step."""
        try:
            tag = _tag_bytes(msg.auth)  # read before _payload swaps the field
            return self.verify(topic, sender, step, self._payload(msg, serialize), tag)
        except (TypeError, ValueError, AttributeError, struct.error, OverflowError):
            return False
