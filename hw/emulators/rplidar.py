"""An RPLidar C1 served on a pseudo-terminal: info, health, and a Standard-mode scan stream.

Answers GET_INFO (model 0x41, the C1's byte per the reference) and GET_HEALTH; SCAN answers the
descriptor after ``spinup_s`` of silence (the reference's ~2 s motor spin-up) and then streams
``points`` nodes per revolution at ``rate_hz``, paced in real time, the first node of each
revolution flagged S. The scene is a function angle (deg, clockwise as the lidar measures) ->
distance (mm); the default is a 4 m x 3 m box room centred on the sensor. STOP ends the stream;
RESET ends it and prints an ASCII banner (as the C1 is said to; unverified).

Faults: ``inject(b)`` splices bytes into the stream at the next write (garbage, a stray
banner), ``drop(n)`` loses the next n bytes, ``silent`` stops all output.
"""
from __future__ import annotations

import math
import time
from typing import Callable

import numpy as np

from hw.drivers.rplidar_protocol import (HEALTH_DESCRIPTOR, INFO_DESCRIPTOR, NODE, SCAN_DESCRIPTOR, SYNC, Req,
                                         encode_nodes)
from hw.emulators.pty_port import PtyDevice

BANNER = b"RP S/N: 0000000000000000\r\nVersion: C1 emulated\r\n"


def box_room(half_x_mm: float = 2000.0, half_y_mm: float = 1500.0) -> Callable[[np.ndarray], np.ndarray]:
    def dist(angle_deg: np.ndarray) -> np.ndarray:
        th = np.radians(angle_deg)
        c, s = np.abs(np.cos(th)), np.abs(np.sin(th))
        with np.errstate(divide="ignore"):
            return np.minimum(np.where(c > 1e-9, half_x_mm / c, np.inf), np.where(s > 1e-9, half_y_mm / s, np.inf))
    return dist


class RplidarEmulator(PtyDevice):
    def __init__(self, *, points: int = 500, rate_hz: float = 10.0, spinup_s: float = 0.0,
                 scene: Callable[[np.ndarray], np.ndarray] | None = None, model: int = 0x41, health: int = 0):
        super().__init__()
        self.points, self.rate_hz, self.spinup_s = points, rate_hz, spinup_s
        self.model, self.health = model, health
        angles = np.arange(points) * 360.0 / points
        self.scene_mm = (scene or box_room())(angles)
        start = np.zeros(points, dtype=np.uint8)
        start[0] = 1
        self.revolution = encode_nodes(angles, self.scene_mm, 47, start)
        self.requests: list[int] = []
        self.scanning = False
        self.silent = False
        self._t_scan = 0.0
        self._sent_nodes = 0
        self._described = False
        self._inject = b""
        self._drop = 0
        self._pending = b""

    def inject(self, data: bytes) -> None:
        self._inject += data

    def drop(self, n: int) -> None:
        self._drop += n

    def on_bytes(self, data: bytes) -> None:
        data = self._pending + data
        i = 0
        while i < len(data):
            if data[i] != SYNC:
                i += 1
                continue
            if i + 1 >= len(data):
                break
            cmd = data[i + 1]
            if cmd & 0x80:  # request with payload: A5 cmd len payload chk
                if i + 2 >= len(data) or i + 4 + data[i + 2] > len(data):
                    break
                i += 4 + data[i + 2]
            else:
                i += 2
            self._request(cmd)
        self._pending = data[i:]

    def _request(self, cmd: int) -> None:
        self.requests.append(cmd)
        if cmd == Req.STOP:
            self.scanning = False
        elif cmd == Req.RESET:
            self.scanning = False
            self._out(BANNER)
        elif cmd == Req.GET_INFO:
            serial = bytes(range(0x10, 0x20))
            self._out(INFO_DESCRIPTOR + bytes([self.model, 1, 1, 18]) + serial)
        elif cmd == Req.GET_HEALTH:
            self._out(HEALTH_DESCRIPTOR + bytes([self.health, 0, 0]))
        elif cmd in (Req.SCAN, Req.FORCE_SCAN):
            self.scanning, self._described = True, False
            self._t_scan, self._sent_nodes = time.monotonic(), 0

    def _out(self, data: bytes) -> None:
        if self.silent:
            return
        if self._inject:
            data, self._inject = self._inject + data, b""
        if self._drop:
            k = min(self._drop, len(data))
            data, self._drop = data[k:], self._drop - k
        self.send(data)

    def on_idle(self) -> None:
        if not self.scanning:
            return
        t = time.monotonic() - self._t_scan - self.spinup_s
        if t < 0:
            return
        if not self._described:
            self._out(SCAN_DESCRIPTOR)
            self._described = True
        due = int(math.floor(t * self.rate_hz * self.points))
        n = min(due - self._sent_nodes, 4 * self.points)
        if n <= 0:
            return
        k = self._sent_nodes % self.points
        reps = (k + n) // self.points + 1
        stream = self.revolution * reps
        self._out(stream[k * NODE:(k + n) * NODE])
        self._sent_nodes += n
