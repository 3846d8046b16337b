"""Every parameter of ``uav_agent`` in one place, and their reading into a frozen :class:`NodeConfig`.

:func:`declare_agent_parameters` lists each parameter with its default and :class:`ParamSpec`
(description, read-only, range); the node declares exactly these. :func:`unknown_parameters`
names what the node was given but does not declare (a misspelt name would otherwise be ignored
silently by rclpy, and the run would use the default), and :func:`node_config` validates the
values, raising :class:`~fire_uav_agent.errors.ConfigError` with a one-line message naming the
parameter and the value. The defaults here and in ``config/agent.yaml`` are the same
(test_parameters). ROS-free: the node hands the values in.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from fire_uav_common.auth import Authenticator, authenticator_from
from fire_uav_common.lockstep import OfflineWindow, parse_schedule
from fire_uav_common.scenario import LinkOutage

from .agent_config import AgentConfig, config_from_scenario
from .errors import ConfigError
from .search_io import SearchParams

__all__ = [
    "RCLPY_PARAMETERS",
    "NodeConfig",
    "ParamSpec",
    "declare_agent_parameters",
    "node_config",
    "unknown_parameters",
]

#: parameters every rclpy node has (declared by rclpy itself)
RCLPY_PARAMETERS = frozenset({"use_sim_time", "start_type_description_service"})


@dataclass(frozen=True)
class ParamSpec:
    """How a parameter is declared: its description, whether it is read-only, its range."""

    description: str
    read_only: bool = True
    float_range: tuple[float, float] | None = None
    int_range: tuple[int, int] | None = None


def _ro(text: str, **kw) -> ParamSpec:
    return ParamSpec(text, True, **kw)


def _float_range(lo: float, hi: float) -> tuple[float, float]:
    return (lo, hi)


def _int_range(lo: int, hi: int) -> tuple[int, int]:
    return (lo, hi)


def declare_agent_parameters() -> list[tuple[str, object, ParamSpec]]:
    """(name, default, descriptor) of every parameter of ``uav_agent``."""
    return [
        # rclpy declares it on every node; the agent always runs on the world's /clock
        ("use_sim_time", True, ParamSpec("sim time from /clock (always true)", read_only=False)),
        ("uav_id", -1, _ro("0-based UAV id; -1: from the namespace /uav_<id>")),
        ("uav_count", 0, _ro("fleet size N; 0: the scenario's uavs.count")),
        ("seed", -1, _ro("run seed (loss draws); -1: the scenario's seed")),
        ("scenario_file", "", _ro("scenario YAML (docs/scenario.md)")),
        ("mode", "lockstep", _ro("lockstep | realtime")),
        ("loss_probability", -1.0, _ro(
            "peer message loss on receipt [0, 1]; < 0: the scenario's comms.loss_probability")),
        ("liveness_check_wall_s", 0.5, _ro(
            "lockstep: how often [s wall] to check that the peers waited for still have a process "
            "(DDS graph); a live peer is never timed out", float_range=_float_range(0.01, 60.0))),
        ("prior_fires", [-1.0], _ro(
            "known-fires mode: the dispatch briefing as flat (x_m, y_m, extent_m) triples [m]; "
            "[-1.0]: none (the runner writes it when mission.prior_fires is known)")),
        ("offline_schedule", "", _ro(
            "lockstep fault schedule 'K@T1:T2;K@T1' [s sim] (fire_uav_common.lockstep), the same "
            "string the world gets: peers offline by it are not waited for")),
        ("crash_threshold_steps", 0, _ro(
            "missed steps before a peer is declared crashed; 0: the scenario's value",
            int_range=_int_range(0, 10000))),
        ("outage_from", [-1], _ro("link outages: sender ids ([-1]: none; else scenario)")),
        ("outage_to", [-1], _ro("link outages: receiver ids")),
        ("outage_start_s", [0.0], _ro("link outages: start [s sim]")),
        ("outage_end_s", [0.0], _ro("link outages: end [s sim]")),
        ("marker_every_steps", 5, _ro("publish viz markers every n steps (0: never)")),
        ("monitors_per_fire", -1, _ro(
            "PM perimeter monitors per active fire; -1: the scenario's mission.monitors_per_fire",
            int_range=_int_range(-1, 64))),
        ("monitor_planner", "importance", _ro("perimeter monitor: importance (PM) | circling (baseline)")),
        ("monitor_alpha", 1.0, _ro(
            "PM Eq. 7 heterogeneity-adjusting factor (>= 0)", float_range=_float_range(0.0, 100.0))),
        ("search_mode", "auto", _ro(
            "coverage search: auto (bo if the scenario's mission.search_first) | bo | random | off")),
        ("search_budget", 18, _ro(
            "candidate evaluations, fleet-wide (CP III-F)", int_range=_int_range(1, 1000))),
        ("search_lambda", 1e-3, _ro(
            "lambda of the cost lambda*sum(E_i) + r_max [m/J]", float_range=_float_range(0.0, 1.0))),
        ("search_cell_m", 0.0, _ro(
            "coarse coverage cell edge [m]; 0: from the fire sensor range",
            float_range=_float_range(0.0, 10000.0))),
        ("auth", True, _ro(
            "HMAC-SHA256 authentication of fleet and command topics with fleet_key (docs/security.md)")),
        # not read-only: it is undeclared once read, so the parameter services never hand it out
        ("fleet_key", "", ParamSpec("per-mission key, 64 hex digits (undeclared once read)", read_only=False)),
    ]  # fmt: skip


@dataclass(frozen=True)
class NodeConfig:
    """What ``uav_agent`` reads from its parameters, validated (units in names)."""

    agent: AgentConfig
    mode: str  # "lockstep" | "realtime"
    liveness_check_wall_s: float
    marker_every_steps: int
    offline_schedule: tuple[OfflineWindow, ...]
    search: SearchParams
    # None: authentication off; never printed (the key is inside)
    authenticator: Authenticator | None = field(default=None, repr=False)

    @property
    def uav_id(self) -> int:
        return self.agent.uav_id


def unknown_parameters(given: set[str] | list[str], known: set[str] | list[str]) -> list[str]:
    """Names the node was given that it does not declare (sorted); rclpy's own are allowed, and so
    are the ``qos_overrides.`` parameters rclpy reads for QoS overriding."""
    return sorted(n for n in set(given) - set(known) - RCLPY_PARAMETERS if not n.startswith("qos_overrides."))


def _uav_id(value: int, namespace: str) -> int:
    if value >= 0:
        return value
    m = re.fullmatch(r"/uav_(\d+)", namespace.rstrip("/"))
    if not m:
        raise ConfigError(f"parameter uav_id not set and namespace {namespace!r} is not /uav_<id>")
    return int(m.group(1))


def _outages(ofrom: list, oto: list, ostart: list, oend: list) -> tuple[LinkOutage, ...] | None:
    if ofrom == [-1]:
        return None
    if not len(ofrom) == len(oto) == len(ostart) == len(oend):
        raise ConfigError(
            "parameters outage_from/outage_to/outage_start_s/outage_end_s must have equal lengths, got "
            f"{len(ofrom)}/{len(oto)}/{len(ostart)}/{len(oend)}"
        )
    return tuple(
        LinkOutage(int(a), int(b), float(s), float(e))
        for a, b, s, e in zip(ofrom, oto, ostart, oend, strict=True)
    )


def _prior_fires(flat: list[float]) -> tuple[tuple[float, float, float], ...]:
    if flat == [-1.0]:
        return ()
    if len(flat) % 3:
        raise ConfigError(
            f"parameter prior_fires: {len(flat)} numbers, expected (x_m, y_m, extent_m) triples"
        )
    return tuple((flat[i], flat[i + 1], flat[i + 2]) for i in range(0, len(flat), 3))


def _authenticator(auth: bool, key: str) -> Authenticator | None:
    """``auth`` / ``fleet_key`` (docs/security.md); None when authentication is off."""
    return authenticator_from(auth, key, ConfigError)


def node_config(values: Mapping[str, Any], namespace: str) -> NodeConfig:
    """The parameters' ``values`` (name -> value, every declared one) into a :class:`NodeConfig`;
    ``namespace``: the node's, where ``uav_id`` -1 takes the id from. Raises :class:`ConfigError`."""

    def p(name: str) -> Any:
        return values[name]

    uid = _uav_id(int(p("uav_id")), namespace)
    mode = str(p("mode"))
    if mode not in ("lockstep", "realtime"):
        raise ConfigError(f"parameter mode must be 'lockstep' or 'realtime', got {mode!r}")
    path = str(p("scenario_file"))
    if not path:
        raise ConfigError("parameter scenario_file is required (a scenario YAML, docs/scenario.md)")
    planner = str(p("monitor_planner"))
    if planner not in ("importance", "circling"):
        raise ConfigError(f"parameter monitor_planner must be 'importance' or 'circling', got {planner!r}")
    outages = _outages(
        list(p("outage_from")), list(p("outage_to")), list(p("outage_start_s")), list(p("outage_end_s"))
    )
    prior = _prior_fires([float(v) for v in p("prior_fires")])
    try:
        schedule = parse_schedule(str(p("offline_schedule")))
    except ValueError as e:
        raise ConfigError(f"parameter offline_schedule: {e}") from None
    from fire_uav_common.scenario import load_scenario  # imported late: it pulls in the scenario loader

    scenario = load_scenario(path)
    count, seed, loss = int(p("uav_count")) or None, int(p("seed")), float(p("loss_probability"))
    thr, mpf = int(p("crash_threshold_steps")), int(p("monitors_per_fire"))
    agent = config_from_scenario(
        scenario, uid, uav_count=count, seed=seed if seed >= 0 else None, prior_fires=prior,
        loss_probability=loss if loss >= 0 else None, outages=outages,
        crash_threshold_steps=thr if thr > 0 else None, monitors_per_fire=mpf if mpf >= 0 else None,
        monitor_circling=planner == "circling", monitor_alpha=float(p("monitor_alpha")),
    )  # fmt: skip
    search_mode = str(p("search_mode"))
    if search_mode == "auto":
        search_mode = "bo" if agent.search_first else "off"
    search = SearchParams(
        mode=search_mode,
        budget=int(p("search_budget")),
        lambda_m_per_j=float(p("search_lambda")),
        cell_size_m=float(p("search_cell_m")),
    )
    liveness_s = float(p("liveness_check_wall_s"))
    if not (math.isfinite(liveness_s) and liveness_s > 0):
        raise ConfigError(f"parameter liveness_check_wall_s must be > 0, got {liveness_s}")
    return NodeConfig(
        agent=agent,
        mode=mode,
        liveness_check_wall_s=liveness_s,
        marker_every_steps=int(p("marker_every_steps")),
        offline_schedule=schedule,
        search=search,
        authenticator=_authenticator(bool(p("auth")), str(p("fleet_key"))),
    )
