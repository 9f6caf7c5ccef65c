"""A Hiwonder TTL bus with LX-series servos on it, served on a pseudo-terminal.

Each ``EmuServo`` follows the protocol's semantics: MOVE_TIME_WRITE ramps linearly from where
it is to the target over the time given (clamped to its angle limits); ANGLE_OFFSET_ADJUST (17)
shifts commands and reads at once and is volatile, ANGLE_OFFSET_WRITE (18) persists it; offsets
are signed bytes; POS_READ is a signed 16-bit count; load / unload, voltage, temperature, the
error flags. Faults from the seed: ``EmuServo.stall()`` (the trip: torque off, the joint sags
under gravity, stalled-rotor flag, until a load command) and ``latched = True`` (commands and
load ignored while the position still reads: only a power cycle would clear it).

``BusFaults`` injects line trouble into the replies: ``bad_checksum`` / ``drop`` / ``extra``
(counts of replies to spoil), ``garbage`` (bytes sent once before the next reply), ``echo``
(the adapter echoes every byte it sends, as some one-wire adapters do), ``silent`` (nobody
answers). ``frames`` records every valid request.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from hw.drivers.hiwonder_protocol import (BROADCAST, ERR_STALLED, Cmd, Frame, FrameParser, encode, from_i8,
                                          i8, u16)
from hw.emulators.pty_port import PtyDevice


@dataclass
class EmuServo:
    position: float = 500.0
    """Physical position, counts (what the horn is at, before the offset)."""
    offset: int = 0
    saved_offset: int = 0
    limits: tuple[int, int] = (0, 1000)
    vin_mv: int = 12000
    temperature_c: int = 36
    loaded: bool = True
    latched: bool = False
    errors: int = 0
    sag_counts_per_s: float = 0.0
    """While unloaded the joint drifts this fast (gravity), counts/s."""
    _start: float = 500.0
    _target: float = 500.0
    _t0: float = 0.0
    _duration: float = 0.0
    _t_last: float = field(default_factory=time.monotonic)

    def advance(self, now: float) -> None:
        if self.loaded:
            if self._duration > 0 and now < self._t0 + self._duration:
                self.position = self._start + (self._target - self._start) * (now - self._t0) / self._duration
            else:
                self.position = self._target
        else:
            self.position -= self.sag_counts_per_s * (now - self._t_last)
        self._t_last = now

    def move(self, counts: int, duration_ms: int, now: float) -> None:
        self.advance(now)
        if self.latched or not self.loaded:
            return
        lo, hi = self.limits
        self._start = self.position
        self._target = float(min(max(counts, lo), hi) + self.offset)
        self._t0, self._duration = now, duration_ms / 1000.0

    def set_load(self, loaded: bool, now: float) -> None:
        self.advance(now)
        if self.latched:
            return
        self.loaded = loaded
        self._start = self._target = self.position
        self._duration = 0.0
        if loaded:
            self.errors &= ~ERR_STALLED

    def stall(self, sag_counts_per_s: float = 50.0) -> None:
        """Seed: the shoulder_lift trips against gravity: unloads, flags a stall, sags."""
        self.set_load(False, time.monotonic())
        self.sag_counts_per_s = sag_counts_per_s
        self.errors |= ERR_STALLED

    def read_position(self) -> int:
        return int(round(self.position)) - self.offset

    def place(self, counts: float) -> None:
        """Put the horn at ``counts`` (physical, before the offset), at rest there."""
        self.position = self._start = self._target = float(counts)
        self._duration = 0.0


@dataclass
class BusFaults:
    bad_checksum: int = 0
    drop: int = 0
    extra: int = 0
    echo: bool = False
    silent: bool = False
    garbage: bytes = b""
    """Sent once, right before the next reply (line noise, a stray frame)."""


class HiwonderBusEmulator(PtyDevice):
    def __init__(self, servos: dict[int, EmuServo] | None = None, baud: int | None = None):
        super().__init__(baud)
        self.servos = servos if servos is not None else {i: EmuServo() for i in range(2, 7)}
        self.faults = BusFaults()
        self.parser = FrameParser()
        self.frames: list[Frame] = []
        self.lock = threading.Lock()

    def servo(self, servo_id: int) -> EmuServo:
        return self.servos[servo_id]

    def on_bytes(self, data: bytes) -> None:
        if self.faults.echo:
            self.send(data)
        for frame in self.parser.feed(data):
            with self.lock:
                self.frames.append(frame)
                reply = self.handle(frame, time.monotonic())
            if reply is not None and not self.faults.silent:
                self._reply(reply, len(frame.params) + 6)

    def _reply(self, reply: bytes, request_len: int) -> None:
        f = self.faults
        if f.bad_checksum:
            f.bad_checksum -= 1
            reply = reply[:-1] + bytes([reply[-1] ^ 0x5A])
        if f.drop:
            f.drop -= 1
            reply = reply[:3] + reply[4:]
        if f.extra:
            f.extra -= 1
            reply = b"\x55\x00\xAA" + reply
        if f.garbage:
            reply, f.garbage = f.garbage + reply, b""
        if self.baud:
            time.sleep(self.wire_time(request_len + len(reply)))
        self.send(reply)

    def handle(self, frame: Frame, now: float) -> bytes | None:
        targets = list(self.servos) if frame.servo_id == BROADCAST else [frame.servo_id]
        reply = None
        for sid in targets:
            s = self.servos.get(sid)
            if s is None:
                continue
            s.advance(now)
            reply = self._command(sid, s, frame.cmd, frame.params, now)
        return reply if frame.servo_id != BROADCAST or frame.cmd == Cmd.ID_READ else None

    def _command(self, sid: int, s: EmuServo, cmd: int, p: bytes, now: float) -> bytes | None:
        def ok(params: bytes) -> bytes:
            return encode(sid, cmd, params)

        if cmd == Cmd.MOVE_TIME_WRITE and len(p) == 4:
            s.move(int.from_bytes(p[0:2], "little"), int.from_bytes(p[2:4], "little"), now)
        elif cmd == Cmd.MOVE_TIME_READ:
            return ok(u16(round(s._target) - s.offset) + u16(round(s._duration * 1000)))
        elif cmd == Cmd.MOVE_STOP:
            s._start = s._target = s.position
            s._duration = 0.0
        elif cmd == Cmd.ID_READ:
            return ok(bytes([sid]))
        elif cmd == Cmd.ANGLE_OFFSET_ADJUST and len(p) == 1:
            s.offset = max(-125, min(125, from_i8(p[0])))
        elif cmd == Cmd.ANGLE_OFFSET_WRITE:
            s.saved_offset = s.offset
        elif cmd == Cmd.ANGLE_OFFSET_READ:
            return ok(bytes([i8(s.offset)]))
        elif cmd == Cmd.ANGLE_LIMIT_WRITE and len(p) == 4:
            lo, hi = int.from_bytes(p[0:2], "little"), int.from_bytes(p[2:4], "little")
            if 0 <= lo < hi <= 1000:
                s.limits = (lo, hi)
        elif cmd == Cmd.ANGLE_LIMIT_READ:
            return ok(u16(s.limits[0]) + u16(s.limits[1]))
        elif cmd == Cmd.VIN_READ:
            return ok(u16(s.vin_mv))
        elif cmd == Cmd.TEMP_READ:
            return ok(bytes([s.temperature_c & 0xFF]))
        elif cmd == Cmd.POS_READ:
            return ok(u16(s.read_position()))
        elif cmd == Cmd.LOAD_OR_UNLOAD_WRITE and len(p) == 1:
            s.set_load(bool(p[0]), now)
        elif cmd == Cmd.LOAD_OR_UNLOAD_READ:
            return ok(bytes([int(s.loaded)]))
        elif cmd == Cmd.LED_ERROR_READ:
            return ok(bytes([s.errors]))
        return None
