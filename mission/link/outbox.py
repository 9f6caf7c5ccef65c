"""The outgoing side of the link: a bounded queue and one sender thread.

The control loop only appends (``post``): encoding (JSON, zlib) and the Zenoh ``put`` happen on
the sender thread, and when the queue is full the oldest message is dropped, never the caller
blocked. So a slow or absent network costs the robot nothing but stale telemetry.
"""
from __future__ import annotations

import collections
import logging
import threading
from typing import Callable

log = logging.getLogger(__name__)

Put = Callable[[str, bytes], None]


class Outbox:
    def __init__(self, put: Put, size: int):
        self.put = put
        self._queue: collections.deque[tuple[str, Callable[[], bytes | None]]] = collections.deque(maxlen=size)
        self._wake = threading.Condition()
        self._closed = False
        self.dropped = 0
        self.sent = 0
        self.bytes: collections.Counter[str] = collections.Counter()
        """Bytes put on the link per key since start (payloads, not transport overhead)."""
        self._thread = threading.Thread(target=self._run, name="link-outbox", daemon=True)
        self._thread.start()

    def post(self, key: str, payload: Callable[[], bytes | None]) -> None:
        """Queue ``payload()`` (called on the sender thread) for ``key``; never blocks."""
        with self._wake:
            if len(self._queue) == self._queue.maxlen:
                self.dropped += 1
            self._queue.append((key, payload))
            self._wake.notify()

    def _run(self) -> None:
        failing = False
        while True:
            with self._wake:
                while not self._queue and not self._closed:
                    self._wake.wait()
                if self._closed and not self._queue:
                    return
                key, payload = self._queue.popleft()
            try:
                data = payload()
                if data is None:
                    continue
                self.put(key, data)
                self.sent += 1
                self.bytes[key] += len(data)
                failing = False
            except Exception as exc:  # the link must never take the robot down
                if not failing:
                    log.warning("link: could not send %s: %s", key, exc)
                    failing = True

    def close(self, timeout: float = 1.0) -> None:
        with self._wake:
            self._closed = True
            self._wake.notify()
        self._thread.join(timeout)
