"""Seeded random streams: one independent, reproducible stream per (seed, purpose, ids).

House style rule 3: one ``numpy.random.Generator`` per process and purpose, seeded from the
scenario seed and the UAV id, so that lockstep runs repeat exactly.
"""

from __future__ import annotations

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
    return bool(stream(seed, purpose, *ids).random() < p)
