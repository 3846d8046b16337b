"""Mission orchestration without ROS launch: process groups, executables, the mission runner.

Public API: :class:`ProcessGroup`, :func:`executable`, :func:`private_domain_id`.
"""

from fire_mission.procs import MissionError, ProcessGroup, executable, private_domain_id, ros_run_argv

__all__ = ["MissionError", "ProcessGroup", "executable", "private_domain_id", "ros_run_argv"]
