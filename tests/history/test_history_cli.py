"""`lupin history`: patrols, a pot's timeline, changes, pests (with its picture), export; human
text by default, one JSON document with --json; bad input is one line and exit 2."""
from __future__ import annotations

import csv
import json
import sqlite3
from datetime import timedelta

import cv2
import numpy as np
import pytest

from lupin.cli import main
from mission.history.migrations import LATEST
from nav.map_io import save_map
from nav.occupancy import OccupancyMap

from .conftest import T0, add_patrol, obs


@pytest.fixture
def db(tmp_path, sqlite_history):
    """Three patrols of 'm' (a pest appears at P02 and stays, P03 fails) and one of 'other'."""
    h = sqlite_history
    add_patrol(h, [obs("P01", x=0, y=0), obs("P02", x=1, y=0), obs("P03", x=2, y=0)], started=T0)
    add_patrol(h, [obs("P01", x=0, y=0), obs("P02", x=1, y=0, bug=True), obs("P03", x=2, y=0)],
               started=T0 + timedelta(hours=6))
    add_patrol(h, [obs("P09", x=5, y=5)], mission="other", robot="fred", started=T0 + timedelta(hours=7))
    report = tmp_path / "run3" / "report.json"
    report.parent.mkdir()
    add_patrol(h, [obs("P01", x=0, y=0, color="white"), obs("P02", x=1, y=0, bug=True, blooms=2),
                   obs("P03", x=2, y=0, status="failed", anomalies=("unreachable",))],
               started=T0 + timedelta(hours=12), report_path=str(report))
    return str(h.target.path)


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_patrols_newest_first(db, capsys):
    code, out, _ = run(capsys, "history", "patrols", "--history", db)
    lines = out.splitlines()
    assert code == 0 and lines[0].split()[:2] == ["id", "started"]
    assert [line.split()[0] for line in lines[1:]] == ["4", "3", "2", "1"]
    assert "fred" in lines[2] and "other" in lines[2] and "completed" in lines[1]
    code, out, _ = run(capsys, "history", "patrols", "--history", db, "--json", "--mission", "m", "--limit", "2")
    data = json.loads(out)
    assert [p["id"] for p in data["patrols"]] == [4, 2]
    assert data["patrols"][0]["observed"] == 3 and data["patrols"][0]["pests"] == 1
    assert data["patrols"][0]["started_at"] == "2025-05-01T18:00:00Z"


def test_a_pots_timeline(db, capsys):
    code, out, _ = run(capsys, "history", "pot", "P02", "--history", db)
    lines = out.splitlines()
    assert code == 0 and lines[0].startswith("pot P02: 3 observation(s)")
    assert [line.split()[2] for line in lines[2:]] == ["1", "2", "4"]  # patrol ids, oldest first
    assert lines[2].split()[6] == "no" and lines[3].split()[6] == "YES" and lines[4].split()[5] == "2"
    code, out, _ = run(capsys, "history", "pot", "P03", "--history", db, "--json")
    timeline = json.loads(out)["timeline"]
    assert [t["status"] for t in timeline] == ["inspected", "inspected", "failed"]
    assert timeline[-1]["anomalies"] == ["unreachable"] and timeline[-1]["mission"] == "m"


def test_changes_between_the_last_two_patrols(db, capsys):
    code, out, _ = run(capsys, "history", "changes", "--history", db)
    head = out.splitlines()[0]
    assert code == 0 and head.startswith("m: patrol 2 (2025-05-01 12:00) -> patrol 4 (2025-05-01 18:00): 3")
    kinds = [line.split()[:2] for line in out.splitlines()[1:]]
    assert kinds == [["P01", "color"], ["P02", "blooms"], ["P03", "failed"]]
    code, out, _ = run(capsys, "history", "changes", "--history", db, "--mission", "other", "--json")
    data = json.loads(out)
    assert data["before"] is None and data["changes"] == [] and data["after"]["id"] == 3


def test_pests_with_a_plain_plot_and_on_the_saved_map(db, tmp_path, capsys):
    png = tmp_path / "pests.png"
    code, out, _ = run(capsys, "history", "pests", "--history", db, "--last", "3", "-o", str(png))
    assert code == 0 and "1 of 3 pots with a pest in the last 3 patrol(s)" in out and "plain plot" in out
    row = next(line for line in out.splitlines() if line.strip().startswith("P02"))
    assert row.split()[1:4] == ["2/3", "0.67", "2"]  # pests/judged, pressure, streak
    plain = cv2.imread(str(png))
    assert plain is not None and plain.shape[0] > 100
    # the latest patrol's saved map: the picture is drawn on it (its walls are there)
    grid = np.zeros((60, 80), np.int8)
    grid[0, :] = grid[-1, :] = 100
    save_map(OccupancyMap(grid, 0.05, -0.5, -1.0), tmp_path / "run3" / "map.yaml")
    code, out, _ = run(capsys, "history", "pests", "--history", db, "-o", str(png), "--json")
    data = json.loads(out)
    assert code == 0 and data["picture"] == str(png) and data["patrols"] == [4, 2, 1]
    p02 = next(p for p in data["pots"] if p["pot_id"] == "P02")
    assert (p02["pests"], p02["observed"], p02["streak"]) == (2, 3, 2)
    on_map = cv2.imread(str(png))
    assert (on_map < 40).all(axis=2).sum() > (plain < 40).all(axis=2).sum()  # the map's black walls


def test_export_csv(db, tmp_path, capsys):
    out_dir = tmp_path / "csv"
    code, out, _ = run(capsys, "history", "export", "--csv", str(out_dir), "--history", db)
    assert code == 0 and "observations.csv (10 rows)" in out
    with open(out_dir / "observations.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 10 and rows[0]["observed_at"] == "2025-05-01T06:00:00Z"
    assert {"patrol_id", "pot_id", "seq", "status", "bug", "anomalies", "x", "y"} <= set(rows[0])
    assert sum(r["bug"] == "true" for r in rows) == 2
    with open(out_dir / "patrols.csv") as f:
        assert [r["id"] for r in csv.DictReader(f)] == ["1", "2", "3", "4"]
    code, out, _ = run(capsys, "history", "export", "--csv", str(out_dir), "--history", db, "--mission", "other",
                       "--json")
    assert json.loads(out)["rows"] == {"patrols.csv": 1, "observations.csv": 1}


def test_an_empty_history_says_so(tmp_path, capsys, sqlite_history):
    db = str(sqlite_history.target.path)
    for cmd in ("patrols", "changes", "pests"):
        code, out, _ = run(capsys, "history", cmd, "--history", db)
        assert code == 0 and "no patrols recorded" in out


def test_bad_input_is_one_line_and_exit_2(db, tmp_path, capsys):
    newer = tmp_path / "newer.db"
    with sqlite3.connect(db) as src, sqlite3.connect(newer) as dst:
        src.backup(dst)  # the WAL's pages too: a file copy could miss them
    with sqlite3.connect(newer) as c:
        c.execute("INSERT INTO schema_version VALUES (?, '2031-01-01 00:00:00', 'future')", (LATEST + 1,))
    cases = [
        (["history", "pot", "P77", "--history", db], "pot P77: not in"),
        (["history", "patrols", "--history", str(tmp_path / "absent.db")], "no history database there"),
        (["history", "changes", "--history", "none"], "the history is off"),
        (["history", "changes", "--history", "mysql://a@b/c"], "not a history database"),
        (["history", "changes", "--history", db, "--mission", "nope"], "--mission nope: no patrol of it"),
        (["history", "pests", "--history", db, "-o", str(tmp_path / "x.jpg")], "must name a .png"),
        (["history", "pests", "--history", db, "--last", "0"], "--last"),
        (["history", "export", "--history", db], "--csv"),
        (["history", "patrols", "--history", str(newer)], "newer than this Lupin"),
        (["history", "patrols", "--history", "postgresql://nobody@127.0.0.1:1/none"], "cannot open the history"),
    ]
    for argv, says in cases:
        code, _, err = run(capsys, *argv)
        assert code == 2, argv
        assert says in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, (argv, err)
    assert not (tmp_path / "absent.db").exists()
