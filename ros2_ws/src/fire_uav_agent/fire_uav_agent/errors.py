"""The agent package's errors: every error raised on purpose derives from :class:`AgentError`.

Each also derives from ``ValueError``: callers that predate the family (and rclpy's own parameter
handling) catch ``ValueError``, and a bad value is what each of them reports.
"""

from __future__ import annotations

__all__ = ["AgentError", "ConfigError", "InputError"]


class AgentError(Exception):
    """Base class of the agent package's errors."""


class ConfigError(AgentError, ValueError):
    """A parameter or configuration value is unknown, out of range or inconsistent (raised at start-up
    or at construction, naming the parameter or field and the value)."""


class InputError(AgentError, ValueError):
    """Data handed to an algorithm at run time has the wrong shape or lengths (a malformed sample
    block, cell list or peer row)."""


# Bytes that are no CDR of a message are fire_uav_common.cdr.CdrError (the codecs' error).
