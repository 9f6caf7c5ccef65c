"""The Slamtec RPLidar C1 on USB serial: the HAL's Lidar, plus info / health for bring-up.

Start-up is STOP, flush, SCAN, then wait for the scan descriptor for up to ``spinup_s``: the C1
is silent ~2 s while its motor spins up (reference), which is a wait, not a failure. A reader
thread then feeds whatever arrives to the vectorised ``ScanParser`` and keeps the newest whole
revolution; ``latest_scan`` is non-blocking and returns None before the first revolution or
when the newest is older than ``stale_s`` (a dropout). Garbage in the stream costs the frames
it overlaps, never the thread; a vanished port stops the thread and shows as staleness.
``close`` (also on exit, via the backend) sends STOP so the motor does not keep spinning.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Callable

from hw.drivers.hiwonder import open_serial
from hw.drivers.rplidar_protocol import (Descriptor, Info, Req, ScanParser, parse_descriptor, parse_health, parse_info,
                                         request)
from hw.interfaces import DeviceError, LidarScan

log = logging.getLogger(__name__)
SCAN_TYPE, NODE_LEN = 0x81, 5
READ_WINDOW_S = 0.02


class RplidarC1:
    def __init__(self, port, *, timeout_s: float = 0.5, spinup_s: float = 3.0, stale_s: float = 0.5,
                 range_min: float = 0.05, range_max: float = 12.0, clock: Callable[[], float] = time.monotonic):
        self.port, self.timeout_s, self.spinup_s, self.stale_s = port, timeout_s, spinup_s, stale_s
        self.parser = ScanParser(range_min, range_max)
        self.clock = clock
        self._latest: LidarScan | None = None
        self._thread: threading.Thread | None = None
        self._running = threading.Event()
        self._got_scan = threading.Event()
        self.error: str | None = None

    @classmethod
    def open(cls, path: str, baud: int = 460800, **kw) -> "RplidarC1":
        port = open_serial(path, baud, "RPLidar", timeout=0.05)
        try:
            port.dtr = False  # A-series: DTR low runs the motor; the C1 ignores it
        except OSError:
            pass  # no modem lines (a pseudo-terminal, some adapters)
        return cls(port, **kw)

    # --- request / response -------------------------------------------------------------
    def _response(self, cmd: int, timeout: float) -> tuple[Descriptor, bytes]:
        """Send ``cmd`` and read its descriptor; returns it and any bytes read past it."""
        self.port.reset_input_buffer()
        self.port.write(request(cmd))
        self.port.flush()
        buf = bytearray()
        deadline = time.monotonic() + timeout
        while True:
            i = buf.find(b"\xA5\x5A")
            if i >= 0 and len(buf) >= i + 7:
                return parse_descriptor(bytes(buf[i:i + 7])), bytes(buf[i + 7:])
            left = deadline - time.monotonic()
            if left <= 0:
                raise DeviceError(f"RPLidar on {self.port.port}: no reply to {Req(cmd).name} within {timeout:.1f} s")
            self.port.timeout = min(left, 0.1)
            buf += self.port.read(max(1, self.port.in_waiting))

    def _single(self, cmd: int, length: int) -> bytes:
        self._halt_reader()
        desc, rest = self._response(cmd, self.timeout_s)
        if desc.length != length or desc.mode != 0:
            raise DeviceError(f"RPLidar: unexpected descriptor for {Req(cmd).name}: {desc}")
        self.port.timeout = self.timeout_s
        data = rest + self.port.read(max(0, length - len(rest)))
        if len(data) < length:
            raise DeviceError(f"RPLidar: {Req(cmd).name} reply cut short ({len(data)} of {length} bytes)")
        return data[:length]

    def info(self) -> Info:
        return parse_info(self._single(Req.GET_INFO, 20))

    def health(self) -> tuple[str, int]:
        return parse_health(self._single(Req.GET_HEALTH, 3))

    def stop(self) -> None:
        self._halt_reader()
        try:
            self.port.write(request(Req.STOP))
            self.port.flush()
        except OSError:
            pass
        time.sleep(0.002)  # the sensor needs ~1 ms before the next request
        self.port.reset_input_buffer()

    # --- scanning -----------------------------------------------------------------------
    def start(self) -> None:
        """STOP, SCAN, wait out the spin-up for the descriptor, start the reader thread."""
        self.stop()
        desc, rest = self._response(Req.SCAN, self.spinup_s + self.timeout_s)
        if desc.length != NODE_LEN or desc.mode != 1 or desc.dtype != SCAN_TYPE:
            raise DeviceError(f"RPLidar: unexpected SCAN descriptor {desc}")
        self._handle(rest)
        self._running.set()
        self._thread = threading.Thread(target=self._read_loop, name="rplidar", daemon=True)
        self._thread.start()

    def wait_for_scan(self, timeout: float) -> LidarScan | None:
        self._got_scan.wait(timeout)
        return self._latest

    def _handle(self, data: bytes) -> None:
        for angles, ranges in self.parser.feed(data):
            self._latest = LidarScan(self.clock(), angles, ranges)
            self._got_scan.set()

    def _read_loop(self) -> None:
        # Block reads of up to 4 kB that return after READ_WINDOW_S: ~500 B (100 nodes) per
        # parser call at the C1's 25 kB/s, so the numpy work is batched and the latency small.
        self.port.timeout = READ_WINDOW_S
        while self._running.is_set():
            try:
                data = self.port.read(max(4096, self.port.in_waiting))
            except Exception as exc:  # the port vanished (unplugged): stop, show as stale
                self.error = str(exc)
                log.error("RPLidar read failed: %s", exc)
                return
            if data:
                self._handle(data)

    def _halt_reader(self) -> None:
        self._running.clear()
        if self._thread is not None:
            self._thread.join(timeout=1.0)
            self._thread = None

    def latest_scan(self) -> LidarScan | None:
        scan = self._latest
        if scan is None or self.clock() - scan.stamp > self.stale_s:
            return None
        return scan

    def close(self) -> None:
        self.stop()
        self.port.close()
