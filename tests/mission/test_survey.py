"""`lupin survey` in the sim: a greenhouse explored from the dock, every pot found by its tag and
placed where it stands; the world file only builds the sim (its pots listed shuffled, under
wrong ids, change nothing); and the CLI writes the mission, map, report and picture."""
from __future__ import annotations

import json
import math
import random

import pytest

from hw.odometry import Pose2D
from lupin.cli import main
from mission.patrol.mission_file import load_mission
from nav.frames import compose, inverse
from sim.generate import generate_world
from sim.world import dump_world

pytestmark = pytest.mark.slow


def scrambled(world):
    """The same greenhouse, its pots listed in another order under ids that mean nothing."""
    pots = [p.model_copy(update={"id": f"X{k * 7 % 13}"}) for k, p in enumerate(world.pots)]
    random.Random(5).shuffle(pots)
    return world.model_copy(update={"pots": pots})


def test_the_survey_command_finds_every_pot_by_its_tag_whatever_the_world_file_calls_it(tmp_path, capsys):
    """One survey, through the command as a grower runs it: every pot found and placed by its
    tag, however the world file lists and names them; the mission, map, report and picture."""
    world = scrambled(generate_world(2, 3, 6))
    (tmp_path / "w.yaml").write_text(dump_world(world))
    out = tmp_path / "s"
    assert main(["survey", "--world", str(tmp_path / "w.yaml"), "-o", str(out / "m.yaml"),
                 "--map-out", str(out / "map.yaml"), "--report", str(out / "survey.json")]) == 0
    printed = capsys.readouterr().out
    assert "6 pots found by their tags" in printed and "m2 explored" in printed
    assert {f.name for f in out.iterdir()} >= {"m.yaml", "map.yaml", "map.pgm", "survey.json", "survey.png"}
    mission = load_mission(out / "m.yaml")
    dock = inverse(Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw))
    truth = {p.tag: compose(dock, Pose2D(p.x, p.y, p.facing)) for p in world.pots}
    assert sorted(p.tag for p in mission.pots) == sorted(truth)  # every pot, once
    assert all(p.id == f"T{p.tag:03d}" for p in mission.pots)  # named by their tags, not the world's ids
    for p in mission.pots:
        t = truth[p.tag]
        assert math.hypot(p.x - t.x, p.y - t.y) <= 0.05, p
        assert abs(math.remainder(p.facing - t.yaw, 2 * math.pi)) <= 0.1, p
    report = json.loads((out / "survey.json").read_text())
    assert report["pots_found"] == 6 and report["explored_m2"] > 5 and all(p["sightings"] >= 1 for p in report["pots"])
    assert report["ended"] == "complete"  # it ended because it was done, not on the time limit
    assert main(["survey", "-o", str(out / "m.txt")]) == 2  # a bad output path: nothing started
    assert "must be a .yaml" in capsys.readouterr().err
