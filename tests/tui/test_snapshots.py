"""Snapshots of the console's main states (pytest-textual-snapshot). After a deliberate change,
regenerate with ``pytest tests/tui --snapshot-update`` and look at the SVGs before committing.
Deterministic: fixed terminal sizes, hand-made views, nothing time-dependent on screen."""
from __future__ import annotations

from tests.tui.fakes import (HistoryRecorder, Recorder, estopped_view, greenhouse_view, idle_view, patrol_history,
                             patrolling_view)
from tui.app import make_app

SIZE = (160, 48)


def test_idle(snap_compare):
    assert snap_compare(make_app(idle_view, Recorder()), terminal_size=SIZE)


def test_patrolling(snap_compare):
    assert snap_compare(make_app(patrolling_view, Recorder()), terminal_size=SIZE)


def test_estopped(snap_compare):
    assert snap_compare(make_app(estopped_view, Recorder()), terminal_size=SIZE)


def test_patrolling_on_a_small_terminal(snap_compare):
    """100 x 40: the status bar wraps between its chips instead of losing the end."""
    assert snap_compare(make_app(patrolling_view, Recorder()), terminal_size=(100, 40))


def test_clear_map_question(snap_compare):
    assert snap_compare(make_app(patrolling_view, Recorder()), press=["c"], terminal_size=SIZE)


def test_patrol_at_scale(snap_compare):
    """200 pots in two bays, 120 done: the map fitted to the greenhouse, the tree folded to the
    pot in progress (P121) and the pot table scrolled to it."""
    assert snap_compare(make_app(greenhouse_view, Recorder()), terminal_size=SIZE)


def test_following_the_robot_zoomed_in(snap_compare):
    assert snap_compare(make_app(greenhouse_view, Recorder()), press=["t", "plus"], terminal_size=SIZE)


def test_pots_with_anomalies_only(snap_compare):
    assert snap_compare(make_app(greenhouse_view, Recorder()), press=["a"], terminal_size=SIZE)


def settled(*keys):
    """Press ``keys``, then wait for what they asked the robot (the history's answers)."""
    async def run(pilot):
        await pilot.pause()
        for key in keys:
            await pilot.press(key)
            await pilot.app.workers.wait_for_complete()
            await pilot.pause()
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
    return run


def test_patrolling_with_history(snap_compare):
    """The pot table with the history's columns: since the last patrol, the pest streak."""
    assert snap_compare(make_app(patrolling_view, HistoryRecorder(patrol_history())), terminal_size=SIZE,
                        run_before=settled())


def test_a_pots_timeline(snap_compare):
    """P02 picked with ``[`` (from P03, in progress), its timeline opened with ``i``."""
    assert snap_compare(make_app(patrolling_view, HistoryRecorder(patrol_history())), terminal_size=SIZE,
                        run_before=settled("left_square_bracket", "i"))
