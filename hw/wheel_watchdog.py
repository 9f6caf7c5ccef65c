"""The wheels' watchdog: a control loop that stops writing cuts the motors.

The PCA9685 holds its last duties until told otherwise, and the H-bridges behind it have no
command timeout of their own (hardware reference: plain PWM in, no link to time out). So a
runtime whose loop stalls while the robot drives (a kernel compiled on its first use, a
machine swapping, a debugger's breakpoint) leaves the wheels turning at the last twist, with
nobody reading the lidar, the e-stop's soft half or the people guard: the mux's source timeouts
(0.3-0.5 s) are judged by that same loop, so they cannot help. The SLAM worker was once seen
busy for over 5 s on a first-use compile (``nav.slam.worker.warm_up``); the control loop has
the same kind of kernels.

A thread of its own, apart from the loop, looks every ``period`` s: when the wheels were left
turning by a write more than ``limit`` ago, every output goes full-off in one write (the e-stop
path's ``all_off``, ``HBridgeWheels.cut``), once, logged at ERROR with how long the loop had been
silent. The loop's next write drives again: by then its twists are judged afresh (a source that
went silent meanwhile is stale, the collision monitor reads the newest scan). A robot standing
still (its last write all zeros) is never cut: a loop may idle.

``limit`` (``hw.devices.pwm.watchdog_s``, 0.5 s) is five of the controller's 100 ms beats: well
clear of a beat's jitter, and at the base's 0.3 m/s about 0.15 m driven blind before the cut.
"""
from __future__ import annotations

import logging
import threading
from typing import Protocol

log = logging.getLogger(__name__)


class CuttableWheels(Protocol):
    lock: threading.RLock
    driving: bool
    written_at: float

    def clock(self) -> float: ...

    def cut(self) -> None: ...


class WheelWatchdog:
    def __init__(self, wheels: CuttableWheels, limit: float, period: float | None = None):
        self.wheels, self.limit = wheels, limit
        self.period = period if period is not None else limit / 5.0
        self.cuts = 0
        """Stalls caught so far."""
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def check(self) -> bool:
        """One look: cut the wheels if they were left turning more than ``limit`` ago (True)."""
        w = self.wheels
        with w.lock:  # judged and cut under one hold: a write that lands meanwhile is never undone
            silent = w.clock() - w.written_at
            if not (w.driving and silent > self.limit):
                return False
            w.cut()
        self.cuts += 1
        log.error("control loop silent for %.2f s with the wheels turning: every motor output cut "
                  "(the loop's next command drives again)", silent)
        return True

    def start(self) -> "WheelWatchdog":
        self._thread = threading.Thread(target=self._run, name="wheel-watchdog", daemon=True)
        self._thread.start()
        return self

    def _run(self) -> None:
        while not self._stop.wait(self.period):
            try:
                self.check()
            except Exception:  # noqa: BLE001 - a bus error now must not end the watch for good
                log.exception("wheel watchdog: the look failed; looking again")

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
