"""fire_mission.procs: a runner that dies, even by SIGKILL, takes its fleet with it."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

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
