"""Events files (spec/events.md): every action of the spec reads; every mistake is one line
naming the file, the entry, its action and the field."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from hw.errors import InputError
from mission.patrol.events_file import load_events, parse_events
from mission.runtime.config import LupinConfig, with_overrides

SPEC_EXAMPLE = """
- {at: 30.0, do: estop, engaged: true}
- {at: 31.0, do: soft_estop, engaged: true}
- {at: 35.0, do: estop, engaged: false}
- {at: 36.0, do: resume}
- {at: 50.0, do: lidar_dropout, duration: 3.0}
- {at: 60.0, do: servo_stall, joint: shoulder_lift}
- {at: 70.0, do: battery, voltage: 11.0}
- {at: 80.0, do: clear_map}
- {at: 90.0, do: teleop, source: joy, vx: 0.2, vy: 0.0, wz: 0.0, duration: 1.0}
- {at: 95.0, do: place_box, x: 3.0, y: 1.0, sx: 0.3, sy: 0.3}
- {at: 0.0, do: controller_race, controllers: [mirte_base_controller], state: unconfigured}
- {at: 5.0, do: pause}
- {at: 40.0, do: move_pot, pot: P03, dx: 0.15, dy: 0.0, dyaw: 0.2}
- {at: 0.0, do: history_down, duration: 120.0}
- {at: 20.0, do: runtime_crash}
"""


def test_the_spec_example_reads_sorted_by_time(tmp_path):
    f = tmp_path / "events.yaml"
    f.write_text(SPEC_EXAMPLE)
    events = load_events(f, LupinConfig())
    assert [e.do for e in events][:4] == ["controller_race", "history_down", "pause", "runtime_crash"]
    assert next(e for e in events if e.do == "history_down").duration == 120.0
    assert [e.at for e in events] == sorted(e.at for e in events)
    stall = next(e for e in events if e.do == "servo_stall")
    assert stall.mode == "unload"  # the spec's "goes limp"


def test_any_event_may_wait_for_the_base_to_move():
    events = parse_events([{"at": 12.0, "do": "estop", "engaged": True, "when_moving": 0.2},
                           {"at": 20.0, "do": "estop", "engaged": False}], "e.yaml", LupinConfig())
    assert [e.when_moving for e in events] == [0.2, None]


def test_same_instant_events_keep_file_order():
    events = parse_events([{"at": 5.0, "do": "soft_estop", "engaged": True}, {"at": 1.0, "do": "pause"},
                           {"at": 5.0, "do": "estop", "engaged": True}], "e.yaml", LupinConfig())
    assert [e.do for e in events] == ["pause", "soft_estop", "estop"]


@pytest.mark.parametrize("data, message", [
    ({"at": 1}, "e.yaml: top level: must be a list of events"),
    ([{"at": 1, "do": "reboot"}], "e.yaml: events[0]: unknown action 'reboot' (known: estop, soft_estop"),
    ([{"at": 1}], "e.yaml: events[0]: field 'do': missing required key"),
    ([{"at": -1.0, "do": "pause"}], "e.yaml: events[0] (do pause): field 'at': must be >= 0 (got -1.0)"),
    ([{"at": 1, "do": "estop"}], "e.yaml: events[0] (do estop): field 'engaged': missing required key"),
    ([{"at": 1, "do": "estop", "engaged": "yes"}], "field 'engaged': must be true or false (got 'yes')"),
    ([{"at": 1, "do": "pause", "for": 2}], "e.yaml: events[0] (do pause): field 'for': unknown key (allowed: at, when_moving, do)"),
    ([{"at": 1, "do": "pause", "when_moving": 0}], "e.yaml: events[0] (do pause): field 'when_moving': must be > 0 (got 0)"),
    ([{"at": 1, "do": "estop", "engaged": True, "when_moving": "fast"}], "field 'when_moving': must be a number (got 'fast')"),
    ([{"at": 1, "do": "servo_stall", "joint": "knee"}], "events[0] (do servo_stall): field 'joint': must be one of shoulder_pan"),
    ([{"at": 1, "do": "servo_stall", "joint": "elbow", "mode": "melt"}], "field 'mode': must be one of unload, latch"),
    ([{"at": 1, "do": "teleop", "source": "auto", "duration": 1.0}], "field 'source': must be one of joy, manual (got 'auto')"),
    ([{"at": 1, "do": "teleop", "source": "joy", "duration": 0}], "field 'duration': must be > 0"),
    ([{"at": 1, "do": "battery", "voltage": float("nan")}], "field 'voltage': must be a finite number"),
    ([{"at": 1, "do": "controller_race", "controllers": ["nav2"], "state": "inactive"}],
     "field 'controllers': unknown 'nav2' (known: joint_state_broadcaster"),
    ([{"at": 1, "do": "camera_dropout", "camera": "depth", "duration": 1.0}], "field 'camera': must be one of front, wrist"),
    ([{"at": float(i), "do": "place_box", "x": 1.0, "y": 1.0, "sx": 0.2, "sy": 0.2} for i in range(5)],
     "events[4] (do place_box): at most 4 boxes"),
    ([7], "events[0]: must be a mapping"),
])
def test_mistakes_are_named(data, message):
    with pytest.raises(InputError) as exc:
        parse_events(data, "e.yaml", LupinConfig())
    assert message in str(exc.value)


class _World:
    """The two id lists the events file checks against (the sim's World has them)."""
    pots = [SimpleNamespace(id="P01"), SimpleNamespace(id="P02")]
    walkers = [SimpleNamespace(id="W1")]


def test_a_pot_moved_must_be_one_of_the_worlds():
    pots = _World()
    moved = parse_events([{"at": 3.0, "do": "move_pot", "pot": "P02", "dx": 0.1}], "e.yaml", LupinConfig(), pots)
    assert (moved[0].pot, moved[0].dx, moved[0].dy, moved[0].dyaw) == ("P02", 0.1, 0.0, 0.0)
    with pytest.raises(InputError, match=r"e.yaml: events\[0\] \(do move_pot\): field 'pot': the world has no pot 'P09'"):
        parse_events([{"at": 3.0, "do": "move_pot", "pot": "P09"}], "e.yaml", LupinConfig(), pots)
    with pytest.raises(InputError, match="field 'pot': missing required key"):
        parse_events([{"at": 3.0, "do": "move_pot", "dx": 0.1}], "e.yaml", LupinConfig(), pots)


def test_a_walker_event_must_name_one_of_the_worlds_walkers():
    stop = parse_events([{"at": 3.0, "do": "walker", "walker": "W1", "moving": False}], "e.yaml", LupinConfig(), _World())
    assert (stop[0].walker, stop[0].moving) == ("W1", False)
    with pytest.raises(InputError, match=r"events\[0\] \(do walker\): field 'walker': the world has no walker 'W7' \(walkers: W1\)"):
        parse_events([{"at": 3.0, "do": "walker", "walker": "W7", "moving": True}], "e.yaml", LupinConfig(), _World())
    with pytest.raises(InputError, match="field 'moving': missing required key"):
        parse_events([{"at": 3.0, "do": "walker", "walker": "W1"}], "e.yaml", LupinConfig(), _World())


def test_every_problem_is_reported_at_once():
    with pytest.raises(InputError) as exc:
        parse_events([{"at": 1, "do": "estop"}, {"at": 2, "do": "teleop", "source": "joy"}], "e.yaml", LupinConfig())
    lines = str(exc.value).splitlines()
    assert len(lines) == 2 and lines[0].startswith("e.yaml: events[0]") and lines[1].startswith("e.yaml: events[1]")


def test_clear_map_needs_a_live_map():
    amcl = with_overrides(LupinConfig(), {"nav": {"slam": False, "map_file": "map.yaml"}})
    with pytest.raises(InputError, match="no live map to clear"):
        parse_events([{"at": 1.0, "do": "clear_map"}], "e.yaml", amcl)


@pytest.mark.parametrize("text, message", [("", "the events file is empty"), ("- {at: 1, do: [", "not valid YAML")])
def test_unreadable_files(tmp_path, text, message):
    f = tmp_path / "events.yaml"
    f.write_text(text)
    with pytest.raises(InputError, match=message):
        load_events(f, LupinConfig())
