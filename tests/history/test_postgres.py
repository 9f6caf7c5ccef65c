"""The history on a real PostgreSQL 15 server (started on loopback for these tests, see
conftest): the same schema and questions as on SQLite, a role that cannot write refused before
anything moves, and two robots recording two patrols into one database at once."""
from __future__ import annotations

import subprocess
import sys
import textwrap
from datetime import timedelta
from pathlib import Path

import psycopg
import pytest
from sqlalchemy import inspect

from hw.errors import InputError
from lupin.cli import main
from mission.history import schema
from mission.history.migrations import LATEST
from mission.history.store import open_history

from .conftest import T0, add_patrol, obs


def test_the_schema_and_the_questions_on_postgresql(pg_url, capsys):
    h = open_history(pg_url)
    assert h.version() == LATEST
    insp = inspect(h.engine)
    for table in (schema.patrols, schema.observations):
        assert {c["name"] for c in insp.get_columns(table.name)} == set(table.c.keys())
    add_patrol(h, [obs("P01", x=0, y=0), obs("P02", x=1, y=0)], started=T0)
    add_patrol(h, [obs("P01", x=0, y=0, bug=True), obs("P02", x=1, y=0, status="failed")],
               started=T0 + timedelta(hours=6))
    assert [(c.pot, c.kind) for c in h.changes().changes] == [("P01", "pest_new"), ("P02", "failed")]
    assert [e.observation.bug for e in h.pot_timeline("P01")] == [False, True]
    assert h.pot_timeline("P01")[0].started_at == T0  # timestamptz, UTC
    assert main(["history", "pests", "--history", pg_url]) == 0
    assert "1 of 2 pots with a pest" in capsys.readouterr().out
    h.close()
    again = open_history(pg_url)  # opening a current database changes nothing
    assert again.version() == LATEST and len(again.patrols()) == 2
    again.close()


def test_a_role_that_cannot_write_is_refused_before_anything_moves(pg_url):
    open_history(pg_url).close()
    with psycopg.connect(pg_url, autocommit=True) as c:
        c.execute("CREATE ROLE reader LOGIN")
        c.execute("GRANT SELECT ON ALL TABLES IN SCHEMA public TO reader")
    reader = pg_url.replace("postgresql://lupin@", "postgresql://reader@")
    with pytest.raises(InputError) as err:
        open_history(reader)
    assert "cannot open the history database" in str(err.value) and "permission denied" in str(err.value)
    readable = open_history(reader, create=False)  # reading needs no write
    assert readable.patrols() == []
    readable.close()


def test_a_newer_database_on_the_server_is_refused(pg_url):
    open_history(pg_url).close()
    with psycopg.connect(pg_url, autocommit=True) as c:
        c.execute("INSERT INTO schema_version VALUES (%s, now(), 'future')", (LATEST + 1,))
    with pytest.raises(InputError, match="newer than this Lupin"):
        open_history(pg_url)


WRITER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    sys.path.insert(0, {root!r})
    from mission.history.recorder import start_recording
    from mission.history.store import open_history
    from mission.patrol.mission_file import Mission, MissionPot

    go = Path({go!r})
    while not go.exists():      # both writers start together
        time.sleep(0.01)
    h = open_history({url!r})   # both open (and build) the new database at the same moment
    pots = [MissionPot(id=f"P{{k:03d}}", x=float(k % 20), y=float(k // 20), facing=0.0) for k in range({n})]
    m = Mission(name="shared", pots=pots)
    r = start_recording(h, m, {robot!r}, None, Path({report!r}))
    for k, pot in enumerate(pots):
        entry = {{"id": pot.id, "status": "inspected", "tag_read": None, "images": [],
                  "flower": {{"color": "red", "blooms": 1, "bug": k % 7 == 0, "confidence": 0.9}}}}
        r.recorded(pot, entry, ["bug"] if k % 7 == 0 else [])
        if k % 10 == 0:
            r.drain()           # interleave the two robots' transactions
    r.finished({{"outcome": "completed", "sim_time_s": 1.0, "distance_m": 2.0, "pots": []}})
    assert r.wait() and not r.errors, r.errors
    print(r.patrol_id)
""")


def test_two_robots_record_two_patrols_into_one_database_at_once(pg_url, tmp_path):
    root, go, n = str(Path(__file__).resolve().parents[2]), tmp_path / "go", 120
    procs = [subprocess.Popen([sys.executable, "-c", WRITER.format(root=root, go=str(go), url=pg_url, n=n, robot=robot,
                                                                     report=str(tmp_path / robot / "report.json"))],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for robot in ("mirte", "fred")]
    go.touch()
    outs = [p.communicate(timeout=180) for p in procs]
    for p, (out, err) in zip(procs, outs):
        assert p.returncode == 0, err
    ids = sorted(int(out.strip()) for out, _ in outs)
    h = open_history(pg_url, create=False)
    patrols = {p.id: p for p in h.patrols()}
    assert sorted(patrols) == ids and {p.robot for p in patrols.values()} == {"mirte", "fred"}
    for pid in ids:
        rows = h.observations(pid)
        assert [o.seq for o in rows] == list(range(1, n + 1))  # every pot, in order, none lost
        assert sum(bool(o.bug) for o in rows) == len(range(0, n, 7))
        assert patrols[pid].outcome == "completed" and patrols[pid].ended_at is not None
    with psycopg.connect(pg_url) as c:  # built once, not twice
        assert [r[0] for r in c.execute("SELECT version FROM schema_version ORDER BY version")] == list(
            range(1, LATEST + 1))
    h.close()
