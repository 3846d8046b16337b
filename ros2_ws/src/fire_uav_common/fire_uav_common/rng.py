"""Seeded random streams: one independent, reproducible stream per (seed, purpose, ids).

House style rule 3: one ``numpy.random.Generator`` per process and purpose, seeded from the
scenario seed and the UAV id, so that lockstep runs repeat exactly.
"""

from __future__ import annotations

import hashlib
import struct
import zlib

import numpy as np

__all__ = ["stream", "bernoulli"]


def _key(purpose: str) -> int:
    return zlib.crc32(purpose.encode())


def stream(seed: int, purpose: str, *ids: int) -> np.random.Generator:
    """Independent generator for ``purpose`` (e.g. ``"gps"``) and ids (e.g. the UAV id)."""
    if seed < 0 or any(i < 0 for i in ids):
        raise ValueError(f"seed and ids must be >= 0, got seed={seed}, ids={ids}")
    return np.random.default_rng(np.random.SeedSequence([seed, _key(purpose), *ids]))


def bernoulli(p: float, seed: int, purpose: str, *ids: int) -> bool:
    """One draw that depends only on its arguments, not on call order.

    Used for packet loss on receipt: whether message ``(sender, receiver, step)`` is lost is
    the same whatever order messages arrive in, so lockstep runs repeat exactly.
    """
    if not 0.0 <= p <= 1.0:
        raise ValueError(f"probability must be in [0, 1], got {p}")
    if p == 0.0:
        return False
    if seed < 0 or any(i < 0 for i in ids):
        raise ValueError(f"seed and ids must be >= 0, got seed={seed}, ids={ids}")
    # a keyed hash of the arguments, not a Generator: one draw per peer message and step made
    # SeedSequence + PCG64 construction ~45 % of an agent step (docs/profile.md); BLAKE2b's
    # 64-bit output is uniform, so u in [0, 1) and P(u < p) = p
    key = struct.pack(f"<{2 + len(ids)}Q", seed, _key(purpose), *ids)
    u = int.from_bytes(hashlib.blake2b(key, digest_size=8).digest(), "little") / 2.0**64
    return u < p
