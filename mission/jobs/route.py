"""Scripted drive routes: body-frame moves closed on wheel odometry, through the twist_mux.

A route is a list of moves ("1 m forward", "90 deg left", ...). The driver publishes a twist on
the mux's ``auto`` source at the control rate until wheel odometry says the move is done, then
holds still for a moment so the next move starts from rest. This is how a person checks a base:
command a known motion, then compare what the wheels think happened with what really happened.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from hw.odometry import Pose2D, wrap_angle


@dataclass(frozen=True)
class Move:
    name: str
    axis: str  # "x" forward, "y" left, "yaw" counter-clockwise
    amount: float  # m or rad, signed
    speed: float  # m/s or rad/s, positive


#: Ramp down over the last part of a move so the base stops near the target without overshoot.
SLOW_ZONE = {"x": 0.10, "y": 0.10, "yaw": 0.15}
MIN_SPEED = {"x": 0.05, "y": 0.05, "yaw": 0.15}
SETTLE_S = 1.0

ROUTES: dict[str, list[Move]] = {
    "straight": [Move("forward 1 m", "x", 1.0, 0.25)],
    "strafe": [Move("strafe left 1 m", "y", 1.0, 0.20)],
    "turn": [Move("turn left 90 deg", "yaw", math.pi / 2, 0.5)],
    # The default greenhouse: out along the south aisle and back, strafe across the west cross
    # aisle into the middle aisle, turn in place both ways, then drive the aisle to its east end.
    "tour": [
        Move("forward 1 m", "x", 1.0, 0.25),
        Move("back 1 m", "x", -1.0, 0.25),
        Move("strafe left 2 m", "y", 2.0, 0.20),
        Move("turn left 90 deg", "yaw", math.pi / 2, 0.5),
        Move("turn right 90 deg", "yaw", -math.pi / 2, 0.5),
        Move("aisle 4.5 m", "x", 4.5, 0.30),
    ],
}


FLOOR_STEP = 0.05
"""Metres between the poses a move is checked at against the walls before the robot moves."""


def leaves_the_floor(moves: list[Move], start: Pose2D, floor: tuple[float, float], radius: float) -> str | None:
    """The first move whose nominal motion from ``start`` (world frame) would take the robot's
    circle through a wall, said in a sentence; None when the whole route stays on the floor."""
    pose = start
    for move in moves:
        if move.axis == "yaw":
            pose = Pose2D(pose.x, pose.y, wrap_angle(pose.yaw + move.amount))
            continue
        fx, fy = (math.cos(pose.yaw), math.sin(pose.yaw)) if move.axis == "x" else (-math.sin(pose.yaw), math.cos(pose.yaw))
        for s in np.append(np.arange(0.0, abs(move.amount), FLOOR_STEP), abs(move.amount)) * math.copysign(1.0, move.amount):
            x, y = pose.x + fx * s, pose.y + fy * s
            if not (radius <= x <= floor[0] - radius and radius <= y <= floor[1] - radius):
                return (f"move {move.name!r} would take the robot off the floor: at ({x:.2f}, {y:.2f}) its "
                        f"{radius:.2f} m circle crosses a wall of the {floor[0]:g} x {floor[1]:g} m floor")
        pose = Pose2D(pose.x + fx * move.amount, pose.y + fy * move.amount, pose.yaw)
    return None


def side_of(move: Move) -> str:
    """Where the robot is heading on a translation move, in its own words."""
    return {("x", 1): "ahead", ("x", -1): "behind", ("y", 1): "on the left", ("y", -1): "on the right"}[
        (move.axis, 1 if move.amount > 0 else -1)]


def relative(start: Pose2D, end: Pose2D) -> tuple[float, float, float]:
    """``end`` seen from ``start``'s body frame: (forward, left, yaw change wrapped to +-pi)."""
    dx, dy = end.x - start.x, end.y - start.y
    c, s = math.cos(start.yaw), math.sin(start.yaw)
    return c * dx + s * dy, -s * dx + c * dy, wrap_angle(end.yaw - start.yaw)


@dataclass
class MoveResult:
    move: Move
    odom: tuple[float, float, float]
    truth: tuple[float, float, float]

    @property
    def error(self) -> tuple[float, float, float]:
        return tuple(o - t for o, t in zip(self.odom, self.truth))


class RouteDriver:
    """Drives ``moves`` one after another. ``odom()`` and ``truth()`` return Pose2Ds."""

    def __init__(self, moves: list[Move], publish: Callable[[Twist, float], None],
                 odom: Callable[[], Pose2D], truth: Callable[[], Pose2D]):
        self.moves = list(moves)
        self.publish = publish
        self.odom = odom
        self.truth = truth
        self.results: list[MoveResult] = []
        self._i = 0
        self._start: tuple[Pose2D, Pose2D] | None = None
        self._settle_until: float | None = None

    @property
    def done(self) -> bool:
        return self._i >= len(self.moves)

    @property
    def current(self) -> Move | None:
        return None if self.done else self.moves[self._i]

    def tick(self, now: float) -> None:
        if self.done:
            self.publish(ZERO_TWIST, now)
            return
        move = self.moves[self._i]
        if self._start is None:
            self._start = (self.odom(), self.truth())
        if self._settle_until is not None:
            self.publish(ZERO_TWIST, now)
            if now >= self._settle_until:
                odom0, truth0 = self._start
                self.results.append(MoveResult(move, relative(odom0, self.odom()), relative(truth0, self.truth())))
                self._i += 1
                self._start = None
                self._settle_until = None
            return
        done_so_far = relative(self._start[0], self.odom())[("x", "y", "yaw").index(move.axis)]
        remaining = abs(move.amount) - math.copysign(1.0, move.amount) * done_so_far
        if remaining <= 0.0:
            self._settle_until = now + SETTLE_S
            self.publish(ZERO_TWIST, now)
            return
        speed = max(MIN_SPEED[move.axis], min(move.speed, move.speed * remaining / SLOW_ZONE[move.axis]))
        v = math.copysign(speed, move.amount)
        self.publish(Twist(**{{"x": "vx", "y": "vy", "yaw": "wz"}[move.axis]: v}), now)
