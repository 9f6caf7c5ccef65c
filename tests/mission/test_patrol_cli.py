"""`lupin patrol` as a user runs it: bad input before the robot moves, a short patrol to its end,
and a report that survives the process being killed mid-patrol."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from lupin.cli import main
from mission.patrol.mission_file import dump_mission, mission_from_world
from sim.world import load_default_world


def short_mission(path: Path, ids=("P01", "P02")) -> Path:
    m = mission_from_world(load_default_world())
    m = m.model_copy(update={"pots": [p for p in m.pots if p.id in ids]})
    path.write_text(dump_mission(m))
    return path


def test_a_bad_mission_file_is_exit_2_before_the_robot_moves(tmp_path, capsys):
    bad = tmp_path / "m.yaml"
    bad.write_text("name: x\npots:\n  - {id: P01, x: 1.0, y: 0.5, facing: 'south'}\n")
    report = tmp_path / "out" / "report.json"
    assert main(["patrol", "--mission", str(bad), "--report", str(report)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(bad) in err[0] and "pots[0]" in err[0] and "facing" in err[0]
    assert not report.parent.exists()  # nothing ran, nothing written


@pytest.mark.parametrize("args, words", [
    (["--report", "out.txt"], ["--report", ".json"]),
    (["--world", "no/such/world.yaml"], ["no/such/world.yaml"]),
    (["--backend", "hw"], ["--mission"]),
    (["--backend", "tractor"], ["--backend"]),
    (["--seed", "x"], ["--seed"]),
    (["--max-legs", "0"], ["--max-legs"]),
    (["--resume", "no/such/report.json"], ["no/such/report.json", "not found"]),
])
def test_bad_options_are_exit_2_with_one_line(tmp_path, monkeypatch, capsys, args, words):
    monkeypatch.chdir(tmp_path)
    assert main(["patrol", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and all(w in err[0] for w in words), err


def test_the_robot_backend_names_the_missing_device(tmp_path, capsys):
    mission = short_mission(tmp_path / "m.yaml")
    assert main(["patrol", "--backend", "hw", "--mission", str(mission), "--report", str(tmp_path / "r.json")]) == 2
    err = capsys.readouterr().err
    assert "/dev/" in err and "Traceback" not in err


@pytest.mark.slow
def test_a_short_patrol_runs_to_its_end_quietly_off_a_terminal(tmp_path, capsys):
    mission = short_mission(tmp_path / "m.yaml")
    report = tmp_path / "run" / "morning.json"
    assert main(["patrol", "--mission", str(mission), "--report", str(report), "--seed", "3"]) == 0
    first, out = capsys.readouterr().out.split("\n", 1)
    assert first == "lupin patrol: sim backend, world 'default'"
    assert out.startswith("default-patrol: completed, 2/2 pots inspected")
    assert "pot 1 of 2" not in out  # no progress display when stdout is not a terminal
    doc = json.loads(report.read_text())
    assert [(p["id"], p["tag_read"], p["flower"]["color"]) for p in doc["pots"]] == [("P01", 1, "red"), ("P02", 2, "white")]
    names = {p.name for p in report.parent.iterdir()}
    assert {"config.yaml", "map.yaml", "map.pgm", "run.png", "P01_front.jpg", "P02_wrist.jpg"} <= names


@pytest.mark.slow
def test_a_report_read_after_a_kill_holds_every_pot_finished_before_it(tmp_path):
    mission = short_mission(tmp_path / "m.yaml", ("P01", "P02", "P03", "P04"))
    report = tmp_path / "run" / "report.json"
    lupin = Path(sys.executable).with_name("lupin")
    proc = subprocess.Popen([str(lupin), "patrol", "--mission", str(mission), "--report", str(report)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 240  # test harness wait, not a timing assertion
        while time.monotonic() < deadline and proc.poll() is None:
            if report.exists() and len(json.loads(report.read_text())["pots"]) >= 2:
                break
            time.sleep(0.05)
        assert proc.poll() is None, "the patrol ended before it could be killed"
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    doc = json.loads(report.read_text())  # whole JSON: every write was atomic
    assert doc["outcome"] is None
    ids = [p["id"] for p in doc["pots"]]
    assert ids == ["P01", "P02", "P03", "P04"][:len(ids)] and len(ids) >= 2
    for p in doc["pots"]:
        assert p["status"] == "inspected"
        for name in p["images"]:
            assert (report.parent / name).stat().st_size > 1000


@pytest.mark.slow
def test_sigterm_aborts_the_patrol_and_finishes_the_report(tmp_path):
    mission = short_mission(tmp_path / "m.yaml", ("P01", "P02", "P03"))
    report = tmp_path / "run" / "report.json"
    lupin = Path(sys.executable).with_name("lupin")
    proc = subprocess.Popen([str(lupin), "patrol", "--mission", str(mission), "--report", str(report)],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    deadline = time.monotonic() + 240  # harness wait, not a timing assertion
    while time.monotonic() < deadline and not (report.exists() and json.loads(report.read_text())["pots"]):
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    out, _ = proc.communicate(timeout=120)
    assert proc.returncode == 1
    doc = json.loads(report.read_text())
    assert doc["outcome"] == "aborted" and doc["pots"][0]["status"] == "inspected"
    assert "skipped" in [p["status"] for p in doc["pots"]]
    assert out.split("\n", 1)[1].startswith("default-patrol: aborted, ")


def test_the_summary_says_how_many_pots_were_not_inspected_and_why():
    from lupin.cli.patrol import summary

    pot = {"tag_read": None, "flower": None}
    doc = {"mission": "m", "outcome": "completed", "sim_time_s": 10.0, "wall_time_s": 2.0, "distance_m": 3.0,
           "pots": [{**pot, "id": "A", "status": "inspected"}, {**pot, "id": "B", "status": "failed"},
                    {**pot, "id": "C", "status": "failed"}, {**pot, "id": "D", "status": "skipped"}],
           "anomalies": [{"kind": "no_bloom", "pot": "A", "detail": ""}, {"kind": "unreachable", "pot": "B", "detail": ""},
                         {"kind": "unreachable", "pot": "C", "detail": ""}, {"kind": "skipped", "pot": "D", "detail": ""}],
           "discovered_tags": []}
    first = summary(doc, Path("r.json")).splitlines()[0]
    assert first.startswith("m: completed, 1/4 pots inspected, 2 unreachable, 1 skipped, 10.0 s robot time")
