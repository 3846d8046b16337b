"""The algorithm modules must not import rclpy (the layering: algorithms stay free of ROS)."""

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "fire_uav_agent"
PURE = [
    "estimation", "peer_link", "consensus", "coverage", "mission", "agent_core", "agent_config", "agent_types",
    "planning", "staleness_search", "monitor_role", "lake_sequence", "testing/harness", "wind_estimation",
]  # fmt: skip


def test_no_rclpy_in_algorithm_modules():
    for name in PURE:
        tree = ast.parse((PKG / f"{name}.py").read_text())
        for node in ast.walk(tree):
            mods = []
            if isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                mods = [node.module]
            for m in mods:
                assert not m.startswith(("rclpy", "fire_uav_msgs", "geometry_msgs")), f"{name}.py imports {m}"
