"""The Slamtec RPLidar byte protocol (C1, Standard scan mode): requests, descriptors, nodes.

Reference facts: requests are ``A5 cmd`` or ``A5 cmd len payload chk`` (chk = XOR of every
preceding byte); a response starts with a 7-byte descriptor ``A5 5A`` + u32 LE (low 30 bits
length, top 2 bits mode: 0 single, 1 multiple) + type. SCAN answers ``A5 5A 05 00 00 40 81``
and then streams 5-byte nodes: b0 = quality<<2 | !S<<1 | S (S: first node of a revolution),
b1 bit 0 = check bit (1), angle_q6 = b2<<7 | b1>>1 (deg = q6 / 64), distance_q2 = b3 | b4<<8
(mm = q2 / 4, 0 = no return).

``ScanParser`` is vectorised with numpy (the C1 streams ~5000 nodes/s; the parser must not be
what limits a 4-core A55): every byte offset gets a validity bit at once (S != !S, check bit
set, angle < 360 deg), runs of nodes are taken at stride 5 in one slice, and after a bad node
the parser resynchronises on the next offset where three consecutive nodes are valid (one
valid-looking node is a 1-in-8 accident in random bytes, three in a row 1-in-500). Complete
revolutions come out as (angles, ranges) in REP-103 (counter-clockwise, radians in [0, 2 pi),
sorted) and metres, ``inf`` where there was no return or the range is outside the sensor's.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass

import numpy as np

SYNC, SYNC2 = 0xA5, 0x5A
NODE = 5
SCAN_DESCRIPTOR = bytes.fromhex("A5 5A 05 00 00 40 81")
INFO_DESCRIPTOR = bytes.fromhex("A5 5A 14 00 00 00 04")
HEALTH_DESCRIPTOR = bytes.fromhex("A5 5A 03 00 00 00 06")
RESYNC_RUN = 3
TWO_PI = np.float32(2 * np.pi)


class Req(enum.IntEnum):
    STOP = 0x25
    RESET = 0x40
    SCAN = 0x20
    FORCE_SCAN = 0x21
    GET_INFO = 0x50
    GET_HEALTH = 0x52
    GET_SAMPLERATE = 0x59
    EXPRESS_SCAN = 0x82
    GET_LIDAR_CONF = 0x84


def request(cmd: int, payload: bytes | None = None) -> bytes:
    if payload is None:
        return bytes([SYNC, cmd])
    body = bytes([SYNC, cmd, len(payload)]) + payload
    chk = 0
    for b in body:
        chk ^= b
    return body + bytes([chk])


@dataclass(frozen=True)
class Descriptor:
    length: int
    mode: int
    dtype: int


def descriptor(length: int, mode: int, dtype: int) -> bytes:
    return bytes([SYNC, SYNC2]) + (length & 0x3FFFFFFF | mode << 30).to_bytes(4, "little") + bytes([dtype])


def parse_descriptor(b: bytes) -> Descriptor:
    if len(b) != 7 or b[0] != SYNC or b[1] != SYNC2:
        raise ValueError(f"not a response descriptor: {b.hex(' ')}")
    word = int.from_bytes(b[2:6], "little")
    return Descriptor(word & 0x3FFFFFFF, word >> 30, b[6])


@dataclass(frozen=True)
class Info:
    model: int
    firmware: str
    hardware: int
    serial: str


def parse_info(b: bytes) -> Info:
    if len(b) != 20:
        raise ValueError(f"GET_INFO payload must be 20 bytes, got {len(b)}")
    return Info(b[0], f"{b[2]}.{b[1]:02d}", b[3], b[4:20].hex().upper())


HEALTH = {0: "good", 1: "warning", 2: "error"}


def parse_health(b: bytes) -> tuple[str, int]:
    if len(b) != 3:
        raise ValueError(f"GET_HEALTH payload must be 3 bytes, got {len(b)}")
    return HEALTH.get(b[0], f"unknown ({b[0]})"), int.from_bytes(b[1:3], "little")


def encode_nodes(angle_deg, dist_mm, quality=47, start=None) -> bytes:
    """Nodes as the lidar sends them (vectorised; the emulator and the tests use this)."""
    angle_deg = np.asarray(angle_deg, dtype=np.float64)
    n = angle_deg.size
    s = np.zeros(n, dtype=np.uint8) if start is None else np.asarray(start, dtype=np.uint8)
    q6 = np.round(np.mod(angle_deg, 360.0) * 64).astype(np.int64) % (360 * 64)
    q2 = np.clip(np.round(np.asarray(dist_mm, dtype=np.float64) * 4), 0, 0xFFFF).astype(np.int64)
    out = np.empty((n, NODE), dtype=np.uint8)
    out[:, 0] = (np.broadcast_to(quality, n).astype(np.int64) << 2 & 0xFC) | (1 - s) << 1 | s
    out[:, 1] = (q6 & 0x7F) << 1 | 1
    out[:, 2] = q6 >> 7
    out[:, 3] = q2 & 0xFF
    out[:, 4] = q2 >> 8
    return out.tobytes()


class ScanParser:
    def __init__(self, range_min: float = 0.05, range_max: float = 12.0, max_points: int = 4096):
        self.range_min, self.range_max = range_min, range_max
        self.max_points = max_points
        self._tail = np.zeros(0, dtype=np.uint8)
        self._synced = False
        self._rev_q6: list[np.ndarray] = []
        self._rev_q2: list[np.ndarray] = []
        self._rev_started = False
        self.nodes = 0
        self.resyncs = 0
        self.revolutions = 0

    def feed(self, data: bytes) -> list[tuple[np.ndarray, np.ndarray]]:
        a = np.concatenate((self._tail, np.frombuffer(data, dtype=np.uint8)))
        n = a.size
        if n < NODE:
            self._tail = a
            return []
        m = n - NODE + 1  # offsets where a whole node fits
        b0, b1, b2 = a[:m], a[1:m + 1], a[2:m + 2]
        q6 = b2.astype(np.int32) << 7 | b1 >> 1
        ok = (((b0 ^ (b0 >> 1)) & 1) & b1 & 1).astype(bool) & (q6 < 360 * 64)
        pos, runs = 0, []
        while pos + NODE <= n:
            if not self._synced:
                if m - pos <= NODE * (RESYNC_RUN - 1):
                    break
                span = m - pos - NODE * (RESYNC_RUN - 1)
                cand = ok[pos:pos + span].copy()
                for k in range(1, RESYNC_RUN):
                    cand &= ok[pos + NODE * k:pos + NODE * k + span]
                hits = np.flatnonzero(cand)
                if hits.size == 0:
                    pos += span
                    break
                pos += int(hits[0])
                self._synced = True
            idx = np.arange(pos, m, NODE)
            bad = np.flatnonzero(~ok[idx])
            good = idx if bad.size == 0 else idx[:bad[0]]
            if good.size:
                runs.append(good)
                pos = int(good[-1]) + NODE
            if bad.size:
                self._synced = False
                self.resyncs += 1
                pos = int(idx[bad[0]]) + 1
            elif pos + NODE > n or not good.size:
                break
        self._tail = a[pos:].copy()
        if not runs:
            return []
        starts = np.concatenate(runs)
        self.nodes += starts.size
        q2 = a[starts + 3].astype(np.int32) | a[starts + 4].astype(np.int32) << 8
        return self._revolutions(a[starts] & 1, q6[starts], q2)

    def _revolutions(self, s: np.ndarray, q6: np.ndarray, q2: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        out = []
        cuts = np.flatnonzero(s)
        prev = 0
        for c in cuts:
            self._append(q6[prev:c], q2[prev:c])
            if self._rev_started and self._rev_q6:
                out.append(self._finish())
            self._rev_q6, self._rev_q2 = [], []
            self._rev_started = True
            prev = c
        self._append(q6[prev:], q2[prev:])
        return out

    def _append(self, q6: np.ndarray, q2: np.ndarray) -> None:
        if q6.size and self._rev_started and sum(x.size for x in self._rev_q6) < self.max_points:
            self._rev_q6.append(q6)
            self._rev_q2.append(q2)

    def _finish(self) -> tuple[np.ndarray, np.ndarray]:
        q6 = np.concatenate(self._rev_q6)
        q2 = np.concatenate(self._rev_q2)
        self.revolutions += 1
        angles = np.mod(TWO_PI - q6.astype(np.float32) * np.float32(np.pi / (180 * 64)), TWO_PI)
        ranges = q2.astype(np.float32) * np.float32(0.00025)
        ranges[(ranges < self.range_min) | (ranges > self.range_max)] = np.inf
        order = np.argsort(angles, kind="stable")
        return angles[order], ranges[order]
