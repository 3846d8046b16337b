"""The codecs' readers (``fire_uav_common.codecs``) on what Fast DDS actually delivers.

A message published as a message (as the world published its SensorBundle) reaches a raw subscription padded to
a multiple of 4 bytes, which ``serialize_message`` does not do: a reader tested only on
``serialize_message`` output refused every real bundle (found in a 20-UAV run). Here real rclpy
and Fast DDS (two nodes of this process), the fleet's topic helpers and QoS, a private context
and domain; what arrives is read both ways and must agree.
"""

from __future__ import annotations

import time

import pytest

rclpy = pytest.importorskip("rclpy")

from fire_uav_agent.testing import rclpy_reference as rclpy_ref  # noqa: E402
from fire_uav_agent.testing.compare import same  # noqa: E402
from fire_uav_common import topics  # noqa: E402
from fire_uav_common.codecs.sensor_bundle import read_sensor_bundle  # noqa: E402
from fire_uav_common.codecs.uav_state import read_uav_state  # noqa: E402
from fire_uav_msgs.msg import (  # noqa: E402
    FireDetection,
    FireEstimate,
    FireFront,
    GpsFix,
    PerimeterMap,
    SensorBundle,
    UavState,
)
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402
from sensor_msgs.msg import Imu, Range  # noqa: E402


def _bundle(k: int) -> SensorBundle:
    m = SensorBundle(uav_id=1, step=k, control_period_s=0.1, water_kg=10.0 + k, vehicle_status=1)
    m.header.frame_id = "map"[: k % 4]
    m.gyro = [Imu() for _ in range(k % 11)]
    for j, s in enumerate(m.gyro):
        s.header.frame_id, s.angular_velocity.z = "uav_1"[: (j + k) % 6], 0.01 * j
    m.altimeter = [Range(range=float(j)) for j in range(k % 3)]
    m.gps = [GpsFix(x_m=float(k)) for _ in range(k % 2)]
    m.fires = [FireDetection(track_id=j, x_m=1.0) for j in range(k % 4)]
    n = k % 5
    m.cells.x_m, m.cells.y_m, m.cells.state = [1.0] * n, [2.0] * n, bytes([1] * n)
    return m


def _state(k: int) -> UavState:
    m = UavState(uav_id=2, sequence=k + 1, step=k, water_kg=float(k))
    m.header.frame_id = "map"[: k % 4]
    m.alive_peers, m.sent_per_topic = list(range(k % 5)), [1] * (k % 3)
    m.fires = [FireEstimate(fire_id=j) for j in range(k % 3)]
    return m


def _round_trip(node_pair, spec, make, count: int, uav_id: int | None) -> list[bytes]:
    a, b, spin = node_pair
    got: list[bytes] = []
    topics.subscription(b, spec, got.append, uav_id=uav_id, raw=True)
    pub = topics.publisher(a, spec, uav_id=uav_id)
    end = time.monotonic() + 10
    while pub.get_subscription_count() == 0 and time.monotonic() < end:
        spin()
    for k in range(count):
        pub.publish(make(k))  # as a message, the way the world published its bundles before its codec
        spin()
    end = time.monotonic() + 10
    while len(got) < count and time.monotonic() < end:
        spin()
    assert len(got) == count
    return got


def test_bundles_published_as_messages_read_as_rclpy_reads_them(node_pair):
    got = _round_trip(node_pair, topics.SENSORS_SPEC, _bundle, 24, uav_id=1)
    assert any(len(serialize_message(_bundle(k))) % 4 for k in range(24))  # some need the padding
    for k, data in enumerate(got):
        w = read_sensor_bundle(data)
        assert same(w.bundle, rclpy_ref.to_bundle(deserialize_message(data, SensorBundle)))
        assert w.bundle.step == k


def test_states_published_as_messages_read_as_rclpy_reads_them(node_pair):
    got = _round_trip(node_pair, topics.FLEET_STATE_SPEC, _state, 12, uav_id=None)
    for k, data in enumerate(got):
        w = read_uav_state(data)
        assert same(w.state, rclpy_ref.to_peer_state(deserialize_message(data, UavState)))
        assert w.step == k


def test_bundles_the_world_writes_as_bytes_arrive_as_written(node_pair):
    """As the world publishes them: its writer's bytes, published raw."""
    from fire_uav_common.codecs.sensor_bundle import write_sensor_bundle
    from fire_world_sim.sensors import AltimeterSample, GyroSample
    from fire_world_sim.world import SensorBundleRecord

    def make(k: int) -> bytes:
        b = SensorBundleRecord(1, k, 100_000_000 * (k + 1), 0.1, water_kg=float(k), vehicle_status=1)
        b.gyro = [GyroSample(10_000_000 * j, 0.01 * j) for j in range(k % 11)]
        b.altimeter = [AltimeterSample(0, float(j), 40.0) for j in range(k % 3)]
        return write_sensor_bundle(b, 0.3)

    got = _round_trip(node_pair, topics.SENSORS_SPEC, make, 12, uav_id=1)
    for k, data in enumerate(got):
        assert same(read_sensor_bundle(data).bundle, read_sensor_bundle(make(k)).bundle)
        assert same(
            read_sensor_bundle(data).bundle, rclpy_ref.to_bundle(deserialize_message(data, SensorBundle))
        )


def _perimeter(k: int) -> PerimeterMap:
    m = PerimeterMap(uav_id=3, sequence=k + 1, fire_id=k - 2, center_x_m=0.5 * k)
    m.header.frame_id = "map"[: k % 4]
    m.outer_distance_m = [float(j) for j in range(k % 7)]
    m.importance = [0.25] * (k % 3)
    return m


def _front(k: int) -> FireFront:
    m = FireFront(uav_id=3, sequence=k + 1, cell_size_m=5.0)
    m.header.frame_id = "map"[: k % 4]
    n = k % 4
    m.x_m, m.y_m, m.state, m.spread_rate_mps = [1.5] * n, [2.5] * n, bytes([2] * n), [0.5] * n
    m.observed_s = [float(k)] * n  # n = 0: an empty double sequence (Fast CDR's tail)
    return m


@pytest.mark.parametrize("as_bytes", [False, True], ids=["as messages", "as the codec's bytes"])
def test_perimeter_maps_and_fronts_arrive_readable(node_pair, as_bytes):
    """Published as messages (as the agent did before the codecs) or as the writers' bytes (as it
    does now): what arrives reads as rclpy reads it."""
    from fire_uav_agent.incoming import peer_front, peer_perimeter
    from fire_uav_common.codecs.fire_front import read_fire_front
    from fire_uav_common.codecs.perimeter_map import read_perimeter_map

    def written(make):
        return (lambda k: bytes(serialize_message(make(k)))) if as_bytes else make

    got = _round_trip(node_pair, topics.FLEET_PERIMETER_SPEC, written(_perimeter), 12, uav_id=None)
    for k, data in enumerate(got):
        want = rclpy_ref.to_peer_perimeter(deserialize_message(data, PerimeterMap), 0.1)
        assert same(peer_perimeter(read_perimeter_map(data), 0.1), want) and want.sequence == k + 1
    got = _round_trip(node_pair, topics.FLEET_FRONT_SPEC, written(_front), 12, uav_id=None)
    for k, data in enumerate(got):
        want = rclpy_ref.to_peer_front(deserialize_message(data, FireFront), 0.1)
        assert same(peer_front(read_fire_front(data), 0.1), want) and want.sequence == k + 1
