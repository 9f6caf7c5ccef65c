"""One patrol written into the history as it goes, without ever holding up the robot.

The patrol's report (``mission.patrol.report.PatrolReport``) tells its observers of each pot
as it is recorded and of the end. :class:`PatrolRecorder` is such an observer:

- at the start (on the caller's thread, before the robot moves) it reads the previous patrol of
  the same mission in the same greenhouse (spec/history.md: sim patrols of the same world, robot
  patrols with robot patrols) and sends this patrol's start, ``ended_at`` null;
- each recorded pot becomes an :class:`~mission.history.records.Observation`, compared with the
  previous patrol's row for that pot (``report.json``'s ``changes``), and is handed to a writer
  thread that sends it through the history's outbox (:mod:`mission.history.outbox`). The
  runtime's thread only appends to a list: a slow or unreachable server never stalls the
  control loop;
- at the end the pots never reached are written ``skipped`` and the patrol's row gets its
  outcome, time, distance and ``ended_at``.

The patrol is named by its own uid (:mod:`mission.history.writes`), so when the database does not
answer, at start or mid-patrol, its writes wait in the spool and are sent in order when it does:
logged loudly once (ERROR, naming the pots and the database), never costing the robot or
``report.json``. A process killed mid-patrol leaves the pots already written (or spooled) and
``ended_at`` null.
"""
from __future__ import annotations

import logging
import queue
import threading
from pathlib import Path
from typing import Iterable

from mission.history.changes import pot_changes
from mission.history.records import Change, Observation, Patrol, PatrolStart, iso
from mission.history.store import FAILURES, History, reason
from mission.history.writes import Begin, End, Rows, new_uid
from mission.patrol.mission_file import Mission, MissionPot

log = logging.getLogger("lupin.history")

_STOP = object()
_KICK = object()


def observation(pot: MissionPot, entry: dict, kinds: Iterable[str], seq: int, when, directory: Path) -> Observation:
    """A report's pot entry (spec/report.md) as the history's row: where the pot was found (its
    measured pose when it had moved), its flower, its anomaly kinds, its images' full paths."""
    flower = entry.get("flower") or {}
    located = entry.get("located") or {}
    images = {name: str((directory / name).absolute()) for name in entry.get("images", [])}
    front = next((p for n, p in images.items() if n.endswith("_front.jpg")), None)
    wrist = next((p for n, p in images.items() if n.endswith("_wrist.jpg")), None)
    return Observation(
        pot_id=pot.id, seq=seq, observed_at=when, status=entry["status"], tag_read=entry.get("tag_read"),
        flower_color=flower.get("color"), blooms=flower.get("blooms"), bug=flower.get("bug"),
        confidence=flower.get("confidence"), x=located.get("x", pot.x), y=located.get("y", pot.y),
        anomalies=tuple(dict.fromkeys(kinds)), front_image=front, wrist_image=wrist,
        facing=located.get("facing", pot.facing), tag_expected=pot.tag)


class PatrolRecorder:
    """Writes one patrol; a ``mission.patrol.report`` observer."""

    def __init__(self, history: History, mission: Mission, start: PatrolStart, directory: Path):
        self.history, self.mission, self.directory = history, mission, Path(directory)
        self.pots = {p.id: p for p in mission.pots}
        self.uid = new_uid()
        self.errors: list[str] = []
        self.write_s: list[float] = []
        """Seconds each write transaction took (filled only when ``timer`` is set)."""
        self.timer = None
        self.changes: list[Change] = []
        self._rows: list[Observation] = []
        self._end: tuple | None = None
        self._ended = False
        self._seq = 0
        self._recorded: set[str] = set()
        self._lock = threading.Lock()
        self._kicks: queue.SimpleQueue = queue.SimpleQueue()
        self.previous: Patrol | None = None
        self._before: dict[str, Observation] = {}
        answers = history.outbox.down is None  # a database known down is not waited on before the robot moves
        if answers:
            try:
                self.previous, self._before = history.previous_observations(mission.name, start.world)
            except FAILURES as exc:
                log.warning("history %s: no earlier patrol to compare with: %s", history.shown, reason(exc))
                answers = False
        self._send([Begin(self.uid, start, history.clock())], "the patrol's start", try_now=answers)
        self._thread = threading.Thread(target=self._loop, name=f"history-{self.uid[:8]}", daemon=True)
        self._thread.start()

    @property
    def patrol_id(self) -> int | None:
        """The database's id of this patrol; None until the database has its start."""
        return self.history.patrol_id(self.uid)

    # --- the report's observer (the runtime's thread) --------------------------------------------
    def recorded(self, pot: MissionPot, entry: dict, kinds: Iterable[str]) -> None:
        self._seq += 1
        self._recorded.add(pot.id)
        obs = observation(pot, entry, kinds, self._seq, self.history.clock(), self.directory)
        prior = self._before.get(pot.id)
        if prior is not None:
            self.changes += pot_changes(prior, obs)
        self._queue([obs])

    def sections(self) -> dict:
        """``report.json``'s keys from the history: ``changes`` against the previous patrol of the
        same mission (``changes_since`` names it; null for a first patrol) and where it is recorded."""
        since = None if self.previous is None else {
            "patrol": self.previous.id, "started_at": iso(self.previous.started_at), "outcome": self.previous.outcome}
        return {"changes": [c.as_json() for c in self.changes], "changes_since": since,
                "history": {"database": self.history.shown, "patrol": self.patrol_id, "write_errors": len(self.errors),
                            "spooled": self.history.outbox.waiting}}

    def finished(self, doc: dict) -> None:
        """The end: pots never reached as ``skipped`` rows, then the patrol's outcome."""
        skipped = []
        for entry in doc["pots"]:
            if entry["status"] == "skipped" and entry["id"] in self.pots and entry["id"] not in self._recorded:
                self._seq += 1
                skipped.append(observation(self.pots[entry["id"]], entry, ("skipped",), self._seq,
                                           self.history.clock(), self.directory))
        with self._lock:
            self._end = (doc["outcome"], doc.get("sim_time_s"), doc.get("distance_m"), self.history.clock(),
                         tuple(doc.get("legs", ())))
        self._queue(skipped)
        self._kicks.put(_STOP)

    def _queue(self, rows: list[Observation]) -> None:
        with self._lock:
            self._rows += rows
        self._kicks.put(_KICK)

    # --- the writer's thread -----------------------------------------------------------------------
    def _loop(self) -> None:
        while True:
            item = self._kicks.get()
            if isinstance(item, threading.Event):  # drain(): everything before it has been tried
                item.set()
                continue
            self._write()
            if item is _STOP:
                return

    def _write(self) -> None:
        with self._lock:
            rows, end = list(self._rows), self._end
        writes = [Rows(self.uid, tuple(rows))] if rows else []
        if end is not None and not self._ended:
            writes.append(End(self.uid, *end))
        if not writes:  # nothing new: a chance to send what waits in the spool
            try:
                self.history.outbox.flush()
            except Exception as exc:  # the spool itself failed; the next write says so
                log.warning("history spool: %s", reason(exc))
            return
        what = f"pot(s) {', '.join(o.pot_id for o in rows)}" if rows else "the patrol's end"
        t0 = self.timer() if self.timer else 0.0
        if not self._send(writes, what):
            return
        if self.timer and rows:
            self.write_s.append(self.timer() - t0)
        with self._lock:
            del self._rows[:len(rows)]
        self._ended = self._ended or end is not None

    def _send(self, writes: list, what: str, try_now: bool = True) -> bool:
        """Hand ``writes`` to the outbox: True when they are in the database or the spool."""
        try:
            if self.history.outbox.send(writes, try_now):
                return True
            self._failed(what, self.history.outbox.down or "not tried: the database did not answer before",
                         spooled=True)
            return True
        except Exception as exc:  # the spool itself failed (a full disk): kept here, tried again
            self._failed(what, reason(exc), spooled=False)
            return False

    def _failed(self, what: str, why: str, spooled: bool) -> None:
        where = "kept in the spool, sent when it answers" if spooled else "kept in memory, tried again"
        msg = f"history {self.history.shown}: could not record {what} of patrol {self.uid[:8]} now ({why}): {where}"
        self.errors.append(msg)
        log.log(logging.ERROR if len(self.errors) == 1 else logging.WARNING,
                "%s; the patrol goes on and report.json has everything", msg)

    # --- the end ---------------------------------------------------------------------------------
    @property
    def pending(self) -> int:
        """Rows not written yet (plus one while the end is not)."""
        with self._lock:
            return len(self._rows) + (0 if self._ended or self._end is None else 1)

    @property
    def delivered(self) -> bool:
        """Everything of this patrol (and before it) is in the database: nothing pending or spooled."""
        return self._ended and not self.pending and self.history.outbox.waiting == 0

    def drain(self, timeout: float = 30.0) -> bool:
        """Wait until every row queued so far has been tried once (written, or failed and kept);
        False when the writer did not get there within ``timeout`` s or is not running."""
        if not self._thread.is_alive():
            return False
        reached = threading.Event()
        self._kicks.put(reached)
        return reached.wait(timeout)

    def wait(self, timeout: float = 30.0, retry: bool = True) -> bool:
        """Let the writer finish (after ``finished``); True when everything is in the database.
        With ``retry``, what waits (here or in the spool) is tried once more on this thread."""
        if self._thread.is_alive():
            self._thread.join(timeout)
        if self._thread.is_alive():
            log.error("history %s: %d row(s) of patrol %s still unwritten after %g s", self.history.shown,
                      self.pending, self.uid[:8], timeout)
            return False
        if retry and (self.pending or self.history.outbox.waiting):
            self._write()  # one last try on this thread: the writer's last attempt failed
        return self.delivered


def start_recording(history: History | None, mission: Mission, robot: str, world: str | None,
                    report_path: Path) -> PatrolRecorder | None:
    """The recorder for a patrol about to start, or None when the history is off."""
    if history is None:
        return None
    start = PatrolStart(robot=robot, mission=mission.name, world=world, report_path=str(Path(report_path).absolute()),
                        pots=len(mission.pots))
    return PatrolRecorder(history, mission, start, Path(report_path).parent)
