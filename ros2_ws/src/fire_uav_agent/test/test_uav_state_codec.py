"""``fire_uav_common.codecs.uav_state.read_uav_state`` against rclpy's own deserialisation (the reference it replaces).

Generated UavStates (every field random, frame ids of every length mod 8 so that each alignment
rule is exercised, up to 6 fires) are serialised by ``rclpy.serialization.serialize_message``
(rmw_fastrtps's CDR) and read both ways; the results must be equal field for field. The field lists
of UavState.msg and FireEstimate.msg are pinned, so a message change fails here first. Bad bytes
(every truncation, bytes left over, another encapsulation, noise) raise ValueError and nothing else.
"""

from __future__ import annotations

import math

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.testing import rclpy_reference as rclpy_ref
from fire_uav_agent.testing.compare import assert_same_message, same
from fire_uav_agent.testing.msg_strategies import f32, f64, frame_ids, i32, stamps, u8, u16, u32
from fire_uav_common.auth import Authenticator
from fire_uav_common.codecs.uav_state import FIREESTIMATE_FIELDS, UAVSTATE_FIELDS, read_uav_state
from fire_uav_msgs.msg import FireEstimate, UavState
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message


@st.composite
def uav_states(draw) -> UavState:
    m = UavState(uav_id=draw(u8), sequence=draw(u32), step=draw(u32), objective=draw(u8))
    m.header.stamp = draw(stamps)
    m.header.frame_id = draw(frame_ids(17))
    m.x_m, m.y_m, m.z_m, m.yaw_rad = (draw(f64) for _ in range(4))
    m.covariance = [draw(f64) for _ in range(16)]
    m.target_fire_id, m.water_kg = draw(i32), draw(f32)
    m.centroid_x_m, m.centroid_y_m = draw(f64), draw(f64)
    m.alive_peers = draw(st.lists(u8, max_size=41))
    m.crashed_peers = draw(st.lists(u8, max_size=9))
    m.packets_received, m.packets_lost, m.packets_rejected = draw(u32), draw(u32), draw(u32)
    m.sent_per_topic = draw(st.lists(u16, max_size=7))
    m.final = draw(st.booleans())
    m.fires_sequence = draw(u32)
    for _ in range(draw(st.integers(0, 6))):
        f = FireEstimate(fire_id=draw(u32), status=draw(u8))
        f.x_m, f.y_m, f.extent_m, f.vx_mps, f.vy_mps = (draw(f64) for _ in range(5))
        f.last_measurement = draw(stamps)
        f.front_x_m, f.front_y_m, f.max_spread_rate_mps = draw(f64), draw(f64), draw(f64)
        m.fires.append(f)
    m.auth = list(draw(st.binary(min_size=32, max_size=32)))
    return m


def test_the_message_definitions_are_the_ones_the_reader_reads():
    assert tuple(UavState.get_fields_and_field_types().items()) == UAVSTATE_FIELDS
    assert tuple(FireEstimate.get_fields_and_field_types().items()) == FIREESTIMATE_FIELDS


@settings(max_examples=300, deadline=None)
@given(uav_states())
def test_read_equals_rclpys_deserialisation(m):
    data = serialize_message(m)
    w = read_uav_state(data)
    ref = deserialize_message(data, UavState)
    assert same(w.state, rclpy_ref.to_peer_state(ref))
    assert same(w.fires, rclpy_ref.to_peer_fires(ref))
    assert (w.uav_id, w.step, w.final) == (ref.uav_id, ref.step, ref.final)
    assert w.sent_per_topic == tuple(ref.sent_per_topic)
    assert all(type(v) is int for v in w.sent_per_topic)


@settings(max_examples=60, deadline=None)
@given(uav_states(), st.integers(0, 255), st.integers(0, 2**32 - 1))
def test_a_signed_state_reads_as_its_message(m, sender, step):
    """As the fleet sends it: serialised with a zero tag, the tag then written into its last 32 bytes."""
    m.auth = [0] * 32
    auth = Authenticator(bytes(range(32)))
    data = auth.sign_serialized(serialize_message(m), "/fleet/state", sender, step)
    assert data[-32:] != bytes(32)
    assert same(read_uav_state(data).state, rclpy_ref.to_peer_state(m))


def test_values_come_through_exactly():
    """A hand-built state: every value the agent uses, including the float32 gauge and the stamp."""
    m = UavState(uav_id=7, sequence=11, step=42, x_m=1.25, y_m=-3.5, z_m=60.0, yaw_rad=-0.75)
    m.header.frame_id = "map"
    m.objective, m.target_fire_id, m.water_kg = 2, -1, 123.456
    m.centroid_x_m, m.centroid_y_m = math.nan, 9.0
    m.sent_per_topic, m.final, m.fires_sequence = [1, 0, 65535], True, 5
    f = FireEstimate(fire_id=3, status=FireEstimate.STATUS_EXTINGUISHED, x_m=10.0, y_m=20.0, extent_m=4.0)
    f.last_measurement = Time(sec=12, nanosec=300_000_000)
    f.front_x_m, f.front_y_m, f.max_spread_rate_mps = 11.0, math.inf, 0.5
    m.fires = [FireEstimate(fire_id=1, x_m=-1.0), f]
    w = read_uav_state(serialize_message(m))
    s = w.state
    assert (s.uav_id, s.sequence, s.step, s.x_m, s.y_m, s.z_m, s.yaw_rad) == (
        7,
        11,
        42,
        1.25,
        -3.5,
        60.0,
        -0.75,
    )
    assert (s.objective, s.target_fire_id, s.centroid_y_m) == (2, -1, 9.0) and math.isnan(s.centroid_x_m)
    assert s.water_kg == pytest.approx(123.456, rel=1e-7) and s.water_kg != 123.456  # float32, widened
    assert (w.uav_id, w.step, w.sent_per_topic, w.final) == (7, 42, (1, 0, 65535), True)
    assert (w.fires.uav_id, w.fires.sequence, w.fires.step) == (7, 5, 42)
    a, b = w.fires.fires
    assert (a.fire_id, a.active, a.x_m) == (1, True, -1.0)
    assert (b.fire_id, b.active, b.x_m, b.y_m, b.extent_m) == (3, False, 10.0, 20.0, 4.0)
    assert (b.last_measurement_s, b.front_x_m, b.front_y_m, b.max_spread_rate_mps) == (
        12.3,
        11.0,
        math.inf,
        0.5,
    )


def _sample() -> bytes:
    m = UavState(uav_id=2, step=3)
    m.header.frame_id = "map"
    m.alive_peers, m.sent_per_topic = [0, 1, 2], [1, 1]
    m.fires = [FireEstimate(fire_id=1), FireEstimate(fire_id=2)]
    return serialize_message(m)


def test_every_truncation_is_a_value_error():
    data = _sample()
    for n in range(len(data)):
        with pytest.raises(ValueError, match="UavState|CDR|length"):
            read_uav_state(data[:n])


def test_bytes_left_after_the_auth_field_are_refused():
    with pytest.raises(ValueError, match="expected its auth field to end"):
        read_uav_state(_sample() + b"\x00")


@pytest.mark.parametrize("head", [b"\x00\x00", b"\x00\x03", b"\x00\x07", b""])
def test_another_encapsulation_is_refused_by_name(head):
    data = _sample()
    with pytest.raises(ValueError, match="not XCDR1 little-endian"):
        read_uav_state(head + data[2:] if head else b"")


def test_a_length_past_the_end_is_named():
    m = UavState()
    m.sent_per_topic = [1, 2]
    data = bytearray(serialize_message(m))
    # the sent_per_topic length is the uint32 holding 2 just before the two uint16 values 1, 2
    at = bytes(data).index(b"\x02\x00\x00\x00\x01\x00\x02\x00")
    data[at : at + 4] = (10**6).to_bytes(4, "little")
    with pytest.raises(ValueError, match="sent_per_topic length 1000000 runs past the end"):
        read_uav_state(bytes(data))


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=600), st.booleans())
def test_noise_is_a_value_error_or_a_state(noise, with_header):
    data = (b"\x00\x01\x00\x00" + noise) if with_header else noise
    try:
        read_uav_state(data)
    except ValueError:
        pass


@settings(max_examples=150, deadline=None)
@given(uav_states(), st.data())
def test_a_flipped_byte_never_raises_anything_else(m, data):
    raw = bytearray(serialize_message(m))
    i = data.draw(st.integers(0, len(raw) - 1))
    raw[i] ^= data.draw(st.integers(1, 255))
    try:
        read_uav_state(bytes(raw))
    except ValueError:
        pass


def _error(data: bytes) -> str:
    with pytest.raises(ValueError) as e:
        read_uav_state(data)
    return str(e.value)


def test_the_errors_name_the_type_and_the_field_exactly():
    data = _sample()
    assert _error(b"\x00\x00" + data[2:]) == "UavState: not XCDR1 little-endian CDR (encapsulation 0000)"
    assert _error(data[:18]) == "UavState header.frame_id length 4 does not fit in 18 bytes"
    n = len(data)
    assert _error(data + bytes(4)) == (
        f"UavState of {n + 4} bytes: expected its auth field to end at byte {n + 4}, not {n}"
    )


def _with_count(m: UavState, count_of: bytes, value: int) -> bytes:
    """``m`` serialised, with the uint32 length just before ``count_of`` (its elements) set to ``value``."""
    data = bytearray(serialize_message(m))
    at = bytes(data).index(count_of) - 4
    data[at : at + 4] = value.to_bytes(4, "little")
    return bytes(data)


def test_lengths_are_bounded_by_the_bytes_left_and_named():
    m = UavState()
    m.sent_per_topic = [4660, 22136]  # 0x1234, 0x5678
    data = serialize_message(m)
    values = (4660).to_bytes(2, "little") + (22136).to_bytes(2, "little")
    left = len(data) - (data.index(values))  # bytes from the first value to the end
    k = left // 2 + 1  # one uint16 more than there are bytes left
    assert (
        _error(_with_count(m, values, k))
        == f"sent_per_topic length {k} runs past the end of {len(data)} bytes"
    )
    assert read_uav_state(_with_count(m, values, 2)).sent_per_topic == (4660, 22136)
    m = UavState(fires_sequence=0x0BADF00D)
    m.fires = [FireEstimate(fire_id=0x0C0FFEE0)]
    fires_at = (0x0C0FFEE0).to_bytes(4, "little")
    assert _error(_with_count(m, fires_at, 10)).startswith("fires length 10 runs past the end of ")
    assert len(read_uav_state(_with_count(m, fires_at, 1)).fires.fires) == 1


def test_a_long_sent_per_topic_reads():
    m = UavState()
    m.sent_per_topic = list(range(300))
    assert read_uav_state(serialize_message(m)).sent_per_topic == tuple(range(300))


def test_a_cut_right_after_a_sequence_is_a_truncation():
    m = UavState()
    m.sent_per_topic = [4660, 22136]
    data = serialize_message(m)
    end = data.index((22136).to_bytes(2, "little")) + 2  # just after the last value
    assert _error(data[:end]) == f"UavState truncated: {end} bytes"
    m = UavState()
    m.fires = [FireEstimate(fire_id=0x0C0FFEE0)]
    data = serialize_message(m)
    end = data.index((0x0C0FFEE0).to_bytes(4, "little")) + 77  # the least a fire takes, no padding
    assert _error(data[:end]) == f"UavState truncated: {end} bytes"


# --- the writer -------------------------------------------------------------------------------------
sim_stamps = st.builds(Time, sec=st.integers(0, 10**6), nanosec=st.integers(0, 999_999_999))


@st.composite
def written_states(draw) -> UavState:
    """States the agent writes: frame ``map``, auth zero, status ACTIVE / EXTINGUISHED, stamps of
    sim time (>= 0; up to ~11 days, where seconds as a float still hold every nanosecond)."""
    m = draw(uav_states())
    m.header.frame_id = "map"
    m.header.stamp = draw(sim_stamps)
    m.auth = [0] * 32
    for f in m.fires:
        f.status = draw(st.sampled_from([0, 1]))
        f.last_measurement = draw(sim_stamps)
    return m


def _write(m: UavState) -> bytes:
    from fire_uav_common.codecs.uav_state import write_uav_state
    from fire_uav_common.stamps import stamp_to_ns

    fires = list(rclpy_ref.to_peer_fires(m).fires)  # the FireEntry rows the message carries
    return write_uav_state(
        stamp_ns=stamp_to_ns(m.header.stamp), uav_id=m.uav_id, sequence=m.sequence, step=m.step,
        pose=(m.x_m, m.y_m, m.z_m, m.yaw_rad), covariance=list(m.covariance), objective=m.objective,
        target_fire_id=m.target_fire_id, water_kg=m.water_kg, centroid_xy=(m.centroid_x_m, m.centroid_y_m),
        alive_peers=list(m.alive_peers), crashed_peers=list(m.crashed_peers),
        packets=(m.packets_received, m.packets_lost, m.packets_rejected), sent_per_topic=list(m.sent_per_topic),
        final=m.final, fires_sequence=m.fires_sequence, fires=fires,
    )  # fmt: skip


@settings(max_examples=150, deadline=None)
@given(written_states())
def test_the_writer_writes_the_message(m):
    """rclpy reads the bytes as the message, and they are as long as rclpy's own (whose padding
    bytes are whatever the buffer held: they are not compared; the writer's are zeros)."""
    data = _write(m)
    assert len(data) == len(serialize_message(m))
    assert_same_message(deserialize_message(data, UavState), m)


def test_the_agents_state_bytes_are_the_message_the_node_built() -> None:
    """``outgoing.state_bytes`` of real agent outputs reads as the UavState the node built from them (``rclpy_reference.from_state`` / ``add_fires``), fires included."""
    from fire_uav_agent.outgoing import sent_per_topic, state_bytes
    from fire_uav_agent.testing.harness import Harness, scenario_path
    from fire_uav_common.stamps import to_time_msg

    h = Harness.from_file(scenario_path("ff_two_fires"), seed=3)
    checked = fires = 0
    for _ in range(120):
        r = h.step()
        for out in h.outputs:
            if out is None:
                continue
            b = r.bundles[out.state.uav_id]
            sent = sent_per_topic(out.perimeter is not None, out.front is not None)
            m = rclpy_ref.add_fires(rclpy_ref.from_state(out, to_time_msg(b.stamp_ns, Time)), out)
            m.sent_per_topic, m.final = sent, False
            data = state_bytes(out, b.stamp_ns, sent, False)
            assert len(data) == len(serialize_message(m))
            assert_same_message(deserialize_message(data, UavState), m)
            checked += 1
            fires += len(out.fires)
    assert checked > 300 and fires > 0


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def test_every_frame_id_length_puts_the_fields_after_it_where_rclpy_reads_them():
    """Each length of header.frame_id mod 8 (0 to 8 characters), one message each: uav_id is then
    followed by 0-3 bytes of padding before sequence, and the pose by 0 or 4 before it."""
    for n in range(9):
        m = UavState(uav_id=3, sequence=0x01020304, step=0x0A0B0C0D, objective=2, target_fire_id=-7)
        m.header.frame_id = "f" * n
        m.x_m, m.yaw_rad, m.water_kg, m.centroid_y_m = 1.5, -0.25, 4.0, 8.0
        w = read_uav_state(serialize_message(m))
        assert (w.uav_id, w.state.sequence, w.step, w.state.x_m, w.state.yaw_rad) == (
            3, 0x01020304, 0x0A0B0C0D, 1.5, -0.25,
        ), n  # fmt: skip
        assert (w.state.objective, w.state.target_fire_id, w.state.water_kg, w.state.centroid_y_m) == (
            2, -7, 4.0, 8.0,
        ), n  # fmt: skip


def test_a_fire_picture_is_finite_only_if_every_fire_is():
    from fire_uav_common.codecs.uav_state import FireEntry, PeerFires

    ok = FireEntry(1, True, 1.0, 2.0, 3.0)
    assert PeerFires(1, 1, 0).finite() and PeerFires(1, 1, 0, (ok, ok)).finite()
    for bad in (math.nan, math.inf, -math.inf):
        assert not PeerFires(1, 1, 0, (ok, FireEntry(2, True, bad, 2.0, 3.0))).finite()
        late = FireEntry(2, True, 1.0, 2.0, 3.0, last_measurement_s=bad)
        assert not PeerFires(1, 1, 0, (late, ok)).finite()


def test_the_writer_refuses_a_bad_stamp_or_pose_naming_them():
    from fire_uav_common.codecs.uav_state import write_uav_state

    args = dict(
        stamp_ns=0, uav_id=0, sequence=0, step=0, pose=(0.0,) * 4, covariance=(0.0,) * 16, objective=0,
        target_fire_id=-1, water_kg=0.0, centroid_xy=(0.0, 0.0), alive_peers=(), crashed_peers=(),
        packets=(0, 0, 0), sent_per_topic=(), final=False, fires_sequence=0, fires=(),
    )  # fmt: skip
    assert deserialize_message(write_uav_state(**args), UavState).target_fire_id == -1
    with pytest.raises(ValueError, match=r"^UavState stamp must be >= 0 ns, got -1$"):
        write_uav_state(**{**args, "stamp_ns": -1})
    for pose, cov in (((0.0,) * 3, (0.0,) * 16), ((0.0,) * 4, (0.0,) * 15)):
        with pytest.raises(
            ValueError,
            match=rf"^UavState pose needs 4 values and covariance 16, got {len(pose)} and {len(cov)}$",
        ):
            write_uav_state(**{**args, "pose": pose, "covariance": cov})


def test_a_fires_time_that_is_not_finite_or_negative_is_written_as_zero():
    """Writer doc: last_measurement_s as whole nanoseconds, 0 when negative or not finite."""
    from fire_uav_common.codecs.uav_state import FireEntry, write_uav_state

    for t in (math.nan, math.inf, -math.inf, -3.0):
        data = write_uav_state(
            stamp_ns=0, uav_id=0, sequence=0, step=0, pose=(0.0,) * 4, covariance=(0.0,) * 16, objective=0,
            target_fire_id=-1, water_kg=0.0, centroid_xy=(0.0, 0.0), alive_peers=(), crashed_peers=(),
            packets=(0, 0, 0), sent_per_topic=(), final=False, fires_sequence=0,
            fires=(FireEntry(1, True, 1.0, 2.0, 3.0, last_measurement_s=t),),
        )  # fmt: skip
        lm = deserialize_message(data, UavState).fires[0].last_measurement
        assert (lm.sec, lm.nanosec) == (0, 0), t


# --- the fast reading against the field-by-field one it falls back to ---------------------------------
def _outcome(read, data: bytes):
    """What ``read`` makes of ``data``: its result, with each object's ``__dict__`` (a field set
    outside the dataclass's own ``__init__`` shows there), or the error it raises."""
    try:
        w = read(data)
    except ValueError as e:
        return ("error", type(e), str(e))
    fires = tuple(sorted(f.__dict__.items()) for f in w.fires.fires)
    return ("read", w, sorted(w.state.__dict__.items()), sorted(w.fires.__dict__.items()), fires)


def _same_outcome(a, b) -> bool:
    if a[0] != b[0]:
        return False
    if a[0] == "error":
        return a == b
    return same(a[1], b[1]) and all(repr(x) == repr(y) for x, y in zip(a[2:], b[2:], strict=True))


@settings(max_examples=300, deadline=None)
@given(uav_states(), st.data())
def test_the_fast_reading_is_the_checked_one_for_any_bytes(m, data):
    """``read_uav_state`` (one unpack for the fixed fields, one per fire, objects built without
    their frozen ``__init__``) against ``read_uav_state_checked`` (the reader as it was, each field
    read and checked in turn): the same values, types and attributes for every message (frame ids
    of every length, 0-6 fires at either 8-byte phase), read without falling back, and the same
    error or the same values once a byte is flipped, the bytes are cut anywhere or bytes are added."""
    from unittest import mock

    from fire_uav_common.codecs import uav_state
    from fire_uav_common.codecs.uav_state import read_uav_state_checked

    raw = serialize_message(m)
    want = _outcome(read_uav_state_checked, raw)
    with mock.patch.object(uav_state, "read_uav_state_checked", side_effect=AssertionError("fell back")):
        assert _same_outcome(_outcome(read_uav_state, raw), want)  # a message: read without falling back
    flipped = bytearray(raw)
    i = data.draw(st.integers(0, len(raw) - 1))
    flipped[i] ^= data.draw(st.integers(1, 255))
    cut = raw[: data.draw(st.integers(0, len(raw)))]
    longer = raw + data.draw(st.binary(min_size=1, max_size=9))
    for b in (bytes(flipped), cut, longer):
        assert _same_outcome(_outcome(read_uav_state, b), _outcome(read_uav_state_checked, b))
