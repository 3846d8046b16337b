"""The world node's parameters without ROS: one table, one validation, one error naming the
parameter."""

from __future__ import annotations

import pytest
from fire_uav_common.auth import KEY_BYTES
from fire_world_sim.errors import ConfigError, WorldError
from fire_world_sim.world_config import PARAMETERS, authenticator_from, config_from_parameters


def defaults(**kw: object) -> dict[str, object]:
    v = {p.name: p.default for p in PARAMETERS}
    v["scenario_file"] = "s.yaml"
    v.update(kw)
    return v


def test_every_parameter_once_and_the_key_is_the_only_one_not_read_only() -> None:
    names = [p.name for p in PARAMETERS]
    assert len(names) == len(set(names))
    assert [p.name for p in PARAMETERS if not p.read_only] == ["fleet_key"]
    for p in PARAMETERS:  # every default lies in its own range
        lo_hi = p.int_range or p.float_range
        if lo_hi is not None:
            assert lo_hi[0] <= p.default <= lo_hi[1], p.name  # type: ignore[operator]


def test_the_defaults_make_a_config() -> None:
    cfg = config_from_parameters(defaults(offline_schedule="1@2:3"))
    assert cfg.mode == "lockstep" and cfg.seed == -1 and cfg.uav_count == 0 and not cfg.no_fleet
    assert [(w.uav_id, w.start_s, w.end_s) for w in cfg.offline_schedule] == [(1, 2.0, 3.0)]


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"scenario_file": ""}, r"^parameter scenario_file is required"),
        ({"mode": "fast"}, r"^parameter mode must be 'lockstep' or 'realtime', got 'fast'$"),
        ({"real_time_factor": 0.0}, r"^parameter real_time_factor must be > 0, got 0.0$"),
        ({"real_time_factor": float("nan")}, r"^parameter real_time_factor must be > 0, got nan$"),
        ({"max_duration_s": -1.0}, r"^parameter max_duration_s must be >= 0, got -1.0$"),
        ({"offline_schedule": "x@1"}, r"^parameter offline_schedule: offline schedule entry 'x@1'"),
        ({"offline_schedule": "300@1"}, r"^parameter offline_schedule: UAV ids are 0..255$"),
    ],
)
def test_a_bad_value_names_the_parameter(kw: dict[str, object], match: str) -> None:
    with pytest.raises(ConfigError, match=match) as err:
        config_from_parameters(defaults(**kw))
    assert isinstance(err.value, WorldError) and isinstance(err.value, ValueError)


def test_the_fleet_key() -> None:
    assert authenticator_from(False, "") is None
    assert authenticator_from(True, "ab" * KEY_BYTES) is not None
    with pytest.raises(ConfigError, match=r"^parameter fleet_key is required when auth is true"):
        authenticator_from(True, "")
    with pytest.raises(ConfigError, match=r"^parameter fleet_key: fleet key must be 64 hex digits, got 3"):
        authenticator_from(True, "abc")


def test_the_table_is_the_default_yaml() -> None:
    """Every parameter of the table is in config/world.yaml with the same default, and back."""
    from pathlib import Path

    import yaml

    path = Path(__file__).resolve().parents[1] / "config" / "world.yaml"
    conf = yaml.safe_load(path.read_text())["/**"]["ros__parameters"]
    assert {p.name: p.default for p in PARAMETERS} == conf
