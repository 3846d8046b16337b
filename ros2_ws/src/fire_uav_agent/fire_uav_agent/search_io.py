"""ROS adapter of the in-fleet coverage search (CP): coverage topics <-> :class:`SearchCoordinator`.

``attach_search(node, agent, params)`` creates the
publishers and subscriptions of ``/fleet/coverage/{weights,candidates,mst}`` (names and QoS from
``fire_uav_common.topics``), and plugs the coordinator's :class:`SearchPlanner` in as the agent's
SEARCH planner. The node calls :meth:`SearchLink.step` once per control step after
``Agent.step``. Messages are converted here and nowhere else; the injected loss on receipt is the
peer link's rule (``agent.link.is_lost(sender, step, topic_index)``: loss probability, seed and
scheduled outages) with each topic's ``TopicSpec.loss_index`` (``search.coordinator.TOPIC_SPECS``).
Nothing here waits: coverage messages are not part of the lockstep peer wait.

Parameters (declared and read with the node's others, ``agent_params``): ``search_mode`` (``auto`` | ``bo`` | ``random`` | ``off``; ``auto`` = ``bo``
when the scenario's ``mission.search_first`` is true, else ``off``), ``search_budget``
(evaluations fleet-wide), ``search_lambda`` [m/J], ``search_cell_m`` (coarse cell edge [m]; 0 =
from the sensor range).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from builtin_interfaces.msg import Time as TimeMsg
from fire_uav_common import topics
from fire_uav_common.constants import CandidateKind, MstKind, Objective
from fire_uav_common.stamps import s_to_ns, stamp_to_ns, stamp_to_step, step_to_ns, to_time_msg
from fire_uav_msgs.msg import CoverageCandidate, CoverageWeight, MstFragment
from geometry_msgs.msg import Point
from rclpy.node import Node
from visualization_msgs.msg import Marker, MarkerArray

from .agent_core import Agent
from .errors import ConfigError
from .search.bayesopt import CandidateMessage
from .search.coordinator import TOPIC_SPECS, Envelope, SearchConfig, SearchCoordinator, Topic
from .search.mst import MstMessage
from .search.power_diagram import WeightReport

__all__ = ["SearchLink", "SearchParams", "attach_search"]

PATH_MARKER_STEP_M = 5.0  # [m] arc-length spacing of the planned-path marker's points


@dataclass(frozen=True)
class SearchParams:
    mode: str  # "bo" | "random" | "off"
    budget: int = 18
    lambda_m_per_j: float = 1e-3
    cell_size_m: float = 0.0  # 0: from the sensor range

    def __post_init__(self) -> None:
        if self.mode not in ("bo", "random", "off"):
            raise ConfigError(f"parameter search_mode must be auto, bo, random or off, got {self.mode!r}")
        if self.budget < 1:
            raise ConfigError(f"parameter search_budget must be >= 1, got {self.budget}")
        if not (math.isfinite(self.lambda_m_per_j) and self.lambda_m_per_j >= 0.0):
            raise ConfigError(f"parameter search_lambda must be >= 0, got {self.lambda_m_per_j}")
        if not self.cell_size_m >= 0.0:
            raise ConfigError(f"parameter search_cell_m must be >= 0, got {self.cell_size_m}")


# --- conversions (the only place coverage messages meet the coordinator's types) --------------------
def _step_of(stamp: TimeMsg, period_s: float) -> int:
    """Header stamps are the bundle stamp t_{k+1} = (k + 1) T of the step they were sent at."""
    return stamp_to_step(stamp_to_ns(stamp), s_to_ns(period_s))


def to_msg(e: Envelope, period_s: float) -> CoverageWeight | CoverageCandidate | MstFragment:
    m = e.msg
    stamp = to_time_msg(step_to_ns(e.step, s_to_ns(period_s)), TimeMsg)
    if isinstance(m, WeightReport):
        w = CoverageWeight(uav_id=e.sender, iteration=int(m.iteration), seed_x_m=float(m.seed_x_m),
                           seed_y_m=float(m.seed_y_m), weight_m2=float(m.weight_m2),
                           area_m2=float(m.area_m2), target_area_m2=float(m.target_area_m2))  # fmt: skip
        w.header.stamp, w.header.frame_id = stamp, "map"
        return w
    if isinstance(m, CandidateMessage):
        c = CoverageCandidate(uav_id=e.sender, kind=int(m.kind), candidate_id=int(m.candidate_id),
                              seeds=[Point(x=float(x), y=float(y), z=0.0) for x, y in m.seeds_m],
                              start_offsets=[float(s) for s in m.start_offsets], energy_j=float(m.energy_j),
                              radio_radius_m=float(m.radio_radius_m), cost=float(m.cost))  # fmt: skip
        c.header.stamp, c.header.frame_id = stamp, "map"
        return c
    f = MstFragment(uav_id=e.sender, kind=int(m.kind), round=int(m.round), sample_index=int(m.sample_index),
                    fragment_id=int(m.fragment_id), edge_from=int(m.edge_from), edge_to=int(m.edge_to),
                    edge_length_m=float(m.edge_length_m), radius_m=float(m.radius_m))  # fmt: skip
    f.header.stamp = stamp
    return f


def weight_envelope(m: CoverageWeight, period_s: float) -> Envelope:
    r = WeightReport(int(m.uav_id), int(m.iteration), m.seed_x_m, m.seed_y_m, m.weight_m2, m.area_m2,
                     m.target_area_m2)  # fmt: skip
    return Envelope(Topic.WEIGHTS, int(m.uav_id), _step_of(m.header.stamp, period_s), r)


def candidate_envelope(m: CoverageCandidate, period_s: float) -> Envelope:
    c = CandidateMessage(int(m.uav_id), CandidateKind(int(m.kind)), int(m.candidate_id),
                         tuple((float(p.x), float(p.y)) for p in m.seeds),
                         tuple(float(s) for s in m.start_offsets), float(m.energy_j), float(m.radio_radius_m),
                         float(m.cost))  # fmt: skip
    return Envelope(Topic.CANDIDATES, int(m.uav_id), _step_of(m.header.stamp, period_s), c)


def mst_envelope(m: MstFragment, period_s: float) -> Envelope:
    f = MstMessage(int(m.uav_id), MstKind(int(m.kind)), int(m.round), int(m.sample_index), int(m.fragment_id),
                   int(m.edge_from), int(m.edge_to), float(m.edge_length_m), float(m.radius_m))  # fmt: skip
    return Envelope(Topic.MST, int(m.uav_id), _step_of(m.header.stamp, period_s), f)


# --- the link ------------------------------------------------------------------------------------------
class SearchLink:
    """Publishers, subscriptions and the per-step drive of one agent's :class:`SearchCoordinator`."""

    def __init__(self, node: Node, agent: Agent, coordinator: SearchCoordinator) -> None:
        self.node = node
        self.agent = agent
        self.coordinator = coordinator
        self.period_s = float(agent.cfg.control_period_s)
        self.uav_id = int(agent.cfg.uav_id)
        self._pub = {t: topics.publisher(node, spec) for t, spec in TOPIC_SPECS.items()}
        self._sub = {}
        convert = {
            Topic.WEIGHTS: weight_envelope,
            Topic.CANDIDATES: candidate_envelope,
            Topic.MST: mst_envelope,
        }
        for t, spec in TOPIC_SPECS.items():
            self._sub[t] = topics.subscription(node, spec, lambda m, c=convert[t]: self._receive(c, m))
        #: called with (sender, step, loss_index) for every valid peer message, before the loss
        #: draw (the node's lockstep wait counts physical arrivals)
        self.on_arrival: Callable[[int, int, int], None] | None = None
        self._inbox: list[Envelope] = []
        self.received = 0
        self.lost = 0
        self.rejected = 0
        self._plans_published = 0

    def _receive(self, convert, msg) -> None:
        if int(msg.uav_id) == self.uav_id:
            return  # our own broadcast
        try:
            e = convert(msg, self.period_s)
        except ValueError:  # unknown kind constant
            self.rejected += 1
            return
        if not 0 <= e.sender < self.agent.cfg.uav_count or e.step < 0:
            self.rejected += 1
            return
        if self.on_arrival is not None:
            self.on_arrival(e.sender, e.step, TOPIC_SPECS[e.topic].loss_index)
        if self.agent.link.is_lost(e.sender, e.step, TOPIC_SPECS[e.topic].loss_index):
            self.lost += 1
            return
        self.received += 1
        self._inbox.append(e)

    def step(self, t_s: float, step: int, alive_ids) -> list[Envelope]:
        """Run the coordinator for control step ``step`` (after ``Agent.step``) on the peers'
        messages of earlier steps; returns what to publish (:meth:`publish`)."""
        # a total order (per sender, DDS keeps each writer's order; across senders it does not)
        take = sorted(
            (e for e in self._inbox if e.step < step), key=lambda e: (e.step, int(e.topic), e.sender)
        )
        self._inbox = [e for e in self._inbox if e.step >= step]
        out = self.coordinator.on_step(t_s, step, alive_ids, take)
        log = self.node.get_logger()
        for line in self.coordinator.log:
            log.info(f"step {step}: {line}")
        self.coordinator.log.clear()
        return list(out)

    def publish(self, envelopes: list[Envelope]) -> None:
        for e in envelopes:
            self._pub[e.topic].publish(to_msg(e, self.period_s))

    def plan_marker(self, stamp: TimeMsg) -> MarkerArray | None:
        """The own planned STC path as a LINE_STRIP (ns ``uav_<k>_search_path``, id 0, map frame,
        z = 0), once per new plan (None otherwise): on the agent's viz topic, so the bag records
        what was planned next to what was flown (the report's CP section). Not a peer topic."""
        plans = self.coordinator.plans
        if len(plans) == self._plans_published:
            return None
        self._plans_published = len(plans)
        path = plans[-1].paths.get(self.uav_id)
        if path is None:
            return None
        s_m = np.linspace(0.0, path.length_m, max(2, math.ceil(path.length_m / PATH_MARKER_STEP_M)) + 1)
        xy = path.positions_at(s_m)
        m = Marker(ns=f"uav_{self.uav_id}_search_path", id=0, type=Marker.LINE_STRIP, action=Marker.ADD)
        m.header.stamp, m.header.frame_id = stamp, "map"
        m.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in xy]
        m.scale.x = 2.0
        m.color.r, m.color.g, m.color.b, m.color.a = 0.2, 0.4, 1.0, 0.9
        m.text = (
            f"candidate {plans[-1].candidate_id}, plan step {plans[-1].step}, length {path.length_m:.0f} m"
        )
        return MarkerArray(markers=[m])

    @staticmethod
    def counts(envelopes: list[Envelope]) -> dict[int, int]:
        """Messages per loss index (the ``sent_per_topic`` entries of the step's UavState)."""
        out = {TOPIC_SPECS[t].loss_index: 0 for t in TOPIC_SPECS}
        for e in envelopes:
            out[TOPIC_SPECS[e.topic].loss_index] += 1
        return out

    def endpoints(self) -> list[tuple[object, bool]]:
        """(publisher or subscription, is_publisher) for the start-up matching check."""
        return [(p, True) for p in self._pub.values()] + [(q, False) for q in self._sub.values()]


def attach_search(node: Node, agent: Agent, params: SearchParams) -> SearchLink | None:
    """Set up the in-fleet search on an agent node; None when ``search_mode`` resolves to off."""
    cfg = agent.cfg
    if params.mode == "off":
        return None
    config = SearchConfig(
        mode=params.mode,
        budget=params.budget,
        lambda_m_per_j=params.lambda_m_per_j,
        cell_size_m=params.cell_size_m or None,
        sensor_range_m=cfg.fire_range_m,
        speed_mps=max(cfg.limits.v_stall_mps + 5.0, min(50.0, cfg.limits.v_max_mps)),
    )
    rng = np.random.default_rng([int(cfg.seed), int(cfg.uav_id), 0x5EA7C4])
    coord = SearchCoordinator(cfg.uav_id, cfg.uav_count, cfg.area_m, cfg.seed, config, rng)
    agent.planners[int(Objective.SEARCH)] = coord.planner
    link = SearchLink(node, agent, coord)
    node.get_logger().info(
        f"coverage search: mode {params.mode}, budget {params.budget}, lambda {params.lambda_m_per_j:g} m/J, "
        f"cell {coord.grid.cell_size_m:.1f} m ({coord.grid.nx}x{coord.grid.ny}), speed {config.speed_mps:.0f} m/s"
    )
    return link
