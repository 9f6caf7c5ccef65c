"""An operator at the real console, as a process of its own, for ``runtime.cpu_serve``.

``python -m lupin.bench.operator ENDPOINT ROBOT TOKEN HZ`` runs the console app itself
(``tui.app.make_app`` over a ``LinkClient``, as ``lupin console --connect`` does) headless at
160 x 48, and its autopilot presses the console's own keys: ``m`` once the link is up (the
default patrol, every pot of the world), then ``f`` (the front camera) every ``1 / HZ`` seconds
of wall time, until SIGTERM. Then it prints one JSON line: the presses, the snapshots asked,
answered (JPEG bytes) and not, and its own CPU seconds.

A process of its own because on the robot the console runs on the operator's laptop: its CPU
(telemetry folded, panels redrawn at 10 Hz, JPEGs decoded into half-blocks) must never be
billed to the runtime being metered. The camera panel has no stream: a snapshot is a key press,
so the rate is the operator's; the benchmark presses at the front camera's producer cap
(``perception.rates.front``), the most a console can make the robot capture and encode.
"""
from __future__ import annotations

import asyncio
import json
import resource
import signal
import sys
import threading
import time

CONNECT_S = 30.0
"""Wall seconds the console waits for the link before pressing ``m`` anyway (counted)."""


class CountingLink:
    """The link client as the console's ``commands``, counting every snapshot it is asked for."""

    def __init__(self, client):
        self.client = client
        self.asked = 0
        self.answered = 0
        self.jpeg_bytes: list[int] = []
        self.send, self.history, self.view = client.send, client.history, client.view

    def snapshot(self, camera: str) -> bytes | None:
        self.asked += 1
        jpeg = self.client.snapshot(camera)
        if jpeg is not None:
            self.answered += 1
            self.jpeg_bytes.append(len(jpeg))
        return jpeg


def main(endpoint: str, robot: str, token: str, hz: float) -> dict:
    from mission.link.client import LinkClient
    from tui.app import make_app

    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    client = LinkClient(endpoint, robot, clock=time.monotonic, token=token)
    link = CountingLink(client)
    tally = {"connected": False, "presses": 0}

    async def operator(pilot) -> None:
        end = time.monotonic() + CONNECT_S
        while not link.view().connected and time.monotonic() < end and not stop.is_set():
            await asyncio.sleep(0.1)
        tally["connected"] = link.view().connected
        await pilot.press("m")
        while not stop.is_set():
            await pilot.press("f")
            tally["presses"] += 1
            await asyncio.sleep(1.0 / hz)
        pilot.app.exit()

    try:
        make_app(link.view, link).run(headless=True, size=(160, 48), auto_pilot=operator)
    finally:
        client.close()
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return {**tally, "asked": link.asked, "answered": link.answered, "jpeg_bytes": link.jpeg_bytes,
            "cpu_s": round(usage.ru_utime + usage.ru_stime, 2)}


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]))), flush=True)
