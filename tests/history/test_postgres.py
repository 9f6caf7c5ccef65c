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

    sync, me, other = Path({sync!r}), {robot!r}, {other!r}

    def barrier(name):          # lock-step with the other robot: neither goes on before both got here
        (sync / f"{{me}}-{{name}}").touch()
        while not (sync / f"{{other}}-{{name}}").exists():
            time.sleep(0.005)

    barrier("go")
    h = open_history({url!r})   # both open (and build) the new database at the same moment
    pots = [MissionPot(id=f"P{{k:03d}}", x=float(k % 20), y=float(k // 20), facing=0.0) for k in range({n})]
    m = Mission(name="shared", pots=pots)
    r = start_recording(h, m, me, None, Path({report!r}))
    for k, pot in enumerate(pots):
        entry = {{"id": pot.id, "status": "inspected", "tag_read": None, "images": [],
                  "flower": {{"color": "red", "blooms": 1, "bug": k % 7 == 0, "confidence": 0.9}}}}
        r.recorded(pot, entry, ["bug"] if k % 7 == 0 else [])
        if k % {chunk} == {chunk} - 1:
            assert r.drain()    # this chunk committed ...
            barrier(k)          # ... while the other robot's patrol is open and writing its own
    r.finished({{"outcome": "completed", "sim_time_s": 1.0, "distance_m": 2.0, "pots": []}})
    assert r.wait() and not r.errors, r.errors
    print(r.patrol_id)
""")


def test_two_robots_record_two_patrols_into_one_database_at_once(pg_url, tmp_path):
    """Two processes write their patrols in lock-step (a file barrier after every chunk of pots),
    so their transactions interleave; the database then shows the rows of the two patrols
    alternating in time, chunk by chunk, and every row of both there once, in order."""
    root, n, chunk = str(Path(__file__).resolve().parents[2]), 120, 10
    (tmp_path / "sync").mkdir()
    robots = ("mirte", "fred")
    procs = [subprocess.Popen([sys.executable, "-c", WRITER.format(
        root=root, sync=str(tmp_path / "sync"), url=pg_url, n=n, chunk=chunk, robot=robot, other=other,
        report=str(tmp_path / robot / "report.json"))], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for robot, other in zip(robots, reversed(robots))]
    outs = [p.communicate(timeout=180) for p in procs]
    for p, (out, err) in zip(procs, outs):
        assert p.returncode == 0, err
    ids = sorted(int(out.strip()) for out, _ in outs)
    h = open_history(pg_url, create=False)
    patrols = {p.id: p for p in h.patrols()}
    assert sorted(patrols) == ids and {p.robot for p in patrols.values()} == {"mirte", "fred"}
    timeline = []
    for pid in ids:
        rows = h.observations(pid)
        assert [o.seq for o in rows] == list(range(1, n + 1))  # every pot, in order, none lost
        assert sum(bool(o.bug) for o in rows) == len(range(0, n, 7))
        assert patrols[pid].outcome == "completed" and patrols[pid].ended_at is not None
        timeline += [(o.observed_at, patrols[pid].robot) for o in rows]
    by_time = [robot for _, robot in sorted(timeline)]
    switches = sum(a != b for a, b in zip(by_time, by_time[1:]))
    assert switches >= n // chunk - 1  # they overlapped: chunk after chunk, not one patrol then the other
    with psycopg.connect(pg_url) as c:  # built once, not twice
        assert [r[0] for r in c.execute("SELECT version FROM schema_version ORDER BY version")] == list(
            range(1, LATEST + 1))
    h.close()


def test_a_server_down_at_the_start_gets_the_patrol_when_it_comes_up(tmp_path, capsys, monkeypatch):
    """The robot opens its history while the farm server is down (nothing listens on its port):
    no error, the patrol is recorded into the spool; then a server comes up on that port and
    ``lupin history sync`` sends it, in order, once."""
    from lupin.bench.pg_server import PostgresServer, free_port
    from lupin.cli.patrol import open_patrol_history
    from mission.history.spool import open_spool
    from mission.runtime.config import load_config

    from .test_recorder import record, report_with_history, visit

    port = free_port()
    url = f"postgresql://lupin@127.0.0.1:{port}/postgres"
    monkeypatch.setenv("LUPIN_RUNTIME__STATE_DIR", str(tmp_path / "state"))
    h = open_patrol_history(load_config(), url)  # as lupin patrol and lupin serve open it
    assert h.outbox.down and "refused" in h.outbox.down
    r, mission, recorder = report_with_history(tmp_path, h)
    for pot, tag in (("P01", 1), ("P02", 2)):
        record(r, mission, pot, visit(pot, tag, bug=pot == "P02"))
    assert recorder.drain()  # both pots handed over before the report's last write counts the spool
    doc = r.finish("completed")
    assert not recorder.wait(retry=False) and doc["history"]["patrol"] is None and doc["history"]["spooled"] >= 3
    h.close()
    assert main(["history", "sync", "--history", url]) == 1  # still down: nothing lost
    assert open_spool(tmp_path / "state").rows(url) == 5
    server = PostgresServer(port=port)
    try:
        capsys.readouterr()
        assert main(["history", "status", "--history", url]) == 0
        assert "reachable: yes" in capsys.readouterr().out
        assert main(["history", "sync", "--history", url]) == 0
        assert main(["history", "sync", "--history", url]) == 0  # a second sync sends nothing twice
        db = open_history(url, create=False)
        [patrol] = db.patrols()
        assert patrol.outcome == "completed" and patrol.world == "unit-world"
        assert [(o.pot_id, o.seq, o.bug) for o in db.observations(patrol.id)] == [
            ("P01", 1, False), ("P02", 2, True), ("P03", 3, None)]
        db.close()
    finally:
        server.stop()
