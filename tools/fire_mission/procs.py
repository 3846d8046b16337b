"""Start ROS executables as child processes in one process group and end them by PID.

This replaces ``launch`` (not available from PyPI, see shared notes): every child is started
in one new process group (so a Ctrl-C on the terminal reaches only the supervisor, which then
ends the group in order), its stdout/stderr go to a log file, and :meth:`ProcessGroup.stop_all`
sends SIGINT, waits, then SIGKILLs what is left. Nothing is ever killed by name.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import random
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from fire_mission.errors import MissionError

__all__ = ["DOMAIN_RANGE", "MissionError", "ProcessGroup", "claim_domain", "executable", "ros_run_argv"]


def _ament_prefixes() -> list[Path]:
    return [Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]


def executable(package: str, exe: str) -> Path:
    """Resolve ``<prefix>/lib/<package>/<exe>`` through the ament index, as ``ros2 run`` does.

    ``ros2 run`` looks the package up in ``share/ament_index/resource_index/packages`` of each
    prefix on AMENT_PREFIX_PATH and runs ``<prefix>/lib/<package>/<exe>``.
    """
    prefixes = _ament_prefixes()
    if not prefixes:
        raise MissionError("AMENT_PREFIX_PATH is empty: source scripts/env.sh first")
    for prefix in prefixes:
        if (prefix / "share/ament_index/resource_index/packages" / package).is_file():
            path = prefix / "lib" / package / exe
            if not (path.is_file() and os.access(path, os.X_OK)):
                raise MissionError(f"package '{package}' found in {prefix} but it has no executable '{exe}'")
            return path
    raise MissionError(f"package '{package}' not found on AMENT_PREFIX_PATH ({len(prefixes)} prefixes)")


def ros_run_argv(package: str, exe: str, ros_args: list[str] | None = None) -> list[str]:
    """The argv of ``ros2 run package exe --ros-args ...``: the real ``ros2`` when installed,
    otherwise the same executable by path (identical behaviour)."""
    tail = ["--ros-args", *ros_args] if ros_args else []
    if shutil.which("ros2") and os.environ.get("FIRE_UAV_NO_ROS2_CLI") != "1":
        return ["ros2", "run", package, exe, *tail]
    return [str(executable(package, exe)), *tail]


#: ROS domain ids a run or test may claim. Ids above 101 with many participants can collide
#: with ephemeral ports on some systems; with LOCALHOST discovery and < 120 participants per
#: domain, 100..199 is safe.
DOMAIN_RANGE = range(100, 200)


def _lock_dir() -> Path:
    d = Path(tempfile.gettempdir()) / "fire_uav_domains"
    d.mkdir(exist_ok=True)
    return d


@contextlib.contextmanager
def claim_domain(hint: int | None = None, lock_dir: Path | None = None) -> Iterator[int]:
    """Hold a ROS_DOMAIN_ID that no other run, test or sweep mission on this host holds.

    Every fleet on one host (``scripts/run_mission``, system tests, benchmark sweeps, on any
    number of workers) claims its domain here, so two fleets never share a domain and never
    hear each other's lockstep messages. Tries the ids of :data:`DOMAIN_RANGE` from ``hint``
    (mod the range; None: a start drawn from the pid and the clock) and keeps an exclusive
    ``flock`` on ``<tmp>/fire_uav_domains/<id>.lock`` for the ``with`` body -- released by the
    kernel even if the holder is killed. Raises :class:`MissionError` when all 100 are held.
    """
    d = lock_dir or _lock_dir()
    n = len(DOMAIN_RANGE)
    if hint is None:
        hint = random.Random(os.getpid() * 7919 + time.monotonic_ns()).randrange(n)
    for k in range(n):
        dom = DOMAIN_RANGE[(hint + k) % n]
        f = open(d / f"{dom}.lock", "a+")  # held open for the lock's lifetime
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        try:
            yield dom
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)
            f.close()
        return
    raise MissionError(
        f"no free ROS domain id in {DOMAIN_RANGE.start}..{DOMAIN_RANGE.stop - 1} on {socket.gethostname()} "
        f"(locks in {d})"
    )


@dataclass
class Child:
    name: str
    argv: list[str]
    popen: subprocess.Popen
    log_path: Path
    started_wall_s: float = field(default_factory=time.monotonic)

    @property
    def pid(self) -> int:
        return self.popen.pid

    def alive(self) -> bool:
        return self.popen.poll() is None


def _end_with_parent() -> None:
    """In the child, before exec: SIGTERM when the runner dies, even by SIGKILL (Linux
    ``PR_SET_PDEATHSIG``), so a killed runner or a timed-out test leaves no fleet behind. SIGTERM,
    not SIGKILL: the recorder still closes its bag. Elsewhere a no-op."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM, 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


class ProcessGroup:
    """Children in one new process group, logs in ``log_dir``; a context manager that always
    ends every child it started (SIGINT, then SIGKILL after ``grace_s``)."""

    def __init__(self, log_dir: Path, env: dict[str, str] | None = None, *, grace_s: float = 5.0) -> None:
        self.log_dir = Path(log_dir)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self.env = dict(os.environ if env is None else env)
        self.grace_s = grace_s
        self.children: dict[str, Child] = {}
        self._pgid: int | None = None

    # -- context manager ------------------------------------------------------------------
    def __enter__(self) -> ProcessGroup:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop_all()

    # -- starting -------------------------------------------------------------------------
    def start(self, name: str, argv: list[str], *, env: dict[str, str] | None = None) -> Child:
        if name in self.children and self.children[name].alive():
            raise MissionError(f"a process named '{name}' is already running (pid {self.children[name].pid})")
        log_path = self.log_dir / f"{name}.log"
        log = open(log_path, "ab")  # the child keeps its own copy; ours is closed below
        full_env = dict(self.env)
        if env:
            full_env.update(env)

        def spawn(pgid: int) -> subprocess.Popen:
            return subprocess.Popen(
                argv,
                stdout=log,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                env=full_env,
                process_group=pgid,
                preexec_fn=_end_with_parent,
            )

        try:
            try:
                popen = spawn(self._pgid or 0)
            except PermissionError:
                # every earlier member has exited, so the group is gone: start a new one
                self._pgid = None
                popen = spawn(0)
        except OSError as e:
            log.close()
            raise MissionError(f"cannot start {name}: {argv[0]}: {e}") from e
        log.close()
        if self._pgid is None:
            self._pgid = popen.pid
        child = Child(name, argv, popen, log_path)
        self.children[name] = child
        return child

    # -- signals --------------------------------------------------------------------------
    def signal(self, name: str, sig: int) -> None:
        child = self.children[name]
        if child.alive():
            os.kill(child.pid, sig)

    def pids(self) -> list[int]:
        return [c.pid for c in self.children.values()]

    def alive(self) -> list[str]:
        return [n for n, c in self.children.items() if c.alive()]

    def stop(self, names: list[str], *, grace_s: float | None = None) -> dict[str, int | None]:
        """End the named children: SIGCONT (a stopped child cannot handle signals) + SIGINT;
        after half the grace period SIGTERM (a child started from a non-interactive shell may
        ignore SIGINT; rclpy handles both); after the grace period SIGKILL. Returns exit codes."""
        grace = self.grace_s if grace_s is None else grace_s
        t0 = time.monotonic()
        for sigs, until in (
            ((signal.SIGCONT, signal.SIGINT), t0 + grace / 2),
            ((signal.SIGTERM,), t0 + grace),
        ):
            for n in names:
                c = self.children[n]
                for sig in sigs:
                    if c.alive():
                        try:
                            os.kill(c.pid, sig)
                        except ProcessLookupError:
                            pass
            for n in names:
                try:
                    self.children[n].popen.wait(timeout=max(0.0, until - time.monotonic()))
                except subprocess.TimeoutExpired:
                    pass
        for n in names:
            c = self.children[n]
            if c.alive():
                try:
                    os.kill(c.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            c.popen.wait()
        return {n: self.children[n].popen.returncode for n in names}

    def stop_all(
        self, *, grace_s: float | None = None, first: list[str] | None = None
    ) -> dict[str, int | None]:
        """End every child: those named in ``first`` before the rest (e.g. agents before the
        recorder, so the recorder sees their last messages). Then SIGKILL the whole group in
        case a child left grandchildren."""
        codes: dict[str, int | None] = {}
        order = [n for n in (first or []) if n in self.children]
        if order:
            codes.update(self.stop(order, grace_s=grace_s))
        rest = [n for n in self.children if n not in order]
        codes.update(self.stop(rest, grace_s=grace_s))
        if self._pgid is not None:
            try:
                os.killpg(self._pgid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        return codes

    def tail(self, name: str, lines: int = 30) -> str:
        try:
            text = self.children[name].log_path.read_text(errors="replace")
        except (KeyError, OSError):
            return ""
        return "\n".join(text.splitlines()[-lines:])
