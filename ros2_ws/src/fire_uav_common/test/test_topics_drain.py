"""``topics.drain_queue``: one callback handles the whole queue, in order, up to its limit (no ROS)."""

from __future__ import annotations

import enum
from collections import deque

import pytest
from fire_uav_common import topics


class _Handle:
    def __init__(self, queue: deque) -> None:
        self.queue = queue
        self.entered = 0
        self.calls: list[tuple[object, object]] = []

    def __enter__(self) -> _Handle:
        self.entered += 1
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def take_message(self, msg_type: object, raw: bool):
        self.calls.append((msg_type, raw))
        if not self.queue:
            return None
        item = self.queue.popleft()
        if isinstance(item, Exception):
            raise item
        return (item, {"info": "ignored"})


class _Sub:
    """The attributes of an rclpy Subscription that ``drain_queue`` uses."""

    class CallbackType(enum.Enum):
        MessageOnly = 0
        WithMessageInfo = 1

    def __init__(self, queued: list, callback, kind=None) -> None:
        self.handle = _Handle(deque(queued))
        self.msg_type, self.raw, self.topic_name = object, False, "/fleet/state"
        self.callback = callback
        self._callback_type = kind or self.CallbackType.MessageOnly


def test_the_first_callback_takes_every_queued_message_in_arrival_order():
    seen: list = []
    sub = topics.drain_queue(_Sub([2, 3, 4], seen.append))
    sub.callback(1)  # what the executor took
    assert seen == [1, 2, 3, 4]
    assert not sub.handle.queue
    # taken as the executor takes: the subscription's own type and raw flag, under its handle
    assert sub.handle.calls == [(sub.msg_type, False)] * 4 and all(c[1] is False for c in sub.handle.calls)
    assert sub.handle.entered == 4
    sub.callback(5)  # an empty queue: only the executor's message
    assert seen == [1, 2, 3, 4, 5]


def test_the_limit_leaves_the_rest_for_the_next_wait():
    seen: list = []
    sub = topics.drain_queue(_Sub(list(range(1, 101)), seen.append), limit=10)
    sub.callback(0)
    assert seen == list(range(11))
    assert list(sub.handle.queue) == list(range(11, 101))
    assert topics.DRAIN_LIMIT >= 40  # a 20-UAV step's queue on one topic fits in one callback


def test_an_undecodable_message_raises_after_the_ones_before_it_were_handled():
    seen: list = []
    sub = topics.drain_queue(_Sub([2, RuntimeError("Unable to convert call argument"), 4], seen.append))
    with pytest.raises(RuntimeError, match="Unable to convert"):
        sub.callback(1)
    assert seen == [1, 2]
    assert list(sub.handle.queue) == [4]  # taken on the next wait


def test_a_callback_with_message_info_is_refused_by_name():
    sub = _Sub([], lambda m, info: None, kind=_Sub.CallbackType.WithMessageInfo)
    with pytest.raises(ValueError, match="/fleet/state"):
        topics.drain_queue(sub)


def test_vehicle_namespaces_start_at_uav_0():
    assert topics.uav_namespace(0) == "/uav_0"
    assert topics.uav_topic(3, topics.SENSORS_SPEC.name) == "/uav_3/sensors"
    with pytest.raises(ValueError, match="uav_id must be >= 0, got -1"):
        topics.uav_namespace(-1)
