"""A patrol written into the history as it goes, through the real report (synthetic visits, no
sim): each pot's row when it is recorded, the pots never reached as ``skipped`` and the outcome at
the end, ``report.json``'s ``changes`` against the previous patrol of the mission; a write that
fails is logged loudly, kept and written later, and never costs the report; a killed patrol
leaves its finished pots and ``ended_at`` null."""
from __future__ import annotations

import json
import logging
import signal
import subprocess
import sys
import textwrap
from datetime import timedelta
from pathlib import Path

import numpy as np

from behaviours.visit import PotVisit
from hw.odometry import Pose2D
from lupin.cli import main
from mission.history.recorder import start_recording
from mission.patrol.climate import NoClimate
from mission.patrol.config import PatrolConfig
from mission.patrol.mission_file import parse_mission
from mission.patrol.report import PatrolReport
from perception.camera_pipeline import Frame
from perception.detections import Bloom, FlowerFrame, TagRead

from .conftest import T0, add_patrol, obs

MISSION = {"name": "unit", "pots": [{"id": f"P0{k}", "x": float(k), "y": 0.5, "facing": -1.5708, "tag": k}
                                    for k in (1, 2, 3)]}


def visit(pot: str, tag: int, bug: bool = False, blooms: int = 1) -> PotVisit:
    v = PotVisit(pot, attempts=1, arrived=Pose2D(1.0, 0.0, 1.5708))
    frame = Frame(0.0, np.full((48, 64, 3), 100, np.uint8), "cam")
    v.wrist, v.flower = frame, FlowerFrame(tuple(Bloom("red", (32.0, 24.0), 900, 0.9, bug) for _ in range(blooms)))
    v.front, v.tags = frame, (TagRead(tag, (), (0.0, 0.0, 0.27), (np.pi, 0.0, 0.0), 0.0, 0.1),)
    return v


def report_with_history(tmp_path: Path, history):
    mission = parse_mission(MISSION, "unit.yaml")
    r = PatrolReport(tmp_path / "run" / "report.json", mission, PatrolConfig(), NoClimate(), lambda: 10.0,
                     lambda: 0.0, lambda: 3.5)
    recorder = start_recording(history, mission, "mirte", "unit-world", r.path)
    r.observers.append(recorder)
    return r, mission, recorder


def record(r, mission, pot: str, v: PotVisit) -> None:
    p = next(p for p in mission.pots if p.id == pot)
    r.record(p, v, Pose2D(p.x, p.y - 0.5, 1.5708))


def test_each_pot_is_a_row_when_recorded_and_the_end_completes_the_patrol(tmp_path, sqlite_history):
    h = sqlite_history
    previous = add_patrol(h, [obs("P01", bug=False, blooms=1), obs("P02", blooms=1)], mission="unit",
                          started=T0 - timedelta(hours=6), world="unit-world")
    r, mission, recorder = report_with_history(tmp_path, h)
    record(r, mission, "P01", visit("P01", 1, bug=True, blooms=2))
    assert recorder.drain()
    [patrol] = [p for p in h.patrols() if p.id == recorder.patrol_id]
    assert patrol.ended_at is None and patrol.outcome is None and patrol.pots == 3 and patrol.world == "unit-world"
    [row] = h.observations(recorder.patrol_id)  # written as the patrol goes
    assert (row.pot_id, row.seq, row.status, row.bug, row.blooms, row.tag_read) == ("P01", 1, "inspected", True, 2, 1)
    assert set(row.anomalies) == {"bug"} and Path(row.wrist_image).is_absolute()
    assert Path(row.wrist_image) == tmp_path / "run" / "P01_wrist.jpg" and Path(row.wrist_image).exists()
    doc = json.loads(r.path.read_text())  # the report already carries the pot's changes
    assert doc["changes_since"]["patrol"] == previous
    assert [(c["pot"], c["kind"]) for c in doc["changes"]] == [("P01", "pest_new"), ("P01", "blooms")]

    record(r, mission, "P02", visit("P02", 2))
    doc = r.finish("aborted")
    assert recorder.wait()
    rows = h.observations(recorder.patrol_id)
    assert [(o.pot_id, o.seq, o.status) for o in rows] == [("P01", 1, "inspected"), ("P02", 2, "inspected"),
                                                             ("P03", 3, "skipped")]
    patrol = h.patrol(recorder.patrol_id)
    assert patrol.outcome == "aborted" and patrol.ended_at is not None and patrol.distance_m == 3.5
    assert doc["history"] == {"database": h.shown, "patrol": recorder.patrol_id, "write_errors": 0, "spooled": 0}
    assert [c["kind"] for c in doc["changes"]] == ["pest_new", "blooms"]  # P02 did not change


def test_a_first_patrol_has_no_changes(tmp_path, sqlite_history):
    r, mission, recorder = report_with_history(tmp_path, sqlite_history)
    record(r, mission, "P01", visit("P01", 1))
    doc = r.finish("completed")
    assert doc["changes"] == [] and doc["changes_since"] is None
    assert recorder.wait()


def test_a_write_failure_is_loud_never_costs_the_report_and_is_written_later(tmp_path, sqlite_history, caplog):
    import sqlite3

    r, mission, recorder = report_with_history(tmp_path, sqlite_history)
    record(r, mission, "P01", visit("P01", 1))
    assert recorder.drain()
    db = sqlite3.connect(sqlite_history.target.path)
    db.execute("ALTER TABLE observations RENAME TO observations_away")  # the database breaks mid-patrol
    db.commit()
    with caplog.at_level(logging.ERROR, logger="lupin.history"):
        record(r, mission, "P02", visit("P02", 2, bug=True))
        assert recorder.drain()
    errors = [rec for rec in caplog.records if rec.levelno >= logging.ERROR]
    assert errors and "P02" in errors[0].getMessage() and "report.json has everything" in errors[0].getMessage()
    doc = json.loads(r.path.read_text())
    assert [p["id"] for p in doc["pots"]] == ["P01", "P02"]  # the report lost nothing
    db.execute("ALTER TABLE observations_away RENAME TO observations")  # the database is back
    db.commit()
    doc = r.finish("completed")
    assert doc["history"]["write_errors"] >= 1  # the final report says the history had trouble
    assert recorder.wait()
    rows = sqlite_history.observations(recorder.patrol_id)
    assert [(o.pot_id, o.bug) for o in rows] == [("P01", False), ("P02", True), ("P03", None)]  # kept, then written
    assert sqlite_history.patrol(recorder.patrol_id).outcome == "completed"


KILLED = textwrap.dedent("""
    import os, signal, sys
    from pathlib import Path
    sys.path.insert(0, {root!r})
    from tests.history.test_recorder import report_with_history, record, visit
    from mission.history.store import open_history
    h = open_history({db!r})
    r, mission, recorder = report_with_history(Path({tmp!r}), h)
    record(r, mission, "P01", visit("P01", 1))
    record(r, mission, "P02", visit("P02", 2, bug=True))
    assert recorder.drain()
    os.kill(os.getpid(), signal.SIGKILL)   # no finish, no close: the process is gone
""")


def test_a_killed_patrol_leaves_its_finished_pots_and_no_end(tmp_path, capsys):
    db = tmp_path / "h.db"
    root = str(Path(__file__).resolve().parents[2])
    done = subprocess.run([sys.executable, "-c", KILLED.format(root=root, db=str(db), tmp=str(tmp_path))],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == -signal.SIGKILL, done.stderr
    from mission.history.store import open_history

    h = open_history(str(db), create=False)
    [patrol] = h.patrols()
    assert patrol.ended_at is None and patrol.outcome is None and patrol.observed == 2
    assert [(o.pot_id, o.bug) for o in h.observations(patrol.id)] == [("P01", False), ("P02", True)]
    assert json.loads((tmp_path / "run" / "report.json").read_text())["outcome"] is None  # the report agrees
    assert main(["history", "patrols", "--history", str(db)]) == 0
    assert "running" in capsys.readouterr().out
    h.close()


def test_history_off_records_nothing(tmp_path):
    mission = parse_mission(MISSION, "unit.yaml")
    assert start_recording(None, mission, "mirte", None, tmp_path / "r.json") is None
