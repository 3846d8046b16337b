"""Mission orchestration without ROS launch: process groups, executables, the mission runner.

Public API: :class:`ProcessGroup`, :func:`executable`, :func:`claim_domain`.
"""

from fire_mission.errors import MissionError
from fire_mission.procs import (
    DOMAIN_RANGE,
    ProcessGroup,
    claim_domain,
    executable,
    ros_run_argv,
)

__all__ = ["DOMAIN_RANGE", "MissionError", "ProcessGroup", "claim_domain", "executable", "ros_run_argv"]
