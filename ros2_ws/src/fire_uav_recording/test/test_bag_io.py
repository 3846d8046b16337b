"""fire_uav_recording: typestore, crash-safe writer, validating reader (no ROS processes)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import fire_uav_recording as bag_io
import pytest


def test_typestore_hashes_match_the_build():
    ts = bag_io.fleet_typestore()
    msg_dir = bag_io.find_msg_dir()
    checked = 0
    for js in msg_dir.glob("*.json"):  # installed type descriptions (absent in a bare source tree)
        want = json.loads(js.read_text())["type_hashes"][0]
        assert ts.hash_rihs01(want["type_name"]) == want["hash_string"]
        checked += 1
    assert "fire_uav_msgs/msg/UavState" in ts.fielddefs
    if not checked:
        pytest.skip("no installed .json type descriptions to compare with")


def test_writer_refuses_an_existing_path(tmp_path):
    (tmp_path / "bag").mkdir()
    with pytest.raises(bag_io.BagError, match="exists already"):
        bag_io.BagWriter(tmp_path / "bag")
    with pytest.raises(bag_io.BagError, match="parent directory"):
        bag_io.BagWriter(tmp_path / "no" / "bag")


def test_inspect_errors(tmp_path):
    with pytest.raises(bag_io.BagError, match="does not exist"):
        bag_io.inspect_bag(tmp_path / "x")
    (tmp_path / "d").mkdir()
    with pytest.raises(bag_io.BagError, match="not a rosbag2 bag"):
        bag_io.inspect_bag(tmp_path / "d")
    (tmp_path / "f.txt").write_text("x")
    with pytest.raises(bag_io.BagError, match="not a bag"):
        bag_io.inspect_bag(tmp_path / "f.txt")
    (tmp_path / "e.mcap").write_bytes(b"")
    with pytest.raises(bag_io.BagError, match="empty file"):
        bag_io.inspect_bag(tmp_path / "e.mcap")


WRITER_SCRIPT = textwrap.dedent(
    """
    import os, signal, sys
    import fire_uav_recording as bag_io
    ts = bag_io.fleet_typestore()
    Clock = ts.types["rosgraph_msgs/msg/Clock"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    w = bag_io.BagWriter(sys.argv[1], custom_data={bag_io.KEY_UAV_COUNT: "5"})
    w.open()
    c = w.add_connection("/clock", Clock.__msgtype__, typestore=ts)
    for i in range(3000):
        w.write(c, i * 10**8, ts.serialize_cdr(Clock(clock=Time(sec=i // 10, nanosec=(i % 10) * 10**8)), Clock.__msgtype__))
        if i % 1000 == 999:
            w.flush()
    os.kill(os.getpid(), signal.SIGKILL)
    """
)


def test_sigkilled_writer_leaves_a_readable_bag(tmp_path):
    bag = tmp_path / "bag"
    src = Path(bag_io.__file__).resolve().parents[1]
    res = subprocess.run(
        [sys.executable, "-c", WRITER_SCRIPT, str(bag)],
        env={"PYTHONPATH": str(src)},
        capture_output=True,
        timeout=120,
    )
    assert res.returncode == -signal.SIGKILL, res.stderr
    info = bag_io.inspect_bag(bag)
    assert not info.complete and info.custom_data[bag_io.KEY_CLOSED] == "false"
    with pytest.raises(bag_io.BagError, match="no footer"):
        with bag_io.open_bag(bag, salvage=False):
            pass
    with bag_io.open_bag(bag) as b:
        assert b.reader.message_count == 3000  # everything up to the last flush
        assert b.custom_data[bag_io.KEY_UAV_COUNT] == "5"
        assert sum(1 for _ in b.messages()) == 3000
    result = bag_io.repair_bag(bag, tmp_path / "fixed")
    assert result.messages == 3000
    with bag_io.open_bag(tmp_path / "fixed") as b:
        assert b.reader.message_count == 3000 and not b.warnings[1:]


def test_closed_bag_metadata(tmp_path):
    ts = bag_io.fleet_typestore()
    with bag_io.BagWriter(tmp_path / "b", custom_data={bag_io.KEY_SEED: "9"}) as w:
        w.add_connection("/clock", "rosgraph_msgs/msg/Clock", typestore=ts)
    info = bag_io.inspect_bag(tmp_path / "b")
    assert info.complete and info.custom_data == {bag_io.KEY_SEED: "9", bag_io.KEY_CLOSED: "true"}
