"""`lupin mission resume`: the pots a report left undone, from the mission written beside it."""
from __future__ import annotations

import json

import yaml

from lupin.cli import main
from mission.patrol.mission_file import dump_mission, mission_from_world
from mission.patrol.mission_resume import MISSION_FILE
from sim.world import load_default_world


def ended_early(tmp_path, statuses: dict[str, str]):
    """A report whose pots have ``statuses`` (the others never reached), the mission beside it."""
    (tmp_path / MISSION_FILE).write_text(dump_mission(mission_from_world(load_default_world())))
    report = tmp_path / "report.json"
    report.write_text(json.dumps({"pots": [{"id": k, "status": v} for k, v in statuses.items()], "anomalies": []}))
    return report


def test_resume_writes_exactly_the_skipped_and_never_reached_pots(tmp_path, capsys):
    statuses = {"P01": "inspected", "P02": "failed", "P03": "skipped", "P04": "inspected"}
    report = ended_early(tmp_path, statuses)
    out = tmp_path / "resume.yaml"
    assert main(["mission", "resume", str(report), "-o", str(out)]) == 0
    mission = yaml.safe_load(out.read_text())
    assert sorted(p["id"] for p in mission["pots"]) == ["P03"] + [f"P{k:02d}" for k in range(5, 13)]
    assert mission["order"] == "shortest"


def test_resume_without_the_mission_or_with_nothing_left_is_exit_2(tmp_path, capsys):
    report = ended_early(tmp_path, {f"P{k:02d}": "inspected" for k in range(1, 13)})
    assert main(["mission", "resume", str(report)]) == 2
    assert "nothing to resume" in capsys.readouterr().err
    (tmp_path / MISSION_FILE).unlink()
    assert main(["mission", "resume", str(report)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and MISSION_FILE in err[0] and str(report) in err[0]
