"""Link benchmarks: the operator link end to end on loopback, against a real-time sim runtime.

``link.estop``: a console's soft e-stop to all-zero wheel duty at the simulated motors, wall
time, while the robot is driven by the console's teleop (each trial: drive 0.5 s, wait a random
part of the 100 ms control beat so every phase is sampled, press, wait, release). Every press
counts: ``attempted`` presses, ``stopped`` the ones whose wheels reached zero duty within
``STOP_WITHIN_S`` (the times are theirs), ``failed`` the others, each printed on stderr and
listed in ``failures``; a trial whose robot was not driving when the press was due is counted
in ``not_driving`` (no press, so no time), never dropped silently.

``link.bytes``: payload bytes per second on the link at idle and while a patrol maps the
greenhouse. ``link.jitter``: the base controller's tick-to-tick wall interval, p95 deviation
from its 100 ms beat, without and with a console attached and reading.
"""
from __future__ import annotations

import asyncio
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from lupin.bench import Sample, benchmark
from mission.jobs.serve import run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.client import LinkClient
from mission.link.server import LinkServer, free_endpoint
from mission.runtime.config import LupinConfig, with_overrides
from sim.world import load_default_world

TOKEN = "bench"
ESTOP_TRIALS = 30
STOP_WITHIN_S = 2.0
"""A press whose wheels are not at zero duty this long after it is a failed press."""


@contextmanager
def live_runtime(config: LupinConfig, token: str | None = TOKEN, **fleet):
    """A real-time sim service and its link server on a thread of their own; ``fleet``
    (``connect=``, ``tls=``): its link joins that router instead of listening."""
    config = with_overrides(config, {"sim": {"realtime": True}})
    with tempfile.TemporaryDirectory() as runs:
        service = start_sim_service(load_default_world(), config, Path(runs), time.perf_counter)
        endpoint = fleet.get("connect") or free_endpoint()
        server = LinkServer(service, config.link, token, None if fleet else endpoint, **fleet)
        stop = threading.Event()
        thread = threading.Thread(target=run_service, args=(service, stop, server.close), daemon=True)
        thread.start()
        try:
            yield service, server, endpoint
        finally:
            stop.set()
            thread.join(30)


def _wait(cond, timeout: float) -> bool:
    end = time.perf_counter() + timeout
    while time.perf_counter() < end:
        if cond():
            return True
        time.sleep(0.002)
    return False


@dataclass
class PressTally:
    """Every e-stop press of a run and what came of it."""

    attempted: int = 0
    not_driving: int = 0
    times_ms: list[float] = field(default_factory=list)
    """Press to zero wheel duty, ms, for the presses that stopped the wheels."""
    failures: list[str] = field(default_factory=list)

    @property
    def stopped(self) -> int:
        return len(self.times_ms)

    def figures(self) -> dict:
        return {"attempted": self.attempted, "stopped": self.stopped, "failed": len(self.failures),
                "not_driving": self.not_driving, "stop_within_s": STOP_WITHIN_S, "failures": self.failures}


def press_trials(trials: int, drive: Callable[[], bool], press: Callable[[], float | None],
                 release: Callable[[], None], warn: Callable[[str], None]) -> PressTally:
    """Run ``trials`` trials: ``drive()`` drives and says whether the wheels are turning;
    ``press()`` presses the e-stop and returns ms to zero wheel duty, or None when the wheels
    did not stop within ``STOP_WITHIN_S`` (a failure, counted and told to ``warn``);
    ``release()`` releases it. No press leaves the tally."""
    tally = PressTally()
    for i in range(trials):
        if not drive():
            tally.not_driving += 1
            warn(f"trial {i + 1}: the wheels were not turning when the press was due; no press")
            continue
        tally.attempted += 1
        try:
            ms = press()
        finally:
            release()
        if ms is None:
            msg = f"trial {i + 1}: the wheels did not stop within {STOP_WITHIN_S:g} s of the press"
            tally.failures.append(msg)
            warn(f"FAILED {msg}")
        else:
            tally.times_ms.append(ms)
    return tally


def _stderr(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def timed_redraws(view, frames: int, step) -> list[float]:
    """Wall ms of each of ``frames`` console redraws (and the pause that paints it) of ``view``
    in a 160 x 48 terminal, ``step(i)`` changing the view before frame i."""
    from tui.app import make_app

    times: list[float] = []

    async def go() -> None:
        app = make_app(lambda: view, NullLink())
        async with app.run_test(size=(160, 48)) as pilot:
            await pilot.pause()
            for i in range(frames):
                step(i)
                t0 = time.perf_counter()
                app.redraw()
                await pilot.pause()
                times.append((time.perf_counter() - t0) * 1000.0)

    asyncio.run(go())
    return times


class NullLink:
    """A link that answers every command at once: the console's redraw alone is timed."""

    def send(self, command, /, **args):
        return None

    def snapshot(self, camera):
        return None


def console_presses(service, console: LinkClient, config: LupinConfig, name: str) -> PressTally:
    """``ESTOP_TRIALS`` trials of ``console``'s soft e-stop on ``service``'s robot, timed to
    all-zero wheel duty at the simulated motors (``press_trials``); ``name`` labels what is told."""
    stopped: list[float] = []
    armed = threading.Event()

    def on_duties(t: float, duties: np.ndarray) -> None:
        if armed.is_set() and not duties.any():
            stopped.append(time.perf_counter())
            armed.clear()

    service.robot.hal.wheels.listeners.append(on_duties)
    rng = np.random.default_rng(0)

    def drive() -> bool:
        end = time.perf_counter() + 0.5
        while time.perf_counter() < end:
            console.send("teleop", vx=0.0, vy=0.0, wz=0.4)
            time.sleep(0.05)
        return bool(service.robot.base.last_duties.any())

    def press() -> float | None:
        time.sleep(rng.uniform(0.0, 1.0 / config.hw.base.control_rate))  # any phase of the control beat
        stopped.clear()
        armed.set()
        t0 = time.perf_counter()
        console.send("estop", engaged=True)
        ok = _wait(lambda: bool(stopped), STOP_WITHIN_S)
        armed.clear()
        return (stopped[0] - t0) * 1000.0 if ok else None

    def release() -> None:
        console.send("estop", engaged=False)
        time.sleep(0.3)

    if not _wait(lambda: console.view().connected, 10):
        _stderr(f"{name}: the console did not connect within 10 s; every press will be tried anyway")
    return press_trials(ESTOP_TRIALS, drive, press, release, lambda msg: _stderr(f"{name}: {msg}"))


@benchmark("link.estop")
def estop(config: LupinConfig) -> Sample:
    with live_runtime(config) as (service, server, endpoint):
        console = LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=TOKEN)
        try:
            tally = console_presses(service, console, config, "link.estop")
        finally:
            console.close()
    return Sample(tally.times_ms, tally.figures())


@benchmark("link.bytes")
def link_bytes(config: LupinConfig) -> Sample:
    window = 10.0
    with live_runtime(config) as (service, server, endpoint):
        console = LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=TOKEN)
        try:
            _wait(lambda: console.view().connected, 10)
            time.sleep(2.0)
            idle = _rate(server, window)
            console.send("mission_start")
            time.sleep(3.0)
            mapping = _rate(server, window)
            by_topic = {k.rsplit("/", 1)[-1]: v for k, v in server.outbox.bytes.items()}
        finally:
            console.close()
    return Sample([idle[1] * 1000.0, mapping[1] * 1000.0], {
        "idle_bps": round(idle[0]), "mapping_bps": round(mapping[0]), "window_s": window,
        "dropped": server.outbox.dropped, "total_bytes_by_topic": by_topic})


def _rate(server: LinkServer, window: float) -> tuple[float, float]:
    b0, t0 = sum(server.outbox.bytes.values()), time.perf_counter()
    time.sleep(window)
    dt = time.perf_counter() - t0
    return (sum(server.outbox.bytes.values()) - b0) / dt, dt


@benchmark("link.jitter")
def jitter(config: LupinConfig) -> Sample:
    window = 10.0
    with live_runtime(config) as (service, server, endpoint):
        ticks: list[float] = []
        service.robot.hal.wheels.listeners.append(lambda t, d: ticks.append(time.perf_counter()))
        time.sleep(2.0)
        ticks.clear()
        time.sleep(window)
        without = _p95_dev(ticks, config)
        consoles = [LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=TOKEN) for _ in range(2)]
        try:
            _wait(lambda: all(c.view().connected for c in consoles), 10)
            ticks.clear()
            end = time.perf_counter() + window
            while time.perf_counter() < end:  # consoles reading at 10 Hz, as the console app does
                for c in consoles:
                    c.view()
                time.sleep(0.1)
            attached = _p95_dev(ticks, config)
        finally:
            for c in consoles:
                c.close()
    return Sample([without, attached], {"without_console_p95_ms": round(without, 2),
                                        "with_console_p95_ms": round(attached, 2), "window_s": window})


def _p95_dev(ticks: list[float], config: LupinConfig) -> float:
    period = 1.0 / config.hw.base.control_rate
    dev = np.abs(np.diff(np.asarray(ticks)) - period) * 1000.0
    return float(np.percentile(dev, 95)) if dev.size else float("nan")


@benchmark("link.redraw")
def redraw(config: LupinConfig) -> Sample:
    """The console's full redraw (every panel from a new view, then Textual's render of the
    screen) with a 400 x 400 map and costmap, a plan, 12 pots and a scan, at 160 x 48."""
    from mission.link.view import GridView, PotView, RobotView

    rng = np.random.default_rng(0)
    occ = np.where(rng.random((400, 400)) < 0.1, 100, 0).astype(np.int8)
    occ[:40] = -1
    view = RobotView(robot="mirte", connected=True, pose=(5.0, 5.0, 0.0), grid=GridView(occ, 0.05, -5.0, -5.0),
                     costmap=GridView((rng.random((400, 400)) * 100).astype(np.int8), 0.05, -5.0, -5.0),
                     plan=np.column_stack([np.linspace(0, 8, 60), np.sin(np.linspace(0, 6, 60))]),
                     pots=[PotView(f"P{i:02d}", 1.0 + i % 4, 1.0 + i // 4, "pending") for i in range(12)],
                     scan=rng.random((250, 2)) * 6.0, tree="\n".join(f"--> step {i} [*]" for i in range(60)),
                     mission_state="running")

    def step(i: int) -> None:
        view.pose = (5.0 + 0.01 * i, 5.0, 0.1 * i)

    times = timed_redraws(view, 60, step)
    ms = float(np.median(times[5:]))
    return Sample(times[5:], {"hz": round(1000.0 / ms, 1), "map_cells": 400 * 400, "terminal": "160x48"})
