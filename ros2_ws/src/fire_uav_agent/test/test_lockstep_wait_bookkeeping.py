"""The lockstep wait's stored bookkeeping: only peer messages are recorded.

``PeerWait`` keeps "which peer messages of which step have arrived" (its docstring). A peer is an
id in 0..uav_count-1 other than the agent's own, and steps start at 0 (docs/protocol.md
"Lockstep"), so a message from the agent itself, from an id outside the fleet or of a negative
step is no peer message: ``on_state`` ignores it (``_valid``), and ``on_message`` must too, or
``PeerGate.on_arrival`` (which passes coverage arrivals on unchecked) fills the bookkeeping with
keys that ``missing`` never reads and only a prune removes.
"""

from __future__ import annotations

import pytest
from fire_uav_agent.lockstep_wait import STATE_INDEX, PeerWait
from fire_uav_common.topics import FLEET_FIRES_SPEC

FIRES = FLEET_FIRES_SPEC.loss_index


@pytest.mark.parametrize(
    ("sender", "step"),
    [
        (0, 4),  # the agent itself (uav_id 0)
        (3, 4),  # uav_count: one past the last id
        (9, 4),  # far outside the fleet
        (-1, 4),  # a negative id
        (1, -1),  # a real peer, a step before the first
        (2, -7),
    ],
)
def test_a_message_that_is_no_peer_message_is_not_recorded(sender: int, step: int) -> None:
    w = PeerWait(uav_id=0, uav_count=3, period_s=0.1)
    for t in (STATE_INDEX, FIRES, 5, 17):
        w.on_message(sender, step, t)
    w.on_state(sender, step, (1, 1, 0, 0, 0, 2), False)
    assert dict(w._arrived) == {} and w._sent == {} and w._owed == {}
    assert w.missing(max(step, 0) + 1) == [1, 2]  # and nothing else changed


def test_peer_messages_are_recorded_beside_ignored_ones() -> None:
    """The same calls from a real peer of a real step are recorded, counted per topic."""
    w = PeerWait(uav_id=0, uav_count=3, period_s=0.1)
    w.on_message(1, 4, FIRES)
    w.on_message(0, 4, FIRES)  # itself: ignored
    w.on_message(3, 4, FIRES)  # outside the fleet: ignored
    w.on_message(2, -1, FIRES)  # negative step: ignored
    w.on_message(1, 4, FIRES)
    w.on_state(2, 4, (1, 1, 0, 0, 0, 0), False)
    assert dict(w._arrived) == {(4, 1): {FIRES: 2}, (4, 2): {STATE_INDEX: 1}}


def test_a_second_state_of_a_step_nobody_asked_about_is_counted_again() -> None:
    """A peer's state of a step sent twice (a resend) sets its counts again, whether or not the
    wait was asked about that step in between (``ready`` keeps where its scan stopped only for
    steps it was asked about): the second copy must not fail, and the counts it sets hold."""
    w = PeerWait(uav_id=0, uav_count=3, period_s=0.1)
    w.on_state(1, 4, (1, 1, 0, 0, 0, 0), False)
    w.on_state(1, 4, (1, 0, 0, 0, 0, 0), False)  # no ready(5) between the two
    w.on_state(2, 4, (1, 0, 0, 0, 0, 0), False)
    assert w.ready(5) and w.missing(5) == []
