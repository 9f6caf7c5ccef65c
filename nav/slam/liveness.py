"""Is a silent SLAM worker wedged, or only starved of CPU?

A worker that has not answered for ``reply_timeout`` seconds used to be killed as wedged. On a
machine whose cores are busy (the robot's Cortex-A55 during a map render, or a CI box running
four jobs) a healthy worker can be that slow, and killing it throws away the map mid-patrol
(a 180-pot patrol lost its map that way). What tells the two apart is the worker's own CPU
time, which the kernel keeps for every process:

* a worker that is **working** (runnable, just waiting for a core) keeps gaining CPU time,
  however slowly: it is waited on;
* a worker that is **hung** (blocked forever, stopped) gains none: after ``limit`` seconds
  without any it is wedged;
* a worker that is **spinning** (an endless loop) gains it fast: after ``limit`` CPU seconds
  on one scan it is wedged too, since no scan costs a thousandth of that.

Where the kernel does not say (no ``/proc``), silence alone decides, as before.
"""
from __future__ import annotations

import os
from typing import Optional

_TICK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def cpu_seconds(pid: int) -> Optional[float]:
    """User + system CPU seconds of process ``pid`` (None where ``/proc`` cannot say)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            stat = f.read()
    except OSError:
        return None
    fields = stat[stat.rfind(b")") + 2:].split()  # the command name may hold spaces
    return (int(fields[11]) + int(fields[12])) / _TICK


class Liveness:
    """Watches one late reply from a worker process; made only once a reply is late, so a
    prompt worker never costs a read of ``/proc``."""

    def __init__(self, pid: int, since: float):
        self.pid = pid
        self._progress_at = since
        """When the worker was last seen gaining CPU (at first: when the wait began)."""
        self._cpu_at_start = self._cpu = cpu_seconds(pid)

    def wedged(self, now: float, limit: float) -> Optional[str]:
        """Why the worker counts as wedged at ``now`` (seconds on the caller's clock), or None."""
        cpu = cpu_seconds(self.pid)
        if cpu is None or self._cpu_at_start is None:
            return f"no reply in {limit:g} s" if now - self._progress_at >= limit else None
        if cpu > self._cpu:
            self._cpu, self._progress_at = cpu, now
        if cpu - self._cpu_at_start >= limit:
            return f"{cpu - self._cpu_at_start:.1f} CPU s on one scan (spinning)"
        if now - self._progress_at >= limit:
            return f"no reply and no CPU used in {limit:g} s (hung)"
        return None
