"""Raw (CDR) subscriptions to every wanted topic as it appears on the graph, with its schema.

Shared by the ``recorder`` (writes the bytes into the bag) and the ``foxglove_bridge`` (serves
them over Foxglove's WebSocket protocol): both need the same discovery rule, the same QoS rule
and the same ``ros2msg`` schema text, so they live here once.

- :class:`RawTopicFollower` polls the graph; for each new topic that ``wants(topic)`` and that
  has a publisher (whose QoS it must match) it makes the type known to the rosbags typestore,
  calls ``on_topic(RawTopic)`` and subscribes with ``raw=True`` to the handler that returns.
  :meth:`RawTopicFollower.follow` subscribes at once to fleet topics named in advance (the
  recorder's, from its ``uav_count``), so a publisher's first messages are not lost while the
  graph is polled; such a topic is announced (``on_topic``) when the graph first shows a
  publisher of it or its first message comes, whichever is first.
  Every subscription is drained (``topics.drain_queue``: one callback takes the topic's whole
  queue, as ``/fleet/state`` and ``/tf`` get ~20 messages per step at 20 UAVs), and
  :meth:`RawTopicFollower.take_queued` hands over what is still queued when the consumer stops
  (its rule, what it waits for and how long: :mod:`fire_uav_recording.stop_drain`).
- :func:`subscription_qos` is the QoS rule: the spec's QoS for a fleet topic (depth at least
  :data:`MIN_DEPTH`), rosbag2's adaptive rule for any other, relaxed to match every publisher.
- :func:`schema_text` is the ``ros2msg`` text of a type (the message definition and every
  nested one, rosbag2's concatenated form), what an MCAP schema and a Foxglove channel carry.
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import rclpy
from fire_uav_common import topics
from rclpy.duration import Infinite
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile, ReliabilityPolicy
from rosbags.typesys.store import Typestore

import fire_uav_recording as rec
from fire_uav_recording.stop_drain import drain

__all__ = [
    "MIN_DEPTH",
    "STOP_QUIET_WALL_S",
    "RawTopic",
    "RawTopicFollower",
    "fleet_offered_qos",
    "fleet_topic_names",
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


def fleet_topic_names(uav_count: int) -> list[str]:
    """Every absolute name of ``topics.ALL_TOPICS`` in a fleet of ``uav_count`` vehicles, in the
    table's order (each per-vehicle spec expanded for vehicles ``0 .. uav_count - 1``)."""
    out: list[str] = []
    for spec in topics.ALL_TOPICS:
        if spec.per_uav:
            out.extend(spec.for_uav(k) for k in range(uav_count))
        else:
            out.append(spec.name)
    return out


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


def _matches(sub: QoSProfile, pub: QoSProfile) -> bool:
    """Whether a subscription of QoS ``sub`` matches a publisher offering ``pub`` (reliability
    and durability: a reliable subscription needs a reliable publisher, a transient local one a
    transient local publisher)."""
    if sub.reliability == ReliabilityPolicy.RELIABLE and pub.reliability != ReliabilityPolicy.RELIABLE:
        return False
    transient = DurabilityPolicy.TRANSIENT_LOCAL
    return sub.durability != transient or pub.durability == transient


def fleet_offered_qos(spec: topics.TopicSpec) -> QoSProfile:
    """The QoS a fleet publisher of ``spec`` offers, as the graph shows it (DDS announces no
    history and depth: unknown, 0; infinite deadline, lifespan and lease, as rmw gives them)."""
    want = spec.qos()
    return QoSProfile(
        history=HistoryPolicy.UNKNOWN,
        depth=0,
        reliability=want.reliability,
        durability=want.durability,
        deadline=Infinite,
        lifespan=Infinite,
        liveliness=LivelinessPolicy.AUTOMATIC,
        liveliness_lease_duration=Infinite,
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


class _Relay:
    """The callback of a subscription made before its topic was announced: ``target`` is first
    the follower's announcement (which points it at the consumer's handler), then that handler."""

    __slots__ = ("target",)

    def __init__(self, target: Callable[[bytes], None]) -> None:
        self.target = target

    def __call__(self, data: bytes) -> None:
        self.target(data)


def _ignore(data: bytes) -> None:
    """A relay's target once its consumer declined the topic (the subscription stays: it cannot
    be destroyed from a callback of the executor that may be about to take from it)."""


class RawTopicFollower:
    """Subscribes raw to every wanted topic once it has a publisher (poll with :meth:`discover`),
    and at once to the fleet topics given to :meth:`follow`.

    ``on_topic(topic)`` returns the handler of the topic's CDR bytes, or ``None`` to skip it; it
    is called once per topic, when the topic is announced: when discovery finds it with a
    publisher, or for a topic of :meth:`follow`, when the graph first shows a publisher of it or
    its first message comes, whichever is first (a topic nobody publishes is never announced).
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
        self._name = node.get_name()
        self._wants = wants
        self._typestore = typestore
        self._on_topic = on_topic
        self.subscriptions: dict[str, Any] = {}
        self._counted: dict[str, Callable[[bytes], None]] = {}  # the subscriptions' callbacks
        self.handed: dict[str, int] = {}  # messages handed to each topic's handler so far
        self._skipped: set[str] = set()
        self._pending: dict[str, tuple[_Relay, topics.TopicSpec]] = {}  # by follow(), not announced yet
        self._other_types: set[str] = set()  # topics of follow() with publishers of another type (warned)
        self.announced: dict[str, RawTopic] = {}  # what on_topic was given (and took)

    def follow(self, names: Iterable[str]) -> int:
        """Subscribe now, in the order given, to each topic of ``names`` that has a spec in
        ``fire_uav_common.topics`` and that ``wants``; returns how many subscriptions were made.

        Each gets the spec's type and QoS, as :func:`subscription_qos` gives it for publishers
        that offer the spec's own QoS (every fleet publisher: ``topics.publisher``), so a
        publisher's first messages are in its history even before the graph shows that
        publisher (DDS announces a participant's endpoints in the order they are made: a node
        that sees the last of them has matched the others too). The subscription keeps that QoS:
        a publisher it cannot match (best effort on a reliable topic, volatile on a transient
        local one) is named in a warning when the topic is announced, and later ones by rclpy's
        incompatible-QoS event, as for any subscription. Names already followed, foreign names
        and unwanted ones are passed over (discovery finds foreign topics as before).
        """
        made = 0
        for topic in names:
            if topic in self.subscriptions or topic in self._skipped or not self._wants(topic):
                continue
            spec = spec_of(topic)
            if spec is None:
                continue  # a foreign name: discovery finds it
            cls = self._message_class(topic, spec.type, spec)
            if cls is None:
                continue
            qos = subscription_qos([spec.qos()], spec)
            relay = _Relay(partial(self._first_message, topic))
            self._subscribe(topic, cls, relay, qos)
            self._pending[topic] = (relay, spec)
            made += 1
        return made

    def discover(self) -> None:
        """Subscribe to every wanted topic that has publishers and is not yet followed; announce
        the topics of :meth:`follow` whose publishers have appeared."""
        node = self._node
        for topic, types in node.get_topic_names_and_types():
            if topic in self._pending:
                self._discover_pending(topic)
                continue
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
            cls = self._message_class(topic, ros_type, spec)
            if cls is None:
                continue
            offered = tuple(p.qos_profile for p in pubs)
            qos = subscription_qos(list(offered), spec)
            raw = RawTopic(topic, ros_type, spec, offered, qos)
            handler = self._on_topic(raw)
            if handler is None:
                self._skipped.add(topic)
                continue
            self._subscribe(topic, cls, handler, qos)
            self.announced[topic] = raw
            self._log_following(raw)

    def _message_class(self, topic: str, ros_type: str, spec: topics.TopicSpec | None) -> type | None:
        """The class to subscribe ``topic`` with, its type known to the typestore; ``None``
        (logged once, the topic skipped) if it has no definition or cannot be imported."""
        if not rec.ensure_type(self._typestore, ros_type):
            self._skip(topic, f"type {ros_type} has no .msg definition in AMENT_PREFIX_PATH")
            return None
        try:
            return spec.msg_class() if spec is not None else message_class(ros_type)
        except (ImportError, AttributeError, ValueError) as err:
            self._skip(topic, f"type {ros_type} not importable: {err}")
            return None

    def _subscribe(self, topic: str, cls: type, handler: Callable[[bytes], None], qos: QoSProfile) -> None:
        counted = partial(self._hand_over, topic, handler)
        sub = self._node.create_subscription(cls, topic, counted, qos, raw=True)
        self.subscriptions[topic] = topics.drain_queue(sub)
        self._counted[topic] = counted
        self.handed[topic] = 0

    def _hand_over(self, topic: str, handler: Callable[[bytes], None], data: bytes) -> None:
        """Every message of ``topic`` goes to its handler through here, counted in ``handed``
        (whoever took it: the executor's callback or :meth:`take_queued`)."""
        self.handed[topic] += 1
        handler(data)

    def _discover_pending(self, topic: str) -> None:
        """Announce a topic of :meth:`follow` once the graph shows a publisher of its type."""
        pubs = self._node.get_publishers_info_by_topic(topic)
        ros_type = self._pending[topic][1].type
        if any(p.topic_type == ros_type for p in pubs):
            self._announce(topic, pubs)
        elif pubs and topic not in self._other_types:
            self._other_types.add(topic)
            types = sorted({p.topic_type for p in pubs})
            self._logger().warning(
                f"not recording the publishers of {topic}: they publish {types}; it was subscribed "
                f"before they appeared, with the fleet's type {ros_type}"
            )

    def _first_message(self, topic: str, data: bytes) -> None:
        """A topic of :meth:`follow` got its first message before discovery saw a publisher:
        announce it with the publishers the graph shows now, then hand the message over."""
        try:
            pubs = self._node.get_publishers_info_by_topic(topic)
        except Exception:  # the context is shut down (take_queued at a stop): the spec's QoS is assumed
            pubs = []
        handler = self._announce(topic, pubs)
        if handler is not None:
            handler(data)

    def _announce(self, topic: str, pubs: Sequence[Any]) -> Callable[[bytes], None] | None:
        """Hand a topic of :meth:`follow` to ``on_topic``: ``offered`` is the QoS of the
        publishers of its type in ``pubs`` (if there are none yet, what every fleet publisher
        offers: :func:`fleet_offered_qos`); warn of those publishers the subscription cannot match."""
        relay, spec = self._pending.pop(topic)
        sub = self.subscriptions[topic]
        ours = [p for p in pubs if p.topic_type == spec.type]
        unmatched = [
            f"{p.node_namespace.rstrip('/')}/{p.node_name} ({p.topic_type}, "
            f"{p.qos_profile.reliability.name.lower()}, {p.qos_profile.durability.name.lower()})"
            for p in pubs
            if p.topic_type != spec.type or not _matches(sub.qos_profile, p.qos_profile)
        ]
        if unmatched:
            self._logger().warning(
                f"not recording the publishers of {topic} {unmatched}: it was subscribed before they "
                f"appeared, with the fleet's type {spec.type} and QoS "
                f"({sub.qos_profile.reliability.name.lower()}, {sub.qos_profile.durability.name.lower()}), "
                "which they do not offer"
            )
        offered = tuple(p.qos_profile for p in ours) or (fleet_offered_qos(spec),)
        raw = RawTopic(topic, spec.type, spec, offered, sub.qos_profile)
        handler = self._on_topic(raw)
        if handler is None:
            relay.target = _ignore
            self._skipped.add(topic)
            return None
        relay.target = handler
        self.announced[topic] = raw
        self._log_following(raw, "" if ours else "; no publisher on the graph yet: the fleet's QoS assumed")
        return handler

    def _log_following(self, topic: RawTopic, note: str = "") -> None:
        self._logger().info(
            f"following {topic.name} [{topic.ros_type}] ({topic.qos.reliability.name.lower()}, "
            f"{topic.qos.durability.name.lower()}){note}"
        )

    def _logger(self) -> Any:
        """The node's logger; rclpy's of the same name once the context is shut down (a stop),
        whose rosout would complain."""
        return self._node.get_logger() if self._node.context.ok() else rclpy.logging.get_logger(self._name)

    def take_queued(
        self,
        cap_wall_s: float,
        cancelled: Callable[[], bool] = lambda: False,
        quiet_wall_s: float = STOP_QUIET_WALL_S,
        wait: Callable[[float], bool] | None = None,
        expecting: Callable[[], str | None] = lambda: None,
    ) -> tuple[dict[str, int], bool]:
        """Hand every message still queued in a followed subscription to its handler (at a stop).

        Passes over every subscription, taking each queue until it is empty. Between passes it
        blocks in ``wait(timeout_s)``, which must return once a subscription may have a message
        (the node's executor, :meth:`fire_uav_common.ros_io.LeanExecutor.spin_once`: its callbacks
        take what came, counted here too) or ``timeout_s`` [s, wall] has passed, and return False
        when it cannot wait any more (the context is shut down). It ends when ``expecting()``
        names nothing still expected (``MissionEndWatch.missing``: the world's final truth, once
        announced) and nothing has come for ``quiet_wall_s`` [s, wall] (a message a publisher sent
        just before it stopped may still be on its way); when ``cap_wall_s`` [s, wall] has passed
        (publishers that go on publishing, an expected message that never comes) or
        ``cancelled()``. Without ``wait`` (or once it cannot wait) one pass is all it does: it
        works with no executor and after the context is shut down (the DDS reader histories live
        as long as the subscriptions). No sleep: only the wait on the subscriptions.

        Returns the messages handed over per topic (topics with none left out) and whether it
        ended with nothing expected left and the queues empty (not cut short).
        """
        start = dict(self.handed)

        def take_all(stop: Callable[[], bool]) -> bool:
            for topic, sub in self.subscriptions.items():
                handler = self._counted[topic]
                while True:
                    if stop():
                        return True
                    with sub.handle:
                        got = sub.handle.take_message(sub.msg_type, sub.raw)
                    if got is None:
                        break
                    handler(got[0])
            return False

        done = drain(
            take_all,
            lambda: sum(self.handed.values()),
            cap_wall_s,
            cancelled=cancelled,
            quiet_wall_s=quiet_wall_s,
            wait=wait,
            expecting=expecting,
        )
        taken = {t: k - start.get(t, 0) for t, k in self.handed.items() if k > start.get(t, 0)}
        return taken, done

    def _skip(self, topic: str, why: str) -> None:
        self._skipped.add(topic)
        self._node.get_logger().warning(f"not following {topic}: {why}")
