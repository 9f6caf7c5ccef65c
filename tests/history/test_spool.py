"""The history never stops the robot (spec/history.md, issue 29): while the database does not
answer, a patrol's writes wait in the spool (a SQLite file in the state directory) and reach the
database in order when it answers, nothing lost and nothing doubled; a resend is a no-op; the
spool outlives the process and ``lupin history sync`` empties it; ``lupin history status`` says
where the history is, whether it answers and what waits."""
from __future__ import annotations

import json
from datetime import timedelta

import pytest

from lupin.cli import main
from mission.history.records import PatrolStart
from mission.history.spool import FILE_NAME, Spool, open_spool
from mission.history.store import Unreachable, open_history
from mission.history.writes import Begin, End, Rows, from_json, new_uid

from .conftest import T0, obs
from .test_recorder import record, report_with_history, visit


class StepClock:
    """The runtime's clock as the fault hook reads it (seconds), moved by the test."""

    def __init__(self):
        self.t = 0.0

    def now(self) -> float:
        return self.t


def writes_of(uid: str, pots: list[str]):
    return [Begin(uid, PatrolStart("mirte", "m", "w", None, len(pots)), T0),
            Rows(uid, tuple(obs(p, seq=k + 1, bug=k == 1) for k, p in enumerate(pots))),
            End(uid, "completed", 10.0, 2.0, T0 + timedelta(minutes=5))]


def test_a_write_keeps_its_meaning_through_the_spool_file(tmp_path):
    uid = new_uid()
    spool = Spool(tmp_path / FILE_NAME)
    spool.append("db", writes_of(uid, ["P01", "P02"]))
    spool.close()
    again = open_spool(tmp_path)  # another process, later
    kept = [w for _, w in again.oldest("db", 10)]
    assert kept == writes_of(uid, ["P01", "P02"]) and again.count("db") == 3 and again.rows("db") == 4
    assert again.count("other") == 0 and again.databases() == {"db": 3}
    with pytest.raises(ValueError):
        from_json({"op": "drop"})


def test_a_resend_is_a_no_op(tmp_path):
    h = open_history(str(tmp_path / "h.db"))
    uid = new_uid()
    h.deliver(writes_of(uid, ["P01", "P02"]))
    h.deliver(writes_of(uid, ["P01", "P02"]))  # the spool sent it again (a crash before it forgot it)
    h.deliver(writes_of(uid, ["P01"])[:2])
    [patrol] = h.patrols()
    assert patrol.id == h.patrol_id(uid) and patrol.observed == 2 and patrol.outcome == "completed"
    assert [(o.pot_id, o.seq, o.bug) for o in h.observations(patrol.id)] == [("P01", 1, False), ("P02", 2, True)]
    h.close()


def test_an_outage_mid_patrol_spools_the_rows_and_delivers_them_in_order_when_it_ends(tmp_path):
    clock, spool = StepClock(), open_spool(tmp_path)
    h = open_history(str(tmp_path / "h.db"), spool=spool)
    r, mission, recorder = report_with_history(tmp_path, h)
    record(r, mission, "P01", visit("P01", 1))
    assert recorder.drain() and h.outbox.waiting == 0
    h.outage_until(30.0, clock.now)  # spec/events.md history_down at t=0 for 30 s
    record(r, mission, "P02", visit("P02", 2, bug=True))
    assert recorder.drain()
    assert spool.count(h.shown) == 1
    with pytest.raises(Unreachable):  # reads fail too while it is down, at once
        h.observations(recorder.patrol_id)
    assert h.outbox.down is not None and recorder.errors
    clock.t = 10.0
    record(r, mission, "P03", visit("P03", 3))  # still down: queued behind P02
    assert recorder.drain() and spool.rows(h.shown) == 2
    clock.t = 30.0  # the database answers again
    doc = r.finish("completed")
    assert doc["history"]["spooled"] == 2 and doc["history"]["write_errors"] == 2
    assert recorder.wait()
    assert spool.count(h.shown) == 0 and h.outbox.down is None and h.outbox.delivered == 3
    rows = h.observations(recorder.patrol_id)
    assert [(o.pot_id, o.seq, o.bug) for o in rows] == [("P01", 1, False), ("P02", 2, True), ("P03", 3, False)]
    assert h.patrol(recorder.patrol_id).outcome == "completed" and len(h.patrols()) == 1
    h.close()


def test_a_database_down_at_the_start_gets_the_whole_patrol_later_and_sync_sends_it(tmp_path, capsys, monkeypatch):
    """The spool outlives the process: a patrol recorded entirely while the database was down
    is sent by ``lupin history sync`` in another run, once; ``status`` says what waits."""
    monkeypatch.setenv("LUPIN_RUNTIME__STATE_DIR", str(tmp_path / "state"))
    (tmp_path / "state").mkdir()
    db = str(tmp_path / "h.db")
    clock = StepClock()
    h = open_history(db, spool=open_spool(tmp_path / "state"))
    h.outage_until(1e9, clock.now)  # down from before the start to after the end
    r, mission, recorder = report_with_history(tmp_path, h)
    assert recorder.patrol_id is None
    for pot, tag in (("P01", 1), ("P02", 2)):
        record(r, mission, pot, visit(pot, tag))
        assert recorder.drain()  # one write a pot: a writer behind the patrol would send both as one
    r.finish("completed")
    assert not recorder.wait()  # not in the database: it waits in the spool
    h.close()
    capsys.readouterr()
    assert main(["history", "status", "--history", db, "--json"]) == 0
    status = json.loads(capsys.readouterr().out)
    assert status["reachable"] is True and status["spool"] == str(tmp_path / "state" / FILE_NAME)
    assert status["waiting"] == 5 and status["rows_waiting"] == 5  # the start, P01, P02, P03 skipped, the end
    assert main(["history", "sync", "--history", db]) == 0
    assert "5 row(s) sent" in capsys.readouterr().out
    assert main(["history", "sync", "--history", db]) == 0  # nothing left: a no-op
    again = open_history(db, create=False)
    [patrol] = again.patrols()
    assert patrol.outcome == "completed" and patrol.world == "unit-world"
    assert [(o.pot_id, o.seq, o.status) for o in again.observations(patrol.id)] == [
        ("P01", 1, "inspected"), ("P02", 2, "inspected"), ("P03", 3, "skipped")]
    again.close()
    assert main(["history", "status", "--history", db]) == 0
    out = capsys.readouterr().out
    assert f"history: {db}" in out and "reachable: yes" in out and "0 row(s) waiting" in out


def test_status_says_an_unreachable_server_and_sync_fails_without_losing_anything(tmp_path, capsys, monkeypatch):
    from lupin.bench.pg_server import free_port

    monkeypatch.setenv("LUPIN_RUNTIME__STATE_DIR", str(tmp_path))
    url = f"postgresql://lupin@127.0.0.1:{free_port()}/farm"  # nothing listens there
    spool = open_spool(tmp_path)
    spool.append(url, writes_of(new_uid(), ["P01"]))
    assert main(["history", "status", "--history", url]) == 0
    out = capsys.readouterr().out
    assert "reachable: no (" in out and "1 row(s) waiting" not in out and "3 row(s) waiting (3 write(s))" in out
    assert main(["history", "sync", "--history", url]) == 1
    assert "3 write(s) still wait" in capsys.readouterr().out and spool.count(url) == 3
    assert main(["history", "status", "--history", "postgresql://x@h:notaport/db"]) == 2  # malformed: bad input


def test_a_sim_run_without_a_state_directory_spools_in_memory_and_leaves_no_directory(tmp_path, capsys, monkeypatch):
    """A sim run's own state directory is fresh and thrown away, so no later command could find a
    spool there: it is kept in memory, and nothing is left in the temp dir (one per patrol, before)."""
    import tempfile

    from mission.history.spool import runtime_spool
    from mission.runtime.settings import RuntimeConfig

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    spool = runtime_spool(RuntimeConfig(), "sim")
    spool.append("db", writes_of(new_uid(), ["P01"]))
    assert spool.path is None and spool.count("db") == 3 and list(tmp_path.iterdir()) == []
    kept = runtime_spool(RuntimeConfig(state_dir=str(tmp_path / "kept")), "sim")
    assert kept.path == tmp_path / "kept" / FILE_NAME  # named: it outlives the run
    db = str(tmp_path / "h.db")
    open_history(db).close()
    assert main(["history", "status", "--history", db, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["spool"] is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.db", "kept"]
