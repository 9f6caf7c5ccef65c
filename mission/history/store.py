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
"""
from __future__ import annotations

import logging
import sqlite3
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import Callable, Iterator, Sequence

from sqlalchemy import Connection, Engine, create_engine, event, func, select, update
from sqlalchemy.exc import SQLAlchemyError

from hw.errors import InputError
from mission.history import queries
from mission.history.migrations import LATEST, NewerSchema, NotAHistory, migrate
from mission.history.records import (ChangeSet, Observation, Patrol, PatrolStart, PestMap, TimelineEntry)
from mission.history.schema import observations, patrols, schema_version
from mission.history.url import HistoryTarget, parse_history_url

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

    def __init__(self, engine: Engine, target: HistoryTarget, clock: Clock = utc_now):
        self.engine, self.target, self.clock = engine, target, clock

    @property
    def shown(self) -> str:
        return self.target.shown

    @contextmanager
    def _writing(self) -> Iterator[Connection]:
        with self.engine.connect() as conn:
            conn = conn.execution_options(immediate=True)
            with conn.begin():
                yield conn

    @contextmanager
    def reading(self) -> Iterator[Connection]:
        """A connection in one transaction: a consistent view for a query or several."""
        with self.engine.connect() as conn, conn.begin():
            yield conn

    def close(self) -> None:
        self.engine.dispose()

    # --- writing a patrol -----------------------------------------------------------------
    def begin_patrol(self, start: PatrolStart, started_at: datetime | None = None) -> int:
        """Its ``patrols`` row (``ended_at`` null while it runs); the id."""
        with self._writing() as conn:
            r = conn.execute(patrols.insert().values(
                robot=start.robot, mission=start.mission, world=start.world, report_path=start.report_path,
                pots=start.pots, started_at=started_at or self.clock()).returning(patrols.c.id))
            return int(r.scalar_one())

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
    def patrol(self, patrol_id: int) -> Patrol | None:
        with self.reading() as c:
            return queries.patrol(c, patrol_id)

    def patrols(self, mission: str | None = None, robot: str | None = None, limit: int | None = None) -> list[Patrol]:
        with self.reading() as c:
            return queries.patrols(c, mission, robot, limit)

    def observations(self, patrol_id: int) -> list[Observation]:
        with self.reading() as c:
            return queries.observations(c, patrol_id)

    def pot_timeline(self, pot_id: str, mission: str | None = None) -> list[TimelineEntry]:
        with self.reading() as c:
            return queries.pot_timeline(c, pot_id, mission)

    def changes(self, mission: str | None = None) -> ChangeSet:
        with self.reading() as c:
            return queries.changes(c, mission)

    def pest_map(self, last: int, mission: str | None = None) -> PestMap:
        with self.reading() as c:
            return queries.pest_map(c, last, mission)

    def previous_observations(self, mission: str) -> tuple[Patrol | None, dict[str, Observation]]:
        with self.reading() as c:
            return queries.previous_observations(c, mission)

    def pots_known(self, mission: str | None = None) -> list[str]:
        with self.reading() as c:
            return queries.pots_known(c, mission)

    def latest_mission(self) -> str | None:
        with self.reading() as c:
            return queries.latest_mission(c)

    def version(self) -> int:
        with self.reading() as c:
            return int(c.execute(select(func.max(schema_version.c.version))).scalar() or 0)


def open_history(url: str, option: str = "--history", create: bool = True, clock: Clock = utc_now,
                 connect_timeout: float = 5.0) -> History | None:
    """The history ``url`` names, upgraded and proven writable; None for ``none``.

    InputError (one line naming ``option`` and the database) when it cannot be opened or
    written, is newer than this Lupin, or is not a history; with ``create=False`` also when a
    SQLite file does not exist (reading commands must not leave empty databases behind)."""
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
    except (NewerSchema, NotAHistory) as exc:
        engine.dispose()
        raise InputError(f"{where}: {exc}") from None
    except SQLAlchemyError as exc:
        engine.dispose()
        raise InputError(f"{where}: cannot open the history database: {reason(exc)}") from None
    if before and before < after:
        log.warning("history %s upgraded from schema version %d to %d", target.shown, before, after)
    return History(engine, target, clock)


def _check_sqlite_path(path: Path, where: str, create: bool) -> None:
    if path.is_dir():
        raise InputError(f"{where}: is a directory (give the database file)")
    if not path.exists():
        if not create:
            raise InputError(f"{where}: no history database there (a patrol creates it)")
        if not path.parent.is_dir():
            raise InputError(f"{where}: cannot create the history database: directory {path.parent} does not exist")


__all__ = ["History", "HistoryError", "LATEST", "open_history", "utc_now"]
