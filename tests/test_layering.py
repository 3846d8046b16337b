"""Algorithm modules stay free of ROS: only node modules (``*_node.py``) and the adapters
``ros_io.py``/``search_io.py`` may import rclpy."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ["fire_uav_common", "fire_world_sim", "fire_uav_agent", "fire_perimeter_monitor"]
ROS_MODULES = (
    "rclpy",
    "fire_uav_msgs",
    "rosgraph_msgs",
    "geometry_msgs",
    "sensor_msgs",
    "nav_msgs",
    "visualization_msgs",
    "std_msgs",
    "builtin_interfaces",
)


def _algorithm_modules() -> list[Path]:
    out = []
    for pkg in PACKAGES:
        for path in (ROOT / "ros2_ws/src" / pkg / pkg).rglob("*.py"):
            if not path.name.endswith("_node.py") and path.name not in ("ros_io.py", "search_io.py"):
                out.append(path)
    return out


def test_algorithm_modules_do_not_import_ros():
    offenders = []
    for path in _algorithm_modules():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            for n in names:
                if n.split(".")[0] in ROS_MODULES:
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} imports {n}")
    # fire_uav_common.topics imports rclpy.qos lazily inside qos(), which ast.walk sees too:
    offenders = [
        o for o in offenders if not o.startswith("ros2_ws/src/fire_uav_common/fire_uav_common/topics.py")
    ]
    assert not offenders, "ROS imports in algorithm modules:\n" + "\n".join(offenders)


def test_there_are_algorithm_modules_to_check():
    assert len(_algorithm_modules()) >= 4


def _imports(path: Path) -> list[tuple[int, str]]:
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            out.append((node.lineno, node.module))
    return out


def test_agent_package_uses_the_world_only_in_its_test_support():
    """The agent knows the world through its sensors: only ``fire_uav_agent/testing/`` (the
    in-process harness) may import fire_world_sim."""
    pkg = ROOT / "ros2_ws/src/fire_uav_agent/fire_uav_agent"
    offenders = [
        f"{path.relative_to(ROOT)}:{line} imports {name}"
        for path in pkg.rglob("*.py")
        if "testing" not in path.relative_to(pkg).parts
        for line, name in _imports(path)
        if name.split(".")[0] == "fire_world_sim"
    ]
    assert not offenders, "fire_world_sim imported outside testing/:\n" + "\n".join(offenders)
    harness = pkg / "testing" / "harness.py"
    assert any(n.split(".")[0] == "fire_world_sim" for _, n in _imports(harness))  # the check sees imports


def test_new_agent_modules_are_checked():
    paths = {p.relative_to(ROOT / "ros2_ws/src").as_posix() for p in _algorithm_modules()}
    for name in (
        "agent_core",
        "agent_config",
        "agent_types",
        "planning",
        "staleness_search",
        "testing/harness",
    ):
        assert f"fire_uav_agent/fire_uav_agent/{name}.py" in paths
