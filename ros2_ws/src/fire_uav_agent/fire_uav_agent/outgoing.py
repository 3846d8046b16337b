"""What an agent sends its peers each step, as bytes: the node publishes them, the in-process
harness hands the same bytes to the peers' readers (their side: ``incoming``). ROS-free.

The UavState of step k is the one peer message every step has: it carries this agent's fire
picture and ``sent_per_topic``, the count of what else it sent at k on each peer topic (indexed by
the topic's loss index, ``fire_uav_common.topics``), which the peers' lockstep wait holds out for.
"""

from __future__ import annotations

from collections.abc import Mapping

from fire_uav_common import topics
from fire_uav_common.codecs.fire_front import write_fire_front
from fire_uav_common.codecs.perimeter_map import write_perimeter_map
from fire_uav_common.codecs.uav_state import write_uav_state

from .agent_types import StepOutput
from .fire_front import FrontCells

__all__ = ["front_bytes", "perimeter_bytes", "sent_per_topic", "state_bytes"]

_TOPICS = 1 + max(s.loss_index for s in topics.ALL_TOPICS if s.loss_index is not None)


def sent_per_topic(perimeter: bool, front: bool, coverage: Mapping[int, int] | None = None) -> list[int]:
    """Messages sent this step per loss index: the state and its fire picture (one each), a
    perimeter map and a front picture (0 or 1), and the coverage messages (``coverage``: loss
    index -> count)."""
    sent = [0] * _TOPICS
    sent[topics.FLEET_STATE_SPEC.draw_index] = 1
    sent[topics.FLEET_FIRES_SPEC.draw_index] = 1  # the part the state carries (its own loss draw)
    sent[topics.FLEET_PERIMETER_SPEC.draw_index] = int(perimeter)
    sent[topics.FLEET_FRONT_SPEC.draw_index] = int(front)
    for index, n in (coverage or {}).items():
        sent[index] = n
    return sent


def state_bytes(out: StepOutput, stamp_ns: int, sent: list[int], final: bool) -> bytes:
    """``out``'s UavState (with its fire picture) as CDR bytes, stamped ``stamp_ns`` (the bundle
    stamp of the step), ``auth`` zero; ``final``: the vehicle crashed (its last state)."""
    st = out.state
    return write_uav_state(
        stamp_ns=stamp_ns,
        uav_id=st.uav_id,
        sequence=st.sequence,
        step=st.step,
        pose=[float(v) for v in st.s],
        covariance=[float(v) for v in st.covariance.ravel()],
        objective=st.objective,
        target_fire_id=st.target_fire_id,
        water_kg=st.water_kg,
        centroid_xy=st.centroid_xy,
        alive_peers=st.alive_peers,
        crashed_peers=st.crashed_peers,
        packets=(st.packets_received, st.packets_lost, st.packets_rejected),
        sent_per_topic=sent,
        final=final,
        fires_sequence=out.fires_sequence,
        fires=out.fires,
    )


def perimeter_bytes(out: StepOutput, stamp_ns: int, sequence: int) -> bytes | None:
    """``out``'s PerimeterMap as CDR bytes (``auth`` zero), or None if it has none this step. A
    briefed fire's id (beyond int32) is sent as -1."""
    if out.perimeter is None:
        return None
    fire_id, s = out.perimeter
    return write_perimeter_map(
        stamp_ns=stamp_ns,
        uav_id=out.state.uav_id,
        sequence=sequence,
        fire_id=int(fire_id) if fire_id < 2**31 else -1,
        center_xy=(s["center_x_m"], s["center_y_m"]),
        outer_distance_m=s["outer_distance_m"],
        outer_visit_time_s=s["outer_visit_time_s"],
        spread_rate_mps=s["spread_rate_mps"],
        importance=s["importance"],
        direction=int(s["direction"]),
        direction_changes=int(s["direction_changes"]),
    )


def front_bytes(out: StepOutput, stamp_ns: int, sequence: int, cell_size_m: float) -> bytes | None:
    """``out``'s FireFront as CDR bytes, or None if it has no front picture this step."""
    c = out.front
    if not isinstance(c, FrontCells):
        return None
    return write_fire_front(
        stamp_ns=stamp_ns,
        uav_id=out.state.uav_id,
        sequence=sequence,
        cell_size_m=cell_size_m,
        x_m=c.x_m,
        y_m=c.y_m,
        state=c.state,
        observed_s=c.t_obs_s,
        spread_rate_mps=c.ros_mps,
    )
