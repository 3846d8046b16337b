"""Message authentication for fleet and command topics: HMAC-SHA256 with a per-mission key.

docs/security.md. The Fast DDS build in the PyPI wheels has no DDS Security plugins, so SROS2 is
not available; this module is the stand-in. It is ROS-free: it works on bytes (the nodes
serialise and deserialise with ``rclpy.serialization``).

The fleet signs *serialised* messages (:meth:`Authenticator.sign_serialized`): the tag is
``HMAC-SHA256(key, DOMAIN || topic || sender || step || body)`` (RFC 2104 with SHA-256, FIPS
180-4), where ``body`` is the message's CDR bytes as sent, up to its ``auth`` field (every signed
type's last field, so its last 32 bytes, where the tag then goes); ``sender`` (int32) and ``step``
(int64) are big-endian, so a tag is bound to one topic, one sender and one step (for a
PayloadRequest, the stamp in nanoseconds). The sender publishes those bytes as they are and the
receivers subscribe raw and check the bytes that arrived (:meth:`Authenticator.check_serialized`),
then deserialise them. What it does not give: confidentiality, protection against a replay of an
authentic message (the receivers' step plausibility and duplicate checks handle that), or
protection once the key leaks (anyone holding it is the fleet).

Why the bytes as sent and not a re-serialisation: CDR aligns fields, and the serialiser in the
wheels leaves the alignment padding uninitialised. A sender's padding held heap garbage where the
receiver's re-serialisation had zeros, so every UavState failed its check and the fleet stalled at
step 1. Nothing is re-serialised now; the receiver hashes what DDS delivered, the sender's bytes.
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
import struct
from typing import Any

from .errors import FleetKeyError

__all__ = ["KEY_BYTES", "TAG_BYTES", "Authenticator", "authenticator_from", "new_key_hex", "parse_key"]

KEY_BYTES = 32  # [B] key length: the SHA-256 block is 64 B; 32 B of entropy is the usual choice
TAG_BYTES = 32  # [B] a full SHA-256 tag (no truncation)
_DOMAIN = b"fire-uav-auth-cdr-v1\x00"  # v1 tagged a canonical encoding of the message object (until [scale])
_ZERO_TAG = bytes(TAG_BYTES)
_BLOCK_BYTES = 64  # SHA-256's block: the key is padded to it with zeros (RFC 2104, section 2)
_SENDER_STEP = struct.Struct(">iq")
_TOPICS_KEPT = 64  # per Authenticator: the topics whose keyed prefix is kept (a node signs a few)


def new_key_hex() -> str:
    """A fresh random key (``secrets``, the OS CSPRNG) as 64 hex digits; one per mission."""
    return secrets.token_hex(KEY_BYTES)


def parse_key(text: str) -> bytes:
    """64 hex digits -> the 32-byte key; a one-line ValueError (never echoing the key) if not."""
    t = text.strip()
    if len(t) != 2 * KEY_BYTES:
        raise FleetKeyError(f"fleet key must be {2 * KEY_BYTES} hex digits, got {len(t)} characters")
    try:
        return bytes.fromhex(t)
    except ValueError:
        raise FleetKeyError("fleet key must be hex digits only (0-9, a-f)") from None


class Authenticator:
    """Signs and verifies serialised messages whose last field is ``uint8[32] auth``."""

    def __init__(self, key: bytes) -> None:
        if len(key) != KEY_BYTES:
            raise FleetKeyError(f"fleet key must be {KEY_BYTES} bytes, got {len(key)}")
        # HMAC (RFC 2104) as hashes of the padded key: H((K ^ opad) || H((K ^ ipad) || text)). The
        # two keyed states are hashed once here, and the inner one also over each topic's fixed
        # head (``_inner_for``): a tag then costs two copies, three updates and two digests
        # instead of ``hmac.new``'s key set-up and its Python layers (an agent of a 30-UAV fleet
        # checks 29 states a step). ``test_auth.py`` holds the tags to ``hmac.new``'s.
        block = key.ljust(_BLOCK_BYTES, b"\x00")
        self._inner = hashlib.sha256(bytes(b ^ 0x36 for b in block))
        self._outer = hashlib.sha256(bytes(b ^ 0x5C for b in block))
        self._topics: dict[str, Any] = {}

    def __repr__(self) -> str:  # never show the key
        return "Authenticator(<key>)"

    def _inner_for(self, topic: str) -> Any:  # hashlib's sha256 object (its type is not public)
        """The inner hash, keyed, over ``DOMAIN || len(topic) || topic`` (kept per topic)."""
        h = self._topics.get(topic)
        if h is None:
            t = topic.encode("utf-8")
            h = self._inner.copy()
            h.update(_DOMAIN + struct.pack(">I", len(t)) + t)
            if len(self._topics) < _TOPICS_KEPT:
                self._topics[topic] = h
        return h

    def tag(self, topic: str, sender: int, step: int, body: bytes | memoryview) -> bytes:
        """The 32-byte HMAC-SHA256 tag of ``body`` bound to ``topic``, ``sender`` and ``step``:
        ``HMAC(key, DOMAIN || len(topic) || topic || sender || step || body)``."""
        h = self._inner_for(topic).copy()
        h.update(_SENDER_STEP.pack(int(sender), int(step)))
        h.update(body)
        outer = self._outer.copy()
        outer.update(h.digest())
        return outer.digest()

    def sign_serialized(self, data: bytes, topic: str, sender: int, step: int) -> bytes:
        """``data`` with its last 32 bytes set to the tag of everything before them.

        ``data`` is the CDR of a message whose last field is ``uint8[32] auth``, serialised with
        that field zero (a fresh message; ``rclpy.serialization.serialize_message``). The sender
        publishes the returned bytes as they are (``Publisher.publish`` takes bytes), and a raw
        subscription hands the receiver the very same bytes, alignment padding included, so
        :meth:`check_serialized` needs no canonical form and no re-serialisation. A ValueError
        names what is wrong if the last 32 bytes are not a zero tag (a type whose ``auth`` is not
        its last field, or a message signed twice).
        """
        if not isinstance(data, bytes) or len(data) < 4 + TAG_BYTES:
            raise FleetKeyError(f"sign_serialized: expected the CDR bytes of a message, got {type(data).__name__} "
                             f"of length {len(data) if hasattr(data, '__len__') else '?'}")  # fmt: skip
        if data[-TAG_BYTES:] != _ZERO_TAG:
            raise FleetKeyError(
                "sign_serialized: the last 32 bytes are not a zero auth field: the message type's auth must be "
                "its last field, and the message must be serialised before it is signed (auth all zeros)"
            )
        body = data[:-TAG_BYTES]
        return body + self.tag(topic, sender, step, body)

    def check_serialized(self, data: bytes, topic: str, sender: int, step: int) -> bool:
        """Whether the last 32 bytes of ``data`` (as received, raw) are the tag of the rest for
        this topic, sender and step (constant-time comparison). False for anything too short."""
        if not isinstance(data, (bytes, bytearray)) or len(data) < 4 + TAG_BYTES:
            return False
        data = bytes(data)  # a bytearray's bytes as they are now (bytes: the same object)
        body = memoryview(data)[:-TAG_BYTES]  # not copied
        return hmac.compare_digest(self.tag(topic, sender, step, body), data[-TAG_BYTES:])


def authenticator_from(auth: bool, key: str, error: type[Exception] = FleetKeyError) -> Authenticator | None:
    """The ``auth`` / ``fleet_key`` parameters of a node (docs/security.md) as an Authenticator;
    None when authentication is off. A missing or malformed key raises ``error`` (the calling
    package's configuration error) naming the parameter."""
    if not auth:
        return None
    if not key:
        raise error("parameter fleet_key is required when auth is true (the runner writes one per mission)")
    try:
        return Authenticator(parse_key(key))
    except ValueError as e:
        raise error(f"parameter fleet_key: {e}") from None
