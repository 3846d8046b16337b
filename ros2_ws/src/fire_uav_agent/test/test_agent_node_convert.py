"""The agent's rclpy message conversions (agent_io) (needs the built fire_uav_msgs; no DDS)."""

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.agent_io import to_peer_perimeter as _to_peer_perimeter
from fire_uav_common.stamps import step_to_ns, to_time_msg
from fire_uav_msgs.msg import PerimeterMap


@pytest.mark.parametrize("period_s", [0.1, 0.2, 0.05])
def test_perimeter_stamp_maps_to_its_step_with_the_scenario_control_period(period_s: float) -> None:
    m = PerimeterMap(uav_id=2, sequence=7, fire_id=3)
    m.header.stamp = to_time_msg(step_to_ns(41, round(period_s * 1e9)), Time)  # sent answering bundle 41
    p = _to_peer_perimeter(m, period_s)
    assert (p.uav_id, p.sequence, p.fire_id, p.step) == (2, 7, 3, 41)  # 0.1 s hard-coded gives 83 at 0.2 s


def test_fire_front_round_trip_keeps_cells_times_and_the_step() -> None:
    import dataclasses

    import numpy as np
    from fire_uav_agent.agent_io import front_msg as _from_front
    from fire_uav_agent.agent_io import to_peer_front as _to_peer_front
    from fire_uav_agent.fire_front import FrontCells

    cells = FrontCells(
        np.array([2.5, 7.5]), np.array([12.5, 17.5]), np.array([1, 2]), np.array([812.3, 799.9]),
        np.array([0.75, np.nan]),
    )  # fmt: skip
    out = type("Out", (), {})()
    out.front = cells
    out.state = type("S", (), {"uav_id": 4})()
    stamp = to_time_msg(step_to_ns(8123, round(0.1 * 1e9)), Time)
    msg = _from_front(out, stamp, 9, 5.0)
    p = _to_peer_front(msg, 0.1)
    assert (p.uav_id, p.sequence, p.step) == (4, 9, 8123)
    got = dataclasses.asdict(p.cells)
    for k, v in dataclasses.asdict(cells).items():
        np.testing.assert_allclose(got[k], v, rtol=1e-6)
    msg.x_m = [1.0]  # unequal lengths: a clear error, the node drops the message
    with pytest.raises(ValueError, match="must have the same length"):
        _to_peer_front(msg, 0.1)
