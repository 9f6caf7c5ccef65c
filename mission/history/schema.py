"""The history's tables as they are now (spec/history.md is the contract; more columns welcome).

These objects are what queries are written against; :mod:`mission.history.migrations` is what
builds a database up to them, one numbered step at a time, and a test checks that the two agree.

Beyond the spec's columns (schema version 2 on):

- ``patrols.pots``: how many pots the mission lists, so a killed patrol shows how far it got;
- ``observations.facing``: the yaw of the pot's inspection side (measured when the pot was found
  moved), so a mission can be written back from the history (``lupin mission rescout``);
- ``observations.tag_expected``: the tag the mission expected there;
- ``patrols.uid`` (version 3): the patrol's own id, made by the robot when it starts (a UUID),
  unique: a patrol's rows can wait in the robot's spool while the server is down and be sent
  later, and a resend finds the patrol already there instead of writing it twice.
- ``legs`` (version 4): a patrol longer than one battery is one patrol in legs out from the
  dock (issue 31): when each left and came back (seconds into the patrol), the charge then
  (share of the pack), the pots it finished, why it came home, and the charge it waited for.

Timestamps are UTC: timezone-aware on PostgreSQL (``timestamptz``), ISO text on SQLite
(``2025-05-01 06:00:00.000000``, which sorts as time does). Ids are integers the database
gives, so several robots writing to one server never collide.
"""
from __future__ import annotations

from sqlalchemy import (Boolean, Column, DateTime, Float, ForeignKey, Index, Integer, MetaData, PrimaryKeyConstraint,
                        Table, Text)

metadata = MetaData()

schema_version = Table(
    "schema_version", metadata,
    Column("version", Integer, primary_key=True, autoincrement=False),
    Column("applied_at", DateTime(timezone=True), nullable=False),
    Column("description", Text, nullable=False),
)

patrols = Table(
    "patrols", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("robot", Text, nullable=False),
    Column("mission", Text, nullable=False),
    Column("world", Text),
    Column("started_at", DateTime(timezone=True), nullable=False),
    Column("ended_at", DateTime(timezone=True)),
    Column("outcome", Text),
    Column("sim_time_s", Float),
    Column("distance_m", Float),
    Column("report_path", Text),
    Column("pots", Integer),
    Column("uid", Text),
)

observations = Table(
    "observations", metadata,
    Column("patrol_id", Integer, ForeignKey("patrols.id", ondelete="CASCADE"), nullable=False),
    Column("pot_id", Text, nullable=False),
    Column("seq", Integer, nullable=False),
    Column("observed_at", DateTime(timezone=True), nullable=False),
    Column("status", Text, nullable=False),
    Column("tag_read", Integer),
    Column("flower_color", Text),
    Column("blooms", Integer),
    Column("bug", Boolean),
    Column("confidence", Float),
    Column("x", Float),
    Column("y", Float),
    Column("anomalies", Text, nullable=False, server_default=""),
    Column("front_image", Text),
    Column("wrist_image", Text),
    Column("facing", Float),
    Column("tag_expected", Integer),
    PrimaryKeyConstraint("patrol_id", "pot_id"),
    sqlite_with_rowid=False,
)

legs = Table(
    "legs", metadata,
    Column("patrol_id", Integer, ForeignKey("patrols.id", ondelete="CASCADE"), nullable=False),
    Column("leg", Integer, nullable=False),
    Column("left_s", Float),
    Column("charge_left", Float),
    Column("returned_s", Float),
    Column("charge_returned", Float),
    Column("pots", Integer),
    Column("why_home", Text),
    Column("charged_s", Float),
    Column("charge_after", Float),
    PrimaryKeyConstraint("patrol_id", "leg"),
    sqlite_with_rowid=False,
)

INDEXES = (
    Index("ix_observations_pot", observations.c.pot_id, observations.c.patrol_id),
    Index("ix_patrols_mission_started", patrols.c.mission, patrols.c.started_at),
    Index("ix_patrols_started", patrols.c.started_at),
)
"""What the grower's questions need at a year's size: one pot's timeline reads its rows by
``pot_id`` (not a scan of millions), "the last N patrols of a mission" reads the patrols index;
a patrol's own rows come by the primary key (patrol_id, pot_id)."""

UID_INDEX = Index("ux_patrols_uid", patrols.c.uid, unique=True)
"""A patrol sent twice (a resend from the spool) is one patrol (schema version 3)."""
