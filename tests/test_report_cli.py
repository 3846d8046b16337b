"""scripts/report's command line: bad input gives one line on stderr and a non-zero exit."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from fire_report.synthetic import write_synthetic_mission

ROOT = Path(__file__).resolve().parents[1]


def run_report(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": f"{ROOT / 'tools'}:{os.environ.get('PYTHONPATH', '')}"}
    env.pop("FIRE_REPORT_DEBUG", None)
    return subprocess.run(
        [sys.executable, "-m", "fire_report", *args], capture_output=True, text=True, env=env, timeout=120
    )


@pytest.fixture(scope="module")
def good_bag(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("b") / "mission"
    write_synthetic_mission(path)
    return path


def assert_one_line_error(res: subprocess.CompletedProcess, *words: str) -> None:
    assert res.returncode != 0
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert "Traceback" not in res.stderr
    assert lines[0].startswith("report: error: ")
    for w in words:
        assert w in lines[0], lines[0]


def test_missing_path(tmp_path):
    assert_one_line_error(run_report(str(tmp_path / "nope")), "does not exist")


def test_directory_that_is_not_a_bag(tmp_path):
    (tmp_path / "stuff").mkdir()
    (tmp_path / "stuff" / "notes.txt").write_text("hello")
    assert_one_line_error(run_report(str(tmp_path / "stuff")), "not a rosbag2 bag")


def test_bad_metadata_yaml(tmp_path, good_bag):
    import shutil

    bag = tmp_path / "bag"
    shutil.copytree(good_bag, bag)
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: [unclosed")
    assert_one_line_error(run_report(str(bag)), "metadata.yaml")


def test_not_mcap(tmp_path):
    (tmp_path / "x.mcap").write_bytes(os.urandom(200))
    assert_one_line_error(run_report(str(tmp_path / "x.mcap")), "not an MCAP file")


def test_empty_mcap(tmp_path):
    (tmp_path / "x.mcap").write_bytes(b"")
    assert_one_line_error(run_report(str(tmp_path / "x.mcap")), "empty")


def test_truncated_mcap_with_nothing_recoverable(tmp_path, good_bag):
    data = (good_bag / "mission.mcap").read_bytes()
    (tmp_path / "t.mcap").write_bytes(data[:3000])
    assert_one_line_error(run_report(str(tmp_path / "t.mcap")), "no complete MCAP chunk")


def test_truncated_mcap_strict(tmp_path, good_bag):
    data = (good_bag / "mission.mcap").read_bytes()
    (tmp_path / "t.mcap").write_bytes(data[: len(data) - 100])
    assert_one_line_error(run_report("--strict", str(tmp_path / "t.mcap")), "no footer")


def test_truncated_mcap_salvaged_with_warning(tmp_path, good_bag):
    data = (good_bag / "mission.mcap").read_bytes()
    (tmp_path / "t.mcap").write_bytes(data[: len(data) - 100])  # summary cut, data complete
    res = run_report(str(tmp_path / "t.mcap"), "-o", str(tmp_path / "out"))
    assert res.returncode == 0, res.stderr
    assert "report: warning:" in res.stderr and "not closed" in res.stderr
    assert (tmp_path / "out" / "index.html").is_file()


def test_corrupted_mcap(tmp_path, good_bag):
    data = bytearray((good_bag / "mission.mcap").read_bytes())
    for i in range(2000, min(20000, len(data) - 2000), 7):
        data[i] ^= 0xFF
    (tmp_path / "c.mcap").write_bytes(bytes(data))
    assert_one_line_error(run_report(str(tmp_path / "c.mcap")), "corrupted")


def test_good_bag(tmp_path, good_bag):
    res = run_report(str(good_bag), "-o", str(tmp_path / "r"))
    assert res.returncode == 0, res.stderr
    assert "outcome=complete" in res.stdout
    assert (tmp_path / "r" / "metrics.json").is_file()
