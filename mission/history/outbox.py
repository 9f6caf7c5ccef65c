"""Where a history write goes: straight to the database while it answers, to the spool while it
does not, and out of the spool, in order, as soon as it answers again (spec/history.md: the
robot never waits for the history and never stops because of it).

Once anything waits in the spool, new writes queue behind it, so the database sees every patrol's
writes in the order they were made (a start before its rows, its rows in ``seq`` order, then its
end). The spool is emptied in batches of :data:`BATCH` writes, each batch one transaction; a
batch is forgotten only after the database committed it, and sending one twice is a no-op
(:mod:`mission.history.writes`), so nothing is lost and nothing doubled whatever fails when.
"""
from __future__ import annotations

import logging
import threading
from typing import Callable, Sequence

from mission.history.spool import MemorySpool, Spool
from mission.history.writes import Write, rows_in

log = logging.getLogger("lupin.history")

BATCH = 200
"""Writes per transaction when the spool is emptied: a 180-pot patrol's writes (a start, a row
per pot, an end) in one or two transactions, and a long outage's backlog without one enormous one."""


class Outbox:
    """Sends writes to one database through ``deliver`` (which raises ``failure`` when it cannot)."""

    def __init__(self, deliver: Callable[[Sequence[Write]], None], database: str, spool: Spool | None,
                 failure: tuple[type[BaseException], ...]):
        self.deliver, self.database, self.failure = deliver, database, failure
        self.spool = spool if spool is not None else MemorySpool()
        self.down: str | None = None
        """Why the database did not take the last write (one line); None while it answers."""
        self.delivered = 0
        """Rows sent from the spool since this outbox opened."""
        self._lock = threading.Lock()

    @property
    def waiting(self) -> int:
        """Writes waiting in the spool for this database."""
        return self.spool.count(self.database)

    def send(self, writes: Sequence[Write], try_now: bool = True) -> bool:
        """Send ``writes`` (after whatever waits); True when the database has them all, False when
        some wait in the spool. ``try_now=False`` spools them without asking the database (a
        database known down is not waited on)."""
        if not writes:
            return self.flush() == 0 if try_now else self.waiting == 0
        with self._lock:
            if try_now and not self.spool.count(self.database):
                try:
                    self.deliver(writes)
                    self._answered()
                    return True
                except self.failure as exc:
                    self._failed(exc, writes)
            self.spool.append(self.database, writes)
            return try_now and self._flush() == 0

    def flush(self) -> int:
        """Send what waits in the spool, oldest first, until it is empty or the database fails;
        the writes still waiting."""
        with self._lock:
            return self._flush()

    def _flush(self) -> int:
        while batch := self.spool.oldest(self.database, BATCH):
            writes = [w for _, w in batch]
            try:
                self.deliver(writes)
            except self.failure as exc:
                self._failed(exc, writes)
                return self.spool.count(self.database)
            self.spool.remove(self.database, batch[-1][0])
            self.delivered += rows_in(writes)
        self._answered()
        return 0

    def _failed(self, exc: BaseException, writes: Sequence[Write]) -> None:
        from mission.history.store import reason

        why = reason(exc)
        if self.down is None:
            where = self.spool.path or "memory (no state directory: lost if the process ends)"
            log.warning("history %s does not answer (%s): %d row(s) kept in the spool %s and sent when it answers",
                      self.database, why, rows_in(writes), where)
        self.down = why

    def _answered(self) -> None:
        if self.down is not None:
            log.warning("history %s answers again; %d row(s) sent from the spool so far", self.database,
                        self.delivered)
        self.down = None
