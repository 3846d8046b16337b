"""Bags the BagWriter writes read as rosbag2 Jazzy's own (fire_uav_recording.conformance)."""

from __future__ import annotations

import json

import fire_uav_recording as bag_io
import pytest
import yaml
from fire_uav_recording.conformance import check_bag
from mcap.reader import make_reader
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
from rosbags.rosbag2 import StoragePlugin, Writer

INF = QosTime(*bag_io.INFINITE_DURATION)
QOS = Qos(
    QosHistory.KEEP_LAST, 10, QosReliability.RELIABLE, QosDurability.VOLATILE,
    INF, INF, QosLiveliness.AUTOMATIC, INF, False,
)  # fmt: skip


def _write(writer, ts):
    clock_t = ts.types["rosgraph_msgs/msg/Clock"]
    time_t = ts.types["builtin_interfaces/msg/Time"]
    c = writer.add_connection("/clock", clock_t.__msgtype__, typestore=ts, offered_qos_profiles=[QOS])
    for i in range(20):
        data = ts.serialize_cdr(clock_t(clock=time_t(sec=i, nanosec=0)), clock_t.__msgtype__)
        writer.write(c, i * 10**9, data)


def test_bag_writer_bags_pass_the_rosbag2_checks(tmp_path):
    ts = bag_io.fleet_typestore()
    with bag_io.BagWriter(tmp_path / "bag") as w:
        _write(w, ts)
    assert check_bag(tmp_path / "bag", deserialize=lambda t, b: ts.deserialize_cdr(b, t)) == []
    meta = yaml.safe_load((tmp_path / "bag" / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert meta["ros_distro"] == "jazzy"
    q = meta["topics_with_message_count"][0]["topic_metadata"]["offered_qos_profiles"][0]
    assert q["deadline"] == {"sec": 9223372036, "nsec": 854775807}  # RMW_DURATION_INFINITE, 2**63 - 1 ns
    with (tmp_path / "bag" / "bag.mcap").open("rb") as f:
        ch = next(iter(make_reader(f).get_summary().channels.values()))
    want = None
    try:  # rosidl's own hash (the installed type description), when ROS is on AMENT_PREFIX_PATH
        for js in bag_io.find_msg_dir("rosgraph_msgs").glob("Clock.json"):
            want = json.loads(js.read_text())["type_hashes"][0]["hash_string"]
    except bag_io.BagError:
        pass
    assert ch.metadata["topic_type_hash"] == (want or ts.hash_rihs01("rosgraph_msgs/msg/Clock"))
    assert ch.metadata["topic_type_hash"].startswith("RIHS01_")


def test_a_plain_rosbags_bag_is_found_wanting(tmp_path):
    ts = bag_io.fleet_typestore()
    with Writer(tmp_path / "bag", version=9, storage_plugin=StoragePlugin.MCAP) as w:
        _write(w, ts)
    problems = "\n".join(check_bag(tmp_path / "bag"))
    assert "topic_type_hash" in problems
    assert "ros_distro 'rosbags'" in problems


def test_bad_messages_and_foxy_durations_are_named(tmp_path):
    ts = bag_io.fleet_typestore()
    foxy = QosTime(2147483647, 4294967295)
    with bag_io.BagWriter(tmp_path / "bag") as w:
        c = w.add_connection(
            "/clock",
            "rosgraph_msgs/msg/Clock",
            typestore=ts,
            offered_qos_profiles=[QOS._replace(deadline=foxy)],
        )
        w.write(c, 5, b"\x00\x01")
    problems = "\n".join(check_bag(tmp_path / "bag", deserialize=lambda t, b: ts.deserialize_cdr(b, t)))
    assert "Foxy-era infinite" in problems
    assert "does not deserialize as rosgraph_msgs/msg/Clock" in problems


def test_check_bag_errors_on_a_missing_path(tmp_path):
    with pytest.raises(bag_io.BagError, match="does not exist"):
        check_bag(tmp_path / "nope")
