"""A scenario file's fleet part (``robots: N``, events addressed to a robot, ``expect.fleet``):
its mistakes named with file, entry and field before anything runs, and the events each robot
gets. The fleet scenarios themselves are files of tests/scenarios/ (fleet-*.yaml)."""
from __future__ import annotations

from pathlib import Path

import pytest

from hw.errors import InputError
from lupin.cli import main
from mission.runtime.config import LupinConfig
from mission.scenario.scenario_file import parse_scenario

FLEET_WORLD = str(Path(__file__).parents[1] / "scenarios" / "worlds" / "fleet-3x4.yaml")
"""The 3 x 4 greenhouse with two docks (``lupin sim generate --robots 2``)."""


def fleet(**more) -> dict:
    return {"name": "x", "world": FLEET_WORLD, "robots": 2, **more}


@pytest.mark.parametrize("data, message", [
    ({"name": "x", "robots": 2}, "s.yaml: field 'robots': 2 robots but the world 'default' has 1 spawn (spawns: in"),
    (fleet(robots=3), "field 'robots': 3 robots but the world 'generated-3x4-seed1' has 2 spawns"),
    (fleet(robots=0), "field 'robots': must be >= 1"),
    (fleet(events=[{"at": 5, "robot": "r3", "do": "estop", "engaged": True}]),
     "s.yaml: events[0] (do estop): field 'robot': no robot 'r3' in this fleet (r1, r2)"),
    (fleet(events=[{"at": 5, "do": "pause"}, {"at": 6, "robot": 2, "do": "resume"}]),
     "events[1] (do resume): field 'robot': no robot 2 in this fleet (r1, r2)"),
    (fleet(events=[{"at": 5, "robot": "r2", "do": "runtime_crash"}]),
     "events[0] (do runtime_crash): field 'do': runtime_crash cannot show its effect in a fleet scenario"),
    (fleet(events=[{"at": 5, "robot": "r2", "do": "estop"}]), "events[0] (do estop): field 'engaged': missing required key"),
    ({"name": "x", "events": [{"at": 5, "robot": "r1", "do": "pause"}]}, "events[0] (do pause): field 'robot': unknown key"),
    ({"name": "x", "expect": {"fleet": {"pots": "all"}}}, "expect: field 'fleet': only in a fleet scenario (give robots: N)"),
    (fleet(expect={"pots": {"inspected": "all"}}), "expect: field 'pots': a fleet scenario judges the pots in expect.fleet.pots"),
    (fleet(expect={"fleet": {"pots": "most"}}), "expect: field 'fleet.pots': must be all, a number or a list of pot ids"),
    (fleet(expect={"fleet": {"robot_contacts": -1}}), "field 'fleet.robot_contacts': must be >= 0"),
    (fleet(expect={"fleet": {"head_on": 0}}), "expect: field 'fleet.head_on': unknown key"),
])
def test_fleet_scenario_mistakes_are_named(tmp_path, data, message):
    with pytest.raises(InputError) as exc:
        parse_scenario(data, tmp_path / "s.yaml", LupinConfig())
    assert message in str(exc.value)


def test_events_go_to_the_robot_they_name_r1_by_default_each_robot_s_in_time_order(tmp_path):
    s = parse_scenario(fleet(events=[{"at": 30, "robot": "r2", "do": "estop", "engaged": False},
                                     {"at": 20, "robot": "r2", "do": "estop", "engaged": True},
                                     {"at": 25, "do": "pause"}, {"at": 31, "robot": "r2", "do": "resume"}]),
                       tmp_path / "s.yaml", LupinConfig())
    assert [(e.at, e.do) for e in s.robot_events["r1"]] == [(25, "pause")]
    assert [(e.at, e.do, getattr(e, "engaged", None)) for e in s.robot_events["r2"]] == [
        (20, "estop", True), (30, "estop", False), (31, "resume", None)]
    assert s.spec.robots == 2 and len(s.events) == 4
    alone = parse_scenario({"name": "x", "events": [{"at": 5, "do": "pause"}]}, tmp_path / "s.yaml", LupinConfig())
    assert alone.robot_events == {} and alone.spec.robots is None  # one robot's scenario as before


def test_lupin_scenario_run_refuses_a_fleet_scenario_with_more_robots_than_docks(tmp_path, capsys):
    bad = tmp_path / "three.yaml"
    bad.write_text(f"name: three\nworld: {FLEET_WORLD}\nrobots: 3\n")
    assert main(["scenario", "run", str(bad), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{bad}: field 'robots': 3 robots but the world" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()
