"""Shared by the system tests that hold a process up for real: wait for a log line; SIGSTOP and SIGCONT.

A process held up by SIGSTOP stands for one descheduled on a busy machine. It is let go (SIGCONT)
after at most ``max_s`` of wall time, below the 10 s DDS lease beyond which its readers count as
dead and nothing waits for them any more, or sooner once the test says when (``release_in``).
"""

from __future__ import annotations

import signal
import threading
import time


def wait_for_line(
    procs, name: str, text: str, timeout_s: float, *, lines: int = 400, poll_s: float = 0.005
) -> str:
    """Wait until ``text`` is in the last ``lines`` lines of ``name``'s log; return that tail.

    Fails, with the log, if the process ends without it or ``timeout_s`` of wall time pass.
    """
    deadline = time.monotonic() + timeout_s
    while text not in (log := procs.tail(name, lines)):
        ended = not procs.children[name].alive() and text not in procs.tail(name, lines)
        assert not ended, f"{name} ended without {text!r}:\n{procs.tail(name)}"
        assert time.monotonic() < deadline, f"{name}: no {text!r}:\n{procs.tail(name)}"
        time.sleep(poll_s)
    return log


class HeldUp:
    """``with HeldUp(procs, name, max_s) as h:`` stops ``name`` now and always lets it go at the end."""

    def __init__(self, procs, name: str, max_s: float) -> None:
        self.procs, self.name, self.max_s = procs, name, max_s
        self.stopped = 0.0
        self._timer: threading.Timer | None = None

    def _release_after(self, s: float) -> None:
        if self._timer is not None:
            self._timer.cancel()
        self._timer = threading.Timer(s, lambda: self.procs.signal(self.name, signal.SIGCONT))
        self._timer.start()

    def __enter__(self) -> HeldUp:
        self.procs.signal(self.name, signal.SIGSTOP)
        self.stopped = time.monotonic()
        self._release_after(self.max_s)
        return self

    def held_s(self) -> float:
        """Wall time since the stop."""
        return time.monotonic() - self.stopped

    def release_in(self, after_s: float) -> float:
        """Let go ``after_s`` from now if that is sooner than ``max_s`` after the stop; return ``held_s()``."""
        if self.max_s - self.held_s() > after_s:
            self._release_after(after_s)
        return self.held_s()

    def __exit__(self, *exc: object) -> None:
        if self._timer is not None:
            self._timer.cancel()
        self.procs.signal(self.name, signal.SIGCONT)
