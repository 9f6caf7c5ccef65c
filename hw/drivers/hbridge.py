"""The four mecanum motors as H-bridges on PCA9685 channel pairs: the HAL's WheelDriver.

Vendor wiring (reference): two channels per motor, forward on A, reverse on B. On a direction
reversal both channels of that motor are held at zero for ``reversal_pause_s`` (~10 ms) before
the new direction is driven, so the bridge never sees an instantaneous reversal (shoot-through
and a current spike on a 5 A-capped pack, seed). While ``inhibit()`` is true (the e-stop pin,
read now) every PCA9685 output goes full-off in one write, whatever duties arrive: the base
controller already sends zeros, this makes the stop independent of it.

The wheels remember when they were last told to turn (``driving``, ``written_at`` on ``clock``)
and take their writes under ``lock``, so ``hw.wheel_watchdog`` can cut them from its own thread
(``cut``) when the control loop that writes them stops.
"""
from __future__ import annotations

import math
import threading
from typing import Callable, Sequence

import numpy as np

from hw.drivers.pca9685 import Pca9685
from hw.interfaces import WHEELS


class HBridgeWheels:
    def __init__(self, pwm: Pca9685, channels: dict[str, tuple[int, int]], reversal_pause_s: float = 0.010,
                 sleep: Callable[[float], None] | None = None, inhibit: Callable[[], bool] | None = None, *,
                 clock: Callable[[], float]):
        """``clock``: the hardware clock's seconds (``hw.wall_clock.WallClock.now``), which each
        write is stamped with for the watchdog."""
        missing = [w for w in WHEELS if w not in channels]
        if missing:
            raise ValueError(f"no PCA9685 channels for wheel(s) {', '.join(missing)}")
        self.pwm = pwm
        self.channels = [tuple(channels[w]) for w in WHEELS]
        self.pause = reversal_pause_s
        self._sleep = sleep or (lambda s: None)
        self._inhibit = inhibit or (lambda: False)
        self.direction = np.zeros(4, dtype=int)
        self.inhibited = False
        self.reversals = 0
        self.clock = clock
        self.lock = threading.RLock()
        """Held for each write (reentrant: the watchdog judges and cuts under one hold)."""
        self.driving = False
        """Did the last write leave any wheel turning?"""
        self.written_at = clock()

    def set_duties(self, duties: Sequence[float]) -> None:
        d = np.array([x if math.isfinite(x) else 0.0 for x in duties], dtype=float)
        if d.shape != (4,):
            raise ValueError(f"expected 4 duties in {WHEELS} order, got {len(d)}")
        d = np.clip(d, -1.0, 1.0)
        with self.lock:
            self._write(d)
            self.written_at = self.clock()

    def cut(self) -> None:
        """Every output full-off in one write, now (the watchdog's; the next ``set_duties`` drives
        again)."""
        with self.lock:
            self.pwm.all_off()
            self.direction[:] = 0
            self.driving = False

    def _write(self, d: np.ndarray) -> None:
        if self._inhibit():
            self.pwm.all_off()
            self.direction[:] = 0
            self.inhibited, self.driving = True, False
            return
        self.inhibited = False
        new_dir = np.sign(d).astype(int)
        reversing = np.flatnonzero(self.direction * new_dir < 0)
        if reversing.size and self.pause > 0:
            for w in reversing:
                for ch in self.channels[w]:
                    self.pwm.set_duty(ch, 0.0)
            self._sleep(self.pause)
        self.reversals += int(reversing.size)
        for (a, b), x in zip(self.channels, d):
            self.pwm.set_duty(a, max(x, 0.0))
            self.pwm.set_duty(b, max(-x, 0.0))
        self.direction = new_dir
        self.driving = bool(np.any(d != 0.0))
