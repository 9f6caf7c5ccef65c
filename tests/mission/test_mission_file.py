"""Mission files (spec/mission.md): parsing, every kind of bad file, approach poses, the order,
`from-world` and its command."""
from __future__ import annotations

import math
import textwrap

import pytest

from hw.errors import InputError
from hw.odometry import Pose2D
from mission.approach import approach_pose
from lupin.cli import main
from mission.patrol.mission_file import dump_mission, load_mission, mission_from_world, parse_mission
from nav.frames import compose
from sim.world import DEFAULT_WORLD, Pose2, load_default_world

SPEC_EXAMPLE = textwrap.dedent("""\
    name: morning-patrol
    home: {x: 0.0, y: 0.0, yaw: 0.0}   # where to return at the end, and on low battery
    standoff: 0.5
    retries: 2
    nav_timeout: 60.0
    return_home: true
    pots:
      - id: P01
        x: 2.0
        y: 1.5
        facing: -1.5708
        tag: 1
    order: as_listed
    """)


def write(tmp_path, text, name="m.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_spec_example_parses(tmp_path):
    m = load_mission(write(tmp_path, SPEC_EXAMPLE))
    assert m.name == "morning-patrol" and m.retries == 2 and m.nav_timeout == 60.0 and m.return_home
    assert [(p.id, p.x, p.y, p.facing, p.tag) for p in m.pots] == [("P01", 2.0, 1.5, -1.5708, 1)]


def test_defaults_fill_what_is_left_out():
    m = parse_mission({"name": "n", "pots": [{"id": "A", "x": 1.0, "y": 2.0, "facing": 0.0}]}, "m.yaml")
    assert (m.standoff, m.retries, m.nav_timeout, m.return_home, m.order) == (0.5, 2, 60.0, True, "as_listed")
    assert m.pots[0].tag is None and (m.home.x, m.home.y, m.home.yaw) == (0.0, 0.0, 0.0)


def test_dump_and_load_round_trip(tmp_path):
    m = mission_from_world(load_default_world()).model_copy(update={"order": "nearest", "retries": 3})
    assert load_mission(write(tmp_path, dump_mission(m))) == m


def test_round_trip_keeps_untagged_pots_odd_names_and_every_setting(tmp_path):
    m = parse_mission({"name": "yes", "home": {"x": -1.25, "y": 0.1, "yaw": 3.0}, "standoff": 0.35, "retries": 5,
                       "nav_timeout": 12.5, "return_home": False, "order": "nearest", "pots": [
                           {"id": "007", "x": 1e-7, "y": -2.0, "facing": 1.0},
                           {"id": "on", "x": 1.0, "y": 2.0, "facing": -0.5, "tag": 586}]}, "m.yaml")
    text = dump_mission(m)
    pot_lines = [line for line in text.splitlines() if line.startswith("- {id: ")]  # one pot per line
    assert text.startswith("#") and len(pot_lines) == 2
    assert "'007'" in pot_lines[0] and "tag" not in pot_lines[0]  # the untagged pot has no tag key
    back = load_mission(write(tmp_path, text))
    assert back == m and back.pots[0].tag is None and back.pots[0].id == "007"


@pytest.mark.parametrize("text, words", [
    ("name: [", ["not valid YAML"]),
    ("- just\n- a list\n", ["top level", "mapping", "a list"]),
    ("name: x\n", ["top level", "field 'pots'", "missing required key"]),
    ("name: x\npots: []\n", ["top level", "field 'pots'", "at least 1"]),
    ("name: x\nspeed: 3\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0}\n", ["speed", "unknown key"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0, colour: red}\n", ["pots[0] (id A)", "colour", "unknown key"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, facing: 0.0}\n", ["pots[0] (id A)", "field 'y'", "missing"]),
    ("name: x\npots:\n  - {id: A, x: '1.0', y: 1.0, facing: 0.0}\n", ["pots[0] (id A)", "field 'x'"]),
    ("name: x\npots:\n  - {id: A, x: .nan, y: 1.0, facing: 0.0}\n", ["pots[0] (id A)", "field 'x'", "finite"]),
    ("name: x\norder: random\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0}\n", ["field 'order'", "as_listed, nearest"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0, tag: 900}\n", ["pots[0] (id A)", "field 'tag'", "0..586"]),
    ("name: x\nretries: 0\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0}\n", ["field 'retries'", ">= 1"]),
    ("name: x\nhome: {x: 1.0, z: 2.0}\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0}\n", ["home", "field 'z'"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0}\n  - {id: A, x: 2.0, y: 1.0, facing: 0.0}\n",
     ["pots[1] (id A)", "field 'id'", "pots[0] (id A)"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, y: 1.0, facing: 0.0, tag: 3}\n  - {id: B, x: 2.0, y: 1.0, facing: 0.0, tag: 3}\n",
     ["pots[1] (id B)", "same tag 3", "pots[0] (id A)", "'tag'"]),
    ("name: x\npots:\n  - {id: A, x: 1.0, x: 2.0, y: 1.0, facing: 0.0}\n", ["duplicate key"]),
])
def test_bad_files_name_the_file_the_entry_and_the_field(tmp_path, text, words):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as err:
        load_mission(path)
    message = str(err.value)
    assert message.startswith(str(path)) and all(w in message for w in words), message


def test_missing_and_empty_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        load_mission(tmp_path / "nope.yaml")
    with pytest.raises(InputError, match=str(tmp_path / "empty.yaml")):
        load_mission(write(tmp_path, "", "empty.yaml"))


def test_every_problem_of_a_file_is_reported_at_once(tmp_path):
    path = write(tmp_path, "name: x\npots:\n  - {id: A, x: a, y: 1.0, facing: 0.0}\n  - {id: B, x: 1.0, y: b, facing: 0.0}\n")
    with pytest.raises(InputError) as err:
        load_mission(path)
    assert len(str(err.value).splitlines()) == 2


def test_the_approach_pose_stands_off_along_facing_looking_back():
    m = parse_mission({"name": "n", "standoff": 0.4, "pots": [
        {"id": "A", "x": 2.0, "y": 1.0, "facing": -math.pi / 2},
        {"id": "B", "x": 0.0, "y": 0.0, "facing": math.pi}]}, "m.yaml")
    assert m.approach(m.pots[0]) == pytest.approx((2.0, 0.6, math.pi / 2))
    assert m.approach(m.pots[1]) == pytest.approx((-0.4, 0.0, 0.0), abs=1e-12)  # pi + pi wraps to 0


def test_the_approach_heading_is_wrapped_to_minus_pi_exclusive_pi_inclusive():
    m = parse_mission({"name": "n", "pots": [
        {"id": "A", "x": 1.0, "y": 1.0, "facing": 0.0},
        {"id": "B", "x": 0.0, "y": 0.0, "facing": math.pi / 4}]}, "m.yaml")
    assert m.approach(m.pots[0]) == (1.5, 1.0, math.pi)  # not -pi
    h = 0.5 / math.sqrt(2)
    assert m.approach(m.pots[1]) == pytest.approx((h, h, -3 * math.pi / 4))


def test_from_world_puts_pots_in_the_dock_frame():
    world = load_default_world()  # spawn (1.0, 0.5) looking east
    m = mission_from_world(world)
    p01 = m.pots[0]
    assert (p01.id, p01.x, p01.y, p01.facing, p01.tag) == ("P01", 1.0, 0.5, -1.5708, 1)
    assert len(m.pots) == len(world.pots) and m.name == "default-patrol"
    assert (m.home.x, m.home.y, m.home.yaw) == (0.0, 0.0, 0.0)


def test_from_world_with_a_spawn_looking_north_rotates_the_pots():
    world = load_default_world()
    world = world.model_copy(update={"spawn": Pose2(x=1.0, y=0.5, yaw=math.pi / 2)})
    m = mission_from_world(world)
    p01, p05 = m.pots[0], m.pots[4]  # world (2.0, 1.0) facing south; (2.0, 2.0) facing north
    assert (p01.x, p01.y) == (0.5, -1.0)  # 0.5 ahead (north), 1.0 to the right (east); rounded exactly
    assert -math.pi < p01.facing <= math.pi and p01.facing == pytest.approx(math.pi, abs=1e-4)  # south is behind
    assert (p05.x, p05.y) == (1.5, -1.0) and p05.facing == pytest.approx(0.0, abs=1e-4)  # north is ahead


def test_from_world_approach_poses_land_where_the_world_puts_them():
    world = load_default_world()
    world = world.model_copy(update={"spawn": Pose2(x=-0.7, y=2.3, yaw=2.5)})
    m = mission_from_world(world)
    dock = Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw)
    for pot, wp in zip(m.pots, world.pots, strict=True):
        seen = compose(dock, Pose2D(*m.approach(pot)))  # back into the world frame
        want = approach_pose(wp.x, wp.y, wp.facing, m.standoff)
        assert (seen.x, seen.y) == pytest.approx((want.x, want.y), abs=1e-5), pot.id
        assert math.remainder(seen.yaw - want.yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-5), pot.id
        assert pot.tag == wp.tag


def test_the_from_world_command(tmp_path, capsys):
    out = tmp_path / "sub" / "patrol.yaml"
    assert main(["mission", "from-world", str(DEFAULT_WORLD), "-o", str(out)]) == 0
    assert load_mission(out) == mission_from_world(load_default_world())
    assert list(out.parent.iterdir()) == [out]  # no temporary file left beside it
    capsys.readouterr()
    assert main(["mission", "from-world", str(DEFAULT_WORLD)]) == 0
    assert capsys.readouterr().out.startswith("# Lupin patrol mission")


def test_the_from_world_command_on_a_bad_world(tmp_path, capsys):
    bad = write(tmp_path, "name: w\nfloor: {x: 5.0, y: 4.0}\n", "w.yaml")
    assert main(["mission", "from-world", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(bad) in err[0]
