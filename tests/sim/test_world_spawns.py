"""A fleet's docks in a world file (spec/world.md ``spawns``) and ``lupin sim generate --robots N``."""
from __future__ import annotations

import pytest
import yaml

from hw.errors import InputError
from lupin.cli import main
from sim.generate import generate_world
from sim.world import dump_world, load_world


def test_generate_robots_writes_a_dock_per_robot_that_loads_back(tmp_path):
    world = generate_world(3, 4, seed=1, robots=3)
    path = tmp_path / "fleet.yaml"
    path.write_text(dump_world(world))
    again = load_world(path)
    assert again == world
    assert [(p.x, p.y) for p in again.spawn_poses] == [(1.0, 0.5), (1.0, 1.5), (1.0, 2.5)]
    assert again.spawn_poses[0] == again.spawn
    one = generate_world(3, 4, seed=1)
    assert one.spawns == [] and one.spawn_poses == [one.spawn] and "spawns" not in dump_world(one)
    assert one.pots == world.pots  # the docks moved nothing else


def _with_spawns(tmp_path, spawns) -> str:
    data = yaml.safe_load(dump_world(generate_world(3, 4, seed=1)))
    data["spawns"] = spawns
    path = tmp_path / "w.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(InputError) as err:
        load_world(path)
    assert str(err.value).startswith(str(path))
    return str(err.value)


def test_bad_spawns_are_named_by_entry_and_field(tmp_path):
    first = {"x": 1.0, "y": 0.5, "yaw": 0.0}
    assert "spawns[0]: fields 'x', 'y', 'yaw'" in _with_spawns(tmp_path, [{"x": 1.0, "y": 1.5, "yaw": 0.0}])
    msg = _with_spawns(tmp_path, [first, {"x": 1.2, "y": 0.6, "yaw": 0.0}])
    assert "spawns[1]: fields 'x', 'y': 0.22 m from spawns[0]" in msg
    assert "spawns[1] overlaps pots[0]" in _with_spawns(tmp_path, [first, {"x": 2.0, "y": 1.1, "yaw": 0.0}])
    assert "spawns[1]:" in _with_spawns(tmp_path, [first, {"x": -1.0, "y": 1.5, "yaw": 0.0}])
    assert "spawns[1]" in _with_spawns(tmp_path, [first, {"x": 1.0, "y": 1.5, "z": 0.0}])  # an unknown key


def test_sim_generate_robots_on_the_command_line(tmp_path, capsys):
    out = tmp_path / "g.yaml"
    assert main(["sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "4", "--robots", "3", "-o", str(out)]) == 0
    assert len(load_world(out).spawn_poses) == 3
    assert main(["sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "4", "--robots", "4"]) == 2
    err = capsys.readouterr().err
    assert "--robots 4" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert main(["sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "4", "--robots", "0"]) == 2


def test_each_robot_of_a_fleet_knows_the_world_from_its_own_dock():
    world = generate_world(3, 4, seed=1, robots=3)
    r2 = world.for_robot(1)
    assert r2.spawn == r2.dock_pose == world.spawns[1] and r2.spawns == world.spawns and r2.pots == world.pots
    one = generate_world(3, 4, seed=1).model_copy(update={"dock": world.spawns[1]})
    assert one.for_robot(0) == one  # one spawn: the world as it is, its own dock kept
