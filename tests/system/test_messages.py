"""Every fire_uav_msgs type crosses a process boundary over DDS intact, field for field."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

pytestmark = pytest.mark.system


def test_every_message_type_round_trips(procs, tmp_path):
    import msg_probe

    out = tmp_path / "received.jsonl"
    types = msg_probe.message_types()
    assert len(types) >= 16, f"expected the full fleet message set, found {types}"
    sub = procs.start("sub", [sys.executable, str(HERE / "msg_probe.py"), "sub", str(out)])
    procs.start("pub", [sys.executable, str(HERE / "msg_probe.py"), "pub"])
    deadline = time.monotonic() + 60
    while sub.alive() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not sub.alive(), f"receiver did not get every type within 60 s:\n{procs.tail('sub')}"
    received = {}
    for line in out.read_text().splitlines():
        rec = json.loads(line)
        received[rec["type"]] = rec["msg"]
    assert sorted(received) == types
    for t in types:
        expected = json.loads(
            json.dumps(msg_probe.to_plain(msg_probe.sample(msg_probe._cls(f"fire_uav_msgs/{t}"))))
        )
        assert received[t] == expected, f"{t} changed on the way"
