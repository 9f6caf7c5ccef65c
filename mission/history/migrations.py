"""Versioned schema migrations: an older history database is upgraded in place, a newer one is
refused.

``schema_version`` holds one row per step applied (its number, when, what). Opening a database
runs, in one transaction, every step above the highest applied one; on PostgreSQL under an
advisory lock and on SQLite under the write lock (``BEGIN IMMEDIATE``), so two robots opening a
new database at once do not both build it. DDL is transactional on both, so a step that fails
leaves the database as it was.

A database whose version is above :data:`LATEST` was written by a newer Lupin: it is refused
(:class:`NewerSchema`) rather than written with columns this one does not know. One with tables
but no ``schema_version`` is not a Lupin history and is refused too.

Each step builds exactly what it added, with its own table objects (never the current ones in
:mod:`mission.history.schema`, which would drift as steps are added); a test checks that every
step applied in turn gives the tables ``schema`` describes.
"""
from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime, timezone
from typing import Callable

from sqlalchemy import (Boolean, Column, Connection, DateTime, Float, ForeignKey, Integer, MetaData,
                        PrimaryKeyConstraint, Table, Text, func, inspect, select, text)

from mission.history import schema


class NewerSchema(Exception):
    """The database was made by a newer Lupin."""


class NotAHistory(Exception):
    """The database holds tables, but not a Lupin history's."""


@dataclass(frozen=True)
class Migration:
    version: int
    description: str
    apply: Callable[[Connection], None]


def _v1(conn: Connection) -> None:
    """spec/history.md's two tables, and the version table."""
    md = MetaData()
    Table("schema_version", md,
          Column("version", Integer, primary_key=True, autoincrement=False),
          Column("applied_at", DateTime(timezone=True), nullable=False),
          Column("description", Text, nullable=False))
    Table("patrols", md,
          Column("id", Integer, primary_key=True, autoincrement=True),
          Column("robot", Text, nullable=False), Column("mission", Text, nullable=False), Column("world", Text),
          Column("started_at", DateTime(timezone=True), nullable=False), Column("ended_at", DateTime(timezone=True)),
          Column("outcome", Text), Column("sim_time_s", Float), Column("distance_m", Float),
          Column("report_path", Text))
    Table("observations", md,
          Column("patrol_id", Integer, ForeignKey("patrols.id", ondelete="CASCADE"), nullable=False),
          Column("pot_id", Text, nullable=False), Column("seq", Integer, nullable=False),
          Column("observed_at", DateTime(timezone=True), nullable=False), Column("status", Text, nullable=False),
          Column("tag_read", Integer), Column("flower_color", Text), Column("blooms", Integer), Column("bug", Boolean),
          Column("confidence", Float), Column("x", Float), Column("y", Float),
          Column("anomalies", Text, nullable=False, server_default=""),
          Column("front_image", Text), Column("wrist_image", Text),
          PrimaryKeyConstraint("patrol_id", "pot_id"), sqlite_with_rowid=False)
    md.create_all(conn)


def _v2(conn: Connection) -> None:
    """The indexes a year of patrols needs (``schema.INDEXES``), the mission's pot count, and
    each pot's facing and expected tag (a mission can be written back from the history)."""
    for table, column, kind in (("patrols", "pots", "INTEGER"), ("observations", "facing", "DOUBLE PRECISION"),
                                ("observations", "tag_expected", "INTEGER")):
        kind = "REAL" if kind == "DOUBLE PRECISION" and conn.dialect.name == "sqlite" else kind
        conn.exec_driver_sql(f"ALTER TABLE {table} ADD COLUMN {column} {kind}")
    for index in schema.INDEXES:
        index.create(conn)


def _v3(conn: Connection) -> None:
    """``patrols.uid``, unique: the id a robot gives its patrol, so rows sent again from its spool
    are a no-op (spec/history.md)."""
    conn.exec_driver_sql("ALTER TABLE patrols ADD COLUMN uid TEXT")
    conn.exec_driver_sql("CREATE UNIQUE INDEX ux_patrols_uid ON patrols (uid)")


def _v4(conn: Connection) -> None:
    """``legs``: a patrol's trips out from the dock between charges (issue 31)."""
    md = MetaData()
    Table("patrols", md, Column("id", Integer, primary_key=True))  # only what the foreign key names
    legs = Table("legs", md,
                 Column("patrol_id", Integer, ForeignKey("patrols.id", ondelete="CASCADE"), nullable=False),
                 Column("leg", Integer, nullable=False), Column("left_s", Float), Column("charge_left", Float),
                 Column("returned_s", Float), Column("charge_returned", Float), Column("pots", Integer),
                 Column("why_home", Text), Column("charged_s", Float), Column("charge_after", Float),
                 PrimaryKeyConstraint("patrol_id", "leg"), sqlite_with_rowid=False)
    legs.create(conn)


MIGRATIONS: tuple[Migration, ...] = (
    Migration(1, "patrols and observations (spec/history.md)", _v1),
    Migration(2, "indexes for a year of patrols; patrols.pots, observations.facing and tag_expected", _v2),
    Migration(3, "patrols.uid: the robot's id of a patrol, unique (a resend from the spool is a no-op)", _v3),
    Migration(4, "legs: a patrol's trips out from the dock between charges", _v4),
)
LATEST = MIGRATIONS[-1].version
ADVISORY_LOCK = 0x1A9_0C0DE
"""PostgreSQL advisory lock key held while migrating (any constant unique to Lupin)."""


def current_version(conn: Connection) -> int:
    """The highest step applied; 0 for an empty database. NotAHistory when it holds other tables."""
    tables = inspect(conn).get_table_names()
    if "schema_version" not in tables:
        if tables:
            raise NotAHistory(f"not a Lupin history database (it has tables {', '.join(sorted(tables)[:5])} "
                              f"but no schema_version)")
        return 0
    return conn.execute(select(func.max(schema.schema_version.c.version))).scalar() or 0


def check_version(version: int) -> None:
    if version > LATEST:
        raise NewerSchema(f"history schema version {version} is newer than this Lupin knows ({LATEST}): "
                          f"it was written by a newer Lupin; upgrade Lupin to use it")


def migrate(conn: Connection, up_to: int = LATEST, now: Callable[[], datetime] | None = None) -> tuple[int, int]:
    """Bring the database to version ``up_to`` inside the caller's transaction; (from, to)."""
    if conn.dialect.name == "postgresql":
        conn.execute(text("SELECT pg_advisory_xact_lock(:k)"), {"k": ADVISORY_LOCK})
    before = current_version(conn)
    check_version(before)
    now = now or (lambda: datetime.now(timezone.utc))
    for step in MIGRATIONS:
        if before < step.version <= up_to:
            step.apply(conn)
            conn.execute(schema.schema_version.insert().values(version=step.version, applied_at=now(),
                                                               description=step.description))
    return before, max(before, min(up_to, LATEST))
