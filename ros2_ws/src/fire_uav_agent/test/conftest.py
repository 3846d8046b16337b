"""Fixtures shared by fire_uav_agent's tests that need rclpy (imported only when a test uses them,
so the mutation stage, which has no ROS build, still collects the rest)."""

from __future__ import annotations

import pytest


@pytest.fixture
def ros_context():
    """A private rclpy context on a ROS domain no other test or run on this host holds."""
    rclpy = pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain

    with claim_domain() as domain:
        ctx = rclpy.Context()
        rclpy.init(context=ctx, domain_id=domain)
        try:
            yield ctx
        finally:
            rclpy.try_shutdown(context=ctx)
