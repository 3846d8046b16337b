"""Post-mission review of a recorded fleet bag, without ROS.

``load_mission(path)`` reads a mission bag (rosbags ``AnyReader``, message definitions from
the bag) into numpy arrays; ``compute_metrics(mission)`` gives the numbers of metrics.json;
``write_report(path, out_dir)`` writes metrics.json, the figures (PNG) and index.html.
Command line: ``scripts/report BAG [-o DIR]`` (``python -m fire_report``).
"""

from fire_report.data import RecordedEvent, RecordedMission, load_mission
from fire_report.errors import ReportError
from fire_report.metrics import compute_metrics

__all__ = [
    "RecordedEvent",
    "RecordedMission",
    "ReportError",
    "compute_metrics",
    "load_mission",
    "write_report",
]


def __getattr__(name: str):
    """``write_report`` on first use: it brings matplotlib (~0.3 s, ~1.4 s CPU on a loaded
    machine), which the metrics alone (the runner's summary at every mission end) do not need."""
    if name == "write_report":
        from fire_report.report import write_report

        return write_report
    raise AttributeError(f"module 'fire_report' has no attribute {name!r}")
