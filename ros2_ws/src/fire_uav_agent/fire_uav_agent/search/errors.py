"""Domain exceptions of the coverage-search library.

Every error raised on purpose by :mod:`fire_uav_agent.search` derives from :class:`SearchError`, so a
caller (the ROS adapter) can catch the whole family in one place.
"""

from __future__ import annotations

from ..errors import AgentError, ConfigError


class SearchError(AgentError):
    """Base class of all coverage-search errors (part of the agent package's family)."""


class SearchConfigError(SearchError, ConfigError):
    """A configuration value is out of range or inconsistent (raised at construction)."""


class PartitionError(SearchError):
    """Area division failed: bad grid, bad seeds, or the free space is not connected."""


class PathError(SearchError):
    """Spanning-tree coverage path could not be built (e.g. turn radius does not fit the grid)."""


class MstError(SearchError):
    """Fragment-merge minimum spanning tree received inconsistent messages."""


class OptimizationError(SearchError):
    """Bayesian optimisation was given an unusable budget, pool or objective value."""
