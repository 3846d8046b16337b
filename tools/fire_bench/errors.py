"""The benchmarks' error family: every error fire_bench raises itself is a :class:`BenchError`,
whose one-line message says what is wrong."""

from __future__ import annotations

__all__ = ["BenchError", "SweepError"]


class BenchError(RuntimeError):
    """Base of the benchmarks' own errors."""


class SweepError(BenchError):
    """A sweep cannot run (bad spec, no scheduler, no dask); the message is one line."""
