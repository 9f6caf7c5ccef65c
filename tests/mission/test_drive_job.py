"""`lupin sim drive`, the main job until the patrol lands: the default tour end to end."""
import json
import math

import pytest
import yaml

from lupin.cli import main
from mission.runtime.config import load_config
from mission.jobs.drive import drive
from sim.world import dump_world, load_default_world

pytestmark = pytest.mark.slow


def test_tour_of_the_default_greenhouse_is_clean():
    run = drive(load_default_world(), load_config(env={}), "tour")
    assert run.driver.done
    assert [r.move.name for r in run.results] == [m.name for m in run.driver.moves]
    assert run.bumps == {}  # the route fits the built-in greenhouse
    assert run.sim.engine.warnings() == {}
    assert 9 * 20 < run.scans  # ~10 Hz lidar over the whole run
    for r in run.results:
        axis = ("x", "y", "yaw").index(r.move.axis)
        if r.move.axis == "yaw":
            assert abs(math.degrees(r.error[2])) <= 2.0
        else:
            assert abs(r.error[axis]) <= 0.02 * abs(r.truth[axis])


def test_a_route_that_does_not_fit_reports_the_bump(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("LUPIN_HW__COLLISION_MONITOR__ENABLED", "false")  # else it stops short of the crate
    world = load_default_world()
    crowded = world.model_copy(update={"obstacles": [*world.obstacles, world.obstacles[0].model_copy(
        update={"x": 1.6, "y": 0.5, "sx": 0.3, "sy": 0.3})]})
    path = tmp_path / "crowded.yaml"
    path.write_text(dump_world(crowded))
    out = tmp_path / "run"
    code = main(["sim", "drive", "--world", str(path), "--route", "straight", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == 0
    assert "bumped into obstacle_" in printed
    report = json.loads((out / "drive.json").read_text())
    assert report["bumps"] and report["completed"]
    (move,) = report["moves"]
    assert move["odom"][0] > move["truth"][0] + 0.2  # wheels spun on against the crate
    assert yaml.safe_load((out / "config.yaml").read_text())["sim"]["seed"] == 0


def _crowded(tmp_path):
    world = load_default_world()
    crowded = world.model_copy(update={"obstacles": [*world.obstacles, world.obstacles[0].model_copy(
        update={"x": 1.6, "y": 0.5, "sx": 0.3, "sy": 0.3})]})
    path = tmp_path / "crowded.yaml"
    path.write_text(dump_world(crowded))
    return path


def test_a_move_the_collision_monitor_holds_ends_the_route_at_once(tmp_path, capsys):
    """The crate 0.6 m ahead stops the straight move; the command says which move, the side and
    how near, and exits 1 within seconds of robot time, not after the 600 s limit."""
    out = tmp_path / "run"
    code = main(["sim", "drive", "--world", str(_crowded(tmp_path)), "--route", "straight", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 1
    assert "move 'forward 1 m' held by the collision monitor" in err and "ahead" in err
    report = json.loads((out / "drive.json").read_text())
    assert not report["completed"] and report["bumps"] == []
    assert report["sim_time_s"] < 10.0
    assert "held by the collision monitor" in report["held"]


def test_a_route_off_the_floor_is_refused_before_the_robot_moves(tmp_path, capsys):
    world = load_default_world()
    near_wall = world.model_copy(update={"spawn": world.spawn.model_copy(update={"x": 1.0, "y": 2.5})})
    path = tmp_path / "near.yaml"
    path.write_text(dump_world(near_wall))
    code = main(["sim", "drive", "--world", str(path), "--route", "tour", "--out", str(tmp_path / "run")])
    err = capsys.readouterr().err
    assert code == 2
    assert "move 'strafe left 2 m' would take the robot off the floor" in err and "Traceback" not in err
    assert not (tmp_path / "run" / "drive.json").exists()
