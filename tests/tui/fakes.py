"""Hand-made views, a recording ``Commands`` and a Pilot driver for the console's tests."""
from __future__ import annotations

import time

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


class HistoryRecorder(Recorder):
    """A ``Recorder`` whose robot keeps a patrol history: ``history(query, **args)`` answers from
    ``answers`` (query -> answer; ``pot`` -> {pot id: timeline}) as ``lupin serve`` does, or is
    refused with ``refusal`` (a robot without a history). ``asked`` records every question."""

    def __init__(self, answers: dict | None = None, refusal: str | None = None, **kw):
        super().__init__(**kw)
        self.answers, self.refusal = answers or {}, refusal
        self.asked: list[tuple[str, dict]] = []

    def history(self, query: str, **args) -> tuple[dict | None, str | None]:
        with self._lock:
            self.asked.append((query, args))
        if self.refusal is not None:
            return None, self.refusal
        if query == "pot":
            timeline = self.answers.get("pot", {}).get(args.get("pot"), [])
            return {"pot": args.get("pot"), "timeline": timeline}, None
        return self.answers.get(query), None


def entry(patrol: int, day: int, status: str = "inspected", color: str | None = "red", blooms: int | None = 1,
          bug: bool | None = False, anomalies: tuple[str, ...] = (), mission: str = "default-patrol") -> dict:
    """One timeline entry as ``lupin serve`` sends it (``TimelineEntry.as_json``'s fields)."""
    if status != "inspected":
        color, blooms, bug = None, None, None
    return {"patrol": patrol, "mission": mission, "robot": "mirte", "started_at": f"2025-05-{day:02d}T06:00:00Z",
            "pot_id": "?", "seq": 1, "observed_at": f"2025-05-{day:02d}T06:01:00Z", "status": status,
            "flower_color": color, "blooms": blooms, "bug": bug, "anomalies": list(anomalies)}


def patrol_history() -> dict:
    """The answers of a robot that patrolled ``default-patrol`` before (``patrolling_view`` is its
    patrol #7): what changed so far (P01 pink -> red, P02 a new pest and 3 -> 2 blooms, P05
    failed now) and the pest streaks (P01 three patrols running, P02 this one)."""
    changes = {"after": {"id": 7}, "before": {"id": 6}, "changes": [
        {"pot": "P01", "kind": "color", "before": "pink", "after": "red", "detail": "colour pink -> red"},
        {"pot": "P02", "kind": "pest_new", "before": False, "after": True, "detail": "pest"},
        {"pot": "P02", "kind": "blooms", "before": 3, "after": 2, "detail": "blooms 3 -> 2"},
        {"pot": "P05", "kind": "failed", "before": "inspected", "after": "failed", "detail": "failed now"}]}
    pests = {"last": 20, "mission": "default-patrol", "patrols": [7, 6, 5],
             "pots": [{"pot_id": "P01", "pests": 3, "observed": 3, "streak": 3},
                      {"pot_id": "P02", "pests": 1, "observed": 3, "streak": 1},
                      {"pot_id": "P06", "pests": 1, "observed": 2, "streak": 0}]}
    timeline = {"P02": [entry(5, 1, color="white", blooms=3), entry(6, 2, color="white", blooms=3),
                        entry(7, 3, color="white", blooms=2, bug=True, anomalies=("bug",))],
                "P03": [entry(5, 1), entry(6, 2, status="failed", anomalies=("unreachable",))]}
    return {"changes": changes, "pests": pests, "pot": timeline}


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


# --- a greenhouse at scale: 200 pots in two bays ----------------------------------------------
BAY_PITCH, ROW_PITCH, PER_ROW, ROWS = 1.4, 1.0, 10, 10
"""Two bays of 10 x 10 pots; bay 2 starts 15 m east of bay 1 (a divider wall at x = 15)."""


def pot_xy(i: int) -> tuple[float, float]:
    bay, k = divmod(i, PER_ROW * ROWS)
    row, col = divmod(k, PER_ROW)
    return 1.0 + 15.0 * bay + BAY_PITCH * col, 0.5 + ROW_PITCH * row


def has_anomaly(i: int) -> bool:
    return i % 9 == 4


def greenhouse_grid(east: float = 31.0) -> GridView:
    """The SLAM grid of the greenhouse as explored up to ``east`` metres: a 0.05 m grid larger
    than what is known (unknown all round), walls round x -1 .. 31, y -1 .. 11, a divider at
    x = 15 with two doorways. The grid grows with ``east`` (its origin stays at -12, -6)."""
    res, x0, y0 = 0.05, -12.0, -6.0
    width = int(round((max(east, 20.0) + 12.0 - x0) / res))
    g = np.full((480, width), -1, np.int8)

    def cells(xa, xb, ya, yb):
        return slice(int(round((ya - y0) / res)), int(round((yb - y0) / res))), slice(int(round((xa - x0) / res)), int(round((xb - x0) / res)))

    g[cells(-1.0, east, -1.0, 11.0)] = 0
    for wall in ((-1.0, east, -1.0, -0.95), (-1.0, east, 10.95, 11.0), (-1.0, -0.95, -1.0, 11.0)):
        g[cells(*wall)] = 100
    if east > 15.05:  # the divider, two doorways in it
        g[cells(15.0, 15.05, -1.0, 11.0)] = 100
        for door in ((15.0, 15.05, 2.0, 3.0), (15.0, 15.05, 7.0, 8.0)):
            g[cells(*door)] = 0
    if east >= 31.0:
        g[cells(30.95, 31.0, -1.0, 11.0)] = 100
    return GridView(g, res, x0, y0)


def pot_line(pid: str, status: str, step: int | None) -> list[str]:
    """A pot's branch as py_trees' unicode tree draws it (``mission.patrol.tree``'s shape); a
    pot not in progress shows its statuses, the one in progress runs its ``step``-th leaf."""
    mark = {"inspected": "✓", "failed": "✓", "active": "*"}.get(status, "-")

    def leaf(i: int) -> str:
        if step is None:
            return mark
        return "✓" if i < step else "*" if i == step else "-"

    done = " -- oneshot completed" if mark == "✓" else ""
    lines = [f"-^- {pid} [{mark}]{done}", f"    {{o}} visit {pid} [{mark}]", f"        {{-}} inspect {pid} [{mark}]",
             f"            -^- approach {pid} [{leaf(0)}]", f"                -^- approach {pid} (timeout) [{leaf(0)}]",
             f"                    --> approach {pid} (navigate) [{leaf(0)}]" + (" -- running" if leaf(0) == "*" else "")]
    for i, name in enumerate(("front camera", "find", "moved", "wrist", "record", "stow arm"), start=1):
        lines.append(f"            --> {name} {pid} [{leaf(i)}]" + (" -- running" if leaf(i) == "*" else ""))
    lines.append(f"        --> {pid} failed [-]")
    return lines


def patrol_tree(statuses: list[str], step: int = 0, held: str | None = None) -> str:
    """A patrol's tree mid-run (the pot ``active`` on its ``step``-th leaf) or, ``held`` (the
    pause's reason), as py_trees draws it under a hold: everything below the guard stopped."""
    run = "-" if held else "*"
    head = ["-^- Lupin patrol [*]", f"    -^- operator pause [*]" + (f" -- {held}" if held else ""),
            f"        [o] mission [{run}]", f"            {{-}} battery low [{'-' if held else '✕'}]",
            f"                --> battery low? [{'-' if held else '✕'}]" + ("" if held else " -- failure"),
            "                --> go home [-]", f"            {{-}} patrol [{run}]",
            f"                -^- start-up (once) [{'-' if held else '✓'}] -- oneshot completed",
            f"                    {{-}} start-up [{'-' if held else '✓'}]", f"                /_/ pots and tags [{run}]",
            f"                    {{-}} pots [{run}]"]
    body = []
    for i, status in enumerate(statuses):
        shown = "-" if held else status
        body += [" " * 24 + line for line in pot_line(f"P{i + 1:03d}", shown, step if status == "active" and not held else None)]
    return "\n".join(head + body + [f"                    --> watch tags [{run}]", "                --> finish [-]"])


def greenhouse_view(pots: int = 200, done: int = 120) -> RobotView:
    """A 200-pot patrol in two bays, ``done`` pots finished (every ninth from the fifth with an
    anomaly), the next one in progress, the robot at its approach."""
    v = idle_view()
    v.mux_source, v.nav_state, v.mission_state, v.mission_name = "auto", "following", "running", "two-bay"
    v.pots = []
    for i in range(pots):
        x, y = pot_xy(i)
        status = "inspected" if i < done else "active" if i == done else "pending"
        anomalies = ["no_bloom"] if status == "inspected" and has_anomaly(i) else []
        v.pots.append(PotView(f"P{i + 1:03d}", x, y, status, i + 1 if status == "inspected" else None,
                              "red" if status == "inspected" else None, 1 if status == "inspected" else 0, anomalies))
    ax, ay = pot_xy(done)
    v.pose, v.goal = (ax - 0.5, ay, 0.0), (ax - 0.4, ay, 0.0)
    v.mission_step = f"approach P{done + 1:03d}"
    v.grid = greenhouse_grid()
    v.plan = np.array([[ax - 0.5, ay], [ax - 0.4, ay]])
    v.tree = patrol_tree([p.status for p in v.pots])
    v.log = [f"  40.0 I patrol two-bay started ({pots} pots)"]
    return v


async def until(pilot, cond, timeout: float = 20.0) -> bool:
    """Let the app run (Pilot pauses of 50 ms) until ``cond()`` or ``timeout`` wall seconds."""
    end = time.monotonic() + timeout
    while not cond() and time.monotonic() < end:
        await pilot.pause(0.05)
    return cond()
