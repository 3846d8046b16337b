"""Fixtures shared by fire_uav_recording's tests."""

from __future__ import annotations

import pytest


@pytest.fixture
def own_domain():
    """A ROS domain for this test alone; the test initializes rclpy's default context on it, this
    shuts it down."""
    rclpy = pytest.importorskip("rclpy")
    from fire_mission.procs import claim_domain

    with claim_domain() as domain:
        try:
            yield domain
        finally:
            rclpy.try_shutdown()
