"""The one spin loop of the project's nodes and helper processes (imports rclpy when called).

ROS adapter module (the layering test lets ``ros_io.py`` import rclpy); the rest of
fire_uav_common stays ROS-free.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["spin"]


def spin(node: Any, on_exit: Callable[[], None] | None = None) -> None:
    """Spin ``node`` until Ctrl-C, an external shutdown or a ``SystemExit`` raised by a callback
    (a process ending itself), then call ``on_exit`` (if given), destroy the node and shut rclpy
    down (``try_shutdown``: a no-op when a signal handler already did)."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException, SystemExit):
        pass
    finally:
        if on_exit is not None:
            on_exit()
        node.destroy_node()
        rclpy.try_shutdown()
