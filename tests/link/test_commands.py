"""Command checking: the token rule, malformed payloads refused with a reason, fuzzed input
never raising anything but a refusal."""
from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mission.link.commands import SCHEMAS, CommandRefused, parse_command

TOKEN = "s3cret"


def cmd(name, **args):
    return parse_command(name, json.dumps(args).encode(), TOKEN)


def test_engaging_the_soft_estop_needs_no_token_everything_else_does():
    assert cmd("estop", engaged=True).engaged is True
    with pytest.raises(CommandRefused, match="operator token"):
        cmd("estop", engaged=False)
    assert cmd("estop", engaged=False, token=TOKEN).engaged is False
    for name in ("resume", "pause", "mission_abort", "clear_map", "heal"):
        with pytest.raises(CommandRefused, match="operator token"):
            cmd(name)
        with pytest.raises(CommandRefused, match="operator token"):
            cmd(name, token="guess")
        cmd(name, token=TOKEN)


@pytest.mark.parametrize("name, payload, words", [
    ("reboot", b"{}", "unknown command 'reboot'"),
    ("teleop", b"not json", "not a JSON object"),
    ("teleop", b"[1, 2]", "must be a JSON object"),
    ("teleop", b'{"vx": "fast", "token": "s3cret"}', "teleop: vx:"),
    ("teleop", b'{"vx": 9.0, "token": "s3cret"}', "less than or equal to 1"),
    ("teleop", b'{"vx": NaN, "token": "s3cret"}', "teleop: vx:"),
    ("teleop", b'{"speed": 1, "token": "s3cret"}', "teleop: speed:"),
    ("gripper", b'{"action": "crush", "token": "s3cret"}', "gripper: action:"),
    ("estop", b"{}", "estop: engaged:"),
    ("snapshot", b'{"camera": "depth", "token": "s3cret"}', "snapshot: camera:"),
    ("teleop", b"\xff\xfe", "not a JSON object"),
    ("teleop", b"{" * 100000, "payload of"),
    ("clear_map", b'{"\\n": null}', "clear_map: \\n: Extra inputs"),  # found by hypothesis: one line, always
    ("mission_start", b'{"aisles": {"A": [[0, 0]]}, "token": "s3cret"}', "aisles.A.[key]"),
    ("mission_start", b'{"aisles": {"0": [[0, 0, 1]]}, "token": "s3cret"}', "aisles.0.0: List should have at most 2"),
])
def test_malformed_commands_are_refused_with_the_reason(name, payload, words):
    with pytest.raises(CommandRefused) as exc:
        parse_command(name, payload, TOKEN)
    assert words in str(exc.value)


json_values = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
                           lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
                           max_leaves=12)


@settings(max_examples=400, deadline=None)
@given(name=st.sampled_from(sorted(SCHEMAS)) | st.text(max_size=12),
       payload=st.binary(max_size=200) | json_values.map(lambda v: json.dumps(v).encode())
       | st.fixed_dictionaries({"token": st.sampled_from(["", TOKEN, "wrong"])}, optional={
           "engaged": st.booleans(), "vx": st.floats(), "name": st.text(max_size=5), "action": st.text(max_size=6)})
       .map(lambda d: json.dumps(d).encode()))
def test_fuzzed_commands_are_accepted_or_refused_never_raise(name, payload):
    try:
        args = parse_command(name, payload, TOKEN)
    except CommandRefused as exc:
        assert str(exc) and "\n" not in str(exc)
        return
    assert name in SCHEMAS
    assert json.loads(payload).get("token") == TOKEN or (name == "estop" and args.engaged)


def test_a_runtime_without_a_token_takes_only_the_stop():
    assert parse_command("estop", b'{"engaged": true}', "").engaged
    with pytest.raises(CommandRefused, match="no operator token"):
        parse_command("pause", b'{"token": ""}', "")


def test_a_mission_comes_with_a_fleets_aisles_as_outlines():
    args = cmd("mission_start", aisles={"3": [[0, 0], [1.5, 0], [1.5, 0.8]]}, token=TOKEN)
    assert args.aisles == {"3": [[0.0, 0.0], [1.5, 0.0], [1.5, 0.8]]} and cmd("mission_start", token=TOKEN).aisles is None
