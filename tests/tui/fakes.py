"""Hand-made views, a recording ``Commands`` and a Pilot driver for the console's tests."""
from __future__ import annotations

import asyncio
import threading
from typing import Callable

import cv2
import numpy as np

from mission.link.view import GridView, PotView, RobotView
from tui.app import ConsoleApp, make_app

SIZE = (160, 48)


class Recorder:
    """A ``Commands`` that records what it was sent. ``refuse`` maps a command to the reason
    it is refused (or to an exception it raises); with ``hold`` (an Event) every send waits for
    it, as over a slow link; ``entered`` is set by the first send."""

    def __init__(self, refuse: dict[str, str | Exception] | None = None, hold: threading.Event | None = None):
        self.sent: list[tuple[str, dict]] = []
        self.snapshots: list[str] = []
        self.refuse = refuse or {}
        self.hold = hold
        self.entered = threading.Event()
        self._lock = threading.Lock()

    def send(self, command: str, /, **args) -> str | None:
        with self._lock:
            self.sent.append((command, args))
        self.entered.set()
        if self.hold is not None:
            self.hold.wait(10)
        refusal = self.refuse.get(command)
        if isinstance(refusal, Exception):
            raise refusal
        return refusal

    def snapshot(self, camera: str) -> bytes | None:
        self.snapshots.append(camera)
        img = np.zeros((48, 64, 3), np.uint8)
        img[:, :32] = (0, 0, 255)  # red left half (BGR)
        return cv2.imencode(".jpg", img)[1].tobytes()


def idle_view() -> RobotView:
    return RobotView(robot="mirte", t=3.0, connected=True, battery_voltage=12.6, battery_percentage=38.5,
                     controllers={"pid_wheels_controller": "active", "mirte_base_controller": "active"})


def grid(n: int = 120) -> GridView:
    """A walled square room, 1 m of unknown around it (cells 0.05 m, origin -1, -1)."""
    g = np.full((n, n), -1, np.int8)
    g[10:n - 10, 10:n - 10] = 0
    g[10, 10:n - 10] = g[n - 11, 10:n - 10] = 100
    g[10:n - 10, 10] = g[10:n - 10, n - 11] = 100
    return GridView(g, 0.05, -1.0, -1.0)


def patrolling_view() -> RobotView:
    v = idle_view()
    v.t, v.pose, v.mux_source, v.nav_state = 41.2, (2.0, 0.5, 0.3), "auto", "following"
    v.mission_state, v.mission_name, v.mission_step = "running", "default-patrol", "approach P03"
    v.grid, v.plan, v.goal = grid(), np.array([[2.0, 0.5], [3.0, 0.8], [3.5, 1.5]]), (3.5, 1.5, 1.57)
    c = np.zeros((120, 120), np.int8)
    c[40:60, 40:60] = 80
    v.costmap = GridView(c, 0.05, -1.0, -1.0)
    v.pots = [PotView("P01", 1.0, 1.0, "inspected", 1, "red", 1), PotView("P02", 2.0, 1.0, "inspected", 2, "white", 2, ["bug"]),
              PotView("P03", 3.0, 1.0, "active"), PotView("P04", 4.0, 1.0, "pending"),
              PotView("P05", 1.0, 3.0, "failed", anomalies=["unreachable"]), PotView("P06", 2.0, 3.0, "skipped")]
    v.tree = ("{-} Lupin patrol [*]\n    {-} patrol [*]\n        -^- P01 [✓]\n        -^- P02 [✓]\n"
              "        -^- P05 [✕]\n        -^- P03 [*]\n            --> approach P03 [*]\n        -^- P04 [-]")
    v.log = ["  40.0 I patrol default-patrol started (6 pots)"]
    return v


def estopped_view() -> RobotView:
    v = patrolling_view()
    v.estop_engaged, v.estop_latched, v.mux_source, v.mission_state, v.mission_step = True, True, "estop", "estop", "e-stop engaged"
    return v


def console(view_source: Callable[[], RobotView], steps, commands: Recorder | None = None, size=SIZE,
            notifications: list | None = None):
    """Run the console over ``view_source`` and play ``steps``: a key name is pressed and then
    every command it started is awaited; a callable ``step(app)`` is called (and awaited if it
    returns a coroutine). Returns (commands, app) once the app has closed."""
    rec = commands if commands is not None else Recorder()

    async def go() -> ConsoleApp:
        app = make_app(view_source, rec)
        if notifications is not None:
            app.notify = lambda message, **kw: notifications.append(message)
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            for step in steps:
                if callable(step):
                    result = step(app)
                    if asyncio.iscoroutine(result):
                        await result
                else:
                    await pilot.press(step)
                await app.workers.wait_for_complete()
                await pilot.pause()
        return app

    app = asyncio.run(go())
    return rec, app
