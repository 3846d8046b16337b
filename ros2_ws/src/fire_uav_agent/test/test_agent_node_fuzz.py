"""Fuzz of the agent's readers (the codecs, ``incoming.peer_perimeter``) and the peer link behind them.

Random field values within the message types' ranges (NaN, inf, huge arrays, any id, any enum
value, any step and sequence): a conversion never raises, and the peer link then accepts or
rejects, counting every rejection. Needs the built fire_uav_msgs; no DDS.
"""

import math

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.incoming import peer_perimeter
from fire_uav_agent.peer_gate import step_verdict as _step_verdict
from fire_uav_agent.peer_link import PeerLink, Verdict
from fire_uav_common.codecs.perimeter_map import read_perimeter_map
from fire_uav_common.codecs.sensor_bundle import read_sensor_bundle
from fire_uav_common.codecs.uav_state import read_uav_state
from fire_uav_msgs.msg import FireEstimate, PerimeterMap, SensorBundle, UavState
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import serialize_message

f64 = st.floats(allow_nan=True, allow_infinity=True)
f32 = st.floats(width=32, allow_nan=True, allow_infinity=True)
u8, u32 = st.integers(0, 255), st.integers(0, 2**32 - 1)
i32 = st.integers(-(2**31), 2**31 - 1)
stamp = st.builds(Time, sec=i32, nanosec=st.integers(0, 999_999_999))


@st.composite
def uav_states(draw):
    m = UavState(uav_id=draw(u8), sequence=draw(u32), step=draw(u32), objective=draw(u8))
    m.header.stamp = draw(stamp)
    m.x_m, m.y_m, m.z_m, m.yaw_rad = draw(f64), draw(f64), draw(f64), draw(f64)
    m.centroid_x_m, m.centroid_y_m, m.water_kg = draw(f64), draw(f64), draw(f32)
    m.target_fire_id = draw(i32)
    m.sent_per_topic = draw(st.lists(st.integers(0, 65535), max_size=3000))
    m.alive_peers = draw(st.lists(u8, max_size=300))
    m.fires_sequence = draw(u32)  # the fire picture rides in the state
    n = draw(st.sampled_from([0, 1, 3, 500]))
    for _ in range(n):
        f = FireEstimate(fire_id=draw(u32), status=draw(u8), x_m=draw(f64), y_m=draw(f64), extent_m=draw(f64))
        f.last_measurement = draw(stamp)
        f.front_x_m, f.max_spread_rate_mps = draw(f64), draw(f64)
        m.fires.append(f)
    return m


@st.composite
def perimeters(draw):
    m = PerimeterMap(uav_id=draw(u8), sequence=draw(u32), fire_id=draw(i32))
    m.header.stamp = draw(stamp)
    m.center_x_m, m.center_y_m = draw(f64), draw(f64)
    m.outer_distance_m = draw(st.lists(f32, max_size=50)) + [0.0] * draw(st.sampled_from([0, 20000]))
    m.outer_visit_time_s = draw(st.lists(f32, max_size=50))
    return m


def _link() -> PeerLink:
    return PeerLink(0, 4, seed=1, loss_probability=0.05, control_period_s=0.1)


@settings(max_examples=80, deadline=None)
@given(st.lists(uav_states(), min_size=1, max_size=8), st.integers(0, 2**32))
def test_fuzzed_states_and_their_fires_convert_and_are_counted(msgs, now):
    link = _link()
    for m in msgs:
        w = read_uav_state(serialize_message(m))  # the codec on the bytes rclpy writes
        p, q = w.state, w.fires  # the state and the fire picture it carries
        assert (q.uav_id, q.sequence, q.step) == (m.uav_id, m.fires_sequence, m.step)
        assert len(q.fires) == len(m.fires)
        v_state = link.receive_state(p, now_step=now)
        for part, v in ((p, v_state), (q, link.receive_fires(q, now_step=now))):
            assert v in (Verdict.ACCEPTED, Verdict.LOST, Verdict.REJECTED)
            if v == Verdict.ACCEPTED:  # only plausible, finite messages get through
                assert (
                    0 < part.uav_id < 4
                    and now - link.max_step_lag <= part.step < now
                    and 1 <= part.sequence <= part.step + 1
                )
        if v_state == Verdict.ACCEPTED:
            assert all(math.isfinite(x) for x in (p.x_m, p.y_m, p.z_m, p.yaw_rad))
    assert link.received + link.lost + link.rejected == 2 * len(msgs)


@settings(max_examples=60, deadline=None)
@given(perimeters(), st.sampled_from([0.05, 0.1, 0.2]))
def test_fuzzed_perimeter_converts(m, period_s):
    p = peer_perimeter(read_perimeter_map(serialize_message(m)), period_s)
    assert p.uav_id == m.uav_id and isinstance(p.step, int)


@settings(max_examples=60, deadline=None)
@given(st.integers(-(2**40), 2**40), st.integers(-1, 2**32), st.booleans(), st.integers(0, 100))
def test_step_verdict_admits_exactly_the_lockstep_window(step, last, lockstep, slack):
    v = _step_verdict(step, last, lockstep, slack)
    if 0 <= step and (not lockstep or step >= last) and step <= last + 1 + slack:
        assert v is None
    else:
        assert v in ("negative step", "stale step", "implausible step")


@settings(max_examples=40, deadline=None)
@given(u32, stamp, f64, u8, f32, st.sampled_from([0, 1, 1000]))
def test_fuzzed_bundle_converts(step, t, x, status, water, n):
    from fire_uav_msgs.msg import GpsFix

    m = SensorBundle(step=step, vehicle_status=status, water_kg=water, control_period_s=0.1)
    m.header.stamp = t
    m.gps = [GpsFix(x_m=x, y_m=x, variance_m2=x) for _ in range(n)]
    m.cells.x_m = [x] * n
    m.cells.y_m = [x] * (n // 2)  # mismatched lengths: the cells are dropped, not misread
    b = read_sensor_bundle(serialize_message(m)).bundle
    assert b.step == step and b.samples.gps.shape == (n, 3) and b.cells is None or n == 0
