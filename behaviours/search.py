"""Search for a pot's tag: drive to one look after another and read the front camera at each,
until a read is the one sought.

The looks come from a callable, read when the search starts (the tree computes them from the map
as it is then); each is a goal for the navigator with a time limit of its own, and a look the
robot cannot reach is passed over. After arriving, the frame must be taken ``settle`` seconds
later (the base has stopped); every frame taken on the way is read too (a plate passed is a
plate found; ``on_the_way`` False: only frames taken standing at a look count, for a search that
must end standing where it read). ``found(reads, robot)`` decides (and keeps what it needs); the
search then succeeds. Out of looks, it fails, saying how many it tried. Stopping it cancels the
goal it was driving to (only while it runs, as ``behaviours.navigate.NavigateTo``).
"""
from __future__ import annotations

from typing import Callable

import py_trees
from py_trees.common import Status

from hw.interfaces import Clock
from hw.odometry import Pose2D
from nav.navigator import Navigator, State
from perception.camera_pipeline import CameraPipeline
from perception.detections import TagRead
from perception.tag_reader import TagReader


LOOK_TOLERANCE = 0.08
"""Metres a look must be reached to: a plate framed from 0.2 m off its look can leave the frame."""


class SearchTag(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, nav: Navigator, looks: Callable[[], list[Pose2D]], camera: CameraPipeline,
                 reader: TagReader, found: Callable[[tuple[TagRead, ...], Pose2D], bool], clock: Clock,
                 settle: float, look_timeout: float, on_the_way: bool = True):
        super().__init__(name)
        self.on_the_way = on_the_way
        self.nav, self.looks, self.camera, self.reader, self.found = nav, looks, camera, reader, found
        self.clock, self.settle, self.look_timeout = clock, settle, look_timeout
        self._left: list[Pose2D] = []
        self._tried = 0
        self._since: float | None = None
        self._seen: float | None = None

    def initialise(self) -> None:
        self._left, self._tried, self._since = list(self.looks()), 0, None
        self.feedback_message = ""
        self._next()

    def update(self) -> Status:
        if self.on_the_way and self._read(self.camera.request()):
            self.nav.cancel(self.clock.now(), "found on the way")
            return Status.SUCCESS
        state = self.nav.state
        if state is State.SUCCEEDED:
            if self._since is None:
                self._since = self.clock.now() + self.settle
            standing = self.camera.fresh(self._since)
            if standing is None:
                return Status.RUNNING
            if self._read(standing):
                return Status.SUCCESS
        elif self.nav.active:
            return Status.RUNNING
        if not self._next():
            self.feedback_message = f"not found from {self._tried} look(s)" if self._tried else "no look where the robot fits"
            return Status.FAILURE
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self.status is Status.RUNNING:
            self.nav.cancel(self.clock.now(), f"{self.name} stopped")

    def _read(self, frame) -> bool:
        """Read a frame not read yet; True when it holds what is sought."""
        if frame is None or frame.stamp == self._seen:
            return False
        self._seen = frame.stamp
        return self.found(self.reader.read(frame.image), self.nav.map_pose())

    def _next(self) -> bool:
        """Drive to the next look; False when none is left."""
        if not self._left:
            return False
        self._tried += 1
        self._since = None
        self.nav.navigate_to(self._left.pop(0), self.clock.now(), self.look_timeout, LOOK_TOLERANCE)
        return True

