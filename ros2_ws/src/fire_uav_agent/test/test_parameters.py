"""Every parameter a node declares is in its default YAML, with the same default, and nothing else."""

import ast
from pathlib import Path

import pytest
import yaml

SRC = Path(__file__).resolve().parents[2]


def _literal(node: ast.AST):
    return ast.literal_eval(node)


def declared(*modules: Path) -> dict[str, object]:
    """name -> default of every ``declare_parameter("name", default, ...)`` and every
    ``("name", default, descriptor)`` tuple in a ``declare_*_parameters`` function."""
    out: dict[str, object] = {}
    for path in modules:
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "declare_parameter"
                and node.args
                and isinstance(node.args[0], ast.Constant)
            ):
                out[node.args[0].value] = _literal(node.args[1]) if len(node.args) > 1 else None
            if (
                isinstance(node, ast.FunctionDef)
                and node.name.startswith("declare_")
                and node.name.endswith("_parameters")
            ):
                for t in ast.walk(node):
                    if isinstance(t, ast.Tuple) and len(t.elts) == 3 and isinstance(t.elts[0], ast.Constant):
                        out[t.elts[0].value] = _literal(t.elts[1])
    return out


def yaml_params(path: Path) -> dict[str, object]:
    doc = yaml.safe_load(path.read_text())
    return doc["/**"]["ros__parameters"]


CASES = [
    (
        [
            SRC / "fire_uav_agent/fire_uav_agent/agent_params.py",
        ],
        SRC / "fire_uav_agent/config/agent.yaml",
    ),
    (
        [SRC / "fire_perimeter_monitor/fire_perimeter_monitor/viewer_node.py"],
        SRC / "fire_perimeter_monitor/config/perimeter_viewer.yaml",
    ),
]


@pytest.mark.parametrize(("modules", "config"), CASES, ids=["uav_agent", "perimeter_viewer"])
def test_declared_parameters_match_the_default_yaml(modules: list[Path], config: Path) -> None:
    code, conf = declared(*modules), yaml_params(config)
    assert sorted(set(code) - set(conf)) == [], f"declared but not in {config.name}"
    assert sorted(set(conf) - set(code)) == [], f"in {config.name} but not declared"
    assert {k: conf[k] for k in code} == code, "defaults differ"


def test_the_parser_finds_the_declarations() -> None:
    names = declared(*CASES[0][0])
    assert {"uav_id", "scenario_file", "monitor_alpha", "search_budget"} <= set(names)
