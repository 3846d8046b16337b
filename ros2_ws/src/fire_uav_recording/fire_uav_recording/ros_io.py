"""Raw (CDR) subscriptions to every wanted topic as it appears on the graph, with its schema.

Shared by the ``recorder`` (writes the bytes into the bag) and the ``foxglove_bridge`` (serves
them over Foxglove's WebSocket protocol): both need the same discovery rule, the same QoS rule
and the same ``ros2msg`` schema text, so they live here once.

- :class:`RawTopicFollower` polls the graph; for each new topic that ``wants(topic)`` and that
  has a publisher (whose QoS it must match) it makes the type known to the rosbags typestore,
  calls ``on_topic(RawTopic)`` and subscribes with ``raw=True`` to the handler that returns.
  Every subscription is drained (``topics.drain_queue``: one callback takes the topic's whole
  queue, as ``/fleet/state`` and ``/tf`` get ~20 messages per step at 20 UAVs), and
  :meth:`RawTopicFollower.take_queued` hands over what is still queued when the consumer stops.
- :func:`subscription_qos` is the QoS rule: the spec's QoS for a fleet topic (depth at least
  :data:`MIN_DEPTH`), rosbag2's adaptive rule for any other, relaxed to match every publisher.
- :func:`schema_text` is the ``ros2msg`` text of a type (the message definition and every
  nested one, rosbag2's concatenated form), what an MCAP schema and a Foxglove channel carry.
"""

from __future__ import annotations

import importlib
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from fire_uav_common import topics
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rosbags.typesys.store import Typestore

import fire_uav_recording as rec

__all__ = [
    "MIN_DEPTH",
    "STOP_QUIET_WALL_S",
    "RawTopic",
    "RawTopicFollower",
    "message_class",
    "schema_text",
    "spec_of",
    "subscription_qos",
]

# queue depth floor per topic [messages]: ~3 s of /tf at 20 UAVs (21 publishers, ~21 messages per
# step at ~15 steps/s), which a recorder held up by its start-up discovery or by a flush on two
# busy cores must not overflow (at 100, a 20-UAV mission lost the /tf of ~2 steps at each hold-up)
MIN_DEPTH = 1000
STOP_QUIET_WALL_S = 0.1  # [s, wall] RawTopicFollower.take_queued ends once nothing came for this long
_QUIET_POLL_WALL_S = 0.005  # [s, wall] between its passes over the subscriptions while waiting so


def compile_patterns(
    name: str, patterns: Sequence[str], error: type[ValueError]
) -> tuple[re.Pattern[str], ...]:
    """Topic regular expressions of parameter ``name``; ``error`` (naming it) on a bad one."""
    out = []
    for p in patterns:
        try:
            out.append(re.compile(p))
        except re.error as err:
            raise error(f"parameter {name}: bad regular expression {p!r}: {err}") from None
    return tuple(out)


def topic_wanted(topic: str, include: Sequence[re.Pattern[str]], exclude: Sequence[re.Pattern[str]]) -> bool:
    """Whether ``topic`` full-matches an include pattern and no exclude pattern (recorder, bridge)."""
    return any(p.fullmatch(topic) for p in include) and not any(p.fullmatch(topic) for p in exclude)


def spec_of(topic: str) -> topics.TopicSpec | None:
    """The fleet's spec of ``topic`` (``None`` for a topic fire_uav_common does not declare)."""
    try:
        return topics.topic_by_name(topic)
    except KeyError:
        return None


def subscription_qos(offered: list[QoSProfile], spec: topics.TopicSpec | None = None) -> QoSProfile:
    """A subscription QoS that matches every offered publisher profile.

    Starts from ``spec.qos()`` (depth at least :data:`MIN_DEPTH`) when the topic has a spec, else
    from rosbag2's adaptive rule; then gives up reliability / transient local where a
    publisher does not offer it (a stricter subscription would never match that publisher).
    """
    best_effort = any(p.reliability == ReliabilityPolicy.BEST_EFFORT for p in offered)
    transient = bool(offered) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in offered)
    if spec is not None:
        want = spec.qos()
        best_effort = best_effort or want.reliability == ReliabilityPolicy.BEST_EFFORT
        transient = transient and want.durability == DurabilityPolicy.TRANSIENT_LOCAL
        depth = max(MIN_DEPTH, int(want.depth))
        keep_all = want.history == HistoryPolicy.KEEP_ALL  # the recorder loses nothing the fleet keeps
    else:
        depth = max([1000 if transient else MIN_DEPTH, *[int(p.depth) for p in offered]])
        keep_all = False
    return QoSProfile(
        history=HistoryPolicy.KEEP_ALL if keep_all else HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE,
    )


def message_class(ros_type: str) -> type:
    """``pkg/msg/Name`` -> the generated Python class (ImportError/AttributeError if not installed).

    For types no spec of fire_uav_common.topics names (the recorder records what it finds).
    """
    pkg, kind, name = ros_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)


def schema_text(typestore: Typestore, ros_type: str) -> str:
    """The ``ros2msg`` schema of ``ros_type``: its definition, then each nested type's after a
    ``===`` separator line and ``MSG: pkg/msg/Name`` (rosbag2's and the MCAP ``ros2`` profile's
    form; the text rosbags writes into the bag's schema records)."""
    if not rec.ensure_type(typestore, ros_type):
        raise rec.BagError(f"type {ros_type} has no .msg definition in AMENT_PREFIX_PATH")
    text, _ = typestore.generate_msgdef(ros_type, ros_version=2)
    return text


@dataclass(frozen=True)
class RawTopic:
    """A topic found on the graph: what a consumer of its raw messages needs to know."""

    name: str
    ros_type: str  # pkg/msg/Name
    spec: topics.TopicSpec | None  # the fleet's spec, None for a foreign topic
    offered: tuple[QoSProfile, ...]  # the publishers' QoS profiles when it was found
    qos: QoSProfile  # the subscription's


class RawTopicFollower:
    """Subscribes raw to every wanted topic once it has a publisher (poll with :meth:`discover`).

    ``on_topic(topic)`` returns the handler of the topic's CDR bytes, or ``None`` to skip it.
    Topics that cannot be subscribed (several types, no definition, not importable) are logged
    once and skipped. Each subscription's callback takes the handler's message and then the rest
    of the topic's queue (``topics.drain_queue``), in arrival order.
    """

    def __init__(
        self,
        node: Node,
        wants: Callable[[str], bool],
        typestore: Typestore,
        on_topic: Callable[[RawTopic], Callable[[bytes], None] | None],
    ) -> None:
        self._node = node
        self._wants = wants
        self._typestore = typestore
        self._on_topic = on_topic
        self.subscriptions: dict[str, Any] = {}
        self._handlers: dict[str, Callable[[bytes], None]] = {}
        self._skipped: set[str] = set()

    def discover(self) -> None:
        """Subscribe to every wanted topic that has publishers and is not yet followed."""
        node = self._node
        for topic, types in node.get_topic_names_and_types():
            if topic in self.subscriptions or topic in self._skipped or not self._wants(topic):
                continue
            pubs = node.get_publishers_info_by_topic(topic)
            if not pubs:
                continue  # only subscribers so far: wait for a publisher to learn its QoS
            if len(types) != 1:
                self._skip(topic, f"has {len(types)} types {types}; following none")
                continue
            ros_type = types[0]
            spec = spec_of(topic)
            if spec is not None and spec.type != ros_type:
                spec = None  # someone publishes another type under a fleet name: take it as it is
            if not rec.ensure_type(self._typestore, ros_type):
                self._skip(topic, f"type {ros_type} has no .msg definition in AMENT_PREFIX_PATH")
                continue
            try:
                cls = spec.msg_class() if spec is not None else message_class(ros_type)
            except (ImportError, AttributeError, ValueError) as err:
                self._skip(topic, f"type {ros_type} not importable: {err}")
                continue
            offered = tuple(p.qos_profile for p in pubs)
            qos = subscription_qos(list(offered), spec)
            handler = self._on_topic(RawTopic(topic, ros_type, spec, offered, qos))
            if handler is None:
                self._skipped.add(topic)
                continue
            sub = node.create_subscription(cls, topic, handler, qos, raw=True)
            self.subscriptions[topic] = topics.drain_queue(sub)
            self._handlers[topic] = handler
            node.get_logger().info(
                f"following {topic} [{ros_type}] ({qos.reliability.name.lower()}, "
                f"{qos.durability.name.lower()})"
            )

    def take_queued(
        self,
        cap_wall_s: float,
        cancelled: Callable[[], bool] = lambda: False,
        quiet_wall_s: float = STOP_QUIET_WALL_S,
    ) -> tuple[dict[str, int], bool]:
        """Hand every message still queued in a followed subscription to its handler (at a stop).

        Passes over every subscription, taking each queue until it is empty, until no message
        has come for ``quiet_wall_s`` [s, wall] (one a publisher sent just before it stopped may
        still be on its way into the reader history), ``cap_wall_s`` [s, wall] has passed
        (publishers that go on publishing) or ``cancelled()``. Needs no executor and works
        after the context is shut down (the DDS reader histories live as long as the
        subscriptions). Returns the messages taken per topic (topics with none left out) and
        whether the queues were found empty and quiet (not cut short).
        """
        t0 = time.monotonic()
        end, last = t0 + cap_wall_s, t0
        taken: dict[str, int] = {}
        while True:
            for topic, sub in self.subscriptions.items():
                handler = self._handlers[topic]
                while True:
                    now = time.monotonic()
                    if now >= end or cancelled():
                        return taken, False
                    with sub.handle:
                        got = sub.handle.take_message(sub.msg_type, sub.raw)
                    if got is None:
                        break
                    handler(got[0])
                    taken[topic] = taken.get(topic, 0) + 1
                    last = now
            if time.monotonic() - last >= quiet_wall_s:
                return taken, True
            time.sleep(_QUIET_POLL_WALL_S)

    def _skip(self, topic: str, why: str) -> None:
        self._skipped.add(topic)
        self._node.get_logger().warning(f"not following {topic}: {why}")
