"""World files (spec/world.md): the default greenhouse, round trips, and every class of bad file
rejected with one clear message naming the file, the entry and the field."""
from __future__ import annotations

import copy
import math
from pathlib import Path

import pytest
import yaml
from pydantic import ValidationError

from hw.errors import InputError
from sim.config import GreenhouseGeometry
from sim.world import (
    DEFAULT_WORLD,
    ROBOT_RADIUS,
    World,
    dump_world,
    load_default_world,
    load_world,
    parse_world,
    validate_world,
    world_problems,
)

GOOD = {
    "name": "tiny",
    "floor": {"x": 5.0, "y": 3.0},
    "spawn": {"x": 0.5, "y": 0.5, "yaw": 0.0},
    "pots": [
        {"id": "P01", "x": 2.0, "y": 1.0, "facing": -1.5708, "tag": 1, "flower": "red"},
        {"id": "P02", "x": 3.0, "y": 1.0, "facing": -1.5708, "tag": 2, "flower": "white", "blooms": 2},
    ],
    "obstacles": [{"x": 4.5, "y": 2.5, "sx": 0.3, "sy": 0.3}],
    "climate": {1: {"temperature": 20.0}},
}


def _write(tmp_path: Path, name: str, data) -> Path:
    path = tmp_path / f"{name}.yaml"
    if isinstance(data, bytes):
        path.write_bytes(data)
    elif isinstance(data, str):
        path.write_text(data)
    else:
        path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _load_error(path: Path) -> str:
    with pytest.raises(InputError) as info:
        load_world(path)
    return str(info.value)


# --- the built-in greenhouse ----------------------------------------------------------------


def test_default_world_is_the_documented_greenhouse():
    w = load_default_world()
    assert DEFAULT_WORLD.name == "default.yaml" and DEFAULT_WORLD.parent.parent.name == "sim"
    assert w.name == "default"
    assert (w.floor.x, w.floor.y) == (7.0, 4.0)
    assert (w.spawn.x, w.spawn.y, w.spawn.yaw) == (1.0, 0.5, 0.0)
    assert len(w.pots) == 12 and len({p.id for p in w.pots}) == 12
    assert sorted(p.tag for p in w.pots) == list(range(1, 13))
    for y, facing in ((1.0, -1.5708), (2.0, 1.5708), (3.0, -1.5708)):
        row = [p for p in w.pots if p.y == y]
        assert sorted(p.x for p in row) == [2.0, 3.0, 4.0, 5.0]
        assert all(p.facing == facing for p in row)
    flowers = [p.flower for p in w.pots]
    assert flowers.count("none") == 1
    assert {"red", "white", "pink"} <= set(flowers)
    assert sum(p.bug for p in w.pots) == 1
    assert {p.blooms for p in w.pots} == {1, 2, 3}
    assert len(w.obstacles) == 1
    assert w.climate and set(w.climate) <= {p.tag for p in w.pots}


def test_default_world_round_trips(tmp_path):
    w = load_default_world()
    again = load_world(_write(tmp_path, "again", dump_world(w)))
    assert again == w


def test_dump_omits_missing_tag_and_unknown_climate(tmp_path):
    data = copy.deepcopy(GOOD)
    del data["pots"][1]["tag"]
    w = parse_world(data, "mem")
    text = dump_world(w)
    assert "None" not in text and "null" not in text
    back = load_world(_write(tmp_path, "t", text))
    assert back == w and back.pots[1].tag is None and back.climate[1].humidity is None


def test_touching_pots_and_zero_optional_sections_are_fine():
    data = copy.deepcopy(GOOD)
    data["pots"][1]["x"] = 2.2  # edges touch: 0.20 m apart
    del data["obstacles"], data["climate"]
    w = parse_world(data, "mem")
    assert w.obstacles == [] and w.climate == {}


def test_geometry_argument_sets_the_pot_radius():
    w = parse_world(copy.deepcopy(GOOD), "mem")
    assert world_problems(w) == []
    assert any("overlaps pots[0]" in p for p in world_problems(w, GreenhouseGeometry(pot_radius=0.6)))


def test_yawed_obstacle_is_checked_in_its_own_frame():
    data = copy.deepcopy(GOOD)
    # A thin plank 1.0 x 0.1 m rotated 90 deg: it now runs north-south through P02's centre.
    data["obstacles"] = [{"x": 3.0, "y": 1.5, "sx": 1.0, "sy": 0.1, "yaw": math.pi / 2}]
    with pytest.raises(InputError, match=r"pots\[1\] \(id P02\) overlaps obstacles\[0\]"):
        parse_world(data, "mem")
    data["obstacles"][0]["yaw"] = 0.0  # east-west at y = 1.5: clear of both pots
    parse_world(data, "mem")


def test_spawn_clearance_uses_the_robot_radius():
    data = copy.deepcopy(GOOD)
    data["spawn"] = {"x": 2.0, "y": 1.0 - 0.10 - ROBOT_RADIUS + 0.01}
    with pytest.raises(InputError, match="spawn overlaps pots"):
        parse_world(data, "mem")
    data["spawn"]["y"] = 1.0 - 0.10 - ROBOT_RADIUS - 0.01
    parse_world(data, "mem")


def test_several_problems_are_reported_one_per_line():
    data = copy.deepcopy(GOOD)
    data["pots"][0]["flower"] = "blue"
    data["pots"][1]["blooms"] = 9
    with pytest.raises(InputError) as info:
        parse_world(data, "w.yaml")
    lines = str(info.value).splitlines()
    assert len(lines) == 2 and all(line.startswith("w.yaml: pots[") for line in lines)


def test_validate_world_on_a_model_built_in_code():
    w = parse_world(copy.deepcopy(GOOD), "mem")
    bad = w.model_copy(update={"spawn": w.spawn.model_copy(update={"x": -1.0})})
    with pytest.raises(InputError, match="code: spawn: field 'x'.*west wall"):
        validate_world(bad, "code")


def test_parse_world_rejects_a_non_mapping():
    with pytest.raises(InputError, match="src: top level: must be a mapping"):
        parse_world([1, 2], "src")


# --- every class of bad file ----------------------------------------------------------------


def _edit(fn):
    data = copy.deepcopy(GOOD)
    fn(data)
    return data


def _set(path, value):
    def apply(data):
        target = data
        for key in path[:-1]:
            target = target[key]
        target[path[-1]] = value
    return apply


def _del(path):
    def apply(data):
        target = data
        for key in path[:-1]:
            target = target[key]
        del target[path[-1]]
    return apply


BAD_DATA = {
    "unknown_top_key": (_set(["colour"], "red"), ["top level", "field 'colour'", "unknown key"]),
    "unknown_pot_key": (_set(["pots", 1, "colour"], "red"), ["pots[1] (id P02)", "field 'colour'", "unknown key"]),
    "unknown_floor_key": (_set(["floor", "z"], 2.0), ["floor", "field 'z'", "unknown key (allowed: x, y)"]),
    "missing_pot_key": (_del(["pots", 1, "flower"]), ["pots[1] (id P02)", "field 'flower'", "missing required key"]),
    "missing_top_key": (_del(["spawn"]), ["top level", "field 'spawn'", "missing required key"]),
    "duplicate_id": (_set(["pots", 1, "id"], "P01"), ["pots[1] (id P01)", "field 'id'", "duplicate of pots[0]"]),
    "duplicate_tag": (_set(["pots", 1, "tag"], 1), ["pots[1] (id P02)", "field 'tag'", "tag 1 is already on pots[0]"]),
    "tag_out_of_family": (_set(["pots", 1, "tag"], 587), ["pots[1] (id P02)", "field 'tag'", "0..586"]),
    "tag_negative": (_set(["pots", 0, "tag"], -1), ["pots[0] (id P01)", "field 'tag'", "36h11"]),
    "tag_bool": (_set(["pots", 0, "tag"], True), ["pots[0] (id P01)", "field 'tag'", "must be an integer (got true)"]),
    "pot_in_east_wall": (_set(["pots", 1, "x"], 4.95), ["pots[1] (id P02)", "field 'x'", "east wall"]),
    "pot_in_south_wall": (_set(["pots", 0, "y"], 0.05), ["pots[0] (id P01)", "field 'y'", "south wall"]),
    "pot_outside_floor": (_set(["pots", 0, "x"], -3.0), ["pots[0] (id P01)", "field 'x'", "west wall"]),
    "overlapping_pots": (_set(["pots", 1, "x"], 2.15),
                         ["pots[1] (id P02) overlaps pots[0] (id P01)", "0.15 m apart, need >= 0.20 m", "'x'"]),
    "pot_in_obstacle": (_set(["pots", 1], {"id": "P02", "x": 4.4, "y": 2.4, "facing": 0.0, "flower": "pink"}),
                        ["pots[1] (id P02) overlaps obstacles[0]", "'x'"]),
    "obstacle_outside": (_set(["obstacles", 0, "x"], 4.9), ["obstacles[0]", "'x'", "outside the floor"]),
    "obstacle_zero_size": (_set(["obstacles", 0, "sx"], 0.0), ["obstacles[0]", "field 'sx'", "must be > 0"]),
    "spawn_in_obstacle": (_set(["spawn"], {"x": 4.5, "y": 2.5}), ["spawn overlaps obstacles[0]", "'x'"]),
    "spawn_in_pot": (_set(["spawn"], {"x": 2.0, "y": 0.75}), ["spawn overlaps pots[0] (id P01)", "'x'"]),
    "spawn_outside": (_set(["spawn", "x"], 6.0), ["spawn", "field 'x'", "east wall"]),
    "bad_flower": (_set(["pots", 1, "flower"], "blue"),
                   ["pots[1] (id P02)", "field 'flower'", "must be one of red, white, pink, none (got 'blue')"]),
    "blooms_0": (_set(["pots", 1, "blooms"], 0), ["pots[1] (id P02)", "field 'blooms'", "must be >= 1 (got 0)"]),
    "blooms_4": (_set(["pots", 1, "blooms"], 4), ["pots[1] (id P02)", "field 'blooms'", "must be <= 3 (got 4)"]),
    "bad_type": (_set(["pots", 0, "x"], "abc"), ["pots[0] (id P01)", "field 'x'", "must be a number (got 'abc')"]),
    "empty_value": (_set(["pots", 0, "y"], None), ["pots[0] (id P01)", "field 'y'", "must be a number (got nothing)"]),
    "nan": (_set(["spawn", "yaw"], float("nan")), ["spawn", "field 'yaw'", "finite"]),
    "pots_not_a_list": (_set(["pots"], 5), ["top level", "field 'pots'", "must be a list"]),
    "pot_not_a_mapping": (_set(["pots", 1], "P02"), ["pots[1]", "must be a mapping"]),
    "climate_unknown_tag": (_set(["climate", 40], {"temperature": 20.0}), ["climate[40]", "key 40", "no pot carries tag 40"]),
    "climate_unknown_field": (_set(["climate", 1, "temp"], 20.0), ["climate[1]", "field 'temp'", "unknown key"]),
    "climate_out_of_range": (_set(["climate", 1, "humidity"], 140.0), ["climate[1]", "field 'humidity'", "<= 100"]),
    "climate_key_not_a_tag": (_set(["climate", "abc"], {"temperature": 1.0}), ["climate['abc']", "key 'abc'", "integer"]),
    "floor_zero": (_set(["floor", "x"], 0.0), ["floor", "field 'x'", "must be > 0 (got 0.0)"]),
    "floor_negative": (_set(["floor", "y"], -4.0), ["floor", "field 'y'", "must be > 0"]),
}


@pytest.mark.parametrize("case", sorted(BAD_DATA))
def test_bad_world_data_is_rejected_with_file_entry_and_field(tmp_path, case):
    edit, expected = BAD_DATA[case]
    path = _write(tmp_path, case, _edit(edit))
    message = _load_error(path)
    assert message.startswith(f"{path}: ")
    for text in expected:
        assert text in message, f"{text!r} not in {message!r}"


BAD_FILES = {
    "not_yaml": ("name: [unclosed\nfloor: {x: 1\n", ["not valid YAML", "line "]),
    "empty": ("", ["empty"]),
    "only_comments": ("# nothing here\n\n", ["empty"]),
    "list_top_level": ("- a\n- b\n", ["top level", "must be a mapping", "a list"]),
    "text_top_level": ("just some words\n", ["top level", "must be a mapping", "(got text 'just some words')"]),
    "binary": (b"\x89PNG\r\n\x1a\n\xff\xfe\x00", ["not a YAML world file"]),
    "duplicate_yaml_key": ("name: a\nname: b\n", ["not valid YAML", "duplicate key 'name'", "line 2"]),
    "python_tag": ("!!python/object:os.system {}\n", ["not valid YAML"]),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_files_are_rejected_with_the_file_name(tmp_path, case):
    content, expected = BAD_FILES[case]
    path = _write(tmp_path, case, content)
    message = _load_error(path)
    assert message.startswith(f"{path}: ")
    for text in expected:
        assert text in message, f"{text!r} not in {message!r}"


def test_missing_file_and_directory(tmp_path):
    assert _load_error(tmp_path / "nope.yaml") == f"{tmp_path / 'nope.yaml'}: world file not found"
    assert "is a directory" in _load_error(tmp_path)


def test_errors_carry_no_chained_traceback(tmp_path):
    path = _write(tmp_path, "bad", "name: [\n")
    with pytest.raises(InputError) as info:
        load_world(path)
    assert info.value.__cause__ is None and info.value.__suppress_context__


def test_world_model_forbids_unknown_fields_in_code_too():
    with pytest.raises(ValidationError):
        World.model_validate({**GOOD, "extra": 1})
