"""Perception leaves: take a fresh frame from a camera pipeline and run a detector on it.

A frame counts only if it was captured after the leaf started plus ``settle`` (the arm has
stopped swinging the wrist camera, the base has stopped), so a pot is never judged on the
frame of the pot before. The pipelines cap the capture rate (perception.camera_pipeline); these
leaves just ask. How long to wait for a frame is the ``Timeout`` decorator's business.
"""
from __future__ import annotations

import math
from typing import Callable

import py_trees
from py_trees.common import Status

from behaviours.visit import PotVisit
from hw.interfaces import Clock
from hw.odometry import Pose2D
from perception.camera_pipeline import CameraPipeline, Frame
from perception.detections import TagRead
from perception.flower_detector import FlowerDetector
from perception.tag_reader import TagReader


class _FreshFrame(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, camera: CameraPipeline, clock: Clock, settle: float):
        super().__init__(name)
        self.camera, self.clock, self.settle = camera, clock, settle
        self.since = 0.0

    def initialise(self) -> None:
        self.since = self.clock.now() + self.settle
        self.feedback_message = ""

    def update(self) -> Status:
        if self.clock.now() < self.since:
            return Status.RUNNING
        frame = self.camera.fresh(self.since)
        if frame is None:
            self.feedback_message = f"waiting for a {self.camera.name} frame ({self.camera.failures} failed captures)"
            return Status.RUNNING
        self.use(frame)
        return Status.SUCCESS

    def use(self, frame: Frame) -> None:
        raise NotImplementedError


class DetectFlower(_FreshFrame):
    """The wrist frame and the flower detector's reading of it, into the visit."""

    def __init__(self, name: str, camera: CameraPipeline, detector: FlowerDetector, visit: PotVisit,
                 clock: Clock, settle: float):
        super().__init__(name, camera, clock, settle)
        self.detector, self.visit = detector, visit

    def use(self, frame: Frame) -> None:
        self.visit.wrist, self.visit.flower = frame, self.detector.detect(frame.image)


class ReadTags(_FreshFrame):
    """The front frame and every tag read in it, into the visit."""

    def __init__(self, name: str, camera: CameraPipeline, reader: TagReader, visit: PotVisit,
                 clock: Clock, settle: float):
        super().__init__(name, camera, clock, settle)
        self.reader, self.visit = reader, visit

    def use(self, frame: Frame) -> None:
        self.visit.front, self.visit.tags = frame, self.reader.read(frame.image)


class WatchTags(py_trees.behaviour.Behaviour):
    """Always RUNNING beside the patrol: the tags in view go to ``seen`` (the mission keeps the
    ones it does not list, with their map positions).

    It asks for a frame only when the view has changed since the last one it read: the robot
    has moved ``spacing`` metres or turned ``turn`` radians (``pose`` gives its map pose). A
    robot standing at a pot for its inspection sees the same tags frame after frame; reading
    them again costs the Pi a tag detection (and the sim a render) each and adds nothing, so the
    cost follows the distance driven, not the time spent."""

    def __init__(self, name: str, camera: CameraPipeline, reader: TagReader,
                 seen: Callable[[Frame, tuple[TagRead, ...]], None], pose: Callable[[], Pose2D],
                 spacing: float, turn: float):
        super().__init__(name)
        self.camera, self.reader, self.seen = camera, reader, seen
        self.pose, self.spacing, self.turn = pose, spacing, turn
        self.last: float | None = None
        self._viewed_from: Pose2D | None = None

    def _view_changed(self, here: Pose2D) -> bool:
        was = self._viewed_from
        return was is None or math.hypot(here.x - was.x, here.y - was.y) >= self.spacing \
            or abs(math.remainder(here.yaw - was.yaw, 2 * math.pi)) >= self.turn

    def update(self) -> Status:
        here = self.pose()
        if not self._view_changed(here):
            return Status.RUNNING
        frame = self.camera.request()
        if frame is not None and frame.stamp != self.last:
            self.last, self._viewed_from = frame.stamp, here
            reads = self.reader.read(frame.image)
            if reads:
                self.seen(frame, reads)
        return Status.RUNNING
