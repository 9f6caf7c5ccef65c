"""The soft e-stop's latch on disk: a runtime restarted after a crash comes back stopped.

ISO 13850: resetting a stop never restarts motion. A soft stop held only in memory is released
by any crash: systemd restarts ``lupin serve`` and the robot is free to drive with the operator
believing it stopped. So the latch lives in the runtime's state directory:

- ``soft-estop.json``: the soft stop as the operator last set it, written atomically on every
  change (a power cut leaves the old file or the new one, never half);
- ``runtime.running``: created when a runtime starts, removed when it closes cleanly. Found at
  start-up, it means the last runtime ended without closing (a crash, a kill, a power loss).

A runtime starts engaged when the last one left the soft stop engaged, or did not exit cleanly,
or the latch cannot be read (fail safe); the reason is logged and kept for the console. Only an
operator's release (``EStopBridge.set_soft(False)``) clears it.
"""
from __future__ import annotations

import json
import logging
import os
from pathlib import Path

from hw.atomic_file import write_atomic

LATCH = "soft-estop.json"
RUNNING = "runtime.running"


class SoftStopLatch:
    def __init__(self, directory: str | Path, log: logging.Logger | None = None):
        self.directory = Path(directory)
        self.log = log if log is not None else logging.getLogger(__name__)
        self.reason = ""
        """Why the runtime started engaged ('' when it started released)."""

    def open(self) -> bool:
        """Read what the last runtime left, mark this one as running; True: start engaged."""
        latch, running = self.directory / LATCH, self.directory / RUNNING
        reasons = []
        try:
            engaged = bool(json.loads(latch.read_text())["engaged"]) if latch.exists() else False
        except (OSError, ValueError, KeyError, TypeError) as exc:
            engaged = True
            reasons.append(f"the soft stop's latch {latch} is unreadable ({exc})")
        else:
            if engaged:
                reasons.append("the soft stop was engaged when the last runtime stopped")
        if running.exists():
            reasons.append("the last runtime did not exit cleanly (crash, kill or power loss)")
        write_atomic(running, f"{os.getpid()}\n".encode())
        self.reason = "; ".join(reasons)
        if reasons:
            self.log.warning("soft e-stop ENGAGED at start-up: %s; an operator's release clears it", self.reason)
            self.save(True)
        return bool(reasons)

    def save(self, engaged: bool) -> None:
        """The operator's soft stop, as it now stands; a write that fails is logged, not raised
        (the stop itself is in memory and holds; only a crash before the next write could lose it)."""
        try:
            write_atomic(self.directory / LATCH, json.dumps({"engaged": engaged}).encode())
        except OSError as exc:
            self.log.error("soft e-stop: cannot write its latch in %s (%s)", self.directory, exc)

    def close(self) -> None:
        """A clean exit: the next runtime need not assume a crash."""
        (self.directory / RUNNING).unlink(missing_ok=True)
