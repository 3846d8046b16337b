"""agent_node's message conversions (needs the built fire_uav_msgs; no DDS)."""

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.agent_node import _to_peer_perimeter
from fire_uav_common.stamps import step_to_ns, to_time_msg
from fire_uav_msgs.msg import PerimeterMap


@pytest.mark.parametrize("period_s", [0.1, 0.2, 0.05])
def test_perimeter_stamp_maps_to_its_step_with_the_scenario_control_period(period_s: float) -> None:
    m = PerimeterMap(uav_id=2, sequence=7, fire_id=3)
    m.header.stamp = to_time_msg(step_to_ns(41, round(period_s * 1e9)), Time)  # sent answering bundle 41
    p = _to_peer_perimeter(m, period_s)
    assert (p.uav_id, p.sequence, p.fire_id, p.step) == (2, 7, 3, 41)  # 0.1 s hard-coded gives 83 at 0.2 s
