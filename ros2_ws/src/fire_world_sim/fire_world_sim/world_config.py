"""The world node's parameters, declared from one table and validated once into a frozen config.

ROS-free: :data:`PARAMETERS` lists every parameter (name, default, description, range) and the
node turns each row into a read-only ``declare_parameter``; :func:`config_from_parameters`
checks the values it read and raises :class:`~fire_world_sim.errors.ConfigError` naming the
parameter. The fleet key is read apart (:func:`authenticator_from`): the node undeclares it once
read, so it is never listed or logged.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from fire_uav_common.auth import Authenticator
from fire_uav_common.auth import authenticator_from as auth_from_parameters
from fire_uav_common.lockstep import OfflineWindow, parse_schedule

from .errors import ConfigError

__all__ = [
    "MODES",
    "PARAMETERS",
    "ParameterSpec",
    "WorldNodeConfig",
    "authenticator_from",
    "config_from_parameters",
]

MODES = ("lockstep", "realtime")


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of the world node; ``int_range`` / ``float_range`` (inclusive) if bounded."""

    name: str
    default: object
    description: str
    int_range: tuple[int, int] | None = None
    float_range: tuple[float, float] | None = None
    read_only: bool = True


PARAMETERS: tuple[ParameterSpec, ...] = (
    ParameterSpec("scenario_file", "", "scenario YAML (required)"),
    ParameterSpec("seed", -1, "RNG seed; -1 = the scenario's", int_range=(-1, 2**31 - 1)),
    ParameterSpec("uav_count", 0, "vehicles; 0 = the scenario's", int_range=(0, 255)),
    ParameterSpec("mode", "lockstep", "lockstep | realtime"),
    ParameterSpec("real_time_factor", 1.0, "realtime mode: sim seconds per wall second (> 0)"),
    ParameterSpec(
        "liveness_check_wall_s",
        0.5,
        "[s wall] lockstep: how often to check that the agents waited for still have a process "
        "(DDS graph); never a timeout on a live agent",
        float_range=(0.01, 60.0),
    ),
    ParameterSpec(
        "startup_timeout_wall_s",
        120.0,
        "[s wall] wait for every agent's ready handshake before step 0",
        float_range=(0.0, 3600.0),
    ),
    ParameterSpec(
        "offline_schedule",
        "",
        "lockstep fault schedule 'K@T1:T2;K@T1' [s sim]: agent K offline (frozen / killed); "
        "see fire_uav_common.lockstep",
    ),
    ParameterSpec("max_duration_s", 0.0, "[s sim] mission limit; 0 = the scenario's"),
    ParameterSpec(
        "wait_for_subscribers",
        0,
        "[-] before step 0, also wait (up to startup_timeout_wall_s) until /world/truth has this "
        "many subscribers, e.g. the recorder, so a bag starts at step 0",
        int_range=(0, 1000),
    ),
    ParameterSpec("viz_rate_hz", 2.0, "[Hz sim] /viz/* publication rate", float_range=(0.01, 100.0)),
    ParameterSpec(
        "no_fleet", False, "no vehicle at all: the fire burns alone (the suppression baseline, --uavs 0)"
    ),
    ParameterSpec("auth", True, "verify HMAC-SHA256 tags (docs/security.md)"),
    # not read-only: the node undeclares it once read, so the key is not left readable
    ParameterSpec("fleet_key", "", "per-mission key, 64 hex digits", read_only=False),
)


@dataclass(frozen=True)
class WorldNodeConfig:
    scenario_file: str
    seed: int
    uav_count: int
    mode: str
    real_time_factor: float
    liveness_check_wall_s: float
    startup_timeout_wall_s: float
    offline_schedule: tuple[OfflineWindow, ...]
    max_duration_s: float
    viz_rate_hz: float
    wait_for_subscribers: int
    no_fleet: bool = False


def _schedule(text: str) -> tuple[OfflineWindow, ...]:
    try:
        return parse_schedule(text)
    except ValueError as e:
        raise ConfigError(f"parameter offline_schedule: {e}") from None


def config_from_parameters(values: Mapping[str, Any]) -> WorldNodeConfig:
    """The config from the values of :data:`PARAMETERS` (by name); ConfigError on a bad one."""
    v = values
    cfg = WorldNodeConfig(
        scenario_file=str(v["scenario_file"]),
        seed=int(v["seed"]),
        uav_count=int(v["uav_count"]),
        mode=str(v["mode"]),
        real_time_factor=float(v["real_time_factor"]),
        liveness_check_wall_s=float(v["liveness_check_wall_s"]),
        startup_timeout_wall_s=float(v["startup_timeout_wall_s"]),
        offline_schedule=_schedule(str(v["offline_schedule"])),
        max_duration_s=float(v["max_duration_s"]),
        viz_rate_hz=float(v["viz_rate_hz"]),
        no_fleet=bool(v["no_fleet"]),
        wait_for_subscribers=int(v["wait_for_subscribers"]),
    )
    if any(w.uav_id >= 256 for w in cfg.offline_schedule):
        raise ConfigError("parameter offline_schedule: UAV ids are 0..255")
    if not cfg.scenario_file:
        raise ConfigError("parameter scenario_file is required (path to a scenario YAML)")
    if cfg.mode not in MODES:
        raise ConfigError(f"parameter mode must be 'lockstep' or 'realtime', got {cfg.mode!r}")
    if not (math.isfinite(cfg.real_time_factor) and cfg.real_time_factor > 0):
        raise ConfigError(f"parameter real_time_factor must be > 0, got {cfg.real_time_factor}")
    if not (math.isfinite(cfg.max_duration_s) and cfg.max_duration_s >= 0):
        raise ConfigError(f"parameter max_duration_s must be >= 0, got {cfg.max_duration_s}")
    return cfg


def authenticator_from(auth: bool, key: str) -> Authenticator | None:
    """``auth`` / ``fleet_key`` (docs/security.md): None when authentication is off; a bad key is
    this package's ConfigError."""
    return auth_from_parameters(auth, key, ConfigError)
