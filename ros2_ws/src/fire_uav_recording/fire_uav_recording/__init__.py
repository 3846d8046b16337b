"""Mission recording: a typestore with the fleet's messages, a crash-safe bag writer, a validating
reader that salvages bags cut short, and the ``recorder`` and ``replay`` nodes.

The names below are pure Python (rosbags, mcap, PyYAML, no rclpy), so the report and the tests
read and write bags without ROS. The nodes are :mod:`fire_uav_recording.recorder_node` and
:mod:`fire_uav_recording.replay_node`.

A mission bag is a rosbag2 directory (``metadata.yaml`` + one ``<name>.mcap``) written by
:class:`BagWriter`; :func:`open_bag` reads it (or a bare ``.mcap`` file), repairing an unfinished
one into a temporary copy; :func:`repair_bag` writes such a copy for good.
"""

from __future__ import annotations

from fire_uav_recording.bagfile import MCAP_MAGIC, BagInfo, inspect_bag
from fire_uav_recording.errors import BagError, ConfigError, RecordingError
from fire_uav_recording.metadata import (
    KEY_CLOSED,
    KEY_LOG_TIME_OFFSET_NS,
    KEY_RECORDER_STARTED,
    KEY_SCENARIO_FILE,
    KEY_SCENARIO_YAML,
    KEY_SEED,
    KEY_SOFTWARE_VERSION,
    KEY_UAV_COUNT,
)
from fire_uav_recording.reader import MissionBag, offered_qos, open_bag
from fire_uav_recording.salvage import SalvageResult, repair_bag, salvage_mcap
from fire_uav_recording.typestore import ensure_type, find_msg_dir, fleet_typestore, register_msg_dir
from fire_uav_recording.writer import INFINITE_DURATION, ROS_DISTRO, BagWriter

__all__ = [
    "KEY_CLOSED",
    "KEY_LOG_TIME_OFFSET_NS",
    "KEY_RECORDER_STARTED",
    "KEY_SCENARIO_FILE",
    "KEY_SCENARIO_YAML",
    "KEY_SEED",
    "KEY_SOFTWARE_VERSION",
    "KEY_UAV_COUNT",
    "INFINITE_DURATION",
    "MCAP_MAGIC",
    "ROS_DISTRO",
    "BagError",
    "BagInfo",
    "BagWriter",
    "ConfigError",
    "MissionBag",
    "RecordingError",
    "SalvageResult",
    "ensure_type",
    "find_msg_dir",
    "fleet_typestore",
    "inspect_bag",
    "offered_qos",
    "open_bag",
    "register_msg_dir",
    "repair_bag",
    "salvage_mcap",
]
