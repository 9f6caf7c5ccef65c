"""The console's behaviour beyond single keys: refusals shown, a slow or broken link, the
camera, and each panel redrawing what changed (and only that)."""
from __future__ import annotations

import asyncio
import threading

from mission.link.view import RobotView
from tests.tui.fakes import SIZE, Recorder, console, idle_view, patrolling_view
from tui.app import make_app
from tui.widgets.mission_tree import running_line, tree_text
from tui.widgets.status_bar import status_text

UP = ("teleop", {"vx": 0.2, "vy": 0.0, "wz": 0.0})


def log_text(app) -> str:
    return "\n".join(line.text for line in app.main.log_panel.lines)


# --- refusals and the link --------------------------------------------------------------------
def test_a_refused_command_is_shown_in_the_log_and_as_a_notification():
    notes = []
    rec, app = console(idle_view, ["p"], Recorder(refuse={"pause": "pause: no mission is running"}), notifications=notes)
    assert rec.sent == [("pause", {})]
    assert "[console] pause: no mission is running" in log_text(app)
    assert notes == ["pause: no mission is running"]


def test_a_run_of_the_same_teleop_refusal_is_told_once():
    notes = []
    rec, app = console(idle_view, ["up"] * 3, Recorder(refuse={"teleop": "teleop: e-stop engaged"}), notifications=notes)
    assert rec.sent == [UP] * 3
    assert notes == ["teleop: e-stop engaged"] and log_text(app).count("e-stop engaged") == 1


def test_a_link_that_raises_is_shown_and_the_console_goes_on():
    notes = []
    rec, app = console(idle_view, ["r", "m"], Recorder(refuse={"resume": ConnectionError("link down")}), notifications=notes)
    assert rec.sent == [("resume", {}), ("mission_start", {})]
    assert notes == ["resume: ConnectionError: link down"]


def behind_a_slow_one(first: str, keys: list[str], group: str) -> tuple[list, list[int]]:
    """Press ``first`` over a link that holds it, then ``keys`` while it is stuck; what was
    sent, in order, and how many of ``group``'s workers were busy meanwhile."""
    hold = threading.Event()
    rec = Recorder(hold=hold)
    busy = []

    async def go():
        app = make_app(idle_view, rec)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press(first)
            for _ in range(1000):  # until the first is on its way (and stuck)
                if rec.entered.is_set():
                    break
                await pilot.pause(0.01)
            for key in keys:
                await pilot.press(key)
            busy.append(sum(1 for w in app.workers if w.group == group and not w.is_finished))
            hold.set()
            await app.workers.wait_for_complete()
            await pilot.pause()

    asyncio.run(go())
    return rec.sent, busy


def test_a_slow_link_never_builds_a_backlog_of_twists():
    """Twists pressed while one is on its way replace each other: only the newest goes next,
    so letting go of the key stops the robot however slow the link."""
    sent, busy = behind_a_slow_one("up", ["left", "right", "q", "e"], "teleop")
    assert busy == [1]
    assert sent == [UP, ("teleop", {"vx": 0.0, "vy": 0.0, "wz": -0.5})]


def commands_behind_a_slow_one(keys: list[str]) -> tuple[list, list[int]]:
    """``behind_a_slow_one`` for the operator's commands, behind a held ``pause``."""
    return behind_a_slow_one("p", keys, "commands")


STOP, RELEASE = ("estop", {"engaged": True}), ("estop", {"engaged": False})


def test_commands_reach_the_robot_in_the_order_pressed():
    """A stop then a release arrive in that order, whatever the threads do (one worker): with
    a worker per command the release could land first and be undone by the stop."""
    sent, busy = commands_behind_a_slow_one(["space", "u", "r"])
    assert busy == [1]
    assert sent == [("pause", {}), STOP, RELEASE, ("resume", {})]


def test_a_stop_goes_first_and_takes_a_waiting_release_with_it():
    """The last press of the stop key wins: a release still waiting is dropped, the stop jumps
    the queue, and what was pressed before it otherwise keeps its order."""
    sent, _ = commands_behind_a_slow_one(["u", "r", "m", "space"])
    assert sent == [("pause", {}), STOP, ("resume", {}), ("mission_start", {})]


# --- camera ------------------------------------------------------------------------------------
class NoFrames(Recorder):
    def snapshot(self, camera):
        self.snapshots.append(camera)
        return None


def camera_text(app) -> str:
    return str(app.main.camera_panel.render())


def test_snapshot_keys_fetch_and_draw_the_camera():
    shown = {}
    rec, _ = console(idle_view, ["f", lambda app: shown.setdefault("f", camera_text(app)),
                                 "w", lambda app: shown.setdefault("w", camera_text(app))])
    assert rec.snapshots == ["front", "wrist"]
    assert shown["f"].startswith("front camera\n") and "▀" in shown["f"]
    assert shown["w"].startswith("wrist camera\n")
    shown.clear()
    console(idle_view, ["f", lambda app: shown.setdefault("f", camera_text(app))], NoFrames())
    assert shown["f"] == "front: no frame"


# --- panels ------------------------------------------------------------------------------------
def test_the_status_bar_says_what_matters():
    v = idle_view()
    text = status_text(v).plain
    for part in ("mirte", "link ok", "e-stop clear", "battery 38% 12.60 V", "mission: idle", "nav: idle",
                 "wheels: idle", "controllers: all active"):
        assert part in text
    v.connected, v.battery_low, v.battery_current = False, True, 1.25
    v.estop_latched, v.nav_state, v.nav_reason = True, "failed", "no path"
    v.controllers["arm_controller"] = "inactive"
    v.mission_state, v.mission_step = "estop", "approach P03"
    text = status_text(v).plain
    for part in ("NO LINK", "battery 38% 12.60 V 1.2 A LOW", "e-stop released: r to resume", "nav: failed (no path)",
                 "controllers: arm_controller inactive", "mission: estop / approach P03"):
        assert part in text
    v.estop_engaged = True
    assert "E-STOP ENGAGED" in status_text(v).plain
    assert "stop" not in status_text(idle_view()).plain.replace("e-stop", "")  # the monitor says nothing when clear
    v.monitor_action, v.monitor_nearest = "slowdown", 0.52
    assert " slowdown 0.52 m " in status_text(v).plain


def test_the_status_bar_wraps_between_chips_on_a_narrow_terminal():
    v = patrolling_view()
    lines = status_text(v, 60).plain.split("\n")
    assert len(lines) > 1 and all(len(line) <= 60 for line in lines)
    assert "\n" not in status_text(v, 400).plain


def test_the_tree_is_read_not_shown_raw_and_its_running_step_found():
    coloured = "{-} patrol [\x1b[34m*\x1b[0m]\n    --> approach P03 [\x1b[34m*\x1b[0m]\n    --> P04 [\x1b[33m-\x1b[0m]"
    text = tree_text(coloured)
    assert "\x1b" not in text.plain and text.plain.splitlines()[1] == "    --> approach P03 [*]"
    assert running_line(text.plain) == 1
    assert running_line(patrolling_view().tree) == 6  # the deepest running line
    assert running_line("{-} patrol [✓]") is None


def test_the_tree_panel_follows_the_running_step():
    v = idle_view()
    lines = [f"    --> step {i} [✓]" for i in range(300)]
    lines[250] = "    --> step 250 [*]"
    v.tree = "{-} patrol [*]\n" + "\n".join(lines)
    seen = {}

    def look(app):
        tree = app.main.mission_tree
        seen["top"], seen["height"] = tree.scroll_y, tree.scrollable_content_region.height

    console(lambda: v, [look])
    assert seen["top"] <= 251 < seen["top"] + seen["height"]


def test_the_pots_table_updates_a_row_and_keeps_the_others_drawn():
    v = patrolling_view()
    seen = {}

    def finish_p03(app):
        table = app.main.pots_table
        seen["rows"] = table.row_count
        seen["kept"] = dict(table._strips)
        v.pots[2].status, v.pots[2].tag, v.pots[2].flower, v.pots[2].blooms = "inspected", 3, "pink", 2
        app.redraw()

    def look(app):
        table = app.main.pots_table
        seen["after"] = table.row_count
        seen["P03"] = table.row("P03")[1:5]
        seen["same"] = [i for i, s in seen["kept"].items() if table._strips.get(i) is s]

    console(lambda: v, [finish_p03, look])
    assert seen["rows"] == seen["after"] == 6 and seen["P03"] == ("inspected", "3", "pink", "2")
    assert sorted(seen["same"]) == [0, 1, 3, 4, 5]  # only P03's row was drawn again


def test_the_log_panel_follows_a_rolling_window():
    """The link client keeps the last 200 lines: once full, the list stops growing but moves."""
    v = idle_view()
    v.log = [f"line {i}" for i in range(200)]

    def roll(app):
        v.log = v.log[3:] + ["line 200", "line 201", "line 202"]  # a new list, as the client makes
        app.redraw()

    rec, app = console(lambda: v, [roll])
    shown = [line.text for line in app.main.log_panel.lines]
    assert shown == [f"line {i}" for i in range(203)]


def test_the_map_is_redrawn_only_when_what_it_shows_changed():
    v = patrolling_view()
    counts = []

    def count(app):
        counts.append(app.main.map_panel.renders)

    def poll(app):
        app.redraw()

    def move(app):
        v.pose = (2.1, 0.5, 0.3)
        app.redraw()

    def cells_in_place(app):  # the link applies map deltas to the same array
        v.grid.data[50, 50] = 100
        app.redraw()

    def new_log_line(app):
        v.log = v.log + ["  41.0 I something"]
        app.redraw()

    console(lambda: v, [count, poll, poll, count, move, count, cells_in_place, count, new_log_line, count])
    assert counts[1] == counts[0] and counts[2] == counts[1] + 1 and counts[3] == counts[2] + 1 and counts[4] == counts[3]


def test_a_view_with_nothing_in_it_still_draws():
    seen = {}
    rec, app = console(RobotView, ["up", lambda app: seen.setdefault("status", str(app.main.status_bar.render()))])
    assert rec.sent == [UP] and "NO LINK" in seen["status"] and "battery ?" in seen["status"]
