"""Walkers in world files (spec/world.md ``walkers``): a path through a pot, a wall or a box is
rejected naming the walker and what it crosses; ids unique; bad fields named; the generator's
walkers are valid and stable."""
from __future__ import annotations

import copy

import pytest

from hw.errors import InputError
from sim.generate import generate_world
from sim.world import dump_world, parse_world

WORLD = {
    "name": "aisle",
    "floor": {"x": 8.0, "y": 3.0},
    "spawn": {"x": 0.5, "y": 0.5, "yaw": 0.0},
    "pots": [{"id": "P01", "x": 3.0, "y": 1.0, "facing": -1.5708, "tag": 1, "flower": "red"}],
    "obstacles": [{"x": 6.0, "y": 2.5, "sx": 0.3, "sy": 0.3}],
    "walkers": [{"id": "W1", "path": [[2.0, 2.0], [7.0, 2.0]], "speed": 0.8}],
}


def _with(**walker):
    data = copy.deepcopy(WORLD)
    data["walkers"][0].update(walker)
    return data


def test_a_good_walker_reads_with_its_defaults_and_round_trips():
    world = parse_world(WORLD, "w.yaml")
    w = world.walkers[0]
    assert (w.pause, w.start, w.width, w.yields, w.posture) == (0.0, 0.0, 0.45, True, "standing")
    assert parse_world(__import__("yaml").safe_load(dump_world(world)), "again").walkers == world.walkers


def test_a_worker_who_stays_put_needs_no_speed_and_any_speed_will_do():
    for extra in ({}, {"speed": 0.0}, {"speed": 7.0}):
        world = parse_world(_with(path=[[4.0, 2.0]], posture="crouching", yields=False, **extra), "w.yaml")
        assert world.walkers[0].path == [[4.0, 2.0]]
    again = parse_world(__import__("yaml").safe_load(dump_world(world)), "again")
    assert again.walkers == world.walkers


def test_a_worker_who_stays_put_must_stand_clear_of_pots_and_walls():
    with pytest.raises(InputError, match=r"walkers\[0\] \(id W1\): field 'path': the point \(3, 1.2\) touches pots\[0\]"):
        parse_world(_with(path=[[3.0, 1.2]]), "w.yaml")
    with pytest.raises(InputError, match=r"the point \(3, 1.35\) touches pots\[0\]"):
        parse_world(_with(path=[[3.0, 1.35]], posture="crouching"), "w.yaml")  # the block is 0.6 m across
    parse_world(_with(path=[[3.0, 1.35]]), "w.yaml")  # a standing person fits there
    with pytest.raises(InputError, match="touches a wall"):
        parse_world(_with(path=[[7.9, 2.0]]), "w.yaml")


@pytest.mark.parametrize("path, crossed", [
    ([[2.0, 1.0], [4.0, 1.0]], "pots[0] (id P01)"),
    ([[2.0, 2.0], [9.0, 2.0]], "a wall"),
    ([[5.0, 2.5], [7.0, 2.5]], "obstacles[0] at (6, 2.5)"),
])
def test_a_path_through_something_names_the_walker_and_what_it_crosses(path, crossed):
    with pytest.raises(InputError) as exc:
        parse_world(_with(path=path), "w.yaml")
    msg = str(exc.value)
    assert msg.startswith("w.yaml: walkers[0] (id W1): field 'path': the segment")
    assert crossed in msg


def test_a_wide_walker_needs_a_wider_gap():
    parse_world(_with(path=[[2.0, 1.45], [4.0, 1.45]]), "w.yaml")  # a person passes 0.13 m from the pot
    with pytest.raises(InputError, match="crosses pots\\[0\\]"):
        parse_world(_with(path=[[2.0, 1.45], [4.0, 1.45]], width=1.0), "w.yaml")  # a cart does not


@pytest.mark.parametrize("walker, message", [
    ({"speed": 3.0}, "field 'speed'"),
    ({"path": []}, "field 'path'"),
    ({"speed": None}, "field 'speed': a path of 2 points is walked at 0.2..1.5 m/s (missing)"),
    ({"speed": 0.1}, "field 'speed'"),
    ({"yields": "sometimes"}, "field 'yields'"),
    ({"posture": "lying"}, "field 'posture': must be one of standing, crouching"),
    ({"posture": "crouching", "width": 0.9}, "field 'width': a crouching worker is at most 0.6 m wide"),
    ({"path": [[2.0, 2.0, 1.0], [3.0, 2.0]]}, "field 'path.0'"),
    ({"pause": -1}, "field 'pause'"),
    ({"width": 2.0}, "field 'width'"),
    ({"shirt": "red"}, "shirt"),
])
def test_bad_walker_fields_are_named(walker, message):
    with pytest.raises(InputError) as exc:
        parse_world(_with(**walker), "w.yaml")
    assert "walkers[0]" in str(exc.value) and message in str(exc.value)


def test_walker_ids_are_unique():
    data = copy.deepcopy(WORLD)
    data["walkers"].append(dict(data["walkers"][0]))
    with pytest.raises(InputError, match=r"walkers\[1\] \(id W1\): field 'id': duplicate of walkers\[0\]"):
        parse_world(data, "w.yaml")


def test_generated_walkers_are_a_mix_in_the_aisles_clear_of_the_spawn_and_leave_the_pots_alone():
    plain, peopled = generate_world(4, 6, seed=5), generate_world(4, 6, seed=5, walkers=4)
    assert plain.pots == peopled.pots and not plain.walkers
    assert [w.id for w in peopled.walkers] == [f"W{k}" for k in range(1, 5)]
    in_aisles = [w for w in peopled.walkers if w.yields]
    assert len({w.path[0][1] for w in in_aisles}) == len(in_aisles) == 3  # one per aisle
    pots_x = [p.x for p in plain.pots]
    for w in peopled.walkers:
        assert min(y for _, y in w.path) > 1.0  # never the south aisle the robot starts in
        if not w.yields:  # across the aisles' mouths, in a cross aisle clear of every pot
            (x0, y0), (x1, y1) = w.path
            assert x0 == x1 and y1 > y0 + 2.0 and (x0 < min(pots_x) - 0.5 or x0 > max(pots_x) + 0.5)
        elif len(w.path) == 2:
            (x0, y0), (x1, y1) = w.path
            assert y0 == y1 and x1 > x0 + 4.0  # along a whole aisle, first pot to last
            assert x0 >= min(pots_x) - 0.1 and x1 <= max(pots_x) + 0.1
        else:
            assert w.path[0][0] == pytest.approx(plain.floor.x - 0.4)  # a worker by the east wall
    kinds = [(len(w.path), w.posture, w.width > 0.6, w.yields) for w in peopled.walkers]
    assert kinds == [(2, "standing", False, False), (1, "standing", False, True), (2, "standing", True, True),
                     (1, "crouching", False, True)]
    many = generate_world(5, 6, seed=5, bays=2, walkers=10).walkers
    assert len(many) == 10 and sum(not w.yields for w in many) == 3  # a third or so do not yield
    assert len({w.path[0][0] for w in many if not w.yields}) == 3  # each its own cross aisle
    assert generate_world(4, 6, seed=5, walkers=4).walkers == peopled.walkers
    with pytest.raises(InputError, match="walkers must be a whole number from 0 to 50"):
        generate_world(4, 6, seed=5, walkers=51)
    with pytest.raises(InputError, match=r"at most 6 walkers in 1 bay\(s\) of 4 rows: one per aisle or cross "
                                         r"aisle, and at most 2 who do not yield \(got 7\)"):
        generate_world(4, 6, seed=5, walkers=7)
    assert len(generate_world(4, 6, seed=5, bays=2, walkers=8).walkers) == 8
