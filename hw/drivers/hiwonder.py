"""Hiwonder bus servos over a half-duplex TTL adapter: the HAL's ServoBus, and the whole set.

One call is one bus transaction (plus bounded retries for reads). The bus is half duplex:
a request goes out, then the one addressed servo answers. Some adapters echo every byte they
send (``echo=True``: the echo is read and checked first). Either way a frame identical to the
request is never accepted as the reply (a known community-driver bug), and a reply must carry
the requested id, command and parameter count. A read that times out or comes back garbled
is retried up to ``retries`` times, then raises ``DeviceError``: the arm code degrades on it.

Also avoided from the reference's list of community-driver bugs: the offset read sends the
servo id (not swapped arguments); negative offsets are two's complement (+256, not +255);
``adjust_offset`` sends ANGLE_OFFSET_ADJUST 17 (volatile), ``write_offset`` sends 18.

Units are the device's: positions 0..1000 counts (0.24 deg each), times in ms (0..30000).
"""
from __future__ import annotations

import os
import threading
import time

from hw.drivers.hiwonder_protocol import REPLY_PARAMS, Cmd, FrameParser, encode, from_i8, i8, u16
from hw.errors import InputError
from hw.interfaces import DeviceError, ServoStatus


def open_serial(path: str, baud: int, what: str, timeout: float = 0.05):
    import serial

    try:
        return serial.Serial(path, baud, timeout=timeout, write_timeout=1.0)
    except (serial.SerialException, OSError, ValueError) as exc:
        errno = getattr(exc, "errno", None)
        reason = os.strerror(errno) if isinstance(errno, int) else (str(exc) or type(exc).__name__)
        raise InputError(f"{what} port {path}: cannot open ({reason})") from None


class HiwonderBus:
    def __init__(self, port, *, echo: bool = False, timeout_s: float = 0.03, retries: int = 2):
        self.port, self.echo, self.timeout_s, self.retries = port, echo, timeout_s, retries
        self.parser = FrameParser()
        self.lock = threading.Lock()
        self.transactions = 0
        self.retried = 0

    @classmethod
    def open(cls, path: str, baud: int = 115200, **kw) -> "HiwonderBus":
        return cls(open_serial(path, baud, "Hiwonder servo bus"), **kw)

    def close(self) -> None:
        self.port.close()

    # --- transactions -------------------------------------------------------------------
    def _write(self, request: bytes) -> None:
        self.port.reset_input_buffer()
        self.parser.buf.clear()
        try:
            self.port.write(request)
            self.port.flush()
        except OSError as exc:
            raise DeviceError(f"servo bus: write failed ({exc})") from None
        self.transactions += 1
        if self.echo:
            self.port.timeout = self.timeout_s
            echo = self.port.read(len(request))
            if echo != request:  # collision or a lost byte: keep what came for the parser
                self.parser.feed(echo)

    def _send(self, servo_id: int, cmd: int, params: bytes = b"") -> None:
        with self.lock:
            self._write(encode(servo_id, cmd, params))

    def _query(self, servo_id: int, cmd: Cmd, params: bytes = b"") -> bytes:
        request = encode(servo_id, cmd, params)
        n = REPLY_PARAMS[cmd]
        with self.lock:
            for attempt in range(self.retries + 1):
                if attempt:
                    self.retried += 1
                self._write(request)
                reply = self._await(servo_id, cmd, n, request)
                if reply is not None:
                    return reply
        raise DeviceError(f"servo id {servo_id}: no valid reply to {cmd.name} "
                          f"({self.retries + 1} attempts, {self.timeout_s * 1000:.0f} ms each)")

    def _await(self, servo_id: int, cmd: int, n: int, request: bytes) -> bytes | None:
        deadline = time.monotonic() + self.timeout_s
        want = n + 6
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            self.port.timeout = left
            chunk = self.port.read(max(want - len(self.parser.buf), self.port.in_waiting, 1))
            for f in self.parser.feed(chunk):
                if f.servo_id == servo_id and f.cmd == cmd and len(f.params) == n and f.encode() != request:
                    return f.params

    # --- HAL: ServoBus --------------------------------------------------------------------
    def move(self, servo_id: int, position: int, duration_ms: int) -> None:
        pos = max(0, min(1000, int(position)))
        ms = max(0, min(30000, int(duration_ms)))
        self._send(servo_id, Cmd.MOVE_TIME_WRITE, u16(pos) + u16(ms))

    def read_position(self, servo_id: int) -> int:
        return int.from_bytes(self._query(servo_id, Cmd.POS_READ), "little", signed=True)

    def read_status(self, servo_id: int) -> ServoStatus:
        return ServoStatus(self.read_position(servo_id), self.read_vin(servo_id),
                           self.read_temperature(servo_id), self.read_load(servo_id))

    def set_load(self, servo_id: int, loaded: bool) -> None:
        self._send(servo_id, Cmd.LOAD_OR_UNLOAD_WRITE, bytes([1 if loaded else 0]))

    def adjust_offset(self, servo_id: int, offset: int) -> None:
        """Volatile offset, -125..125 units (+-30 deg): ANGLE_OFFSET_ADJUST (17)."""
        if not -125 <= int(offset) <= 125:
            raise ValueError(f"servo offset {offset} out of -125..125")
        self._send(servo_id, Cmd.ANGLE_OFFSET_ADJUST, bytes([i8(offset)]))

    def read_offset(self, servo_id: int) -> int:
        return from_i8(self._query(servo_id, Cmd.ANGLE_OFFSET_READ)[0])

    # --- the rest of the command set ------------------------------------------------------
    def write_offset(self, servo_id: int) -> None:
        """Persist the adjusted offset in the servo: ANGLE_OFFSET_WRITE (18)."""
        self._send(servo_id, Cmd.ANGLE_OFFSET_WRITE)

    def stop(self, servo_id: int) -> None:
        self._send(servo_id, Cmd.MOVE_STOP)

    def ping(self, servo_id: int) -> bool:
        try:
            return self._query(servo_id, Cmd.ID_READ)[0] == servo_id
        except DeviceError:
            return False

    def read_move(self, servo_id: int) -> tuple[int, int]:
        p = self._query(servo_id, Cmd.MOVE_TIME_READ)
        return int.from_bytes(p[0:2], "little"), int.from_bytes(p[2:4], "little")

    def write_angle_limits(self, servo_id: int, lo: int, hi: int) -> None:
        if not 0 <= lo < hi <= 1000:
            raise ValueError(f"angle limits must satisfy 0 <= min < max <= 1000, got {lo}, {hi}")
        self._send(servo_id, Cmd.ANGLE_LIMIT_WRITE, u16(lo) + u16(hi))

    def read_angle_limits(self, servo_id: int) -> tuple[int, int]:
        p = self._query(servo_id, Cmd.ANGLE_LIMIT_READ)
        return int.from_bytes(p[0:2], "little"), int.from_bytes(p[2:4], "little")

    def read_vin(self, servo_id: int) -> int:
        return int.from_bytes(self._query(servo_id, Cmd.VIN_READ), "little")

    def read_temperature(self, servo_id: int) -> int:
        return self._query(servo_id, Cmd.TEMP_READ)[0]

    def read_load(self, servo_id: int) -> bool:
        return bool(self._query(servo_id, Cmd.LOAD_OR_UNLOAD_READ)[0])

    def read_errors(self, servo_id: int) -> int:
        """Bits: 1 over-temperature, 2 over-voltage, 4 stalled rotor."""
        return self._query(servo_id, Cmd.LED_ERROR_READ)[0]
