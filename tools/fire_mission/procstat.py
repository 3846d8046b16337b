"""CPU time and resident memory of child processes, read from /proc (Linux)."""

from __future__ import annotations

import os
from dataclasses import dataclass

_TICK = os.sysconf("SC_CLK_TCK")


@dataclass
class ProcSample:
    cpu_s: float  # user + system CPU time so far [s]
    rss_mb: float  # resident set size now [MiB]
    peak_rss_mb: float  # high-water mark [MiB]


def sample(pid: int) -> ProcSample | None:
    """The process's CPU time and memory now, or None if it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        with open(f"/proc/{pid}/status") as f:
            status = {line.split(":")[0]: line.split(":")[1].strip() for line in f if ":" in line}
    except (OSError, IndexError):
        return None
    if fields[0] == "Z":
        return None
    cpu = (int(fields[11]) + int(fields[12])) / _TICK  # utime, stime
    rss = int(status.get("VmRSS", "0 kB").split()[0]) / 1024
    peak = int(status.get("VmHWM", "0 kB").split()[0]) / 1024
    return ProcSample(cpu, rss, peak)
