"""The patrol's leaves and the clock-based timeout, in tiny trees on a SimClock (no physics)."""
from __future__ import annotations

import math

import numpy as np
import py_trees
from py_trees.common import Status
from py_trees.composites import Selector, Sequence
from py_trees.decorators import Retry

from behaviours.navigate import NavigateTo
from behaviours.perceive import DetectFlower, ReadTags, WatchTags
from behaviours.steps import Do, WaitUntil
from behaviours.timeout import Timeout
from behaviours.visit import PotVisit
from hw.odometry import Pose2D
from nav.navigator import State
from perception.camera_pipeline import CameraPipeline
from perception.detections import FlowerFrame
from sim.clock import SimClock


class FakeNav:
    """The navigator's goal API, driven by the test."""

    def __init__(self):
        self.state, self.reason, self.goals, self.cancels = State.IDLE, "", [], 0

    def navigate_to(self, goal, now, timeout=None, xy_tolerance=None):
        self.goals.append((goal, now, timeout))
        self.state = State.FOLLOWING

    def cancel(self, now, reason="canceled"):
        if self.state in (State.FOLLOWING, State.RECOVERING):
            self.cancels += 1
            self.state, self.reason = State.CANCELED, reason


class Still(py_trees.behaviour.Behaviour):
    """RUNNING for ever; remembers how it was stopped."""

    def __init__(self):
        super().__init__("still")
        self.stopped_with = None

    def update(self):
        return Status.RUNNING

    def terminate(self, new_status):
        self.stopped_with = new_status


def tick_at(root, clock, t):
    clock.wait_until(t)
    root.tick_once()
    return root.status


def test_timeout_runs_on_the_runtime_clock_and_stops_its_child():
    clock, child = SimClock(), Still()
    root = Timeout("t", child, clock, 2.0)
    assert tick_at(root, clock, 0.0) is Status.RUNNING
    assert tick_at(root, clock, 1.99) is Status.RUNNING  # however much wall time passed
    assert tick_at(root, clock, 2.0) is Status.FAILURE
    assert child.stopped_with is Status.INVALID
    assert "timed out after 2 s" in root.feedback_message


def test_navigate_to_mirrors_the_navigator_and_cancels_when_stopped():
    clock, nav = SimClock(), FakeNav()
    starts = []
    leaf = NavigateTo("go", nav, lambda: Pose2D(1.0, 2.0, 0.5), clock, lambda: starts.append(clock.now()))
    root = Timeout("t", leaf, clock, 5.0)
    assert tick_at(root, clock, 0.0) is Status.RUNNING
    assert nav.goals[0][0] == Pose2D(1.0, 2.0, 0.5) and math.isinf(nav.goals[0][2])  # the decorator times it
    assert tick_at(root, clock, 5.0) is Status.FAILURE
    assert nav.cancels == 1 and starts == [0.0]


def test_retry_starts_a_fresh_attempt_after_a_failure():
    clock, nav = SimClock(), FakeNav()
    root = Retry("x2", NavigateTo("go", nav, lambda: Pose2D(0, 0, 0), clock), 2)
    tick_at(root, clock, 0.0)
    nav.state, nav.reason = State.FAILED, "no path"
    assert tick_at(root, clock, 0.1) is Status.RUNNING  # first failure: retried
    tick_at(root, clock, 0.2)
    assert len(nav.goals) == 2
    nav.state = State.FAILED
    assert tick_at(root, clock, 0.3) is Status.FAILURE
    assert "no path" in root.decorated.feedback_message


def test_a_failed_drive_cleared_later_by_its_selector_leaves_the_next_drive_alone():
    """py_trees' selector with memory stops the children before the one it runs at its next tick:
    the drive that failed must not cancel the goal the next child has just given."""
    clock, nav = SimClock(), FakeNav()
    first = NavigateTo("go", nav, lambda: Pose2D(0, 0, 0), clock)
    second = NavigateTo("beside", nav, lambda: Pose2D(1, 0, 0), clock)
    root = Selector("get there", memory=True, children=[first, second])
    tick_at(root, clock, 0.0)
    nav.state, nav.reason = State.FAILED, "no path"
    assert tick_at(root, clock, 0.1) is Status.RUNNING and nav.goals[-1][0] == Pose2D(1, 0, 0)
    assert tick_at(root, clock, 0.2) is Status.RUNNING
    assert first.status is Status.INVALID and nav.cancels == 0 and nav.state is State.FOLLOWING


def test_navigate_succeeds_when_the_navigator_does():
    clock, nav = SimClock(), FakeNav()
    leaf = NavigateTo("go", nav, lambda: Pose2D(0, 0, 0), clock)
    tick_at(leaf, clock, 0.0)
    nav.state = State.SUCCEEDED
    assert tick_at(leaf, clock, 0.1) is Status.SUCCESS and nav.cancels == 0


def test_wait_until_fails_with_the_reason():
    flag = {"done": False, "why": None}
    leaf = WaitUntil("w", lambda: flag["done"], lambda: flag["why"])
    leaf.tick_once()
    assert leaf.status is Status.RUNNING
    flag["why"] = "navigation waiting for map"
    leaf.tick_once()
    assert leaf.status is Status.FAILURE and leaf.feedback_message == "navigation waiting for map"


def test_do_records_and_a_selector_notes_a_failure():
    notes = []
    failing = Do("fails", lambda: "camera unplugged")
    root = Selector("s", memory=True, children=[failing, Do("note", lambda: notes.append(failing.feedback_message))])
    root.tick_once()
    assert root.status is Status.SUCCESS and notes == ["camera unplugged"]


class Camera:
    def __init__(self, fail=False):
        self.fail, self.n = fail, 0

    def capture(self):
        self.n += 1
        if self.fail:
            return None
        return np.full((48, 64, 3), self.n, np.uint8)


def test_a_frame_counts_only_after_the_settle_time():
    clock, visit = SimClock(), PotVisit("P01")
    cam = CameraPipeline(Camera(), clock, 2.0, "wrist")
    cam.request()  # a frame from before: must not be used
    detector = type("D", (), {"detect": lambda self, image: FlowerFrame()})()
    leaf = DetectFlower("look", cam, detector, visit, clock, settle=0.3)
    assert tick_at(leaf, clock, 0.0) is Status.RUNNING and visit.wrist is None
    assert tick_at(leaf, clock, 0.3) is Status.RUNNING  # the camera's 2 Hz cap: next capture at 0.5
    assert tick_at(leaf, clock, 0.5) is Status.SUCCESS
    assert visit.wrist.stamp == 0.5 and visit.flower == FlowerFrame()


def test_a_dead_camera_keeps_the_leaf_waiting_and_the_timeout_fails_it():
    clock, visit = SimClock(), PotVisit("P01")
    cam = CameraPipeline(Camera(fail=True), clock, 2.0, "front")
    reader = type("R", (), {"read": lambda self, image: ()})()
    root = Timeout("t", ReadTags("tag", cam, reader, visit, clock, 0.0), clock, 3.0)
    for t in np.arange(0.0, 3.01, 0.1):
        tick_at(root, clock, float(t))
    assert root.status is Status.FAILURE and visit.front is None and cam.failures >= 6


def test_watch_tags_reports_each_new_frame_once_and_never_ends():
    clock, seen = SimClock(), []
    cam = CameraPipeline(Camera(), clock, 2.0, "front")
    reader = type("R", (), {"read": lambda self, image: ("tag",)})()
    leaf = WatchTags("watch", cam, reader, lambda frame, reads: seen.append(frame.stamp),
                     lambda: Pose2D(clock.now(), 0.0, 0.0), 0.0, 0.0)  # always a new view
    for t in np.arange(0.0, 1.01, 0.1):
        assert tick_at(leaf, clock, float(t)) is Status.RUNNING
    assert seen == [0.0, 0.5, 1.0]


def test_watch_tags_looks_again_only_once_the_view_has_changed():
    clock, seen, pose = SimClock(), [], [Pose2D()]
    cam = CameraPipeline(Camera(), clock, 2.0, "front")
    reader = type("R", (), {"read": lambda self, image: ("tag",)})()
    leaf = WatchTags("watch", cam, reader, lambda frame, reads: seen.append(frame.stamp), lambda: pose[0], 0.25, 0.25)
    for t in np.arange(0.0, 3.01, 0.1):  # standing still for 3 s: one look
        tick_at(leaf, clock, float(t))
    assert seen == [0.0] and cam.captures == 1
    pose[0] = Pose2D(0.2, 0.0, 0.2)  # not far enough, not turned enough
    tick_at(leaf, clock, 3.5)
    pose[0] = Pose2D(0.0, 0.0, -0.3)  # turned
    tick_at(leaf, clock, 4.0)
    pose[0] = Pose2D(0.0, 0.26, -0.3)  # moved
    tick_at(leaf, clock, 4.5)
    assert seen == [0.0, 4.0, 4.5]


def test_a_sequence_of_leaves_stops_at_the_first_failure():
    order = []
    root = Sequence("s", memory=True, children=[Do("a", lambda: order.append("a")), Do("b", lambda: False),
                                                Do("c", lambda: order.append("c"))])
    root.tick_once()
    assert root.status is Status.FAILURE and order == ["a"]
