"""`lupin patrol` records the patrol it runs: a real sim patrol (two pots of the default
greenhouse) writes its rows into SQLite and into PostgreSQL, matching its report, with
``changes`` against a previous patrol of the same mission; a history that cannot be opened is
exit 2 before anything is built or moves (these run in the fast lane: no MuJoCo model is made)."""
from __future__ import annotations

import json
from datetime import timedelta

import pytest

from lupin.cli import main
from mission.history.changes import pot_changes
from mission.history.store import open_history, utc_now
from mission.patrol.mission_file import dump_mission, mission_from_world
from sim.world import load_default_world

from .conftest import add_patrol, obs


def two_pot_mission(tmp_path):
    m = mission_from_world(load_default_world())
    m = m.model_copy(update={"pots": [p for p in m.pots if p.id in ("P01", "P02")]})
    path = tmp_path / "two.yaml"
    path.write_text(dump_mission(m))
    return m, path


def patrol_and_check(tmp_path, url: str) -> None:
    m, mission_file = two_pot_mission(tmp_path)
    h = open_history(url)
    earlier = utc_now() - timedelta(days=1)
    seeded = [obs("P01", bug=True, color="white", blooms=3), obs("P02", status="failed", anomalies=("unreachable",))]
    previous = add_patrol(h, seeded, mission=m.name, started=earlier, world=load_default_world().name)  # the same greenhouse
    report = tmp_path / "run" / "report.json"
    code = main(["patrol", "--mission", str(mission_file), "--report", str(report), "--history", url, "--seed", "0"])
    doc = json.loads(report.read_text())
    assert code == (0 if doc["outcome"] == "completed" else 1)
    [patrol] = [p for p in h.patrols() if p.id != previous]
    assert patrol.mission == m.name and patrol.world == load_default_world().name and patrol.robot == "mirte"
    assert patrol.outcome == doc["outcome"] and patrol.ended_at is not None
    assert patrol.report_path == str(report.absolute()) and patrol.distance_m == doc["distance_m"]
    rows = {o.pot_id: o for o in h.observations(patrol.id)}
    assert set(rows) == {p["id"] for p in doc["pots"]} == {"P01", "P02"}
    for entry in doc["pots"]:
        o, flower = rows[entry["id"]], entry.get("flower") or {}
        assert (o.status, o.tag_read, o.flower_color, o.blooms, o.bug) == (
            entry["status"], entry["tag_read"], flower.get("color"), flower.get("blooms"), flower.get("bug"))
        kinds = {a["kind"] for a in doc["anomalies"] if a["pot"] == entry["id"]}
        assert set(o.anomalies) == kinds
        for image in (o.front_image, o.wrist_image):
            assert image is None or (report.parent / image.rsplit("/", 1)[-1]).exists()
    # the report's changes are those against the seeded patrol, pot by pot
    expected = [c.as_json() for p in doc["pots"] for c in pot_changes(
        next(s for s in seeded if s.pot_id == p["id"]), rows[p["id"]])]
    assert doc["changes"] == expected and doc["changes_since"]["patrol"] == previous
    assert doc["history"]["patrol"] == patrol.id and doc["history"]["write_errors"] == 0
    h.close()


@pytest.mark.slow
def test_a_sim_patrol_writes_its_rows_into_sqlite(tmp_path):
    patrol_and_check(tmp_path, str(tmp_path / "h.db"))


@pytest.mark.slow
def test_a_sim_patrol_writes_its_rows_into_postgresql(tmp_path, pg_url):
    patrol_and_check(tmp_path, pg_url)


def test_a_history_that_cannot_be_opened_stops_the_patrol_before_it_starts(tmp_path, capsys):
    _, mission_file = two_pot_mission(tmp_path)
    report = tmp_path / "run" / "report.json"
    bad = [str(tmp_path / "no" / "dir" / "h.db"), str(tmp_path), "mysql://x@y/z", "postgresql://nobody@127.0.0.1:1/"]
    for url in bad:
        assert main(["patrol", "--mission", str(mission_file), "--report", str(report), "--history", url]) == 2
        err = capsys.readouterr().err
        assert "--history" in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert not (report.parent / "config.yaml").exists()  # nothing started


def test_the_config_names_the_history_when_the_option_does_not(tmp_path, capsys, monkeypatch):
    _, mission_file = two_pot_mission(tmp_path)
    monkeypatch.setenv("LUPIN_HISTORY__URL", str(tmp_path / "missing" / "h.db"))
    assert main(["patrol", "--mission", str(mission_file), "--report", str(tmp_path / "r.json")]) == 2
    assert "history.url" in capsys.readouterr().err


def test_serve_refuses_a_history_it_cannot_open_before_it_starts(tmp_path, capsys):
    assert main(["serve", "--history", str(tmp_path / "no" / "h.db"), "--runs", str(tmp_path / "runs")]) == 2
    err = capsys.readouterr().err
    assert "--history" in err and "does not exist" in err and not (tmp_path / "runs").exists()




@pytest.mark.slow
def test_a_rescout_mission_from_a_sim_patrol_patrols_like_any_mission(tmp_path, capsys):
    """Patrol P02..P04 (P04 has the pest), re-scout within 1.5 m (P04 and P03 1 m away, not P02
    2 m away: a radius of exactly the spacing would hang on the measured positions' millimetres),
    then patrol the re-scouting mission: it loads, runs and is recorded like any other."""
    m = mission_from_world(load_default_world())
    m = m.model_copy(update={"pots": [p for p in m.pots if p.id in ("P02", "P03", "P04")]})
    (tmp_path / "m.yaml").write_text(dump_mission(m))
    db = str(tmp_path / "h.db")
    main(["patrol", "--mission", str(tmp_path / "m.yaml"), "--report", str(tmp_path / "a" / "report.json"),
          "--history", db])
    first = json.loads((tmp_path / "a" / "report.json").read_text())
    assert next(p for p in first["pots"] if p["id"] == "P04")["flower"]["bug"] is True
    capsys.readouterr()
    assert main(["mission", "rescout", "--history", db, "--last", "1", "--radius", "1.5",
                 "-o", str(tmp_path / "r.yaml")]) == 0
    code = main(["patrol", "--mission", str(tmp_path / "r.yaml"), "--report", str(tmp_path / "b" / "report.json"),
                 "--history", db])
    second = json.loads((tmp_path / "b" / "report.json").read_text())
    assert second["mission"] == f"{m.name}-rescout" and {p["id"] for p in second["pots"]} == {"P03", "P04"}
    assert code == (0 if second["outcome"] == "completed" else 1)
    assert next(p for p in second["pots"] if p["id"] == "P04")["status"] == "inspected"
    h = open_history(db, create=False)
    latest = h.patrols()[0]
    assert latest.mission == f"{m.name}-rescout" and latest.observed == 2 and latest.outcome == second["outcome"]
    h.close()
