"""The Hold guard and the mission's holds (e-stop latch, pause, resume) in tiny trees."""
from __future__ import annotations

import logging

import py_trees
from py_trees.common import OneShotPolicy, Status
from py_trees.composites import Sequence
from py_trees.decorators import OneShot

from behaviours.guard import Hold
from hw.config import EStopConfig
from hw.estop import EStopBridge
from mission.patrol.holds import MissionHolds
from tests.fixtures import FakeButton


class Counting(py_trees.behaviour.Behaviour):
    """RUNNING for ``ticks`` updates, then SUCCESS; counts starts and INVALID stops."""

    def __init__(self, name, ticks=3):
        super().__init__(name)
        self.ticks, self.left, self.starts, self.stops = ticks, ticks, 0, 0

    def initialise(self):
        self.starts += 1
        self.left = self.ticks

    def update(self):
        self.left -= 1
        return Status.SUCCESS if self.left <= 0 else Status.RUNNING

    def terminate(self, new_status):
        if new_status is Status.INVALID:
            self.stops += 1


def test_hold_stops_the_running_child_and_resumes_it_from_the_start():
    reason = [None]
    leaf = Counting("drive", ticks=3)
    hold = Hold("guard", leaf, lambda: reason[0])
    hold.tick_once()
    assert hold.status is Status.RUNNING and leaf.starts == 1
    reason[0] = "e-stop engaged"
    hold.tick_once()
    assert hold.status is Status.RUNNING and hold.feedback_message == "e-stop engaged"
    assert leaf.stops == 1 and leaf.status is Status.INVALID  # cancelled what it started
    hold.tick_once()
    assert leaf.stops == 1 and leaf.starts == 1  # held: not ticked at all
    reason[0] = None
    for _ in range(3):
        hold.tick_once()
    assert leaf.starts == 2 and hold.status is Status.SUCCESS


def test_one_shot_work_survives_a_hold_and_the_step_in_progress_is_redone():
    reason = [None]
    first, second = Counting("P01", ticks=1), Counting("P02", ticks=3)
    seq = Sequence("pots", memory=True, children=[OneShot("P01 once", first, OneShotPolicy.ON_COMPLETION),
                                                  OneShot("P02 once", second, OneShotPolicy.ON_COMPLETION)])
    hold = Hold("guard", seq, lambda: reason[0])
    hold.tick_once()
    hold.tick_once()
    assert first.starts == 1 and second.starts == 1
    reason[0] = "paused"
    hold.tick_once()
    reason[0] = None
    for _ in range(3):
        hold.tick_once()
    assert hold.status is Status.SUCCESS
    assert first.starts == 1 and second.starts == 2  # P01 not redone, P02 started over


def make_holds():
    button = FakeButton(0)
    bridge = EStopBridge(EStopConfig(engaged_level=1), button, logging.getLogger("test"))
    clock = [100.0]
    return MissionHolds(bridge, lambda: clock[0], 100.0), bridge, button, clock


def test_release_does_not_clear_the_latch_only_resume_after_release_does():
    holds, bridge, button, clock = make_holds()
    assert holds.estop() is None
    button.level, clock[0] = 1, 140.0
    assert holds.estop() == "e-stop engaged"
    assert holds.resume() is not None  # refused while engaged
    assert holds.estop() == "e-stop engaged"
    button.level, clock[0] = 0, 145.0
    assert "waiting for the operator's resume" in holds.estop()
    assert holds.estop() is not None  # still latched, tick after tick
    assert holds.resume() is None
    assert holds.estop() is None
    assert holds.estop_events == [{"t": 40.0, "engaged": True}, {"t": 45.0, "engaged": False}]


def test_soft_stop_and_a_press_between_two_mission_ticks_both_latch():
    holds, bridge, button, clock = make_holds()
    bridge.set_soft(True)
    assert holds.estop() == "e-stop engaged"
    bridge.set_soft(False)
    holds.resume()
    assert holds.estop() is None
    button.level = 1
    bridge.engaged()  # the base controller's live read sees a short press ...
    button.level = 0
    assert holds.estop() is not None  # ... the mission, ticking after the release, still latches
    assert [e["engaged"] for e in holds.estop_events] == [True, False, True, False]


def test_pause_holds_until_resume():
    holds, *_ = make_holds()
    assert holds.pause_reason() is None
    holds.pause()
    assert "paused" in holds.pause_reason()
    assert holds.resume() is None and holds.pause_reason() is None
