"""Every message constant of ``fire_uav_msgs`` as an IntEnum, the one place outside the .msg files.

Each enum mirrors one group of constants of one message (``UavState.OBJECTIVE_*`` is
:class:`Objective`, ...). ``test_constants.py`` parses the ``.msg`` files and fails if a name or a
value differs, so a constant changed in a message cannot drift from the code that uses it.
ROS-free: algorithm modules use these instead of importing the generated message classes.
"""

from __future__ import annotations

from enum import IntEnum

__all__ = [
    "MSG_CONSTANTS",
    "CandidateKind",
    "CellState",
    "EventType",
    "FireStatus",
    "MstKind",
    "Objective",
    "PayloadAction",
    "PerimeterDirection",
    "VehicleStatus",
]


class Objective(IntEnum):
    """``UavState.OBJECTIVE_*``: what a UAV is doing (FF IV-D objectives, plus CP search and PM)."""

    GROUNDED = 0
    SUPPRESS = 1
    REFILL = 2
    LAND = 3
    SEARCH = 4
    MONITOR = 5
    LANDED = 6


class VehicleStatus(IntEnum):
    """``SensorBundle.VEHICLE_*``: the vehicle's own flight status as the world reports it."""

    ON_GROUND = 0
    AIRBORNE = 1
    LANDED = 2
    CRASHED = 3


class EventType(IntEnum):
    """``MissionEvent.TYPE_*``."""

    TAKEOFF = 1
    DROP = 2
    REFILL = 3
    CRASH = 4
    EXTINGUISHED = 5
    LANDED = 6
    PEER_CRASHED = 7
    PEER_REJOINED = 8
    COMMAND_CLAMPED = 9
    MISSION_COMPLETE = 10
    FIRE_DETECTED = 11
    OBJECTIVE = 12
    COMMAND_MISSED = 13
    IGNITION = 14
    AGENT_READY = 15
    AGENT_LOST = 16
    RESEND_REQUEST = 17


class FireStatus(IntEnum):
    """``FireEstimate.STATUS_*`` (also used in ``FireTruth.status``)."""

    ACTIVE = 0
    EXTINGUISHED = 1


class CellState(IntEnum):
    """``FireCells.CELL_*``: state of one raster cell."""

    UNBURNED = 0
    BURNING = 1
    BURNED = 2


class PayloadAction(IntEnum):
    """``PayloadRequest.ACTION_*``."""

    NONE = 0
    DROP = 1
    REFILL = 2


class PerimeterDirection(IntEnum):
    """``PerimeterMap.DIRECTION_*``: the monitor's direction of travel along the perimeter."""

    CCW = 0
    CW = 1


class CandidateKind(IntEnum):
    """``CoverageCandidate.KIND_*`` (CP Bayesian optimisation traffic)."""

    PROPOSAL = 0
    COST = 1


class MstKind(IntEnum):
    """``MstFragment.KIND_*`` (CP fragment-merge MST traffic)."""

    PROBE = 0
    MERGE = 1
    DONE = 2


#: (message, constant prefix) -> enum, for the test against the .msg files and for name lookups
MSG_CONSTANTS: dict[tuple[str, str], type[IntEnum]] = {
    ("UavState", "OBJECTIVE_"): Objective,
    ("SensorBundle", "VEHICLE_"): VehicleStatus,
    ("MissionEvent", "TYPE_"): EventType,
    ("FireEstimate", "STATUS_"): FireStatus,
    ("FireCells", "CELL_"): CellState,
    ("PayloadRequest", "ACTION_"): PayloadAction,
    ("PerimeterMap", "DIRECTION_"): PerimeterDirection,
    ("CoverageCandidate", "KIND_"): CandidateKind,
    ("MstFragment", "KIND_"): MstKind,
}
