"""The history store: one object the patrol, ``lupin serve``, the CLI and the console read and
write the history through (spec/history.md).

:func:`open_history` turns a ``--history`` value into a :class:`History` (or None for ``none``):
it connects, upgrades an older schema in place, refuses a newer one, and proves it can write,
so a database that cannot be used is one clear line (``InputError``, exit 2) before the robot
moves. Reading commands open with ``create=False``: a path with no database is an error, not
a new empty file.

SQLite: WAL journal (readers never block the patrol's writer, nor it them), a 30 s busy wait
for a second writer, foreign keys on, reads through a memory map; every transaction starts with a real ``BEGIN`` (the
Python driver's own would leave DDL outside it). PostgreSQL: psycopg 3, a connect timeout, a
small pool; each robot's rows are its own transactions, so several write at once.

The engine is thread-safe: the patrol's rows are written on the recorder's thread
(:mod:`mission.history.recorder`) while the CLI or the link reads on theirs.

A patrol's writes go through :attr:`History.outbox` (:mod:`mission.history.outbox`): to the
database while it answers, to the spool while it does not. The robot's runtime opens the history
with a spool (``spool=``, in its state directory): then a server that cannot be reached at start
is no error, the robot starts, and the database is built or upgraded when it first answers. Only
a malformed URL or an unusable local file is bad input then. :meth:`History.outage_until` is the
sim's fault hook (spec/events.md ``history_down``).
"""
from __future__ import annotations

import logging
import sqlite3
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import Callable, Iterator, Sequence

from sqlalchemy import Connection, Engine, create_engine, event, func, select, update
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.exc import SQLAlchemyError

from hw.errors import InputError
from mission.history import queries
from mission.history.migrations import LATEST, NewerSchema, NotAHistory, migrate
from mission.history.outbox import Outbox
from mission.history.records import (ChangeSet, Observation, Patrol, PatrolStart, PestMap, TimelineEntry)
from mission.history.schema import legs, observations, patrols, schema_version
from mission.history.spool import Spool
from mission.history.url import HistoryTarget, parse_history_url
from mission.history.writes import Begin, End, Rows, Write, new_uid

log = logging.getLogger("lupin.history")

Clock = Callable[[], datetime]
SQLITE_CACHE_KB = 32_000
"""SQLite's page cache per connection: a patrol's and a year's worth of index pages stay in it."""
SQLITE_MMAP_BYTES = 1 << 30
"""SQLite reads the file through memory mapping (up to 1 GiB): a pot's timeline touches ~1,500
scattered pages of a year's database, each then a memory read rather than a read() call."""


def utc_now() -> datetime:
    """Wall-clock UTC: the history's timestamps say when, for a grower, not runtime seconds."""
    return datetime.now(timezone.utc)


class HistoryError(Exception):
    """The database could not be read or written (the reason, one line)."""


class Unreachable(HistoryError):
    """The database does not answer (a fault injected by :meth:`History.outage_until`)."""


FAILURES = (SQLAlchemyError, HistoryError)
"""What a history call raises when the database cannot answer it."""


def reason(exc: BaseException) -> str:
    """One line of why a database call failed (the driver's own words, no SQL, no traceback)."""
    orig = getattr(exc, "orig", None) or exc
    text = str(orig).strip().splitlines()
    return text[0] if text else type(orig).__name__


def make_engine(target: HistoryTarget, connect_timeout: float = 5.0) -> Engine:
    if target.is_sqlite:
        engine = create_engine(target.url, connect_args={"timeout": 30.0, "check_same_thread": False})

        @event.listens_for(engine, "connect")
        def _connect(dbapi, record) -> None:
            dbapi.isolation_level = None  # transactions are ours (below), DDL included
            cur = dbapi.cursor()
            cur.execute("PRAGMA foreign_keys=ON")
            cur.execute(f"PRAGMA cache_size=-{SQLITE_CACHE_KB}")
            cur.execute(f"PRAGMA mmap_size={SQLITE_MMAP_BYTES}")
            try:
                cur.execute("PRAGMA journal_mode=WAL")
            except sqlite3.DatabaseError:  # a read-only file is still readable
                pass
            cur.close()

        @event.listens_for(engine, "begin")
        def _begin(conn) -> None:
            conn.exec_driver_sql("BEGIN IMMEDIATE" if conn.get_execution_options().get("immediate") else "BEGIN")

        return engine
    return create_engine(target.url, pool_size=2, max_overflow=4, pool_pre_ping=True,
                         connect_args={"connect_timeout": max(1, int(round(connect_timeout))),
                                       "application_name": "lupin"})


class History:
    """An open history database: write a patrol as it goes, ask the grower's questions."""

    def __init__(self, engine: Engine, target: HistoryTarget, clock: Clock = utc_now, spool: Spool | None = None,
                 ready: bool = True):
        self.engine, self.target, self.clock = engine, target, clock
        self._ready = ready
        """The schema is known current (checked at open, or at the first answer after an outage)."""
        self._ids: dict[str, int] = {}
        self._outage: tuple[float, Callable[[], float]] | None = None
        self.outbox = Outbox(self.deliver, target.shown, spool, FAILURES)

    @property
    def shown(self) -> str:
        return self.target.shown

    # --- the fault hook ------------------------------------------------------------------------
    def outage_until(self, until: float | None, now: Callable[[], float] | None = None) -> None:
        """The database does not answer this process while ``now() < until`` (spec/events.md
        ``history_down``: ``history.outage_until(t + duration, scheduler.clock.now)``); ``None``
        ends it. Reads and writes alike fail as a server that is down would, at once."""
        self._outage = None if until is None else (float(until), now)

    def _check_reachable(self) -> None:
        if self._outage is not None:
            until, now = self._outage
            if now() < until:
                raise Unreachable(f"unreachable until t={until:g} s (injected outage)")
            self._outage = None

    @contextmanager
    def _connection(self, write: bool) -> Iterator[Connection]:
        self._check_reachable()
        with self.engine.connect() as conn:
            if write:
                conn = conn.execution_options(immediate=True)
            if not self._ready:
                self._bring_up(conn)
            with conn.begin():
                yield conn

    def _bring_up(self, conn: Connection) -> None:
        """The first answer after opening unreached: build or upgrade it now (NewerSchema and
        NotAHistory are failures like any other: the rows wait in the spool)."""
        try:
            with conn.begin():
                before, after = migrate(conn)
        except (NewerSchema, NotAHistory) as exc:
            raise HistoryError(str(exc)) from None
        if before < after:
            log.warning("history %s built or upgraded from schema version %d to %d", self.shown, before, after)
        self._ready = True

    @contextmanager
    def _writing(self) -> Iterator[Connection]:
        with self._connection(write=True) as conn:
            yield conn

    @contextmanager
    def reading(self) -> Iterator[Connection]:
        """A connection in one transaction: a consistent view for a query or several."""
        with self._connection(write=False) as conn:
            yield conn

    def close(self) -> None:
        self.engine.dispose()

    def reachable(self) -> str | None:
        """None when the database answers now; else why not (one line)."""
        try:
            with self.reading() as c:
                c.execute(select(func.max(schema_version.c.version))).scalar()
        except FAILURES as exc:
            return reason(exc)
        return None

    # --- writing a patrol -----------------------------------------------------------------
    def deliver(self, writes: Sequence[Write]) -> None:
        """``writes`` in one transaction, each a no-op when the database has it already (a
        resend from the spool): a patrol is found by its uid, a pot's row by (patrol, pot)."""
        with self._writing() as conn:
            for w in writes:
                if isinstance(w, Begin):
                    s = w.start
                    conn.execute(_insert_new(conn, patrols).values(
                        uid=w.uid, robot=s.robot, mission=s.mission, world=s.world, report_path=s.report_path,
                        pots=s.pots, started_at=w.started_at))
                    self._ids[w.uid] = conn.execute(select(patrols.c.id).where(patrols.c.uid == w.uid)).scalar_one()
                elif isinstance(w, Rows):
                    if w.rows:
                        pid = self._id(conn, w.uid)
                        conn.execute(_insert_new(conn, observations), [o.row(pid) for o in w.rows])
                elif isinstance(w, End):
                    pid = self._id(conn, w.uid)
                    conn.execute(update(patrols).where(patrols.c.id == pid).values(
                        ended_at=w.ended_at, outcome=w.outcome, sim_time_s=w.sim_time_s, distance_m=w.distance_m))
                    if w.legs:
                        conn.execute(_insert_new(conn, legs), [{"patrol_id": pid, **_leg_row(g)} for g in w.legs])

    def _id(self, conn: Connection, uid: str) -> int:
        if uid not in self._ids:
            pid = conn.execute(select(patrols.c.id).where(patrols.c.uid == uid)).scalar()
            if pid is None:
                raise HistoryError(f"patrol {uid} is not in the database (its start was not sent)")
            self._ids[uid] = pid
        return self._ids[uid]

    def patrol_id(self, uid: str) -> int | None:
        """The database's id of the patrol the robot calls ``uid``, once the database has it."""
        return self._ids.get(uid)

    def begin_patrol(self, start: PatrolStart, started_at: datetime | None = None) -> int:
        """Its ``patrols`` row (``ended_at`` null while it runs), written now; the id."""
        uid = new_uid()
        self.deliver([Begin(uid, start, started_at or self.clock())])
        return self._ids[uid]

    def add_observations(self, patrol_id: int, rows: Sequence[Observation]) -> None:
        """Pots' rows in one transaction: all of them or none."""
        if rows:
            with self._writing() as conn:
                conn.execute(observations.insert(), [o.row(patrol_id) for o in rows])

    def end_patrol(self, patrol_id: int, outcome: str, sim_time_s: float | None, distance_m: float | None,
                   ended_at: datetime | None = None) -> None:
        with self._writing() as conn:
            conn.execute(update(patrols).where(patrols.c.id == patrol_id).values(
                ended_at=ended_at or self.clock(), outcome=outcome, sim_time_s=sim_time_s, distance_m=distance_m))

    # --- reading (the one interface the CLI, serve's link and the console use) ----------------
    def legs(self, patrol_id: int) -> list[dict]:
        """The patrol's legs out from the dock, in order (none for a patrol ended before its end)."""
        with self.reading() as c:
            rows = c.execute(select(legs).where(legs.c.patrol_id == patrol_id).order_by(legs.c.leg)).mappings()
            return [{k: v for k, v in row.items() if k != "patrol_id"} for row in rows]

    def patrol(self, patrol_id: int) -> Patrol | None:
        with self.reading() as c:
            return queries.patrol(c, patrol_id)

    def patrols(self, mission: str | None = None, robot: str | None = None, limit: int | None = None) -> list[Patrol]:
        with self.reading() as c:
            return queries.patrols(c, mission, robot, limit)

    def observations(self, patrol_id: int) -> list[Observation]:
        with self.reading() as c:
            return queries.observations(c, patrol_id)

    def pot_timeline(self, pot_id: str, mission: str | None = None, every: bool = False) -> list[TimelineEntry]:
        with self.reading() as c:
            return queries.pot_timeline(c, pot_id, mission, every)

    def changes(self, mission: str | None = None, every: bool = False) -> ChangeSet:
        with self.reading() as c:
            return queries.changes(c, mission, every)

    def pest_map(self, last: int, mission: str | None = None, every: bool = False) -> PestMap:
        with self.reading() as c:
            return queries.pest_map(c, last, mission, every)

    def previous_observations(self, mission: str, world=queries.EVERY) -> tuple[Patrol | None, dict[str, Observation]]:
        """The latest patrol of ``mission`` in the greenhouse ``world`` (None: the robot's)."""
        with self.reading() as c:
            return queries.previous_observations(c, mission, world)

    def pots_known(self, mission: str | None = None) -> list[str]:
        with self.reading() as c:
            return queries.pots_known(c, mission)

    def latest_mission(self) -> str | None:
        with self.reading() as c:
            return queries.latest_mission(c)

    def version(self) -> int:
        with self.reading() as c:
            return int(c.execute(select(func.max(schema_version.c.version))).scalar() or 0)


def _leg_row(leg: dict) -> dict:
    """A report's ``legs`` entry as a ``legs`` row (its columns only)."""
    return {c.name: leg.get(c.name) for c in legs.columns if c.name != "patrol_id"}


def _insert_new(conn: Connection, table):
    """An INSERT that skips a row whose key the table has already (both databases say
    ``ON CONFLICT DO NOTHING``)."""
    dialect = postgresql if conn.dialect.name == "postgresql" else sqlite
    return dialect.insert(table).on_conflict_do_nothing()


def open_history(url: str, option: str = "--history", create: bool = True, clock: Clock = utc_now,
                 connect_timeout: float = 5.0, spool: Spool | None = None) -> History | None:
    """The history ``url`` names, upgraded and proven writable; None for ``none``.

    InputError (one line naming ``option`` and the database) when it cannot be opened or
    written, is newer than this Lupin, or is not a history; with ``create=False`` also when a
    SQLite file does not exist (reading commands must not leave empty databases behind).

    With a ``spool`` (the robot's runtime) a server that does not answer, or refuses, is no
    error: the history opens unready, its writes wait in the spool, and the database is
    brought up to date when it first answers. A local SQLite file is still checked now."""
    target = parse_history_url(url, option)
    if target is None:
        return None
    where = f"{option} {target.shown}"
    if target.is_sqlite:
        _check_sqlite_path(target.path, where, create)
    engine = make_engine(target, connect_timeout)
    try:
        with engine.connect() as conn:
            conn = conn.execution_options(immediate=create)
            with conn.begin():
                before, after = migrate(conn)
                if create:  # a write proven now, not at the first pot: a read-only file or role fails here
                    conn.execute(update(schema_version).where(schema_version.c.version == after)
                                 .values(version=schema_version.c.version))
    except (NewerSchema, NotAHistory, SQLAlchemyError) as exc:
        why = str(exc) if isinstance(exc, (NewerSchema, NotAHistory)) else reason(exc)
        if spool is not None and not target.is_sqlite:
            log.error("history %s: %s; the robot runs on, its patrols kept in the spool %s until it answers",
                      target.shown, why, spool.path or "in memory (lost if the process ends)")
            history = History(engine, target, clock, spool, ready=False)
            history.outbox.down = why
            return history
        engine.dispose()
        if isinstance(exc, SQLAlchemyError):
            raise InputError(f"{where}: cannot open the history database: {why}") from None
        raise InputError(f"{where}: {why}") from None
    if before and before < after:
        log.warning("history %s upgraded from schema version %d to %d", target.shown, before, after)
    return History(engine, target, clock, spool)


def _check_sqlite_path(path: Path, where: str, create: bool) -> None:
    if path.is_dir():
        raise InputError(f"{where}: is a directory (give the database file)")
    if not path.exists():
        if not create:
            raise InputError(f"{where}: no history database there (a patrol creates it)")
        if not path.parent.is_dir():
            raise InputError(f"{where}: cannot create the history database: directory {path.parent} does not exist")


__all__ = ["FAILURES", "History", "HistoryError", "LATEST", "Unreachable", "open_history", "utc_now"]
