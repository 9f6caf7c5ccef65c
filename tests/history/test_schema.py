"""The history's schema and its migrations: a new database is built to the latest version and
matches ``mission.history.schema``; an older one is upgraded in place with its rows kept; a newer
one, or a database that is not a history, is refused with one clear line; where it lives
(``--history`` values) is parsed as spec/history.md says."""
from __future__ import annotations

import sqlite3

import pytest
from sqlalchemy import create_engine, inspect

from hw.errors import InputError
from mission.history import schema
from mission.history.migrations import LATEST, MIGRATIONS, migrate
from mission.history.store import make_engine, open_history
from mission.history.url import parse_history_url

from .conftest import add_patrol, obs

SPEC_PATROLS = {"id", "robot", "mission", "world", "started_at", "ended_at", "outcome", "sim_time_s", "distance_m",
                "report_path"}
SPEC_OBSERVATIONS = {"patrol_id", "pot_id", "seq", "observed_at", "status", "tag_read", "flower_color", "blooms", "bug",
                     "confidence", "x", "y", "anomalies", "front_image", "wrist_image"}


def test_a_new_database_is_built_to_the_latest_version_with_the_spec_tables(tmp_path):
    h = open_history(str(tmp_path / "h.db"))
    assert h.version() == LATEST >= 2
    insp = inspect(h.engine)
    for table in (schema.patrols, schema.observations, schema.schema_version, schema.legs):
        assert {c["name"] for c in insp.get_columns(table.name)} == set(table.c.keys())  # migrations == schema.py
    assert SPEC_PATROLS <= set(schema.patrols.c.keys())
    assert SPEC_OBSERVATIONS <= set(schema.observations.c.keys())
    names = {i["name"] for t in ("patrols", "observations") for i in insp.get_indexes(t)}
    assert {i.name for i in schema.INDEXES} <= names
    h.close()


def _v1_database(path) -> None:
    """A database as the first Lupin with a history left it, with a patrol in it."""
    engine = create_engine(f"sqlite:///{path}")
    with engine.begin() as conn:
        migrate(conn, up_to=1)
    with engine.begin() as conn:
        conn.exec_driver_sql("INSERT INTO patrols (id, robot, mission, world, started_at, ended_at, outcome) VALUES "
                             "(1, 'mirte', 'm', 'w', '2025-05-01 06:00:00.000000', NULL, NULL)")
        conn.exec_driver_sql("INSERT INTO observations (patrol_id, pot_id, seq, observed_at, status, flower_color, "
                             "blooms, bug, x, y, anomalies) VALUES (1, 'P01', 1, '2025-05-01 06:01:00.000000', "
                             "'inspected', 'red', 2, 1, 1.5, 0.5, 'bug')")
    engine.dispose()


def test_an_older_database_is_upgraded_in_place_and_keeps_its_rows(tmp_path):
    path = tmp_path / "old.db"
    _v1_database(path)
    assert sqlite3.connect(path).execute("SELECT max(version) FROM schema_version").fetchone() == (1,)
    h = open_history(str(path))
    assert h.version() == LATEST
    [entry] = h.pot_timeline("P01")
    o = entry.observation
    assert (o.flower_color, o.blooms, o.bug, o.x, o.anomalies) == ("red", 2, True, 1.5, ("bug",))
    assert o.facing is None and o.tag_expected is None  # added by version 2, unknown for old rows
    assert h.patrols()[0].ended_at is None  # the killed patrol stays unfinished
    versions = [r[0] for r in sqlite3.connect(path).execute("SELECT version FROM schema_version ORDER BY version")]
    assert versions == [m.version for m in MIGRATIONS]
    add_patrol(h, [obs("P01", bug=False)])  # and it takes new rows
    assert len(h.pot_timeline("P01")) == 2
    h.close()


def test_a_newer_database_is_refused_with_a_clear_message(tmp_path):
    path = tmp_path / "new.db"
    open_history(str(path)).close()
    with sqlite3.connect(path) as c:
        c.execute("INSERT INTO schema_version VALUES (?, '2031-01-01 00:00:00', 'from the future')", (LATEST + 1,))
    with pytest.raises(InputError) as err:
        open_history(str(path))
    msg = str(err.value)
    assert f"version {LATEST + 1}" in msg and "newer" in msg and str(path) in msg and "\n" not in msg
    with sqlite3.connect(path) as c:  # untouched
        assert c.execute("SELECT max(version) FROM schema_version").fetchone() == (LATEST + 1,)


def test_a_database_that_is_not_a_history_is_refused(tmp_path):
    path = tmp_path / "other.db"
    with sqlite3.connect(path) as c:
        c.execute("CREATE TABLE plants (name TEXT)")
    with pytest.raises(InputError, match="not a Lupin history database"):
        open_history(str(path))


def test_a_file_that_is_not_a_database_is_one_clear_line(tmp_path):
    path = tmp_path / "notes.db"
    path.write_text("these are my notes, not a database\n" * 50)
    with pytest.raises(InputError) as err:
        open_history(str(path))
    assert "cannot open the history database" in str(err.value) and str(path) in str(err.value)


def test_places_that_cannot_hold_a_database(tmp_path):
    with pytest.raises(InputError, match="is a directory"):
        open_history(str(tmp_path))
    with pytest.raises(InputError, match="does not exist"):
        open_history(str(tmp_path / "no" / "such" / "h.db"))
    with pytest.raises(InputError, match="no history database there"):
        open_history(str(tmp_path / "absent.db"), create=False)
    assert not (tmp_path / "absent.db").exists()  # reading never leaves an empty database behind


def test_history_urls():
    assert parse_history_url("none") is None and parse_history_url("NONE") is None
    t = parse_history_url("lupin-history.db")
    assert t.is_sqlite and t.path.name == "lupin-history.db"
    assert parse_history_url("sqlite:////var/lib/lupin/h.db").path.as_posix() == "/var/lib/lupin/h.db"
    pg = parse_history_url("postgresql://grower:secret@farm.local:5432/lupin")
    assert not pg.is_sqlite and pg.url.drivername == "postgresql+psycopg"
    assert "secret" not in pg.shown and pg.shown.startswith("postgresql://grower:***@farm.local")
    for bad, why in (("mysql://x@y/z", "not a history database"), ("sqlite://", "in-memory"),
                     ("postgresql://x@y", "name the database"), ("", "empty")):
        with pytest.raises(InputError, match=why):
            parse_history_url(bad)


def test_the_sqlite_engine_journals_ahead_so_readers_never_block_the_patrol(tmp_path):
    h = open_history(str(tmp_path / "h.db"))
    with h.engine.connect() as c:
        assert c.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert c.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
    h.close()
    assert make_engine(parse_history_url(str(tmp_path / "h.db"))).dialect.name == "sqlite"
