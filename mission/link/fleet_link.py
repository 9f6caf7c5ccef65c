"""A console's link to a fleet: one session to the router, every robot that is up, one shown.

The roster (``mission.link.roster``) says who is up; a ``LinkClient`` per robot, all on the one
session, folds each robot's telemetry as it comes, so switching the robot shown (keys 1-9) is
instant and a fleet view can draw every robot. It is a ``Commands`` like ``LinkClient``: what
the console sends goes to the robot shown; ``stop_fleet`` stops them all (``lupin/fleet/stop``),
``resume_fleet`` releases every robot's soft stop and resumes its patrol (commands: a console's).
A robot that dies stays in its slot only while it is shown, its view going stale (NO LINK); the
roster drops it from the list within a second.
"""
from __future__ import annotations

import threading
from typing import Callable

from mission.link.client import LinkClient
from mission.link.roster import Roster, stop_fleet
from mission.link.session import TlsFiles, open_session, session_config
from mission.link.view import OtherRobot, RobotView

NONE_UP = "no robot is up on the router"


class FleetLink:
    def __init__(self, endpoint: str, *, clock: Callable[[], float], tls: TlsFiles | None = None, token: str = "",
                 timeout: float = 3.0):
        self.clock, self.token, self.timeout = clock, token, timeout
        self.session = open_session(session_config("connect", endpoint, tls), "connect", endpoint, "--connect")
        self._lock = threading.Lock()
        self.clients: dict[str, LinkClient] = {}
        self.shown: str | None = None
        self.roster = Roster(self.session)

    def _follow(self) -> list[str]:
        """The robots up, each with its client (declared on the caller's thread, never inside a
        Zenoh callback); called at every poll of the view."""
        robots = self.roster.robots()
        for robot in robots:
            self.client(robot)
        return robots

    def client(self, robot: str) -> LinkClient:
        with self._lock:
            c = self.clients.get(robot)
            if c is None:
                c = self.clients[robot] = LinkClient(None, robot, clock=self.clock, token=self.token,
                                                     timeout=self.timeout, session=self.session)
            return c

    def robots(self) -> list[str]:
        return self.roster.robots()

    def select(self, index: int) -> str | None:
        """Show the ``index``-th robot up (0-based, the key's digit minus one); None: no such robot."""
        robots = self.robots()
        if not 0 <= index < len(robots):
            return None
        self.shown = robots[index]
        return self.shown

    def _current(self) -> LinkClient | None:
        if self.shown is None:
            robots = self.robots()
            self.shown = robots[0] if robots else None
        return self.client(self.shown) if self.shown is not None else None

    def view(self) -> RobotView:
        robots = self._follow()
        c = self._current()
        v = c.view() if c is not None else RobotView(robot="")
        v.fleet = robots
        v.others = []
        for r in robots:
            if r != self.shown and (o := self.client(r).view()).connected:
                v.others.append(OtherRobot(r, o.pose, o.plan))
        return v

    # --- Commands ------------------------------------------------------------------------------
    def send(self, command: str, /, **args) -> str | None:
        c = self._current()
        return c.send(command, **args) if c is not None else f"{command}: {NONE_UP}"

    def snapshot(self, camera: str) -> bytes | None:
        c = self._current()
        return c.snapshot(camera) if c is not None else None

    def ask(self, command: str, /, **args) -> tuple[dict | None, str | None]:
        c = self._current()
        return c.ask(command, **args) if c is not None else (None, f"{command}: {NONE_UP}")

    def history(self, query: str, **args) -> tuple[dict | None, str | None]:
        return self.ask("history", query=query, **args)

    def stop_fleet(self) -> list[str]:
        """Engage every robot's soft stop; the robots that answered."""
        return stop_fleet(self.session, self.timeout)

    def resume_fleet(self) -> dict[str, str | None]:
        """Release every robot's soft stop and resume its patrol where it held: per robot up,
        None when it resumed, else why not."""
        out = {}
        for robot in self.robots():
            c = self.client(robot)
            out[robot] = c.send("estop", engaged=False) or c.send("resume")
        return out

    def close(self) -> None:
        self.roster.close()
        with self._lock:
            for c in self.clients.values():
                c.close()
        self.session.close()
