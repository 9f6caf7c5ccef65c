"""The Hiwonder / LewanSoul bus-servo byte protocol (LX-16A family): frames and a stream parser.

Frame (reference): ``55 55 ID LEN CMD P1..Pn CHK`` with LEN = n + 3 and
CHK = ~(ID + LEN + CMD + sum(P)) & 0xFF; ID 0..253, 254 broadcast. Worked examples:
move id 1 to 500 in 1000 ms is ``55 55 01 07 01 F4 01 E8 03 16``; POS_READ id 1 is
``55 55 01 03 1C DF``; its reply at 500 is ``55 55 01 05 1C F4 01 E8``.

``FrameParser`` is shared by the driver and the bus emulator. It takes bytes as they come and
returns whole frames; on a bad length or checksum it drops one byte and hunts for the next
``55 55``, so any garbage (noise, a half frame, an echo collision) costs at most the frames it
overlaps and never raises.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass

HEADER = b"\x55\x55"
BROADCAST = 254
MAX_PARAMS = 7  # longest frame body the protocol defines (writes carry at most 4 bytes)


class Cmd(enum.IntEnum):
    MOVE_TIME_WRITE = 1
    MOVE_TIME_READ = 2
    MOVE_TIME_WAIT_WRITE = 7
    MOVE_START = 11
    MOVE_STOP = 12
    ID_WRITE = 13
    ID_READ = 14
    ANGLE_OFFSET_ADJUST = 17
    ANGLE_OFFSET_WRITE = 18
    ANGLE_OFFSET_READ = 19
    ANGLE_LIMIT_WRITE = 20
    ANGLE_LIMIT_READ = 21
    VIN_LIMIT_WRITE = 22
    VIN_LIMIT_READ = 23
    TEMP_MAX_LIMIT_WRITE = 24
    TEMP_MAX_LIMIT_READ = 25
    TEMP_READ = 26
    VIN_READ = 27
    POS_READ = 28
    OR_MOTOR_MODE_WRITE = 29
    OR_MOTOR_MODE_READ = 30
    LOAD_OR_UNLOAD_WRITE = 31
    LOAD_OR_UNLOAD_READ = 32
    LED_CTRL_WRITE = 33
    LED_CTRL_READ = 34
    LED_ERROR_WRITE = 35
    LED_ERROR_READ = 36


#: Parameter bytes in the servo's reply to each read command.
REPLY_PARAMS: dict[int, int] = {
    Cmd.MOVE_TIME_READ: 4, Cmd.ID_READ: 1, Cmd.ANGLE_OFFSET_READ: 1, Cmd.ANGLE_LIMIT_READ: 4,
    Cmd.VIN_LIMIT_READ: 4, Cmd.TEMP_MAX_LIMIT_READ: 1, Cmd.TEMP_READ: 1, Cmd.VIN_READ: 2,
    Cmd.POS_READ: 2, Cmd.OR_MOTOR_MODE_READ: 4, Cmd.LOAD_OR_UNLOAD_READ: 1, Cmd.LED_CTRL_READ: 1,
    Cmd.LED_ERROR_READ: 1,
}

#: LED_ERROR_READ bits.
ERR_OVER_TEMPERATURE, ERR_OVER_VOLTAGE, ERR_STALLED = 1, 2, 4


def checksum(body: bytes) -> int:
    """``body`` = ID, LEN, CMD, params."""
    return ~sum(body) & 0xFF


def encode(servo_id: int, cmd: int, params: bytes = b"") -> bytes:
    if not 0 <= servo_id <= BROADCAST:
        raise ValueError(f"servo id {servo_id} out of 0..254")
    body = bytes([servo_id, len(params) + 3, int(cmd)]) + bytes(params)
    return HEADER + body + bytes([checksum(body)])


def u16(v: int) -> bytes:
    return int(v & 0xFFFF).to_bytes(2, "little")


def i8(v: int) -> int:
    """A signed offset as its byte: two's complement (+256, not the community driver's +255)."""
    return int(v) & 0xFF


def from_i8(b: int) -> int:
    return b - 256 if b > 127 else b


@dataclass(frozen=True)
class Frame:
    servo_id: int
    cmd: int
    params: bytes

    def encode(self) -> bytes:
        return encode(self.servo_id, self.cmd, self.params)


class FrameParser:
    def __init__(self) -> None:
        self.buf = bytearray()
        self.bad_frames = 0
        self.skipped = 0

    def feed(self, data: bytes) -> list[Frame]:
        self.buf += data
        out: list[Frame] = []
        buf = self.buf
        while True:
            i = buf.find(HEADER)
            if i < 0:
                keep = 1 if buf[-1:] == b"\x55" else 0
                self.skipped += len(buf) - keep
                del buf[:len(buf) - keep]
                return out
            if i:
                self.skipped += i
                del buf[:i]
            if len(buf) < 4:
                return out
            length = buf[3]
            if not 3 <= length <= MAX_PARAMS + 3:
                self.bad_frames += 1
                del buf[:1]
                continue
            if len(buf) < length + 3:
                return out
            body = bytes(buf[2:length + 2])
            if checksum(body) != buf[length + 2]:
                self.bad_frames += 1
                del buf[:1]
                continue
            out.append(Frame(body[0], body[2], body[3:]))
            del buf[:length + 3]
