"""`lupin patrol --map`: a map saved by one patrol serves the next (AMCL instead of SLAM), and a
map that does not cover the mission's pots is refused before the robot moves, naming them."""
from __future__ import annotations

import json

import numpy as np
import pytest

from lupin.cli import main
from mission.patrol.map_coverage import uncovered_pots
from mission.patrol.mission_file import dump_mission, mission_from_world, parse_mission
from nav.map_io import save_map
from nav.occupancy import OccupancyMap
from sim.generate import generate_world
from sim.world import dump_world

MISSION = {"name": "m", "pots": [{"id": "IN", "x": 1.0, "y": 1.0, "facing": -1.5708},
                                 {"id": "WALL", "x": 2.0, "y": 1.0, "facing": -1.5708},
                                 {"id": "DARK", "x": 3.0, "y": 1.0, "facing": -1.5708},
                                 {"id": "OUT", "x": 9.0, "y": 1.0, "facing": -1.5708}]}


def test_each_pot_whose_approach_pose_the_map_does_not_hold_as_free_is_named():
    occ = np.zeros((40, 80), np.int8)  # 4 x 2 m from the origin, free
    occ[8:12, 38:42] = 100  # on WALL's approach pose (2.0, 0.5)
    occ[:, 56:] = -1  # never seen from x = 2.8 m on: DARK's approach pose (3.0, 0.5)
    lines = uncovered_pots(parse_mission(MISSION, "m.yaml"), OccupancyMap(occ, 0.05, 0.0, 0.0))
    assert [line.split(":")[0] for line in lines] == ["pot WALL", "pot DARK", "pot OUT"]
    assert "inside an obstacle" in lines[0] and "never saw" in lines[1] and "outside the map" in lines[2]


def test_a_map_that_does_not_cover_the_pots_is_exit_2_before_anything_starts(tmp_path, capsys):
    save_map(OccupancyMap(np.zeros((20, 20), np.int8), 0.05, 0.0, 0.0), tmp_path / "small.yaml")  # 1 x 1 m
    report = tmp_path / "out" / "report.json"
    assert main(["patrol", "--map", str(tmp_path / "small.yaml"), "--report", str(report)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "small.yaml: does not cover pot P02" in err[0] and "P12" in err[0]
    assert "pot P01" not in err[0]  # the one pot whose approach pose is on the 1 m square
    assert not report.parent.exists()
    assert main(["patrol", "--map", str(tmp_path / "none.yaml")]) == 2
    assert "none.yaml: map file not found" in capsys.readouterr().err


@pytest.mark.slow
def test_the_map_one_patrol_saved_serves_the_next(tmp_path, capsys):
    world = generate_world(2, 3, 7)
    (tmp_path / "w.yaml").write_text(dump_world(world))
    (tmp_path / "m.yaml").write_text(dump_mission(mission_from_world(world)))
    first, second = tmp_path / "first" / "report.json", tmp_path / "second" / "report.json"
    common = ["--world", str(tmp_path / "w.yaml"), "--mission", str(tmp_path / "m.yaml")]
    assert main(["patrol", *common, "--report", str(first)]) == 0
    assert main(["patrol", *common, "--report", str(second), "--map", str(first.parent / "map.yaml")]) == 0
    capsys.readouterr()
    report = json.loads(second.read_text())
    assert report["outcome"] == "completed" and all(p["status"] == "inspected" for p in report["pots"])
    assert all(p["truth_error"]["xy"] <= 0.1 for p in report["pots"])  # where AMCL said it was
    config = (second.parent / "config.yaml").read_text()
    assert "slam: false" in config and "map.yaml" in config
    assert (second.parent / "map.yaml").exists()
