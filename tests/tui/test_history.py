"""The console reading the robot's patrol history (issue 22): the pot table's "since last" and
pest-streak columns, ``[`` / ``]`` and a click picking a pot, ``i`` opening its timeline, and a
robot (or a link) without a history saying so. Under Pilot against a fake link that answers
as ``lupin serve`` does (tests/tui/fakes.py)."""
from __future__ import annotations

import asyncio
import threading

from tests.tui.fakes import (SIZE, HistoryRecorder, Recorder, console, entry, greenhouse_view, patrol_history,
                             patrolling_view)
from tui.app import NO_HISTORY, make_app
from tui.history_marks import PotMarks, change_text, pot_marks, since_texts
from tui.screens.timeline import Timeline

NO_HISTORY_ON_ROBOT = "history: this robot records no patrol history (--history none)"


def table_of(seen: dict, key: str = "table"):
    def look(app):
        t = app.main.pots_table
        seen[key] = {"rows": {r[0]: r for r in t.rows}, "header": t.header.plain if t.header else "",
                     "widest": max(len(line.plain) for line in [t.header] + t.lines),
                     "width": t.scrollable_content_region.width}
    return look


def timeline_of(seen: dict, key: str = "timeline"):
    def look(app):
        s = app.screen
        seen[key] = None if not isinstance(s, Timeline) else {
            "pot": s.pot, "message": str(s.message.render()),
            "lines": [line.plain.split() for line in s.table.lines]}
    return look


def screen_name(seen: dict, key: str):
    return lambda app: seen.__setitem__(key, type(app.screen).__name__)


# --- what a change and a streak read as -------------------------------------------------------
def test_each_kind_of_change_in_a_few_characters():
    assert [change_text(c) for c in (
        {"kind": "pest_new"}, {"kind": "pest_cleared"}, {"kind": "color", "before": "red", "after": "pink"},
        {"kind": "blooms", "before": 2, "after": 3}, {"kind": "failed", "before": "inspected"})] == \
        ["pest new", "pest gone", "red→pink", "bloom 2→3", "failed now"]


def test_a_pot_with_several_changes_names_the_most_telling_and_counts_the_rest():
    changes = {"changes": [{"pot": "P01", "kind": "blooms", "before": 1, "after": 2},
                           {"pot": "P01", "kind": "color", "before": "red", "after": "pink"},
                           {"pot": "P01", "kind": "pest_new"},
                           {"pot": "P02", "kind": "blooms", "before": 2, "after": 1}]}
    assert since_texts(changes) == {"P01": "pest new +2", "P02": "bloom 2→1"}
    assert since_texts(None) == {} and since_texts({"changes": None}) == {}


def test_a_pot_the_running_patrol_has_not_reached_keeps_its_streak():
    """The running patrol is the history's latest: it has not judged the pots ahead, so their
    streak reads 0 there; the console keeps the one it knew. A pot it has judged gets the new one."""
    known = {"P03": PotMarks(streak=2), "P04": PotMarks(streak=4), "P01": PotMarks(streak=5)}
    pests = {"last": 20, "pots": [{"pot_id": "P02", "streak": 1}]}
    marks = pot_marks(None, pests, known, not_yet=["P03", "P04"])
    assert {p: m.streak for p, m in marks.items()} == {"P02": 1, "P03": 2, "P04": 4}  # P01 judged now: no pest
    assert pot_marks(None, {"last": 3, "pots": [{"pot_id": "P01", "streak": 3}]})["P01"].streak_text == "x3+"


# --- the pot table ---------------------------------------------------------------------------
def test_the_pot_table_shows_what_changed_since_the_last_patrol_and_the_pest_streak():
    seen = {}
    rec, _ = console(patrolling_view, [table_of(seen)], HistoryRecorder(patrol_history()))
    rows, header = seen["table"]["rows"], seen["table"]["header"].split()
    assert header[-3:] == ["since", "last", "pests"]
    assert rows["P01"][-2:] == ("pink→red", "x3")
    assert rows["P02"][-2:] == ("pest new +1", "x1")
    assert rows["P05"][-2:] == ("failed now", "")
    assert rows["P03"][-2:] == rows["P04"][-2:] == rows["P06"][-2:] == ("", "")  # nothing changed: blank
    assert rows["P05"][5] == "unreachable"  # the other columns as they were
    assert seen["table"]["widest"] <= seen["table"]["width"]  # fits the side panel of a 160-column console
    assert ("changes", {"mission": "default-patrol"}) in rec.asked
    assert ("pests", {"mission": "default-patrol", "last": 20}) in rec.asked


def test_without_a_history_answer_the_table_has_no_history_columns():
    for commands in (Recorder(), HistoryRecorder(refusal=NO_HISTORY_ON_ROBOT)):
        seen = {}
        console(patrolling_view, [table_of(seen)], commands)
        assert "since" not in seen["table"]["header"] and all(len(r) == 6 for r in seen["table"]["rows"].values())


def test_the_history_is_asked_again_when_a_pot_is_finished_and_when_the_patrol_ends():
    v = patrolling_view()
    rec = HistoryRecorder(patrol_history())
    counts = []

    def count(app):
        counts.append(sum(1 for q, _ in rec.asked if q == "changes"))

    def poll(app):
        app.redraw()

    def finish_p03(app):
        v.pots[2].status, v.pots[3].status = "inspected", "active"
        app.redraw()

    def patrol_ends(app):
        v.pots[3].status, v.mission_state = "inspected", "done"
        app.redraw()

    console(lambda: v, [count, poll, poll, count, finish_p03, count, patrol_ends, count], rec)
    assert counts[1] == counts[0] and counts[2] == counts[1] + 1 and counts[3] == counts[2] + 1


def test_a_slow_history_never_holds_the_console_up():
    """The robot's history takes its time: the console still drives and redraws meanwhile."""
    hold = threading.Event()
    answers = patrol_history()

    class Slow(HistoryRecorder):
        def history(self, query, **args):
            hold.wait(10)
            return super().history(query, **args)

    rec = Slow(answers)
    seen = {}
    v = patrolling_view()

    async def go():
        app = make_app(lambda: v, rec)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause()
            before = app.main.map_panel.renders
            await pilot.press("up")
            v.pose = (2.5, 0.5, 0.3)
            app.redraw()
            await pilot.pause()
            seen["while"] = (len(rec.sent), app.main.pots_table.marks, app.main.map_panel.renders > before)
            hold.set()
            await app.workers.wait_for_complete()
            await pilot.pause()
            seen["after"] = app.main.pots_table.rows[0][-2:]

    asyncio.run(go())
    assert seen["while"] == (1, None, True)  # the twist went out, the table waits for the answer
    assert seen["after"] == ("pink→red", "x3")


# --- a pot's timeline ------------------------------------------------------------------------
def test_i_opens_the_timeline_of_the_pot_in_progress_and_escape_closes_it():
    seen = {}
    rec, _ = console(patrolling_view, ["i", timeline_of(seen), "escape", screen_name(seen, "after")],
                     HistoryRecorder(patrol_history()))
    t = seen["timeline"]
    assert t["pot"] == "P03" and ("pot", {"pot": "P03"}) in rec.asked
    assert "2 patrols, newest first" in t["message"]
    assert [line[:2] + line[3:5] for line in t["lines"]] == [["2025-05-02", "06:00", "default-patrol", "failed"],
                                                             ["2025-05-01", "06:00", "default-patrol", "inspected"]]
    assert t["lines"][0][-1] == "unreachable"
    assert seen["after"] == "MainScreen" and rec.sent == []


def test_brackets_pick_the_pot_and_i_shows_its_pests():
    seen = {}
    rec, app = console(patrolling_view, ["left_square_bracket", "i", timeline_of(seen, "P02"), "i",
                                         screen_name(seen, "closed"), "right_square_bracket",
                                         "right_square_bracket", "i", timeline_of(seen, "P04")],
                       HistoryRecorder(patrol_history()))
    p02 = seen["P02"]
    assert p02["pot"] == "P02" and "3 patrols, newest first, 1 with a pest" in p02["message"]
    assert [line[7] for line in p02["lines"]] == ["PEST", "no", "no"]  # newest first
    assert seen["closed"] == "MainScreen"  # i again closes it too
    assert seen["P04"]["pot"] == "P04" and "no patrol has recorded P04 yet" in seen["P04"]["message"]
    assert app.main.pots_table.selected == "P04"


def test_a_click_picks_the_pot():
    seen = {}

    async def go():
        app = make_app(patrolling_view, HistoryRecorder(patrol_history()))
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause()
            await pilot.click("#pots", offset=(3, 6))  # the border, the header, P01 .. P05
            await pilot.press("i")
            await app.workers.wait_for_complete()
            await pilot.pause()
            seen["selected"] = app.main.pots_table.selected
            timeline_of(seen)(app)

    asyncio.run(go())
    assert seen["selected"] == "P05" and seen["timeline"]["pot"] == "P05"


def test_a_robot_without_a_history_says_so_in_the_timeline():
    seen = {}
    console(patrolling_view, ["i", timeline_of(seen, "refused")], HistoryRecorder(refusal=NO_HISTORY_ON_ROBOT))
    console(patrolling_view, ["i", timeline_of(seen, "no link")], Recorder())
    assert seen["refused"]["message"] == f"no history for P03: {NO_HISTORY_ON_ROBOT}"
    assert seen["no link"]["message"] == f"no history for P03: {NO_HISTORY}"
    assert seen["refused"]["lines"] == seen["no link"]["lines"] == []


def test_i_on_a_long_patrol_opens_the_pot_in_progress_and_the_timeline_is_long():
    """200 pots, P121 in progress; a year of its patrols (1,460) in the timeline."""
    year = [entry(k + 1, 1 + k % 28, bug=k % 5 == 0) for k in range(1460)]
    seen = {}
    rec, _ = console(greenhouse_view, ["i", timeline_of(seen)], HistoryRecorder({"pot": {"P121": year}}))
    t = seen["timeline"]
    assert t["pot"] == "P121" and len(t["lines"]) == 1460 and t["lines"][0][2] == "#1460"
    assert "292 with a pest" in t["message"]
