"""The runtime's end of the link: a Zenoh session that publishes telemetry and answers commands.

Commands arrive on Zenoh's threads. Each is checked there (``mission.link.commands``), then
handed to the runtime's own thread through a queue that a 20 Hz scheduler task drains, so the
robot's state is only ever touched by the loop that owns it; the Zenoh thread waits (at most
``link.command_timeout``) for the answer and replies, the loop never waits for anyone. One
exception, on purpose: engaging the soft e-stop is applied at once on the Zenoh thread (one
attribute write that the base controller reads on its next tick), so a stop does not also
wait for the queue's beat. A release queued before a stop arrived is refused when its turn
comes, not applied: it would undo the later stop (a stop's "at once" must not let an earlier
release overtake it). And one read: a ``history`` question is answered on the Zenoh thread
from the database (``mission.history.answers``), never queued onto the robot's loop.

The stop keys (``lupin/<robot>/stop`` and ``lupin/fleet/stop``, spec/fleet.md) engage the soft
stop the same way, for anyone the router lets ask; releasing stays a command. The liveliness
token ``lupin/<robot>/alive`` is held while the link is up, so consoles see the robot come and
go (``mission.link.roster``).
"""
from __future__ import annotations

import logging
import queue
import threading
from dataclasses import dataclass, field

import zenoh

from hw.odometry import Pose2D
from mission.link.aisle_client import AisleLockClient
from mission.link.commands import CommandRefused, parse_command
from mission.link.config import LinkConfig
from mission.link.outbox import Outbox
from mission.link.peers import Peers
from mission.link.session import (ROBOT_LEASE_MS, TlsFiles, check_endpoint, free_endpoint, open_session,
                                  session_config)
from mission.link.telemetry import LinkLogHandler, Telemetry
from mission.link.wire import FLEET_STOP, alive_key, cmd_key, dumps, stop_key

__all__ = ["LinkServer", "check_endpoint", "free_endpoint", "session_config"]  # the session's, kept importable here

log = logging.getLogger("lupin.link")

COMMAND_RATE = 20.0
"""How often the runtime takes queued commands, Hz: at most 50 ms added to an operator's action."""


@dataclass
class _Pending:
    name: str
    args: object
    done: threading.Event = field(default_factory=threading.Event)
    result: bytes | None = None
    error: str | None = None
    stops_before: int = 0
    """Stops engaged when this command arrived: a release after a newer stop is refused."""


class LinkServer:
    def __init__(self, service, config: LinkConfig, token: str | None, endpoint: str | None = None, *,
                 connect: str | None = None, tls: TlsFiles | None = None):
        """Listen on ``endpoint`` (a robot alone: consoles connect to it), or with ``connect``
        join a fleet's router as a client (``tls``: this robot's certificate). ``token`` None:
        no operator token; the router's access control alone says who commands (a fleet with
        certificates, spec/fleet.md "Security")."""
        self.service, self.config, self.token = service, config, token
        mode, option = ("connect", "--connect") if connect else ("listen", "--listen")
        self.endpoint = check_endpoint(connect or endpoint or config.listen, option)
        lease = ROBOT_LEASE_MS if connect else None  # on a router: gone within a second if it falls silent
        self.session = open_session(session_config(mode, self.endpoint, tls, lease_ms=lease), mode, self.endpoint, option)
        self.outbox = Outbox(self.session.put, config.queue)
        self.telemetry = Telemetry(service, self.outbox, config.robot)
        self._inbox: queue.SimpleQueue[_Pending] = queue.SimpleQueue()
        self._stopped = 0
        """Stops engaged on Zenoh's threads so far: it only grows (two racing stops may count as one,
        which still changes it, all a queued release looks at)."""
        self._queryable = self.session.declare_queryable(cmd_key(config.robot, "*"), self._on_query)
        self._stops = [self.session.declare_queryable(k, self._on_stop) for k in (stop_key(config.robot), FLEET_STOP)]
        self._alive = self.session.liveliness().declare_token(alive_key(config.robot))
        self.peers: Peers | None = None
        if connect:  # in a fleet: its patrols ask the dispatcher for aisles through this session
            service.aisle_client = AisleLockClient(self.session, config.robot)
            self.peers = self._peers(service, config.robot)
        self._log = LinkLogHandler(self.outbox, config.robot, lambda: service.now)
        logging.getLogger().addHandler(self._log)
        sched = service.robot.scheduler
        sched.every("link.fast", config.fast_rate, self.telemetry.fast)
        sched.every("link.slow", config.slow_rate, self.telemetry.slow)
        sched.every("link.maps", config.map_rate, self.telemetry.maps)
        sched.every("link.commands", COMMAND_RATE, self._drain)
        self.commands_done = 0

    def _peers(self, service, robot: str) -> Peers | None:
        """The other robots kept out of (``mission.link.peers``), from this robot's dock."""
        dock = service.config.fleet.docks.get(robot)
        if dock is None:
            log.warning("%s: no dock of its own in fleet.docks: it cannot tell the others where it is, "
                        "nor place them, and keeps out of them on its lidar only", robot)
            return None
        peers = Peers(self.session, self.outbox, robot, Pose2D(*dock), service.wall_now)
        peers.attach(service.nav, service.robot.scheduler)
        people = getattr(service.robot, "people", None)
        if people is not None:  # the others' pucks and arms are robots, not people (``mission.runtime.people``)
            people.robots = peers.around
        return peers

    # --- Zenoh's threads -----------------------------------------------------------------------
    def _stop_now(self) -> None:
        self._stopped += 1
        self.service.estop(True)

    def _on_stop(self, query: zenoh.Query) -> None:
        """A stop key: engaged at once, for anyone the router lets ask (spec/fleet.md)."""
        self._stop_now()
        query.reply(query.key_expr, dumps({"ok": True, "robot": self.config.robot}))

    def _on_query(self, query: zenoh.Query) -> None:
        name = str(query.key_expr).rsplit("/", 1)[-1]
        payload = query.payload.to_bytes() if query.payload is not None else b""
        try:
            args = parse_command(name, payload, self.token)
        except CommandRefused as exc:
            query.reply_err(dumps({"error": str(exc)}))
            return
        if name == "estop" and args.engaged:
            self._stop_now()  # at once: see the module docstring
            query.reply(query.key_expr, dumps({"ok": True}))
            return
        if name == "history":  # a read of the database, answered here: the control loop never waits on it
            try:
                query.reply(query.key_expr, self.service.history_query(**args.model_dump(exclude={"token"})))
            except CommandRefused as exc:
                query.reply_err(dumps({"error": str(exc)}))
            return
        pending = _Pending(name, args, stops_before=self._stopped)
        self._inbox.put(pending)
        if not pending.done.wait(self.config.command_timeout):
            query.reply_err(dumps({"error": f"{name}: the runtime did not answer within {self.config.command_timeout:g} s"}))
        elif pending.error is not None:
            query.reply_err(dumps({"error": pending.error}))
        else:
            query.reply(query.key_expr, pending.result if pending.result is not None else dumps({"ok": True}))

    # --- the runtime's thread ------------------------------------------------------------------
    def _drain(self, now: float) -> None:
        while True:
            try:
                p = self._inbox.get_nowait()
            except queue.Empty:
                return
            try:
                if p.name == "estop" and p.stops_before != self._stopped:  # only releases queue
                    raise CommandRefused("estop: release refused: a stop came after it (release again)")
                out = getattr(self.service, p.name)(**p.args.model_dump(exclude={"token"}))
                p.result = out if isinstance(out, bytes) else None
            except CommandRefused as exc:
                p.error = str(exc)
            except Exception as exc:  # a command must never take the loop down
                log.exception("command %s failed", p.name)
                p.error = f"{p.name} failed: {exc}"
            self.commands_done += 1
            p.done.set()

    def close(self) -> None:
        for task in ("link.fast", "link.slow", "link.maps", "link.commands"):
            self.service.robot.scheduler.cancel(task)
        logging.getLogger().removeHandler(self._log)
        self._queryable.undeclare()
        for q in self._stops:
            q.undeclare()
        self._alive.undeclare()
        if self.peers is not None:
            self.peers.close(self.service.nav, self.service.robot.scheduler)
            if getattr(self.service.robot, "people", None) is not None:
                self.service.robot.people.robots = tuple
        self.service.aisle_client = None
        self.outbox.close()
        self.session.close()
