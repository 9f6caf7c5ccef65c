"""`lupin mission update`: moved pots to their measured poses, discovered tags added as new pots
flagged for review; the file round-trips; bad reports are one clear line."""
from __future__ import annotations

import json

from lupin.cli import main
from mission.patrol.mission_file import dump_mission, load_mission, parse_mission

MISSION = {"name": "m", "pots": [{"id": "P01", "x": 1.0, "y": 0.5, "facing": -1.5708, "tag": 1},
                                 {"id": "P02", "x": 2.0, "y": 0.5, "facing": -1.5708, "tag": 2}]}
REPORT = {"pots": [], "anomalies": [
    {"kind": "bug", "pot": "P01", "detail": "dark spot"},
    {"kind": "moved", "pot": "P02", "detail": "0.15 m", "x": 2.12, "y": 0.41, "facing": -1.4}],
    "discovered_tags": [{"id": 17, "x": 5.1, "y": 2.2, "sightings": 3, "pot": {"x": 5.1, "y": 2.3, "facing": -1.57}},
                        {"id": 1, "x": 1.0, "y": 0.4, "sightings": 1, "pot": {"x": 1.0, "y": 0.5, "facing": -1.57}},
                        {"id": 23, "x": 0.0, "y": 0.0}]}


def write(tmp_path, report=REPORT):
    (tmp_path / "m.yaml").write_text(dump_mission(parse_mission(MISSION, "m.yaml")))
    (tmp_path / "r.json").write_text(json.dumps(report))
    return tmp_path / "m.yaml", tmp_path / "r.json"


def test_moved_pots_move_and_discovered_tags_become_new_pots_for_review(tmp_path, capsys):
    mission, report = write(tmp_path)
    out = tmp_path / "new.yaml"
    assert main(["mission", "update", str(mission), "--report", str(report), "-o", str(out)]) == 0
    assert "1 moved (P02), 1 added for review (T017)" in capsys.readouterr().out
    m = load_mission(out)  # round-trips through the strict reader
    pots = {p.id: p for p in m.pots}
    assert (pots["P01"].x, pots["P01"].y) == (1.0, 0.5)  # untouched
    assert (pots["P02"].x, pots["P02"].y, pots["P02"].facing) == (2.12, 0.41, -1.4)
    assert (pots["T017"].x, pots["T017"].y, pots["T017"].tag) == (5.1, 2.3, 17)
    assert set(pots) == {"P01", "P02", "T017"}  # tag 1 is P01's; tag 23 has no pot pose
    flagged = [line for line in out.read_text().splitlines() if "NEW:" in line]
    assert len(flagged) == 1 and "T017" in flagged[0]


def test_without_o_the_mission_goes_to_stdout_and_the_summary_to_stderr(tmp_path, capsys):
    mission, report = write(tmp_path)
    assert main(["mission", "update", str(mission), "--report", str(report)]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("# Lupin patrol mission") and "T017" in out and "1 moved" in err


def test_bad_reports_are_one_clear_line(tmp_path, capsys):
    mission, report = write(tmp_path, {"pots": [], "anomalies": [{"kind": "moved", "pot": "P09", "x": 1, "y": 1}]})
    assert main(["mission", "update", str(mission), "--report", str(report)]) == 2
    assert "anomalies[0] (moved 'P09'): the mission has no such pot" in capsys.readouterr().err
    report.write_text("{not json")
    assert main(["mission", "update", str(mission), "--report", str(report)]) == 2
    assert "not a patrol report (JSON)" in capsys.readouterr().err
    report.write_text(json.dumps({"pots": [], "anomalies": [{"kind": "moved", "pot": "P01", "x": "left"}]}))
    assert main(["mission", "update", str(mission), "--report", str(report)]) == 2
    assert "needs numbers 'x' and 'y'" in capsys.readouterr().err
    assert main(["mission", "update", str(mission), "--report", str(tmp_path / "none.json")]) == 2
