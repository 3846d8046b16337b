"""Shared, ROS-free pieces of the fire UAV fleet: topic names and QoS, RNG streams, terrain.

Public API: :mod:`fire_uav_common.topics` (names, QoS), :func:`fire_uav_common.rng.stream`,
:class:`fire_uav_common.terrain.Terrain`.
"""

__version__ = "0.1.0"
