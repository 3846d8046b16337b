"""Fixtures shared by fire_uav_agent's tests that need rclpy (imported only when a test uses them,
so the mutation stage, which has no ROS build, still collects the rest)."""

from __future__ import annotations

import pytest


@pytest.fixture
def ros_context():
    """A private rclpy context on a ROS domain no other test or run on this host holds."""
    pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain
    from fire_uav_common.ros_io import private_context

    with claim_domain() as domain, private_context(domain) as ctx:
        yield ctx


@pytest.fixture
def node_pair(ros_context):
    """Two nodes of this process on ``ros_context``, each on its own ``LeanExecutor`` as an agent's
    is: yields ``(sender, receiver, spin)``, ``spin()`` turning both once."""
    rclpy = pytest.importorskip("rclpy")
    from fire_uav_common.ros_io import LeanExecutor

    a = rclpy.create_node("sender", context=ros_context)
    b = rclpy.create_node("receiver", context=ros_context)
    ea, eb = LeanExecutor(context=ros_context), LeanExecutor(context=ros_context)
    ea.add_node(a)
    eb.add_node(b)

    def spin() -> None:
        ea.spin_once(timeout_sec=0.02)
        eb.spin_once(timeout_sec=0.02)

    try:
        yield a, b, spin
    finally:
        ea.shutdown()
        eb.shutdown()
        a.destroy_node()
        b.destroy_node()
