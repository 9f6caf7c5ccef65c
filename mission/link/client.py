"""The client's end of the link: telemetry folded into a ``RobotView``, commands as queries.

A console (or a test, or a second console) opens one ``LinkClient`` on the runtime's endpoint.
Telemetry arrives on Zenoh's threads and is folded into the view under a lock; ``view()`` hands
the UI a consistent copy-free snapshot reference. A topic it cannot read is dropped (and
counted), never raised. ``send`` returns None when the runtime accepted a command, else the
one-line reason it gave (or that nobody answered). Several clients may share one session (a
console watching a fleet opens one connection to the router, ``session=``), each following its
robot's keys.
"""
from __future__ import annotations

import math

import json
import threading
import zlib
from collections import deque
from typing import Callable

import numpy as np
import zenoh

from mission.link.session import TlsFiles, open_session, session_config
from mission.link.view import GridView, PersonView, PotView, RobotView
from mission.link.wire import Grid, apply_grid, cmd_key, dumps, stop_key, tel_key

STALE_S = 1.0
"""No telemetry for this long (on the console's clock) and the view says disconnected."""
LOG_LINES = 200


def _finite(value: float | None) -> float:
    """A number off the wire, nan for null (JSON has no nan)."""
    return float("nan") if value is None else float(value)


class LinkClient:
    def __init__(self, endpoint: str | None, robot: str, *, clock: Callable[[], float], token: str = "",
                 timeout: float = 3.0, tls: TlsFiles | None = None, session: zenoh.Session | None = None):
        """``clock``: the console's seconds, which a link's staleness is measured on (a console
        has no runtime clock of its own: the command line gives it the wall clock). ``session``:
        an open one to share (then ``endpoint`` and ``tls`` are not used, and ``close`` leaves
        it open)."""
        self.robot, self.token, self.timeout, self.clock = robot, token, timeout, clock
        self._owns_session = session is None
        self.session = session if session is not None else open_session(
            session_config("connect", endpoint, tls), "connect", endpoint, "--connect")
        self._lock = threading.Lock()
        self._view = RobotView(robot=robot)
        self._grids: dict[str, Grid | None] = {"map": None, "costmap": None}
        self._log: deque[str] = deque(maxlen=LOG_LINES)
        self._last_rx = float("-inf")
        self.bad_messages = 0
        self.received: dict[str, int] = {}
        self._sub = self.session.declare_subscriber(tel_key(robot, "**"), self._on_sample)

    # --- telemetry -----------------------------------------------------------------------------
    def _on_sample(self, sample: zenoh.Sample) -> None:
        topic = str(sample.key_expr).rsplit("/", 1)[-1]
        data = sample.payload.to_bytes()
        try:
            with self._lock:
                self._fold(topic, data)
                self._last_rx = self.clock()
                self.received[topic] = self.received.get(topic, 0) + 1
        except Exception:  # a garbled message is dropped, not raised into Zenoh
            self.bad_messages += 1

    def _fold(self, topic: str, data: bytes) -> None:
        v = self._view
        if topic in ("map", "costmap"):
            g = apply_grid(self._grids[topic], data)
            self._grids[topic] = g
            if g is not None:
                setattr(v, "grid" if topic == "map" else "costmap", GridView(g.data, g.resolution, g.origin_x, g.origin_y))
            return
        if topic == "scan":
            v.scan = np.frombuffer(data, np.float16).astype(float).reshape(-1, 2)
            return
        if topic == "tree":
            v.tree = zlib.decompress(data).decode("utf-8", "replace")
            return
        if topic == "log":
            self._log.append(data.decode("utf-8", "replace"))
            v.log = list(self._log)
            return
        m = json.loads(data)
        if topic == "state":
            v.t, v.pose, v.velocity, v.mux_source = m["t"], tuple(m["pose"]), tuple(m["velocity"]), m["mux"]
            monitor = m.get("monitor") or {}
            v.monitor_action = monitor.get("action", "none")
            nearest = monitor.get("nearest")
            v.monitor_nearest = float(nearest) if isinstance(nearest, (int, float)) else math.inf
            v.monitor_fault = monitor.get("fault")
            v.monitor_enabled = monitor.get("enabled", True) is not False
            v.estop_engaged, v.estop_latched = m["estop"]["engaged"], m["estop"]["latched"]
            v.estop_why = m["estop"].get("why", "")
            b = m["battery"]
            v.battery_voltage, v.battery_percentage = _finite(b["voltage"]), _finite(b["percentage"])
            v.battery_current = _finite(b.get("current"))
            v.battery_low = b["low"]
            v.people = [PersonView.row(r) for r in m.get("people", ())]  # left out: nobody tracked
        elif topic == "nav":
            v.nav_state, v.nav_reason = m["state"], m["reason"]
            v.goal = tuple(m["goal"]) if m["goal"] else None
            v.plan = np.asarray(m["plan"], dtype=float).reshape(-1, 2)
        elif topic == "status":
            v.controllers = dict(m["controllers"])
        elif topic == "mission":
            v.mission_state, v.mission_name, v.mission_step = m["state"], m["name"], m["step"]
            v.mission_outcome = m["outcome"]
            energy = m.get("energy") or {}
            v.charge, v.charge_at_dock = _finite(energy.get("charge")), _finite(energy.get("at_dock"))
            v.heading_home = energy.get("why_home") or ""
        elif topic == "pots":
            v.pots = [PotView(p["id"], p["x"], p["y"], p["status"], p["tag"], p["flower"], p["blooms"], p["anomalies"])
                      for p in m["pots"]]

    def view(self) -> RobotView:
        """The latest view (the same object, updated in place; read it on the UI's timer)."""
        with self._lock:
            self._view.connected = self.clock() - self._last_rx < STALE_S
            return self._view

    # --- commands ------------------------------------------------------------------------------
    def _query(self, name: str, args: dict, key: str | None = None) -> tuple[bytes | None, str | None]:
        try:
            replies = self.session.get(key or cmd_key(self.robot, name), payload=dumps({**args, "token": self.token}),
                                       timeout=self.timeout)
            for reply in replies:
                if reply.ok is not None:
                    return reply.ok.payload.to_bytes(), None
                try:
                    return None, json.loads(reply.err.payload.to_bytes())["error"]
                except (ValueError, KeyError, TypeError):
                    return None, reply.err.payload.to_bytes().decode("utf-8", "replace")
        except zenoh.ZError as exc:
            return None, f"{name}: link error: {exc}"
        return None, f"{name}: no answer from robot {self.robot!r} within {self.timeout:g} s (is `lupin serve` running?)"

    def send(self, command: str, /, **args) -> str | None:
        return self._query(command, args)[1]

    def stop(self) -> str | None:
        """Engage the robot's soft stop on its stop key, open to every member of a fleet (a
        command, ``send("estop", engaged=True)``, is a console's only)."""
        return self._query("stop", {}, stop_key(self.robot))[1]

    def snapshot(self, camera: str) -> bytes | None:
        data, error = self._query("snapshot", {"camera": camera})
        return data if error is None else None

    def ask(self, command: str, /, **args) -> tuple[dict | None, str | None]:
        """A command the robot answers with JSON (``history``, ``arm_calibrate``): (answer, None)
        or (None, why not)."""
        data, error = self._query(command, args)
        if error is not None:
            return None, error
        try:
            return json.loads(data), None
        except (ValueError, TypeError):
            return None, f"{command}: the robot's answer is not JSON"

    def history(self, query: str, **args) -> tuple[dict | None, str | None]:
        """Ask the robot's patrol history (``mission.history.answers``)."""
        return self.ask("history", query=query, **args)

    def close(self) -> None:
        self._sub.undeclare()
        if self._owns_session:
            self.session.close()
