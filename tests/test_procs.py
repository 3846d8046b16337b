"""fire_mission.procs: a runner that dies, even by SIGKILL, takes its fleet with it; no two fleets
on one host share a ROS domain."""

import contextlib
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from fire_mission.procs import DOMAIN_RANGE, MissionError, claim_domain

ROOT = Path(__file__).resolve().parents[1]


def _gone(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    try:  # a zombie waiting for init to reap it is gone too
        return Path(f"/proc/{pid}/stat").read_text().split()[2] == "Z"
    except OSError:
        return True


def test_children_end_when_the_runner_is_killed(tmp_path):
    parent = textwrap.dedent(
        f"""
        import sys, time
        sys.path.insert(0, {str(ROOT / "tools")!r})
        from fire_mission.procs import ProcessGroup
        g = ProcessGroup({str(tmp_path / "logs")!r}, {{}}, grace_s=1.0)
        c = g.start("sleeper", ["sleep", "120"])
        print(c.pid, flush=True)
        time.sleep(120)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", parent], stdout=subprocess.PIPE, text=True)
    child = int(p.stdout.readline())
    assert not _gone(child)
    p.kill()  # SIGKILL: no cleanup code of the runner runs
    p.wait()
    for _ in range(100):  # the kernel delivers the parent-death signal at once; allow a slow machine
        if _gone(child):
            break
        time.sleep(0.1)
    else:
        os.kill(child, signal.SIGKILL)
        raise AssertionError(f"child {child} outlived its SIGKILLed runner")


def test_domain_claims_are_exclusive_and_run_out(tmp_path: Path) -> None:
    with contextlib.ExitStack() as stack:
        held = [stack.enter_context(claim_domain(7, tmp_path)) for _ in DOMAIN_RANGE]
        assert sorted(held) == list(DOMAIN_RANGE)  # every id once, none twice
        with (
            pytest.raises(MissionError, match="no free ROS domain id in 100..199"),
            claim_domain(0, tmp_path),
        ):
            pass
    with claim_domain(7, tmp_path) as d:  # released again
        assert d == DOMAIN_RANGE[7]


def test_a_domain_held_by_another_process_is_not_given_out(tmp_path):
    """Two runs started at once (two run_mission, a test beside a sweep) each get their own domain."""
    holder = textwrap.dedent(
        f"""
        import sys, time
        sys.path.insert(0, {str(ROOT / "tools")!r})
        from pathlib import Path
        from fire_mission.procs import claim_domain
        with claim_domain(3, Path({str(tmp_path)!r})) as d:
            print(d, flush=True)
            time.sleep(60)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", holder], stdout=subprocess.PIPE, text=True)
    try:
        theirs = int(p.stdout.readline())
        assert theirs == DOMAIN_RANGE[3]
        with claim_domain(3, tmp_path) as mine:
            assert mine == DOMAIN_RANGE[4]
    finally:
        p.kill()
        p.wait()
    with claim_domain(3, tmp_path) as again:  # the kernel released the killed holder's lock
        assert again == DOMAIN_RANGE[3]
