"""``/world/fire_type``: the fire type grid on the raster's frame, row 0 the southern row."""

from __future__ import annotations

import numpy as np
from fire_world_sim import ros_messages as msgs
from fire_world_sim.fires import FireGrid


def test_fire_type_msg_carries_the_grid_on_the_fire_grids_frame() -> None:
    state = np.zeros((2, 3), dtype=np.uint8)
    grid = FireGrid(100.0, -50.0, 30.0, state, np.zeros_like(state, dtype=bool))
    types = np.array([[1, 0, 2], [3, 1, 0]], dtype=np.uint8)
    m = msgs.fire_type_msg(grid, types, 5_000_000_000)
    assert (m.info.width, m.info.height) == (3, 2)
    assert m.info.resolution == 30.0
    assert (m.info.origin.position.x, m.info.origin.position.y) == (100.0, -50.0)
    assert m.header.stamp.sec == 5
    assert np.array_equal(np.asarray(m.data, dtype=np.int8).reshape(2, 3), types)
