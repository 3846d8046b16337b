"""A private rclpy context for tests that talk DDS inside one process (rclpy imported on use)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["private_rclpy_context"]


@contextlib.contextmanager
def private_rclpy_context() -> Iterator[object]:
    """An initialised ``rclpy.Context`` on a domain claimed by ``fire_mission.procs.claim_domain``
    (no other run or test on this host holds it), shut down on exit."""
    import rclpy
    from fire_mission.procs import claim_domain

    with claim_domain() as domain:
        ctx = rclpy.Context()
        rclpy.init(context=ctx, domain_id=domain)
        try:
            yield ctx
        finally:
            rclpy.try_shutdown(context=ctx)
