"""When the agent node builds its viz markers: ``UavAgentNode._want_markers`` on a stand-in for
the node (only what the method touches)."""

from __future__ import annotations

import types

import pytest

pytest.importorskip("rclpy")

from fire_uav_agent.agent_node import UavAgentNode


@pytest.mark.parametrize(
    ("every", "readers", "want"),
    [(5, 1, [0, 5, 10]), (5, 0, []), (0, 1, []), (1, 2, list(range(12)))],
)
def test_markers_are_built_every_n_steps_while_a_viz_reader_is_matched(every, readers, want):
    """``viz`` is best effort and volatile: markers with no matched reader reach no one, so the
    agent builds them only while one is matched (a viewer or the recorder), every n steps."""
    pub = types.SimpleNamespace(get_subscription_count=lambda: readers)
    stub = types.SimpleNamespace(marker_every=every, pub_viz=pub)
    assert [k for k in range(12) if UavAgentNode._want_markers(stub, k)] == want
