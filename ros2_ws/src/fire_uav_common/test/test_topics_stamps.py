"""TopicSpec table and stamp conversions."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from fire_uav_common import stamps, topics
from hypothesis import given
from hypothesis import strategies as st

MSG_DIR = Path(__file__).resolve().parents[2] / "fire_uav_msgs" / "msg"


def test_names_unique_and_loss_indices_distinct() -> None:
    names = [s.name for s in topics.ALL_TOPICS]
    assert len(names) == len(set(names))
    idx = [s.loss_index for s in topics.ALL_TOPICS if s.loss_index is not None]
    assert sorted(idx) == list(range(len(idx)))
    # every peer-to-peer topic except the events has a loss index
    for s in topics.ALL_TOPICS:
        if s.name.startswith("/fleet/") and s.qos_kind == "fleet":
            assert s.loss_index is not None, s.name


def test_project_types_exist_as_msg_files() -> None:
    for s in topics.ALL_TOPICS:
        pkg, kind, name = s.type.split("/")
        assert kind == "msg"
        if pkg == "fire_uav_msgs":
            assert (MSG_DIR / f"{name}.msg").is_file(), s.type


def test_topic_by_name_and_patterns() -> None:
    assert topics.topic_by_name("/uav_12/cmd") is topics.CMD_SPEC
    assert topics.topic_by_name("/fleet/state") is topics.FLEET_STATE_SPEC
    with pytest.raises(KeyError, match="no topic '/nope'"):
        topics.topic_by_name("/nope")
    pats = [re.compile(p) for p in topics.recorded_patterns()]
    for name in ("/clock", "/uav_3/sensors", "/fleet/coverage/mst", "/world/truth", "/viz/perimeter"):
        assert any(p.fullmatch(name) for p in pats), name
    assert not any(p.fullmatch("/uav_x/cmd") for p in pats)


def test_spec_validation() -> None:
    with pytest.raises(ValueError, match="unknown QoS kind"):
        topics.TopicSpec("/a", "std_msgs/msg/Empty", "nope")
    with pytest.raises(ValueError, match="relative"):
        topics.TopicSpec("/a", "std_msgs/msg/Empty", "viz", per_uav=True)
    with pytest.raises(ValueError, match="not a per-vehicle"):
        topics.FLEET_STATE_SPEC.for_uav(1)
    assert topics.SENSORS_SPEC.for_uav(4) == "/uav_4/sensors"
    with pytest.raises(ValueError, match="uav_id must be >= 0"):
        topics.uav_namespace(-1)


class _T:
    def __init__(self, sec: int, nanosec: int) -> None:
        self.sec, self.nanosec = sec, nanosec


@given(st.integers(min_value=0, max_value=2**62))
def test_stamp_round_trip(t_ns: int) -> None:
    msg = stamps.to_time_msg(t_ns, _T)
    assert 0 <= msg.nanosec < 10**9
    assert stamps.stamp_to_ns(msg) == t_ns


@given(st.integers(min_value=0, max_value=10**7), st.integers(min_value=1, max_value=10**10))
def test_step_round_trip(step: int, period_ns: int) -> None:
    assert stamps.stamp_to_step(stamps.step_to_ns(step, period_ns), period_ns) == step
    # a float round trip through seconds still lands on the step
    t_s = stamps.ns_to_s(stamps.step_to_ns(step, period_ns))
    assert stamps.stamp_to_step(stamps.s_to_ns(t_s), period_ns) == step


def test_stamp_errors_and_values() -> None:
    assert stamps.stamp_to_s(_T(2, 500_000_000)) == 2.5
    assert stamps.s_to_ns(0.1) == 100_000_000
    with pytest.raises(ValueError, match="stamp must be >= 0"):
        stamps.to_time_msg(-1, _T)
    with pytest.raises(ValueError, match="control period must be > 0"):
        stamps.stamp_to_step(10, 0)
    # step 0 of a 0.25 s period is stamped 0.25 s
    assert stamps.step_to_ns(0, 250_000_000) == 250_000_000
