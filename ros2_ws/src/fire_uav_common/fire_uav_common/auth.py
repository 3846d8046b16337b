"""Message authentication for fleet and command topics: HMAC-SHA256 with a per-mission key.

docs/security.md. The Fast DDS build in the PyPI wheels has no DDS Security plugins, so SROS2 is
not available; this module is the stand-in. It is ROS-free: it reads a message through the
field table every generated ROS 2 Python message has (``get_fields_and_field_types()``).

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

import array
import hashlib
import hmac
import operator
import secrets
import struct
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

__all__ = ["KEY_BYTES", "TAG_BYTES", "Authenticator", "canonical_bytes", "new_key_hex", "parse_key"]

KEY_BYTES = 32  # [B] key length: the SHA-256 block is 64 B; 32 B of entropy is the usual choice
TAG_BYTES = 32  # [B] a full SHA-256 tag (no truncation)
_DOMAIN = b"fire-uav-auth-v1\x00"
_WIRE_DOMAIN = b"fire-uav-auth-cdr-v1\x00"  # the serialised form (sign_serialized): never confused with v1
_ZERO_TAG = bytes(TAG_BYTES)


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


# IDL primitive -> numpy dtype at its wire width (big-endian); rosidl's names
_PRIMITIVE = {
    "boolean": ">u1", "octet": ">u1", "byte": ">u1", "char": ">u1", "uint8": ">u1", "int8": ">i1",
    "uint16": ">u2", "int16": ">i2", "uint32": ">u4", "int32": ">i4", "uint64": ">u8", "int64": ">i8",
    "float": ">f4", "double": ">f8",
}  # fmt: skip
_AUTH_FIELD = "auth"


def _element_type(ftype: str) -> tuple[str, bool]:
    """``'sequence<float, 5>'`` / ``'float[16]'`` / ``'float'`` -> (``'float'``, is_array)."""
    if ftype.startswith("sequence<") and ftype.endswith(">"):
        return ftype[len("sequence<") : -1].split(",")[0].strip(), True
    if ftype.endswith("]") and "[" in ftype:
        return ftype[: ftype.index("[")], True
    return ftype, False


def _encode(value: Any, ftype: str, out: list[bytes]) -> None:
    base, is_array = _element_type(ftype)
    if base.startswith(("string", "wstring")):
        items = list(value) if is_array else [value]
        if is_array:
            out.append(struct.pack(">Q", len(items)))
        for text in items:
            raw = str(text).encode("utf-8")
            out.append(struct.pack(">Q", len(raw)) + raw)
        return
    dtype = _PRIMITIVE.get(base)
    if dtype is None:  # a nested message type, e.g. 'std_msgs/Header' or 'sequence<fire_uav_msgs/FireCell>'
        items = list(value) if is_array else [value]
        if is_array:
            out.append(struct.pack(">Q", len(items)))
        for item in items:
            out.append(canonical_bytes(item))
        return
    if isinstance(value, (bytes, bytearray)):  # octet/byte fields and uint8[] may arrive as bytes
        arr = np.frombuffer(bytes(value), dtype=np.uint8)
    elif is_array:
        arr = np.asarray(list(value) if not hasattr(value, "dtype") else value)
    else:
        arr = np.asarray([value])
    if arr.dtype == object or arr.dtype.kind in "SU":  # elements given as 1-byte bytes objects
        arr = np.array([v[0] if isinstance(v, (bytes, bytearray)) else v for v in arr.ravel()])
    packed = arr.astype(dtype, casting="unsafe").tobytes()
    out.append((struct.pack(">Q", arr.size) if is_array else b"") + packed)


# numeric scalar primitives that struct packs exactly as numpy's cast does for in-range values
_SCALAR_STRUCT = {
    "boolean": struct.Struct(">B"), "uint8": struct.Struct(">B"), "int8": struct.Struct(">b"),
    "uint16": struct.Struct(">H"), "int16": struct.Struct(">h"), "uint32": struct.Struct(">I"),
    "int32": struct.Struct(">i"), "uint64": struct.Struct(">Q"), "int64": struct.Struct(">q"),
    "float": struct.Struct(">f"), "double": struct.Struct(">d"),
}  # fmt: skip
_PLAIN = (int, float, bool)
_ARRAY_KINDS = frozenset("biuf")  # numpy dtype kinds that cast to a numeric field exactly as _encode does
_ARRAY_TYPECODES = frozenset("bBhHiIlLqQfd")  # array.array typecodes that are numpy type characters too


class _Step(NamedTuple):
    """One step of a class's encoding plan: the fields it writes and how."""

    names: tuple[str, ...]
    encode: Callable[[Any, list[bytes]], None]


def _run_step(names: tuple[str, ...], types: tuple[str, ...]) -> _Step:
    """Consecutive numeric scalar fields packed by one :mod:`struct` call (``>``: no padding, so
    the same bytes as one call per field); a value the run cannot pack (not a plain int, float or
    bool, or out of its field's range) sends the run through :func:`_encode` field by field."""
    getter = operator.attrgetter(*names)
    run = struct.Struct(">" + "".join(_SCALAR_STRUCT[_element_type(t)[0]].format[1:] for t in types))
    single = len(names) == 1

    def encode(msg: Any, out: list[bytes]) -> None:
        values = (getter(msg),) if single else getter(msg)
        if all(type(v) in _PLAIN for v in values):
            try:
                out.append(run.pack(*values))
                return
            except (struct.error, OverflowError):
                pass  # out of a field's range: numpy's cast decides, as before
        for value, ftype in zip(values, types, strict=True):
            _encode(value, ftype, out)

    return _Step(names, encode)


def _field_step(name: str, ftype: str) -> _Step:
    """Any other field: strings, numeric arrays (a shortcut for a numpy array or an
    ``array.array``, what rclpy's setters store: the same bytes as :func:`_encode`'s numpy cast),
    sequences of messages (each by its own plan), else :func:`_encode`."""
    base, is_array = _element_type(ftype)
    dtype = _PRIMITIVE.get(base)
    getter = operator.attrgetter(name)
    if dtype is None and is_array and not base.startswith(("string", "wstring")):

        def encode_messages(msg: Any, out: list[bytes]) -> None:
            items = getter(msg)
            out.append(_LENGTH.pack(len(items)))
            for item in items:
                for step in _plan(item):
                    step.encode(item, out)

        return _Step((name,), encode_messages)
    if base == "string" and not is_array:

        def encode_string(msg: Any, out: list[bytes]) -> None:
            value = getter(msg)
            if type(value) is not str:
                _encode(value, ftype, out)
                return
            raw = value.encode("utf-8")
            out.append(_LENGTH.pack(len(raw)) + raw)

        return _Step((name,), encode_string)
    if not is_array or dtype is None:

        def encode(msg: Any, out: list[bytes]) -> None:
            _encode(getter(msg), ftype, out)

        return _Step((name,), encode)

    def encode_array(msg: Any, out: list[bytes]) -> None:
        value = getter(msg)
        kind = type(value)
        if kind is np.ndarray and value.dtype.kind in _ARRAY_KINDS:
            arr = value.ravel()
        elif kind is array.array and value.typecode in _ARRAY_TYPECODES:
            arr = np.frombuffer(value, dtype=value.typecode)
        else:
            _encode(value, ftype, out)
            return
        out.append(_LENGTH.pack(arr.size) + arr.astype(dtype).tobytes())  # astype casts unsafely by default

    return _Step((name,), encode_array)


_LENGTH = struct.Struct(">Q")
_PLANS: dict[type, tuple[_Step, ...]] = {}


def _generated(value: Any) -> bool:
    """A generated ROS message (its field table is a class attribute, fixed per type)."""
    return isinstance(getattr(type(value), "_fields_and_field_types", None), dict)


def _plan(msg: Any) -> tuple[_Step, ...]:
    """The encoding plan of ``msg``'s class: every field but ``auth``, in declaration order, as
    runs of numeric scalars (:func:`_run_step`) and single other fields (:func:`_field_step`).

    A nested generated message (a Header, a Time) is flattened into its parent's plan under a
    dotted name, so its scalars join the parent's runs: the bytes are the same, since a nested
    message's bytes are its fields' bytes one after the other. Kept per class for generated ROS
    messages; built afresh for any other object, whose table may differ between instances."""
    cls = type(msg)
    plan = _PLANS.get(cls)
    if plan is not None:
        return plan
    steps: list[_Step] = []
    run: list[tuple[str, str]] = []

    def close_run() -> None:
        if run:
            steps.append(_run_step(tuple(n for n, _ in run), tuple(t for _, t in run)))
            run.clear()

    def walk(obj: Any, prefix: str) -> None:
        for name, ftype in obj.get_fields_and_field_types().items():
            if name == _AUTH_FIELD:  # at any depth, as a nested message's own encoding skips it
                continue
            base, is_array = _element_type(ftype)
            if not is_array and base in _SCALAR_STRUCT:
                run.append((prefix + name, ftype))
                continue
            if not is_array and "/" in base and _generated(child := getattr(obj, name)):
                walk(child, prefix + name + ".")
                continue
            close_run()
            steps.append(_field_step(prefix + name, ftype))

    walk(msg, "")
    close_run()
    plan = tuple(steps)
    if _generated(msg):
        _PLANS[cls] = plan
    return plan


def canonical_bytes(msg: Any) -> bytes:
    """The bytes a tag covers: every field of ``msg`` except ``auth``, in declaration order.

    Each field at its declared wire width, big-endian, with no alignment padding: a float32 field
    as float32 (rounded as the wire rounds it), integers at their width, booleans as one byte,
    strings and every array or sequence with an 8-byte length first, nested messages recursively.
    Equal messages give equal bytes on every host, whatever memory the serialiser reused.

    The plan is read once per message class (:func:`_plan`). A run of numeric scalar fields whose
    values are plain ints, floats or bools is packed by one :mod:`struct` call, and a numeric
    array held as numpy or ``array.array`` is cast without a list: the same bytes as the numpy
    cast of :func:`_encode` gives for every value rclpy's setters accept. Anything else, or a value
    struct refuses, goes through :func:`_encode` (issue [scale], docs/profile.md).
    """
    out: list[bytes] = []
    for step in _plan(msg):
        step.encode(msg, out)
    return b"".join(out)


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

    # --- on serialised messages: what the fleet sends and checks ---------------------------------
    def _wire_tag(self, topic: str, sender: int, step: int, body: bytes) -> bytes:
        t = topic.encode("utf-8")
        head = _WIRE_DOMAIN + struct.pack(">I", len(t)) + t + struct.pack(">iq", int(sender), int(step))
        return hmac.new(self._key, head + body, hashlib.sha256).digest()

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
            raise ValueError(f"sign_serialized: expected the CDR bytes of a message, got {type(data).__name__} "
                             f"of length {len(data) if hasattr(data, '__len__') else '?'}")  # fmt: skip
        if data[-TAG_BYTES:] != _ZERO_TAG:
            raise ValueError(
                "sign_serialized: the last 32 bytes are not a zero auth field: the message type's auth must be "
                "its last field, and the message must be serialised before it is signed (auth all zeros)"
            )
        body = data[:-TAG_BYTES]
        return body + self._wire_tag(topic, sender, step, body)

    def check_serialized(self, data: bytes, topic: str, sender: int, step: int) -> bool:
        """Whether the last 32 bytes of ``data`` (as received, raw) are the tag of the rest for
        this topic, sender and step (constant-time comparison). False for anything too short."""
        if not isinstance(data, (bytes, bytearray)) or len(data) < 4 + TAG_BYTES:
            return False
        data = bytes(data)
        return hmac.compare_digest(self._wire_tag(topic, sender, step, data[:-TAG_BYTES]), data[-TAG_BYTES:])

    # --- on messages ---------------------------------------------------------------------------
    def sign(self, msg: Any, topic: str, sender: int, step: int) -> None:
        """Set ``msg.auth`` to the tag of ``msg`` (call after every other field is set)."""
        # a list: rclpy's uint8[32] setter takes a sequence of ints, not bytes
        msg.auth = list(self.tag(topic, sender, step, canonical_bytes(msg)))

    def check(self, msg: Any, topic: str, sender: int, step: int) -> bool:
        """Whether ``msg.auth`` is the tag of ``msg`` for this topic, sender and step."""
        try:
            tag = _tag_bytes(msg.auth)
            return self.verify(topic, sender, step, canonical_bytes(msg), tag)
        except (TypeError, ValueError, AttributeError, KeyError, IndexError, struct.error, OverflowError):
            return False
