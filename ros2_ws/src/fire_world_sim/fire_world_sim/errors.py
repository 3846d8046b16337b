"""Domain exceptions of the world simulation (raised early, with a message naming what is wrong)."""

from __future__ import annotations

__all__ = ["ConfigError", "WorldError"]


class WorldError(RuntimeError):
    """The world cannot continue (an internal invariant broke)."""


class ConfigError(ValueError):
    """A world parameter or argument is invalid (bad uav_count, unknown fire model, ...)."""
