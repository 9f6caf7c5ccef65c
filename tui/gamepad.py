"""The console's gamepad: a Linux evdev pad drives the robot as the ``joy`` source, dead-man held.

The seed drove with an Xbox pad plugged into the laptop, never into the robot (its BLE pairing on
the robot was fragile), on the mux's dead-man source ``joy`` (priority 100, 0.3 s: seed
twist_mux.yaml), which preempts the console's keys and autonomy alike. Here the pad is read on
the console's machine and each twist crosses the link as ``teleop`` with ``source: joy``:

- the dead-man is the left bumper (``BTN_TL``): while it is held, a twist from the sticks goes
  out at ``RATE`` (left stick: forward / back and strafe, the mecanum base; right stick: turn);
- let go, one zero twist goes out at once, so the wheels are told zero on the next control beat,
  and nothing after (the mux hands the bus back 0.3 s later);
- the link lost, or the pad unplugged: no twist reaches the robot and the mux times ``joy`` out
  within 0.3 s (the same zero, three beats later at most); a pad that stops reading counts as
  released.

Events are read straight from the device file (``/dev/input/eventN``): each is a kernel
``struct input_event`` (a timeval, then type, code and value), so no binding is needed, and a
recorded or piped event stream reads exactly as the pad does. Axis ranges are the Xbox pad's
(sticks signed 16-bit); a stick inside ``DEADZONE`` reads zero, as a resting stick never centres
exactly.
"""
from __future__ import annotations

import os
import select
import struct
import threading
from dataclasses import dataclass, field
from typing import Callable, Iterator

EVENT = struct.Struct("llHHi")
"""struct input_event on 64-bit Linux: tv_sec, tv_usec, type, code, value."""
EV_KEY, EV_ABS = 0x01, 0x03
BTN_TL = 0x136
"""The left bumper: the dead-man."""
ABS_X, ABS_Y, ABS_RX = 0x00, 0x01, 0x03
AXIS_MAX = 32767.0
DEADZONE = 0.1
SPEED = 0.3
"""m/s at full stick, forward and strafe: the console keys' 0.2 m/s with room to creep."""
TURN = 1.0
"""rad/s at full stick."""
RATE = 20.0
"""Twists per second while the dead-man is held: well inside the mux's 0.3 s joy timeout (the
same 20 Hz the scenario events' joystick publishes at)."""


@dataclass
class PadState:
    deadman: bool = False
    axes: dict[int, float] = field(default_factory=dict)
    """Axis code -> -1..1."""

    def apply(self, etype: int, code: int, value: int) -> None:
        if etype == EV_KEY and code == BTN_TL:
            self.deadman = value != 0  # 1 pressed, 2 auto-repeat, 0 released
        elif etype == EV_ABS:
            v = max(-1.0, min(1.0, value / AXIS_MAX))
            self.axes[code] = 0.0 if abs(v) < DEADZONE else v

    def twist(self) -> tuple[float, float, float]:
        """(vx, vy, wz): stick up is forward, left is +y and +yaw (REP-103); evdev's y grows down."""
        a = self.axes.get
        return (round(-a(ABS_Y, 0.0) * SPEED, 3), round(-a(ABS_X, 0.0) * SPEED, 3), round(-a(ABS_RX, 0.0) * TURN, 3))


def events(fd: int, stop: threading.Event, poll_s: float = 0.1) -> Iterator[tuple[int, int, int]]:
    """(type, code, value) from the event stream on ``fd`` until it ends or ``stop`` is set."""
    buf = b""
    while not stop.is_set():
        ready, _, _ = select.select([fd], [], [], poll_s)
        if not ready:
            continue
        chunk = os.read(fd, EVENT.size * 64)
        if not chunk:
            return
        buf += chunk
        whole = len(buf) - len(buf) % EVENT.size
        for i in range(0, whole, EVENT.size):
            _, _, etype, code, value = EVENT.unpack_from(buf, i)
            yield etype, code, value
        buf = buf[whole:]


class Gamepad:
    """Reads the pad on ``fd`` and drives through ``send`` (``Commands.send``: None when accepted,
    else the reason); ``refused`` hears every refusal once per run of the same one."""

    def __init__(self, fd: int, send: Callable[..., str | None], refused: Callable[[str], None] = lambda r: None,
                 rate: float = RATE):
        self.fd, self.send, self.refused, self.period = fd, send, refused, 1.0 / rate
        self.state = PadState()
        self.sent = 0
        self._lock = threading.Lock()
        self._beat = threading.Lock()
        """One step at a time (the reader's at a release, the driver's at its beat), so a held
        twist read before the release never lands after its zero."""
        self._stop = threading.Event()
        self._held = False
        self._last_refusal: str | None = None
        self._reader = threading.Thread(target=self._read, name="gamepad-read", daemon=True)
        self._driver = threading.Thread(target=self._drive, name="gamepad-drive", daemon=True)

    def start(self) -> "Gamepad":
        self._reader.start()
        self._driver.start()
        return self

    def _read(self) -> None:
        try:
            for etype, code, value in events(self.fd, self._stop):
                with self._lock:
                    self.state.apply(etype, code, value)
                if etype == EV_KEY and code == BTN_TL and value == 0:
                    self.step()  # let go: the zero now, not at the next beat
        except OSError:
            pass  # unplugged: released below
        with self._lock:
            self.state = PadState()

    def _drive(self) -> None:
        while not self._stop.wait(self.period):
            self.step()

    def step(self) -> None:
        """One beat: the sticks' twist while the dead-man is held, one zero when it is let go."""
        with self._beat:
            with self._lock:
                held, twist = self.state.deadman, self.state.twist()
            if not held and not self._held:
                return
            self._held = held
            vx, vy, wz = twist if held else (0.0, 0.0, 0.0)
            try:
                refusal = self.send("teleop", vx=vx, vy=vy, wz=wz, source="joy")
            except Exception as exc:  # a broken link must not stop the pad's thread
                refusal = f"teleop: {type(exc).__name__}: {exc}"
            self.sent += 1
            if refusal != self._last_refusal and refusal:
                self.refused(refusal)
            self._last_refusal = refusal

    def close(self) -> None:
        self._stop.set()
        for t in (self._reader, self._driver):
            if t.is_alive():
                t.join(2.0)
