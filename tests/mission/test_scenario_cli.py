"""Scenario files and `lupin scenario run` on bad input: exit 2, the file, entry and field named,
nothing started (no report directory, so the robot never moved). The good scenarios themselves
are the files of tests/scenarios/, collected by its conftest."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from hw.errors import InputError
from lupin.cli import main
from lupin.cli.scenario import report_dir
from mission.scenario.scenario_file import load_scenario, parse_scenario
from mission.runtime.config import LupinConfig

BAD = Path(__file__).parents[1] / "scenarios" / "bad"
GOOD = Path(__file__).parents[1] / "scenarios" / "estop-mid-approach.yaml"


@pytest.mark.parametrize("name, words", [
    ("bad-mission.yaml", ["mission-with-a-word-for-facing.yaml", "pots[1] (id P02)", "field 'facing'", "'south'"]),
    ("bad-world.yaml", ["world-with-a-pot-off-the-floor.yaml", "pots[1] (id P02)", "field 'x'", "east wall"]),
    ("bad-events.yaml", ["bad-events.yaml", "events[0] (do estop)", "field 'engagd': unknown key"]),
    ("bad-scenario.yaml", ["bad-scenario.yaml", "expect: field 'outcome'", "finished", "field 'pots.inspected'"]),
])
def test_a_bad_file_is_exit_2_and_nothing_runs(tmp_path, capsys, name, words):
    out = tmp_path / "runs"
    # the good scenario first: every file is checked before any runs, so it must not run either
    assert main(["scenario", "run", str(GOOD), str(BAD / name), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    for w in words:
        assert w in err
    assert not out.exists()


def test_patrol_events_are_checked_before_the_robot_moves(tmp_path, capsys):
    report = tmp_path / "out" / "report.json"
    assert main(["patrol", "--events", str(BAD / "bad-events.yaml"), "--report", str(report)]) == 2
    err = capsys.readouterr().err
    assert "top level: must be a list of events" in err  # a scenario is not an events file
    events = tmp_path / "e.yaml"
    events.write_text("- {at: 5.0, do: teleop, source: joy, vx: 0.1}\n")
    assert main(["patrol", "--events", str(events), "--report", str(report)]) == 2
    assert "events[0] (do teleop): field 'duration': missing required key" in capsys.readouterr().err
    assert main(["patrol", "--backend", "hw", "--mission", str(BAD / "mission-with-a-word-for-facing.yaml"),
                 "--events", str(events), "--report", str(report)]) == 2
    assert not report.parent.exists()


@pytest.mark.parametrize("data, message", [
    ({"expect": {}}, "top level: field 'name': missing required key"),
    ({"name": "x", "expect": {"arm": "wave"}}, "expect: field 'arm': must be one of home"),
    ({"name": "x", "expect": {"estop": {"zero_duty_within_ticks": 0}}}, "field 'estop.zero_duty_within_ticks': must be >= 1"),
    ({"name": "x", "expect": {"home": {"within": -1}}}, "field 'home.within': must be > 0"),
    ({"name": "x", "expect": {"estop": {"min_speed_at_press": 0}}}, "field 'estop.min_speed_at_press': must be > 0"),
    ({"name": "x", "expect": {"effects": {"wave": {}}}}, "expect: field 'effects.wave': unknown key (allowed: pause, lidar_dropout"),
    ({"name": "x", "expect": {"effects": {"clear_map": {"map_back": 1.5}}}}, "field 'effects.clear_map.map_back': must be <= 1"),
    ({"name": "x", "expect": {"effects": {"pause": {"still_within": 0}}}}, "field 'effects.pause.still_within': must be > 0"),
    ({"name": "x", "events": [{"at": 1, "do": "pause", "when_moving": -0.1}]}, "events[0] (do pause): field 'when_moving': must be > 0"),
    ({"name": "x", "expect": {"max_sim_time": "long"}}, "field 'max_sim_time': must be a number"),
    ({"name": "x", "config": {"nav": {"mppi": {"frequency": -1}}}}, "config: field 'nav.mppi.frequency'"),
    ({"name": "x", "world": "nowhere.yaml"}, "nowhere.yaml: world file not found"),
    ({"name": "x", "colour": "red"}, "top level: field 'colour': unknown key"),
    ({"name": "x", "expect": {"people": {"min_clearance": 0.2}}}, "expect: field 'people': the world 'default' has no walkers"),
    ({"name": "x", "expect": {"people": {"contacts": -1}}}, "field 'people.contacts': must be >= 0"),
    ({"name": "x", "expect": {"people": {"encounters": -1}}}, "field 'people.encounters': must be >= 0"),
    ({"name": "x", "events": [{"at": 1, "do": "walker", "walker": "W1", "moving": False}]},
     "events[0] (do walker): field 'walker': the world has no walker 'W1' (walkers: none)"),
    (["name"], "top level: must be a mapping"),
])
def test_scenario_mistakes_are_named(tmp_path, data, message):
    with pytest.raises(InputError) as exc:
        parse_scenario(data, tmp_path / "s.yaml", LupinConfig())
    assert message in str(exc.value)


@pytest.mark.slow
def test_a_press_at_rest_fails_a_scenario_that_asks_for_speed(tmp_path, capsys):
    """Issue 18's held-out case in the sim: a press while the robot stands at a pot. Every other
    e-stop figure passes (there was nothing to stop); the speed at the press fails the run."""
    assert main(["scenario", "run", str(BAD / "press-at-rest.yaml"), "--json", "--out", str(tmp_path)]) == 1
    result = json.loads(capsys.readouterr().out)
    failed = [c for c in result["checks"] if not c["passed"]]
    assert [c["name"] for c in failed] == ["estop.min_speed_at_press"]
    assert failed[0]["expected"] == "every press to find the base driving at >= 0.2 m/s (true speed)"
    assert failed[0]["actual"] == "speed at press: 0.00 m/s at 9.0 s (a press at rest tests nothing)"
    assert result["estop"][0]["ticks_to_zero"] == 1 and result["estop"][0]["speed_mps"] < 0.01


def test_paths_are_relative_to_the_scenario_and_the_seed_and_config_apply(tmp_path):
    s = load_scenario(GOOD)
    assert s.config.sim.seed == 3 and len(s.mission.pots) == 12 and s.events[0].do == "estop"
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "m.yaml").write_text("name: two\npots:\n  - {id: A, x: 1.0, y: 0.5, facing: 0.0}\n")
    (tmp_path / "s.yaml").write_text("name: x\nmission: sub/m.yaml\nconfig: {patrol: {settle: 0.5}}\n")
    s = load_scenario(tmp_path / "s.yaml")
    assert [p.id for p in s.mission.pots] == ["A"] and s.config.patrol.settle == 0.5
    assert s.expect.max_sim_time == 600.0 and s.events == []


def test_report_directories_stay_inside_out(tmp_path):
    assert report_dir(tmp_path, "../../etc/passwd").parent == tmp_path
    assert report_dir(tmp_path, "estop mid/approach").name == "estop_mid_approach"
