"""`lupin patrol --record` as a user runs it: run.mcap beside the report, readable by any MCAP
reader; a recording that cannot be written is bad input, and the sim is shut down."""
from __future__ import annotations

import json

import pytest

from lupin.cli import main
from tests.mission.test_patrol_cli import short_mission
from tests.record.fixtures import read_mcap
from tests.record.test_channels import EXPECTED_SCHEMAS


@pytest.mark.slow
def test_record_writes_run_mcap_beside_the_report(tmp_path, capsys):
    mission = short_mission(tmp_path / "m.yaml", ("P01",))
    report = tmp_path / "run" / "report.json"
    assert main(["patrol", "--mission", str(mission), "--report", str(report), "--seed", "3", "--record"]) == 0
    assert capsys.readouterr().out.split("\n", 1)[1].startswith("default-patrol: completed, 1/1 pots inspected")
    doc = json.loads(report.read_text())
    rec = read_mcap(report.parent / "run.mcap")
    assert set(rec.topics) == set(EXPECTED_SCHEMAS)
    assert abs(rec.counts["/tf"] - (10 * doc["sim_time_s"] + 1)) <= 1.5
    final = rec.decoded("/mission/state")[-1]
    assert (final["outcome"], final["pots"]) == ("completed", {"P01": "inspected"})


@pytest.mark.slow
def test_a_recording_that_cannot_be_written_is_exit_2_in_one_line(tmp_path, capsys):
    mission = short_mission(tmp_path / "m.yaml", ("P01",))
    report = tmp_path / "run" / "report.json"
    (report.parent / "run.mcap").mkdir(parents=True)  # a directory where the file must go
    assert main(["patrol", "--mission", str(mission), "--report", str(report), "--record"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "run.mcap" in err[0] and "Traceback" not in err[0], err
