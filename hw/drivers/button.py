"""The physical e-stop button on a GPIO line: the HAL's EStopButton.

``read_level`` returns the pin's level now, except that a press seen in the edge events since
the last read is latched for one read: a tap shorter than the 10 Hz control beat still stops
the wheels for a beat and reaches the e-stop bridge, instead of falling between two polls.
Which level means pressed is config (``hw.estop.engaged_level``, UNVERIFIED on the robot).
"""
from __future__ import annotations

from hw.drivers.gpio import is_rising, level
from hw.interfaces import DeviceError


class GpioButton:
    def __init__(self, request, line: int, engaged_level: int = 1):
        self.request, self.line, self.engaged_level = request, line, int(engaged_level)
        self.presses = 0

    def read_level(self) -> int:
        try:
            latched = False
            while self.request.wait_edge_events(0):
                batch = self.request.read_edge_events()
                if not batch:
                    break
                hits = sum(1 for e in batch if e.line_offset == self.line and int(is_rising(e)) == self.engaged_level)
                self.presses += hits
                latched |= hits > 0
            now = level(self.request.get_value(self.line))
        except OSError as exc:
            raise DeviceError(f"e-stop GPIO line {self.line}: {exc.strerror or exc}") from None
        return self.engaged_level if latched else now

    def peek(self) -> int:
        """The pin's level now, leaving the edge events (and the latch) to ``read_level``."""
        try:
            return level(self.request.get_value(self.line))
        except OSError as exc:
            raise DeviceError(f"e-stop GPIO line {self.line}: {exc.strerror or exc}") from None

    def close(self) -> None:
        self.request.release()
