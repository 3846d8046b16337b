"""What RViz / Foxglove would still draw from a recorded ``MarkerArray`` topic, replayed message by
message with the Marker semantics (ADD/MODIFY replaces ``(ns, id)``, DELETE removes it,
DELETEALL clears the namespace or everything) - an independent reading of the bag."""

from __future__ import annotations

from dataclasses import dataclass

from fire_uav_common.constants import FireStatus
from fire_uav_common.stamps import stamp_to_s

ADD, DELETE, DELETEALL = 0, 2, 3  # visualization_msgs/Marker action constants (the message's own)


@dataclass
class Drawn:
    t_s: float  # when it was last added [s sim]
    marker: object


def replay(messages) -> list[tuple[float, dict[tuple[str, int], Drawn]]]:
    """(time [s], what is drawn after that message) for each ``MarkerArray`` in ``messages``.

    The time is the markers' header stamp (the sim time they describe), else the bag time.
    """
    drawn: dict[tuple[str, int], Drawn] = {}
    out = []
    for _topic, t_ns, arr in messages:
        for m in arr.markers:
            key = (m.ns, int(m.id))
            if m.action == DELETEALL:
                for k in [k for k in drawn if not m.ns or k[0] == m.ns]:
                    del drawn[k]
            elif m.action == DELETE:
                drawn.pop(key, None)
            else:
                drawn[key] = Drawn(stamp_to_s(m.header.stamp), m)
        t_s = stamp_to_s(arr.markers[0].header.stamp) if arr.markers else t_ns * 1e-9
        out.append((t_s, dict(drawn)))
    return out


def fire_out_times(truth_messages) -> dict[int, float]:
    """fire id -> first sim time [s] at which ``/world/truth`` says it is no longer ACTIVE."""
    out: dict[int, float] = {}
    for _topic, _t, msg in truth_messages:
        for f in msg.fires:
            if f.status != FireStatus.ACTIVE and int(f.fire_id) not in out:
                out[int(f.fire_id)] = stamp_to_s(msg.header.stamp)
    return out


def stale_fire_markers(viz_messages, truth_messages, fire_ns: str = "fire") -> list[str]:
    """Every /viz/world frame after a fire is out that still draws a marker for it."""
    out_at = fire_out_times(truth_messages)
    stale = []
    for t_s, drawn in replay(viz_messages):
        for ns, i in drawn:
            if ns == fire_ns and i in out_at and t_s > out_at[i] + 1e-6:
                stale.append(f"t = {t_s:.1f} s: fire {i} (out at {out_at[i]:.1f} s) still drawn")
    return stale
