"""What an agent takes from its peers' PerimeterMap and FireFront, read by the codecs
(``fire_uav_common.codecs``): the node and the in-process harness both call these on the bytes
received (the sending side: ``outgoing``). ROS-free.

A message's step is that of its stamp: a peer stamps what it sends at step k with the bundle
stamp (k + 1) T it answers (docs/protocol.md).
"""

from __future__ import annotations

from fire_uav_common.codecs.fire_front import WireFront
from fire_uav_common.codecs.perimeter_map import WirePerimeter
from fire_uav_common.stamps import s_to_ns, stamp_to_step

from .agent_types import PeerPerimeter
from .fire_front import FrontCells
from .front_consensus import PeerFront

__all__ = ["message_step", "peer_front", "peer_perimeter"]


def message_step(stamp_ns: int, control_period_s: float) -> int:
    """The step k whose answer carries stamp ``stamp_ns`` [ns]."""
    return stamp_to_step(stamp_ns, s_to_ns(control_period_s))


def peer_perimeter(w: WirePerimeter, control_period_s: float) -> PeerPerimeter:
    """A peer's PerimeterMap as its monitor merges it (``PerimeterMonitor.merge``'s summary keys)."""
    summary = {
        "center_x_m": w.center_x_m,
        "center_y_m": w.center_y_m,
        "outer_distance_m": w.outer_distance_m,
        "outer_visit_time_s": w.outer_visit_time_s,
    }
    step = message_step(w.stamp_ns, control_period_s)
    return PeerPerimeter(w.uav_id, w.sequence, step, w.fire_id, summary)


def peer_front(w: WireFront, control_period_s: float) -> PeerFront:
    """A peer's FireFront with its cell size (the receiver merges it only into a picture of that
    side: :func:`.front_consensus.same_cell_size`); raises ValueError
    (:class:`~fire_uav_agent.errors.ConfigError`) if its arrays differ in length: the caller drops
    the content."""
    cells = FrontCells(w.x_m, w.y_m, w.state, w.observed_s, w.spread_rate_mps)
    step = message_step(w.stamp_ns, control_period_s)
    return PeerFront(w.uav_id, w.sequence, step, cells, float(w.cell_size_m))
