"""What an agent sends its peers each step, as bytes: the node publishes them, the in-process
harness hands the same bytes to the peers' readers. ROS-free.

The UavState of step k is the one peer message every step has: it carries this agent's fire
picture and ``sent_per_topic``, the count of what else it sent at k on each peer topic (indexed by
the topic's loss index, ``fire_uav_common.topics``), which the peers' lockstep wait holds out for.
"""

from __future__ import annotations

from collections.abc import Mapping

from fire_uav_common import topics
from fire_uav_common.codecs.uav_state import write_uav_state

from .agent_types import StepOutput

__all__ = ["sent_per_topic", "state_bytes"]

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
