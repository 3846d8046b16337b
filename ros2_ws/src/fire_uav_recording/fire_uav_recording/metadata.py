"""The ``custom_data`` keys a mission bag carries in its ``metadata.yaml`` (all values are strings)."""

from __future__ import annotations

__all__ = [
    "KEY_CLOSED",
    "KEY_LOG_TIME_OFFSET_NS",
    "KEY_RECORDER_STARTED",
    "KEY_SCENARIO_FILE",
    "KEY_SCENARIO_YAML",
    "KEY_SEED",
    "KEY_SOFTWARE_VERSION",
    "KEY_UAV_COUNT",
]

KEY_SCENARIO_FILE = "fire_uav.scenario_file"  # path the recorder was given
KEY_SCENARIO_YAML = "fire_uav.scenario_yaml"  # the file's full text ("" if none)
KEY_SEED = "fire_uav.seed"  # int, as text
KEY_UAV_COUNT = "fire_uav.uav_count"  # int, as text
KEY_SOFTWARE_VERSION = "fire_uav.software_version"  # versions of the recording package, the world, rosbags
KEY_RECORDER_STARTED = "fire_uav.recorder_started_utc"  # ISO 8601 wall time
KEY_CLOSED = "fire_uav.closed_cleanly"  # "true" once close() ran, "false" in the snapshots
KEY_LOG_TIME_OFFSET_NS = "fire_uav.log_time_offset_ns"  # int, as text: bag time - sim time [ns] (0: sim time)
