"""Layering: algorithm modules stay free of ROS (only node modules ``*_node.py`` and the
adapters in ``ROS_ADAPTERS`` may import rclpy); the report is ROS-free; the tools import ROS
only in the modules that run nodes; nothing edits ``sys.path`` outside the tests."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = [
    "fire_uav_common",
    "fire_world_sim",
    "fire_uav_agent",
    "fire_perimeter_monitor",
    "fire_uav_recording",
]
# tools/<package>: the modules that may import ROS (they run or talk to nodes); all others are ROS-free
TOOLS_ROS_MODULES = {
    "fire_mission": {"runner.py"},
    "fire_bench": {"skeleton.py"},
    "fire_report": set(),
    "fire_study": set(),
}
# ROS adapter modules besides the nodes: the spin loop, the agent's search adapter, the recording's
# raw subscriptions, the world's message builders
ROS_ADAPTERS = {"ros_io.py", "search_io.py", "agent_io.py", "raw_topics.py", "ros_messages.py"}
# test support that builds and reads ROS messages for the codec tests (never imported by a node)
ROS_TEST_SUPPORT = {"fire_uav_agent/testing/rclpy_reference.py", "fire_uav_agent/testing/msg_strategies.py"}
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


def _ros_imports(path: Path) -> list[str]:
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module]
        out += [
            f"{path.relative_to(ROOT)}:{node.lineno} imports {n}"
            for n in names
            if n.split(".")[0] in ROS_MODULES
        ]
    return out


def _algorithm_modules() -> list[Path]:
    out = []
    for pkg in PACKAGES:
        for path in (ROOT / "ros2_ws/src" / pkg / pkg).rglob("*.py"):
            test_support = path.relative_to(ROOT / "ros2_ws/src" / pkg).as_posix() in ROS_TEST_SUPPORT
            if not path.name.endswith("_node.py") and path.name not in ROS_ADAPTERS and not test_support:
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


def test_tools_import_ros_only_where_they_run_nodes():
    offenders = []
    for pkg, allowed in TOOLS_ROS_MODULES.items():
        paths = sorted((ROOT / "tools" / pkg).rglob("*.py"))
        assert paths, f"tools/{pkg} is empty"
        offenders += [o for p in paths if p.name not in allowed for o in _ros_imports(p)]
    assert not offenders, "ROS imports in ROS-free tools:\n" + "\n".join(offenders)


def test_report_reads_bags_through_the_recording_package_only():
    """fire_report is ROS-free and reads bags with fire_uav_recording's pure modules, never its nodes."""
    offenders = []
    for path in sorted((ROOT / "tools/fire_report").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and node.module:
                mods = [node.module]
            offenders += [
                f"{path.relative_to(ROOT)}:{node.lineno} imports {m}"
                for m in mods
                if m.endswith("_node")
                or m.startswith(("fire_world_sim", "fire_uav_agent", "rosbags.rosbag2"))
            ]
    assert not offenders, "\n".join(offenders)


def _repo_files() -> list[Path]:
    skip = {".venv", ".git", "build", "install", "log", "runs", "__pycache__", ".hypothesis"}
    out = []
    for path in ROOT.rglob("*"):
        rel = path.relative_to(ROOT)
        if not path.is_file() or skip & set(rel.parts) or rel.parts[0] == "tests" or "test" in rel.parts:
            continue
        if (
            path.suffix == ".py"
            or (path.parent.name == "scripts" and not path.suffix)
            or path.suffix == ".sh"
        ):
            out.append(path)
    return out


def test_nothing_edits_sys_path_outside_tests():
    """Imports come from installed packages (the colcon workspace, the tools' install), never from path edits."""
    pattern = re.compile(r"sys\.path\s*(\.\s*(insert|append|extend)\b|\[[^\]]*\]\s*=|\s*\+=)")
    files = _repo_files()
    assert any(p.name == "runner.py" for p in files) and any(p.name == "run_mission" for p in files)
    offenders = [
        f"{p.relative_to(ROOT)}:{n}: {line.strip()}"
        for p in files
        for n, line in enumerate(p.read_text(errors="replace").splitlines(), 1)
        if pattern.search(line)
    ]
    assert not offenders, "sys.path edited:\n" + "\n".join(offenders)


def test_no_message_constant_copies_in_the_tools():
    """The tools use fire_uav_common.constants: no literal copies of a message constant (TYPE_DROP = 2)."""
    from fire_uav_common.constants import MSG_CONSTANTS

    names = {f"{p}{e.name}" for (_, p), enum in MSG_CONSTANTS.items() for e in enum}
    assign = re.compile(
        r"^\s*([A-Z][A-Z0-9_]*(?:\s*,\s*[A-Z][A-Z0-9_]*)*)\s*=\s*-?\d+(?:\s*,\s*-?\d+)*\s*(#.*)?$"
    )
    offenders = []
    for path in sorted((ROOT / "tools").rglob("*.py")) + sorted((ROOT / "tests").rglob("*.py")):
        for n, line in enumerate(path.read_text().splitlines(), 1):
            m = assign.match(line)
            if m and {x.strip() for x in m.group(1).split(",")} & names:
                offenders.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not offenders, "message constants redefined:\n" + "\n".join(offenders)
