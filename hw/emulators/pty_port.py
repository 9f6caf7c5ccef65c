"""A serial device served on a real pseudo-terminal, from a thread.

``os.openpty()`` gives a master and a slave end; the slave is a real tty that pyserial opens by
path (``PtyDevice.path``) exactly like /dev/ttyUSB0, so the drivers' real serial code runs. The
emulator reads requests from the master and writes replies to it. Everything has a timeout:
the thread polls with ``select`` every 20 ms, so ``stop()`` returns promptly, and the master is
non-blocking (when the reader falls behind, output is dropped like a UART overrun instead of
blocking the thread). Use as a context manager so tests always stop the thread.
"""
from __future__ import annotations

import os
import select
import threading
import time
import tty


class PtyDevice:
    def __init__(self, baud: int | None = None):
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        os.set_blocking(self.master, False)
        self.path = os.ttyname(self.slave)
        self.baud = baud
        """If set, replies are delayed by their wire time at this baud (10 bits a byte)."""
        self.dropped_out = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=type(self).__name__, daemon=True)

    # --- subclass hooks -----------------------------------------------------------------
    def on_bytes(self, data: bytes) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def on_idle(self) -> None:
        """Called every loop (~20 ms or sooner); streaming devices write here."""

    # --- plumbing -----------------------------------------------------------------------
    def start(self) -> "PtyDevice":
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        for fd in (self.master, self.slave):
            try:
                os.close(fd)
            except OSError:
                pass

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    def wire_time(self, nbytes: int) -> float:
        return nbytes * 10.0 / self.baud if self.baud else 0.0

    def send(self, data: bytes) -> int:
        """Write to the host; returns bytes written (the rest dropped if the tty is full)."""
        try:
            n = os.write(self.master, data)
        except (BlockingIOError, OSError):
            n = 0
        self.dropped_out += len(data) - n
        return n

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select([self.master], [], [], 0.02)
            except (OSError, ValueError):
                return
            if ready:
                try:
                    data = os.read(self.master, 4096)
                except BlockingIOError:
                    data = b""
                except OSError:
                    time.sleep(0.005)  # EIO while no one holds the slave open
                    data = b""
                if data:
                    self.on_bytes(data)
            self.on_idle()
