"""Every key binding under Pilot against a recording ``Commands``: each key sends exactly its
command with exactly its arguments, and nothing else."""
from __future__ import annotations

from tests.tui.fakes import console, estopped_view, idle_view, patrolling_view
from tui.keys import BINDINGS

TWIST = "teleop"
EXPECTED = {  # key -> what it sends, written out by hand (not derived from tui.keys)
    "up": [(TWIST, {"vx": 0.2, "vy": 0.0, "wz": 0.0})],
    "down": [(TWIST, {"vx": -0.2, "vy": 0.0, "wz": 0.0})],
    "left": [(TWIST, {"vx": 0.0, "vy": 0.2, "wz": 0.0})],  # strafe left: +y (REP-103)
    "right": [(TWIST, {"vx": 0.0, "vy": -0.2, "wz": 0.0})],
    "q": [(TWIST, {"vx": 0.0, "vy": 0.0, "wz": 0.5})],
    "e": [(TWIST, {"vx": 0.0, "vy": 0.0, "wz": -0.5})],
    "space": [("estop", {"engaged": True})],
    "u": [("estop", {"engaged": False})],
    "r": [("resume", {})],
    "m": [("mission_start", {})],
    "p": [("pause", {})],
    "1": [("arm_preset", {"name": "home"})],
    "2": [("arm_preset", {"name": "zero"})],
    "3": [("arm_preset", {"name": "tuck"})],
    "4": [("arm_preset", {"name": "pick"})],
    "5": [("arm_preset", {"name": "place"})],
    "6": [("arm_preset", {"name": "inspect"})],
    "o": [("gripper", {"action": "open"})],
    "g": [("gripper", {"action": "close"})],
    "f": [],  # snapshots are not commands: below
    "w": [],
    # the view keys change what the console shows and send nothing (tests/tui/test_scale.py)
    "plus": [], "equals_sign": [], "minus": [], "h": [], "j": [], "k": [], "l": [], "t": [], "0": [], "a": [],
    "left_square_bracket": [], "right_square_bracket": [],
    "i": [],  # the pot's timeline: a history question, not a command (tests/tui/test_history.py); last: a screen
}


def press_each(view_source, keys):
    """Press ``keys`` one at a time in one console: [(key, commands sent, cameras fetched)]."""
    presses, at = [], {}

    def before(app):
        at["sent"], at["shots"] = len(app.commands.sent), len(app.commands.snapshots)

    def after(key):
        return lambda app: presses.append((key, app.commands.sent[at["sent"]:], app.commands.snapshots[at["shots"]:]))

    steps = []
    for k in keys:
        steps += [before, k, after(k)]
    console(view_source, steps)
    return presses


def test_each_key_sends_exactly_its_command():
    presses = press_each(patrolling_view, list(EXPECTED))
    assert {key: sent for key, sent, _ in presses} == EXPECTED
    assert {key: shots for key, _, shots in presses if shots} == {"f": ["front"], "w": ["wrist"]}


def test_space_never_releases_the_estop_however_often_it_is_pressed():
    """A panicked double tap on an engaged robot engages again; only ``u`` releases."""
    presses = press_each(estopped_view, ["space", "space", "u"])
    assert [sent for _, sent, _ in presses] == [[("estop", {"engaged": True})]] * 2 + [[("estop", {"engaged": False})]]


def test_holding_a_drive_key_sends_a_twist_per_repeat():
    presses = press_each(idle_view, ["left"] * 4)  # auto-repeat: the same key, again and again
    assert [sent for _, sent, _ in presses] == [[(TWIST, {"vx": 0.0, "vy": 0.2, "wz": 0.0})]] * 4


def test_clear_map_asks_first():
    assert console(patrolling_view, ["c", "n"])[0].sent == []
    assert console(patrolling_view, ["c", "escape"])[0].sent == []
    assert console(patrolling_view, ["c", "y"])[0].sent == [("clear_map", {})]


def test_the_screen_keeps_redrawing_under_the_question():
    renders = []
    view = patrolling_view()

    def move(app):
        view.pose = (2.5, 0.5, 0.3)
        renders.append(app.main.map_panel.renders)
        app.redraw()
        renders.append(app.main.map_panel.renders)

    rec, app = console(lambda: view, ["c", move, "n"])
    assert rec.sent == [] and renders[1] == renders[0] + 1


def test_the_estop_and_driving_work_while_the_question_is_up():
    def question_up(app):
        assert type(app.screen).__name__ == "Confirm"

    rec, _ = console(patrolling_view, ["c", question_up, "space", "up", question_up, "n"])
    assert rec.sent == [("estop", {"engaged": True}), (TWIST, {"vx": 0.2, "vy": 0.0, "wz": 0.0})]


def test_the_footer_says_what_space_and_u_do():
    def footer_keys(app):
        return {b.key: b.description for _, b, enabled, _ in app.screen.active_bindings.values() if enabled}

    seen = {}
    console(estopped_view, [lambda app: seen.update(footer_keys(app))])
    assert (seen["space"], seen["u"]) == ("E-STOP", "release e-stop")


def test_every_binding_is_tested_here():
    bound = {key for b in BINDINGS for key in b.key.split(",")} - {"ctrl+q"}
    assert bound == set(EXPECTED) | {"c"}


def test_the_footer_shows_every_key_the_view_keys_on_a_line_of_their_own():
    chips = ["↑↓ drive", "←→ strafe", "q e turn", "space E-STOP", "u release e-stop", "r resume", "m mission",
             "p pause", "c clear map", "123456 arm", "o g gripper", "f w camera", "^q quit",
             "+- zoom", "hjkl pan", "t follow robot", "0 fit map", "a pots with anomalies", "[] select pot",
             "i pot timeline"]
    for width, lines in ((160, 2), (100, 3)):
        seen = {}
        console(patrolling_view, [lambda app: seen.update(text=app.main.query_one("#keys").text.plain)],
                size=(width, 40))
        shown = seen["text"].split("\n")
        assert len(shown) == lines and all(len(line) <= width - 2 for line in shown)  # wrapped, nothing cut off
        assert shown[-1].startswith("+- zoom")  # the view's keys: the last line, on their own
        for chip in chips:
            assert sum(chip in line for line in shown) == 1, chip
